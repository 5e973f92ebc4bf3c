"""The explorer's comparison list: overlays, show/hide/solo, albedo curves, BRDF files, fitting, the split sphere."""

import math

import numpy as np
import pytest

from explorer import app as app_mod
from explorer.app import comparing
from explorer.app.command import main
from explorer.app.comparing import ALBEDO_ANGLES_DEG, restrict
from explorer.app.state import AppState
from explorer.app.views import ExplorerModel
from lighting import Lambert, Phong
from lighting.analysis import polar_slice, theta_d_curve, theta_h_curve, theta_v_curve

pv = pytest.importorskip("pyvista")
PI = "const float PI = 3.14159265358979323846;\n"
SIG = "vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)"
LAMBERT = (f"::begin parameters\ncolor kd 0.8 0.5 0.2\n::end parameters\n::begin shader\n{PI}{SIG} "
           "{ return kd / PI; }\n::end shader\n")  # fmt: skip
PHONG = (
    "::begin parameters\ncolor ks 0.5 0.4 0.3\nfloat n 0 1000 20\n::end parameters\n::begin shader\n" + PI + SIG
    + "{\n vec3 R = reflect(-L, N);\n return ks * pow(max(dot(R, V), 0.0), n) / (PI * dot(N, L));\n}\n::end shader\n"
)  # fmt: skip
#: Cook-Torrance GGX, height-correlated Smith, Schlick: the explorer's default fit, written as a file.
GGX = (
    "::begin parameters\ncolor ks 1 1 1\nfloat roughness 0.01 1 0.25\ncolor f0 0.9 0.6 0.3\n::end parameters\n"
    "::begin shader\n" + PI
    + "float lam(float c, float a) { float t2 = (1.0 - c * c) / (c * c);\n"
    " return 0.5 * (sqrt(1.0 + a * a * t2) - 1.0); }\n"
    + SIG + "\n{\n vec3 H = normalize(L + V);\n float nh = dot(N, H), nv = dot(N, V), nl = dot(N, L), vh = dot(V, H);\n"
    " float a2 = roughness * roughness; float d = nh * nh * (a2 - 1.0) + 1.0;\n"
    " float G = 1.0 / (1.0 + lam(nv, roughness) + lam(nl, roughness));\n"
    " vec3 F = f0 + (vec3(1.0) - f0) * pow(1.0 - vh, 5.0);\n"
    " return ks * a2 / (PI * d * d) * G * F / (4.0 * nv * nl);\n}\n::end shader\n"
)  # fmt: skip


def pairs(n=300, seed=1):
    rng = np.random.default_rng(seed)
    l, v = rng.normal(size=(2, n, 3))
    return np.array([0.0, 0.0, 1.0]), l / np.linalg.norm(l, axis=-1, keepdims=True), v / np.linalg.norm(v, axis=-1,
                                                                                                      keepdims=True)


def small_model(**values):
    return ExplorerModel(AppState(**values), sphere_size=48, mesh_size=48, lobe_resolution=8)


# ----------------------------------------------------------------------------- overlays
def test_overlays_are_each_entrys_slices_and_curves():
    m = small_model(model="phong", shininess=20.0, elevation=60.0)
    m.pin()
    m.state.update(model="cook-torrance", roughness=0.2, terms=("diffuse", "specular"))
    m.pin()
    m.state.update(model="blinn-phong", terms=("specular",), phi=150.0)
    m.update()
    s = m.state
    theta, phi = min(s.theta_l, math.pi / 2), math.radians(s.phi)
    opts = s.plot_options()
    assert [o.label for o in m.views["polar"].overlays] == [e.label for e in m.compare]
    for o, e in zip(m.views["polar"].overlays, m.compare, strict=True):
        brdf = restrict(e.brdf, s.terms)
        assert len(brdf.parts) == 1 and brdf.term == "specular"  # the diffuse part is switched off, as for the current
        want = polar_slice(brdf, theta, fixed="light", phi_in=phi, n=361, **opts)
        np.testing.assert_array_equal(o.angles, want.angles)
        np.testing.assert_array_equal(o.values, want.values)
        assert o.colour == e.colour and o.values.max() > 0
    for name, curve in (("theta_v", lambda b: theta_v_curve(b, theta, phi_l=phi, n=181, **opts)),
                        ("theta_h", lambda b: theta_h_curve(b, theta_d=theta, phi_h=phi, n=181, **opts)),
                        ("theta_d", lambda b: theta_d_curve(b, theta_h=0.0, phi_h=phi, n=181, **opts))):  # fmt: skip
        for o, e in zip(m.views[name].overlays, m.compare, strict=True):
            np.testing.assert_array_equal(o.values, curve(restrict(e.brdf, s.terms)).values)


