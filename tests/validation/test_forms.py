"""The stability study's textbook forms: with nothing put back they are the engine, bit for bit; put back, they fail.

The study (``lighting-explorer report stability``) calls the engine's own careful forms and writes out
only the earlier and textbook ones (:mod:`lighting.validation.forms`).  These checks keep the two
joined in the fast loop: a change to a model that the study's compositions no longer follow shows here.
"""

import math

import numpy as np
import pytest

from lighting import BlinnPhong
from lighting.models import Geometry
from lighting.validation import cases as vcases
from lighting.validation import forms


def _quick_geometry(dtype):
    cases = vcases.brdf_cases(True)
    return Geometry(*(np.array([getattr(c, x) for c in cases], dtype=dtype) for x in "nlv"))


def _cook_torrance_specs():
    # The models whose earlier forms the study puts back: isotropic, V-cavity or separable Smith.
    return [s.model for s in vcases.brdf_specs() if s.model.name == "cook-torrance" and not s.general]


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_cook_torrance_with_nothing_put_back_is_the_engine_bit_for_bit(dtype):
    g = _quick_geometry(dtype)
    models = _cook_torrance_specs()
    assert {(m.ndf, m.geometry, m.fresnel) for m in models} >= {
        (ndf, geo, fr) for ndf in ("beckmann", "ggx") for geo in ("v-cavity", "smith") for fr in ("schlick", "none")
    }
    for m in models:
        engine = m.eval_geometry(g)
        assert engine.dtype == dtype
        assert np.array_equal(forms.cook_torrance_fr(m, g), engine), repr(m)
        # D "rounded to the dtype" is D itself in float64.
        if dtype == np.float64:
            assert np.array_equal(forms.cook_torrance_fr(m, g, {"d-dtype"}), engine), repr(m)


def test_with_quantities_lets_the_engine_derive_the_rest():
    g = _quick_geometry(np.float64)
    q = forms.cos_squared_half_angle(g)
    assert np.array_equal(q.n_dot_h, g.n_dot_h)  # derived by the engine from the same vectors
    c = np.clip(g.n_dot_h, -1, 1)
    assert np.array_equal(q.sin2_h, np.clip(1 - c * c, 0, 1))
    model = BlinnPhong(1.0, 100.0)
    assert np.array_equal(model.eval_geometry(forms.with_quantities(g)), model.eval_geometry(g))


@pytest.mark.parametrize("normalized", [False, True])
def test_blinn_phong_peak_form_fails_far_from_the_peak_where_the_engine_does_not(normalized):
    # l = v at 1e-8 rad above the horizon: h = l, n·h = n·l = 1e-8.  1 − n·h rounds away the
    # digits of n·h, so exp(log1p(−(1 − n·h))) is off by about u / 1e-8; the engine takes log(n·h).
    n = np.array([[0.0, 0.0, 1.0]])
    l = np.array([[1.0, 0.0, 1e-8]])  # noqa: E741
    model = BlinnPhong(1.0, 1.0, normalized=normalized)
    g = Geometry(n, l, l)
    true = 1e-8 * 3 / (2 * math.pi) if normalized else 1 / math.pi  # (e+2)/(2π) (n·h)^e, or (n·h)^e/(π n·l)
    engine = float(model.eval_geometry(g)[0, 0])
    textbook = float(forms.blinn_phong_peak_form_fr(model, g)[0, 0])
    assert engine == pytest.approx(true, rel=4e-16)
    assert abs(textbook - true) > 1e-10 * true


def test_batch_normalize_takes_one_path_for_the_whole_batch():
    from lighting.vec import normalize

    a = np.array([[0.02, 0.9, -0.71], [1e-170, 0.0, 0.0], [0.0, 0.0, 0.0]])
    # Alone, the vector takes the direct path, as the engine's per-vector choice does.
    assert np.array_equal(forms.batch_normalize(a[:1]), normalize(a[:1]))
    # Beside a tiny vector the whole batch takes the scaled path: the first row's bits change,
    # the engine's do not.
    out = forms.batch_normalize(a)
    assert np.array_equal(normalize(a)[0], normalize(a[:1])[0])
    assert not np.array_equal(out[0], normalize(a[:1])[0])
    assert out[0] == pytest.approx(normalize(a[:1])[0], rel=1e-15)
    assert out[1:].tolist() == [[1.0, 0.0, 0.0], [0.0, 0.0, 0.0]]
