"""Render the documentation's mathematics at build time, as SVG, with matplotlib's mathtext.

Sphinx's default HTML math renderer loads MathJax from a CDN: offline, and in the
site check's headless Chromium (which has no network), a reader sees raw TeX.
This extension registers the renderer ``mathtext``: every ``:math:`` role and
``.. math::`` directive is drawn by :func:`matplotlib.mathtext.math_to_image`
into an SVG image embedded in the page, with the TeX as its ``alt`` text.
mathtext covers the subset of TeX the pages use (fractions, sums, sub- and
superscripts, accents, Greek letters); a formula it cannot parse fails the
build with the formula in the message.
"""

import base64
import io
from pathlib import Path

import matplotlib
from docutils import nodes
from matplotlib import mathtext
from matplotlib.font_manager import FontProperties
from sphinx.errors import ExtensionError
from sphinx.util.math import get_node_equation_number

#: font sizes in points: running text, displayed equations
INLINE_PT, BLOCK_PT = 12.0, 14.0


def _image(latex, size, css):
    """An ``<img>`` of ``latex`` drawn by mathtext, aligned on the text's baseline."""
    buf = io.BytesIO()
    try:
        with matplotlib.rc_context({"mathtext.fontset": "cm", "svg.fonttype": "path"}):
            depth = mathtext.math_to_image(
                f"${latex}$", buf, prop=FontProperties(size=size), dpi=72, format="svg"
            )
    except ValueError as exc:
        raise ExtensionError(f"mathtext cannot draw the formula {latex!r}: {exc}") from exc
    data = base64.b64encode(buf.getvalue()).decode("ascii")
    alt = latex.replace("&", "&amp;").replace('"', "&quot;").replace("<", "&lt;")
    style = f' style="vertical-align: -{depth:.2f}pt"' if css == "math" else ""
    return f'<img class="{css}" src="data:image/svg+xml;base64,{data}" alt="{alt}"{style}/>'


def visit_math(self, node):
    latex = node.astext().strip()
    self.body.append(_image(latex, INLINE_PT, "math"))
    raise nodes.SkipNode


def visit_math_block(self, node):
    self.body.append(self.starttag(node, "div", CLASS="math-block"))
    if node["number"]:
        number = get_node_equation_number(self, node)
        self.body.append(f'<span class="eqno">({number})</span>')
    for part in node.astext().split("\n\n"):  # one image per equation of the block
        if part.strip():
            latex = " ".join(part.split())
            self.body.append(f"<p>{_image(latex, BLOCK_PT, 'math-display')}</p>")
    self.body.append("</div>\n")
    raise nodes.SkipNode


CSS = """
img.math { height: auto; }
div.math-block { text-align: center; margin: 0.8em 0; }
div.math-block p { margin: 0.3em 0; }
div.math-block span.eqno { float: right; }
"""


def _add_css(app):
    static = Path(app.outdir) / "_static"
    static.mkdir(parents=True, exist_ok=True)
    (static / "mathtext_svg.css").write_text(CSS)


def setup(app):
    app.add_html_math_renderer(
        "mathtext", inline_renderers=(visit_math, None), block_renderers=(visit_math_block, None)
    )
    app.connect("builder-inited", _add_css)
    app.add_css_file("mathtext_svg.css")
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
