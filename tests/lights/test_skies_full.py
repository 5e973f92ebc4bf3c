"""Procedural skies that look like their names, on a fine grid of the sphere (slow set; fast: test_skies.py)."""

import math

import numpy as np
import pytest
from test_skies import _sphere_grid

from lighting.lights.skies import sky

pytestmark = pytest.mark.slow  # the sunset and the studio evaluated on a 721 × 1440 grid of the sphere


def test_daylight_sunset_and_studio_look_like_their_names():
    up, down = np.array([0.0, 0.0, 1.0]), np.array([0.0, 0.0, -1.0])
    day = sky("daylight", sun=(1.0, 0.0, 1.0))
    zen, gnd = day.radiance(up), day.radiance(down)
    assert zen[2] > zen[0] and gnd[0] > gnd[2] and gnd.sum() < day.radiance([0.0, 1.0, 0.3]).sum()
    sun = np.array([1.0, 0.0, 1.0]) / math.sqrt(2)
    assert day.radiance(sun).sum() > 4 * day.radiance(-sun * [1, 1, -1]).sum()
    # Sunset: the brightest direction is the sun; the horizon is warm toward it and cool away from it.
    ss = sky("sunset", sun_elevation_deg=5.0, sun_azimuth_deg=90.0)
    grid = _sphere_grid(721, 1440)
    rad = ss.radiance(grid).sum(-1)
    brightest = grid.reshape(-1, 3)[np.argmax(rad)]
    assert (
        math.degrees(math.acos(np.clip(brightest @ [0.0, math.cos(math.radians(5)), math.sin(math.radians(5))], -1, 1)))
        < 0.5
    )
    toward, away = ss.radiance([0.3, 1.0, 0.02]), ss.radiance([0.0, -1.0, 0.02])
    assert toward[0] / toward[2] > 3 and away[0] / away[2] < 1.5 and ss.radiance(up)[2] > ss.radiance(up)[0]
    # Studio: the key light's centre is its radiance plus the background; the walls are dark.
    st = sky("studio")
    key = np.array([0.55, -0.55, 0.63]) / np.linalg.norm([0.55, -0.55, 0.63])
    np.testing.assert_allclose(st.radiance(key), np.array([12.0, 11.5, 10.5]) + 0.03, rtol=1e-12)
    np.testing.assert_allclose(st.radiance([0.0, 1.0, 0.3]), 0.03, rtol=1e-12)
    lit = st.radiance(grid).max(-1) > 1.0
    assert 0.005 < lit.mean() < 0.1  # two lights of a few percent of the sphere
