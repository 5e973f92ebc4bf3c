"""The shipped energy-compensation tables are the quadrature's: recomputed here and compared entry by entry.

``lighting/models/energy_tables.npz`` saves the four ``E(μ, α)`` tables at the default resolution so that no
process pays for the quadrature; if a change to the quadrature makes this fail, rewrite the file with
``python -c "from lighting.models.energy import _write_shipped_tables; _write_shipped_tables()"``.
"""

from __future__ import annotations

import numpy as np
import pytest

from lighting.models import energy

pytestmark = pytest.mark.slow  # the four tables' quadrature


@pytest.mark.parametrize("ndf", energy.NDFS)
@pytest.mark.parametrize("geometry", energy.GEOMETRIES)
def test_the_shipped_table_is_the_quadratures(ndf, geometry):
    shipped = energy._table(ndf, geometry, energy.RESOLUTION)
    computed = energy._computed_table(ndf, geometry, energy.RESOLUTION)
    # Bit for bit where the file was written; another CPU's sin/exp may round a last bit differently.
    np.testing.assert_allclose(shipped.values, computed.values, rtol=1e-14, atol=0)
    np.testing.assert_allclose(shipped.average, computed.average, rtol=1e-14, atol=0)
    assert np.array_equal(shipped.mu, computed.mu) and np.array_equal(shipped.sqrt_alpha, computed.sqrt_alpha)
    assert shipped.values.shape == (energy.RESOLUTION, energy.RESOLUTION) and not shipped.values.flags.writeable


def test_another_resolution_is_computed():
    t = energy._table("ggx", "smith", 8)
    assert t.values.shape == (8, 8)
    np.testing.assert_array_equal(t.values, energy._computed_table("ggx", "smith", 8).values)
