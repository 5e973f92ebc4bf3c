"""The accuracy studies' laws on their quick run (slow set; fine references and the report: test_accuracy_full.py)."""

import csv

import numpy as np
import pytest

from explorer.reports import accuracy as report_accuracy
from lighting.validation.accuracy import run_studies, summary

pytestmark = pytest.mark.slow  # the quick accuracy studies, measured once per session: seconds of work


@pytest.fixture(scope="module")
def studies(quick_accuracy_studies):
    return quick_accuracy_studies  # run_studies(quick=True), measured once per session (conftest.py)


def _pts(studies, study, case=None, method=None):
    st = next(s for s in studies if s.name == study)
    return [p for p in st.points if (case is None or case in p.case) and (method is None or p.method == method)]


def test_quadrature_converges_to_the_reference(studies):
    for case in ("Lambert, glowing sky", "GGX/Smith"):
        q = sorted(_pts(studies, "integration", case, "quadrature"), key=lambda p: p.cost)
        assert q[-1].error < 1e-5
        assert q[-1].error < q[0].error / 100


def test_monte_carlo_error_falls_like_one_over_root_n(studies):
    # 16 → 1024 samples is 64×: an unbiased estimator's error falls about 8× (2.5× allows for seed noise).
    # Blind (uniform, cosine) sampling of the sharp e=200 lobe is too heavy-tailed for that at two seeds,
    # so those two are checked on the smooth Lambert case.
    for case, methods in (
        ("Lambert, glowing sky", ("uniform", "cosine", "importance", "stratified")),
        ("Blinn-Phong e=200", ("importance", "stratified")),
    ):
        for method in methods:
            pts = sorted(_pts(studies, "integration", case, method), key=lambda p: p.cost)
            assert pts[-1].error < pts[0].error / 2.5, (case, method)
    # Sampling the lobe beats sampling the hemisphere uniformly for a sharp Blinn-Phong lobe.
    imp = {p.cost: p.error for p in _pts(studies, "integration", "Blinn-Phong e=200", "importance")}
    uni = {p.cost: p.error for p in _pts(studies, "integration", "Blinn-Phong e=200", "uniform")}
    assert imp[1024] < uni[1024] / 3


def test_closed_form_reference_for_phong(studies):
    pts = _pts(studies, "integration", "Phong e=1")
    assert pts and all("closed form" in p.reference for p in pts)
    q = max(_pts(studies, "integration", "Phong e=1", "quadrature"), key=lambda p: p.cost)
    assert q.error < 1e-6


def test_area_light_error_falls_with_samples(studies):
    pts = sorted(_pts(studies, "area-light"), key=lambda p: p.cost)
    errors = [p.error for p in pts]
    assert errors[-1] < errors[0] / 10
    assert all(np.isfinite(errors))


def test_phong_interpolation_beats_gouraud_at_equal_tessellation(studies):
    g = {p.cost: p.error for p in _pts(studies, "tessellation", method="gouraud")}
    ph = {p.cost: p.error for p in _pts(studies, "tessellation", method="phong")}
    assert set(g) == set(ph) and len(g) >= 3
    levels = sorted(g)
    assert all(ph[n] < g[n] for n in levels[1:])
    assert ph[levels[-1]] < ph[levels[0]] / 5 and g[levels[-1]] < g[levels[0]] / 5


def test_float32_costs_about_a_single_precision_rounding(studies):
    p32 = _pts(studies, "precision", method="float32")[0]
    p64 = _pts(studies, "precision", method="float64")[0]
    assert p64.error == 0.0
    assert 0 < p32.error < 1e-5


def test_summary_answers_the_question(studies):
    rows = summary(studies)
    cases = {p.case for st in studies for p in st.points}
    assert {r["case"] for r in rows} == cases
    for r in rows:
        if r["method"] is not None:
            st = next(s for s in studies if s.name == r["study"])
            candidates = [p for p in st.points if p.case == r["case"] and p.error <= r["threshold"]]
            assert r["seconds"] == min(p.seconds for p in candidates)


