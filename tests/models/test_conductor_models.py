"""Cook–Torrance and the mirror with the conductor Fresnel term, and the named metals.

The conductor model is the Fresnel-free model times ``conductor(v·h, η, k)``; with ``k = 0`` it is the exact
dielectric; each metal's ``F0`` is the closed form of its table values, and those are the published rows
interpolated linearly in wavelength.
"""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

from lighting.analysis.audit import audit
from lighting.integrate import directional_albedo
from lighting.integrate.ibl import ALBEDO_ANGLES, lobe_albedo
from lighting.models import energy
from lighting.models import fresnel as fr
from lighting.models.cook_torrance import CookTorrance
from lighting.models.fresnel import METAL_WAVELENGTHS_NM, METALS, conductor, eta_from_f0
from lighting.models.mirror import Mirror
from lighting.scene.load import parse_scene

GOLD_ETA, GOLD_K = METALS["gold"]
FORMS = [("beckmann", "v-cavity"), ("ggx", "smith"), ("ggx", "smith-correlated"), ("blinn-phong", "smith")]


def _unit(a):
    return a / np.linalg.norm(a, axis=-1, keepdims=True)


def _directions(seed=3, count=2000):
    """Random normals, lights and viewers, a quarter of the viewers near the mirror direction (float64)."""
    rng = np.random.default_rng(seed)
    n, l, v = (_unit(rng.normal(size=(count, 3))) for _ in range(3))  # noqa: E741
    q = count // 4
    v[:q] = _unit(2 * n[:q] * np.sum(n[:q] * l[:q], axis=-1, keepdims=True) - l[:q] + 0.05 * rng.normal(size=(q, 3)))
    return n, l, v


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize(("ndf", "geometry"), FORMS)
@pytest.mark.parametrize("index", [{"metal": "gold"}, {"eta": (0.2, 1.1, 1.5), "k": (3.1, 2.4, 0.0)}])
def test_conductor_model_is_the_fresnel_free_model_times_the_conductor_f(dtype, ndf, geometry, index):
    common = {"ks": (0.9, 0.8, 1.0), "roughness": 0.35, "ndf": ndf, "geometry": geometry}
    model = CookTorrance(**common, fresnel="conductor", **index)
    plain = CookTorrance(**common, fresnel="none")
    n, l, v = (x.astype(dtype) for x in _directions())  # noqa: E741
    got = model.eval(n, l, v)
    assert got.dtype == dtype
    eta, k = (METALS["gold"] if "metal" in index else (index["eta"], index["k"]))
    h = _unit(l.astype(np.float64) + v.astype(np.float64))
    vh = np.clip(np.sum(_unit(v.astype(np.float64)) * h, axis=-1), 0, 1)
    want = plain.eval(n, l, v).astype(np.float64) * conductor(vh, eta, k)
    assert np.count_nonzero(want) > 500
    # float32: both sides rounded to float32 once (and v·h formed from float32 vectors), a few ulp apart; among
    # subnormal values (a Beckmann tail) an ulp is the smallest subnormal, hence the absolute allowance.
    rtol = 1e-13 if dtype == np.float64 else 4e-6
    np.testing.assert_allclose(got, want, rtol=rtol, atol=4 * np.finfo(dtype).smallest_subnormal)
    # The cosine form (the fast path's separable terms, one per channel) likewise: f_r (n·l).
    want_cos = plain.eval_cos(n, l, v).astype(np.float64) * conductor(vh, eta, k)
    tiny = 4 * np.finfo(dtype).smallest_subnormal
    np.testing.assert_allclose(model.eval_cos(n, l, v), want_cos, rtol=rtol, atol=tiny)


def test_the_public_f_is_the_conductor_f():
    from lighting.models.geometry import Geometry

    n, l, v = _directions(count=300)  # noqa: E741
    g = Geometry(n, l, v)
    m = CookTorrance(fresnel="conductor", metal="copper")
    np.testing.assert_array_equal(m.F(g), conductor(np.clip(g.v_dot_h, 0, 1), *METALS["copper"]))


