"""The documentation site as built: typeset mathematics, no reST left as text, every internal link resolves.

The site is built once per session (``mkdocs build --strict`` with ``LIGHTING_DOCS_QUICK=1``, the quick
figure set) into a temporary folder; the build draws that figure set unless ``build/gallery-quick`` already
holds it for the same sources, so those tests are marked slow (``LIGHTING_DOCS_SITE=DIR`` checks a site
already built instead). The site's Markdown (``pymdownx.arithmatex`` marks each formula for MathJax), the
docstrings' reST rewriting and MathJax's reading of formulas (in Node.js, from the copy the site ships) are
tested directly, in the fast loop.
"""

from __future__ import annotations

import html
import importlib.resources
import json
import os
import re
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

import griffe
import markdown
import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "explorer" / "figures"))

import docstring_rest  # noqa: E402  (the Griffe extension, imported as mkdocstrings imports it: by path)

SPHINX_ROLE = re.compile(r":(func|class|meth|mod|attr|data|obj|exc):`")
# reST a reader would see as text: a role's name, with or without its backticks, and a literal's double backticks.
REST_RESIDUE = re.compile(
    r":(?:py:)?(?:func|class|meth|mod|attr|data|obj|exc|const|ref|doc|term|math|any):|``[^`]*?``|``"
)
# What pymdownx.arithmatex (generic mode) makes of a formula: TeX between \( \) or \[ \] in a span or a div.
ARITHMATEX = re.compile(r'<(span|div) class="arithmatex">(.*?)</\1>', re.S)
MATHJAX_ES5 = importlib.resources.files("mathjax") / "static" / "mathjax" / "es5"


def rest_residue(text: str) -> list[str]:
    """Each place where ``text`` shows reST markup, as the markup with up to 40 characters either side."""
    return [" ".join(text[max(0, m.start() - 40) : m.end() + 40].split()) for m in REST_RESIDUE.finditer(text)]


def site_markdown(text: str) -> str:
    """``text`` as the site's pages are converted: Python-Markdown with ``mkdocs.yml``'s extensions."""
    exts = yaml.safe_load((ROOT / "mkdocs.yml").read_text(encoding="utf-8"))["markdown_extensions"]
    names = [e if isinstance(e, str) else next(iter(e)) for e in exts]
    configs = {next(iter(e)): next(iter(e.values())) for e in exts if isinstance(e, dict)}
    return markdown.Markdown(extensions=names, extension_configs=configs).convert(text)


def formulas(page_html: str) -> list[tuple[str, bool]]:
    """The TeX of every formula arithmatex marked in ``page_html``, with ``True`` for displayed ones."""
    return [(html.unescape(tex)[2:-2], tag == "div") for tag, tex in ARITHMATEX.findall(page_html)]


