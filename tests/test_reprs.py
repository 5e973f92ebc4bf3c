"""Models and lights print one short line: exact strings, no arrays, and the line rebuilds the object."""

from __future__ import annotations

import numpy as np
import pytest

from lighting import AmbientLight, DirectionalLight, Material, PointLight
from lighting.lights import DiskLight, RectLight, SpotLight
from lighting.models import model_variants
from lighting.models.ashikhmin_shirley import AshikhminShirley
from lighting.models.blinn_phong import BlinnPhong
from lighting.models.cook_torrance import CookTorrance
from lighting.models.disney import Disney
from lighting.models.lambert import Lambert
from lighting.models.mirror import Mirror
from lighting.models.oren_nayar import OrenNayar
from lighting.models.phong import Phong
from lighting.models.ward import Ward

MODELS = [
    (Phong(), "Phong(ks=0.5, shininess=32)"),
    (Phong(0.25, 200), "Phong(ks=0.25, shininess=200)"),
    (Lambert((0.8, 0.2, 0.1)), "Lambert(kd=(0.8, 0.2, 0.1))"),
    (BlinnPhong(0.3, 40, normalized=True), "BlinnPhong(ks=0.3, shininess=40, normalized=True)"),
    (CookTorrance(), "CookTorrance(ks=1, roughness=0.3, f0=0.04)"),
    (
        CookTorrance(roughness=0.1, ndf="ggx", geometry="smith"),
        "CookTorrance(ks=1, roughness=0.1, f0=0.04, ndf='ggx', geometry='smith')",
    ),
    (OrenNayar(sigma=0.5), "OrenNayar(kd=0.8, sigma=0.5)"),
    (Ward(1.0, 0.1, 0.4), "Ward(ks=1, alpha_x=0.1, alpha_y=0.4)"),
    (AshikhminShirley(), "AshikhminShirley(rd=0.5, rs=0.05, nu=200, nv=20)"),
    (Disney(), "Disney(base_color=0.8)"),
    (Disney(roughness=0.2, metallic=1.0), "Disney(base_color=0.8, metallic=1, roughness=0.2)"),
    (Mirror(0.9), "Mirror(ks=0.9, f0=0.04)"),
    (Lambert(0.5) + Phong(0.3, 1 / 3), "Lambert(kd=0.5) + Phong(ks=0.3, shininess=0.333333)"),
]

LIGHTS = [
    (PointLight((2, 2, 3), intensity=20), "PointLight(position=(2, 2, 3), intensity=20)"),
    (PointLight((0, 0, 4.0), attenuation=(0, 0, 1)),
     "PointLight(position=(0, 0, 4), intensity=1, attenuation=(0, 0, 1))"),
    (DirectionalLight((0, 0, 2.0), color=(1, 0.5, 0.25)),
     "DirectionalLight(direction=(0, 0, 1), color=(1, 0.5, 0.25), intensity=1)"),
    (DirectionalLight((1, 1, 1)), "DirectionalLight(direction=(0.57735, 0.57735, 0.57735), intensity=1)"),
    (AmbientLight(0.1), "AmbientLight(color=0.1, intensity=0.2)"),
    (
        SpotLight(position=(0, 0, 5), direction=(0, 0, -1), cutoff_deg=20, exponent=8),
        "SpotLight(position=(0, 0, 5), direction=(0, 0, -1), cutoff_deg=20, intensity=1, exponent=8)",
    ),
    (
        RectLight(center=(0, 2, 1), samples=64, two_sided=True),
        "RectLight(center=(0, 2, 1), edge_u=(1, 0, 0), edge_v=(0, -1, 0), intensity=1, samples=64, two_sided=True)",
    ),
    (DiskLight(radius=0.25, seed=3),
     "DiskLight(center=(0, 0, 5), normal_dir=(0, 0, -1), radius=0.25, intensity=1, seed=3)"),
]  # fmt: skip

NAMESPACE = {c.__name__: c for c in (Phong, Lambert, BlinnPhong, CookTorrance, OrenNayar, Ward, AshikhminShirley,
                                     Disney, Mirror, PointLight, DirectionalLight, AmbientLight, SpotLight, RectLight,
                                     DiskLight)}  # fmt: skip


@pytest.mark.parametrize(("obj", "text"), MODELS + LIGHTS, ids=lambda x: x if isinstance(x, str) else "")
def test_exact_repr(obj, text):
    assert repr(obj) == text
    assert "array" not in text and "\n" not in text


