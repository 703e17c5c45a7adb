"""Check the built documentation site in a real browser.

    python docs/check_site.py                       # docs/_build/html
    python docs/check_site.py --site DIR --shots DIR --chromium PATH

Serves the built site on 127.0.0.1 (a free port, a server thread), then

1. crawls every HTML page over HTTP: every internal link (page and ``#anchor``)
   and every image, stylesheet and script it names must resolve, and no page
   may hold a Python traceback, TeX left unrendered or a path of the machine
   that built it (the checkout, the Python install, a temporary folder);
2. loads the home page, the model page, "Choosing rtol", the gallery index, two
   gallery examples and the API page of ``faultnet.simulate`` in headless
   Chromium (driven over the DevTools protocol), waits for every image, fails
   on an image the browser could not decode (``naturalWidth == 0``), a traceback
   in the rendered text or a model page with fewer than six drawn equations,
   and saves a full-page screenshot of each (``docs/_build/screenshots`` by
   default).

Exits 1 and lists every problem found; needs Debian's ``chromium`` and the
``websocket-client`` package (in the ``docs`` extra).
"""

from __future__ import annotations

import argparse
import base64
import contextlib
import functools
import http.server
import json
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import time
import urllib.error
import urllib.request
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urldefrag, urljoin, urlparse

HERE = Path(__file__).resolve().parent
#: a Python traceback with its frames (a doctest's expected exception shows no frames)
TRACEBACK = re.compile(r'Traceback \(most recent call last\):\s+File "')
#: TeX that reached the page as text: the math renderer did not draw it
RAW_TEX = re.compile(r"\\(?:d?frac|sum|sigma|alpha|phi|dot|ddot|propto|qquad|mathrm)\b")
#: equations the model page must show, drawn (``docs/_ext/mathtext_svg.py``)
MIN_EQUATIONS = 6


def _machine_paths():
    """Paths of the machine that builds the docs, which no page may show."""
    import os
    import tempfile

    paths = {str(HERE.parent), sys.prefix, os.path.expanduser("~")}
    paths.add(os.path.join(tempfile.gettempdir(), "tmp"))  # mkdtemp's folders
    return sorted(p for p in paths if len(p) > 4)


#: the pages opened in the browser: (name, path below the site root)
PAGES = [
    ("home", "index.html"),
    ("model", "guide/model.html"),
    ("choosing-rtol", "guide/accuracy.html"),  # its first section
    ("gallery", "auto_examples/index.html"),
    ("example-fig08", "auto_examples/plot_fig08_magnitude_1d_2d.html"),
    ("example-showcase", "auto_examples/plot_showcase_b_vs_alpha.html"),
    ("api-simulate", "generated/faultnet.simulate.html"),
]
_WAIT_FOR_IMAGES = """
Promise.all(Array.from(document.images).map(img => {
    img.loading = "eager";
    if (img.complete) return null;
    return new Promise(done => { img.onload = done; img.onerror = done; });
})).then(() => JSON.stringify({
    images: Array.from(document.images).map(img => ({
        src: img.currentSrc || img.src, ok: img.complete && img.naturalWidth > 0,
        width: img.naturalWidth, cls: img.className})),
    text: document.body.innerText,
    title: document.title,
}))
"""


# ------------------------------------------------------------------ the server
class _QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


@contextlib.contextmanager
def serve(root):
    """Serve ``root`` on 127.0.0.1 at a free port; yield the base URL."""
    handler = functools.partial(_QuietHandler, directory=str(root))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}/"
    finally:
        server.shutdown()
        server.server_close()


# ------------------------------------------------------------------- the crawl
class _Links(HTMLParser):
    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.refs = []  # (kind, url)
        self.ids = set()
        self.text = []
        self.prose = []  # the text outside code blocks
        self._code = 0

    def handle_data(self, data):
        self.text.append(data)
        if not self._code:
            self.prose.append(data)

    def handle_endtag(self, tag):
        if tag == "pre" and self._code:
            self._code -= 1

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "pre":
            self._code += 1
        for key in ("id", "name"):
            if a.get(key):
                self.ids.add(a[key])
        if tag == "a" and a.get("href"):
            self.refs.append(("link", a["href"]))
        elif tag in ("img", "script") and a.get("src"):
            self.refs.append((tag, a["src"]))
        elif tag == "link" and a.get("href") and a.get("rel") != "canonical":
            self.refs.append(("link-tag", a["href"]))


