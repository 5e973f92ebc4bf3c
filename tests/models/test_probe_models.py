"""Fuzz probe of the public API of the reflectance models, the microfacet and Fresnel functions and the OpenGL mode.

Extreme exponents, finite results, checked arguments and the spot cone kept as seeded, bounded probes (hypothesis
with ``derandomize=True``):

(a) legal extremes, float32 and float64: grazing and exactly-horizontal directions, ``l = −v``,
    the half vector on the horizon, mirror directions, zero and tiny and huge vectors, exponents
    from 0 through subnormal to 1e300, roughness down to 1e-6, huge and tiny colours, spot cutoffs
    0/90/180, vanishing attenuation.  Every result must be finite, >= 0 (the GL colours in [0, 1]),
    of the input dtype, and raise no warning;
(b) illegal values, one per call: every one must raise ``ValueError``/``TypeError`` whose message
    names the parameter.

Failures are counted by kind rather than stopping at the first, and each test prints one
summary line (``pytest -s`` shows it) before asserting that there are none.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from probes import PROBE_SETTINGS, IllegalTally, LegalTally

from lighting import fresnel, gl, microfacet
from lighting.models.brdf import BlinnPhong, BRDFSum, CookTorrance, Lambert, Phong
from lighting.shading.stacked import StackedGeometry
from lighting.vec import normalize

pytestmark = pytest.mark.slow  # seeded probe: many generated calls of the models' API

SETTINGS = PROBE_SETTINGS | dict(suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])

DTYPES = (np.float32, np.float64)

# --------------------------------------------------------------------------- legal values
EXPONENTS = [0.0, 5e-324, 1e-300, 1e-45, 1e-40, 1e-8, 0.5, 1.0, 50.0, 1e6, 1e7, 1e38, 1e39, 1e300]
ROUGHNESS = [1e-6, 1e-5, 1e-3, 0.05, 0.3, 1.0, 3.0, 100.0]
COLOURS = [0.0, 1e-300, 1e-40, 1e-8, 0.5, 1.0, 1e30, 1e300]
F0S = [0.0, 1e-300, 0.04, 0.5, 1.0 - 1e-16, 1.0]

exponents = st.one_of(st.sampled_from(EXPONENTS), st.floats(0, 1e300))
roughness = st.one_of(st.sampled_from(ROUGHNESS), st.floats(1e-6, 10.0))
colours = st.one_of(st.sampled_from(COLOURS), st.tuples(*[st.sampled_from(COLOURS)] * 3))
f0s = st.one_of(st.sampled_from(F0S), st.tuples(*[st.sampled_from(F0S)] * 3))

models = st.one_of(
    st.builds(Lambert, colours),
    st.builds(Phong, colours, exponents),
    st.builds(BlinnPhong, colours, exponents, st.booleans()),
    st.builds(
        CookTorrance,
        colours,
        roughness,
        f0s,
        st.sampled_from(CookTorrance.NDFS),
        st.sampled_from(CookTorrance.GEOMETRIES),
        st.sampled_from(CookTorrance.FRESNELS),
        st.sampled_from(CookTorrance.DENOMINATORS),
    ),
)
models = st.one_of(models, st.builds(lambda a, b: a + b, models, models))


def _hard_directions():
    """The normal, exactly horizontal, grazing by 1e-8/1e-30/subnormal, below, tiny and huge lengths."""
    out = [[0, 0, 1.0], [1.0, 0, 0], [-1.0, 0, 0], [0, 1.0, 0], [0, 0, -1.0], [0.6, 0, 0.8], [-0.6, 0, 0.8]]
    for d in (1e-3, 1e-8, 1e-30, 1e-45, 5e-324, -1e-30):
        out += [[1.0, 0, d], [-1.0, 0, d], [math.cos(0.3), math.sin(0.3), d]]
    out += [[0, 0, 1e-30], [3e-25, 0, 4e-25], [1e30, 0, 1e30], [1e-300, 0, 1e-300], [0, 0, 0]]
    return np.array(out)


HARD = _hard_directions()
NORMALS = np.array([[0, 0, 1.0], [0, 0, 7.5], [0, 0, 1e-20], [1e-3, 0, 1.0], [0.6, 0, 0.8], [0, 0, 0]])


@st.composite
def configurations(draw):
    """``(n, l, v)`` batches mixing hard directions, random ones and their special relations."""
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    k = 24
    n = NORMALS[rng.integers(0, len(NORMALS), k)]
    l = HARD[rng.integers(0, len(HARD), k)]  # noqa: E741
    v = HARD[rng.integers(0, len(HARD), k)]
    r = rng.normal(size=(k, 3))
    pick = rng.random(k)
    v = np.where((pick < 0.2)[:, None], -l, v)  # l = −v
    nn = n / np.maximum(np.linalg.norm(n, axis=-1, keepdims=True), 1e-300)
    mirror = 2 * nn * np.sum(nn * l, axis=-1, keepdims=True) - l
    v = np.where(((pick >= 0.2) & (pick < 0.35))[:, None], mirror, v)  # the peak of the Phong lobe
    # h on the horizon: l and v mirror images through the tangent plane's normal direction
    # (equal tangential parts, opposite normal parts), so l + v is tangential.
    flip = l - 2 * nn * np.sum(nn * l, axis=-1, keepdims=True)
    v = np.where(((pick >= 0.35) & (pick < 0.45))[:, None], flip, v)
    l = np.where((pick >= 0.9)[:, None], r, l)  # noqa: E741
    dtype = draw(st.sampled_from(DTYPES))
    # Lengths near the top and the bottom of the dtype's range (directions unchanged).
    info = np.finfo(dtype)
    for a in (n, l, v):
        unit = a / np.maximum(np.max(np.abs(a), axis=-1, keepdims=True), 1e-300)
        sizes = [1.0, float(info.max) / 4, float(info.smallest_subnormal) * 8]
        scale = rng.choice(sizes, size=(k, 1), p=[0.8, 0.1, 0.1])
        a[...] = np.where(scale != 1.0, unit * scale, a)
    return n.astype(dtype), l.astype(dtype), v.astype(dtype)


def _stacked(model, n, l, v, dtype):  # noqa: E741
    """The renderer's path: ``separable_cos``/``separable_classic`` on a :class:`StackedGeometry` of unit vectors."""
    def unit(x):  # the renderer's unit vectors; a zero one stands in for the normal
        x = normalize(x.astype(np.float64))
        return np.where(np.any(x != 0, axis=-1, keepdims=True), x, [0, 0, 1.0]).astype(dtype)

    g = StackedGeometry(unit(n), unit(l), unit(v))
    out = []
    for fields in (model.separable_cos(g), model.separable_classic(g)):
        out += [s for s, _ in fields]
    return out


