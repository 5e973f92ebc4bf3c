"""An integral over the sphere orients an anisotropic lobe as a direct light does: in the surface's own frame.

A small bright patch tends to a point light (:func:`lighting.integrate.point_light_limit`); for an anisotropic
model the two agree only if the integral turns the lobe's long axis the same way as the direct-light path, by
the documented default tangent ``t = ẑ × n / |ẑ × n|``.  Checked at a tilted normal where Duff et al.'s frame
is about 30° away from that tangent, and with the light turned about the normal.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from lighting.integrate import point_light_limit
from lighting.integrate.ibl import ProgressiveRadiance
from lighting.lights.environment import SmallPatchEnvironment
from lighting.models import create_model
from lighting.render.tangents import default_tangents

NORMAL = np.array([0.3, -0.5, 0.81]) / np.linalg.norm([0.3, -0.5, 0.81])


def _turned(theta, phi):
    t = default_tangents(NORMAL[None])[0]
    b = np.cross(NORMAL, t)
    return math.cos(theta) * NORMAL + math.sin(theta) * (math.cos(phi) * t + math.sin(phi) * b)


@pytest.mark.parametrize("model", [dict(name="ward", ks=1.0, alpha_x=0.1, alpha_y=0.4),
                                   dict(name="ashikhmin-shirley", nu=200, nv=10, diffuse=False)],
                         ids=["ward", "ashikhmin-shirley"])  # fmt: skip
@pytest.mark.parametrize("phi", [0.0, 1.0, 2.5])
def test_a_small_patch_tends_to_the_point_light_of_an_anisotropic_lobe(model, phi):
    kwargs = dict(model)
    brdf = create_model(kwargs.pop("name"), **kwargs)
    v = _turned(0.6, phi + 3.0)
    l = _turned(0.5, phi)  # noqa: E741
    rows = point_light_limit(brdf, l, NORMAL, v, radiance=1e4, solid_angles=(1e-4, 1e-5), samples=4096)
    for row in rows:
        assert float(np.max(row.point)) > 1e4 * row.solid_angle * 1e-3  # the light is inside the lobe
        assert row.relative_error < 0.02, (row.solid_angle, row.patch, row.point)


def test_the_monte_carlo_reference_orients_the_lobe_in_the_same_frame():
    brdf = create_model("ward", ks=1.0, alpha_x=0.05, alpha_y=0.4)
    v = _turned(0.6, 1.2)
    l = _turned(0.5, 1.2 + math.pi)  # the mirror direction about the normal: the lobe's peak
    omega = 1e-3
    env = SmallPatchEnvironment(l, omega, 1.0 / omega)
    ref = ProgressiveRadiance(brdf, env, NORMAL[None], v[None], seed=3)
    for _ in range(8):
        ref.add(4096)
    point = point_light_limit(brdf, l, NORMAL, v, radiance=1.0 / omega, solid_angles=(omega,), samples=4096)[0]
    # Within 4 standard errors and the patch's own O(Ω) difference from a point light.
    assert np.all(np.abs(ref.value[0] - point.patch) <= 4 * ref.error[0] + 1e-9), (ref.value, ref.error, point.patch)
