"""Event-storm probe of the explorer: seeded, bounded storms over every control.

Two storms, each counted by event kind and by kind of failure, each asserting zero failures and
printing one summary line (``pytest -s`` shows it):

* the window (:class:`explorer.qt.window.ExplorerWindow`, under pytest-qt): slider drags through the
  control panel's editors themselves (positions past either end included), releases, keys, check boxes,
  choice boxes, and invalid values;
* the model alone (:class:`explorer.app.views.ExplorerModel`, no VTK): many more random states,
  every control at once, light at, near and below the horizon, extreme materials.

After each event, once the views are up to date (a drag leaves the plots for the release):

* every view is finite (no NaN, no inf in any float array);
* item 2: a light on or below the horizon (θ_l >= 90° at the facing point) reflects nothing in
  every BRDF view — the lobe, both polar slices, the θ_v and θ_h curves, the albedo;
* item 3: otherwise the 3D lobe, the polar slice and the θ_v curve report the same peak (stated
  bound: 1e-6 relative; 1 % would be acceptable);
* the sliders, choice boxes and check boxes show the state (the model's own controls included);
* an invalid value is refused with a message naming the control (a ValueError from the state, the
  same line in the window's status bar), and leaves the state and every view unchanged.
"""

from __future__ import annotations

import math
from collections import Counter

import numpy as np
import pytest

from explorer.app.lights import EXTRA_LIGHT_TYPES, new_light
from explorer.app.params import offered_parameters
from explorer.app.state import CONTROLS, MODELS, AppState
from explorer.app.views import LIVE_VIEWS, ExplorerModel

pytestmark = pytest.mark.slow  # seeded probe: event storms over every control

pytest.importorskip("pyvista")

SEED = 20241114
PEAK_RTOL = 1e-6
APP_EVENTS = 200
MODEL_EVENTS = 260
#: The controls the storms draw from.  The extra lights (scene_lights) change in a stream of their own (the model
#: storm), so that adding them left the storms' seeded sequences of events as they were.
STORM_CONTROLS = tuple(n for n in CONTROLS if n != "scene_lights")
#: The key actions the window's storm presses (explorer.qt.keys.KEY_ACTIONS: m M t i c f 1 2 3 l n arrows r h e).
KEYS = ("model+", "model-", "light+", "mode+", "channel+", "form+", "term1", "term2", "term3", "log", "times_cos",
        "scan-", "scan+", "tess-", "tess+", "reset", "help", "edges")  # fmt: skip

#: Invalid values by control kind (besides out-of-range numbers, made per control below).
INVALID = {
    "float": [b"1", "0.5", None, float("nan"), float("inf"), -float("inf"), 1j, True, [0.5], {}, object()],
    "int": [7.5, "8", b"8", None, float("nan"), True, 8 + 0j, [8]],
    "choice": ["bogus", b"phong", 0, None, ("phong",)],
    "rgb": [
        b"1",
        "1,0,0",
        (1.0, 2.0, 0.0),
        (0.5, 0.5),
        (float("nan"), 0.0, 0.0),
        None,
        (True, False, True),
        -0.1,
        (b"1", 0.0, 0.0),
        {"r": 1.0},
    ],  # fmt: skip
    "terms": [{}, {"ambient": 1}, "glow", b"ambient", 3, ("ambient", 1), None],
    "bool": ["yes", 1, None, 0.0, b"1"],
    "lights": ["rect", b"rect", {"type": "rect", "center": [0.0, 0.0, 3.0]}, 3, None],
}


def _invalid_values(name):
    spec = CONTROLS[name]
    values = list(INVALID[spec.kind])
    if spec.kind in ("float", "int") and name not in ("azimuth", "phi"):  # the angles wrap: 361° is 1°
        values += [spec.lo - 1.0 - abs(spec.lo), spec.hi + 1.0 + abs(spec.hi)]
        if spec.kind == "int":
            values = [int(v) if isinstance(v, float) and v.is_integer() else v for v in values]
    return values