@pytest.mark.parametrize(("obj", "text"), [m for m in MODELS if "+" not in m[1]] + LIGHTS,
                         ids=lambda x: x if isinstance(x, str) else "")  # fmt: skip
def test_repr_rebuilds_an_equal_object(obj, text):
    # The line is a constructor call: evaluated, it gives an object that behaves the same (to 6 digits).
    again = eval(text, NAMESPACE)  # noqa: S307 - our own repr strings
    assert type(again) is type(obj) and repr(again) == text
    if hasattr(obj, "eval"):
        n, l, v = np.array([0, 0, 1.0]), np.array([0.3, 0.1, 0.9]), np.array([-0.2, 0.2, 0.95])
        l, v = l / np.linalg.norm(l), v / np.linalg.norm(v)
        np.testing.assert_allclose(again.eval(n, l, v), obj.eval(n, l, v), rtol=1e-12)
    else:
        np.testing.assert_allclose(again.radiant, obj.radiant, rtol=1e-12)


def test_every_registered_model_prints_one_short_line():
    for name, (cls, fixed) in model_variants().items():
        text = repr(cls(**fixed))
        assert text.startswith(cls.__name__ + "(") and "\n" not in text and "array" not in text, name
        assert len(text) <= 80, (name, text)


@pytest.mark.parametrize(
    ("material", "text"),
    [
        (lambda: Material(Lambert(0.8) + Phong(0.5, 32)), "Material(Lambert(kd=0.8) + Phong(ks=0.5, shininess=32))"),
        (
            lambda: Material(Phong(0.5, 32), ambient=0.1, emission=(1, 0, 0)),
            "Material(Phong(ks=0.5, shininess=32), ambient=0.1, emission=(1, 0, 0))",
        ),
        (lambda: Material(Lambert((0.8, 0.2, 0.1)), ambient=(0.8, 0.2, 0.1)), "Material(Lambert(kd=(0.8, 0.2, 0.1)))"),
    ],
)
def test_material_repr_leaves_out_its_defaults_and_rebuilds_it(material, text):
    m = material()
    assert repr(m) == text
    again = eval(text, {"Material": Material, "Lambert": Lambert, "Phong": Phong})  # noqa: S307 - our own repr
    np.testing.assert_array_equal(again.ambient, m.ambient)
    np.testing.assert_array_equal(again.emission, m.emission)
    assert repr(again.brdf) == repr(m.brdf)


# --------------------------------------------------------------------------- analysis results
# Every result prints one line of at most 300 characters: its class, the model, its counts and its key numbers, each
# number here computed from the closed form (or counted) by the test, never read back from the result.
from lighting.analysis import (  # noqa: E402 - the analysis results' part of this file
    half_diff_image,
    lobe_mesh,
    lobe_peak,
    polar_slice,
    theta_d_curve,
    theta_h_curve,
    theta_v_curve,
)
from lighting.analysis.audit import AuditRow, AuditTable, audit  # noqa: E402
from lighting.analysis.fit import FitResult  # noqa: E402
from lighting.analysis.machband import scanline_profile  # noqa: E402
from lighting.integrate import albedo_curve  # noqa: E402


def g4(x):
    return f"{x:.4g}"


def short_line(text, *parts):
    assert len(text) <= 300 and "\n" not in text and "array" not in text, text
    for p in parts:
        assert p in text, (p, text)


