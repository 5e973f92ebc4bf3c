"""Procedural skies: SH9 exactness for the band-limited sky against a closed form and a 65,536-node quadrature, and
skies that look like their names, on a fine grid of the sphere (slow set; fast: test_skies.py)."""

import math

import numpy as np
import pytest
from test_skies import _rand_dirs, _sphere_grid

from lighting import Lambert
from lighting.integrate import outgoing_radiance
from lighting.integrate.sh import _band_basis, sh_coefficients, sh_irradiance
from lighting.lights.skies import band_limited_irradiance, sky

pytestmark = pytest.mark.slow  # a 65,536-node quadrature of a sky; the sunset and the studio on a 721 × 1440 grid


def test_band_limited_sky_has_nothing_above_band_two_and_sh9_is_exact():
    env = sky("band-limited")
    # Nothing in bands 3 and 4: a 64-point Gauss rule in z times 128 in φ integrates degree 8 exactly.
    z, wz = np.polynomial.legendre.leggauss(64)
    phi = (np.arange(128) + 0.5) * (2 * math.pi / 128)
    r = np.sqrt(1 - z * z)
    d = np.stack(np.broadcast_arrays(r[:, None] * np.cos(phi), r[:, None] * np.sin(phi), z[:, None]), axis=-1)
    d = d.reshape(-1, 3)
    w = np.repeat(wz, 128) * (2 * math.pi / 128)
    rad = env.radiance(d)
    for band in (3, 4):
        proj = np.einsum("i,im,ic->mc", w, _band_basis(d, band), rad)
        assert np.abs(proj).max() < 1e-13
    # SH9 irradiance equals the closed form (Funk–Hecke) and an independent quadrature.
    n = np.concatenate([_rand_dirs(40, 3), np.eye(3), -np.eye(3)])
    coeffs = sh_coefficients(env, samples=4096)
    exact = band_limited_irradiance(n)
    np.testing.assert_allclose(sh_irradiance(coeffs, n), exact, rtol=1e-10)
    quad = math.pi * outgoing_radiance(Lambert(1.0), env, n, n, method="quadrature", samples=65536)
    np.testing.assert_allclose(quad, exact, rtol=1e-6)
    # Positive everywhere (its smallest value per channel is above 0.2).
    assert env.radiance(_sphere_grid()).min() > 0.2


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