def test_probe_models_legal_extremes():
    tally = LegalTally()

    @settings(max_examples=500, **SETTINGS)
    @given(models, configurations())
    def run(model, nlv):
        n, l, v = nlv  # noqa: E741
        dtype = n.dtype.type
        what = f"{model!r} {np.dtype(dtype).name}"
        tally.check(what + " eval", lambda: model.eval(n, l, v), dtype=dtype)
        tally.check(what + " eval_cos", lambda: model.eval_cos(n, l, v), dtype=dtype)
        tally.check(what + " classic", lambda: model.classic(n, l, v), dtype=dtype)
        tally.check(what + " stacked", lambda: _stacked(model, n, l, v, dtype), dtype=dtype)

    run()
    print(f"\nprobe models (legal extremes): {tally.summary()}")
    assert tally.cases >= 1500
    assert not tally.failures, tally.examples


# --------------------------------------------------------------------------- microfacet and Fresnel
COSINES = [-1.0, -0.5, -1e-30, 0.0, 5e-324, 1e-300, 1e-30, 1e-8, 0.01, 0.5, 1 - 1e-8, 1 - 1e-16, 1.0]
cosines = st.lists(st.one_of(st.sampled_from(COSINES), st.floats(-1, 1)), min_size=1, max_size=12)


