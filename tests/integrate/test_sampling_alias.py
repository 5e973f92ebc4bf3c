"""``lighting.sampling`` (the contract's import path) exports every sampler class, the visible-normal one included."""

from __future__ import annotations

import numpy as np


def test_visible_normal_sampler_is_exported_like_the_others():
    import lighting.sampling as s
    import lighting.sampling.brdf as home
    from lighting.models.cook_torrance import CookTorrance
    from lighting.sampling.microfacet import VisibleNormalSampler

    # A plain re-export: every public name of the module where the code lives is the same object here.
    assert s.__all__ == home.__all__ and all(getattr(s, name) is getattr(home, name) for name in home.__all__)
    for name in ("UniformSampler", "CosineSampler", "PhongSampler", "MicrofacetSampler", "MixtureSampler",
                 "VisibleNormalSampler"):  # fmt: skip
        assert name in s.__all__ and hasattr(s, name), name
    assert s.VisibleNormalSampler is VisibleNormalSampler
    sampler = CookTorrance(1.0, 0.3, ndf="ggx", geometry="smith").sampler()
    assert isinstance(sampler, s.VisibleNormalSampler)
    # The exported class is the working sampler: its pdf at its own samples is the density they came with.
    v = np.array([0.6, 0.0, 0.8])
    out = sampler.sample(np.random.default_rng(2).random((4, 2)), v)
    assert out.directions.shape == (4, 3) and np.all(out.pdf > 0)
    np.testing.assert_allclose(sampler.pdf(out.directions, v), out.pdf, rtol=1e-12)
