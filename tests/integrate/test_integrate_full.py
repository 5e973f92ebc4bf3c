"""The rendering equation's error estimates over many seeds (slow set; fast: test_integrate.py)."""

import pytest

from lighting.integrate import hemispherical_albedo
from lighting.models.brdf import Phong

pytestmark = pytest.mark.slow  # a hundred seeds of the hemispherical albedo, against a 65,536-node reference


# ==================================================================================== honest error estimates
def test_hemispherical_albedo_error_is_honest():
    model = Phong(1.0, 50.0)
    ref = float(hemispherical_albedo(model, 1 << 16)[0])
    covered = 0
    for seed in range(100):
        est = hemispherical_albedo(model, 256, "importance", view_samples=8, seed=seed, return_error=True)
        covered += abs(float(est.value[0]) - ref) <= 2 * float(est.error[0])
    assert covered >= 90