def test_probe_microfacet_fresnel_legal_extremes():
    tally = LegalTally()

    @settings(max_examples=400, **SETTINGS)
    @given(cosines, roughness, exponents, f0s, st.one_of(st.sampled_from([1e-300, 1e-8, 0.5, 1.0, 1.5, 1e8, 1e300]),
                                                          st.floats(1e-300, 1e300)),
           st.booleans(), st.sampled_from(DTYPES))
    def run(cos, alpha, e, f0, eta, with_sin2, dtype):
        c = np.array(cos, dtype)
        s2 = (1 - np.abs(c.astype(np.float64))) * (1 + np.abs(c.astype(np.float64)))
        s2 = s2.astype(dtype) if with_sin2 else None
        what = f"cos={cos} α={alpha} e={e} f0={f0} η={eta} {np.dtype(dtype).name}"
        tally.check("beckmann_ndf " + what, lambda: microfacet.beckmann_ndf(c, alpha, s2), dtype=dtype)
        tally.check("ggx_ndf " + what, lambda: microfacet.ggx_ndf(c, alpha, s2), dtype=dtype)
        tally.check("blinn_phong_ndf " + what, lambda: microfacet.blinn_phong_ndf(c, e, s2), dtype=dtype)
        tally.check("blinn_phong_ndf(exponent(α)) " + what,
                    lambda: microfacet.blinn_phong_ndf(c, microfacet.blinn_phong_exponent(alpha), s2), dtype=dtype)
        tally.check("smith_g1_beckmann " + what, lambda: microfacet.smith_g1_beckmann(c, alpha, s2), dtype=dtype)
        tally.check("smith_g1_ggx " + what, lambda: microfacet.smith_g1_ggx(c, alpha, s2), dtype=dtype)
        tally.check("vcavity_g " + what, lambda: microfacet.vcavity_g(c, c[::-1], c, np.abs(c)), dtype=dtype,
                    hi=1.0)
        tally.check("schlick " + what, lambda: fresnel.schlick(c, f0), dtype=dtype, hi=1.0)
        tally.check("dielectric " + what, lambda: fresnel.dielectric(c, eta), dtype=dtype, hi=1.0)
        tally.check("f0_from_eta " + what, lambda: fresnel.f0_from_eta(eta), dtype=np.float64, hi=1.0)
        tally.check("eta_from_f0 " + what, lambda: fresnel.eta_from_f0(f0), dtype=np.float64)

    run()
    print(f"\nprobe microfacet/fresnel (legal extremes): {tally.summary()}")
    assert tally.cases >= 4000
    assert not tally.failures, tally.examples


# --------------------------------------------------------------------------- OpenGL mode
GL_COLOURS = [0.0, 1e-300, 0.5, 1.0, 1e300, -1e300, -0.5]
gl_colours = st.tuples(*[st.sampled_from(GL_COLOURS)] * 3)
gl_reflectances = st.tuples(*[st.sampled_from([c for c in GL_COLOURS if c >= 0])] * 3)
gl_vectors = st.sampled_from([(0, 0, 1.0), (0, 0, -1.0), (1.0, 0, 0), (1e-300, 0, 0), (1e300, 1e300, 1e300),
                              (0.3, -0.2, 0.9), (-1e300, 0, 1e-300)])


@st.composite
def gl_lights(draw):
    w = draw(st.sampled_from([0.0, 1.0, 1e-300, 1e300, -2.0]))
    xyz = draw(gl_vectors)
    if w == 0.0 and not any(xyz):
        xyz = (0, 0, 1.0)
    att = draw(st.sampled_from([(1.0, 0.0, 0.0), (0.0, 0.0, 1.0), (1e-300, 0.0, 0.0), (0.0, 1e-300, 0.0),
                                (1e300, 1e300, 1e300), (0.5, 0.1, 0.01)]))
    return gl.Light(
        ambient=draw(gl_colours), diffuse=draw(gl_colours), specular=draw(gl_colours),
        position=(*xyz, w), spot_direction=draw(gl_vectors),
        spot_exponent=draw(st.sampled_from([0.0, 1e-300, 1.0, 128.0])),
        spot_cutoff=draw(st.sampled_from([0.0, 1e-10, 45.0, 89.999999, 90.0, 180.0])),
        constant_attenuation=att[0], linear_attenuation=att[1], quadratic_attenuation=att[2],
    )


