"""Fuzz probe of the integration and sampling API (checked arguments, honest errors), seeded and bounded.

(a) Legal extremes, drawn by hypothesis (derandomized) in float32 and float64: grazing views up to
    θ_v = π/2, shininess up to 1e6, roughness down to 1e-4, sample counts 1 … 48, tiny and huge
    patches, every method.  Each call must return finite values >= 0 with finite errors >= 0, keep
    the dtype, and raise no exception or NumPy warning.
(b) Illegal arguments, one per call, over every public function of lighting.integrate,
    lighting.sampling.brdf, lighting.lights.environment, lighting.analysis.audit and
    lighting.validation.accuracy: each must raise a ValueError or TypeError whose message names
    the parameter.

Both parts count their cases and failures by kind and print one summary line (``pytest -s``).
"""

from __future__ import annotations

import collections
import math
import re
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from probes import PROBE_SETTINGS, IllegalTally

from lighting import audit, environment, integrate, sampling
from lighting.models.brdf import BlinnPhong, CookTorrance, Lambert, Phong
from lighting.validation import accuracy

pytestmark = pytest.mark.slow  # seeded probe: many generated calls of the integration API

# ------------------------------------------------------------------------------------------ (a) legal extremes
LEGAL = collections.Counter()
LEGAL_FAILURES = collections.Counter()
LEGAL_EXAMPLES = []

unit = st.floats(0.0, 1.0)
shininess = st.sampled_from([0.0, 1e-300, 0.5, 1.0, 50.0, 1e3, 1e6]) | st.floats(0.0, 1e6)
roughness = st.sampled_from([1e-4, 1e-3, 0.02, 0.3, 1.0, 3.0]) | st.floats(1e-4, 3.0)


@st.composite
def models(draw):
    kind = draw(st.sampled_from(["lambert", "phong", "blinn", "ct", "sum"]))
    if kind == "lambert":
        return Lambert(draw(unit))
    if kind == "phong":
        return Phong(draw(unit), draw(shininess))
    if kind == "blinn":
        return BlinnPhong(draw(unit), draw(shininess), normalized=draw(st.booleans()))
    ct = CookTorrance(
        draw(unit),
        draw(roughness),
        draw(unit),
        ndf=draw(st.sampled_from(["beckmann", "ggx", "blinn-phong"])),
        geometry=draw(st.sampled_from(["v-cavity", "smith"])),
        fresnel=draw(st.sampled_from(["schlick", "none"])),
    )
    return ct if kind == "ct" else Lambert(draw(unit)) + ct


grazing = st.sampled_from([0.0, 1e-8, math.pi / 2 - 1e-7, math.pi / 2 - 1e-12, math.pi / 2])
grazing = grazing | st.floats(0.0, math.pi / 2)


def _direction(theta, phi):
    return np.array([math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)])


def _check_result(kind, value, dtype, error=None, nonnegative=True):
    value = np.asarray(value)
    if value.dtype != dtype:
        return "dtype"
    if not np.all(np.isfinite(value)):
        return "nonfinite"
    if nonnegative and np.any(value < 0):
        return "negative"
    if error is not None:
        error = np.asarray(error)
        if not np.all(np.isfinite(error)) or np.any(error < 0):
            return "bad error"
    return None


def _run_legal(kind, call, check):
    LEGAL[kind] += 1
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            with np.errstate(all="warn", under="ignore"):  # NumPy's defaults: underflow is no warning
                out = call()
    except Exception as exc:  # noqa: BLE001 - every kind of failure is counted
        LEGAL_FAILURES[f"{kind}: {type(exc).__name__}"] += 1
        LEGAL_EXAMPLES.append(f"{kind}: {type(exc).__name__}: {exc}")
        return
    bad = check(out)
    if bad:
        LEGAL_FAILURES[f"{kind}: {bad}"] += 1
        LEGAL_EXAMPLES.append(f"{kind}: {bad}")


PROBE = settings(max_examples=600, suppress_health_check=list(HealthCheck), **PROBE_SETTINGS)


@PROBE
@given(
    model=models(),
    theta=grazing,
    samples=st.integers(1, 48),
    method=st.sampled_from(integrate.METHODS),
    f32=st.booleans(),
    seed=st.integers(0, 2**32 - 1),
)
def test_probe_a_directional_albedo(model, theta, samples, method, f32, seed):
    dt = np.float32 if f32 else np.float64
    th = np.array([theta, 0.0], dtype=dt)

    def call():
        return integrate.directional_albedo(model, th, samples, method, seed=seed, return_error=True)

    def check(est):
        bad = _check_result("albedo", est.value, dt, est.error)
        if bad is None and est.unconverged.shape != est.value.shape:
            bad = "flag shape"
        return bad

    _run_legal("directional_albedo", call, check)


