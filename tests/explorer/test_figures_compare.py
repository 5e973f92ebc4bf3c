"""explorer.figures.compare: what plot_brdfs draws, read back from the Matplotlib artists, and the
figure ``compare_brdfs``'s measured numbers against independent computations."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from explorer.compare import BRDFList
from explorer.figures.compare import VIEWS, albedo_channel, plot_brdfs
from lighting import BlinnPhong, Lambert, Phong
from lighting.analysis import polar_slice, theta_d_curve, theta_h_curve
from lighting.integrate import albedo_curve
from lighting.models import CookTorrance

Y = np.array([0.2126, 0.7152, 0.0722])  # Rec. 709 luminance of linear sRGB
THETAS = np.radians([0.0, 20.0, 40.0, 60.0, 80.0, 89.0])
GGX = {"ndf": "ggx", "geometry": "smith-correlated", "fresnel": "schlick"}


def _gids(ax):
    return {a.get_gid(): a for a in [*ax.lines, *ax.collections] if a.get_gid()}


def _group():
    group = BRDFList()
    group.add(Lambert((0.2, 0.5, 0.8)), "lambert")
    group.add(Phong(0.6, 30.0), "phong")
    group.add(CookTorrance(1.0, 0.2, (0.9, 0.6, 0.3), **GGX), "ggx")
    return group


@pytest.fixture(scope="module")
def drawn():
    group = _group()
    group.set_visible(1, False)
    return group, plot_brdfs(group, albedo_thetas=THETAS, albedo_samples=1024, n=181, curve_n=91)


def test_every_shown_entry_draws_the_engine_s_values_in_every_view(drawn):
    group, p = drawn
    assert [i for i, _ in p.shown] == [0, 2]
    t = math.radians(45.0)
    for i in (0, 2):
        e = group[i]
        art = {v: _gids(p.axes[v]) for v in VIEWS}
        s = polar_slice(e.brdf, t, n=181, channel="luminance")
        line = art["polar"][f"polar:{i}"]
        np.testing.assert_array_equal(line.get_xdata(), s.xy[:, 0])
        np.testing.assert_array_equal(line.get_ydata(), s.xy[:, 1])
        assert line.get_color() == e.colour and line.get_label() == e.label
        for view, curve in (("theta_h", theta_h_curve(e.brdf, 0.0, n=91, channel="luminance")),
                            ("theta_d", theta_d_curve(e.brdf, 0.0, n=91, channel="luminance"))):  # fmt: skip
            line = art[view][f"{view}:{i}"]
            np.testing.assert_array_equal(line.get_xdata(), np.degrees(curve.angles[curve.valid]))
            np.testing.assert_array_equal(line.get_ydata(), curve.values[curve.valid])
            assert line.get_color() == e.colour
        c = albedo_curve(e.brdf, THETAS, 1024)
        line = art["albedo"][f"albedo:{i}"]
        np.testing.assert_allclose(np.radians(line.get_xdata()), THETAS, rtol=1e-15)
        np.testing.assert_allclose(line.get_ydata(), c.albedo @ Y, rtol=1e-14)
        band = art["albedo"][f"albedo-band:{i}"].get_paths()[0].vertices[:, 1]
        assert band.min() == pytest.approx(float(np.min(c.albedo @ Y - 2 * c.error @ Y)), abs=1e-14)
        assert band.max() == pytest.approx(float(np.max(c.albedo @ Y + 2 * c.error @ Y)), abs=1e-14)
        for v in VIEWS:
            for a in art[v].values():
                data = a.get_xydata() if hasattr(a, "get_xydata") else a.get_paths()[0].vertices
                assert np.isfinite(data).all()


def test_lambert_albedo_is_kd_and_phong_at_normal_view_is_2ks_over_e_plus_1(drawn):
    _, p = drawn
    rho, err, flag = albedo_channel(p.albedo[0], "luminance")
    np.testing.assert_allclose(rho, 0.2126 * 0.2 + 0.7152 * 0.5 + 0.0722 * 0.8, rtol=1e-12)
    assert not flag.any()
    for channel, kd in ((0, 0.2), ("g", 0.5), ("blue", 0.8)):
        np.testing.assert_allclose(albedo_channel(p.albedo[0], channel)[0], kd, rtol=1e-12)
    # A hidden entry is not integrated; drawn solo, the slides' Phong gives 2 k_s/(e+1) at θ_v = 0.
    assert 1 not in p.albedo
    q = plot_brdfs([(Phong(0.6, 30.0), "phong")], views=("albedo",), albedo_thetas=[0.0], channel="r")
    assert q.axes["albedo"].lines[0].get_ydata()[0] == pytest.approx(2 * 0.6 / 31, rel=1e-9)


def test_hidden_entries_are_absent_and_solo_draws_exactly_one(drawn):
    group, p = drawn
    for v in VIEWS:
        gids = set(_gids(p.axes[v]))
        assert not any(g.endswith(":1") for g in gids)  # the hidden Phong
        assert {g for g in gids if g.startswith(f"{v}:")} == {f"{v}:0", f"{v}:2"}
    assert [t.get_text() for t in p.legend.get_texts()][:2] == ["lambert", "ggx"]
    group.set_solo(1)  # solo wins over hidden
    q = plot_brdfs(group, albedo_thetas=THETAS, albedo_samples=256, n=91, curve_n=31)
    for v in VIEWS:
        assert {g for g in _gids(q.axes[v]) if g.startswith(f"{v}:")} == {f"{v}:1"}
        assert _gids(q.axes[v])[f"{v}:1"].get_color() == group[1].colour
    assert [i for i, _ in q.shown] == [1] and list(q.albedo) == [1]
    assert [t.get_text() for t in q.legend.get_texts()][0] == "phong"


def test_unconverged_marks_are_drawn_exactly_where_the_integrator_flags():
    # A sharp GGX lobe with 96 importance samples: the relative error is about 1.5 %, above 2 % only at grazing.
    sharp = CookTorrance(1.0, 0.02, 0.9, **GGX)
    thetas = np.radians(np.append(np.arange(0.0, 89.0, 2.0), 89.0))
    p = plot_brdfs([(sharp, "sharp"), (Lambert(0.5), "matte")], views=("albedo",), albedo_thetas=thetas,
                   albedo_samples=[96, 256], albedo_method=["importance", "quadrature"], seed=1)  # fmt: skip
    ref = albedo_curve(sharp, thetas, 96, "importance", seed=1)
    flagged = ref.unconverged.any(axis=1)
    assert 0 < flagged.sum() < flagged.size  # some values flagged, not all
    marks = _gids(p.axes["albedo"])["albedo-flags:0"]
    np.testing.assert_allclose(marks.get_xdata(), np.degrees(thetas[flagged]), rtol=1e-15)
    np.testing.assert_allclose(marks.get_ydata(), (ref.albedo @ Y)[flagged], rtol=1e-14)
    assert len(_gids(p.axes["albedo"])["albedo-flags:1"].get_xdata()) == 0  # Lambert converges everywhere
    # One channel: that channel's flag only.
    q = plot_brdfs([(sharp, "sharp")], views=("albedo",), albedo_thetas=thetas, albedo_samples=96,
                   albedo_method="importance", seed=1, channel=1)  # fmt: skip
    np.testing.assert_allclose(q.axes["albedo"].lines[1].get_xdata(), np.degrees(thetas[ref.unconverged[:, 1]]))
    labels = [t.get_text() for t in p.legend.get_texts()]
    assert labels[:2] == ["sharp", "matte"] and labels[-1] == "unconverged: error > 2 % of $\\rho$"


def test_log_option_is_the_engine_s_per_view():
    model = CookTorrance(1.0, 0.1, 0.9, **GGX)
    p = plot_brdfs([model], views=("polar", "theta_d"), log=("theta_d",), n=91, curve_n=31)
    c = theta_d_curve(model, 0.0, n=31, channel="luminance", log=True)
    np.testing.assert_array_equal(p.axes["theta_d"].lines[0].get_ydata(), c.values[c.valid])
    s = polar_slice(model, math.radians(45.0), n=91, channel="luminance")
    np.testing.assert_array_equal(_gids(p.axes["polar"])["polar:0"].get_ydata(), s.xy[:, 1])


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_albedo_channel_keeps_dtype_and_finite_values(dtype):
    c = albedo_curve(Lambert((0.2, 0.5, 0.8)), np.asarray(THETAS, dtype=dtype), 64)
    rho, err, flag = albedo_channel(c)
    assert rho.dtype == c.albedo.dtype and np.isfinite(rho).all() and np.isfinite(err).all()
    np.testing.assert_allclose(rho, float(Y @ (0.2, 0.5, 0.8)), rtol=1e-6)


@pytest.mark.parametrize(
    ("kwargs", "error", "message"),
    [
        (
            {"views": ("polar", "spheres")},
            ValueError,
            "views must be distinct names among polar, theta_h, theta_d, albedo; got ('polar', 'spheres')",
        ),
        ({"views": ("albedo", "albedo")}, ValueError, "views must be distinct names"),
        ({"views": ()}, ValueError, "views must be distinct names"),
        ({"channel": "alpha"}, ValueError, "channel must be 0, 1, 2, 'r', 'g', 'b' or 'luminance'; got 'alpha'"),
        ({"channel": 3}, ValueError, "channel must be"),
        (
            {"albedo_samples": [64]},
            ValueError,
            "albedo_samples must be one value or one per entry of the list (2); got 1",
        ),
        ({"albedo_method": ["quadrature"] * 3}, ValueError, "albedo_method must be one value or one per entry"),
        ({"log": ("albedo",)}, ValueError, "log must be True, False or names among polar, theta_h, theta_d"),
        ({"theta_l": 2.0}, ValueError, "theta_in must be a finite angle in radians in [0, 1.5708]"),
        ({"albedo_method": "guess"}, ValueError, "method"),
    ],
)
def test_bad_options_are_named(kwargs, error, message):
    with pytest.raises(error, match=re.escape(message)):
        plot_brdfs([Lambert(0.5), Phong(0.5, 10.0)], albedo_thetas=[0.0], **kwargs)


def test_bad_lists_and_axes_are_named():
    from explorer.figures.base import new_figure

    with pytest.raises(TypeError, match="brdfs must be a BRDFList, a BRDF or a list of BRDFs or"):
        plot_brdfs("lambert")
    with pytest.raises(TypeError, match="brdf must be a BRDF model; got float"):
        plot_brdfs([0.5])
    axes = new_figure(4, 3).subplots(1, 2)
    with pytest.raises(ValueError, match=re.escape("axes must hold one Axes per view (4); got 2")):
        plot_brdfs([Lambert(0.5)], axes=axes)


def test_an_empty_or_all_hidden_list_draws_empty_views():
    group = BRDFList([Lambert(0.5)])
    group.set_visible(0, False)
    p = plot_brdfs(group, albedo_thetas=[0.0])
    assert p.shown == [] and p.albedo == {} and p.legend is None
    assert not any(_gids(ax) for ax in p.axes.values())


def test_plot_brdfs_works_with_blinn_phong_and_a_plain_brdf():
    p = plot_brdfs(BlinnPhong(0.5, 30.0, normalized=True), views=("theta_h",), curve_n=11)
    c = theta_h_curve(BlinnPhong(0.5, 30.0, normalized=True), 0.0, n=11, channel="luminance")
    np.testing.assert_array_equal(p.axes["theta_h"].lines[0].get_ydata(), c.values[c.valid])
