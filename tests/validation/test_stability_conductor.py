"""The conductor Fresnel term in the stability sweep, and ``report stability --docs``.

The sweep's ``CT conductor`` cases (Cook–Torrance GGX with the height-correlated G2 and the exact conductor
Fresnel term: gold channel by channel, ``η → 0``, huge ``k``, ``k = 0``) and their 80-digit reference, and the
options that command refuses.  The family's rows in the quick sweep and the page the command writes are checked
on the sweep that ``test_stability.py`` runs once for every family.
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
