"""BRDF plots as data: polar slices, half/difference angles, 3D lobes.

Values are checked against the models' closed forms along the plotted curves,
against the symmetry laws (reciprocity, the (n·v)/(n·l) factor of the slides'
Phong BRDF), and meshes against the definition of a valid triangulation.
"""

import functools
import math

import mpmath as mp
import numpy as np
import pytest

from lighting import BlinnPhong, CookTorrance, Lambert, Phong, vec
from lighting.analysis import (
    LUMINANCE,
    dirs_to_half_diff,
    half_diff_image,
    half_diff_to_dirs,
    lobe_mesh,
    lobe_peak,
    lobe_width,
    polar_slice,
    reciprocity_pair,
    theta_d_curve,
    theta_h_curve,
    theta_v_curve,
)
from lighting.models.brdf import BRDF, cos_power
from lighting.models.oren_nayar import OrenNayar

N = np.array([0.0, 0.0, 1.0])
RNG = np.random.default_rng(20240531)


def sph(theta, phi=0.0):
    """Unit vector(s) at polar angle ``theta``, azimuth ``phi``, shape ``theta.shape + (3,)``."""
    t = np.asarray(theta, dtype=np.float64)
    return np.stack(np.broadcast_arrays(np.sin(t) * np.cos(phi), np.sin(t) * np.sin(phi), np.cos(t)), axis=-1)


def luminance(rgb):
    return rgb @ np.array(LUMINANCE)


def assert_lobe_close(got, ref, slope):
    """``got`` matches ``ref`` to the conditioning of a lobe sampled at double-precision angles.

    An angle carries one rounding (~2ε absolute); a lobe ``g(ψ)`` with
    ``|d log g / dψ| = slope`` turns that into a relative error ``2 ε · slope``.
    Subnormal results (below 1e-290) are compared absolutely.
    """
    eps = np.finfo(float).eps
    normal = ref > 1e-290
    rel = np.abs(got[normal] / ref[normal] - 1)
    bound = 2 * (2 * eps * slope[normal] + eps)
    assert np.all(rel <= bound), f"worst {np.max(rel / bound):.3g} × the bound"
    np.testing.assert_allclose(got[~normal], ref[~normal], rtol=0, atol=1e-300)


RECIPROCAL = [
    Lambert((0.2, 0.5, 0.7)),
    BlinnPhong(0.8, 50, normalized=True),
    BlinnPhong(1.0, 1e6, normalized=True),
    CookTorrance(1.0, 0.3, 0.04),
    CookTorrance((1.0, 0.5, 0.2), 0.05, (0.9, 0.6, 0.3), ndf="ggx", geometry="smith", fresnel="dielectric"),
    CookTorrance(1.0, 0.5, 0.5, ndf="blinn-phong", denominator="pi"),
    CookTorrance(1.0, 1e-6, 0.04),
]


# --------------------------------------------------------------------------- polar slices
@pytest.mark.parametrize("fixed", ["light", "view"])
@pytest.mark.parametrize("theta", [0.0, 0.6, 1.4])
def test_polar_slice_geometry(fixed, theta):
    phi = 0.9
    s = polar_slice(Lambert(1.0), theta, fixed=fixed, phi_in=phi, n=181)
    assert (s.fixed, s.plane, s.cosine, s.log) == (fixed, "incidence", None, False)
    np.testing.assert_array_equal(s.angles, np.linspace(-np.pi / 2, np.pi / 2, 181))
    np.testing.assert_allclose(np.linalg.norm(s.directions, axis=1), 1.0, rtol=1e-15)
    np.testing.assert_allclose(s.fixed_direction, sph(theta, phi), atol=1e-16)
    np.testing.assert_allclose(s.mirror_direction, vec.reflect(sph(theta, phi), N), atol=1e-15)

    # d(t) = (−sin t cos φ, −sin t sin φ, cos t): the fixed direction at −θ, its mirror at +θ.
    def d(t):
        return np.stack([-np.sin(t) * math.cos(phi), -np.sin(t) * math.sin(phi), np.cos(t)], axis=-1)

    np.testing.assert_allclose(s.directions[1:-1], d(s.angles[1:-1]), atol=1e-16)
    np.testing.assert_allclose(d(s.incident_angle), s.fixed_direction, atol=1e-15)
    np.testing.assert_allclose(d(s.mirror_angle), s.mirror_direction, atol=1e-15)
    assert s.mirror_angle == theta and s.incident_angle == -theta
    # The ends lie exactly on the horizon, where f_r = 0: the polar curve closes at the origin.
    assert np.all(s.directions[[0, -1], 2] == 0.0)
    assert np.all(s.values[[0, -1]] == 0.0) and np.all(s.values[1:-1] > 0)


@pytest.mark.parametrize("theta", [0.0, 0.35, 1.0, 1.5])
@pytest.mark.parametrize("e", [1.0, 40.0, 1000.0])
def test_phong_light_slice_matches_closed_form(theta, e):
    # In the incidence plane R_l sits at +θ, so R_l·v = cos(t − θ): f = ks cos^e(t − θ)_+ / (π cos θ).
    ks = np.array([0.9, 0.5, 0.25])
    s = polar_slice(Phong(ks, e), theta, phi_in=-2.0, n=181)
    t = s.angles[1:-1]
    with mp.workdps(40):
        ref = np.array([float(max(mp.cos(mp.mpf(x) - theta), 0) ** e / (mp.pi * mp.cos(theta))) for x in t])
    # d/dψ log cos^e ψ = e tan ψ, ψ the angle between R_l and v.
    slope = e * np.abs(np.tan(t - theta))
    for k in range(3):
        assert_lobe_close(s.values[1:-1, k] / ks[k], ref, slope)
    assert np.argmax(s.values[:, 0]) == np.argmin(np.abs(s.angles - theta))


@pytest.mark.parametrize("theta", [0.2, 1.1])
def test_phong_perpendicular_slice_matches_closed_form(theta):
    # Perpendicular plane: v = (−sin t sin φ, sin t cos φ, cos t), so R_l·v = cos θ cos t.
    e = 25.0
    s = polar_slice(Phong(1.0, e), theta, phi_in=0.4, plane="perpendicular", n=361, channel=0)
    t = s.angles[1:-1]
    with mp.workdps(40):
        ref = np.array([float((mp.cos(theta) * mp.cos(mp.mpf(x))) ** e / (mp.pi * mp.cos(theta))) for x in t])
    psi = np.arccos(math.cos(theta) * np.cos(t))  # the angle between R_l and v
    assert_lobe_close(s.values[1:-1], ref, e * np.tan(psi))
    assert s.mirror_angle == 0.0 and s.incident_angle == 0.0
    assert np.argmax(s.values) == 180  # the plane passes nearest to R_l at the normal