def test_probe_gl_legal_extremes():
    tally = LegalTally()

    def arrays(dtype):
        """Vertices at the eye, tiny, huge (a quarter of the dtype's range) and ordinary; normals likewise."""
        big, tiny = float(np.finfo(dtype).max) / 4, float(np.finfo(dtype).smallest_subnormal)
        p = np.array([[0, 0, 0], [0, 0, -1.0], [tiny, 0, 0], [big, -big, big], [0.5, 0.2, -2.0], [0, 0, 1.0],
                      [3e-25, 4e-25, 0]], dtype)
        n = np.array([[0, 0, 1.0], [0, 0, 0], [tiny, 0, 0], [big, 0, big], [0.6, 0, 0.8], [0, 0, -1.0],
                      [1.0, 0, 0]], dtype)
        return p, n

    @settings(max_examples=300, **SETTINGS)
    @given(gl_reflectances, gl_reflectances, gl_reflectances, gl_colours,
           st.sampled_from([0.0, 1e-300, 1.0, 128.0]), st.lists(gl_lights(), max_size=3), gl_colours,
           st.booleans(), st.booleans(), st.sampled_from(DTYPES))
    def run(amb, dif, spe, emi, shin, lights, scene_ambient, local_viewer, normalize, dtype):
        m = gl.Material(ambient=amb, diffuse=(*dif, 1.0), specular=spe, emission=emi, shininess=shin)
        p, n = arrays(dtype)
        tally.check(f"shade_vertices {m} {lights} {np.dtype(dtype).name}",
                    lambda: gl.shade_vertices(p, n, m, lights, scene_ambient, local_viewer, normalize=normalize),
                    dtype=dtype, hi=1.0)

    run()
    print(f"\nprobe gl (legal extremes): {tally.summary()}")
    assert tally.cases >= 300
    assert not tally.failures, tally.examples


# --------------------------------------------------------------------------- illegal values, one per call
NUMBER_BAD = [float("nan"), float("inf"), -float("inf"), 1j, "1", b"1", None, object(), [1.0, 2.0], {}, True]
COLOUR_BAD = [float("nan"), (0.5, float("nan"), 0.5), -0.1, (0.5, -1e-300, 0.5), (1, 2), [[1, 2, 3]], "red", b"1",
              None, 1j, np.array([1 + 0j, 0, 0]), (1, 2, 3, 4), {}, np.array([True, False, True])]
VECTOR_BAD = [(0, 0, float("nan")), (float("inf"), 0, 1), (0, 1), np.zeros((2, 4)), "up", b"001", None,
              (1j, 0, 1), np.array([[0, 0, 1 + 1j]]), object(), np.array([True, False, True]), ("0", "0", "1")]
COS_BAD = [float("nan"), float("inf"), 1.5, -2.0, "0.5", b"1", None, 1j, np.array([0.5, np.nan]), object(),
           True, np.array([0.5, 1j]), [0.5, "x"]]
SIN2_BAD = [b for b in COS_BAD if b is not None] + [-0.5]  # None is the default: "not given"
# The microfacet and Fresnel parameters may be arrays: a list of numbers is legal there.
ARRAY_NUMBER_BAD = [b for b in NUMBER_BAD if not isinstance(b, list)]

V = (0, 0, 1.0)