@pytest.mark.parametrize("f0", [0.04, (0.02, 0.3, 0.9)])
def test_k_zero_is_the_exact_dielectric_of_f0(f0):
    n, l, v = _directions(seed=9)  # noqa: E741
    for ndf, geometry in FORMS:
        di = CookTorrance(0.7, 0.2, f0, ndf=ndf, geometry=geometry, fresnel="dielectric")
        co = CookTorrance(0.7, 0.2, ndf=ndf, geometry=geometry, fresnel="conductor", eta=eta_from_f0(f0), k=0.0)
        # The dielectric is written in √f0 (F0 exact); the conductor takes the rounded η: a few ulp apart.
        np.testing.assert_allclose(co.eval(n, l, v), di.eval(n, l, v), rtol=1e-13, atol=0)
        # Left unset, η is f0's and k is 0: the same model.
        unset = CookTorrance(0.7, 0.2, f0, ndf=ndf, geometry=geometry, fresnel="conductor")
        np.testing.assert_array_equal(unset.eval(n, l, v), co.eval(n, l, v))
    c = np.linspace(0.0, 1.0, 101)
    np.testing.assert_allclose(Mirror(0.8, fresnel="conductor", eta=eta_from_f0(f0), k=0.0).reflectance(c),
                               Mirror(0.8, f0, "dielectric").reflectance(c), rtol=1e-13, atol=1e-300)  # fmt: skip


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_mirror_reflectance_is_ks_times_the_conductor_f(dtype):
    c = np.linspace(-1.0, 1.0, 401).astype(dtype)
    m = Mirror((0.9, 0.5, 1.0), fresnel="conductor", metal="gold")
    got = m.reflectance(c)
    assert got.dtype == dtype and got.shape == (401, 3)
    c64 = c.astype(np.float64)
    want = np.where((c64 > 0)[:, None], np.array([0.9, 0.5, 1.0]) * conductor(np.clip(c64, 0, 1), GOLD_ETA, GOLD_K), 0)
    np.testing.assert_allclose(got, want, rtol=2 * np.finfo(dtype).eps, atol=0)
    # The delta's weight under every albedo method is the reflectance itself.
    theta = np.radians([0.0, 45.0, 80.0])
    np.testing.assert_array_equal(directional_albedo(m, theta, 16, "quadrature"), m.reflectance(np.cos(theta)))


def test_reciprocity():
    n, l, v = _directions(seed=4)  # noqa: E741
    for ndf, geometry in FORMS:
        for metal in METALS:
            m = CookTorrance(0.8, 0.3, ndf=ndf, geometry=geometry, fresnel="conductor", metal=metal)
            np.testing.assert_allclose(m.eval(n, l, v), m.eval(n, v, l), rtol=1e-13, atol=0)


def test_energy_albedo_at_most_one_as_the_audit_checks():
    cases = [(f"{metal} {ndf}/{geometry}", CookTorrance(1.0, 0.3, ndf=ndf, geometry=geometry, fresnel="conductor",
                                                        metal=metal))
             for metal in METALS for ndf, geometry in (("ggx", "smith-correlated"), ("beckmann", "v-cavity"))]
    cases.append(("silver +ms", CookTorrance(1.0, 1.0, ndf="ggx", geometry="smith-correlated", fresnel="conductor",
                                             metal="silver", energy_compensation=True)))
    table = audit(cases, view_angles_deg=[0.0, 30.0, 60.0, 80.0, 89.0])
    assert len(table.rows) == len(cases)
    for row in table.rows:
        assert row.positive and row.reciprocal and row.energy, row
        assert 0 < row.albedo_max <= 1.0, row
    # At normal incidence a smooth-ish metal reflects about its F0 (less what shadowing loses).
    smooth = CookTorrance(1.0, 0.05, ndf="ggx", geometry="smith-correlated", fresnel="conductor", metal="gold")
    np.testing.assert_allclose(directional_albedo(smooth, 0.0, 4096), smooth.f0, rtol=0.02)


@pytest.mark.parametrize("metal", list(METALS))
def test_each_metals_f0_is_the_closed_form_of_its_table_values(metal):
    eta, k = (np.array(x) for x in METALS[metal])
    closed = ((eta - 1) ** 2 + k**2) / ((eta + 1) ** 2 + k**2)
    for model in (CookTorrance(fresnel="conductor", metal=metal), Mirror(fresnel="conductor", metal=metal)):
        np.testing.assert_allclose(model.f0, closed, rtol=1e-15)
        np.testing.assert_array_equal(model.eta, eta)
        np.testing.assert_array_equal(model.k, k)
    np.testing.assert_allclose(conductor(1.0, eta, k), closed, rtol=1e-15)
    assert np.all((closed > 0.4) & (closed < 1.0))