@pytest.mark.parametrize("fixed", ["light", "view"])
def test_lambert_slice_cosine_options(fixed):
    kd, theta = 0.6, 0.8
    t = np.linspace(-np.pi / 2, np.pi / 2, 91)[1:-1]
    cos_t = np.cos(t)
    plain = polar_slice(Lambert(kd), theta, fixed=fixed, n=91, channel="g").values[1:-1]
    light = polar_slice(Lambert(kd), theta, fixed=fixed, n=91, channel="g", cosine=True).values[1:-1]
    view = polar_slice(Lambert(kd), theta, fixed=fixed, n=91, channel="g", cosine="view").values[1:-1]
    np.testing.assert_allclose(plain, kd / math.pi, rtol=1e-15)
    # "× n·l": constant cos θ_in when the light is fixed, cos t when the light sweeps; "× n·v" the other way round.
    l_cos = math.cos(theta) if fixed == "light" else cos_t
    v_cos = cos_t if fixed == "light" else math.cos(theta)
    np.testing.assert_allclose(light, kd / math.pi * l_cos, rtol=1e-15)
    np.testing.assert_allclose(view, kd / math.pi * v_cos, rtol=1e-15)


def test_cosine_light_removes_phong_division():
    # f_r (n·l) of the slides' Phong BRDF is its classic term over π, computed without dividing.
    s = polar_slice(Phong(1.0, 8), 1.5, cosine="light", n=181, channel=0)
    t = s.angles[1:-1]
    np.testing.assert_allclose(s.values[1:-1], np.maximum(np.cos(t - 1.5), 0) ** 8 / math.pi, rtol=1e-12)


@pytest.mark.parametrize("model", RECIPROCAL, ids=repr)
@pytest.mark.parametrize("theta", [0.0, 0.4, 1.2, 1.55])
@pytest.mark.parametrize("plane", ["incidence", "perpendicular"])
def test_reciprocal_models_give_equal_slices(model, theta, plane):
    a, b = reciprocity_pair(model, theta, plane=plane, phi_in=0.7)
    assert (a.fixed, b.fixed) == ("light", "view")
    # The two paths round differently (h, v·h versus l·h); near grazing the 1/(n·l)(n·v) of
    # Cook–Torrance amplifies that rounding to ~1e-12, elsewhere the slices agree to ~1e-15.
    np.testing.assert_allclose(a.values, b.values, rtol=1e-11, atol=0)
    if plane == "incidence":  # the refined grid catches even a 1e-6-wide lobe
        assert np.any(a.values > 0)


@pytest.mark.parametrize("model", [Phong((1.0, 0.5, 0.2), 30), BlinnPhong(1.0, 30), Phong(1.0, 1e5)], ids=repr)
@pytest.mark.parametrize("theta", [0.0, 0.4, 1.2, 1.55])
def test_phong_slices_differ_by_the_cosine_ratio(model, theta):
    # f(l, v) / f(v, l) = (n·v)/(n·l): in the light slice n·v = cos t, n·l = cos θ_in.
    a, b = reciprocity_pair(model, theta, n=721)
    both = (a.values > 1e-290) & (b.values > 1e-290)  # subnormals carry too few digits for a ratio
    assert both.sum() >= 3 * 3
    ratio = (np.cos(a.angles)[:, None] / math.cos(theta)) * np.ones(3)
    np.testing.assert_allclose(a.values[both] / b.values[both], ratio[both], rtol=1e-14)
    assert np.array_equal(a.values > 0, b.values > 0)
    if theta > 0:
        assert not np.allclose(a.values, b.values, rtol=1e-3)


def test_channel_luminance_and_log():
    model = Lambert((0.2, 0.4, 0.9)) + Phong((0.5, 0.3, 0.1), 60)
    rgb = polar_slice(model, 0.5, n=73, refine=False).values
    assert rgb.shape == (73, 3)
    np.testing.assert_array_equal(polar_slice(model, 0.5, n=73, channel="b", refine=False).values, rgb[:, 2])
    np.testing.assert_array_equal(polar_slice(model, 0.5, n=73, channel=1, refine=False).values, rgb[:, 1])
    lum = polar_slice(model, 0.5, n=73, channel="luminance", refine=False).values
    np.testing.assert_allclose(lum, 0.2126 * rgb[:, 0] + 0.7152 * rgb[:, 1] + 0.0722 * rgb[:, 2], rtol=1e-15)
    logged = polar_slice(model, 0.5, n=73, channel="luminance", log=True, refine=False).values
    np.testing.assert_allclose(logged, [math.log10(1 + x) for x in lum], rtol=1e-14)
    # log10(1 + x) keeps tiny values: x = 1e-20 gives 1e-20 / ln 10, not 0.
    tiny = polar_slice(Lambert(1e-19), 0.3, n=5, channel=0, log=True).values
    np.testing.assert_allclose(tiny[1:-1], 1e-19 / math.pi / math.log(10), rtol=1e-14)


def test_slice_xy_is_the_polar_curve():
    s = polar_slice(Phong(1.0, 50), 0.5, n=181, refine=False)  # the uniform grid (refine adds the peak)
    xy = s.xy
    assert xy.shape == (181, 3, 2)
    np.testing.assert_allclose(xy[..., 0], s.values * np.sin(s.angles)[:, None], rtol=1e-15)
    np.testing.assert_allclose(xy[..., 1], s.values * np.cos(s.angles)[:, None], rtol=1e-15)
    assert polar_slice(Lambert(1.0), 0.5, n=9, channel=0).xy.shape == (9, 2)


