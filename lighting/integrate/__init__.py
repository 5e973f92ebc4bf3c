r"""The rendering equation over the hemisphere: sampling, quadrature, albedo, radiance, SH irradiance.

The CMSC 435 deck's rendering equation, for a surface with normal ``n`` seen from ``v``:

    L_o(v) = ∫_Ω f_r(v, l) L_i(l) (n·l) dω(l)                (full environment)
    L_o(v) = Σ_i f_r(v, l_i) E_i (n·l_i)                      (point lights)

and, with ``L_i = 1`` everywhere, the directional albedo ``ρ(v) = ∫_Ω f_r(v, l) (n·l) dω(l)``
(conventions.md).  The modules, in the order they build on each other:

============ ======================================================================================
sampling     hemisphere warps, the importance samplers of the models and their mixtures
estimate     :class:`Estimate` (value, honest error, cost), the Monte Carlo error terms,
             :data:`UNCONVERGED_RELATIVE_ERROR`
quadrature   polar rules centred on each model's lobe, cut at the horizon (``method="quadrature"``)
montecarlo   sampled means (``"uniform"``, ``"cosine"``, ``"importance"``, ``"stratified"``)
albedo       :func:`directional_albedo`, :func:`albedo_curve`, :func:`hemispherical_albedo`
sh           spherical-harmonic irradiance (Ramamoorthi & Hanrahan 2001)
radiance     :func:`outgoing_radiance` under an environment (also ``"environment"``, ``"mis"``,
             ``"sh"``) and :func:`point_light_limit`
============ ======================================================================================

Every integrator takes ``samples`` (its cost: integrand evaluations per result) and a ``method``;
with ``return_error=True`` it returns an :class:`Estimate` whose error is honest: the true error lies
within two reported errors in at least 90 % of seeds, rare events included.  Arguments are checked
once, at the public boundary; all integration runs in float64 and results come back in the working
dtype of the array inputs (float32 in, float32 out).

Examples
--------
>>> from lighting.models.brdf import Lambert
>>> directional_albedo(Lambert(0.5), 0.3).round(12).tolist()
[0.5, 0.5, 0.5]
"""

from __future__ import annotations

from ..sampling import brdf as sampling  # noqa: F401
from ..sampling.brdf import *  # noqa: F403
from . import albedo, estimate, montecarlo, quadrature, radiance, sh  # noqa: F401
from .albedo import *  # noqa: F403
from .estimate import *  # noqa: F403
from .radiance import *  # noqa: F403
from .sh import *  # noqa: F403

__all__ = [
    "sampling",
    *sampling.__all__,
    *estimate.__all__,
    *albedo.__all__,
    *radiance.__all__,
    *sh.__all__,
]
