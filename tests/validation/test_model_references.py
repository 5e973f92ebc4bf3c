"""The general reference path of the stability sweep, and the model arithmetic it made accurate.

The sweep found, at points where the true value is well conditioned (κ ≈ 1), that

* Oren–Nayar's full model lost ``1 − |cos Δφ|`` to a sine clamped at 1 (nearly opposite azimuths:
  4e-5 relative error in float32, 563 κu) and ``sin α − (2β/π)³`` to cancellation where both
  directions graze (2.35e7 κu in float64 at 1e-8 rad);
* Disney's Schlick weights ``(1 − cos)^5`` from a three-rounding quotient (17 ulp after the fifth
  power) and the subsurface's ``1 + (F_ss90 − 1) F_L`` cancelling at grazing pairs (15.5 κu).

Each point is checked here against the 80-digit reference with its condition number.
"""

import math

import mpmath
import numpy as np
import pytest

from lighting.models import create_model
from lighting.validation import cases as vcases
from lighting.validation import model_references as mr
from lighting.validation.general import general_table

pytestmark = pytest.mark.slow  # the stability sweep's 80-digit references of the newer models


def _ratio(model, n, l, v, dtype, form="eval"):  # noqa: E741
    """``|engine − true| / (max(κ,1) u)`` at one input rounded to ``dtype``."""
    n, l, v = (np.asarray(x, dtype=dtype) for x in (n, l, v))  # noqa: E741
    spec = vcases.ModelSpec("x", "x", model, {form: None}, True, "", general=True)
    ref = general_table([spec], [(0, form)], [(n.tolist(), l.tolist(), v.tolist(), False)], 80)
    got = float(getattr(model, form)(n, l, v)[0])
    true = ref["hi"][0, 0] + ref["lo"][0, 0]
    u = float(np.finfo(dtype).eps) / 2
    return abs(got - true) / true / (max(ref["kappa"][0, 0], 1.0) * u), ref["kappa"][0, 0]


def _grazing(eps, phi):
    return (math.cos(eps) * math.cos(phi), math.cos(eps) * math.sin(phi), math.sin(eps))


Z = (0.0, 0.0, 1.0)
ON_POINTS = [
    (_grazing(1e-4, 0.0), _grazing(1e-4, math.pi + 1e-3)),  # nearly opposite azimuths
    (_grazing(1e-8, 0.0), _grazing(1e-8, math.pi)),  # both grazing, opposite
    (_grazing(1e-4, 0.0), _grazing(1e-4, math.pi)),
    (_grazing(1e-6, 0.3), _grazing(1e-2, 0.3 + 1e-6)),  # nearly equal azimuths
]


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("sigma", [0.3, 1.5])
@pytest.mark.parametrize("k", range(len(ON_POINTS)))
def test_oren_nayar_full_at_grazing_and_opposite_azimuths(k, sigma, dtype):
    l, v = ON_POINTS[k]  # noqa: E741
    model = create_model("oren-nayar", kd=1.0, sigma=sigma, form="full")
    for form in ("eval", "eval_cos"):
        ratio, kappa = _ratio(model, Z, l, v, dtype, form)
        assert kappa < 10 and ratio <= 4, (form, ratio, kappa)


def test_oren_nayar_full_keeps_reciprocity_bit_for_bit():
    rng = np.random.default_rng(5)
    l, v = rng.normal(size=(2, 500, 3))  # noqa: E741
    l[:, 2], v[:, 2] = np.abs(l[:, 2]) * 1e-3, np.abs(v[:, 2])  # noqa: E741
    model = create_model("oren-nayar", kd=0.9, sigma=0.8, form="full")
    np.testing.assert_array_equal(model.eval(Z, l, v), model.eval(Z, v, l))


DISNEY_POINTS = [
    (_grazing(1e-4, 0.0), _grazing(1e-4, math.pi + 1e-3)),
    (_grazing(1e-8, 0.0), _grazing(1e-3 + 1e-8, math.pi)),
    (_grazing(1e-6, 0.0), (0.0, 0.0, 1.0)),
    ((0.6, 0.0, 0.8), (-0.6, 0.01, 0.8)),
]


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("setting", ["subsurface", "sheen", "diffuse", "metal smooth anisotropic"])
def test_disney_weights_and_subsurface_at_grazing_pairs(setting, dtype):
    prm = {
        "diffuse": dict(base_color=1.0, specular=0.0, roughness=0.5),
        "subsurface": dict(base_color=1.0, subsurface=1.0, specular=0.0, roughness=0.8),
        "sheen": dict(base_color=1.0, sheen=1.0, sheen_tint=0.0, specular=0.0, roughness=0.5),
        "metal smooth anisotropic": dict(base_color=1.0, metallic=1.0, roughness=0.0, anisotropic=1.0),
    }[setting]
    model = create_model("disney", **prm)
    for l, v in DISNEY_POINTS:  # noqa: E741
        for form in ("eval", "eval_cos"):
            ratio, _ = _ratio(model, Z, l, v, dtype, form)
            assert ratio <= 6, (l, v, form, ratio)


def test_condition_numbers_of_the_general_path_by_hand():
    # Lambert through Oren–Nayar at σ = 0: f_r = 1/π has κ = 0; f_r (n·l) has the κ of n·l, which for
    # n = z, l = (sin t, 0, cos t) is Σ |∂ ln(n·l)/∂ ln l_i| = 2 sin²t (the factor path's test value).
    t = 0.7
    model = create_model("oren-nayar", kd=1.0, sigma=0.0)
    l = (math.sin(t), 0.0, math.cos(t))  # noqa: E741
    spec = vcases.ModelSpec("x", "x", model, {"eval": None, "eval_cos": None}, True, "", general=True)
    ref = general_table([spec], [(0, "eval"), (0, "eval_cos")], [(Z, l, Z, False)], 80)
    assert ref["kappa"][0, 0] == 0.0
    assert ref["kappa"][0, 1] == pytest.approx(2 * math.sin(t) ** 2, rel=1e-12)
    # Ward's isotropic α counts once: f ∝ exp(−tan²θ_h/α²)/α², so |∂ ln f/∂ ln α| = |2 tan²θ_h/α² − 2|;
    # the directions add theirs (here 1.668...: 2.755 in all).
    m = create_model("ward", ks=1.0, alpha_x=0.3, normalization="duer")
    spec = vcases.ModelSpec("x", "x", m, {"eval": None}, True, "", general=True)
    lv = (math.sin(0.2), 0.0, math.cos(0.2))
    ref = general_table([spec], [(0, "eval")], [(Z, lv, lv, False)], 80)
    # κ = the α term + the directions' (l = v at 0.2 rad: h = l, tan θ_h = tan 0.2).
    x = math.tan(0.2) ** 2 / 0.09
    assert abs(2 * x - 2) < ref["kappa"][0, 0] < abs(2 * x - 2) + 2
    with mpmath.workdps(80):
        q = mr.frame(Z, lv, lv)
        assert float(q["vh"]) == pytest.approx(1.0, abs=1e-15) and float(q["nh"]) == pytest.approx(math.cos(0.2))