def test_angle_curves_print_their_counts_and_peak():
    # Normalized Blinn–Phong at θ_d = 0: (e+2)/(2π) cos^e θ_h, largest at θ_h = 0; θ_h = 90° is on the horizon.
    c = theta_h_curve(BlinnPhong(1.0, 10, normalized=True), channel=0)
    short_line(
        repr(c),
        "AngleCurve(f_r [0] against θ_h of BlinnPhong(ks=1, shininess=10, normalized=True)",
        "181 samples",
        "θ_h 0° to 90°",
        "180 above the horizon",
        "θ_d=0°, φ_d=90°, φ_h=0°",
        f"max {g4(12 / (2 * np.pi))} at θ_h=0°",
    )
    # Lambert is kd/π wherever l and v are above the horizon.
    c = theta_d_curve(Lambert(0.5), n=91)
    short_line(
        repr(c),
        "against θ_d of Lambert(kd=0.5)",
        "91 samples",
        "90 above the horizon",
        f"max {g4(0.5 / np.pi)} at θ_d=0°",
    )
    # The slides' Phong BRDF peaks at the mirror direction with ks / (π cos θ_l); the × n·l option names itself.
    c = theta_v_curve(Phong(1.0, 10), 0.3, channel="r")
    short_line(
        repr(c),
        "against θ_v of Phong(ks=1, shininess=10)",
        "θ_l=17.19°",
        f"max {g4(1 / (np.pi * np.cos(0.3)))} at θ_v=17.19°",
        f"{len(c.angles)} samples",
    )
    c = theta_v_curve(Phong(1.0, 10), 0.3, cosine=True, log=True, channel=0)
    short_line(
        repr(c), "AngleCurve(log10(1 + f_r·(n·l)) [0] against θ_v", f"max {g4(np.log10(1 + 1 / np.pi))} at θ_v=17.19°"
    )


def test_polar_slice_prints_its_direction_and_peak():
    s = polar_slice(Phong(1.0, 20), np.pi / 4, channel="r")
    short_line(
        repr(s),
        "PolarSlice(f_r [r] of Phong(ks=1, shininess=20), light fixed at θ=45°, φ=0°, incidence plane",
        f"{len(s.angles)} samples",
        f"max {g4(1 / (np.pi * np.cos(np.pi / 4)))} at 45°",
        "mirror at 45°",
    )
    s = polar_slice(Lambert(0.8), 0.5, fixed="view", plane="perpendicular", n=181, refine=False, lock=True)
    short_line(repr(s), "view locked to the light: 181 samples", f"max {g4(0.8 / np.pi)}", "mirror at 0°")


def test_half_diff_image_prints_its_size_and_range():
    # φ_d = π/2: both directions have z = cos θ_h cos θ_d, above the horizon except on the last row and column.
    im = half_diff_image(Lambert((0.8, 0.4, 0.2)))
    short_line(
        repr(im),
        "HalfDiffImage(f_r of Lambert(kd=(0.8, 0.4, 0.2)): 91×91 (rows θ_d, columns θ_h)",
        "φ_d=90°, φ_h=0°",
        f"{90 * 90} above the horizon",
        f"range {g4(0.2 / np.pi)} to {g4(0.8 / np.pi)}",
    )
    # φ_d = 0: only θ_h + θ_d < 90° is above the horizon (3 of the 3 × 3 samples).
    im = half_diff_image(Lambert(1.0), phi_d=0.0, n_h=3, n_d=3, channel=0)
    short_line(repr(im), "3×3", "φ_d=0°", "; 3 above the horizon", f"range {g4(1 / np.pi)} to {g4(1 / np.pi)}")


def test_lobe_mesh_and_peak_print_their_counts_and_peak():
    m = lobe_mesh(Lambert(1.0), (0.0, 0.0, 1.0), resolution=8)
    short_line(
        repr(m),
        "LobeMesh(f_r [luminance] lobe of Lambert(kd=1), light at θ=0°",
        f"{1 + 2 * 8**2} vertices",
        f"{2 * 16 * (8 - 1) + 16} faces (8 rings × 16 segments)",
        f"max {g4(1 / np.pi)}",
        "width inf rad",
    )
    # Phong, e = 1000, lit from θ = 36.87°: the peak is the mirror direction, ks/(π cos θ_l), width 1/√e.
    m = lobe_mesh(Phong(1.0, 1000), (0.6, 0.0, 0.8))
    short_line(
        repr(m),
        "light at θ=36.87°, φ=0°",
        "toward θ=36.87°, φ=180°",
        f"max {g4(1 / (0.8 * np.pi))}",
        f"width {g4(1 / np.sqrt(1000))} rad",
    )
    assert (
        repr(lobe_peak(Phong(1.0, 1000), (0.6, 0.0, 0.8)))
        == f"LobePeak(direction=(-0.6, 0, 0.8), value={g4(1 / (0.8 * np.pi))})"
    )


def test_albedo_curve_prints_its_extremes():
    # The slides' Phong BRDF reflects ρ(0) = 2 ks/(e + 1) at normal view, less toward grazing.
    a = albedo_curve(Phong(0.5, 1.0), [0.0, 0.5, 1.0], samples=256)
    short_line(
        repr(a),
        "AlbedoCurve(quadrature",
        f"{a.samples} samples",
        "3 view angles 0° to 57.3°",
        f"ρ max {g4(2 * 0.5 / 2)} at θ_v=0°",
        "min",
        "at θ_v=57.3°",
        f"error ≤ {g4(np.max(a.error))}",
    )