@PROBE
@given(
    model=models(),
    theta_n=st.floats(0.0, math.pi), phi_n=st.floats(0.0, 2 * math.pi),
    theta_v=grazing, phi_v=st.floats(0.0, 2 * math.pi),
    samples=st.integers(1, 40),
    method=st.sampled_from(integrate.RADIANCE_METHODS),
    env_kind=st.sampled_from(["constant", "patch", "big patch", "latlong", "function"]),
    solid=st.sampled_from([1e-12, 1e-6, 1e-3, 4 * math.pi]),
    f32=st.booleans(),
    seed=st.integers(0, 2**32 - 1),
)  # fmt: skip
def test_probe_a_outgoing_radiance(model, theta_n, phi_n, theta_v, phi_v, samples, method, env_kind, solid, f32, seed):
    dt = np.float32 if f32 else np.float64
    n = _direction(theta_n, phi_n).astype(dt)
    v = _direction(theta_v, phi_v).astype(dt)
    if method == "sh":
        model = Lambert(0.5)
    env = {
        "constant": lambda: environment.ConstantEnvironment((1.0, 0.0, 1e3)),
        "patch": lambda: environment.SmallPatchEnvironment(_direction(theta_v, phi_n + 1), solid, 1e6),
        "big patch": lambda: environment.SmallPatchEnvironment((0, 0, -1.0), 4 * math.pi - 1e-9, 2.0),
        "latlong": lambda: environment.LatLongEnvironment(np.eye(6)[:, :, None].repeat(2, 1)[:, :8].repeat(3, 2)),
        "function": lambda: environment.FunctionEnvironment(lambda d: np.abs(d) ** 4),
    }[env_kind]()

    def call():
        return integrate.outgoing_radiance(model, env, n, v, method=method, samples=samples, seed=seed,
                                           sh_samples=64, return_error=True)  # fmt: skip

    _run_legal("outgoing_radiance", call, lambda est: _check_result("radiance", est.value, dt, est.error))


@PROBE
@given(
    model=models(),
    u0=st.sampled_from([0.0, 1.0, 1 - 2**-53, 0.5]) | unit,
    u1=unit,
    theta_v=grazing,
    which=st.sampled_from(["importance", "uniform", "cosine"]),
)
def test_probe_a_samplers(model, u0, u1, theta_v, which):
    sampler = {"uniform": sampling.UniformSampler(), "cosine": sampling.CosineSampler()}.get(which)
    sampler = sampler or sampling.importance_sampler(model)
    v = _direction(theta_v, 0.3)

    def call():
        s = sampler.sample(np.array([[u0, u1]]), v)
        return s, sampler.pdf(s.directions, v)

    def check(out):
        s, p = out
        bad = _check_result("sample", s.directions, np.float64, nonnegative=False)
        bad = bad or _check_result("pdf", s.pdf, np.float64) or _check_result("pdf", p, np.float64)
        return bad

    _run_legal("sampler", call, check)


@PROBE
@given(
    coeff=st.floats(-1e3, 1e3),
    theta=st.floats(0.0, math.pi),
    f32=st.booleans(),
    samples=st.integers(1, 30),
    view_samples=st.integers(1, 4),
    model=models(),
)
def test_probe_a_sh_and_hemispherical(coeff, theta, f32, samples, view_samples, model):
    dt = np.float32 if f32 else np.float64
    c = np.zeros((9, 3))
    c[0] = 1.0
    c[6] = coeff
    normal = _direction(theta, 1.0).astype(dt)
    _run_legal("sh_irradiance", lambda: integrate.sh_irradiance(c, normal), lambda e: _check_result("sh", e, dt))

    def hemi():
        return integrate.hemispherical_albedo(model, samples, "importance", view_samples=view_samples, seed=1,
                                              return_error=True)  # fmt: skip

    _run_legal("hemispherical_albedo", hemi, lambda est: _check_result("hemi", est.value, np.float64, est.error))


def test_probe_a_summary():
    # Runs after the hypothesis tests above (file order); asserts what they counted.
    total, fails = sum(LEGAL.values()), sum(LEGAL_FAILURES.values())
    if total == 0:
        pytest.skip("the (a) probes above did not run in this test run (deselected)")
    kinds = ", ".join(f"{k} {v}" for k, v in sorted(LEGAL.items()))
    print(f"\nprobe integrate (a) legal extremes: {total} cases ({kinds}), {fails} failures "
          f"{dict(LEGAL_FAILURES) or ''}")  # fmt: skip
    assert total >= 3000
    assert fails == 0, LEGAL_EXAMPLES[:10]


