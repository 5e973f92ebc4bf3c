"""χ² of the samplers at grazing views, the quick subset of the fast loop (the full grid: test_sampler_grazing_full.py).

One sampler of each kind at θ_v = 89° (cosine, Phong, the D(h)(n·h) microfacet sampler of the V-cavity
Cook–Torrance, the visible-normal GGX sampler, Ward, the Ashikhmin–Shirley mixture, Disney, the
energy-compensated mixture), and Ashikhmin–Shirley ν = 1000:10 at 60° across the tangent, where the former
fixed (cos θ, φ) grid gave p = 1.9e-53: with cells that follow the lobe it gives p = 0.44, so that was the
grid, not the sampler.  Cells in the half vector, the density integrated adaptively (tests/chi2.py); 1 %
family-wise with the Šidák correction; fixed seeds.
"""

import pytest
from chi2 import chi2_test, sidak
from grazing_cases import view

from lighting.models import create_model

QUICK = [
    ("lambert", {}, 89.0, 0.0),
    ("phong", {}, 89.0, 0.0),
    ("cook-torrance", {}, 89.0, 0.0),
    ("cook-torrance", {"ndf": "ggx", "geometry": "smith-correlated", "roughness": 0.1}, 89.0, 20.0),
    ("cook-torrance", {"ndf": "ggx", "geometry": "smith-correlated", "energy_compensation": True}, 85.0, 0.0),
    ("ward", {"alpha_x": 0.05, "alpha_y": 0.4}, 89.0, 90.0),
    ("ashikhmin-shirley", {}, 89.0, 0.0),
    ("ashikhmin-shirley", {"nu": 1000, "nv": 10}, 60.0, 90.0),
    ("disney", {"clearcoat": 1.0}, 89.0, 20.0),
    ("oren-nayar", {}, 89.0, 0.0),
]
LEVEL = sidak(0.01, len(QUICK))


@pytest.mark.slow  # seconds of work: the full run has it, the fast loop leaves it out
@pytest.mark.parametrize("name, kwargs, theta_v, phi_v", QUICK, ids=[f"{q[0]}{q[1]}@{q[2]:g}/{q[3]:g}" for q in QUICK])
def test_sampler_chi_square_at_a_grazing_view(name, kwargs, theta_v, phi_v):
    r = chi2_test(create_model(name, **kwargs).sampler(), view(theta_v, phi_v), count=50_000)
    assert r.p > LEVEL, r
