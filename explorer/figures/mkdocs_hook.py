r"""MkDocs hook: draw the figure set while the documentation builds, and list it on the gallery page.

``mkdocs.yml`` names this file under ``hooks:``.  Before the build the hook writes the
figures (``explorer.figures.generate``) into ``build/gallery`` — or reuses the set
already there when its manifest was drawn from the same sources — and adds every PNG
to the site under ``gallery/``; the page ``gallery.md`` gets one section per figure
(title, image linked to its full-size file, caption, the slides it illustrates, its
parameters) in place of the line ``<!-- figures -->``, and the plausibility audit's section
also gets the audit itself as an HTML table, computed during the build.  So ``mkdocs build``
is the one command, and the gallery can never list a figure the set does not have.  The hook also copies MathJax
(``mkdocs.yml`` says from where and why) into the site, which typesets the formulas that ``pymdownx.arithmatex``
marks.

Every page may quote the figure set instead of copying numbers by hand: ``{{ figures.count }}``
is the number of figures, and ``{{ figures.NAME.KEY }}`` a value the figure ``NAME`` measured
while it was drawn (its sidecar's ``measured`` entry; ``KEY.SUBKEY`` reaches into a nested one),
with an optional format after a colon: ``{{ figures.ibl_error.median_error:.0% }}``, and
``{{ measured.NAME.KEY }}`` a value that one of this hook's quick measurements (:data:`MEASUREMENTS`)
computes while the site is built; the line
``<!-- audit -->`` becomes the plausibility audit's table, computed once per build, and
``<!-- audit: beyond_slides -->`` the same audit of the models beyond the slides; the line
``<!-- output: lighting-explorer ARGS -->`` becomes what that command prints (run in the build's own
process; for quick commands shown as examples), so a page never shows a stale sample; and the text between
``<!-- accuracy: summary -->`` and ``<!-- /accuracy -->`` gives way to the summary of the full
``report accuracy`` studies saved on the building machine, when every one is saved.  A
placeholder that names no figure or no value stops the build with one line naming the page; one
written with a backslash before it, ``\{{ figures.count }}``, is shown as it is, without the backslash.

Environment:

``LIGHTING_DOCS_QUICK=1``
    draw the quick set (low resolution; for CI, where the build is a check).
``LIGHTING_DOCS_FIGURES=DIR``
    use the figures already written to ``DIR`` (by ``lighting-explorer figures``) as they are.
"""

from __future__ import annotations

import hashlib
import html
import json
import os
import re
import sys

