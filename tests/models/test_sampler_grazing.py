"""χ² tests of every registered model's sampler at normal, oblique and grazing views (tests/chi2.py).

``tests/models/test_contract.py`` runs the χ² test of each distinct sampler at one view (θ_v = 40°);
the model files test their own samplers at grazing views (Oren–Nayar, Ward, Ashikhmin–Shirley, Disney,
the visible-normal samplers).  Missing were the slides' samplers (cosine, Phong, Blinn–Phong, the
microfacet sampler of the V-cavity Cook–Torrance) away from 40°, and one table of every sampler at the
same views.  Here: every distinct sampler of every registered model and variant (defaults and choices) at θ_v = 0°
and 60°, the cosine and Phong samplers also at 85° and 89° (the half-vector samplers there: see
``_resolved``), and anisotropic samplers (Ward, Ashikhmin–Shirley, Disney, anisotropic GGX and Beckmann)
with the view across the tangent (φ_v = 90°) at 0° and 40°.
A delta sampler (the mirror) has no histogram: the contract test checks it.
"""

import math

import numpy as np
import pytest
from chi2 import chi2_pvalue

from lighting.models import create_model, model_variants

VIEWS_DEG = (0.0, 60.0, 85.0, 89.0)


def _view(theta_deg, phi=0.0):
    t = math.radians(theta_deg)
    return np.array([math.sin(t) * math.cos(phi), math.sin(t) * math.sin(phi), math.cos(t)])


def _samplers():
    """Each distinct sampler of the registered models' defaults and choices (not the range ends)."""
    seen = {}
    for variant, (cls, fixed) in model_variants().items():
        settings = [("default", dict(fixed))]
        for p in cls.parameters:
            if p.kind == "choice" and p.name not in fixed:
                settings += [(f"{p.name}={c}", {**fixed, p.name: c}) for c in p.choices if c != p.default]
        for label, kwargs in settings:
            model = cls(**kwargs)
            if model.is_delta:
                continue
            sampler = model.sampler()
            seen.setdefault(repr(sampler), (f"{variant}[{label}]", sampler))
    return [pytest.param(s, id=f"{label}:{key}") for key, (label, s) in seen.items()]


SAMPLERS = _samplers()
ANISOTROPIC = [
    pytest.param(create_model("ward", alpha_x=0.05, alpha_y=0.4).sampler(), id="ward(0.05,0.4)"),
    pytest.param(create_model("ashikhmin-shirley", nu=1000, nv=10).sampler(), id="as(1000,10)"),
    pytest.param(create_model("disney", anisotropic=1.0, roughness=0.5, metallic=1.0).sampler(), id="disney-aniso"),
    pytest.param(
        create_model("cook-torrance", ndf="ggx", geometry="smith-correlated", alpha_x=0.05, alpha_y=0.5).sampler(),
        id="ggx(0.05,0.5)",
    ),  # fmt: skip
    pytest.param(
        create_model("cook-torrance", ndf="beckmann", geometry="smith", alpha_x=0.5, alpha_y=0.05).sampler(),
        id="beckmann(0.5,0.05)",
    ),  # fmt: skip
]


def test_every_registered_model_and_variant_has_its_sampler_here():
    tested = {repr(p.values[0]) for p in SAMPLERS}
    for name, (cls, fixed) in model_variants().items():
        model = cls(**fixed)
        assert model.is_delta or repr(model.sampler()) in tested, name


def _resolved(sampler, theta_v):
    """Whether the shared grid's cell integrals of the density are accurate at this view.

    A half-vector sampler's density ``p(l) = D(h)(n·h)/(4 |v·h|)`` has an integrable ``1/|l + v|`` point at
    ``l = −v``, which at 85° and 89° lies 5° and 1° below the horizon, inside a cell of the fixed
    (cos θ, φ) grid of tests/chi2.py: its 6 × 6 Gauss points then miss the cell's mass by more than its
    0.5 % check (the densities themselves integrate to 1 within 1e-6: test_contract.py).  Those samplers
    are tested at grazing views with cells that follow the lobe in their own files (Ward, Ashikhmin–Shirley,
    Disney, the visible-normal samplers); the V-cavity Cook–Torrance's D(h)(n·h) sampler is not yet.
    """
    return theta_v <= 60 or repr(sampler).startswith(("CosineSampler", "PhongSampler"))


@pytest.mark.parametrize("theta_v", VIEWS_DEG)
@pytest.mark.parametrize("sampler", SAMPLERS)
def test_sampler_chi_square_at_normal_oblique_and_grazing_views(sampler, theta_v):
    if not _resolved(sampler, theta_v):
        pytest.skip("the shared grid does not resolve l = −v at this view (see _resolved)")
    assert chi2_pvalue(sampler, _view(theta_v)) > 1e-3


@pytest.mark.parametrize("theta_v", (0.0, 40.0))
@pytest.mark.parametrize("sampler", ANISOTROPIC)
def test_anisotropic_sampler_chi_square_across_the_tangent(sampler, theta_v):
    # The view in the plane of the bitangent (φ_v = 90°).  At 60° the shared grid's cells no longer resolve
    # these 10:1 to 100:1 lobes (its 0.5 % mass check fails for Ward and Disney; Ashikhmin–Shirley's p drops
    # to 1e-53 at ν = 1000:10), which the model files test with lobe-following cells.
    assert chi2_pvalue(sampler, _view(theta_v, math.pi / 2)) > 1e-3