def _fetch(url):
    try:
        with urllib.request.urlopen(url, timeout=30) as resp:
            return resp.status, resp.headers.get_content_type(), resp.read()
    except urllib.error.HTTPError as exc:
        return exc.code, None, b""


def crawl(base):
    """Every page reachable from the home page; returns the list of problems."""
    problems, pages, seen = [], {}, set()
    todo = [urljoin(base, "index.html")]
    resources = {}
    while todo:
        url = todo.pop()
        if url in seen:
            continue
        seen.add(url)
        status, ctype, body = _fetch(url)
        if status != 200:
            problems.append(f"{url}: HTTP {status}")
            continue
        if ctype != "text/html":
            continue
        text = body.decode("utf-8", errors="replace")
        parser = _Links()
        parser.feed(text)
        pages[url] = (parser, text)
        shown = "".join(parser.text)
        if TRACEBACK.search(shown):
            problems.append(f"{url}: the page holds a Python traceback")
        raw = RAW_TEX.search("".join(parser.prose))
        if raw:
            problems.append(f"{url}: TeX shown as text: {raw.group(0)}")
        for path in _machine_paths():
            if path in shown:
                problems.append(f"{url}: shows a path of the build machine ({path})")
        for kind, ref in parser.refs:
            target = urljoin(url, ref)
            if urlparse(target).netloc != urlparse(base).netloc or target.startswith(
                ("mailto:", "javascript:")
            ):
                continue  # external: not checked (no network), or not a link
            page, _ = urldefrag(target)
            if kind == "link" and page.endswith((".html", "/")):
                todo.append(page)
            elif page not in resources:
                resources[page] = _fetch(page)[0]
    for url, status in resources.items():
        if status != 200:
            problems.append(f"{unquote(url)}: HTTP {status} (an image, download or script)")
    # anchors: every internal #fragment must exist in its target page
    for url, (parser, _) in pages.items():
        for kind, ref in parser.refs:
            target = urljoin(url, ref)
            page, frag = urldefrag(target)
            if kind != "link" or not frag or urlparse(target).netloc != urlparse(base).netloc:
                continue
            if page in pages and unquote(frag) not in pages[page][0].ids:
                problems.append(f"{url}: link to a missing anchor {ref}")
    return problems, len(pages), len(resources)


