"""MkDocs hook: draw the figure set while the documentation builds, and list it on the gallery page.

``mkdocs.yml`` names this file under ``hooks:``.  Before the build the hook writes the
figures (``explorer.figures.generate``) into ``build/gallery`` — or reuses the set
already there when its manifest was drawn from the same sources — and adds every PNG
to the site under ``gallery/``; the page ``gallery.md`` gets one section per figure
(title, image, caption, the slides it illustrates, its parameters) in place of the
line ``<!-- figures -->``.  So ``mkdocs build`` is the one command, and the gallery can
never list a figure the set does not have.

Environment:

``LIGHTING_DOCS_QUICK=1``
    draw the quick set (low resolution; for CI, where the build is a check).
``LIGHTING_DOCS_FIGURES=DIR``
    use the figures already written to ``DIR`` (by ``lighting-explorer figures``) as they are.
"""

from __future__ import annotations

import hashlib
import json
import os
import sys

# explorer/figures/mkdocs_hook.py → the checkout
_ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
_MARKER = "<!-- figures -->"
_state: dict = {}


def _sources_digest() -> str:
    """A digest of the code the figures are drawn from: the engine, its example scenes and the figure modules.

    A changed engine or figure module means a fresh set; other front-end files do not matter.

    Returns
    -------
    str
        The first 16 hexadecimal digits of a SHA-256 over every such file's path and bytes.
    """
    h = hashlib.sha256()
    paths = []
    for folder in ("lighting", os.path.join("explorer", "figures")):
        for base, dirs, names in os.walk(os.path.join(_ROOT, folder)):
            dirs[:] = sorted(d for d in dirs if d != "__pycache__")
            paths += [os.path.join(base, n) for n in sorted(names) if not n.endswith(".pyc")]
    for path in paths:
        if os.path.isfile(path):
            with open(path, "rb") as f:
                h.update(os.path.relpath(path, _ROOT).encode() + b"\0" + f.read())
    return h.hexdigest()[:16]


def _figures_dir(log) -> str:
    given = os.environ.get("LIGHTING_DOCS_FIGURES")
    if given:
        return os.path.abspath(given)
    if _ROOT not in sys.path:
        sys.path.insert(0, _ROOT)  # the working tree's packages, not an installed copy
    from explorer.figures import generate

    quick = os.environ.get("LIGHTING_DOCS_QUICK", "") not in ("", "0")
    out = os.path.join(_ROOT, "build", "gallery-quick" if quick else "gallery")
    stamp = os.path.join(out, "sources.txt")
    digest = _sources_digest()
    if os.path.isfile(stamp) and os.path.isfile(os.path.join(out, "figures.json")):
        with open(stamp, encoding="utf-8") as f:
            if f.read().strip() == digest:
                log.info(f"gallery: reusing the figures in {out} (sources unchanged)")
                return out
    log.info(f"gallery: drawing the figure set into {out}{' (quick)' if quick else ''}")
    # The quick set is done faster in this process than worker processes take to start.
    jobs = 1 if quick else max(1, min(4, os.cpu_count() or 1))
    generate(out, formats=("png",), quick=quick, jobs=jobs,
             log=lambda name, sec: log.info(f"gallery: {name} ({sec:.1f} s)"))  # fmt: skip
    from explorer.output import atomic_write

    atomic_write(stamp, (digest + "\n").encode("ascii"), flag="gallery")
    return out


def on_pre_build(config, **kwargs):
    """MkDocs event: draw (or reuse) the figure set and read its manifest.

    Parameters
    ----------
    config : mkdocs.config.Config
        The site's configuration (unused).
    **kwargs
        Other event arguments.

    Returns
    -------
    None
    """
    import logging

    log = logging.getLogger("mkdocs.hooks.gallery")
    folder = _figures_dir(log)
    with open(os.path.join(folder, "figures.json"), encoding="utf-8") as f:
        _state["manifest"] = json.load(f)
    _state["folder"] = folder


def on_files(files, config, **kwargs):
    """MkDocs event: add every figure's PNG to the site under ``gallery/``.

    Parameters
    ----------
    files : mkdocs.structure.files.Files
        The site's files.
    config : mkdocs.config.Config
        The site's configuration.
    **kwargs
        Other event arguments.

    Returns
    -------
    mkdocs.structure.files.Files
        ``files`` with the figures added.
    """
    from mkdocs.structure.files import File

    for rec in _state["manifest"]["figures"]:
        png = rec["files"].get("png")
        if png:
            files.append(File.generated(config, f"gallery/{png}", abs_src_path=os.path.join(_state["folder"], png)))
    return files


def _section(rec) -> str:
    params = ", ".join(f"{k} = {json.dumps(v, ensure_ascii=False)}" for k, v in rec["parameters"].items())
    w, h = rec["size_px"]
    lines = [
        f"### {rec['title']} {{#{rec['name']}}}",
        "",
        f"![{rec['title']}](gallery/{rec['files']['png']})",
        "",
        rec["caption"],
        "",
        f"*Illustrates:* {rec['slides']}.  ",
        f"*Name:* `{rec['name']}` — `lighting-explorer figures --only {rec['name']}` ({w}×{h} px"
        + ("" if rec["deterministic"] else f"; not pixel-reproducible: {rec['nondeterministic_reason']}")
        + ").  ",
        f"*Parameters:* {params or '—'}",
        "",
    ]
    return "\n".join(lines)


def on_page_markdown(markdown, page, config, files, **kwargs):
    """MkDocs event: replace ``<!-- figures -->`` on ``gallery.md`` with one section per figure.

    Parameters
    ----------
    markdown : str
        The page's Markdown.
    page : mkdocs.structure.pages.Page
        The page.
    config, files
        The site's configuration and files (unused).
    **kwargs
        Other event arguments.

    Returns
    -------
    str
        The Markdown, with the gallery in place on ``gallery.md``.
    """
    if page.file.src_uri != "gallery.md" or _MARKER not in markdown:
        return markdown
    m = _state["manifest"]
    intro = f"{len(m['figures'])} figures" + (" (quick set: low resolution)" if m.get("quick") else "") + ".\n\n"
    return markdown.replace(_MARKER, intro + "\n".join(_section(r) for r in m["figures"]))