def test_a_pinned_entry_keeps_its_parameters_and_changing_the_list_recomputes_only_its_views():
    m = small_model(model="phong", shininess=20.0)
    m.update()
    entry = m.pin()
    assert entry.label == "Phong e=20 k_s=0.5"
    n, l, v = pairs()
    want = (Lambert(m.state.diffuse_albedo) + Phong(0.5, 20.0)).eval(n, l, v)
    np.testing.assert_array_equal(entry.brdf.eval(n, l, v), want)
    assert m.update() == {"polar", "theta_v", "theta_h", "theta_d", "albedo"}  # not the images, lobe or half/diff
    m.state.shininess = 300.0
    m.update()
    np.testing.assert_array_equal(entry.brdf.eval(n, l, v), want)  # the controls moved on, the entry did not
    m.compare.set_visible(0, False)
    assert m.update() == {"polar", "theta_v", "theta_h", "theta_d", "albedo"}
    assert m.views["polar"].overlays == ()
    m.state.split = True  # nothing shown: nothing for the right half
    assert "sphere" not in m.update()


# ----------------------------------------------------------------------------- albedo curves
def test_albedo_curves_of_lambert_are_kd_and_entries_are_cached(monkeypatch):
    m = small_model(model="lambert", kd=0.6, color=(1.0, 1.0, 1.0), panel="albedo")
    m.update()
    entry = m.pin()
    m.state.kd = 0.3
    m.update()
    current, pinned = m.views["albedo"].curves
    np.testing.assert_allclose(current.theta, np.radians(ALBEDO_ANGLES_DEG))
    assert current.theta.max() < math.pi / 2  # 90° is the horizon, where every BRDF is 0
    np.testing.assert_allclose(current.value, 0.3, atol=1e-6)
    np.testing.assert_allclose(pinned.value, 0.6, atol=1e-6)
    assert pinned.colour == entry.colour and current.colour is None
    for c in (current, pinned):
        assert c.error.max() < 1e-6 and not c.unconverged.any()
    calls = []
    real = comparing.albedo_curve
    monkeypatch.setattr(comparing, "albedo_curve", lambda *a, **k: calls.append(a[0]) or real(*a, **k))
    for elevation in (20.0, 70.0, 5.0):  # the light moves: no curve depends on it
        m.state.elevation = elevation
        assert "albedo" in m.update()
    m.state.channel = "r"
    m.update()
    assert calls == []
    m.pin()  # a new entry: that one alone is integrated
    m.update()
    assert len(calls) == 1
    np.testing.assert_allclose(m.views["albedo"].curves[2].value, 0.3, atol=1e-6)
    m.state.panel = "angles"  # the angle curves shown: no albedo curves at all
    m.update()
    assert m.views["albedo"].curves == ()


def test_a_sharp_lobe_is_flagged_unconverged():
    # A mirror-like lobe beside a Lambert part: the quadrature's nodes cannot resolve both (4 % error).
    m = small_model(model="cook-torrance", roughness=1e-6, f0=1.0, panel="albedo")
    m.update()
    (c,) = m.views["albedo"].curves
    assert c.unconverged.any()
    rel = c.error[c.unconverged] / np.abs(c.value[c.unconverged])
    assert (rel > 0.02).all()