# ------------------------------------------------------------------------------------------ (b) illegal values
L05 = Lambert(0.5)
N = (0.0, 0.0, 1.0)
ENV = environment.ConstantEnvironment(1.0)
NAN, INF = float("nan"), float("inf")
VECTOR_BAD = ["abc", b"1", (NAN, 0.0, 1.0), (INF, 0.0, 0.0), (1j, 0.0, 1.0), None, (1.0, 2.0), object(), {"x": 1}]
COUNT_BAD = [0, -1, 1.5, "8", b"8", True, None, 10**9, 10**30, 1j]
FLOAT_BAD = [NAN, INF, -INF, "1", b"1", 1j, None, object()]
BOOL_BAD = [1, "yes", None, 0.0]
SEED_BAD = [-1, 1.5, "1", True, b"1"]
METHOD_BAD = ["nope", 3, None, b"importance", ""]
BRDF_BAD = [None, "lambert", 3, object()]
U_BAD = [(1.5, 0.5), (-0.1, 0.5), (NAN, 0.5), (0.5, 0.5, 0.5), "x", b"x", None, (1j, 0.5)]


def _phong_sampler():
    return sampling.PhongSampler(8.0)


def _mixture():
    return sampling.MixtureSampler([sampling.CosineSampler(), sampling.UniformSampler()], [1.0, 1.0])


def _latlong():
    return environment.LatLongEnvironment(np.ones((2, 4, 3)))


def _patch():
    return environment.SmallPatchEnvironment(N, 1e-3, 1.0)