def test_slice_dtypes():
    s32 = polar_slice(CookTorrance(1.0, 0.2, 0.5), np.float32(0.7), n=91)
    assert s32.values.dtype == s32.angles.dtype == s32.directions.dtype == np.float32
    s64 = polar_slice(CookTorrance(1.0, 0.2, 0.5), 0.7, n=91)
    assert s64.values.dtype == np.float64
    np.testing.assert_allclose(s32.values, s64.values, rtol=2e-5, atol=1e-6 * s64.values.max())
    assert polar_slice(Lambert(1.0), 0.7, n=5, dtype="float32").values.dtype == np.float32
    # float32(π/2) rounds above π/2 and is accepted as π/2.
    assert polar_slice(Lambert(1.0), np.float32(np.pi / 2), n=5).theta_in == math.pi / 2


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"theta_in": -0.1}, "theta_in"),
        ({"theta_in": 1.6}, "theta_in"),
        ({"theta_in": float("nan")}, "theta_in"),
        ({"fixed": "both"}, "fixed"),
        ({"plane": "oblique"}, "plane"),
        ({"n": 1}, "n"),
        ({"n": 10.0}, "n"),
        ({"cosine": "normal"}, "cosine"),
        ({"channel": 3}, "channel"),
        ({"channel": "alpha"}, "channel"),
        ({"log": "yes"}, "log"),
        ({"phi_in": float("inf")}, "phi_in"),
        ({"dtype": np.int32}, "dtype"),
    ],
)
def test_slice_errors_name_the_parameter(kwargs, name):
    args = {"theta_in": 0.5, **kwargs}
    with pytest.raises(ValueError, match=name):
        polar_slice(Lambert(1.0), **args)


def test_not_a_brdf():
    with pytest.raises(ValueError, match="brdf"):
        polar_slice("phong", 0.5)
    with pytest.raises(ValueError, match="brdf"):
        lobe_mesh(None, (0, 0, 1.0))


# --------------------------------------------------------------------------- half/difference angles
def test_half_diff_round_trip_from_angles():
    m = 2000
    th = RNG.uniform(1e-3, np.pi / 2, m)
    td = RNG.uniform(1e-3, np.pi / 2, m)
    ph = RNG.uniform(-np.pi, np.pi, m)
    pd = RNG.uniform(-np.pi, np.pi, m)
    l, v = half_diff_to_dirs(th, ph, td, pd)
    np.testing.assert_allclose(np.linalg.norm(l, axis=-1), 1, rtol=1e-15)
    np.testing.assert_allclose(np.linalg.norm(v, axis=-1), 1, rtol=1e-15)
    back = dirs_to_half_diff(l, v)
    np.testing.assert_allclose(back[0], th, rtol=0, atol=1e-12)
    np.testing.assert_allclose(back[2], td, rtol=0, atol=1e-12)
    for got, want in ((back[1], ph), (back[3], pd)):
        wrapped = np.angle(np.exp(1j * (got - want)))
        np.testing.assert_allclose(wrapped, 0, atol=1e-11)


def test_half_diff_round_trip_from_directions():
    m = 2000
    l = vec.normalize(RNG.normal(size=(m, 3)) * [1, 1, 0] + [0, 0, 1] * RNG.uniform(0.01, 2, (m, 1)))  # noqa: E741
    v = vec.normalize(RNG.normal(size=(m, 3)) * [1, 1, 0] + [0, 0, 1] * RNG.uniform(0.01, 2, (m, 1)))
    th, ph, td, pd = dirs_to_half_diff(l, v)
    l2, v2 = half_diff_to_dirs(th, ph, td, pd)
    np.testing.assert_allclose(l2, l, atol=2e-15)
    np.testing.assert_allclose(v2, v, atol=2e-15)
    # The definitions: h has angles (θ_h, φ_h), and cos θ_d = l·h = v·h.
    h = vec.halfway(l, v)
    np.testing.assert_allclose(vec.spherical_direction(th, ph), h, atol=2e-15)
    np.testing.assert_allclose(np.cos(td), vec.dot(l, h), atol=2e-15)
    np.testing.assert_allclose(np.cos(td), vec.dot(v, h), atol=2e-15)


def test_half_diff_conventions():
    # θ_h = 0: h = n, l is d turned by φ_h about n (φ_d counts from φ_h), v is l mirrored about n.
    l, v = half_diff_to_dirs(0.0, 1.3, 0.5, 0.4)
    np.testing.assert_allclose(l, sph(0.5, 1.7), atol=1e-16)
    np.testing.assert_allclose(v, vec.reflect(sph(0.5, 1.7), N), atol=1e-16)
    # θ_d = 0: l = v = h.
    l, v = half_diff_to_dirs(0.7, 2.0, 0.0, 1.0)
    np.testing.assert_allclose(l, sph(0.7, 2.0), atol=1e-16)
    np.testing.assert_allclose(v, sph(0.7, 2.0), atol=1e-16)
    # φ_d = π/2: the difference rotates about the axis through h in the (h, y') plane, l_z = v_z = cos θ_h cos θ_d.
    th, td = RNG.uniform(0, np.pi / 2, (2, 50))
    l, v = half_diff_to_dirs(th, 0.3, td, np.pi / 2)
    np.testing.assert_allclose(l[:, 2], np.cos(th) * np.cos(td), atol=1e-16)
    np.testing.assert_allclose(v[:, 2], np.cos(th) * np.cos(td), atol=1e-16)
    # φ_d = 0: the incidence plane, l_z = cos(θ_h + θ_d), v_z = cos(θ_h − θ_d).
    l, v = half_diff_to_dirs(th, 0.3, td, 0.0)
    np.testing.assert_allclose(l[:, 2], np.cos(th + td), atol=1e-15)
    np.testing.assert_allclose(v[:, 2], np.cos(th - td), atol=1e-15)


def test_half_diff_broadcast_dtype_and_degenerate():
    l, v = half_diff_to_dirs(np.zeros((4, 1), np.float32), 0.0, np.zeros((1, 5), np.float32), 0.0)
    assert l.shape == v.shape == (4, 5, 3) and l.dtype == np.float32
    out = dirs_to_half_diff(np.array([[0, 0, 1.0]], np.float32), np.array([0.6, 0, 0.8], np.float32))
    assert all(a.dtype == np.float32 and a.shape == (1,) for a in out)
    # l = -v has no half vector: finite angles, no warnings.
    th, ph, td, pd = dirs_to_half_diff((0.6, 0.0, 0.8), (-0.6, 0.0, -0.8))
    assert (float(th), float(ph)) == (0.0, 0.0)
    assert float(td) == pytest.approx(math.atan2(0.6, 0.8), abs=1e-15)
    with pytest.raises(ValueError, match="l and v"):
        dirs_to_half_diff((1.0, 0.0), (0.0, 0.0, 1.0))


@pytest.mark.parametrize("theta_d", [0.0, 0.7, 1.3])
def test_theta_h_curve_is_the_normalized_blinn_phong_ndf(theta_d):
    # Normalized Blinn–Phong depends on θ_h alone: f = ks (e+2)/(2π) cos^e θ_h.
    e, ks = 30.0, 0.7
    c = theta_h_curve(BlinnPhong(ks, e, normalized=True), theta_d, n=91, channel=0)
    assert c.variable == "theta_h" and c.params["theta_d"] == theta_d
    np.testing.assert_array_equal(c.angles, np.linspace(0, np.pi / 2, 91))
    assert np.all(c.valid[:-1]) and not c.valid[-1]
    ref = ks * (e + 2) / (2 * math.pi) * np.cos(c.angles) ** e
    np.testing.assert_allclose(c.values[:-1], ref[:-1], rtol=1e-12)
    assert c.values[-1] == 0