# ----------------------------------------------------------------------------- the laws
def _finite(views) -> bool:
    for view in views.values():
        for value in vars(view).values():
            if isinstance(value, np.ndarray) and value.dtype.kind == "f" and not np.all(np.isfinite(value)):
                return False
            if isinstance(value, float) and not math.isfinite(value) and value != math.inf:
                return False  # relative errors may be inf (a zero value with an error); NaN never
    return True


def _isotropic(brdf) -> bool:
    """Whether turning l and v together about the normal leaves f_r as it is (five random pairs, 1e-9)."""
    rng = np.random.default_rng(5)
    d = rng.normal(size=(2, 5, 3))
    d[..., 2] = np.abs(d[..., 2]) + 0.1
    c, s_ = math.cos(0.7), math.sin(0.7)
    turn = np.array([[c, -s_, 0.0], [s_, c, 0.0], [0.0, 0.0, 1.0]])
    n = (0.0, 0.0, 1.0)
    a, b = brdf.eval(n, d[0], d[1]), brdf.eval(n, d[0] @ turn.T, d[1] @ turn.T)
    return bool(np.allclose(a, b, rtol=1e-9, atol=1e-300))


def _check_laws(model, failures: Counter) -> None:
    views = model.views
    if not _finite(views):
        failures["not finite"] += 1
    if model.pending:
        return  # the plots wait for the release; the laws hold once they follow
    s = model.state
    if s.lock:
        return  # the retro-reflection views do not depend on the light: the laws below are the light's
    lobe, polar, curve = views["lobe"], views["polar"], views["theta_v"]
    if s.theta_l >= 0.5 * math.pi:
        dark = (
            lobe.peak == 0.0
            and not np.any(lobe.values)
            and not np.any(polar.light_fixed)
            and not np.any(polar.view_fixed)
            and not np.any(curve.values)
            and not np.any(views["theta_h"].values)
            and views["albedo"].value == 0.0
            and polar.below_horizon
            and lobe.below_horizon
        )
        if not dark:
            failures["horizon: a view reflects light from below"] += 1
    elif s.phi % 90.0 == 0.0 or _isotropic(s.plot_brdf()):  # off the axes an anisotropic lobe leaves the plane
        a, b = float(polar.light_fixed.max()), float(curve.values.max())
        top = lobe.peak
        if not (abs(a - top) <= PEAK_RTOL * top and abs(b - top) <= PEAK_RTOL * top):
            failures["peak: views of one slice disagree"] += 1


def _shows(editor, value) -> bool:
    """Whether a control panel's editor shows ``value`` (a number: the knob at its position, the box its digits)."""
    from explorer.qt._controls_editors import NumberEditor

    if isinstance(editor, NumberEditor):
        spin = editor.spin
        shown = min(max(float(value), spin.minimum()), spin.maximum())
        return editor.slider.value() == editor.to_position(value) and math.isclose(
            spin.value(), shown, rel_tol=1e-12, abs_tol=0.5 * 10.0 ** -spin.decimals() + 1e-12)  # fmt: skip
    return editor.value() == value


def _widgets_show_state(app) -> bool:
    """Every editor of the control panel shows its control's value; the model's own rows are its parameters."""
    panel, s = app.controls, app.state
    if not all(_shows(editor, getattr(s, name)) for name, editor in panel._editors.items()):
        return False
    if set(panel._param_editors) != set(s.params):
        return False  # the model's own controls are its parameters, no more, no fewer
    for name, editor in panel._param_editors.items():
        value = s.params[name]
        box = getattr(editor, "none_box", None)
        if box is not None and box.isChecked() != (value is None):
            return False
        if value is not None and not _shows(editor, max(value) if isinstance(value, tuple) else value):
            return False
    return True


def _invalid_event(setter, name, value, state, views, failures: Counter, prefix: str) -> None:
    before, kept = state.to_dict(), dict(views)
    try:
        setter(name, value)
    except ValueError as exc:  # ArgumentTypeError is a ValueError too
        msg = str(exc)
        if not msg.startswith(prefix) or "\n" in msg:
            failures["invalid: error does not name the control"] += 1
    except Exception:  # noqa: BLE001 - any other exception is a failure of its own kind
        failures["invalid: not a ValueError"] += 1
    else:
        failures["invalid: accepted"] += 1
    if state.to_dict() != before or any(views.get(k) is not v for k, v in kept.items()):
        failures["invalid: state or views changed"] += 1


