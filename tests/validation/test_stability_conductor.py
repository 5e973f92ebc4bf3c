"""The conductor Fresnel term in the stability sweep, and ``report stability --docs``.

The sweep's ``CT conductor`` family (Cook–Torrance GGX with the height-correlated G2 and the exact
conductor Fresnel term: gold channel by channel, ``η → 0``, huge ``k``, ``k = 0``) against its 80-digit
reference, and the command that writes the sweep's table into the documentation.
"""

from __future__ import annotations

import mpmath
import numpy as np
import pytest

from explorer.reports import stability as report_stability
from lighting.models import create_model
from lighting.models.fresnel import METALS
from lighting.validation import cases as vcases
from lighting.validation import model_references as mr
from lighting.validation import stability as st
from lighting.validation import tables as vtables


def _conductor_specs():
    return [s for s in st.brdf_specs() if s.family == "CT conductor"]


def test_the_sweep_holds_gold_channel_by_channel_and_the_extreme_indices():
    specs = _conductor_specs()
    eta, k = METALS["gold"]
    got = {(s.model._alpha, float(s.model.eta[0]), float(s.model.k[0])) for s in specs}
    want = {(0.1, eta[i], k[i]) for i in range(3)} | {(a, eta[1], k[1]) for a in (1.0, 1e-4)}
    want |= {(0.1, e, kk) for _, e, kk in vcases.CONDUCTOR_EXTREMES}
    assert got == want and len(specs) == 8
    for s in specs:
        m = s.model
        assert s.general and s.lobe == "D" and set(s.terms) == {"eval", "eval_cos", "classic", "D"}
        assert (m.fresnel, m.ndf, m.geometry, m.metal) == ("conductor", "ggx", "smith-correlated", "none")
        assert np.all(m.eta == m.eta[0]) and np.all(m.k == m.k[0])  # grey: the reference takes one channel
    # The extremes: η → 0, a huge k, and k = 0.
    assert min(e for _, e, _ in vcases.CONDUCTOR_EXTREMES) <= 1e-3
    assert max(kk for _, _, kk in vcases.CONDUCTOR_EXTREMES) >= 1e4
    assert any(kk == 0 for _, _, kk in vcases.CONDUCTOR_EXTREMES)
    # Appended after the other general families: the factor columns and the other rows keep their places.
    families = [s.family for s in st.brdf_specs()]
    assert families[-8:] == ["CT conductor"] * 8 and families.index("CT conductor") == len(families) - 8


@pytest.mark.parametrize(("eta", "k"), [(0.188, 3.40), (1e-3, 0.0), (0.2, 1e4), (1.5, 0.0)])
def test_the_reference_at_l_v_n_is_f0_over_4_pi_alpha_squared(eta, k):
    # l = v = n: D(n) = 1/(π α²), G2 = 1, F(1) = ((η − 1)² + k²)/((η + 1)² + k²), so f_r = F(1)/(4π α²).
    m = create_model("cook-torrance", ks=1.0, roughness=0.3, ndf="ggx", geometry="smith-correlated",
                     fresnel="conductor", eta=eta, k=k)  # fmt: skip
    assert mr.model_parameters(m) == {"ks": 1.0, "alpha": 0.3, "eta": eta, "k": k}
    assert mr.condition_parameters(m) == (("alpha", "eta", "k") if k else ("alpha", "eta"))
    with mpmath.workdps(80):
        q = mr.frame((0.0, 0.0, 1.0), (0.0, 0.0, 1.0), (0.0, 0.0, 1.0))
        got = mr.model_value(m, q, {name: mpmath.mpf(x) for name, x in mr.model_parameters(m).items()})
        e, kk = mpmath.mpf(eta), mpmath.mpf(k)
        f0 = ((e - 1) ** 2 + kk**2) / ((e + 1) ** 2 + kk**2)
        want = f0 / (4 * mpmath.pi * mpmath.mpf(0.3) ** 2)
        assert abs(got - want) <= want * mpmath.mpf(10) ** -70
        # Grazing incidence reflects everything; k = 0 is the dielectric seen from outside.
        assert mr.conductor_fresnel(0, eta, k) == 1
        if k == 0 and eta > 1:
            c = mpmath.mpf("0.3")
            ct = mpmath.sqrt(1 - (1 - c * c) / e**2)
            r_s, r_p = (c - e * ct) / (c + e * ct), (e * c - ct) / (e * c + ct)
            assert abs(mr.conductor_fresnel(c, eta, k) - (r_s**2 + r_p**2) / 2) < mpmath.mpf(10) ** -75


@pytest.fixture(scope="module")
def conductor_sweep():
    """The quick sweep of Lambert (the factor path needs a column) and the conductor family, both dtypes."""
    only = [s for s in st.brdf_specs() if s.family in ("Lambert", "CT conductor")]
    mp = pytest.MonkeyPatch()
    mp.setattr(st, "brdf_specs", lambda: only)
    mp.setattr(vtables, "brdf_specs", lambda: only)
    try:
        yield st.run(quick=True, workers=1, rearrangements=False)
    finally:
        mp.undo()