# (function, legal keyword arguments, {parameter: [illegal values]}); each call replaces one argument.
CASES = [
    (integrate.directional_albedo, dict(brdf=L05, theta_v=0.3, samples=16, method="uniform", seed=1),
     dict(brdf=BRDF_BAD, theta_v=[-0.1, 2.0, *FLOAT_BAD, (0.1, "x")], samples=COUNT_BAD, method=METHOD_BAD,
          seed=SEED_BAD, replicates=[1, 0, 10**6, 2.5, "4"], return_error=BOOL_BAD)),
    (integrate.albedo_curve, dict(brdf=L05, thetas=[0.1, 0.2], samples=16),
     dict(brdf=BRDF_BAD, thetas=[[-1.0], [[0.1]], "x", [NAN]], samples=COUNT_BAD, method=METHOD_BAD, seed=SEED_BAD)),
    (integrate.hemispherical_albedo, dict(brdf=L05, samples=16),
     dict(brdf=BRDF_BAD, samples=COUNT_BAD, method=METHOD_BAD, view_samples=COUNT_BAD + [5000], seed=SEED_BAD,
          return_error=BOOL_BAD)),
    (integrate.outgoing_radiance, dict(brdf=L05, environment=ENV, normals=N, view_dirs=N, samples=16),
     dict(brdf=BRDF_BAD, environment=["sky", b"1", (NAN, 1, 1), -1.0, None, (1.0, 2.0)], normals=VECTOR_BAD,
          view_dirs=VECTOR_BAD, method=METHOD_BAD, samples=COUNT_BAD, seed=SEED_BAD, sh_samples=COUNT_BAD,
          return_error=BOOL_BAD)),
    (integrate.sh_basis, dict(directions=N), dict(directions=VECTOR_BAD)),
    (integrate.sh_coefficients, dict(environment=ENV, samples=64),
     dict(environment=["sky", None, -2.0], samples=COUNT_BAD, return_error=BOOL_BAD)),
    (integrate.sh_irradiance, dict(coeffs=np.ones(9), normals=N),
     dict(coeffs=[np.ones(8), np.full(9, NAN), "x", None, np.ones((9, 2)), np.ones(9) * 1j], normals=VECTOR_BAD,
          clamp=BOOL_BAD)),
    (integrate.point_light_limit, dict(brdf=L05, light_dir=(0, 0.6, 0.8), solid_angles=(1e-2,), samples=64),
     dict(brdf=BRDF_BAD, light_dir=VECTOR_BAD + [(0, 0, 0)], normal=VECTOR_BAD + [(0, 0, 0)],
          view_dir=VECTOR_BAD + [(0, 0, 0)], radiance=[-1.0, *FLOAT_BAD], solid_angles=[(0.0,), (-1,), (20.0,), "x",
          (NAN,), ()], samples=COUNT_BAD)),
    (sampling.as_generator, dict(seed=1), dict(seed=SEED_BAD)),
    (sampling.jittered, dict(count=4), dict(count=COUNT_BAD, seed=SEED_BAD)),
    (sampling.jittered_batch, dict(batch=(2,), count=4), dict(batch=[5, "x", (1.5,), (-1,), (10**6, 10**6)],
                                                              count=COUNT_BAD, seed=SEED_BAD)),
    (sampling.square_to_uniform_hemisphere, dict(u=(0.5, 0.5)), dict(u=U_BAD)),
    (sampling.square_to_cosine_hemisphere, dict(u=(0.5, 0.5)), dict(u=U_BAD)),
    (sampling.uniform_hemisphere_pdf, dict(d=N), dict(d=VECTOR_BAD)),
    (sampling.cosine_hemisphere_pdf, dict(d=N), dict(d=VECTOR_BAD)),
    (sampling.sample_uniform, dict(count=4), dict(count=COUNT_BAD, seed=SEED_BAD)),
    (sampling.sample_cosine, dict(count=4), dict(count=COUNT_BAD, seed=SEED_BAD)),
    (sampling.sample_stratified, dict(count=4), dict(count=COUNT_BAD, seed=SEED_BAD, warp=METHOD_BAD)),
    (sampling.PhongSampler, dict(exponent=8.0), dict(exponent=[-1.0, *FLOAT_BAD])),
    (sampling.MicrofacetSampler, dict(ndf="ggx", alpha=0.3), dict(ndf=METHOD_BAD, alpha=[0.0, -1.0, *FLOAT_BAD])),
    (sampling.MicrofacetSampler, dict(ndf="blinn-phong", exponent=3.0), dict(exponent=[-1.0, *FLOAT_BAD])),
    (sampling.MixtureSampler, dict(samplers=[sampling.CosineSampler()], weights=[1.0]),
     dict(samplers=[[], "ab", None, 3, [3], sampling.CosineSampler()], weights=[[-1.0], [0.0], [NAN], ["x"], [1, 1],
          None])),
    (lambda u, v: _phong_sampler().sample(u, v), dict(u=(0.5, 0.5), v=N), dict(u=U_BAD, v=VECTOR_BAD)),
    (lambda u, v: sampling.CosineSampler().sample(u, v), dict(u=(0.5, 0.5), v=N), dict(u=U_BAD, v=VECTOR_BAD)),
    (lambda u, v: _mixture().sample(u, v), dict(u=(0.5, 0.5), v=N), dict(u=U_BAD, v=VECTOR_BAD)),
    (lambda l, v: _phong_sampler().pdf(l, v), dict(l=N, v=N), dict(l=VECTOR_BAD, v=VECTOR_BAD)),
    (lambda l, v: sampling.MicrofacetSampler("ggx", 0.3).pdf(l, v), dict(l=N, v=N), dict(l=VECTOR_BAD, v=VECTOR_BAD)),
    (lambda h: sampling.MicrofacetSampler("ggx", 0.3).normal_pdf(h), dict(h=N), dict(h=VECTOR_BAD)),
    (lambda u: sampling.MicrofacetSampler("beckmann", 0.3).sample_normals(u), dict(u=(0.5, 0.5)), dict(u=U_BAD)),
    (lambda v: _mixture().weights(v), dict(v=N), dict(v=VECTOR_BAD)),
    (sampling.importance_sampler, dict(brdf=L05), dict(brdf=BRDF_BAD)),
    (sampling.sample_brdf, dict(brdf=L05, v=N, count=4),
     dict(brdf=BRDF_BAD, v=VECTOR_BAD, count=COUNT_BAD, seed=SEED_BAD, stratified=BOOL_BAD)),
    (sampling.f_cos_local, dict(brdf=L05, l=N, v=N), dict(brdf=BRDF_BAD, l=VECTOR_BAD, v=VECTOR_BAD)),
    (environment.ConstantEnvironment, dict(radiance=1.0), dict(radiance=[-1.0, *FLOAT_BAD, (1.0, 2.0)])),
    (environment.LatLongEnvironment, dict(image=np.ones((2, 4, 3))),
     dict(image=[np.ones((2, 4)), -np.ones((2, 4, 3)), np.full((2, 4, 3), NAN), "x", None, np.ones((2, 4, 3)) * 1j])),
    (environment.LatLongEnvironment.from_function, dict(func=np.abs, height=2),
     dict(func=[3, None, "f"], height=COUNT_BAD, width=[0, -1, 1.5, "8", 10**9])),
    (environment.LatLongEnvironment.pixel_directions, dict(height=2, width=4),
     dict(height=COUNT_BAD, width=COUNT_BAD)),
    (environment.FunctionEnvironment, dict(func=lambda d: d), dict(func=[3, None, "f", b"f"])),
    (environment.SmallPatchEnvironment, dict(direction=N, solid_angle=1e-3, radiance=1.0),
     dict(direction=VECTOR_BAD + [(0, 0, 0), np.ones((2, 3))], solid_angle=[0.0, -1.0, 13.0, *FLOAT_BAD],
          radiance=[-1.0, *FLOAT_BAD])),
    (lambda directions: ENV.radiance(directions), dict(directions=N), dict(directions=VECTOR_BAD)),
    (lambda directions: _latlong().radiance(directions), dict(directions=N), dict(directions=VECTOR_BAD)),
    (lambda directions: _patch().pdf(directions), dict(directions=N), dict(directions=VECTOR_BAD)),
    (lambda u: ENV.sample(u), dict(u=(0.5, 0.5)), dict(u=U_BAD)),
    (lambda u: _latlong().sample(u), dict(u=(0.5, 0.5)), dict(u=U_BAD)),
    (lambda u: _patch().sample(u), dict(u=(0.5, 0.5)), dict(u=U_BAD)),
    (environment.uniform_sphere, dict(u=(0.5, 0.5)), dict(u=U_BAD)),
    (environment.uniform_sphere_pdf, dict(directions=N), dict(directions=VECTOR_BAD)),
    (environment.as_environment, dict(env=1.0), dict(env=["sky", b"1", -1.0, (NAN, 1, 1), None, (1.0, 2.0)])),
    (audit.audit, dict(models=[L05], samples=64, view_angles_deg=[0.0], n_theta=2, n_phi=2),
     dict(models=["ab", L05, [], [3], 5], samples=COUNT_BAD, view_angles_deg=[[-1.0], [91.0], "x", [NAN], []],
          n_theta=COUNT_BAD, n_phi=COUNT_BAD, reciprocity_tol=[-1.0, *FLOAT_BAD], energy_tol=[-1.0, *FLOAT_BAD])),
    (audit.direction_pairs, dict(n_theta=2, n_phi=2),
     dict(n_theta=COUNT_BAD, n_phi=COUNT_BAD, max_theta_deg=[-1.0, 91.0, *FLOAT_BAD])),
    (accuracy.run_studies, dict(only=["precision"]),
     dict(quick=BOOL_BAD, only=[["nope"], [3], 5, b"x"], progress_factory=[3, "x"])),
    (accuracy.summary, dict(studies=[]), dict(studies=[5, ["x"], None], thresholds=[[0.0], [-1.0], ["x"], [NAN], []])),
]  # fmt: skip