# explorer/figures/mkdocs_hook.py → the checkout
_ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
_MARKER = "<!-- figures -->"
# ``<!-- audit -->`` is the audit of the default cases; ``<!-- audit: slides -->`` its rows of the slides' models and
# ``<!-- audit: beyond_slides -->`` its rows of beyond_slides_cases() (one audit per build, split by row).
_AUDIT_RE = re.compile(r"<!-- audit(?::\s*(\w+))? -->")
_AUDIT_CASES = {
    "default": "default_cases()",
    "slides": "default_cases()` before `beyond_slides_cases()",
    "beyond_slides": "beyond_slides_cases()",
}
# ``<!-- output: lighting-explorer ARGS -->`` is what that command prints, run in this process while the page is built.
_OUTPUT_RE = re.compile(r"<!-- output: lighting-explorer ([^\n]*?) -->")
# ``<!-- accuracy: summary -->`` … ``<!-- /accuracy -->``: the text between is shown unless every study of
# ``report accuracy`` (full settings) is saved for this engine; then the summary of the saved studies replaces it.
_ACCURACY_RE = re.compile(r"<!-- accuracy: summary -->\n(.*?)<!-- /accuracy -->", re.S)
_PLACEHOLDER_RE = re.compile(r"(?<!\\)\{\{\s*(figures|measured)\.([\w.]+?)(?::([^}]*?))?\s*\}\}")
# Formats a figure links to when the figure folder has them (the docs build itself writes PNG only).
_LINKED_FORMATS = ("png", "svg", "pdf")
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
    # One worker process per core, up to four: even the quick set's figures take longer than a worker to start.
    jobs = max(1, min(4, os.cpu_count() or 1))
    # PNG for the page; SVG and PDF for a lecturer's slides and notes (linked under each figure).
    generate(out, formats=("png", "svg", "pdf"), quick=quick, jobs=jobs,
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
    # The gallery shows each figure's PNG and links only the other formats that were written.
    for rec in _state["manifest"]["figures"]:
        png = rec["files"].get("png")
        if not png or not os.path.isfile(os.path.join(folder, png)):
            raise ValueError(f"figure set {folder}: figure '{rec['name']}' has no PNG file; draw it with "
                             f"'lighting-explorer figures --format png --out {folder}'")  # fmt: skip


def on_files(files, config, **kwargs):
    """MkDocs event: add every figure's PNG to the site under ``gallery/``, and MathJax under ``javascripts/mathjax/``.

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
    import importlib.resources

    from mkdocs.structure.files import File

    # MathJax from the installed package (the docs extra), served by the site itself: no CDN, works from disk.
    mathjax = importlib.resources.files("mathjax") / "static" / "mathjax"
    for src, dest in ((mathjax / "es5" / "tex-svg-full.js", "tex-svg-full.js"), (mathjax / "LICENSE", "LICENSE")):
        files.append(File.generated(config, f"javascripts/mathjax/{dest}", abs_src_path=str(src)))
    for rec in _state["manifest"]["figures"]:
        for fmt in _LINKED_FORMATS:
            name = rec["files"].get(fmt)
            if name and os.path.isfile(os.path.join(_state["folder"], name)):
                files.append(
                    File.generated(config, f"gallery/{name}", abs_src_path=os.path.join(_state["folder"], name))
                )
    return files


def _section(rec) -> str:
    params = ", ".join(f"{k} = {json.dumps(v, ensure_ascii=False)}" for k, v in rec["parameters"].items())
    w, h = rec["size_px"]
    png = f"gallery/{rec['files']['png']}"
    # The picture is shown at column width and is itself the link to the full-size file.
    links = [f"[PNG]({png}) ({w}×{h} px)"]
    for fmt in ("svg", "pdf"):
        name = rec["files"].get(fmt)
        if name and os.path.isfile(os.path.join(_state["folder"], name)):
            links.append(f"[{fmt.upper()}](gallery/{name})")
    lines = [
        f"### {rec['title']} {{#{rec['name']}}}",
        "",
        f'[![{rec["title"]}]({png}){{ .gallery-img loading=lazy }}]({png} "Open the full-size figure")',
        "",
        rec["caption"],
        "",
        f"*Full size:* {' · '.join(links)}.  ",
        f"*Illustrates:* {rec['slides']}.  ",
        f"*Name:* `{rec['name']}` — `lighting-explorer figures --only {rec['name']}`"
        + ("" if rec["deterministic"] else f" (not pixel-reproducible: {rec['nondeterministic_reason']})")
        + ".  ",
        f"*Parameters:* {params or '—'}",
        "",
    ]
    if rec["name"] == "plausibility_table":
        lines += [_audit(), "The figure above is the same audit drawn for slides.", ""]
    return "\n".join(lines)


def _audit(cases: str = "default", page: str = "page") -> str:
    """An audit table, computed once per build (at the quick set's node count when the set is quick)."""
    if cases not in _AUDIT_CASES:
        raise ValueError(f"{page}: '<!-- audit: {cases} -->' names no audit; allowed: <!-- audit --> or "
                         f"<!-- audit: NAME --> with NAME one of {', '.join(_AUDIT_CASES)}")  # fmt: skip
    if "audit" not in _state:
        from lighting.analysis.audit import audit

        _state["audit"] = audit(samples=1024 if _state.get("manifest", {}).get("quick") else 4096)
    return audit_markdown(cases=cases, table=_state["audit"])


def command_output(args: str, page: str = "page") -> str:
    """What ``lighting-explorer ARGS`` prints, run now in this process, as a fenced text block.

    For the commands whose output a page shows as an example: the page always shows what the command
    prints today.  Only quick commands belong here: every page's generated content is computed in each build.

    Parameters
    ----------
    args : str
        The command line after ``lighting-explorer`` (split as a POSIX shell would).
    page : str
        The page's name, for the error message.

    Returns
    -------
    str
        A fenced ``text`` block holding the command's standard output.

    Raises
    ------
    ValueError
        When the command ends with a status other than 0 (the message names the page, the command and what
        it printed on its error stream).

    Examples
    --------
    >>> print(command_output("render --list").splitlines()[0])
    ```text
    """
    import contextlib
    import io
    import shlex

    if _ROOT not in sys.path:
        sys.path.insert(0, _ROOT)
    from explorer.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(shlex.split(args))
    if status != 0:
        raise ValueError(f"{page}: '<!-- output: lighting-explorer {args} -->': the command ended with status "
                         f"{status}: {err.getvalue().strip()[-300:]}")  # fmt: skip
    return "```text\n" + out.getvalue().rstrip("\n") + "\n```"


def _cell(text: str) -> str:
    return html.escape(str(text)).replace("|", "&#124;")


def accuracy_summary(fallback: str, folder: str | None = None) -> str:
    """The "cheapest method" table of the full ``report accuracy`` studies saved on this machine, or ``fallback``.

    Parameters
    ----------
    fallback : str
        What the page shows when a study is missing from the cache (for this engine and the full settings).
    folder : str, optional
        The cache folder (default :func:`explorer.reports.cache.cache_dir`).

    Returns
    -------
    str
        Markdown: a sentence saying where the numbers come from and the table as the report prints it.
    """
    if _ROOT not in sys.path:
        sys.path.insert(0, _ROOT)
    from explorer.reports.accuracy import format_summary
    from explorer.reports.cache import load_study
    from lighting.validation.accuracy import STUDY_NAMES, summary

    saved = [load_study(name, quick=False, folder=folder) for name in STUDY_NAMES]
    if any(s is None for s in saved):
        return fallback
    return (
        "The summary of the studies `lighting-explorer report accuracy` saved (full settings) on the machine that "
        "built this site, for this engine; its times are that machine's:\n\n```text\n"
        + format_summary(summary([s.study for s in saved])).strip("\n")
        + "\n```\n"
    )


def audit_markdown(samples: int = 4096, cases: str = "default", table=None) -> str:
    """The plausibility audit of the default cases (or of a part of them) as an HTML table, computed now.

    Parameters
    ----------
    samples : int
        Quadrature nodes per view angle for the albedo (as :func:`lighting.analysis.audit.audit`).
    cases : {"default", "slides", "beyond_slides"}
        Which rows: every one of :func:`~lighting.analysis.audit.default_cases`, those of the slides' models,
        or those of :func:`~lighting.analysis.audit.beyond_slides_cases` (the default cases end with them).
    table : AuditTable, optional
        The audit of the default cases already computed (then ``samples`` is not used).

    Returns
    -------
    str
        A short introduction and a ``<table>`` (in a ``<div class="audit-table">``): one row per model with the smallest
        value of ``f_r``, the reciprocity error, the albedo at normal incidence, its minimum and
        maximum over view angles (with the integration error) and the three verdicts.
    """
    from lighting.analysis.audit import AuditTable, audit, beyond_slides_cases

    if table is None:
        table = audit(samples=samples)
    beyond = {c.label for c in beyond_slides_cases()}
    if cases != "default":
        rows = [r for r in table if (r.label in beyond) == (cases == "beyond_slides")]
        table = AuditTable(rows, settings=table.settings)
    s = table.settings
    head = ["model", "parameters", "min f<sub>r</sub>", "recip. err", "ρ(0°)", "ρ min (θ)",
            "ρ max (θ) ± err", "positive", "reciprocal", "energy", "note"]  # fmt: skip
    rows = []
    for r in table:
        cells = [
            f"<td>{_cell(r.label)}</td>",
            f"<td><code>{_cell(r.params)}</code></td>",
            f'<td class="num">{r.min_value:.3g}</td>',
            f'<td class="num">{r.reciprocity:.1e}</td>',
            f'<td class="num">{r.albedo_normal:.4f}</td>',
            f'<td class="num">{r.albedo_min:.4f} ({r.theta_min_deg:g}°)</td>',
            f'<td class="num">{r.albedo_max:.4f} ({r.theta_max_deg:g}°) ± {r.albedo_error:.0e}</td>',
        ]
        for ok in (r.positive, r.reciprocal, r.energy):
            cells.append(f'<td class="{"pass" if ok else "fail"}">{"pass" if ok else "FAIL"}</td>')
        cells.append(f"<td>{_cell(r.note)}</td>")
        rows.append("<tr>" + "".join(cells) + "</tr>")
    intro = (
        f"**The audit as a table** (`lighting.analysis.audit.audit()`, its rows of `{_AUDIT_CASES[cases]}`, "
        "computed while this page was built): "
        r"$\rho$ is the directional albedo $\int f_r\,(\mathbf n\cdot\mathbf l)\,d\omega_l$, the largest over RGB, "
        f"by {s.get('method', 'quadrature')} "
        f"with {s.get('samples')} nodes per angle over {s.get('view_angles')} view angles; reciprocity is "
        f"checked over {s.get('pairs')} direction pairs; energy fails when ρ max − err > 1 + {s.get('energy_tol')}."
    )
    return (
        intro
        + "\n\n"
        # Material styles tables without a class: the class goes on the wrapper, which scrolls sideways.
        + '<div class="audit-table md-typeset__scrollwrap"><div class="md-typeset__table">\n<table>\n<thead><tr>'
        + "".join(f"<th>{h}</th>" for h in head)
        + "</tr></thead>\n<tbody>\n"
        + "\n".join(rows)
        + "\n</tbody>\n</table>\n</div></div>"
    )


# --------------------------------------------------------------------------- numbers measured while the site is built
# Each must stay quick (it runs in every build); a page's ``{{ measured.NAME.KEY }}`` runs NAME once per build.


def _smooth_sky(d):
    """A smooth, coloured sky over the whole sphere (bright zenith, a horizon band, dim ground)."""
    import numpy as np

    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    return np.stack(
        [1.2 + 0.8 * z + 0.3 * x * y, 0.6 + 0.4 * np.sin(2 * x) + 0.2 * z * z, 0.3 + 0.5 * np.exp(-3 * (1 - z))], -1
    )


def measure_delta_limit() -> dict:
    r"""How fast the glossy models tend to the ideal mirror as their lobes sharpen, measured now.

    Under :func:`_smooth_sky` (the sky of ``tests/integrate/test_delta.py``), ``n = ẑ``, views at 0°, 30°, 60° and
    75° in one plane, 4096 quadrature nodes, ``k_s = 0.8``: the largest relative difference (over RGB, relative to
    the largest channel) between each model's outgoing radiance and its mirror's ``R(cos θ_v) L(R_v)``.

    Returns
    -------
    dict
        ``ggx_err_a2``, ``ggx_err_a4``: Cook–Torrance GGX + Smith (Schlick, ``f0 = 0.04``) at ``α = 10⁻²`` and
        ``10⁻⁴``; ``ggx_c``: the largest ``err / (α² ln(1/α))`` over ``α = 10⁻² … 10⁻⁴``; ``phong_c``: the largest
        ``err · e`` of Phong with ``k_s (e+1)/2`` over ``e = 10³ … 10⁵``; ``blinn_phong_c`` and
        ``blinn_phong_c_view_deg``: the largest ``err · e`` of normalized Blinn–Phong with ``k_s/(4 cos²θ_v)`` over
        ``e = 10³, 10⁵`` and the view where it is reached.
    """
    import math

    import numpy as np

    from lighting.integrate import outgoing_radiance
    from lighting.lights.environment import FunctionEnvironment
    from lighting.models.brdf import BlinnPhong, CookTorrance, Phong
    from lighting.models.mirror import Mirror
    from lighting.vec import reflect

    sky = FunctionEnvironment(_smooth_sky)
    theta = np.radians([0.0, 30.0, 60.0, 75.0])
    views = np.stack([np.sin(theta), 0 * theta, np.cos(theta)], -1)
    n = np.array([0.0, 0.0, 1.0])
    ks, f0 = 0.8, 0.04

    def relative(model, mirror):
        want = mirror.reflectance(np.cos(theta)) * _smooth_sky(reflect(views, n))
        got = outgoing_radiance(model, sky, n, views, samples=4096)
        return np.max(np.abs(got - want), axis=-1) / np.max(want, axis=-1)

    ggx = {a: relative(CookTorrance(ks, a, f0, ndf="ggx", geometry="smith", fresnel="schlick"),
                       Mirror(ks, f0, "schlick")).max() for a in (1e-2, 1e-3, 1e-4)}  # fmt: skip
    phong = max((relative(Phong(ks * (e + 1) / 2, e), Mirror(ks)) * e).max() for e in (1e3, 1e4, 1e5))
    # Normalized Blinn–Phong's k_s depends on the view (its limit is a mirror of 4 k_s cos²θ_v): one view at a time.
    bp = np.max([[relative(BlinnPhong(ks / (4 * c * c), e, normalized=True), Mirror(ks))[i] * e
                  for i, c in enumerate(np.cos(theta))] for e in (1e3, 1e5)], axis=0)  # fmt: skip
    return {
        "ggx_err_a2": float(ggx[1e-2]),
        "ggx_err_a4": float(ggx[1e-4]),
        "ggx_c": float(max(err / (a * a * math.log(1 / a)) for a, err in ggx.items())),
        "phong_c": float(phong),
        "blinn_phong_c": float(bp.max()),
        "blinn_phong_c_view_deg": float(np.degrees(theta[int(np.argmax(bp))])),
    }


def measure_albedo_table() -> dict:
    r"""The Kulla–Conty albedo tables against the direct integral, measured now.

    Returns
    -------
    dict
        ``max_error`` and ``rms_error``: ``|E_table − E|`` at ``points`` random off-grid points (seeded; 100 per
        table, ``θ_v ≤ 85°``, ``α ∈ [0.01, 1]``) over the four tables; ``grazing_max_error``: the largest at views
        from 85° to 89.9° and ``α`` from 0.1 to 1; ``blinn_phong_85_smith`` and ``blinn_phong_85_correlated``: the
        albedo of Cook–Torrance with the Blinn–Phong NDF, ``F = 1``, ``α = 1``, at 85°, with the separable and the
        height-correlated Smith G.
    """
    import math

    import numpy as np

    from lighting.integrate import directional_albedo
    from lighting.models import energy
    from lighting.models.cook_torrance import CookTorrance

    rng = np.random.default_rng(17)
    errors, grazing = [], []
    mu_g = np.cos(np.radians(np.linspace(85.0, 89.9, 15)))
    alpha_g = np.linspace(0.1, 1.0, 5)[:, None]
    for ndf in energy.NDFS:
        for geo in energy.GEOMETRIES:
            table = energy.albedo_table(ndf, geo)
            mu = rng.uniform(math.cos(math.radians(85.0)), 1.0, 100)
            alpha = rng.uniform(0.01, 1.0, 100)
            errors.append(np.abs(table.E(mu, alpha) - energy.microfacet_albedo(ndf, geo, mu, alpha)))
            grazing.append(np.abs(table.E(mu_g, alpha_g) - energy.microfacet_albedo(ndf, geo, mu_g, alpha_g)).max())
    err = np.concatenate(errors)

    def blinn_phong(geometry):
        model = CookTorrance(1.0, 1.0, 1.0, ndf="blinn-phong", geometry=geometry, fresnel="none")
        return float(directional_albedo(model, math.radians(85.0))[0])

    return {
        "max_error": float(err.max()),
        "rms_error": float(np.sqrt(np.mean(err**2))),
        "points": int(err.size),
        "grazing_max_error": float(max(grazing)),
        "blinn_phong_85_smith": blinn_phong("smith"),
        "blinn_phong_85_correlated": blinn_phong("smith-correlated"),
    }


MEASUREMENTS = {"delta_limit": measure_delta_limit, "albedo_table": measure_albedo_table}


def measured(name: str) -> dict:
    """The values of measurement ``name`` of :data:`MEASUREMENTS`, computed once per build."""
    cache = _state.setdefault("measured", {})
    if name not in cache:
        if _ROOT not in sys.path:
            sys.path.insert(0, _ROOT)
        cache[name] = MEASUREMENTS[name]()
    return cache[name]


def fill_placeholders(markdown: str, manifest: dict, page: str = "page", measurements=None) -> str:
    """Replace the placeholders in a page by the values the figure set was drawn with, or measured now.

    Parameters
    ----------
    markdown : str
        The page's Markdown.
    manifest : dict
        The figure set's ``figures.json``.
    page : str
        The page's name, for the error message.
    measurements : dict, optional
        Measurement name → function returning its values (default :data:`MEASUREMENTS`); each is run at most
        once per build, when a page first names it.

    Returns
    -------
    str
        The Markdown with ``{{ figures.count }}`` as the number of figures,
        ``{{ figures.NAME.KEY[:FORMAT] }}`` as the value ``KEY`` of figure ``NAME``'s ``measured``
        entry and ``{{ measured.NAME.KEY[:FORMAT] }}`` as the value ``KEY`` of measurement ``NAME``, formatted
        with ``FORMAT`` (Python's format specification) when one is given.

    Raises
    ------
    ValueError
        For a figure, a measurement or a value that does not exist, or a format the value does not take; the
        message names the page, the placeholder and what is allowed.

    Examples
    --------
    >>> m = {"figures": [{"name": "f", "measured": {"err": 0.1234, "by": {"a": 2}}}]}
    >>> fill_placeholders("{{ figures.count }} figures; {{ figures.f.err:.1% }}, {{ figures.f.by.a }}", m)
    '1 figures; 12.3%, 2'
    >>> fill_placeholders("{{ measured.t.x:.2e }}", m, measurements={"t": lambda: {"x": 0.000123}})
    '1.23e-04'
    >>> fill_placeholders(r"write \\{{ figures.count }}", m)
    'write {{ figures.count }}'
    """
    by_name = {rec["name"]: rec for rec in manifest["figures"]}
    measurements = MEASUREMENTS if measurements is None else measurements
    done = {}

    def value(m):
        source, path, spec = m.group(1), m.group(2).split("."), m.group(3)
        where = f"{page}: placeholder '{m.group(0)}'"
        if source == "figures" and path == ["count"] and spec is None:
            return str(len(manifest["figures"]))
        if source == "figures":
            rec = by_name.get(path[0])
            if rec is None:
                raise ValueError(f"{where}: no figure '{path[0]}' in the figure set; allowed: figures.count or "
                                 f"figures.NAME.KEY with NAME one of {', '.join(by_name)}")  # fmt: skip
            v, what = rec.get("measured", {}), f"figure '{path[0]}'"
        else:
            if path[0] not in measurements:
                raise ValueError(f"{where}: no measurement '{path[0]}'; allowed: measured.NAME.KEY with NAME one of "
                                 f"{', '.join(measurements)}")  # fmt: skip
            if path[0] not in done:
                done[path[0]] = measured(path[0]) if measurements is MEASUREMENTS else measurements[path[0]]()
            v, what = done[path[0]], f"measurement '{path[0]}'"
        for i, key in enumerate(path[1:], 1):
            if not isinstance(v, dict) or key not in v:
                keys = ", ".join(v) if isinstance(v, dict) else "none (not a table)"
                raise ValueError(f"{where}: {what} measured no '{'.'.join(path[1:i + 1])}'; "
                                 f"allowed here: {keys}")  # fmt: skip
            v = v[key]
        if len(path) == 1 or isinstance(v, dict):
            raise ValueError(f"{where}: name one value of {what} ({source}.NAME.KEY)")
        try:
            return format(v, spec) if spec else str(v)
        except (TypeError, ValueError):
            raise ValueError(f"{where}: format '{spec}' does not apply to {v!r}") from None

    return _PLACEHOLDER_RE.sub(value, markdown).replace("\\{{", "{{")


def on_page_markdown(markdown, page, config, files, **kwargs):
    """MkDocs event: fill the figure set's placeholders on every page, and put the gallery on ``gallery.md``.

    The line ``<!-- figures -->`` of ``gallery.md`` becomes one section per figure.

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
    m = _state["manifest"]
    markdown = fill_placeholders(markdown, m, page.file.src_uri)
    name = page.file.src_uri
    markdown = _AUDIT_RE.sub(lambda mm: _audit(mm.group(1) or "default", name), markdown)
    markdown = _OUTPUT_RE.sub(lambda mm: command_output(mm.group(1), name), markdown)
    markdown = _ACCURACY_RE.sub(lambda mm: accuracy_summary(mm.group(1)), markdown)
    if page.file.src_uri != "gallery.md" or _MARKER not in markdown:
        return markdown
    intro = f"{len(m['figures'])} figures" + (" (quick set: low resolution)" if m.get("quick") else "") + ".\n\n"
    return markdown.replace(_MARKER, intro + "\n".join(_section(r) for r in m["figures"]))