def _illegal_calls():
    """``(label, parameter, call)`` with one illegal argument each."""
    calls = []

    def add(label, param, bads, make):
        for bad in bads:
            calls.append((f"{label}({param}={bad!r:.40})", param, lambda bad=bad: make(bad)))

    add("Lambert", "kd", COLOUR_BAD, lambda b: Lambert(b))
    add("Phong", "ks", COLOUR_BAD, lambda b: Phong(b, 10))
    add("Phong", "shininess", NUMBER_BAD + [-1.0, -1e-300], lambda b: Phong(0.5, b))
    add("BlinnPhong", "ks", COLOUR_BAD, lambda b: BlinnPhong(b, 10))
    add("BlinnPhong", "shininess", NUMBER_BAD + [-1.0], lambda b: BlinnPhong(0.5, b))
    add("BlinnPhong", "normalized", [1, 0, "yes", None, 1.0, "True"], lambda b: BlinnPhong(0.5, 10, b))
    add("CookTorrance", "ks", COLOUR_BAD, lambda b: CookTorrance(b))
    add("CookTorrance", "roughness", NUMBER_BAD + [0.0, -1e-6, -1.0], lambda b: CookTorrance(1.0, b))
    add("CookTorrance", "f0", COLOUR_BAD + [1.5, (0.5, 1.01, 0.5)], lambda b: CookTorrance(1.0, 0.3, b))
    add("CookTorrance", "ndf", ["phong", "", None, 1, b"ggx"], lambda b: CookTorrance(ndf=b))
    add("CookTorrance", "geometry", ["none", None, 2.0], lambda b: CookTorrance(geometry=b))
    add("CookTorrance", "fresnel", ["metallic", None, True], lambda b: CookTorrance(fresnel=b))
    add("CookTorrance", "denominator", ["2", 2, 4.0, None, True, "π"], lambda b: CookTorrance(denominator=b))
    add("BRDFSum", "parts", ["lambert", None, 3], lambda b: BRDFSum(Lambert(0.5), b))
    models_ = [Lambert(0.5), Phong(0.5, 10), BlinnPhong(0.5, 1e6, True), CookTorrance(1, 0.1, ndf="ggx"),
               Lambert(0.5) + BlinnPhong(0.5, 20)]
    for model in models_:
        for form in ("eval", "eval_cos", "classic"):
            for i, name in enumerate("nlv"):
                def make(b, model=model, form=form, i=i):
                    args = [V, V, V]
                    args[i] = b
                    return getattr(model, form)(*args)

                add(f"{type(model).__name__}.{form}", name, VECTOR_BAD, make)
    big = np.zeros((200_000, 1, 3))
    calls.append(("Lambert.eval(huge broadcast)", "n, l, v",
                  lambda: Lambert(0.5).eval(big + V, np.swapaxes(big, 0, 1) + V, V)))
    calls.append(("Phong.eval(shapes not broadcasting)", "n, l and v",
                  lambda: Phong(0.5, 1).eval(np.ones((2, 3)), np.ones((3, 3)), V)))

    # microfacet
    for fn in (microfacet.beckmann_ndf, microfacet.ggx_ndf):
        add(fn.__name__, "cos_theta_h", COS_BAD, lambda b, fn=fn: fn(b, 0.3))
        add(fn.__name__, "alpha", ARRAY_NUMBER_BAD + [0.0, -1.0, np.array([0.3, -0.1])], lambda b, fn=fn: fn(0.5, b))
        add(fn.__name__, "sin2_theta_h", SIN2_BAD, lambda b, fn=fn: fn(0.5, 0.3, b))
    add("blinn_phong_ndf", "cos_theta_h", COS_BAD, lambda b: microfacet.blinn_phong_ndf(b, 10.0))
    add("blinn_phong_ndf", "exponent", ARRAY_NUMBER_BAD + [-1.0], lambda b: microfacet.blinn_phong_ndf(0.5, b))
    add("blinn_phong_ndf", "sin2_theta_h", SIN2_BAD, lambda b: microfacet.blinn_phong_ndf(0.5, 10.0, b))
    add("blinn_phong_exponent", "alpha", ARRAY_NUMBER_BAD + [0.0, -1.0],
        lambda b: microfacet.blinn_phong_exponent(b))
    for fn in (microfacet.smith_g1_beckmann, microfacet.smith_g1_ggx):
        add(fn.__name__, "cos_theta", COS_BAD, lambda b, fn=fn: fn(b, 0.3))
        add(fn.__name__, "alpha", ARRAY_NUMBER_BAD + [0.0, -1.0], lambda b, fn=fn: fn(0.5, b))
        add(fn.__name__, "sin2_theta", SIN2_BAD, lambda b, fn=fn: fn(0.5, 0.3, b))
    for i, name in enumerate(("n_dot_h", "n_dot_v", "n_dot_l", "v_dot_h")):
        def make_g(b, i=i):
            args = [0.5, 0.5, 0.5, 0.5]
            args[i] = b
            return microfacet.vcavity_g(*args)

        add("vcavity_g", name, COS_BAD, make_g)
    calls.append(("beckmann_ndf(shapes)", "cos_theta_h, sin2_theta_h",
                  lambda: microfacet.beckmann_ndf(np.ones(3) * 0.5, 0.3, np.ones(4) * 0.5)))
    # fresnel
    add("schlick", "cos_theta", COS_BAD, lambda b: fresnel.schlick(b, 0.04))
    add("schlick", "f0", COLOUR_BAD + [1.5, -0.5], lambda b: fresnel.schlick(0.5, b))
    add("dielectric", "cos_theta_i", COS_BAD, lambda b: fresnel.dielectric(b, 1.5))
    add("dielectric", "eta", NUMBER_BAD + [0.0, -1.5, (1.5, 0.0, 1.5)], lambda b: fresnel.dielectric(0.5, b))
    add("f0_from_eta", "eta", ARRAY_NUMBER_BAD + [0.0, -1.0], lambda b: fresnel.f0_from_eta(b))
    add("eta_from_f0", "f0", ARRAY_NUMBER_BAD + [-0.1, 1.5], lambda b: fresnel.eta_from_f0(b))

    # OpenGL mode
    gl_colour_bad = [float("nan"), (0.5, float("nan"), 0.5), (1, 2), [[1, 2, 3]], "red", b"1", None, 1j, 0.5,
                     np.array([1 + 0j, 0, 0]), (1, 2, 3, 4, 5), {}, np.array([True, False, True]), ("1", "0", "0")]
    for name in ("ambient", "diffuse", "specular", "emission"):
        negative = [(0.5, -0.1, 0.5), (0, 0, -1e-300, 1)] if name != "emission" else []  # emission may be < 0
        add("gl.Material", name, gl_colour_bad + negative, lambda b, name=name: gl.Material(**{name: b}))
    add("gl.Material", "shininess", NUMBER_BAD + [-1.0, 128.5, 1e300], lambda b: gl.Material(shininess=b))
    for name in ("ambient", "diffuse", "specular"):
        add("gl.Light", name, [float("nan"), (0, float("inf"), 0), "white", None, 1j, (1, 2), b"1"],
            lambda b, name=name: gl.Light(**{name: b}))
    add("gl.Light", "position", VECTOR_BAD + [(0, 0, 0, 0), (1, 2)], lambda b: gl.Light(position=b))
    add("gl.Light", "spot_direction", VECTOR_BAD + [(0, 0, 0)], lambda b: gl.Light(spot_direction=b))
    add("gl.Light", "spot_exponent", NUMBER_BAD + [-0.5, 129.0], lambda b: gl.Light(spot_exponent=b))
    add("gl.Light", "spot_cutoff", NUMBER_BAD + [-1.0, 90.5, 179.9, 181.0, 360.0], lambda b: gl.Light(spot_cutoff=b))
    for name in ("constant_attenuation", "linear_attenuation", "quadratic_attenuation"):
        add("gl.Light", name, NUMBER_BAD + [-1.0], lambda b, name=name: gl.Light(**{name: b}))
    calls.append(("gl.Light(all attenuations 0)", "constant_attenuation", lambda: gl.Light(constant_attenuation=0.0)))
    add("gl.Light.gl_default", "index", [-1, 1.5, "0", None, True], lambda b: gl.Light.gl_default(b))

    def shade(**kw):
        args = dict(positions=(0, 0, -1.0), normals=V, material=gl.Material(), lights=[gl.Light()])
        args.update(kw)
        return gl.shade_vertices(**args)

    add("gl.shade_vertices", "positions", VECTOR_BAD, lambda b: shade(positions=b))
    add("gl.shade_vertices", "normals", VECTOR_BAD, lambda b: shade(normals=b))
    add("gl.shade_vertices", "material", ["plastic", None, Lambert(0.5), 3], lambda b: shade(material=b))
    add("gl.shade_vertices", "lights", ["sun", b"sun", 3, None, {"a": 1}], lambda b: shade(lights=b))
    add("gl.shade_vertices", "lights[1]", ["sun", None, 3], lambda b: shade(lights=[gl.Light(), b]))
    add("gl.shade_vertices", "scene_ambient", [(0.2, 0.2), "grey", None, (float("nan"), 0, 0), 1j],
        lambda b: shade(scene_ambient=b))
    add("gl.shade_vertices", "local_viewer", ["yes", 1, None, 1.0], lambda b: shade(local_viewer=b))
    add("gl.shade_vertices", "normalize", ["no", 0, None], lambda b: shade(normalize=b))
    calls.append(("gl.shade_vertices(shapes)", "positions and normals",
                  lambda: shade(positions=np.zeros((2, 3)), normals=np.ones((3, 3)))))
    calls.append(("gl.shade_vertices(huge)", "positions",
                  lambda: shade(positions=np.broadcast_to(np.zeros(3), (10**8, 3)))))
    return calls


