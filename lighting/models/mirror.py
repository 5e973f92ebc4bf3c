r"""The ideal mirror: a Dirac-delta BRDF, and its sampler, which returns the one reflected direction.

    f_r(v, l) = R(cos θ_v) δ(l − R_v) / (n·l),     R_v = 2 n (n·v) − v,
    ρ(v) = ∫ f_r (n·l) dω_l = R(cos θ_v),          L_o(v) = R(cos θ_v) L_i(R_v)

``R`` is :meth:`Mirror.reflectance`: ``k_s``, ``k_s F_Schlick``, ``k_s F_dielectric`` or ``k_s F_conductor``.
"""

from __future__ import annotations

import numpy as np

from .._validate import check_choice, check_vectors
from ..numerics import saturate_to, working_dtype
from ..sampling.base import Sampler, Samples
from ..vec import normalize, reflect
from . import fresnel as _fresnel
from .base import BRDFFlags, SeparableBRDF, _color, _color_text
from .protocol import Lobe, Parameter, register_model

__all__ = ["Mirror", "MirrorSampler"]

_NORMAL = np.array([0.0, 0.0, 1.0])  # the local frame's normal


class Mirror(SeparableBRDF):
    r"""The ideal (specular, "perfect") mirror: all reflected light leaves along ``R_v``.

    As a distribution over directions:

        f_r(v, l) = R(cos θ_v) δ_ω(l − R_v) / (n·l),     R_v = 2 n (n·v) − v,

    with ``δ_ω`` the Dirac delta on the sphere.  Its integrals are exact: the directional albedo
    is ``ρ(v) = R(cos θ_v)``, and under distant lighting ``L_o(v) = R(cos θ_v) L_i(R_v)``.
    ``R`` (:meth:`reflectance`) is ``k_s`` (``fresnel="none"``), ``k_s F_Schlick(cos θ_v; F_0)``,
    ``k_s F_dielectric(cos θ_v; η(F_0))`` (:mod:`lighting.models.fresnel`; η from ``F_0`` as
    in :class:`~lighting.models.cook_torrance.CookTorrance`) or ``k_s F_conductor(cos θ_v; η, k)``, a polished
    metal (``Mirror(fresnel="conductor", metal="gold")``).

    The delta is not a function.  ``eval``, ``eval_cos`` and ``classic`` return 0 for every pair of
    directions: under point, directional and spot lights a viewer would see the light only
    where ``R_l = v`` exactly, an event of probability 0 for finitely many samples, so a mirror
    lit by them is black (plus its ambient term).  What it reflects is seen under an environment
    or an area light, and the integrators of :mod:`lighting.integrate` add it exactly
    (``brdf.is_delta``, ``reflectance``), with zero error, also inside a sum with smooth parts
    (``Lambert(0.5) + Mirror(0.3)``).

    The mirror is the limit of the glossy models as their lobes sharpen, with their albedo
    held (tests/models/test_mirror.py measures the approach under an environment):

    * Cook–Torrance (single-scattering microfacets, Smith or V-cavity ``G``) as ``α → 0``:
      ``D → δ`` on the half vectors, ``G → 1``, ``h → n``, so
      ``CookTorrance(ks, α, f0, fresnel=...)`` tends to ``Mirror(ks, f0, fresnel=...)``;
    * Phong, ``k_s (R_l·v)^e / (π n·l)``, as ``e → ∞`` with ``k_s`` scaled by ``(e + 1)/2`` (its
      albedo at normal incidence is ``2 k_s/(e + 1)``): tends to ``Mirror(ks)``;
    * NDF-normalized Blinn–Phong, ``k_s (e + 2)/(2π) (n·h)^e``, as ``e → ∞``: a delta of reflectance
      ``4 k_s cos²θ_v`` — the microfacet factors ``G/(4 (n·v)(n·l))`` are missing, which is why the
      slides combine it with them (Cook–Torrance with ``ndf="blinn-phong"``).

    Parameters
    ----------
    ks : float or RGB triple, >= 0
        Reflectance scale (the mirror's colour; ``k_s <= 1`` conserves energy).
    f0 : float or RGB triple in [0, 1]
        Fresnel reflectance at normal incidence (``fresnel`` ``"schlick"`` or ``"dielectric"``).  Not used
        with ``fresnel="conductor"``: the model's :attr:`f0` is then the conductor's
        ``((η − 1)² + k²) / ((η + 1)² + k²)``, and ``f0`` given only supplies ``η`` when ``eta`` is unset.
    fresnel : {"none", "schlick", "dielectric", "conductor"}
        The angular dependence: none (``R = k_s``), Schlick's approximation, the exact unpolarized
        dielectric with ``η = (1 + √F_0)/(1 − √F_0)``, or the exact conductor of index ``η + i k``.
    eta, k : float or RGB triple, or None
        The conductor's index (``η > 0``, ``k >= 0``, finite), for ``fresnel="conductor"`` only; None:
        ``η`` of ``f0`` and ``k = 0``.
    metal : {"none", "gold", "silver", "copper", "aluminium", "chromium"}
        A named metal's ``η`` and ``k`` (:data:`lighting.models.fresnel.METALS`), for ``fresnel="conductor"``
        only, with ``eta`` and ``k`` unset.

    Notes
    -----
    ``lobe()`` is :class:`~lighting.models.protocol.Lobe` ``()`` (axis ``"normal"``, width ``inf``: no
    lobe to follow), because the function ``f_r (n·l)`` that quadrature rules, polar slices and lobe
    meshes see is 0 everywhere: a zero width would divide by zero in their grid spacings.  Code
    that draws or integrates the reflected direction asks ``is_delta`` and calls :meth:`reflectance`.

    References
    ----------
    M. Pharr, W. Jakob and G. Humphreys, *Physically Based Rendering*, 4th ed., §9.2 (specular
    reflection, delta distributions) and §9.3, 2023.
    R. L. Cook and K. E. Torrance, "A reflectance model for computer graphics", ACM TOG 1(1), 1982.
    B. Walter, S. R. Marschner, H. Li and K. E. Torrance, "Microfacet models for refraction through
    rough surfaces", EGSR 2007.
    C. Schlick, "An inexpensive BRDF model for physically-based rendering", CGF 13(3), 1994.
    B. T. Phong, "Illumination for computer generated pictures", CACM 18(6), 1975.

    Examples
    --------
    >>> m = Mirror(0.9)
    >>> m.is_delta, m.eval((0, 0, 1.0), (0, 0, 1.0), (0, 0, 1.0)).tolist()
    (True, [0.0, 0.0, 0.0])
    >>> m.reflectance(0.5).tolist()
    [0.9, 0.9, 0.9]
    >>> round(float(Mirror(1.0, 0.04, "dielectric").reflectance(1.0)[0]), 12)
    0.04
    >>> Mirror(fresnel="conductor", metal="silver").reflectance(1.0).round(3).tolist()
    [0.988, 0.983, 0.979]
    """

    name = "mirror"
    flags = BRDFFlags.SPECULAR | BRDFFlags.DELTA
    stackable = True
    FRESNELS = ("none", "schlick", "dielectric", "conductor")
    parameters = (
        Parameter("ks", "color", 1.0, slider=(0.0, 1.0), description="reflectance scale k_s (the mirror's colour)"),
        Parameter("f0", "color", 0.04, high=1.0, description="Fresnel reflectance at normal incidence F0"),
        Parameter("fresnel", "choice", "none", choices=FRESNELS,
                  description="Fresnel: none, Schlick, exact dielectric, exact conductor"),
        *_fresnel.CONDUCTOR_PARAMETERS,
    )

    def __init__(self, ks=1.0, f0=0.04, fresnel="none", eta=None, k=None, metal="none"):
        self.ks = _color("ks", ks)
        self.f0 = _color("f0", f0, hi=1.0)
        self.fresnel = check_choice("fresnel", fresnel, self.FRESNELS)
        #: The conductor's η and k as used (RGB float64; None unless ``fresnel="conductor"``), the metal named.
        self.eta, self.k, self.metal, self.f0 = _fresnel._conductor_setup(self.fresnel, self.f0, eta, k, metal)

    @property
    def is_black(self):
        return not np.any(self.ks > 0)

    def _params(self):
        if self.fresnel == "conductor":  # f0 follows from η and k
            return {"ks": self.ks, "fresnel": self.fresnel, **_fresnel._conductor_table(self, plain=False)}
        return {"ks": self.ks, "f0": self.f0, "fresnel": self.fresnel}

    def to_dict(self):
        """With ``fresnel="conductor"`` the table has ``metal`` when one is named, else ``eta`` and ``k``, and no ``f0``
        (which the conductor does not use).
        """
        d = {"model": self.name, "ks": [float(x) for x in np.broadcast_to(self.ks, (3,))]}
        if self.fresnel != "conductor":
            d["f0"] = [float(x) for x in np.broadcast_to(self.f0, (3,))]
        d["fresnel"] = self.fresnel
        d.update(_fresnel._conductor_table(self))
        return d

    def summary(self):
        """For example ``"mirror ks=0.9 F=1"``, ``"mirror ks=1 schlick f0=0.04"`` or ``"mirror ks=1 conductor gold"``.
        """
        from .cook_torrance import _fresnel_text

        return f"mirror ks={_color_text(self.ks)} {_fresnel_text(self)}"

    def reflectance(self, cos_theta) -> np.ndarray:
        r"""The fraction of the radiance arriving from ``R_v`` that leaves toward ``v``: ``R(cos θ_v)``.

        The delta's weight, equal to the directional albedo ``ρ(v)`` (reciprocity: also the fraction of
        a beam from ``l`` sent into ``R_l``).

        Parameters
        ----------
        cos_theta : float or array_like
            ``n·v`` (equivalently ``n·l`` at the mirror direction), in ``[−1, 1]`` (rounding up to
            :data:`~lighting.models.fresnel.COS_SLACK` beyond is tolerated), any shape.

        Returns
        -------
        ndarray, shape cos_theta.shape + (3,)
            ``k_s``, ``k_s F_Schlick``, ``k_s F_dielectric`` or ``k_s F_conductor``; 0 where
            ``cos_theta <= 0`` (the viewer at or below the horizon, as every BRDF of the engine).  In the float dtype of
            ``cos_theta`` (float64 for Python numbers), saturated at its largest value.

        Raises
        ------
        ValueError
            ``cos_theta`` not finite or outside ``[−1, 1]`` (``ArgumentTypeError`` for text, complex, None).

        Notes
        -----
        At grazing incidence (``cos θ → 0⁺``) both Fresnel forms tend to 1, so ``R → k_s``; at exactly
        0 the value is 0, the engine's horizon convention (the directional albedo at ``θ_v = π/2``).

        Examples
        --------
        >>> Mirror(1.0, 0.04, "schlick").reflectance([1.0, 0.0, -0.5])[:, 0].tolist()
        [0.04, 0.0, 0.0]
        """
        dt = working_dtype(cos_theta)
        return saturate_to(self._reflectance(_fresnel._cosines("cos_theta", cos_theta)), dt)

    def _reflectance(self, c: np.ndarray) -> np.ndarray:
        """:meth:`reflectance` on checked float64 cosines ``c`` (the integrators' path): float64 ``(..., 3)``."""
        c = np.asarray(c, dtype=np.float64)
        if self.fresnel == "none":
            f = np.ones(c.shape + (3,))
        elif self.fresnel == "schlick":
            f = _fresnel.schlick(np.clip(c, 0.0, 1.0), self.f0)
        elif self.fresnel == "conductor":
            f = _fresnel._conductor(np.clip(c, 0.0, 1.0), self.eta, self.k)
        else:
            f = _fresnel._dielectric_from_f0(c, self.f0)
        with np.errstate(over="ignore"):
            return np.where((c > 0)[..., None], f * self.ks, 0.0)

    # -- the function part: zero everywhere ------------------------------------------
    def _f(self, g):
        return np.zeros(np.shape(g.n_dot_l) + (3,), dtype=g.dtype)

    def _f_cos(self, g):
        return self._f(g)

    def separable_cos(self, g):
        """One term ``(0, ks)``: the delta contributes nothing to a finite set of light directions."""
        return [(np.zeros(np.shape(g.n_dot_l), dtype=g.dtype), self.ks)]

    def separable_classic(self, g):
        """As :meth:`separable_cos`: one zero term."""
        return self.separable_cos(g)

    # -- what the rest of the engine asks ---------------------------------------------
    def lobe(self):
        """``Lobe()``: axis ``"normal"``, width ``inf``; the function part has no lobe to follow (the Notes above)."""
        return Lobe()

    def sampler(self):
        """``MirrorSampler``: the delta sampler: every sample is ``R_v``, with weight ``reflectance(cos θ_v)``."""
        return MirrorSampler(self)