# Names a message may use for a parameter (the error comes from a helper that knows the public name).
ALIASES = {"env": ("environment",), "only": ("only", "study")}


def _named(message: str, name: str) -> bool:
    for n in (name, *ALIASES.get(name, ())):
        if re.match(rf"{re.escape(n)}\b", message) or re.search(rf"(?<![\w.]){re.escape(n)}(?![\w])", message):
            return True
    return False


def test_probe_b_illegal_values_raise_named_errors():
    tally = IllegalTally()
    for func, legal, bad in CASES:
        fname = getattr(func, "__qualname__", repr(func))
        for param, values in bad.items():
            for value in values:
                kwargs = dict(legal) | {param: value}
                tally.classify(f"{fname}({param}={value!r})", param, lambda f=func, k=kwargs: f(**k), names=_named)
    print("\n" + tally.summary("integrate"))
    assert tally.named == tally.calls and tally.failures() == 0, tally.examples
    assert tally.calls >= 400


def test_probe_b_legal_base_calls_work():
    # The legal keyword sets above must themselves be accepted, so each illegal call tests one argument.
    for func, legal, _bad in CASES:
        func(**legal)


@pytest.mark.parametrize("samples", [10**9, 2**40])
def test_huge_sample_counts_are_refused_before_allocating(samples):
    # Refused by the memory budget before anything is allocated: 10**9 samples would take 6 GiB.
    with pytest.raises(ValueError, match=r"samples needs about .* over the memory budget"):
        integrate.directional_albedo(Phong(1.0, 50.0), 0.3, samples, "importance")
    with pytest.raises(ValueError, match="samples"):
        integrate.outgoing_radiance(L05, ENV, N, N, samples=samples, method="uniform")
    with pytest.raises(ValueError, match="count"):
        sampling.sample_uniform(samples)
