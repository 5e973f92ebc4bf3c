"""Polar slices and lobes at any light azimuth φ, in a given tangent frame, and with the view locked to the light.

* isotropic models: φ turns the plane of incidence and changes nothing (to 1e-12);
* Ward's anisotropic lobe: at φ = 0 the plane holds t and the slice is the closed form with α_x, at
  φ = 90° the one with α_y; a tangent turned by 90° swaps them too;
* the view lock (θ_v = θ_l, φ_v = φ_l): the retro-reflection slice ``f_r(d, d)``, in closed form for
  Phong (``k_s cos^e(2t) / (π cos t)``) and Lambert, and the lobe mesh's radius is the same function.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from lighting import BlinnPhong, Lambert, Phong
from lighting.analysis import lobe_mesh, lobe_peak, polar_slice, reciprocity_pair, theta_v_curve
from lighting.models import create_model


def _ward_closed_form(theta_l, t, alpha_in, alpha_across, ks=1.0):
    """Ward (1992) in the plane of incidence: h lies in the plane, so only the in-plane α counts.

    ``f = k_s exp(−tan²θ_h / α_in²) / (4π α_x α_y √(cos θ_l cos θ_v))`` with θ_v = |t| on the mirror side
    (t > 0) and on the light's side (t < 0); θ_h is half the signed angle between l and v in the plane.
    """
    theta_h = 0.5 * (t - theta_l)  # l at −θ_l, v at t: h at their mean
    cos_v = np.cos(t)
    out = np.zeros_like(t)
    ok = cos_v > 1e-12
    out[ok] = (ks * np.exp(-np.tan(theta_h[ok]) ** 2 / alpha_in**2)
               / (4 * math.pi * alpha_in * alpha_across * np.sqrt(math.cos(theta_l) * cos_v[ok])))  # fmt: skip
    return out


@pytest.mark.parametrize("model", ["lambert", "phong", "blinn-phong", "cook-torrance", "oren-nayar", "disney"])
def test_an_isotropic_slice_does_not_depend_on_phi(model):
    brdf = create_model(model)
    ref = polar_slice(brdf, 0.6, phi_in=0.0, n=181)
    for phi in (0.3, math.pi / 2, 2.0, -math.pi):
        s = polar_slice(brdf, 0.6, phi_in=phi, n=181)
        np.testing.assert_array_equal(s.angles, ref.angles)
        np.testing.assert_allclose(s.values, ref.values, rtol=1e-12, atol=1e-15)
    # A tangent changes nothing either (isotropic models ignore it).
    s = polar_slice(brdf, 0.6, phi_in=0.3, n=181, tangent=(0.0, 1.0, 0.0))
    np.testing.assert_allclose(s.values, ref.values, rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("theta_l", [0.0, 0.4, 1.2])
def test_ward_slices_at_phi_0_and_90_are_the_closed_form_with_alpha_x_and_alpha_y(theta_l):
    ax, ay = 0.12, 0.35
    ward = create_model("ward", ks=1.0, alpha_x=ax, alpha_y=ay, normalization="ward")
    along_t = polar_slice(ward, theta_l, phi_in=0.0, n=241, channel=0)
    along_b = polar_slice(ward, theta_l, phi_in=math.pi / 2, n=241, channel=0)
    t0, t1 = along_t.angles.astype(np.float64), along_b.angles.astype(np.float64)
    np.testing.assert_allclose(along_t.values, _ward_closed_form(theta_l, t0, ax, ay), rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(along_b.values, _ward_closed_form(theta_l, t1, ay, ax), rtol=1e-12, atol=1e-14)
    # The swap: Ward(α_x, α_y) at φ = 90° is Ward(α_y, α_x) at φ = 0 ...
    swapped = create_model("ward", ks=1.0, alpha_x=ay, alpha_y=ax, normalization="ward")
    s = polar_slice(swapped, theta_l, phi_in=0.0, n=241, channel=0, refine=False)
    b = polar_slice(ward, theta_l, phi_in=math.pi / 2, n=241, channel=0, refine=False)
    np.testing.assert_allclose(b.values, s.values, rtol=1e-12, atol=1e-14)
    # ... and so is the tangent turned by 90° (t = +y) at φ = 90°, measured from +x: the plane holds t again.
    turned = polar_slice(ward, theta_l, phi_in=math.pi / 2, n=241, channel=0, refine=False, tangent=(0, 1, 0))
    a = polar_slice(ward, theta_l, phi_in=0.0, n=241, channel=0, refine=False)
    np.testing.assert_allclose(turned.values, a.values, rtol=1e-12, atol=1e-14)
    assert along_t.values.max() != pytest.approx(along_b.values.max(), rel=1e-3) or theta_l == 0.0


def test_lock_is_the_retro_reflection_slice_in_closed_form():
    ks, e = 0.7, 30.0
    s = polar_slice(Phong(ks, e), 0.5, lock=True, n=181, channel=0)
    t = s.angles.astype(np.float64)
    # l = v = d(t): R_l·v = cos 2t, so f = k_s cos^e(2t) / (π cos t) where cos 2t > 0, else 0.
    c2 = np.cos(2 * t)
    expect = np.where((c2 > 0) & (np.cos(t) > 0), ks * np.maximum(c2, 0) ** e / (math.pi * np.cos(t)), 0.0)
    np.testing.assert_allclose(s.values, expect, rtol=1e-11, atol=1e-14)
    assert s.lock and s.angles[np.argmax(s.values)] == 0.0  # the retro peak of a specular lobe: at the normal
    # Lambert is flat under the lock too, and the fixed direction does not matter.
    lam = polar_slice(Lambert(0.6), 1.1, lock=True, n=61, channel=0, phi_in=0.8)
    inside = np.abs(lam.angles) < math.pi / 2
    np.testing.assert_allclose(lam.values[inside], 0.6 / math.pi, rtol=1e-14)
    assert np.all(lam.values[~inside] == 0)
    # A narrow lobe's retro peak (width w/2 about the normal) is sampled: the grid alone would miss it.
    narrow = polar_slice(Phong(1.0, 1e5), 0.3, lock=True, n=91, channel=0)
    assert narrow.values.max() == pytest.approx(1 / math.pi, rel=1e-12)
    assert np.sum(narrow.values > 0.5 / math.pi) >= 8


def test_lock_lobe_mesh_radius_is_the_retro_reflection():
    m = lobe_mesh(Phong(0.5, 20.0), (0.3, 0.0, 0.95), resolution=12, lock=True, channel=0)
    d = m.directions.astype(np.float64)
    ct = d[:, 2]
    c2 = 2 * ct**2 - 1  # cos 2θ: R_d·d for l = v = d
    expect = np.where(c2 > 0, 0.5 * np.maximum(c2, 0) ** 20 / (math.pi * ct), 0.0)
    np.testing.assert_allclose(m.values, expect, rtol=1e-10, atol=1e-14)
    assert m.values[0] == pytest.approx(0.5 / math.pi, rel=1e-13)  # vertex 0, the normal, is the peak


def test_tangent_and_lock_are_checked_by_name():
    with pytest.raises(ValueError, match="tangent must be"):
        polar_slice(Lambert(0.5), 0.3, tangent=(0.0, 0.0, 1.0))
    with pytest.raises(ValueError, match="tangent must be"):
        lobe_mesh(Lambert(0.5), (0, 0, 1), tangent=(1.0, float("nan"), 0.0))
    with pytest.raises(ValueError, match="lock must be"):
        polar_slice(Lambert(0.5), 0.3, lock="yes")


def test_phi_keeps_the_views_of_one_slice_at_one_peak_for_ward_along_its_axes():
    ward = create_model("ward", ks=1.0, alpha_x=0.05, alpha_y=0.3)
    for phi in (0.0, math.pi / 2):
        a, _ = reciprocity_pair(ward, 0.7, phi_in=phi, n=361, channel="luminance")
        c = theta_v_curve(ward, 0.7, phi_l=phi, n=361, channel="luminance")
        peak = lobe_peak(ward, (math.sin(0.7) * math.cos(phi), math.sin(0.7) * math.sin(phi), math.cos(0.7)))
        m = lobe_mesh(ward, (math.sin(0.7) * math.cos(phi), math.sin(0.7) * math.sin(phi), math.cos(0.7)),
                      resolution=16)  # fmt: skip
        assert a.values.max() == pytest.approx(peak.value, rel=1e-9)
        assert c.values.max() == pytest.approx(peak.value, rel=1e-9)
        assert m.values.max() == pytest.approx(peak.value, rel=1e-6)


def test_float32_and_grazing_stay_finite():
    for brdf in (BlinnPhong(1.0, 1e6), create_model("ward", alpha_x=1e-3, alpha_y=0.5)):
        s = polar_slice(brdf, np.float32(1.5707), phi_in=1.0, lock=True, n=101)
        assert s.values.dtype == np.float32 and np.all(np.isfinite(s.values))
        m = lobe_mesh(brdf, np.array([0.0, 1.0, 1e-6], np.float32), resolution=8, lock=True)
        assert m.values.dtype == np.float32 and np.all(np.isfinite(m.vertices))