class MirrorSampler(Sampler):
    r"""The delta sampler of a mirror: every draw is the reflected direction ``R_v = (−v_x, −v_y, v_z)``.

    In the sampler protocol's terms (:class:`~lighting.sampling.base.Sampler`), as pbrt-v4's specular
    ``BSDFSample``:

    * ``delta = True`` marks the sampler (smooth samplers have no such attribute, or ``False``);
    * ``sample(u, v).directions`` is ``R_v`` for every ``u`` (local frame, unit; the zero vector
      for a zero ``v``), and ``.pdf`` is 1: the *probability* of that discrete choice, not a
      density per steradian;
    * ``weight(v)`` is the estimator's ``f_r (n·l) / p`` for that sample, ``reflectance(cos θ_v)``
      ``(..., 3)``, so a one-sample estimate of ``∫ f_r L (n·l) dω`` is ``weight(v) L(R_v)``, exact;
    * ``pdf(l, v)`` is 0 for every direction, as ``eval`` is: the density with respect to solid angle
      has no finite value at ``R_v`` and is 0 elsewhere, so multiple importance sampling gives the
      delta no share of another strategy's samples, and another strategy never draws ``R_v``.

    Parameters
    ----------
    source
        What reflects: an object with ``_reflectance(cos)`` (float64 ``(..., 3)``), a :class:`Mirror`
        or a sum of delta parts.

    Examples
    --------
    >>> s = Mirror(0.5).sampler()
    >>> out = s.sample([[0.3, 0.7]], [0.6, 0.0, 0.8])
    >>> out.directions.round(12).tolist(), out.pdf.tolist(), s.weight([0.6, 0.0, 0.8]).tolist()
    ([[-0.6, 0.0, 0.8]], [1.0], [0.5, 0.5, 0.5])
    """

    name = "mirror"
    delta = True

    def __init__(self, source):
        self.source = source

    def __repr__(self):
        return f"MirrorSampler({self.source!r})"

    def weight(self, v) -> np.ndarray:
        """``f_r (n·l) / p`` of the one sample: ``reflectance(cos θ_v)``, 0 for viewers at or below the horizon.

        Parameters
        ----------
        v : array_like, shape (..., 3)
            View directions in the local frame (need not be unit; a zero vector gives 0).

        Returns
        -------
        ndarray, shape (..., 3)
            float64.
        """
        v = check_vectors("v", v, dtype=np.float64)
        return np.minimum(self._weight(v), np.finfo(np.float64).max)  # a sum of huge k_s saturates

    def _weight(self, v):
        return self.source._reflectance(normalize(np.asarray(v, dtype=np.float64))[..., 2])

    def _sample(self, u, v):
        r = reflect(normalize(np.asarray(v, dtype=np.float64)), _NORMAL)  # R_v = 2 n (n·v) − v, n = ẑ
        shape = np.broadcast_shapes(np.shape(u)[:-1], r.shape[:-1])
        return Samples(np.broadcast_to(r, shape + (3,)).copy(), np.ones(shape))

    def _pdf(self, l, v):  # noqa: E741
        return np.zeros(np.broadcast_shapes(np.shape(l)[:-1], np.shape(v)[:-1]))


register_model(Mirror)
