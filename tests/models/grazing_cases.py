"""The samplers and views of the grazing χ² tests (tests/models/test_sampler_grazing*.py), built once.

Every registered model and variant (:func:`lighting.models.model_variants`) at its defaults, at every
choice and every flag of its parameter table (one at a time), and the Cook–Torrance NDF × geometry grid
with and without energy compensation; a combination the constructor refuses is listed with the
constructor's ValueError (the tests skip it with that reason).  Models sharing a sampler keep one entry
each, so Oren–Nayar's cosine sampler is tested under its own name.  The anisotropic samplers are tested
with the view along the tangent (φ_v = 0) and across it (φ_v = 90°).  Within the last degree, the samplers
whose model files tested them there: Ward at 89.5° and 89.99°, Ashikhmin–Shirley at 89.9°, the cosine
sampler 1e-4° from the horizon (:func:`last_degree`).
"""

from __future__ import annotations

import math

import numpy as np

from lighting.models import create_model, model_variants

VIEWS_DEG = (0.0, 60.0, 85.0, 89.0)


def view(theta_deg, phi_deg=0.0):
    """The unit view at polar angle ``theta_deg`` and azimuth ``phi_deg`` from the tangent ``x``."""
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return np.array([math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)])


def _settings(cls, fixed):
    out = [("default", dict(fixed))]
    for p in cls.parameters:
        if p.name in fixed:
            continue
        if p.kind == "choice":
            out += [(f"{p.name}={c}", {**fixed, p.name: c}) for c in p.choices if c != p.default]
        elif p.kind == "bool":
            out.append((f"{p.name}={not p.default}", {**fixed, p.name: not p.default}))
    if cls.__name__ == "CookTorrance":
        for ndf in ("beckmann", "ggx", "blinn-phong"):
            for geometry in ("v-cavity", "smith", "smith-correlated"):
                for ec in (False, True):
                    out.append((f"{ndf},{geometry}" + (",ms" if ec else ""),
                                {"ndf": ndf, "geometry": geometry, "energy_compensation": ec}))  # fmt: skip
    return out


def registered():
    """``(id, sampler or None, reason)``: each distinct sampler of each variant; None with the refusal."""
    out, seen = [], set()
    for variant, (cls, fixed) in model_variants().items():
        for label, kwargs in _settings(cls, fixed):
            try:
                model = cls(**kwargs)
            except ValueError as exc:
                out.append((f"{variant}[{label}]", None, f"{cls.__name__}({kwargs}) refused: {exc}"))
                continue
            if model.is_delta:  # no density: test_contract.py checks the delta sampler
                continue
            sampler = model.sampler()
            key = (variant, repr(sampler))
            if key in seen:
                continue
            seen.add(key)
            out.append((f"{variant}[{label}]:{sampler!r}", sampler, ""))
    return out


def anisotropic():
    """``(id, sampler)``: lobes of 10:1 to 100:1, the tangent along ``x``."""
    return [
        ("ward(0.05,0.4)", create_model("ward", alpha_x=0.05, alpha_y=0.4).sampler()),
        ("ward(0.01,0.1)", create_model("ward", alpha_x=0.01, alpha_y=0.1).sampler()),
        ("as(1000,10)", create_model("ashikhmin-shirley", nu=1000, nv=10).sampler()),
        ("as-specular(60,3)", create_model("ashikhmin-shirley", nu=60, nv=3, diffuse=False).sampler()),
        ("disney-aniso", create_model("disney", anisotropic=1.0, roughness=0.5, metallic=1.0).sampler()),
        (
            "disney-aniso-clearcoat",
            create_model("disney", anisotropic=1.0, roughness=0.3, clearcoat=1.0, clearcoat_gloss=0.0).sampler(),
        ),  # fmt: skip
        (
            "ggx-vn(0.05,0.5)",
            create_model("cook-torrance", ndf="ggx", geometry="smith-correlated", alpha_x=0.05, alpha_y=0.5).sampler(),
        ),  # fmt: skip
        (
            "beckmann-vn(0.5,0.05)",
            create_model("cook-torrance", ndf="beckmann", geometry="smith", alpha_x=0.5, alpha_y=0.05).sampler(),
        ),  # fmt: skip
    ]


def roughness_range():
    """``(id, sampler)``: the sharp and the broad ends the model files tested at grazing views."""
    out = []
    for ndf in ("beckmann", "ggx"):
        for a in (0.1, 1.0):
            for geometry in ("v-cavity", "smith"):
                m = create_model("cook-torrance", ndf=ndf, geometry=geometry, roughness=a)
                out.append((f"ct({ndf},{geometry},{a})", m.sampler()))
    out += [
        ("ward(0.02)", create_model("ward", alpha_x=0.02).sampler()),
        ("ward(0.5)", create_model("ward", alpha_x=0.5).sampler()),
        ("as-mixture(15)", create_model("ashikhmin-shirley", rd=0.5, rs=0.5, nu=15, nv=15).sampler()),
        ("as-specular(20)", create_model("ashikhmin-shirley", nu=20, nv=20, diffuse=False).sampler()),
        (
            "disney-clearcoat-satin",
            create_model("disney", roughness=0.8, clearcoat=1.0, clearcoat_gloss=0.0, base_color=0.2).sampler(),
        ),  # fmt: skip
        ("disney-sheen", create_model("disney", sheen=1.0, roughness=0.9, base_color=(0.5, 0.1, 0.1)).sampler()),
        ("disney-gloss", create_model("disney", roughness=0.05, metallic=1.0, clearcoat=1.0).sampler()),
        ("phong(1000)", create_model("phong", shininess=1000).sampler()),
    ]
    return out


def last_degree():
    """``(id, sampler, θ_v, φ_v)``: views within a degree of the horizon, at the parameters the model files used.

    Ward at θ_v = 89.5° (φ_v = 90°) and 89.99° (φ_v = 200°), isotropic and 4:1 to 10:1 lobes from α = 0.01
    to 0.5; Ashikhmin–Shirley at 89.9° (φ_v = 90°), specular alone and the mixture with the cosine lobe,
    isotropic and anisotropic; Oren–Nayar's cosine sampler at 90° − 1e-4°.
    """
    out = []
    for ax, ay in ((0.2, 0.2), (0.5, 0.5), (0.1, 0.4), (0.4, 0.15), (0.02, 0.02), (0.01, 0.1)):
        sampler = create_model("ward", alpha_x=ax, alpha_y=ay).sampler()
        out += [(f"ward({ax},{ay})@{t:g}", sampler, t, p) for t, p in ((89.5, 90.0), (89.99, 200.0))]
    for label, kwargs in (
        ("as-specular(20,20)", {"nu": 20, "nv": 20, "diffuse": False}),
        ("as-specular(60,3)", {"nu": 60, "nv": 3, "diffuse": False}),
        ("as-mixture(8,40)", {"rd": 0.5, "rs": 0.05, "nu": 8, "nv": 40}),
        ("as-mixture(15,15)", {"rd": 0.5, "rs": 0.5, "nu": 15, "nv": 15}),
    ):
        out.append((f"{label}@89.9", create_model("ashikhmin-shirley", **kwargs).sampler(), 89.9, 90.0))
    out.append(("oren-nayar@90-1e-4", create_model("oren-nayar", kd=0.8, sigma=0.5).sampler(), 90.0 - 1e-4, 0.0))
    return out
