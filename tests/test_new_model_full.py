"""The audit table with Minnaert's model added, drawn on a slide (slow set; fast: test_new_model.py, which defines
the model and registers it)."""

import pytest
import test_new_model
from test_new_model import Minnaert, _smallest_text_pt

pytestmark = pytest.mark.slow  # the audit of every default case and six Minnaert rows, drawn and measured

#: The fast file's fixture (beside this file): Minnaert's model registered for the test, and unregistered after it.
minnaert = test_new_model.minnaert


def test_the_audit_table_with_it_fits_a_slide_every_cell_inside_its_box(minnaert):
    pytest.importorskip("matplotlib")
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    from explorer.figures.audit import TABLE_MIN_PT, audit_cells, draw_table
    from explorer.figures.base import SLIDE_SIZES
    from lighting.analysis.audit import AuditCase, audit, default_cases

    extra = [AuditCase(f"Minnaert k={k:g}", Minnaert(1.0, k), "2 kd/(k+1) at normal view") for k in (1, 2, 3, 4, 6, 8)]
    table = audit(default_cases() + extra, samples=256)
    head, cells, verdicts = audit_cells(table)
    assert [row[0] for row in cells[-6:]] == [c.label for c in extra]
    assert [float(row[2]) for row in cells[-6:]] == pytest.approx([2 / (k + 1) for k in (1, 2, 3, 4, 6, 8)], abs=5e-4)
    fig = Figure(figsize=SLIDE_SIZES["16:9"])
    font = draw_table(fig, head, cells, verdicts)
    assert font >= TABLE_MIN_PT and _smallest_text_pt(fig) == font
    renderer = FigureCanvasAgg(fig).get_renderer()
    (ax,) = fig.axes
    boxes = [p.get_window_extent(renderer) for p in ax.patches if isinstance(p, Rectangle)]
    texts = list(ax.texts)
    assert len(boxes) == len(texts) == (len(cells) + 1) * len(head)  # one box and one text per cell, header too
    page = fig.bbox
    for box, text in zip(boxes, texts, strict=True):
        inside = text.get_window_extent(renderer)
        assert box.x0 >= page.x0 - 0.5 and box.x1 <= page.x1 + 0.5 and box.y0 >= page.y0 - 0.5, text.get_text()
        if text.get_text():
            assert box.x0 - 0.5 <= inside.x0 and inside.x1 <= box.x1 + 0.5, text.get_text()
            assert box.y0 - 0.5 <= inside.y0 and inside.y1 <= box.y1 + 0.5, text.get_text()