def test_theta_d_curve_shows_fresnel():
    # h = n: D = 1/(π α²), V-cavity G = 1, so f = F_schlick(cos θ_d) / (4 π α² cos² θ_d).
    alpha, f0 = 0.2, 0.04
    c = theta_d_curve(CookTorrance(1.0, alpha, f0), 0.0, n=91, channel=0)
    cd = np.cos(c.angles[:-1])
    ref = (f0 + (1 - f0) * (1 - cd) ** 5) / (4 * math.pi * alpha**2 * cd**2)
    np.testing.assert_allclose(c.values[:-1], ref, rtol=1e-12)
    assert c.values[-1] == 0 and not c.valid[-1]
    # Normalized Blinn–Phong is flat in θ_d at any θ_h.
    c = theta_d_curve(BlinnPhong(1.0, 12, normalized=True), 0.4, n=46, channel="r")
    np.testing.assert_allclose(c.values[:-1], 14 / (2 * math.pi) * math.cos(0.4) ** 12, rtol=1e-13)


def test_theta_d_curve_valid_mask_in_the_incidence_plane():
    # φ_d = 0: l_z = cos(θ_h + θ_d) > 0 only for θ_d < π/2 − θ_h.
    c = theta_d_curve(Lambert(1.0), 0.5, phi_d=0.0, n=1001, channel=0)
    np.testing.assert_array_equal(c.valid, c.angles < np.pi / 2 - 0.5 - 1e-12)
    np.testing.assert_allclose(c.values, np.where(c.valid, 1 / math.pi, 0.0), rtol=1e-15)


@pytest.mark.parametrize("refine", [False, True])
def test_theta_v_curve_is_the_light_slice(refine):
    model = Lambert(0.3) + CookTorrance(1.0, 0.1, 0.5)
    c = theta_v_curve(model, 0.6, phi_l=0.2, n=181, cosine=True, log=True, refine=refine)
    s = polar_slice(model, 0.6, phi_in=0.2, n=181, cosine=True, log=True, refine=refine)
    np.testing.assert_array_equal(c.angles, s.angles)
    np.testing.assert_array_equal(c.values, s.values)
    np.testing.assert_array_equal(c.v, s.directions)
    assert c.variable == "theta_v" and c.valid[1:-1].all() and not c.valid[[0, -1]].any()


def test_half_diff_image_layout_and_values():
    e = 20.0
    im = half_diff_image(BlinnPhong(1.0, e, normalized=True), n_h=64, n_d=32, channel=0)
    assert im.values.shape == im.valid.shape == (32, 64)
    np.testing.assert_array_equal(im.theta_h, np.linspace(0, np.pi / 2, 64))
    np.testing.assert_array_equal(im.theta_d, np.linspace(0, np.pi / 2, 32))
    # Rows are θ_d, columns θ_h; with φ_d = π/2 only the far edges (θ = π/2) leave the hemisphere.
    expect_valid = (im.theta_d[:, None] < np.pi / 2) & (im.theta_h[None, :] < np.pi / 2)
    np.testing.assert_array_equal(im.valid, expect_valid)
    ref = (e + 2) / (2 * math.pi) * np.cos(im.theta_h) ** e
    np.testing.assert_allclose(im.values, np.where(im.valid, ref[None, :], 0.0), rtol=1e-12, atol=0)
    # φ_d = 0: valid exactly where θ_h + θ_d < π/2 (on the grid, the diagonal is the horizon).
    im0 = half_diff_image(Phong(1.0, 5), 0.0, n_h=91, n_d=91, channel=0)
    k = np.arange(91)
    np.testing.assert_array_equal(im0.valid, (k[:, None] + k[None, :]) < 90)
    assert np.all(im0.values[~im0.valid] == 0) and np.all(np.isfinite(im0.values))
    # The largest genuine value is Phong's 1/(π n·l) one step from the horizon (θ_h = 0, θ_d = 89°),
    # not a ~1e16 spike from a diagonal sample a rounding error above it.
    assert im0.values.max() == pytest.approx(1 / (math.pi * math.cos(math.radians(89))), rel=1e-12)


def test_half_diff_image_sqrt_spacing_and_rgb():
    im = half_diff_image(Lambert((0.1, 0.2, 0.3)), n_h=11, n_d=5, theta_h_spacing="sqrt")
    np.testing.assert_allclose(im.theta_h, np.pi / 2 * np.linspace(0, 1, 11) ** 2, rtol=1e-15)
    assert im.values.shape == (5, 11, 3)
    np.testing.assert_allclose(im.values[im.valid], np.tile([0.1, 0.2, 0.3], (im.valid.sum(), 1)) / math.pi)
    with pytest.raises(ValueError, match="theta_h_spacing"):
        half_diff_image(Lambert(1.0), theta_h_spacing="log")
    with pytest.raises(ValueError, match="n_h"):
        half_diff_image(Lambert(1.0), n_h=1)


# --------------------------------------------------------------------------- 3D lobes
def mesh_is_valid(m):
    """Faces in range, positive orientation on the unit sphere, an orientable disk (edges ≤ 2 faces)."""
    v_count = len(m.directions)
    f = m.faces
    assert f.dtype.kind == "i" and f.shape[1] == 3
    assert f.min() >= 0 and f.max() < v_count
    assert len(np.unique(f)) == v_count  # no unused vertices
    d = m.directions.astype(np.float64)
    det = np.einsum("ij,ij->i", d[f[:, 0]], np.cross(d[f[:, 1]], d[f[:, 2]]))
    assert np.all(det > 0), "every face counter-clockwise seen from outside, none degenerate"
    a = np.concatenate([f[:, 0], f[:, 1], f[:, 2]])
    b = np.concatenate([f[:, 1], f[:, 2], f[:, 0]])
    # Consistent winding: no directed edge twice; each undirected edge in one or two faces.
    assert len(np.unique(a * v_count + b)) == len(a)
    _, counts = np.unique(np.minimum(a, b) * v_count + np.maximum(a, b), return_counts=True)
    assert counts.max() <= 2
    assert np.sum(counts == 1) == m.segments  # the only boundary is the rim
    assert v_count - len(counts) + len(f) == 1  # Euler characteristic of a disk
    assert np.all(np.isfinite(m.vertices)) and np.all(np.isfinite(m.values)) and np.all(m.values >= 0)
    return det