def _summary(name, events: Counter, failures: Counter, named: int, invalid: int) -> str:
    kinds = ", ".join(f"{k} {n}" for k, n in sorted(events.items()))
    fails = ", ".join(f"{k}: {n}" for k, n in sorted(failures.items())) or "none"
    share = 100.0 * named / invalid if invalid else 100.0
    return (f"probe {name}: {sum(events.values())} events ({kinds}); {sum(failures.values())} failures ({fails}); "
            f"invalid: {invalid} values, {named} named errors ({share:.0f} %)")  # fmt: skip


# ----------------------------------------------------------------------------- the window
@pytest.fixture(scope="module")
def app():
    pytest.importorskip("PySide6")
    pytest.importorskip("pytestqt")
    from qt_window_support import open_window

    window = open_window((960, 576), lobe_resolution=24)
    yield window
    window.close()


def _sliders(app) -> dict:
    """The control panel's number editors that a mouse can drag now: the controls', then the model's own."""
    from explorer.qt._controls_editors import NumberEditor

    panel = app.controls
    editors = {**panel._editors, **{f"param:{k}": e for k, e in panel._param_editors.items()}}
    return {name: e for name, e in editors.items() if isinstance(e, NumberEditor) and e.slider.isEnabled()}


def _choices(app) -> dict:
    """The control panel's choice and check boxes (the model's own included)."""
    from explorer.qt._controls_editors import CheckEditor, ChoiceEditor

    panel = app.controls
    editors = {**panel._editors, **{f"param:{k}": e for k, e in panel._param_editors.items()}}
    return {name: e for name, e in editors.items() if isinstance(e, ChoiceEditor | CheckEditor) and e.isEnabled()}


def _window_setter(app):
    """``set_control`` as the storm's invalid events call it: a refusal raises its message (the status bar's)."""

    def setter(name, value):
        if not app.set_control(name, value):
            raise ValueError(app.last_error)

    return setter


