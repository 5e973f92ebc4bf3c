"""The quadrature's error estimate is honest at low budgets too: |value − truth| ≤ the stated error.

Before the low-budget coarse rule (:func:`lighting.integrate.quadrature._coarse_rules`), correlated GGX with
α = 0.01 seen at 76° came out as 0.9040 ± 1.8e-5 with 64 or 128 nodes, 2.0e-2 (about 1100 stated errors)
from the truth: the fine and the coarse rule agreed by coincidence.
"""

import math

import numpy as np
import pytest

from lighting.brdf import BlinnPhong, CookTorrance
from lighting.integrate import directional_albedo

MODELS = {
    "ggx α=0.01": CookTorrance(1.0, 0.01, 0.9, ndf="ggx", geometry="smith-correlated"),
    "ggx α=0.1": CookTorrance(1.0, 0.1, 0.9, ndf="ggx", geometry="smith-correlated"),
    "beckmann α=0.01": CookTorrance(1.0, 0.01, 0.9),
    "blinn-phong e=1000": BlinnPhong(1.0, 1000, normalized=True),
}
THETAS = np.radians([0.0, 30.0, 60.0, 76.0, 85.0, 89.0])


def test_the_coincidence_case_is_covered_by_its_error():
    m = MODELS["ggx α=0.01"]
    truth = directional_albedo(m, math.radians(76.0), samples=100_000, method="quadrature", return_error=True)
    assert truth.error[0] < 1e-6
    for samples in (64, 128):
        e = directional_albedo(m, math.radians(76.0), samples=samples, method="quadrature", return_error=True)
        assert abs(e.value[0] - truth.value[0]) > 0.01  # the low-budget value is off …
        assert abs(e.value[0] - truth.value[0]) <= e.error[0]  # … and says so
        assert e.unconverged[0]


@pytest.mark.parametrize("name", list(MODELS))
def test_error_covers_the_truth_for_sharp_lobes_at_every_budget(name):
    m = MODELS[name]
    truth = directional_albedo(m, THETAS, samples=50_000, method="quadrature", return_error=True)
    for samples in (64, 128, 256, 1024):
        e = directional_albedo(m, THETAS, samples=samples, method="quadrature", return_error=True)
        off = np.abs(e.value[:, 0] - truth.value[:, 0])
        # the reference's own error and rounding (values near 1e-4 agree to 1e-15 absolute) are allowed for
        assert np.all(off <= e.error[:, 0] + truth.error[:, 0] + 1e-13), (samples, off, e.error[:, 0])