def edge_ratios(faces, values, floor):
    """max/min of the values at the two ends of every mesh edge whose ends are both >= floor."""
    e = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    a, b = values[e[:, 0]].astype(np.float64), values[e[:, 1]].astype(np.float64)
    inside = (a >= floor) & (b >= floor)
    return np.maximum(a, b)[inside] / np.minimum(a, b)[inside]


def test_lambert_lobe_is_a_hemisphere():
    kd = np.array([0.2, 0.5, 0.8])
    m = lobe_mesh(Lambert(kd), sph(0.7, 1.0))
    assert m.vertices.shape == (8193, 3) and m.segments == 128 and m.rings == 64
    np.testing.assert_allclose(np.linalg.norm(m.vertices, axis=1), luminance(kd) / math.pi, rtol=1e-14)
    np.testing.assert_allclose(m.rgb, np.tile(kd / math.pi, (8193, 1)), rtol=1e-15)
    assert np.all(m.directions[:, 2] > 0)
    np.testing.assert_array_equal(m.center, N)  # no narrow lobe: plain grid about the normal
    rim = m.directions[-m.segments :]
    np.testing.assert_allclose(rim[:, 2], math.sin(1e-6), rtol=1e-9)
    mesh_is_valid(m)


def test_lambert_intensity_lobe_is_a_sphere():
    # × n·v: radius (kd/π) cos θ_v, the sphere of diameter kd/π resting on the surface.
    kd = 0.9
    m = lobe_mesh(Lambert(kd), sph(0.3), cosine="view", channel=0)
    r = kd / (2 * math.pi)
    np.testing.assert_allclose(np.linalg.norm(m.vertices - [0, 0, r], axis=1), r, rtol=1e-13)
    mesh_is_valid(m)


SHARP = [
    Phong(1.0, 1000),
    BlinnPhong(1.0, 1000),
    BlinnPhong(1.0, 1000, normalized=True),
    CookTorrance(1.0, 0.02, 0.04),
    CookTorrance(1.0, 0.02, 1.0, ndf="ggx", geometry="smith"),
    Lambert(0.5) + Phong(0.5, 1000),
]


@pytest.mark.parametrize("model", SHARP, ids=repr)
@pytest.mark.parametrize("theta_l", [0.0, 0.5, 1.2])
def test_sharp_lobe_is_smooth(model, theta_l):
    # Ring spacing w/6 out to 3 widths: neighbours there differ by e^(3/6) ≈ 1.65 at most (Gaussian lobe).
    l = sph(theta_l, 2.5)  # noqa: E741
    m = lobe_mesh(model, l)
    peak = lobe_peak(model, l)
    # The pole of the grid is the peak, so the mesh holds the true maximum.
    assert m.values.max() == pytest.approx(peak.value, rel=1e-12)
    np.testing.assert_allclose(m.center, peak.direction, atol=1e-15)
    spec = luminance(model.parts[-1].eval(N, l, m.directions))  # the lobe alone, without a diffuse floor
    top = spec.max()
    assert np.sum(spec >= 0.5 * top) >= 100, "hundreds of vertices inside the half-maximum contour"
    # Neighbouring vertices inside the lobe (down to 1 % of the peak) differ by less than a factor 2.
    assert edge_ratios(m.faces, spec, 0.01 * top).max() < 2.0
    mesh_is_valid(m)


def test_uniform_grid_misses_the_sharp_lobe():
    # Why the grid is adaptive: a plain 64-ring hemisphere puts a handful of vertices into an e = 1000 lobe.
    l = sph(0.5)  # noqa: E741
    plain = lobe_mesh(Phong(1.0, 1000), l, adaptive=False)
    graded = lobe_mesh(Phong(1.0, 1000), l)
    top = lobe_peak(Phong(1.0, 1000), l).value
    assert np.sum(plain.values >= 0.5 * top) < 20 <= 100 <= np.sum(graded.values >= 0.5 * top)
    assert edge_ratios(plain.faces, plain.values, 0.01 * top).max() > 5
    np.testing.assert_array_equal(plain.center, N)
    # Uniform rings: ring k at polar angle k (π/2 − 1e-6)/64.
    theta = np.arctan2(np.hypot(plain.directions[1:, 0], plain.directions[1:, 1]), plain.directions[1:, 2])
    rings = (np.pi / 2 - 1e-6) * np.arange(1, 65) / 64
    np.testing.assert_allclose(theta.reshape(64, 128), np.repeat(rings[:, None], 128, axis=1), atol=1e-14)


@pytest.mark.parametrize("cosine", [False, "light", "view"])
@pytest.mark.parametrize("model", [Phong((0.9, 0.4, 0.1), 200), CookTorrance(1.0, 0.3, 0.5, ndf="ggx")], ids=repr)
def test_lobe_vertices_are_the_brdf(model, cosine):
    l = sph(0.9, -0.5)  # noqa: E741
    m = lobe_mesh(model, l, cosine=cosine, resolution=24)
    if cosine == "light":
        rgb = model.eval_cos(N, m.light, m.directions)
    else:
        rgb = model.eval(N, m.light, m.directions) * (m.directions[:, 2:] if cosine == "view" else 1.0)
    np.testing.assert_allclose(m.light, l, rtol=1e-15)
    np.testing.assert_allclose(m.rgb, rgb, rtol=1e-15, atol=0)
    np.testing.assert_allclose(m.values, luminance(rgb), rtol=1e-15, atol=0)
    np.testing.assert_array_equal(m.vertices, m.values[:, None] * m.directions)
    np.testing.assert_allclose(np.linalg.norm(m.directions, axis=1), 1, rtol=1e-15)
    assert np.array_equal(lobe_mesh(model, l, resolution=24, cosine=cosine, channel="g").values, m.rgb[:, 1])
    mesh_is_valid(m)


def test_lobe_faces_point_away_from_the_origin():
    m = lobe_mesh(Lambert(0.3) + CookTorrance(1.0, 0.1, 0.9), sph(1.0))
    p = m.vertices[m.faces]
    det = np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2]))
    assert np.all(det > 0)  # = normal · centroid: outward