def test_event_storm_over_every_control_of_the_window(app, qtbot):
    from qt_window_support import drag, flush, release, reset, settle

    from explorer.qt._controls_editors import CheckEditor
    from explorer.qt.keys import do_key

    rng = np.random.default_rng(SEED)
    events, failures = Counter(), Counter()
    named = invalid = 0
    reset(app)
    dragging = None

    def let_go():
        nonlocal dragging
        if dragging is not None:
            release(dragging)
            dragging = None

    for _ in range(APP_EVENTS):
        kind = rng.choice(["drag", "drag", "drag", "release", "key", "checkbox", "button", "button", "invalid",
                           "param-invalid"])  # fmt: skip
        events[kind] += 1
        try:
            if kind == "drag":
                # Like the mouse: positions anywhere along the track and past its ends (the slider clamps them).
                sliders = _sliders(app)  # the model's own sliders change with the model
                names = sorted(sliders)
                held = next((n for n, e in sliders.items() if e is dragging), None)
                name = held if held is not None and rng.random() < 0.6 else str(rng.choice(names))
                if dragging is not None and sliders[name] is not dragging:
                    let_go()
                    flush(app)
                editor = sliders[name]
                lo, hi = editor.slider.minimum(), editor.slider.maximum()
                position = int(round(rng.uniform(lo - 0.1 * (hi - lo), hi + 0.1 * (hi - lo))))
                if rng.random() < 0.2 and name == "elevation":  # near the horizon, where the views used to disagree
                    position = editor.to_position(float(rng.choice([0.0, 1e-6, -1e-6, 0.3, 90.0, -90.0])))
                drag(editor, (position,))
                dragging = editor
                settle(1)  # the coarse spheres follow when the loop is next idle
                if app.model.pending & LIVE_VIEWS:
                    failures["drag: live views left behind"] += 1
            elif kind == "button":  # a pick in a choice box (the model's, a choice parameter's, ...)
                let_go()
                boxes = {n: e for n, e in _choices(app).items() if not isinstance(e, CheckEditor)}
                editor = boxes[str(rng.choice(sorted(boxes)))]
                editor.setCurrentIndex(int(rng.integers(editor.count())))
                flush(app)
            elif kind == "param-invalid":  # a bad value for one of the model's parameters
                params = offered_parameters(app.state.model)
                if not params:
                    continue
                let_go()
                flush(app)
                p = params[int(rng.integers(len(params)))]
                value = [float("nan"), -1e300, "x", b"1", object(), [1, 2]][int(rng.integers(6))]
                if p.kind == "bool":
                    value = "yes"
                invalid += 1
                before = sum(failures.values())
                set_control = _window_setter(app)
                _invalid_event(lambda n, v, set_control=set_control: set_control("params", {n: v}), p.name, value,
                               app.state, app.model.views, failures, f"{p.name} must ")  # fmt: skip
                named += sum(failures.values()) == before
            elif kind == "release":
                let_go()
                flush(app)
                if app.model.pending:
                    failures["release: views still stale"] += 1
            elif kind == "key":
                let_go()
                do_key(app, str(rng.choice(KEYS)))
                flush(app)
            elif kind == "checkbox":
                let_go()
                boxes = {n: e for n, e in _choices(app).items() if isinstance(e, CheckEditor)}
                box = boxes[str(rng.choice(sorted(boxes)))]
                box.click()
                flush(app)
            else:  # "invalid"
                let_go()
                flush(app)
                name = str(rng.choice(list(STORM_CONTROLS)))
                values = _invalid_values(name)
                value = values[int(rng.integers(len(values)))]
                invalid += 1
                before = sum(failures.values())
                _invalid_event(_window_setter(app), name, value, app.state, app.model.views, failures, f"{name} must ")
                named += sum(failures.values()) == before
        except Exception as exc:  # noqa: BLE001 - counted by kind, reported below
            failures[f"{kind}: {type(exc).__name__}: {exc}"[:120]] += 1
            continue
        _check_laws(app.model, failures)
        if dragging is None and not _widgets_show_state(app):
            failures["widgets do not show the state"] += 1
    let_go()
    flush(app)
    _check_laws(app.model, failures)
    if getattr(app, "help_dialog", None) is not None:
        app.help_dialog.close()
    print("\n" + _summary("explorer window", events, failures, named, invalid))
    assert events["drag"] > 30 and events["button"] > 15 and invalid > 20
    assert not failures, dict(failures)


# ----------------------------------------------------------------------------- the model
def _random_value(rng, name):
    spec = CONTROLS[name]
    if spec.kind == "choice":
        return str(rng.choice(spec.choices))
    if spec.kind == "bool":
        return bool(rng.random() < 0.5)
    if spec.kind == "terms":
        return tuple(t for t in spec.choices if rng.random() < 0.7)
    if spec.kind == "lights":  # up to two extra lights of random kinds
        return tuple(new_light(str(k), AppState()) for k in rng.choice(EXTRA_LIGHT_TYPES, size=int(rng.integers(3))))
    if spec.kind == "rgb":
        return tuple(float(x) for x in rng.uniform(0.0, 1.0, 3))
    if spec.kind == "int":
        return int(rng.integers(int(spec.lo), int(spec.hi) + 1))
    if name == "elevation":
        return float(rng.choice([rng.uniform(-90.0, 90.0), 0.0, 1e-6, -1e-6, 1e-3, 40.3, 89.99, -90.0]))
    if spec.log:  # shininess, roughness: spread over the decades, the extremes included
        return float(min(max(10.0 ** rng.uniform(math.log10(max(spec.lo, 1e-6)), math.log10(spec.hi)), spec.lo),
                         spec.hi))  # fmt: skip
    return float(rng.uniform(spec.lo, spec.hi))