@pytest.mark.parametrize("metal", list(METALS))
def test_each_metals_index_is_its_rows_interpolated_linearly_in_wavelength(metal):
    rows = fr._METAL_ROWS[metal]
    eta, k = METALS[metal]
    assert len(eta) == len(k) == 3
    for channel, nm in enumerate(METAL_WAVELENGTHS_NM):
        lam = nm / 1000.0
        (l0, n0, k0), (l1, n1, k1) = next((a, b) for a, b in zip(rows, rows[1:], strict=False) if a[0] <= lam <= b[0])
        t = (lam - l0) / (l1 - l0)
        assert eta[channel] == pytest.approx(n0 + t * (n1 - n0), rel=1e-14)
        assert k[channel] == pytest.approx(k0 + t * (k1 - k0), rel=1e-14)
    assert tuple(METAL_WAVELENGTHS_NM) == (630.0, 532.0, 465.0)


def _average_reference(eta, k):
    """``2 ∫ F μ dμ`` in 30 digits: the textbook F (cos θ_t from Snell's law) under mpmath's adaptive rule."""
    with mpmath.workdps(30):
        n = mpmath.mpc(eta, k)

        def f(c):
            if c == 0:
                return mpmath.mpf(1)
            ct = mpmath.sqrt(1 - (1 - c * c) / (n * n))
            rp = (c - n * ct) / (c + n * ct)
            rl = (n * c - ct) / (n * c + ct)
            return c * (abs(rp) ** 2 + abs(rl) ** 2)

        c2 = 1 - mpmath.mpf(eta) ** 2 + mpmath.mpf(k) ** 2
        points = [0, mpmath.sqrt(c2), 1] if 0 < c2 < 1 else [0, 1]
        return float(mpmath.quad(f, points))


@pytest.mark.parametrize(("eta", "k"), [*(tuple(zip(*METALS[m], strict=True))[0] for m in METALS),
                                        (1.5, 0.0), (0.5, 0.0), (0.5, 0.01), (0.2, 0.5), (3.0, 0.01)])  # fmt: skip
def test_conductor_fresnel_average_against_mpmath(eta, k):
    got = energy.fresnel_average("conductor", 0.5, eta, k)
    np.testing.assert_allclose(got, _average_reference(eta, k), rtol=0, atol=2e-14)


def test_conductor_fresnel_average_per_channel_is_cached_and_feeds_the_multiple_scattering_colour():
    energy._conductor_average.cache_clear()
    avg = energy.fresnel_average("conductor", 0.04, GOLD_ETA, GOLD_K)
    assert avg.shape == (3,) and energy._conductor_average.cache_info().misses == 3
    again = energy.fresnel_average("conductor", 0.9, GOLD_ETA, GOLD_K)  # f0 is not read
    np.testing.assert_array_equal(again, avg)
    assert energy._conductor_average.cache_info().hits == 3
    m = CookTorrance(0.8, 0.4, ndf="ggx", geometry="smith", fresnel="conductor", metal="gold", energy_compensation=True)
    e_avg = energy.albedo_table("ggx", "smith").E_avg(0.4)
    np.testing.assert_allclose(m._ms.colour, 0.8 * energy.multiple_scattering_colour(avg, e_avg), rtol=1e-15)
    with pytest.raises(ValueError, match=r"^fresnel_average: fresnel 'conductor' needs eta and k"):
        energy.fresnel_average("conductor", 0.04)


def test_split_sum_albedo_of_a_metal_is_its_directional_albedo():
    gold = CookTorrance(1.0, 0.3, ndf="ggx", geometry="smith-correlated", fresnel="conductor", metal="gold")
    copper = CookTorrance(1.0, 0.3, ndf="ggx", geometry="smith-correlated", fresnel="conductor", metal="copper")
    table = lobe_albedo(gold)
    np.testing.assert_allclose(table[[0, 30]], directional_albedo(gold, ALBEDO_ANGLES[[0, 30]]), rtol=1e-12)
    assert not np.allclose(lobe_albedo(copper)[0], table[0])  # cached per model: metals do not share a table