def test_lobe_vertex_budget():
    assert len(lobe_mesh(Lambert(1.0), N, resolution=99).values) == 1 + 2 * 99**2 <= 20000
    m = lobe_mesh(Lambert(1.0), N, resolution=4)
    assert (len(m.values), len(m.faces)) == (33, 56)
    for bad in (3, 100, 10.0, True):
        with pytest.raises(ValueError, match="resolution"):
            lobe_mesh(Lambert(1.0), N, resolution=bad)
    with pytest.raises(ValueError, match="adaptive"):
        lobe_mesh(Lambert(1.0), N, adaptive=None)
    with pytest.raises(ValueError, match="l must"):
        lobe_mesh(Lambert(1.0), (0.0, 0.0, 0.0))
    with pytest.raises(ValueError, match="l must"):
        lobe_mesh(Lambert(1.0), (0.0, 1.0))


def test_light_below_the_horizon_gives_a_flat_zero_lobe():
    m = lobe_mesh(Phong(1.0, 50), (0.3, 0.0, -1.0))
    assert np.all(m.values == 0) and np.all(m.vertices == 0)
    mesh_is_valid(m)
    p = lobe_peak(Phong(1.0, 50), (0.3, 0.0, -1.0))
    np.testing.assert_array_equal(p.direction, N)
    assert p.value == 0.0


@pytest.mark.parametrize("model", [Phong(1.0, 30), BlinnPhong(1.0, 1e4), Phong(1.0, 1e6)], ids=repr)
@pytest.mark.parametrize("theta", [0.0, 0.6, 1.4])
def test_phong_family_peaks_at_the_mirror_direction(model, theta):
    l = sph(theta, 0.8)  # noqa: E741
    p = lobe_peak(model, l)
    np.testing.assert_allclose(p.direction, vec.reflect(l, N), atol=1e-9)
    assert p.value == pytest.approx(model.ks[0] / (math.pi * math.cos(theta)), rel=1e-12)


def test_rough_cook_torrance_peaks_off_specular():
    # Beckmann α = 0.2 lit at 0.9 rad peaks inside the hemisphere, well past the mirror direction.
    model = CookTorrance(1.0, 0.2, 0.04)
    l = sph(0.9)  # noqa: E741
    p = lobe_peak(model, l)
    t_peak = math.atan2(-p.direction[0], p.direction[2])  # signed angle, mirror side positive
    assert 0.9 + 0.2 < t_peak < 1.5
    # Nothing on a dense hemisphere grid beats it …
    tt, pp = np.meshgrid(np.linspace(0, np.pi / 2, 721)[:-1], np.linspace(-np.pi, np.pi, 721))
    grid = luminance(model.eval(N, l, sph(tt, pp)))
    assert p.value >= grid.max() * (1 - 1e-12)
    # … and it is the in-plane maximum to ~1e-9 (V-cavity's min() makes the peak a kink).
    scan = luminance(model.eval(N, l, sph(np.linspace(t_peak - 0.01, t_peak + 0.01, 20001), math.pi)))
    assert scan.max() * (1 - 1e-9) <= p.value <= scan.max() * (1 + 1e-12)


def test_grazing_peak_of_rough_ggx_is_at_the_horizon():
    # GGX + Smith, α = 0.35, light at 1.3 rad: f_r keeps rising toward grazing view (Fresnel, 1/(n·v)).
    model = CookTorrance(1.0, 0.35, 0.04, ndf="ggx", geometry="smith")
    p = lobe_peak(model, sph(1.3))
    assert p.direction[0] < 0 and 0 < p.direction[2] < 1e-8
    inner = luminance(model.eval(N, sph(1.3), sph(np.linspace(1.0, 1.57, 300), math.pi)))
    assert p.value >= inner.max()


class MirrorLobe(BRDF):
    """A model this module does not know: the classic Phong lobe ``(R_l·v)^e / π``, written as f_r."""

    def __init__(self, e):
        self.e = e

    def _f(self, g):
        lobe = np.where(g.above, cos_power(g.one_minus_r_dot_v, self.e), 0) / math.pi
        return lobe[..., None] * np.ones(3, dtype=g.dtype)


def test_unknown_model_width_is_measured():
    model = MirrorLobe(1000.0)
    assert math.isnan(lobe_width(model))
    l = sph(0.6, 1.0)  # noqa: E741
    m = lobe_mesh(model, l)
    # The half-maximum scan (1/8° steps) recovers σ = 1/√e to within a step.
    assert m.width == pytest.approx(1 / math.sqrt(1000), abs=0.0025)
    top = lobe_peak(model, l).value
    assert top == pytest.approx(1 / math.pi, rel=1e-12)
    np.testing.assert_allclose(m.center, vec.reflect(l, N), atol=1e-9)
    assert np.sum(m.values >= 0.5 * top) >= 100
    mesh_is_valid(m)


def test_lobe_widths_from_the_models():
    assert lobe_width(Phong(1.0, 400)) == pytest.approx(0.05)
    # Half-vector lobes: 2 cos θ_l times the half-angle width (1/√e, or α/√2 for Beckmann).
    assert lobe_width(BlinnPhong(1.0, 400, normalized=True)) == pytest.approx(0.1)
    assert lobe_width(BlinnPhong(1.0, 400), 1.0) == pytest.approx(0.1 * math.cos(1.0))
    assert lobe_width(CookTorrance(1.0, 0.07)) == pytest.approx(0.07 * math.sqrt(2))
    assert lobe_width(CookTorrance(1.0, 0.07), math.pi / 2) == pytest.approx(0.07 * math.sqrt(2) * 0.1)
    assert lobe_width(Lambert(1.0) + Phong(0.0, 1e6) + CookTorrance(1.0, 0.2)) == pytest.approx(0.2 * math.sqrt(2))
    assert lobe_width(Lambert(1.0)) == math.inf == lobe_width(Phong(1.0, 0.0))


# --------------------------------------------------------------------------- extremes
EXTREME = [
    Phong(1.0, 1e6),
    BlinnPhong(1.0, 1e6),
    BlinnPhong(1.0, 1e6, normalized=True),
    CookTorrance(1.0, 1e-6, 0.04),
    CookTorrance(1.0, 1e-6, 0.04, ndf="ggx", geometry="smith", fresnel="dielectric"),
    CookTorrance(1.0, 1e-6, 1.0, ndf="blinn-phong", denominator="pi"),
    Lambert(1.0) + Phong(1.0, 0.0),
]
GRAZING = [0.0, 1.0, math.pi / 2 - 1e-9, math.pi / 2]


# Several cases below ask a view for the same input: float32 rounds π/2 − 1e-9 to π/2 (the same light), the half/
# difference curves see min(θ, 1.5), and the half/difference image does not depend on θ.  Each view is computed once
# for each distinct input (typed: float32 0.0 and float64 0.0 are different inputs) and only read.
@functools.lru_cache(maxsize=None, typed=True)
def _view(view, model, *args, **kwargs):
    return view(model, *args, **kwargs)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("theta", GRAZING)