def test_cli_writes_csv_and_figure(tmp_path, capsys):
    out = tmp_path / "acc"
    assert report_accuracy.main(["--quick", "--only", "precision", "tessellation", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "Cheapest method that reaches the error" in text
    with open(out / "accuracy.csv", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    assert {"study", "case", "method", "cost", "error", "error_spread", "seconds", "reference"} <= set(rows[0])
    f32 = next(r for r in rows if r["method"] == "float32")
    assert 0 < float(f32["error"]) < 1e-5
    import matplotlib.pyplot as plt

    img = plt.imread(out / "accuracy.png")
    assert img.ndim == 3 and img.shape[0] > 200 and img.std() > 0.05


# -------------------------------------------------------------------------- unconverged points are marked
def test_integration_points_carry_their_own_error_estimate_and_flag(studies):
    pts = _pts(studies, "integration")
    assert pts and all(np.isfinite(p.estimated_error) and 0 <= p.coverage <= 1 for p in pts)
    for p in pts:
        # The flag is the method's own estimate above 2 %, whatever the measured error says.
        assert p.unconverged == (p.estimated_error > 0.02), (p.case, p.method, p.cost)
    # The honesty contract seen in the report: 2σ covers the true error in >= 90 % of (point, seed) pairs.
    mc = [p for p in pts if p.method not in ("quadrature", "sh")]
    assert np.mean([p.coverage for p in mc]) >= 0.9
    # Uniform sampling of the sharp e=200 lobe with 16 samples cannot be trusted, and says so; the
    # converged quadrature says it is converged.
    blind = next(p for p in _pts(studies, "integration", "Blinn-Phong e=200", "uniform") if p.cost == 16)
    assert blind.unconverged
    best = max(_pts(studies, "integration", "GGX/Smith", "quadrature"), key=lambda p: p.cost)
    assert not best.unconverged and best.coverage == 1.0


def test_points_without_an_estimate_are_flagged_by_their_measured_error(studies):
    for p in _pts(studies, "area-light") + _pts(studies, "tessellation"):
        assert np.isnan(p.estimated_error) and np.isnan(p.coverage)
        assert p.unconverged == (p.error > 0.02)


@pytest.mark.parametrize(
    "kwargs, exc, name",
    [
        ({"quick": 1}, TypeError, "quick"),
        ({"only": ["integration", "nope"]}, ValueError, "study"),
        ({"only": [3]}, TypeError, "only"),
        ({"only": 5}, TypeError, "only"),
        ({"progress_factory": 3}, TypeError, "progress_factory"),
    ],
)
def test_run_studies_refuses_bad_arguments_by_name(kwargs, exc, name):
    with pytest.raises(exc, match=name):
        run_studies(**kwargs)


@pytest.mark.parametrize(
    "args, exc, name",
    [
        ((["x"],), TypeError, "studies"),
        ((5,), TypeError, "studies"),
        (([], [0.0]), ValueError, "thresholds"),
        (([], ["0.1"]), TypeError, "thresholds"),
        (([], [float("nan")]), ValueError, "thresholds"),
    ],
)
def test_summary_refuses_bad_arguments_by_name(args, exc, name):
    with pytest.raises(exc, match=name):
        summary(*args)


@pytest.mark.parametrize("argv, flag", [(["--out", "FILE"], "--out"), (["--only", "nope"], "--only"), (["--x"], "--x")])
def test_cli_bad_requests_are_one_line_before_any_work(argv, flag, tmp_path, capsys, monkeypatch):
    (tmp_path / "FILE").write_text("keep")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(report_accuracy, "run_studies", lambda **kw: pytest.fail("ran before refusing"))
    assert report_accuracy.main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("lighting-explorer: error:") and flag in err[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["FILE"] and (tmp_path / "FILE").read_text() == "keep"


def test_csv_written_atomically_keeps_no_temporary_file_when_interrupted(tmp_path, monkeypatch):
    path = tmp_path / "a.csv"
    path.write_text("old\n")

    class Row(dict):
        def get(self, key, default=None):  # csv.DictWriter reads each field through get
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        report_accuracy.write_csv(str(path), [Row(a=1)], ["a"])
    assert [p.name for p in tmp_path.iterdir()] == ["a.csv"] and path.read_text() == "old\n"


# ---------------------------------------------------------------------- image-based lighting
def test_ibl_points_are_finite_ordered_and_honestly_flagged(studies):
    pts = _pts(studies, "ibl")
    assert {p.method for p in pts} == {"SH9 irradiance", "split sum", "dominant lights", "dominant lights, normal grid",
                                       "Monte Carlo, MIS"}  # fmt: skip
    for p in pts:
        assert np.isfinite([p.error, p.error_p95, p.seconds]).all() and p.seconds > 0, p
        assert 0 <= p.error <= p.error_p95, p  # a median never exceeds its 95th percentile
        if p.method != "SH9 irradiance":
            assert np.isfinite(p.reference_error) and p.reference_error > 0
            # A reference noisier than the measured error cannot measure it: flagged.
            if p.reference_error > p.error:
                assert p.unconverged, p
    for case in dict.fromkeys(p.case for p in pts if p.method == "split sum"):
        mc = sorted(_pts(studies, "ibl", case, "Monte Carlo, MIS"), key=lambda p: p.cost)
        assert [p.cost for p in mc] == [8, 32, 128]
        # 16× the samples: an unbiased estimator's error falls about 4× (2.5× allows for the reference's noise).
        # The 95th percentile, not the median: at 8 samples the per-pixel errors are skewed (most pixels
        # miss the rare bright directions and err little), which holds the median low.
        assert mc[-1].error_p95 < mc[0].error_p95 / 2.5, case
        # Its own estimate (the spread of 8 passes) is of the size of its measured error.
        assert 0.5 < mc[-1].estimated_error / mc[-1].error < 2.0, case


def test_the_reports_ibl_panels_draw_only_monte_carlo_as_lines(studies):
    # Every other method is one point per case (a marker): were one of them left out of the markers, it would be
    # joined to the Monte-Carlo line of its model, sorted in by its cost.
    panels = [series for title, series in report_accuracy._panels(studies) if title.startswith("IBL, ")]
    assert panels and all(any(p.method == "Monte Carlo, MIS" for _, pts in series for p in pts) for series in panels)
    for series in panels:
        for _, pts in series:
            lines = {p.method for p in pts if p.method not in report_accuracy._MARKED}
            assert lines <= {"Monte Carlo, MIS"}, lines  # (the SH9 series has no line)
            marked = [p.method for p in pts if p.method in report_accuracy._MARKED]
            assert len(marked) == len(set(marked))  # one marker per method and model


def test_split_sum_is_a_white_furnace_for_lambert_on_the_ibl_sphere():
    from lighting.integrate.ibl import split_sum_radiance
    from lighting.integrate.prefilter import prefilter_environment
    from lighting.lights.environment import ConstantEnvironment
    from lighting.models.brdf import Lambert
    from lighting.validation.accuracy import ibl_pixel_errors, ibl_sphere

    for dt, tol in ((np.float32, 1e-6), (np.float64, 1e-13)):  # zero to rounding (the SH9 pixel sums)
        _, n, v = ibl_sphere(24, dt)
        front = np.sum(n * v, axis=-1) > 0
        out = split_sum_radiance(Lambert(0.6), prefilter_environment(ConstantEnvironment(1.5)), n, v)
        assert out.dtype == dt
        np.testing.assert_allclose(out[front], 0.9, rtol=tol)
        errs, lit, _ = ibl_pixel_errors(out[front], np.full((int(front.sum()), 3), 0.9))
        assert lit.all() and np.max(errs) < tol