@pytest.mark.parametrize("cls", [CookTorrance, Mirror])
@pytest.mark.parametrize("index", [{"metal": "chromium"}, {"eta": (0.3, 1.2, 2.0), "k": 2.5}, {}])
def test_to_dict_from_dict_and_repr_round_trip(cls, index):
    m = cls(fresnel="conductor", **index)
    table = m.to_dict()
    assert "f0" not in table  # not used by the conductor
    if "metal" in index:
        assert table["metal"] == "chromium" and "eta" not in table and "k" not in table
    else:
        assert "metal" not in table and len(table["eta"]) == len(table["k"]) == 3
    again = cls.from_dict(table)
    assert again.to_dict() == table
    np.testing.assert_array_equal(again.eta, m.eta)
    np.testing.assert_array_equal(again.k, m.k)
    text = repr(m)
    assert "fresnel='conductor'" in text and "f0=" not in text
    if "metal" in index:
        assert "metal='chromium'" in text and eval(text).to_dict() == table  # noqa: S307 (the engine's own repr)
    else:
        assert "eta=" in text and "k=" in text
        np.testing.assert_allclose(eval(text).eta, m.eta, rtol=1e-5)  # noqa: S307 (6 significant digits)
    assert "conductor" in m.summary()
    # Other Fresnel choices keep their tables: no eta, k or metal key.
    assert not {"eta", "k", "metal"} & set(cls(fresnel="schlick").to_dict())


def test_a_scene_part_takes_a_metal_by_name():
    scene = parse_scene('''
        [camera]
        eye = [0.0, 0.0, 4.0]
        target = [0.0, 0.0, 0.0]

        [[materials.gold.parts]]
        model = "cook-torrance"
        roughness = 0.2
        ndf = "ggx"
        geometry = "smith-correlated"
        fresnel = "conductor"
        metal = "Gold"

        [[materials.gold.parts]]
        model = "mirror"
        fresnel = "conductor"
        eta = [0.2, 0.9, 1.3]
        k = 3.0

        [[objects]]
        type = "sphere"
        material = "gold"
    ''')
    ct, mirror = scene.materials["gold"].brdf.parts
    assert ct.metal == "gold" and ct.fresnel == "conductor"
    np.testing.assert_array_equal(ct.eta, GOLD_ETA)
    np.testing.assert_array_equal(mirror.eta, [0.2, 0.9, 1.3])
    np.testing.assert_array_equal(mirror.k, [3.0, 3.0, 3.0])
    with pytest.raises(ValueError, match=r"metal.*did you mean 'aluminium'"):
        parse_scene('[camera]\neye = [0.0, 0.0, 4.0]\ntarget = [0.0, 0.0, 0.0]\n[[materials.m.parts]]\n'
                    'model = "mirror"\nfresnel = "conductor"\nmetal = "aluminum"\n'
                    '[[objects]]\ntype = "sphere"\nmaterial = "m"\n')


@pytest.mark.parametrize("cls", [CookTorrance, Mirror])
@pytest.mark.parametrize(
    ("kwargs", "message"),
    [({"fresnel": "conductor", "eta": 0.0}, r"^eta must be a finite scalar or RGB triple > 0; got 0"),
     ({"fresnel": "conductor", "eta": -1.0}, r"^eta must be .*; got -1"),
     ({"fresnel": "conductor", "eta": math.nan}, r"^eta must be"),
     ({"fresnel": "conductor", "eta": (1.0, 2.0)}, r"^eta must be .*shape \(2,\)"),
     ({"fresnel": "conductor", "k": -0.1}, r"^k must be a finite scalar or RGB triple >= 0; got -0.1"),
     ({"fresnel": "conductor", "k": math.inf}, r"^k must be"),
     ({"fresnel": "conductor", "metal": "gould"}, r"^metal must be one of 'none', 'gold', .*; got 'gould' "
                                                  r"\(did you mean 'gold'\?\)$"),
     ({"fresnel": "conductor", "metal": 3}, r"^metal must be one of"),
     ({"fresnel": "schlick", "metal": "gold"}, r"^metal applies to fresnel 'conductor' only; got metal='gold' "
                                               r"with fresnel 'schlick'"),
     ({"fresnel": "dielectric", "eta": 1.3}, r"^eta applies to fresnel 'conductor' only"),
     ({"fresnel": "conductor", "metal": "gold", "k": 2.0}, r"^metal='gold' sets eta and k; got k=2")],
)  # fmt: skip
def test_bad_conductor_parameters_are_refused_in_one_line(cls, kwargs, message):
    with pytest.raises(ValueError, match=message) as info:
        cls(**kwargs)
    assert "\n" not in str(info.value)


def test_metal_index_gives_copies_and_names_the_metals():
    eta, k = fr.metal_index(" Silver ")
    eta[0] = 99.0
    assert METALS["silver"][0][0] != 99.0
    with pytest.raises(ValueError, match=r"^metal must be one of 'gold', 'silver', 'copper', 'aluminium', "
                                         r"'chromium'; got 'brass'$"):  # fmt: skip
        fr.metal_index("brass")