def test_event_storm_over_the_model():
    rng = np.random.default_rng(SEED + 1)
    model = ExplorerModel(AppState(), sphere_size=32, mesh_size=32, lobe_resolution=12)
    model.update()
    events, failures = Counter(), Counter()
    named = invalid = 0
    plain = [n for n in STORM_CONTROLS if n not in ("tessellation", "mode", "scanline", "exposure")]
    lights_rng = np.random.default_rng(SEED + 2)
    for _ in range(MODEL_EVENTS):
        if lights_rng.random() < 0.2:  # the extra lights: a new set (seen at the next update), or an invalid value
            events["scene lights"] += 1
            try:
                if lights_rng.random() < 0.75:
                    model.state.scene_lights = _random_value(lights_rng, "scene_lights")
                else:
                    values = _invalid_values("scene_lights")
                    invalid += 1
                    before = sum(failures.values())
                    _invalid_event(lambda n, v: setattr(model.state, n, v), "scene_lights",
                                   values[int(lights_rng.integers(len(values)))], model.state, model.views, failures,
                                   "scene_lights must ")  # fmt: skip
                    named += sum(failures.values()) == before
            except Exception as exc:  # noqa: BLE001 - counted by kind, reported below
                failures[f"scene lights: {type(exc).__name__}: {exc}"[:120]] += 1
        kind = rng.choice(["set", "set", "set", "burst", "extreme", "param", "param", "invalid"])
        events[kind] += 1
        try:
            if kind == "set":
                name = str(rng.choice(plain))
                model.state.update(**{name: _random_value(rng, name)})
            elif kind == "burst":  # several controls at once, as a key or a reset does
                chosen = rng.choice(plain, size=4, replace=False)
                model.state.update(**{str(n): _random_value(rng, str(n)) for n in chosen})
            elif kind == "extreme":
                name = str(rng.choice(MODELS))
                extreme = {
                    "shininess": float(rng.choice([0.0, 1.0, 1e6])), "roughness": float(rng.choice([1e-6, 1e-3, 1.0])),
                    "f0": float(rng.choice([0.0, 1.0])), "sigma": float(rng.choice([0.0, 1.5])),
                    "alpha_x": float(rng.choice([1e-3, 1.0])), "alpha_y": rng.choice([None, 1e-3, 1.0]),
                    "nu": float(rng.choice([0.0, 1e4])), "nv": float(rng.choice([0.0, 1e4])),
                    "anisotropic": float(rng.choice([0.0, 1.0])),
                }  # fmt: skip
                offered = {p.name for p in offered_parameters(name)}
                model.state.update(
                    model=name, params={k: v for k, v in extreme.items() if k in offered},
                    elevation=float(rng.choice([0.0, 1e-6, 40.3, -5.0])), phi=float(rng.choice([180.0, 90.0, 37.0])),
                    times_cos=bool(rng.random() < 0.5), log=bool(rng.random() < 0.5), lock=bool(rng.random() < 0.2),
                )  # fmt: skip
            elif kind == "param":  # one of the model's own parameters, anywhere in its control range
                params = offered_parameters(model.state.model)
                if params:
                    p = params[int(rng.integers(len(params)))]
                    if p.kind == "choice":
                        value = str(rng.choice(p.choices))
                    elif p.kind == "bool":
                        value = bool(rng.random() < 0.5)
                    else:
                        lo, hi = p.control_range
                        lo = max(lo, 1e-6) if p.low_open else lo
                        value = float(rng.uniform(lo, hi if math.isfinite(hi) else lo + 1.0))
                    before = model.state.to_dict()
                    try:
                        model.state.set_param(p.name, value)
                    except ValueError:  # a combination the model's constructor refuses (it names it)
                        events["param refused"] += 1
                        if model.state.to_dict() != before:
                            failures["param refused: state changed"] += 1
            else:
                name = str(rng.choice(list(STORM_CONTROLS)))
                values = _invalid_values(name)
                invalid += 1
                before = sum(failures.values())
                _invalid_event(lambda n, v: setattr(model.state, n, v), name, values[int(rng.integers(len(values)))],
                               model.state, model.views, failures, f"{name} must ")  # fmt: skip
                named += sum(failures.values()) == before
                continue
            if rng.random() < 0.3:  # a drag: the images now, the rest later
                model.update(only=LIVE_VIEWS)
                _check_laws(model, failures)
            model.update()
        except Exception as exc:  # noqa: BLE001 - counted by kind, reported below
            failures[f"{kind}: {type(exc).__name__}: {exc}"[:120]] += 1
            continue
        _check_laws(model, failures)
    print("\n" + _summary("explorer model", events, failures, named, invalid))
    assert not failures, dict(failures)
    assert invalid > 20