# ----------------------------------------------------------------- the browser
class Chromium:
    """Headless Chromium driven over the DevTools protocol (one tab)."""

    def __init__(self, exe):
        import websocket

        self.profile = tempfile.mkdtemp(prefix="faultnet-check-site-")
        self.proc = subprocess.Popen(
            [
                exe,
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--no-first-run",
                "--hide-scrollbars",
                "--remote-debugging-address=127.0.0.1",
                "--remote-debugging-port=0",
                f"--user-data-dir={self.profile}",
                "about:blank",
            ],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        port_file = Path(self.profile) / "DevToolsActivePort"
        deadline = time.monotonic() + 60
        while not (port_file.exists() and port_file.read_text().count("\n") >= 1):
            if self.proc.poll() is not None or time.monotonic() > deadline:
                self.close()
                raise RuntimeError(f"{exe} did not start its DevTools endpoint")
            time.sleep(0.1)
        port = port_file.read_text().split()[0]
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list", timeout=30) as resp:
            tabs = [t for t in json.load(resp) if t.get("type") == "page"]
        self.ws = websocket.create_connection(
            tabs[0]["webSocketDebuggerUrl"], timeout=120, suppress_origin=True
        )
        self.next_id = 0
        self.events = []
        self.call("Page.enable")
        self.call("Runtime.enable")
        self.call(
            "Emulation.setDeviceMetricsOverride",
            width=1280,
            height=900,
            deviceScaleFactor=1,
            mobile=False,
        )

    def call(self, method, **params):
        self.next_id += 1
        mid = self.next_id
        self.ws.send(json.dumps({"id": mid, "method": method, "params": params}))
        while True:
            msg = json.loads(self.ws.recv())
            if msg.get("id") == mid:
                if "error" in msg:
                    raise RuntimeError(f"{method}: {msg['error']}")
                return msg.get("result", {})
            self.events.append(msg)

    def load(self, url):
        """Navigate and wait for the load event; return the page's image and text report."""
        self.events.clear()
        self.call("Page.navigate", url=url)
        deadline = time.monotonic() + 60
        while not any(e.get("method") == "Page.loadEventFired" for e in self.events):
            if time.monotonic() > deadline:
                raise RuntimeError(f"{url} did not finish loading in 60 s")
            self.events.append(json.loads(self.ws.recv()))
        res = self.call(
            "Runtime.evaluate", expression=_WAIT_FOR_IMAGES, awaitPromise=True, returnByValue=True
        )
        return json.loads(res["result"]["value"])

    def screenshot(self, path):
        size = self.call("Page.getLayoutMetrics")["cssContentSize"]
        height = min(int(size["height"]), 8000)
        shot = self.call(
            "Page.captureScreenshot",
            format="png",
            captureBeyondViewport=True,
            clip={"x": 0, "y": 0, "width": 1280, "height": height, "scale": 1},
        )
        Path(path).write_bytes(base64.b64decode(shot["data"]))

    def close(self):
        with contextlib.suppress(Exception):
            self.ws.close()
        if self.proc.poll() is None:
            self.proc.terminate()
            with contextlib.suppress(subprocess.TimeoutExpired):
                self.proc.wait(10)
            if self.proc.poll() is None:
                self.proc.kill()
        shutil.rmtree(self.profile, ignore_errors=True)


def browse(base, shots, exe):
    problems = []
    shots.mkdir(parents=True, exist_ok=True)
    browser = Chromium(exe)
    try:
        for name, path in PAGES:
            url = urljoin(base, path)
            report = browser.load(url)
            bad = [img["src"] for img in report["images"] if not img["ok"]]
            problems += [f"{path}: image did not load in the browser: {src}" for src in bad]
            if TRACEBACK.search(report["text"]):
                problems.append(f"{path}: the rendered page shows a Python traceback")
            if not report["images"] and name not in ("api-simulate", "choosing-rtol"):
                problems.append(f"{path}: no image on the page")
            drawn = [i for i in report["images"] if i["ok"] and "math" in i.get("cls", "")]
            if name == "model" and len(drawn) < MIN_EQUATIONS:
                problems.append(f"{path}: {len(drawn)} drawn equations, fewer than {MIN_EQUATIONS}")
            out = shots / f"{name}.png"
            browser.screenshot(out)
            print(
                f"  {path}: '{report['title']}', {len(report['images'])} images "
                f"({len(bad)} broken) -> {out}"
            )
    finally:
        browser.close()
    return problems


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--site", default=HERE / "_build" / "html", type=Path, help="built site")
    ap.add_argument("--shots", default=HERE / "_build" / "screenshots", type=Path)
    ap.add_argument("--chromium", default=None, help="browser executable (default: chromium)")
    args = ap.parse_args(argv)
    if not (args.site / "index.html").is_file():
        print(f"no built site in {args.site}: run sphinx-build first", file=sys.stderr)
        return 2
    exe = args.chromium or shutil.which("chromium") or shutil.which("chromium-browser")
    if exe is None:
        print("chromium not found: apt-get install chromium (or --chromium PATH)", file=sys.stderr)
        return 2
    with serve(args.site) as base:
        print(f"serving {args.site} at {base}")
        problems, n_pages, n_files = crawl(base)
        print(f"crawled {n_pages} pages and {n_files} other files")
        problems += browse(base, args.shots, exe)
    if problems:
        print(f"{len(problems)} problems:", file=sys.stderr)
        for p in problems:
            print(f"  {p}", file=sys.stderr)
        return 1
    print(f"site OK; screenshots in {args.shots}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