# ----------------------------------------------------------------------------- files from the command line
class _FakeWindow:
    made = []

    def __init__(self, state, **kwargs):
        self.state, self.kwargs = state, kwargs
        _FakeWindow.made.append(self)

    def image(self):
        return np.zeros((8, 8, 3), np.uint8)

    def close(self):
        pass


def test_brdf_option_opens_files_as_models(tmp_path, monkeypatch, capsys):
    (tmp_path / "my lambert.brdf").write_text(LAMBERT)
    (tmp_path / "phong.brdf").write_text(PHONG)
    monkeypatch.setattr(app_mod, "ExplorerApp", _FakeWindow)
    _FakeWindow.made.clear()
    out = tmp_path / "shot.png"
    argv = ["--brdf", str(tmp_path / "my lambert.brdf"), "--brdf", str(tmp_path / "phong.brdf"), "--screenshot",
            str(out)]  # fmt: skip
    assert main(argv) == 0 and out.exists()
    (window,) = _FakeWindow.made
    state, compare = window.state, window.kwargs["compare"]
    assert state.model == "my-lambert" and [p.name for p in app_mod.state.offered_parameters(state.model)] == ["kd"]
    n, l, v = pairs()
    # The file's own model, its colour its own (no Lambert added, k_d × colour does not replace it).
    np.testing.assert_allclose(state.brdf().eval(n, l, v), Lambert((0.8, 0.5, 0.2)).eval(n, l, v), rtol=1e-6,
                               atol=1e-12)  # fmt: skip
    (entry,) = list(compare)
    assert entry.label == "phong.brdf"
    np.testing.assert_allclose(entry.brdf.eval(n, l, v), Phong((0.5, 0.4, 0.3), 20).eval(n, l, v), rtol=1e-6,
                               atol=1e-12)  # fmt: skip


def test_brdf_option_refuses_a_bad_file_in_one_line(tmp_path, capsys):
    bad = tmp_path / "broken.brdf"
    bad.write_text("::begin shader\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { return L +; }\n::end shader\n")
    assert main(["--brdf", str(bad), "--off-screen"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "broken.brdf" in err and "Traceback" not in err
    assert main(["--brdf", str(tmp_path / "missing.binary"), "--off-screen"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "missing.binary" in err


# ----------------------------------------------------------------------------- fitting and the split sphere
def test_split_sphere_halves_are_the_single_model_renders():
    m = small_model(model="cook-torrance", roughness=0.15, elevation=30.0, azimuth=160.0)
    m.update()
    pinned_alone = m.views["sphere"].image.copy()
    entry = m.pin()
    m.state.update(model="phong", shininess=8.0)
    m.update()
    current_alone = m.views["sphere"].image.copy()
    m.state.split = True
    assert "sphere" in m.update()
    split = m.views["sphere"]
    half = split.image.shape[1] // 2
    mine = split.split_mask  # the current model's half: counter-clockwise of the divider along the light's azimuth
    assert split.split == entry.label and split.split_colour == entry.colour and split.split_angle == 160.0
    np.testing.assert_array_equal(split.image[mine], current_alone[mine])
    np.testing.assert_array_equal(split.image[~mine], pinned_alone[~mine])
    assert not np.array_equal(current_alone[~mine], pinned_alone[~mine])
    # The solo entry takes the right half; a drag re-shades both halves (a live view).
    m.pin()
    m.compare.set_solo(1)
    m.state.elevation = 50.0
    assert m.update(only={"sphere"}) == {"sphere"}
    m.state.split = False
    m.update()
    np.testing.assert_array_equal(m.views["sphere"].image[:, half:], m.views["sphere"].image[:, half:])
    assert m.views["sphere"].split == ""
