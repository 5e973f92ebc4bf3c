"""The grid of normals of the dominant-light method for a narrow lobe on a 240² sphere under the daylight sky (slow
set; fast: test_normalgrid.py)."""

import numpy as np
import pytest
import test_normalgrid

from lighting.integrate._normalgrid import GRID_DENSITY, GRID_SHARE, grid_points, grid_spacing
from lighting.integrate.dominant import dominant_radiance
from lighting.models.brdf import CookTorrance, Lambert

pytestmark = pytest.mark.slow  # a 240² sphere shaded twice under the dominant lights, a quarter of it pixel by pixel

#: The fast file's fixture (beside this file): the daylight sky as a 64-row map, prefiltered, made once for this file.
daylight = test_normalgrid.daylight


def test_a_narrow_lobe_has_a_coarser_grid_that_reads_the_pixels_within_the_interpolations_error(daylight):
    # GGX α = 0.1 (σ = 0.14, narrower than WIDE_LOBE): two rows per σ (2.5° at most: 4,041 points) and its round lobe
    # per pixel, which a 240² sphere's 38,780 pixels pay for; six rows per σ (13,859 points) would not.
    from lighting.integrate.dominant import HALF_GRID_DENSITY as NARROW_GRID_DENSITY
    from lighting.integrate.dominant import WIDE_LOBE
    from lighting.integrate.ibl import lobe_sigma
    from lighting.validation.accuracy import ibl_sphere

    m = Lambert(0.3) + CookTorrance(1.0, 0.1, 1.0, ndf="ggx", fresnel="none")
    sigma = lobe_sigma(m.parts[1].lobe())
    assert sigma < WIDE_LOBE and NARROW_GRID_DENSITY < GRID_DENSITY
    _, n, v = ibl_sphere(240)
    n, v = n.astype(np.float32), v.astype(np.float32)
    narrow, wide = (grid_points(grid_spacing(sigma, d)) for d in (NARROW_GRID_DENSITY, GRID_DENSITY))
    assert narrow <= GRID_SHARE * n.shape[0] < wide
    pre = daylight
    auto, on = (dominant_radiance(m, pre, n, v, normal_grid=g) for g in (None, True))
    np.testing.assert_array_equal(auto, on)
    on = on[::4]  # every fourth pixel shaded on its own is enough to compare
    off = dominant_radiance(m, pre, n[::4], v[::4], normal_grid=False)
    assert not np.array_equal(on, off)
    rel = np.max(np.abs(on - off), -1) / np.max(off, -1)
    assert np.median(rel) < 1e-3 and np.percentile(rel, 95) < 5e-3, (np.median(rel), np.percentile(rel, 95))
