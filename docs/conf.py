"""Sphinx configuration of the faultnet documentation.

Build: ``pip install ".[docs]" && sphinx-build -W -b html docs docs/_build/html``.
The API pages are generated from ``faultnet.__all__`` (the top-level names) and
from the module list in ``api.rst``; the gallery runs ``examples/plot_*.py``.
"""

import importlib
import importlib.util
import inspect
import os
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT))  # document the checkout that is being built
sys.path.insert(0, str(DOCS / "_ext"))  # mathtext_svg: the equations, drawn at build time
os.environ.setdefault("MPLBACKEND", "Agg")
# the example scripts save their PNGs here instead of into examples/figures
os.environ.setdefault("FAULTNET_FIGURES", str(DOCS / "_build" / "example_figures"))

import faultnet  # noqa: E402
import faultnet.cli.commands  # noqa: E402

project = "faultnet"
author = "faultnet developers"
copyright = "faultnet developers"
release = version = faultnet.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
    "mathtext_svg",
]
html_math_renderer = "mathtext"  # offline SVG equations instead of MathJax from a CDN

templates_path = ["_templates"]
exclude_patterns = ["_build", "_generated", "**/*.ipynb"]
html_theme = "pydata_sphinx_theme"
html_title = f"faultnet {release}"
html_theme_options = {
    "navbar_align": "left",
    "show_toc_level": 2,
    "navigation_with_keys": False,
    "header_links_before_dropdown": 6,
    "logo": {"text": "faultnet"},
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version", "theme-version"],
}
html_static_path = []
html_show_sourcelink = False

# --------------------------------------------------------------------- API pages
autosummary_generate = ["api.rst"]
autosummary_ignore_module_all = False
autodoc_member_order = "bysource"
autodoc_typehints = "none"  # numpydoc's Parameters sections carry the types
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_attributes_as_param_list = False


def _public_names():
    """``faultnet.__all__`` split into classes, exceptions and functions (modules go to api.rst)."""
    groups = {"Classes": [], "Functions": [], "Exceptions": []}
    for name in faultnet.__all__:
        obj = getattr(faultnet, name)
        if inspect.ismodule(obj) or name.startswith("_") or not callable(obj):
            continue  # modules are listed in api.rst; __version__ and data are not API pages
        if inspect.isclass(obj) and issubclass(obj, BaseException):
            groups["Exceptions"].append(name)
        elif inspect.isclass(obj):
            groups["Classes"].append(name)
        else:
            groups["Functions"].append(name)
    return groups


def _shadowed_modules():
    """Submodules whose name a top-level function of the same name shadows (``sweep``).

    Their module pages are written with ``:no-index:`` so that the function keeps the name.
    """
    out = []
    for name in faultnet.__all__:
        obj = getattr(faultnet, name)
        if not inspect.ismodule(obj) and importlib.util.find_spec(f"faultnet.{name}") is not None:
            out.append(f"faultnet.{name}")
    return out


def _write(path, text):
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.exists() or path.read_text() != text:
        path.write_text(text)


_STUB = {
    "function": "{title}\n\n.. currentmodule:: faultnet\n\n.. autofunction:: {name}\n",
    "class": "{title}\n\n.. currentmodule:: faultnet\n\n.. autoclass:: {name}\n"
    "   :members:\n   :show-inheritance:\n",
}
_MINIGALLERY = (
    "\n.. minigallery:: faultnet.{name}\n   :add-heading: Gallery examples using ``{name}``\n"
)


def _write_toplevel(path):
    """The autosummary tables of the top-level names, and one page per name.

    The pages are written here (autosummary does not generate stubs for an included file).
    """
    lines = []
    for title, names in _public_names().items():
        if not names:
            continue
        lines += [title, "^" * len(title), "", ".. autosummary::", "   :toctree: generated", ""]
        lines += [f"   faultnet.{name}" for name in sorted(names, key=str.lower)]
        lines.append("")
        for name in names:
            full = f"faultnet.{name}"
            kind = "function" if title == "Functions" else "class"
            text = _STUB[kind].format(title=f"{full}\n{'=' * len(full)}", name=name)
            _write(DOCS / "generated" / f"{full}.rst", text + _MINIGALLERY.format(name=name))
    _write(path, "\n".join(lines))


def _write_cli(path):
    parser = faultnet.cli.commands.build_parser()
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    lines = ["``faultnet``", "-" * 12, "", ".. code-block:: text", ""]
    lines += ["   " + line for line in parser.format_help().splitlines()]
    for name, command in sub.choices.items():
        title = f"``faultnet {name}``"
        lines += ["", title, "-" * len(title), "", ".. code-block:: text", ""]
        lines += ["   " + line.rstrip() for line in command.format_help().splitlines()]
    _write(path, "\n".join(lines) + "\n")


_write_toplevel(DOCS / "_generated" / "toplevel.rst")
_write_cli(DOCS / "_generated" / "cli.rst")


autosummary_context = {"shadowed_modules": _shadowed_modules()}

# ----------------------------------------------------------------------- gallery
sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "ignore_pattern": r"(^|/)_",  # examples/_paper_data.py is a helper, not an example
    "within_subsection_order": "FileNameSortKey",
    "doc_module": ("faultnet",),
    "backreferences_dir": "generated/backreferences",
    "abort_on_example_error": True,
    "only_warn_on_example_error": False,
    "remove_config_comments": True,
    "show_memory": False,
    "download_all_examples": False,
    "image_scrapers": ("matplotlib",),
    "matplotlib_animations": False,
    "min_reported_time": 1,
    "capture_repr": (),  # print() output only, not the repr of a block's last expression
}