@pytest.mark.parametrize("model", EXTREME, ids=repr)
def test_extremes_are_finite(model, theta, dtype):
    t = dtype(theta)
    for fixed in ("light", "view"):
        for plane in ("incidence", "perpendicular"):
            for cosine in (False, "light", "view"):
                s = _view(polar_slice, model, t, fixed=fixed, plane=plane, cosine=cosine, log=cosine == "view", n=181)
                assert s.values.dtype == dtype and np.all(np.isfinite(s.values)) and np.all(s.values >= 0)
    for c in (
        _view(theta_h_curve, model, min(theta, 1.5), dtype=dtype),
        _view(theta_d_curve, model, min(theta, 1.5), dtype=dtype),
        _view(theta_v_curve, model, t),
    ):
        assert c.values.dtype == dtype and np.all(np.isfinite(c.values))
    im = _view(half_diff_image, model, n_h=33, n_d=17, dtype=dtype, log=True)
    assert im.values.dtype == dtype and np.all(np.isfinite(im.values))
    m = lobe_mesh(model, sph(theta, 0.3).astype(dtype), resolution=32)
    assert m.vertices.dtype == dtype
    mesh_is_valid(m)
    p = lobe_peak(model, sph(theta, 0.3).astype(dtype))
    assert math.isfinite(p.value) and p.direction.dtype == dtype


def test_mirror_like_lobe_is_resolved_in_float64():
    # Roughness 1e-6 at 60°: a lobe a microradian wide still gets hundreds of vertices over its half maximum.
    model = CookTorrance(1.0, 1e-6, 1.0)
    l = sph(1.0)  # noqa: E741
    m = lobe_mesh(model, l)
    top = lobe_peak(model, l).value
    assert m.values.max() == pytest.approx(top, rel=1e-9)
    assert np.sum(m.values >= 0.5 * top) >= 100
    mesh_is_valid(m)


def test_light_exactly_on_the_horizon_reflects_nothing():
    # cos(π/2) is 6e-17 in floating point; the slides' Phong BRDF divides by n·l and would show ~1e15.
    import math

    from lighting import BlinnPhong, Phong
    from lighting.analysis import polar_slice, theta_v_curve

    for model in (Phong(1.0, 20.0), BlinnPhong(1.0, 20.0)):
        assert np.all(theta_v_curve(model, math.pi / 2).values == 0)
        assert np.all(polar_slice(model, math.pi / 2).values == 0)


# ------------------------------------------------------------------------------------- one function, one peak
def _views_of_one_slice(model, theta, cosine=False, log=False, dtype=np.float64):
    """The peak each view reports for a light at polar angle ``theta``, as the explorer draws them."""
    l = vec.spherical_direction(theta, math.pi)  # noqa: E741 - the explorer's lobe: light on the −x side
    opts = {"cosine": cosine, "channel": "luminance"}
    peak = lobe_peak(model, l, **opts).value
    # The light-fixed slice of reciprocity_pair, the one drawn (the view-fixed one is not looked at here).
    a = polar_slice(model, dtype(theta), fixed="light", log=log, **opts)
    curve = theta_v_curve(model, dtype(theta), log=log, **opts)
    mesh = lobe_mesh(model, l.astype(dtype), resolution=40, **opts)
    lobe = float(mesh.values.max())
    if log:
        peak, lobe = math.log1p(peak) / math.log(10), math.log1p(lobe) / math.log(10)
    return peak, float(a.values.max()), float(curve.values.max()), lobe


KD = 0.8 * np.array([1.0, 0.42, 0.3])
ONE_PEAK_MODELS = [
    Lambert(KD),
    Lambert(KD) + Phong(0.5, 40.0),
    Lambert(KD) + Phong(0.5, 1e6),
    Lambert(KD) + BlinnPhong(0.5, 40.0),
    Lambert(KD) + BlinnPhong(0.5, 1e6, normalized=True),
    Lambert(KD) + CookTorrance(0.5, 0.25, 0.5),
    Lambert(KD) + CookTorrance(0.5, 1e-6, 0.5),
    CookTorrance(1.0, 1.0, 0.04, ndf="ggx", geometry="smith"),
    # Rough Oren–Nayar's backscatter grows to the horizon: its peak is at the edge no grid sample reaches.
    OrenNayar(KD, 0.941, form="qualitative"),
]


@pytest.mark.parametrize("model", ONE_PEAK_MODELS, ids=repr)
@pytest.mark.parametrize("elevation_deg", [90.0, 40.3, 10.0, 1e-3, 1e-6])
@pytest.mark.parametrize(("cosine", "log"), [(False, False), (True, True)])
def test_the_views_of_one_slice_report_the_same_peak(model, elevation_deg, cosine, log):
    # Before: Cook–Torrance lit 1e-6° above the horizon showed lobe 2.5e12, polar 3.3e4, θ_v curve 8.2e3;
    # Phong e = 1e6 at 40.3° showed a θ_v maximum of 2.7e-7 against 0.246 in the polar slice.  Every
    # view now samples the peak lobe_peak finds, so all four agree to rounding (bound: 1e-9 relative).
    theta = math.radians(90.0 - elevation_deg)
    peak, polar, curve, lobe = _views_of_one_slice(model, theta, cosine, log)
    assert peak > 0
    for name, got in (("polar", polar), ("theta_v", curve), ("lobe", lobe)):
        assert got == pytest.approx(peak, rel=1e-9), name


def test_the_issues_cases_agree_in_float32_too():
    # float32 angles: the slices are computed in float32, the peak in float64; they agree to float32 rounding.
    # (Not at 1e-6° elevation: float32 cannot hold π/2 − 1.7e-8, so that light is another light in float32.)
    for model, elevation in ((Lambert(KD) + CookTorrance(0.5, 0.25, 0.5), 10.0), (Lambert(KD) + Phong(0.5, 1e6), 40.3)):
        theta = math.radians(90.0 - elevation)
        peak, polar, curve, lobe = _views_of_one_slice(model, theta, dtype=np.float32)
        for got in (polar, curve, lobe):
            assert got == pytest.approx(peak, rel=1e-3)


