"""``lighting.sampling``: importance sampling, in one place (and the contract's import path for it).

:mod:`.base`
    The sampler protocol (``sample(u, v)`` → :class:`Samples`, ``pdf(l, v)``), the square-to-hemisphere
    warps and the samplers every model can use (uniform, cosine-weighted).
:mod:`.microfacet`
    Microfacet normal and visible-normal sampling.
:mod:`.brdf`
    Choosing a model's sampler (:func:`importance_sampler`), mixtures, jittered points, the contract's classes.
:mod:`.environment`
    Environment maps: the piecewise-constant 2D distribution over pixel luminance × sin θ.
:mod:`.merl`
    Measured (MERL) data: tabulated half-vector distributions.

Models whose lobe needs a sampler of its own (Ward, Ashikhmin–Shirley, Disney, the mirror) define it beside the
model, as pbrt's BxDFs own their ``Sample_f``; they build it from :mod:`.base`.

This module re-exports :mod:`.brdf`'s public names (its ``__all__``), loaded on first use: the models import
:mod:`.base` while they are being defined, and :mod:`.brdf` imports the models.
"""

from __future__ import annotations

import importlib

__all__ = [
    "Samples", "as_generator", "jittered", "jittered_batch", "square_to_uniform_hemisphere",
    "square_to_cosine_hemisphere", "uniform_hemisphere_pdf", "cosine_hemisphere_pdf", "sample_uniform",
    "sample_cosine", "sample_stratified", "Sampler", "UniformSampler", "CosineSampler", "PhongSampler",
    "MicrofacetSampler", "VisibleNormalSampler", "MirrorSampler", "MixtureSampler", "importance_sampler",
    "sample_brdf", "f_cos_local",
]  # fmt: skip


def __getattr__(name: str):
    if name in __all__:
        return getattr(importlib.import_module(".brdf", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
