"""The plausibility audit as a figure: one table row per audited model, sized to fit one slide.

Registered on import (see :mod:`explorer.figures.base`); drawn by :mod:`explorer.figures`, after the BRDF
figures of :mod:`explorer.figures.brdf` (lecture order).
"""

from __future__ import annotations

import math

from lighting.analysis.audit import audit

from .base import new_figure, register


@register(
    "plausibility_table",
    size="16:9",
    title="Physical plausibility of every model (the audit table)",
    caption=(
        "The plausibility audit (lighting.analysis.audit): for each model and parameter set, whether f_r is positive, "
        "reciprocal (largest relative |f(l,v) − f(v,l)| over {pairs} direction pairs) and energy conserving "
        "(directional albedo ρ = ∫ f_r (n·l) dω_l at most 1, by quadrature with {samples} nodes at each of "
        "{angles} view angles; ρ(0°) at normal incidence, ρ max with the angle where it occurs). Green: pass; "
        "red: FAIL. The slides' Phong BRDF fails reciprocity, and energy at low exponents; the normalized "
        "Blinn–Phong lobe used directly reflects up to 4×; Cook–Torrance passes with the 4 (n·v)(n·l) "
        "denominator and reflects 4/π too much with the slide's π (n·v)(n·l)."
    ),
    slides="CMSC 435: Physically plausible BRDF (positive, reciprocity, conservation of energy)",
)
def plausibility_table(q):
    """The audit table: albedo, reciprocity and energy conservation of every audited model.

    Parameters
    ----------
    q : explorer.figures.base.Quality
        Image sizes and sample counts (full or quick).

    Returns
    -------
    tuple
        ``(figure, measured)``: the Matplotlib figure and the numbers measured while drawing it
        (they fill the caption's fields and the sidecar).
    """
    table = audit(samples=q.audit_samples)
    head, cells, verdicts = audit_cells(table)
    fig = new_figure(layout=None)
    font = draw_table(fig, head, cells, verdicts)
    s = table.settings
    return fig, {"pairs": s["pairs"], "samples": s["samples"], "angles": s["view_angles"], "rows": len(cells),
                 "font_pt": font, "failures": [r.label for r in table if not r.plausible]}  # fmt: skip


def audit_cells(table):
    """The plausibility table's text: column titles, one row of cells per audited model, and the verdicts.

    Parameters
    ----------
    table : lighting.analysis.audit.AuditTable
        What :func:`lighting.analysis.audit.audit` returned.

    Returns
    -------
    head : list of str
        The column titles.
    cells : list of list of str
        One row per audited model: label, parameters, ρ(0°), ρ max with its angle, reciprocity error, the
        three verdicts ("pass" / "FAIL") and the note.
    verdicts : list of list
        Per cell: ``True`` / ``False`` for the three verdict columns, ``None`` elsewhere (see :func:`draw_table`).
    """
    head = ["model", "parameters", "ρ(0°)", "ρ max (θ)", "recip. err", "positive", "reciprocal", "energy", "note"]
    cells, verdicts = [], []
    for r in table:
        params = r.params.replace(" /4(n·v)(n·l)", "").replace(" /π(n·v)(n·l)", " /π(n·v)(n·l)")
        row = [r.label, params, f"{r.albedo_normal:.3f}", f"{r.albedo_max:.3f} ({r.theta_max_deg:g}°)",
               f"{r.reciprocity:.0e}", "pass" if r.positive else "FAIL", "pass" if r.reciprocal else "FAIL",
               "pass" if r.energy else "FAIL", r.note]  # fmt: skip
        cells.append(row)
        verdicts.append([None] * 5 + [r.positive, r.reciprocal, r.energy] + [None])
    return head, cells, verdicts


#: The table's type: as large as the slide allows, up to :data:`TABLE_MAX_PT`; never below :data:`TABLE_MIN_PT`
#: (10 pixels at 1280 pixels across a 16:9 slide).
TABLE_MAX_PT = 12.0
TABLE_MIN_PT = 7.5