@pytest.mark.parametrize("model", ONE_PEAK_MODELS, ids=repr)
def test_light_on_the_horizon_is_dark_in_every_view(model):
    # θ = π/2 built through the exact helpers: z is exactly 0, every view reflects nothing.
    theta = math.pi / 2
    l = vec.spherical_direction(theta, math.pi)  # noqa: E741
    assert l[2] == 0.0
    assert lobe_peak(model, l).value == 0.0
    assert np.all(lobe_mesh(model, l, resolution=16).values == 0)
    for s in reciprocity_pair(model, theta):
        assert np.all(s.values == 0)
    assert np.all(theta_v_curve(model, theta).values == 0)
    assert np.all(theta_h_curve(model, theta_d=theta).values == 0)
    l_h, v_h = half_diff_to_dirs(0.0, 0.0, theta, math.pi / 2)
    assert l_h[2] == 0.0 and v_h[2] == 0.0  # exact, not 6e-17


def test_lobe_mesh_holds_the_grazing_peak_as_a_vertex():
    # The peak of Cook–Torrance lit at grazing is 1e-9 rad above the horizon, below the usual rim (1e-6):
    # the rim comes down to it and the vertex on the peak's ray is the peak.
    model = CookTorrance(0.5, 0.25, 0.5)
    l = vec.direction_from_elevation(1e-6, 180.0)  # noqa: E741
    peak = lobe_peak(model, l)
    m = lobe_mesh(model, l)
    k = int(np.argmax(m.values))
    np.testing.assert_array_equal(m.directions[k], peak.direction)
    assert m.values[k] == peak.value and 0 < peak.direction[2] < 1e-8
    mesh_is_valid(m)


# ------------------------------------------------------------------------------------- illegal input, named
ILLEGAL_ANALYSIS = [
    # (call, parameter the message must name, exception type)
    (lambda: polar_slice(Lambert(1.0), b"1"), "theta_in", TypeError),
    (lambda: polar_slice(Lambert(1.0), "0.5"), "theta_in", TypeError),
    (lambda: polar_slice(Lambert(1.0), 0.5j), "theta_in", TypeError),
    (lambda: polar_slice(Lambert(1.0), None), "theta_in", TypeError),
    (lambda: polar_slice(Lambert(1.0), np.array([0.1, 0.2])), "theta_in", ValueError),
    (lambda: polar_slice(Lambert(1.0), 0.5, phi_in=np.nan), "phi_in", ValueError),
    (lambda: polar_slice(Lambert(1.0), 0.5, n=True), "n", TypeError),
    (lambda: polar_slice(Lambert(1.0), 0.5, n=10**9), "n", ValueError),
    (lambda: polar_slice(Lambert(1.0), 0.5, cosine=1), "cosine", TypeError),
    (lambda: polar_slice(Lambert(1.0), 0.5, channel=1.0), "channel", TypeError),
    (lambda: polar_slice(Lambert(1.0), 0.5, channel=True), "channel", TypeError),
    (lambda: polar_slice(Lambert(1.0), 0.5, log=1), "log", TypeError),
    (lambda: polar_slice(Lambert(1.0), 0.5, refine="no"), "refine", TypeError),
    (lambda: polar_slice(Lambert(1.0), 0.5, fixed=None), "fixed", TypeError),
    (lambda: polar_slice(Lambert(1.0), 0.5, dtype="bogus"), "dtype", TypeError),
    (lambda: polar_slice(object(), 0.5), "brdf", TypeError),
    (lambda: reciprocity_pair(Lambert(1.0), 0.5, fixed="light"), "fixed", ValueError),
    (lambda: theta_v_curve(Lambert(1.0), 2.0), "theta_l", ValueError),
    (lambda: theta_v_curve(Lambert(1.0), 0.5, refine=None), "refine", TypeError),
    (lambda: theta_h_curve(Lambert(1.0), theta_d=-1.0), "theta_d", ValueError),
    (lambda: theta_h_curve(Lambert(1.0), phi_h=np.inf), "phi_h", ValueError),
    (lambda: theta_d_curve(Lambert(1.0), theta_h=b"0"), "theta_h", TypeError),
    (lambda: half_diff_image(Lambert(1.0), n_h=1), "n_h", ValueError),
    (lambda: half_diff_image(Lambert(1.0), n_d=2.0), "n_d", TypeError),
    (lambda: half_diff_image(Lambert(1.0), theta_h_spacing="log"), "theta_h_spacing", ValueError),
    (lambda: half_diff_to_dirs(np.nan, 0.0, 0.0, 0.0), "theta_h", ValueError),
    (lambda: half_diff_to_dirs(0.0, 0.0, "1", 0.0), "theta_d", TypeError),
    (lambda: half_diff_to_dirs(np.zeros(2), 0.0, np.zeros(3), 0.0), "theta_h, phi_h", ValueError),
    (lambda: dirs_to_half_diff((np.nan, 0.0, 1.0), (0.0, 0.0, 1.0)), "l", ValueError),
    (lambda: dirs_to_half_diff((0.0, 0.0, 1.0), (0.0, 0.0, 1j)), "v", TypeError),
    (lambda: dirs_to_half_diff((0.0, 0.0, 1.0), np.zeros((2, 3))), "v", ValueError),
    (lambda: lobe_peak(Lambert(1.0), (np.inf, 0.0, 1.0)), "l", ValueError),
    (lambda: lobe_peak(Lambert(1.0), np.full((2, 3), np.nan)), "l", ValueError),
    (lambda: lobe_peak(Lambert(1.0), b"001"), "l", TypeError),
    (lambda: lobe_peak(Lambert(1.0), (0.0, 0.0, 1.0), channel="alpha"), "channel", ValueError),
    (lambda: lobe_mesh(Lambert(1.0), (0.0, 0.0, 1.0), resolution=40.0), "resolution", TypeError),
    (lambda: lobe_mesh(Lambert(1.0), (0.0, 0.0, 1.0), cosine="normal"), "cosine", ValueError),
    (lambda: lobe_mesh(Lambert(1.0), (0.0, 0.0, 1.0), adaptive="yes"), "adaptive", TypeError),
    (lambda: lobe_mesh(Lambert(1.0), None), "l", TypeError),
    (lambda: lobe_width(Lambert(1.0), float("inf")), "theta_l", ValueError),
    (lambda: lobe_width("phong"), "brdf", TypeError),
]


@pytest.mark.parametrize(("call", "name", "kind"), ILLEGAL_ANALYSIS, ids=[c[1] for c in ILLEGAL_ANALYSIS])
def test_every_illegal_argument_raises_a_named_error(call, name, kind):
    with pytest.raises(kind) as info:
        call()
    msg = str(info.value)
    assert isinstance(info.value, ValueError)  # wrong types raise ArgumentTypeError: a ValueError too
    assert msg.startswith(name) and " must " in msg and "\n" not in msg and len(msg) < 300, msg
    assert "got" in msg  # the value given is quoted