def test_probe_models_illegal_values():
    calls = _illegal_calls()
    tally = IllegalTally()

    # Every fixed illegal value once, then hypothesis-drawn ones: a NaN or inf at a random place of a
    # random-shape vector array, random out-of-range numbers.
    for label, param, call in calls:
        tally.classify(label, param, call)

    @settings(max_examples=300, **SETTINGS)
    @given(st.integers(0, 2**32 - 1), st.sampled_from(DTYPES), st.sampled_from(["eval", "eval_cos", "classic"]),
           st.sampled_from([float("nan"), float("inf"), -float("inf")]), st.floats(-1e300, -1e-300),
           st.floats(1.0 + 1e-5, 1e300), st.floats(90.0001, 179.999))
    def run(seed, dtype, form, bad, negative, above_one, cutoff):
        rng = np.random.default_rng(seed)
        shape = tuple(rng.integers(1, 4, rng.integers(0, 3))) + (3,)
        arr = rng.normal(size=shape).astype(dtype)
        arr[tuple(rng.integers(0, s) for s in shape)] = bad
        which = int(rng.integers(0, 3))
        args = [np.array(V, dtype)] * 3
        args[which] = arr
        model = [Lambert(0.5), Phong(0.5, 10), BlinnPhong(0.5, 10, True), CookTorrance()][seed % 4]
        tally.classify(f"{form}({'nlv'[which]}={bad} at random)", "nlv"[which],
                  lambda: getattr(model, form)(*args))
        tally.classify(f"Phong(shininess={negative})", "shininess", lambda: Phong(0.5, negative))
        tally.classify(f"CookTorrance(f0={above_one})", "f0", lambda: CookTorrance(1.0, 0.3, above_one))
        tally.classify(f"beckmann_ndf(cos={above_one})", "cos_theta_h",
                  lambda: microfacet.beckmann_ndf(above_one, 0.3))
        tally.classify(f"gl.Light(spot_cutoff={cutoff})", "spot_cutoff", lambda: gl.Light(spot_cutoff=cutoff))
        tally.classify(f"gl.Material(shininess={128 * above_one})", "shininess",
                  lambda: gl.Material(shininess=128 * above_one))

    run()
    print("\n" + tally.summary("models"))
    assert tally.calls >= 1500
    assert tally.named == tally.calls and tally.failures() == 0, tally.examples