@pytest.mark.slow  # 80-digit references of the conductor family (the quick case set)
def test_the_conductor_family_meets_the_bound_in_both_dtypes(conductor_sweep):
    rows = [r for r in conductor_sweep.rows if r.model_family == "CT conductor"]
    assert {r.dtype for r in rows} == {"float32", "float64"}
    assert {r.case_family for r in rows} == set(st.CASE_FAMILIES)
    assert {r.model for r in rows} == {s.label for s in _conductor_specs()}
    assert all(r.passed for r in rows), [r.first_failure for r in rows if not r.passed]
    assert sum(r.nonfinite + r.negative + r.warnings for r in rows) == 0
    assert max(r.max_ratio for r in rows) <= st.BOUND_FACTOR
    for dt in ("float32", "float64"):
        assert sum(r.normal for r in rows if r.dtype == dt) > 1000
    # Reciprocity and the NDF's order along the peak sweeps are checked on these rows too.
    assert sum(r.recip_pairs for r in rows) > 0 and sum(r.recip_fail for r in rows) == 0
    assert sum(r.mono_pairs for r in rows) > 0 and sum(r.mono_fail for r in rows) == 0


@pytest.mark.slow  # runs the conductor sweep of the test above
def test_docs_writes_the_table_and_its_numbers_between_the_markers(conductor_sweep, tmp_path):
    page = tmp_path / "stability.md"
    page.write_text("intro\n\n" + report_stability.DOCS_START + "\nold table\n" + report_stability.DOCS_END
                    + "\n\nafter\n", encoding="utf-8")  # fmt: skip
    figure = tmp_path / "fig.png"
    figure.write_bytes(b"\x89PNG\r\n\x1a\nfigure")
    table = report_stability.format_table(conductor_sweep)
    written = report_stability.write_docs(conductor_sweep, table, page, figure)
    assert written == [page, tmp_path / "images" / "stability.png"]
    assert (tmp_path / "images" / "stability.png").read_bytes() == figure.read_bytes()
    text = page.read_text(encoding="utf-8")
    head, rest = text.split(report_stability.DOCS_START + "\n")
    block, tail = rest.split(report_stability.DOCS_END + "\n")
    assert head == "intro\n\n" and tail == "\nafter\n" and "old table" not in text
    assert block.startswith("```text\n" + table + "\n```\n\n")
    rows = conductor_sweep.rows
    total = sum(r.points for r in rows)
    counts = [sum(getattr(r, c) for r in rows) for c in ("normal", "ill", "edge", "zero", "under", "over")]
    assert sum(counts) == total
    para = block.split("\n```\n\n")[1].strip()
    assert para.startswith("In that run every row met the bound")
    worst = max(rows, key=lambda r: r.max_ratio)
    assert f"the worst ratio was {worst.max_ratio:.2f} ({worst.model}, `{worst.form}`" in para
    assert f"{counts[0]:,} normal values".replace(",", " ") in para
    assert f"{counts[3]:,} exact zeros".replace(",", " ") in para
    # Written again, the page changes only inside the markers.
    report_stability.write_docs(conductor_sweep, table, page)
    assert page.read_text(encoding="utf-8") == text


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--quick"], "--docs takes the default run (both dtypes, not --quick); got --quick with --docs"),
        (["--dtype", "float32"], "--docs takes the default run (both dtypes, not --quick); got --dtype float32"),
    ],
)
def test_docs_refuses_a_run_that_is_not_the_default_before_any_work(tmp_path, monkeypatch, capsys, argv, message):
    monkeypatch.setattr(st, "run", lambda **kw: pytest.fail("ran with a bad option"))
    page = tmp_path / "page.md"
    page.write_text(f"{report_stability.DOCS_START}\n{report_stability.DOCS_END}\n", encoding="utf-8")
    assert report_stability.main([*argv, "--out", str(tmp_path / "o"), "--docs", str(page)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("lighting-explorer: error: ") and message in err and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("text", ["no markers\n", "<!-- /stability -->\n<!-- stability: table -->\n",
                                  "<!-- stability: table -->\n<!-- stability: table -->\n<!-- /stability -->\n"])
def test_docs_refuses_a_page_without_its_markers_once_in_order(tmp_path, monkeypatch, capsys, text):
    monkeypatch.setattr(st, "run", lambda **kw: pytest.fail("ran with a bad option"))
    page = tmp_path / "page.md"
    page.write_text(text, encoding="utf-8")
    assert report_stability.main(["--out", str(tmp_path / "o"), "--docs", str(page)]) == 2
    err = capsys.readouterr().err
    assert "--docs page must hold" in err and str(page) in err and len(err.strip().splitlines()) == 1
    assert page.read_text(encoding="utf-8") == text
    assert report_stability.main(["--out", str(tmp_path / "o"), "--docs", str(tmp_path / "missing.md")]) == 2
    assert "--docs must name a readable UTF-8 page" in capsys.readouterr().err