def draw_table(fig, head, cells, verdicts, *, margin_in: float = 0.06) -> float:
    """Draw a table filling ``fig``: columns as wide as their text, type as large as the figure allows.

    The type size is the largest (up to :data:`TABLE_MAX_PT`) at which every column's widest text and
    every row fit the figure; the rows are spaced 1.45 lines apart (1.25 or 1.15 when that keeps
    the type at 9 pt or more). Cells
    holding a verdict are centred in bold on green ("pass") or red ("FAIL").

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        An empty figure without a layout engine (``layout=None``).
    head : list of str
        The column titles.
    cells : list of list of str
        The rows, one string per column.
    verdicts : list of list
        Per cell: ``True`` (pass), ``False`` (FAIL) or ``None`` (plain text).
    margin_in : float, optional
        The white margin around the table, in inches.

    Returns
    -------
    float
        The type size used, in points.

    Raises
    ------
    ValueError
        When the rows cannot fit at :data:`TABLE_MIN_PT` (naming the row count and the figure size).

    Examples
    --------
    >>> from matplotlib.figure import Figure
    >>> fig = Figure(figsize=(40 / 3, 7.5))
    >>> draw_table(fig, ["model", "energy"], [["Lambert", "pass"]] * 10, [[None, True]] * 10)
    12.0
    >>> draw_table(Figure(figsize=(40 / 3, 7.5)), ["model", "energy"], [["Lambert", "pass"]] * 50, [[None, True]] * 50)
    9.0
    >>> draw_table(Figure(figsize=(40 / 3, 7.5)), ["model"], [["Lambert"]] * 80, [[None]] * 80)
    Traceback (most recent call last):
    ValueError: a table of 80 rows does not fit a 13.3 x 7.5 in figure at 7.5 pt or more
    """
    from matplotlib.font_manager import FontProperties
    from matplotlib.patches import Rectangle
    from matplotlib.textpath import TextToPath

    ok, bad, plain, header = "#d4edda", "#f8d7da", "white", "#e9ecef"
    width_pt, height_pt = (x * 72.0 - 2 * margin_in * 72.0 for x in fig.get_size_inches())
    measure = TextToPath()
    ref = 10.0  # widths are measured at 10 pt and scale with the type size

    def text_width(text, bold):
        prop = FontProperties(family="DejaVu Sans", size=ref, weight="bold" if bold else "normal")
        return measure.get_text_width_height_descent(text, prop, ismath=False)[0]

    ncol = len(head)
    widths = [text_width(h, True) for h in head]
    for row, marks in zip(cells, verdicts, strict=True):
        for j, (text, mark) in enumerate(zip(row, marks, strict=True)):
            widths[j] = max(widths[j], text_width(text, mark is not None))
    pad = 0.4  # each side of a cell, in ems
    by_width = width_pt / (sum(widths) / ref + 2 * pad * ncol)
    rows = len(cells) + 1
    for pitch in (1.45, 1.25, 1.15):
        font = min(TABLE_MAX_PT, by_width, height_pt / (pitch * rows))
        if font >= 9.0:
            break
    font = math.floor(font * 4) / 4  # quarter points: the same size from run to run
    if font < TABLE_MIN_PT:
        raise ValueError(f"a table of {len(cells)} rows does not fit a {fig.get_figwidth():.3g} x "
                         f"{fig.get_figheight():.3g} in figure at {TABLE_MIN_PT:g} pt or more")  # fmt: skip
    # The width left over goes to every column in proportion to its text.
    spare = width_pt - (sum(widths) * font / ref + 2 * pad * font * ncol)
    cols = [w * font / ref + 2 * pad * font + spare * w / sum(widths) for w in widths]
    row_h = pitch * font
    x0 = margin_in * 72.0
    y0 = margin_in * 72.0 + max(0.0, (height_pt - rows * row_h) / 2)  # centred when the width decides
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_xlim(0, fig.get_figwidth() * 72.0)
    ax.set_ylim(fig.get_figheight() * 72.0, 0)  # points, from the top
    ax.axis("off")
    for i, (row, marks) in enumerate([(head, [None] * ncol), *zip(cells, verdicts, strict=True)]):
        y = y0 + i * row_h
        x = x0
        for j, (text, mark) in enumerate(zip(row, marks, strict=True)):
            face = header if i == 0 else (plain if mark is None else (ok if mark else bad))
            ax.add_patch(Rectangle((x, y), cols[j], row_h, facecolor=face, edgecolor="0.8", lw=0.6))
            style = {"fontsize": font, "va": "center", "parse_math": False}
            if i == 0:
                ax.text(x + pad * font, y + row_h / 2, text, fontweight="bold", **style)
            elif mark is None:
                ax.text(x + pad * font, y + row_h / 2, text, **style)
            else:
                ax.text(x + cols[j] / 2, y + row_h / 2, text, ha="center", fontweight="bold",
                        color="#1e6b34" if mark else "#a12a33", **style)  # fmt: skip
            x += cols[j]
    return font
