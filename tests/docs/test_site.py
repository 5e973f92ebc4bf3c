"""The documentation site as built: typeset mathematics, no reST left as text, every internal link resolves.

The site is built once per session (``mkdocs build --strict`` with ``LIGHTING_DOCS_QUICK=1``, the quick
figure set) into a temporary folder; the build draws that figure set unless ``build/gallery-quick`` already
holds it for the same sources, so those tests are marked slow (``LIGHTING_DOCS_SITE=DIR`` checks a site
already built instead). The formula conversion itself is tested directly, in the fast loop.
"""

from __future__ import annotations

import html
import os
import re
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "explorer" / "figures"))

import mkdocs_math  # noqa: E402  (the hook module, imported as MkDocs imports it: by path)

SPHINX_ROLE = re.compile(r":(func|class|meth|mod|attr|data|obj|exc):`")
# reST a reader would see as text: a role's name, with or without its backticks, and a literal's double backticks.
REST_RESIDUE = re.compile(
    r":(?:py:)?(?:func|class|meth|mod|attr|data|obj|exc|const|ref|doc|term|math|any):|``[^`]*?``|``"
)


def rest_residue(text: str) -> list[str]:
    """Each place where ``text`` shows reST markup, as the markup with up to 40 characters either side."""
    return [" ".join(text[max(0, m.start() - 40) : m.end() + 40].split()) for m in REST_RESIDUE.finditer(text)]


# --------------------------------------------------------------------------- the conversion itself


def test_inline_and_display_formulas_become_mathml():
    text, formulas = mkdocs_math.protect_math("a $f_r = k_d/\\pi$ b\n\n$$\n\\frac{1}{\\pi}\n$$\n")
    assert formulas == [("\n\\frac{1}{\\pi}\n", True), ("f_r = k_d/\\pi", False)]
    html = mkdocs_math.restore_math(f"<p>{text.split(chr(10))[0]}</p>\n<p>MATHTOKEN00000Z</p>", formulas)
    assert html.count("<math") == 2
    assert '<div class="math-display"><math alttext="\\frac{1}{\\pi}"' in html
    assert 'display="block"' in html and 'display="inline"' in html
    assert "<mfrac><mrow><mn>1</mn></mrow><mrow><mi>&#x003C0;</mi></mrow></mfrac>" in html
    assert "MATHTOKEN" not in html


def test_code_and_prices_are_not_mathematics():
    src = "`$x$` and\n\n```bash\necho $HOME $x$\n```\n\ncosts $5 and $6; a $ b $ c"
    text, formulas = mkdocs_math.protect_math(src)
    assert formulas == []
    assert text == src


def test_formula_across_a_line_break_but_not_across_paragraphs():
    _, formulas = mkdocs_math.protect_math("so $\\int f\n= 1$ here")
    assert formulas == [("\\int f\n= 1", False)]
    _, formulas = mkdocs_math.protect_math("one $a\n\nb$ two")
    assert formulas == []


def test_rest_roles_and_math_directive_become_html():
    page = (
        '<h3 id="lighting.scene.load_scene">load_scene</h3>'
        "<p>See :func:<code>load_scene</code>, :class:<code>~lighting.scene.load_scene</code>, "
        ":mod:<code>lighting._numeric</code> and <code>as :class:`PointLight`</code>; shape::</p>\n"
        '<div class="highlight"><pre><span></span><code>x</code></pre></div>'
        "<p>.. math::</p>\n"
        '<div class="highlight"><pre><span></span><code>E = \\frac{a}{b}\n</code></pre></div>'
    )
    out = mkdocs_math.rest_to_html(page)
    assert SPHINX_ROLE.search(out) is None and ":func:" not in out and ".. math::" not in out
    assert out.count('<a href="#lighting.scene.load_scene"><code>') == 2
    assert "<code>lighting._numeric</code>" in out  # no documented entry: code, no link
    assert "<code>as PointLight</code>" in out
    assert "shape:</p>" in out
    assert '<div class="math-display"><math alttext="E = \\frac{a}{b}"' in out


def test_literals_in_inline_code_lose_their_backticks_code_blocks_keep_them():
    page = (
        "<td><code>ndarray, shape ``theta_v.shape + (3,)`` (RGB), or Estimate</code></td>"
        "<td><code>``a`` and ``b``</code> ``c``</td>"
        '<div class="highlight"><pre><span></span><code>x = "``kept``"</code></pre></div>'
    )
    out = mkdocs_math.rest_to_html(page)
    assert "<code>ndarray, shape theta_v.shape + (3,) (RGB), or Estimate</code>" in out
    assert "<code>a and b</code>" in out
    assert '<code>x = "``kept``"</code></pre>' in out


def test_rest_residue_names_the_markup_and_passes_plain_text():
    assert rest_residue("a ``points`` may be ``None``") == ["a ``points`` may be ``None``"] * 2
    assert rest_residue("an odd `` pair") == ["an odd `` pair"]
    assert rest_residue("see :func:load_scene, and :py:class:`X`") == [
        "see :func:load_scene, and :py:class:`X`",
        "see :func:load_scene, and :py:class:`X`",
    ]
    assert rest_residue("a ratio 1:2:3, a label: value, `x` and Note: done") == []


def test_bad_formula_is_a_one_line_error_naming_it():
    with pytest.raises(ValueError, match=r"formula 'a\^': latex2mathml cannot read it"):
        mkdocs_math.to_mathml("a^", display=False)
    with pytest.raises(ValueError, match=r"formula '\\fracc\{1\}\{2\}': unknown command \\fracc"):
        mkdocs_math.to_mathml("\\fracc{1}{2}", display=True)
    with pytest.raises(ValueError, match="'&' outside split"):
        mkdocs_math.to_mathml("\\begin{aligned} a &= b \\\\ &= c \\end{aligned}", display=True)


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
        if tag in ("script", "style", "code", "pre", "math"):
            self._skip += 1
        if tag in ("script", "style", "pre", "math"):
            self._block += 1
        elif tag in ("p", "li", "td", "th", "div", "h1", "h2", "h3", "h4", "h5", "h6", "br", "tr"):
            self.visible.append("\n")
        self.stack.append(tag)

    def handle_endtag(self, tag):
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
    # Every $...$ of models.md is a <math> element; none is left as LaTeX source in the text.
    n_src = len(mkdocs_math.protect_math((ROOT / "docs" / "models.md").read_text(encoding="utf-8"))[1])
    assert html.count("<math ") == n_src >= 80
    assert html.count('<div class="math-display">') >= 10
    text = "".join(pages["models.html"].text)
    assert "$" not in text and "\\frac" not in text and "\\mathbf" not in text and "MATHTOKEN" not in text
    for page in ("opengl.html", "guide.html", "analysis.html", "stability.html", "api.html"):
        assert '<div class="math-display"><math' in (out / page).read_text(encoding="utf-8"), page


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
    # Roles became links to the documented objects.
    assert len([h for h in api.hrefs if h.startswith("#lighting.")]) > 300


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