def test_scan_line_profile_prints_its_ranges():
    p = scanline_profile(np.array([[0.0, 1.0, 2.0, 4.0]]), 0)
    assert repr(p) == "Profile(4 pixels, columns 0 to 3: intensity 0 to 4, |ΔI| ≤ 2, |Δ²I| ≤ 1)"
    assert repr(scanline_profile(np.zeros((2, 4)), 0, coverage=np.zeros((2, 4), bool))) == (
        "Profile(no covered pixel on the row)"
    )


def test_audit_rows_and_table_print_their_verdicts():
    table = audit([Lambert(0.5), Phong(0.5, 1.0)], samples=256, n_theta=4, n_phi=6)
    lam, pho = table.rows
    short_line(
        repr(lam),
        "AuditRow('Lambert', kd=0.5: positive pass",
        f"min f_r {g4(0.5 / np.pi)}",
        "reciprocal pass (error 0)",
        f"energy pass (ρ max {g4(0.5)}",
    )
    short_line(repr(pho), "AuditRow('Phong', ks=0.5 e=1", "reciprocal FAIL", f"ρ max {g4(2 * 0.5 / 2)}", "at 0°)")
    short_line(repr(table), "AuditTable(2 models, 1 plausible; not plausible: Phong)")
    # Forty failing rows with long labels: the line names those that fit and counts the rest.
    row = AuditRow("a model with a long label", "p", 0.0, 1.0, 0.5, 0.5, 0.0, 0.5, 0.0, 0.0, True, False, True)
    rows = [AuditRow(**{**vars(row), "label": f"{row.label} {k}"}) for k in range(40)]
    text = repr(AuditTable(rows))
    short_line(text, "AuditTable(40 models, 0 plausible; not plausible: a model with a long label 0, ")
    named = text.split("not plausible: ")[1].split(", ")
    assert len(named) - 1 + int(named[-1].split()[1]) == 40 and named[-1].endswith("more)"), text


def test_fit_result_prints_the_model_and_its_residual():
    f = FitResult(
        Phong(0.4, 30),
        {"ks": (0.4,) * 3, "shininess": 30.0},
        1.25e-3,
        0.0375,
        {"ks": (1e-4,) * 3, "shininess": 0.5},
        57,
        True,
        "converged",
    )
    assert repr(f) == (
        "FitResult(Phong(ks=0.4, shininess=30): relative rms 0.0375, rms 0.00125 1/sr, 57 evaluations, converged)"
    )
    assert "not converged" in repr(f._replace(success=False))


def test_every_analysis_result_class_prints_through_the_display_module():
    # A result class added later without its one-line repr would print its arrays again.
    import dataclasses

    import lighting.analysis as analysis
    from lighting.integrate import AlbedoCurve

    inputs = {"AuditCase"}  # what audit() takes, not what it gives: a label, a model and a note
    classes = [getattr(analysis, n) for n in analysis.__all__ if isinstance(getattr(analysis, n), type)]
    results = [
        c
        for c in classes
        if (dataclasses.is_dataclass(c) or hasattr(c, "_fields") or c.__name__ == "AuditTable")
        and c.__name__ not in inputs
    ] + [FitResult, AlbedoCurve]
    assert {c.__name__ for c in results} == {
        "AngleCurve",
        "PolarSlice",
        "HalfDiffImage",
        "LobeMesh",
        "LobePeak",
        "Profile",
        "AuditRow",
        "AuditTable",
        "FitResult",
        "AlbedoCurve",
    }
    for c in results:
        assert c.__repr__.__module__ == "lighting.analysis._display" or "albedo_repr" in c.__repr__.__code__.co_names, c


def test_the_analysis_page_prints_what_the_engine_prints():
    # docs/analysis.md shows one result's line; it is the line the engine prints today.
    from pathlib import Path

    page = (Path(__file__).resolve().parents[1] / "docs" / "analysis.md").read_text(encoding="utf-8")
    shown = page.split(">>> polar_slice(Phong(0.5, 20), 0.5)\n")[1].split("\n")[0]
    assert shown == repr(polar_slice(Phong(0.5, 20), 0.5))