def typeset_errors(tex: list[tuple[str, bool]]) -> list[list[str]]:
    """The formulas MathJax (the site's copy, run by Node.js) cannot read, each with MathJax's message."""
    proc = subprocess.run(
        ["node", str(Path(__file__).with_name("mathjax_check.js")), str(MATHJAX_ES5)],
        input=json.dumps(tex),
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads(proc.stdout)


def rewritten(tmp_path: Path, modules: dict[str, str]) -> griffe.Module:
    """The package ``modules`` (name → source) as Griffe loads it with the site's docstring extension."""
    for name, source in modules.items():
        (tmp_path / "demo").mkdir(exist_ok=True)
        (tmp_path / "demo" / f"{name}.py").write_text(source, encoding="utf-8")
    ext = griffe.load_extensions(f"{docstring_rest.__file__}:RestRoles")
    return griffe.load("demo", search_paths=[str(tmp_path)], extensions=ext, docstring_parser="numpy")


# --------------------------------------------------------------------------- the conversion itself


def test_inline_and_display_formulas_become_arithmatex():
    out = site_markdown("a $f_r = k_d/\\pi$ b\n\n$$\n\\frac{1}{\\pi}\n$$\n")
    assert formulas(out) == [("f_r = k_d/\\pi", False), ("\n\\frac{1}{\\pi}\n", True)]
    assert out.count('class="arithmatex"') == 2
    assert '<div class="arithmatex">\\[\n\\frac{1}{\\pi}\n\\]</div>' in out
    assert '<span class="arithmatex">\\(f_r = k_d/\\pi\\)</span>' in out
    assert "$" not in out
    # MathJax reads both, as the page's script will.
    assert typeset_errors(formulas(out)) == []


def test_code_and_prices_are_not_mathematics():
    src = "`$x$` and\n\n```bash\necho $HOME $x$\n```\n\ncosts $5 and $6; a $ b $ c"
    out = site_markdown(src)
    assert formulas(out) == [] and "arithmatex" not in out
    text = re.sub(r"<[^>]+>", "", out)  # the highlighter's spans
    assert "<code>$x$</code>" in out and "echo $HOME $x$" in text and "costs $5 and $6; a $ b $ c" in text


def test_formula_across_a_line_break_but_not_across_paragraphs():
    assert formulas(site_markdown("so $\\int f\n= 1$ here")) == [("\\int f\n= 1", False)]
    assert formulas(site_markdown("one $a\n\nb$ two")) == []


def test_rest_roles_and_math_directive_become_markdown(tmp_path):
    pkg = rewritten(tmp_path, {
        "__init__": "from demo.scene import load_scene, PointLight\n",
        "_numeric": "",
        "scene": (
            "class PointLight:\n    pass\n\n\n"
            "def load_scene():\n"
            '    r"""See :func:`load_scene`, :class:`~demo.scene.load_scene`, :mod:`demo._numeric` and\n'
            "    ``as :class:`PointLight` ``; shape::\n\n        x\n\n    .. math::\n\n        E = \\frac{a}{b}\n"
            '    """\n'
        ),
    })  # fmt: skip
    doc = pkg["scene.load_scene"].docstring.value
    assert SPHINX_ROLE.search(doc) is None and ":func:" not in doc and ".. math::" not in doc
    # Roles become cross-references to the object's own path (linked when it is on a page, code otherwise).
    assert doc.count('<autoref identifier="demo.scene.load_scene" optional>`load_scene`</autoref>') == 2
    assert '<autoref identifier="demo._numeric" optional>`demo._numeric`</autoref>' in doc
    out = site_markdown(doc)
    assert "<code>as PointLight</code>" in out
    assert "shape:</p>" in out
    assert '<div class="arithmatex">\\[\nE = \\frac{a}{b}\n\\]</div>' in out


def test_literals_in_types_lose_their_backticks_code_blocks_keep_them(tmp_path):
    pkg = rewritten(tmp_path, {"__init__": (
        "def f(x, y):\n"
        '    """F.\n\n    Parameters\n    ----------\n'
        "    x : ndarray, shape ``theta_v.shape + (3,)`` (RGB), or Estimate\n        The ``x``.\n"
        "    y : ``a`` and ``b``\n        Y.\n\n    Examples\n    --------\n"
        '    >>> x = "``kept``"\n    """\n'
    )})  # fmt: skip
    fn = pkg["f"]
    params = next(s for s in fn.docstring.parsed if s.kind.value == "parameters").value
    assert [str(p.annotation) for p in params] == ["ndarray, shape theta_v.shape + (3,) (RGB), or Estimate", "a and b"]
    assert params[0].description == "The ``x``."  # prose keeps its literal: Markdown shows it as code
    assert '>>> x = "``kept``"' in fn.docstring.value


def test_rest_residue_names_the_markup_and_passes_plain_text():
    assert rest_residue("a ``points`` may be ``None``") == ["a ``points`` may be ``None``"] * 2
    assert rest_residue("an odd `` pair") == ["an odd `` pair"]
    assert rest_residue("see :func:load_scene, and :py:class:`X`") == [
        "see :func:load_scene, and :py:class:`X`",
        "see :func:load_scene, and :py:class:`X`",
    ]
    assert rest_residue("a ratio 1:2:3, a label: value, `x` and Note: done") == []


def test_bad_formula_is_a_one_line_error_naming_it():
    aligned = "\\begin{aligned} a &= b \\\\ &= c \\end{aligned}"
    errors = typeset_errors([("a^", False), ("\\fracc{1}{2}", True), ("\\frac{1}{2}", False), (aligned, True)])
    # Each bad formula is named with MathJax's one-line reason; '&' in aligned is read (the site may use it).
    assert errors == [
        ["a^", "Missing superscript or subscript argument"],
        ["\\fracc{1}{2}", "Undefined control sequence \\fracc"],
    ]


# --------------------------------------------------------------------------- the built site


class _Page(HTMLParser):
    """The ids, links, images and visible text of one HTML page."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.ids, self.hrefs, self.srcs, self.text = set(), [], [], []
        # What a reader sees as text, inline code included (``text`` leaves inline code out).
        self.visible = []
        self._skip = 0
        self._block = 0
        self._formula = None
        self.stack = []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if a.get("id"):
            self.ids.add(a["id"])
        if tag == "a" and a.get("href") is not None:
            self.hrefs.append(a["href"])
        if tag in ("img", "script") and a.get("src"):
            self.srcs.append(a["src"])
        if tag == "link" and a.get("href"):
            self.srcs.append(a["href"])
        if "arithmatex" in (a.get("class") or "").split():
            # A formula (text only, no inner tags) holds its TeX until MathJax typesets it: as MathML did, it counts
            # as typeset mathematics, not as text; its closing tag ends it.
            self._formula, tag = tag, "math"
        if tag in ("script", "style", "code", "pre", "math"):
            self._skip += 1
        if tag in ("script", "style", "pre", "math"):
            self._block += 1
        elif tag in ("p", "li", "td", "th", "div", "h1", "h2", "h3", "h4", "h5", "h6", "br", "tr"):
            self.visible.append("\n")
        self.stack.append(tag)

    def handle_endtag(self, tag):
        if tag == self._formula:
            self._formula, tag = None, "math"
        if tag in ("script", "style", "code", "pre", "math") and self._skip:
            self._skip -= 1
        if tag in ("script", "style", "pre", "math") and self._block:
            self._block -= 1

    def handle_data(self, data):
        if not self._skip:
            self.text.append(data)
        if not self._block:
            self.visible.append(data)


@pytest.fixture(scope="session")
def site(tmp_path_factory):
    given = os.environ.get("LIGHTING_DOCS_SITE")  # a site already built from this tree, to iterate on the checks
    if given:
        out = Path(given)
    else:
        out = tmp_path_factory.mktemp("site")
        env = dict(os.environ, LIGHTING_DOCS_QUICK="1", NO_MKDOCS_2_WARNING="1")
        proc = subprocess.run(
            [sys.executable, "-m", "mkdocs", "build", "--strict", "--quiet", "-d", str(out)],
            cwd=ROOT,
            env=env,
            capture_output=True,
            text=True,
        )
        assert proc.returncode == 0, proc.stderr[-3000:]
    pages = {}
    for path in out.rglob("*.html"):
        p = _Page()
        p.feed(path.read_text(encoding="utf-8"))
        pages[path.relative_to(out).as_posix()] = p
    return out, pages


@pytest.mark.slow
def test_models_page_has_typeset_mathematics(site):
    out, pages = site
    html = (out / "models.html").read_text(encoding="utf-8")
    # Every $...$ of models.md is a formula marked for MathJax; none is left as LaTeX source in the text.
    n_src = len(formulas(site_markdown((ROOT / "docs" / "models.md").read_text(encoding="utf-8"))))
    assert len(formulas(html)) == n_src >= 80
    assert html.count('<div class="arithmatex">') >= 10
    text = "".join(pages["models.html"].text)
    assert "$" not in text and "\\frac" not in text and "\\mathbf" not in text and "MATHTOKEN" not in text
    for page in ("opengl.html", "guide.html", "analysis.html", "stability.html", "api.html"):
        assert '<div class="arithmatex">\\[' in (out / page).read_text(encoding="utf-8"), page


@pytest.mark.slow
def test_mathjax_ships_with_the_site_and_reads_every_formula(site):
    out, pages = site
    script = "javascripts/mathjax/tex-svg-full.js"
    assert (out / script).stat().st_size > 1_000_000
    assert "Apache License" in (out / "javascripts" / "mathjax" / "LICENSE").read_text(encoding="utf-8")
    everything = []
    for name, page in sorted(pages.items()):
        found = formulas((out / name).read_text(encoding="utf-8"))
        if not found:
            continue
        everything += found
        # The configuration first, then MathJax itself, each from a path relative to the page (works from disk).
        rel = os.path.relpath(out / script, (out / name).parent).replace(os.sep, "/")
        config = rel.replace("mathjax/tex-svg-full.js", "mathjax-config.js")
        assert config in page.srcs and rel in page.srcs, name
        assert page.srcs.index(config) < page.srcs.index(rel), name
    assert len(everything) >= 150
    # Each formula of every page is one MathJax reads: none would show as an error.
    assert typeset_errors(everything) == []


@pytest.mark.slow
def test_no_rest_markup_in_any_pages_visible_text(site):
    _, pages = site
    found = [
        f"{name}: {snippet}" for name, page in sorted(pages.items()) for snippet in rest_residue("".join(page.visible))
    ]
    assert found == []


@pytest.mark.slow
def test_long_signatures_are_wrapped(site):
    # mkdocstrings formats a separate signature only when a formatter (Ruff or Black) is installed:
    # the docs extra brings Ruff. Unformatted, a signature is one line as long as all its parameters.
    out, _ = site
    api = (out / "api.html").read_text(encoding="utf-8")
    sigs = [
        html.unescape(re.sub(r"<[^>]+>", "", s))
        for s in re.findall(r'<div class="doc-signature highlight"><pre>(.*?)</pre>', api, re.S)
    ]
    assert len(sigs) > 300
    widest = max(sigs, key=lambda s: max(len(line) for line in s.splitlines()))
    assert max(len(line) for line in widest.splitlines()) <= 88, widest
    assert sum(s.count("\n") > 1 for s in sigs) > 50


@pytest.mark.slow
def test_no_rest_left_as_text(site):
    out, pages = site
    for name in pages:
        html = (out / name).read_text(encoding="utf-8")
        assert SPHINX_ROLE.search(html) is None, name
        assert re.search(r":(func|class|meth|mod|attr|data|obj|exc):<code>", html) is None, name
        assert ".. math::" not in html, name
    api = pages["api.html"]
    documented = {i for i in api.ids if i.startswith(("lighting.", "explorer."))}
    assert len(documented) > 300
    assert not [i for i in documented if any(part.startswith("_") for part in i.split("."))]
    # Roles became links to the documented objects; a role naming an object with no entry is code, unlinked.
    assert len([h for h in api.hrefs if h.startswith("#lighting.")]) > 300
    api_html = (out / "api.html").read_text(encoding="utf-8")
    assert re.search(r'<a class="autorefs autorefs-internal"[^>]*href="#lighting.vec.normalize"><code>', api_html)
    assert '<span title="lighting._budget.memory_budget"><code>lighting._budget.memory_budget</code></span>' in api_html


@pytest.mark.slow
def test_every_internal_link_resolves(site):
    out, pages = site
    broken = []
    for name, page in pages.items():
        if name == "404.html":  # served by a web server for any missing path: its links are site-absolute
            continue
        base = (out / name).parent
        for ref in page.hrefs + page.srcs:
            parts = urlsplit(ref)
            if parts.scheme or parts.netloc or ref.startswith(("mailto:", "javascript:")):
                continue
            target = (base / unquote(parts.path)).resolve() if parts.path else (out / name).resolve()
            rel = target.relative_to(out.resolve()).as_posix() if target.is_relative_to(out.resolve()) else None
            if rel is None or not target.exists():
                broken.append(f"{name}: {ref} (no file)")
                continue
            if target.is_dir():
                broken.append(f"{name}: {ref} (a directory: opened from disk it is a listing)")
                continue
            if parts.fragment and rel.endswith(".html") and unquote(parts.fragment) not in pages[rel].ids:
                broken.append(f"{name}: {ref} (no anchor)")
    assert broken == []


@pytest.mark.slow
def test_usable_from_disk_and_offline(site):
    out, pages = site
    for name in pages:
        html = (out / name).read_text(encoding="utf-8")
        assert "fonts.googleapis.com" not in html and "fonts.gstatic.com" not in html, name
        assert "cdn.jsdelivr.net" not in html and "unpkg.com" not in html, name
    # Search works from file://: the index ships as a script (the offline plugin), not fetched.
    assert (out / "search" / "search_index.js").is_file()
    nav = [h for h in pages["index.html"].hrefs if not urlsplit(h).scheme and not h.startswith("#")]
    assert "models.html" in nav and "api.html" in nav


@pytest.mark.slow
def test_gallery_enlargeable_and_audit_as_table(site):
    import json

    out, pages = site
    html = (out / "gallery.html").read_text(encoding="utf-8")
    manifest = json.loads((ROOT / "build" / "gallery-quick" / "figures.json").read_text(encoding="utf-8"))
    for rec in manifest["figures"]:
        png = f"gallery/{rec['files']['png']}"
        # the picture is a link to its own full-size file
        assert re.search(rf'<a href="{re.escape(png)}"[^>]*><img [^>]*src="{re.escape(png)}"', html), rec["name"]
        # and its vector forms, for slides and notes, are linked and shipped with the site
        for kind in ("svg", "pdf"):
            link = f"gallery/{rec['files'][kind]}"
            assert f'href="{link}"' in html and (out / link).stat().st_size > 1000, (rec["name"], kind)
    table = re.search(
        r'<div class="audit-table[^"]*"><div class="md-typeset__table">\s*<table>(.*?)</table>', html, re.S
    ).group(1)
    rows = {
        re.sub("<[^>]+>", "", r[0]): [re.sub("<[^>]+>", "", c) for c in r]
        for r in (re.findall(r"<td[^>]*>(.*?)</td>", row) for row in re.findall(r"<tr>(.*?)</tr>", table))
        if r
    }
    # Closed forms: Lambert's albedo is k_d = 1 at every angle; Phong with e = 0 reflects 2k_s/(e+1) = 2
    # at normal incidence and its division by n·l breaks reciprocity.
    assert rows["Lambert"][4] == "1.0000" and rows["Lambert"][7:10] == ["pass", "pass", "pass"]
    assert rows["Phong e=0"][4] == "2.0000" and rows["Phong e=0"][7:10] == ["pass", "FAIL", "FAIL"]
    assert rows["normalized B-P e=0"][4] == "1.0000"
