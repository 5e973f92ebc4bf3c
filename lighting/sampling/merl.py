r"""Importance sampling of tabulated isotropic BRDFs (MERL tables): a piecewise-constant half-vector density.

For a viewer ``v`` the sampler draws the half vector ``h`` from a piecewise-constant density over bins of
``(θ_h, φ_h − φ_v)`` — the MERL table's 90 √-spaced ``θ_h`` bins times 360 azimuth bins — whose bin
masses are proportional to the light the bin sends to the viewer,

    w_ik ∝ f̄_r(l, v) · max(n·l, 0) · 4 max(v·h, 0) · ΔΩ_ik,      l = 2 (v·h) h − v,

evaluated at the bin centre (``f̄_r`` the mean of the three channels; ``4 (v·h)`` the Jacobian
``dω_l/dω_h``), reflects ``v`` about ``h`` and converts the density, ``p(l) = q(h) / (4 |v·h|)``
(Walter et al. 2007).  A fraction ``cosine_weight`` of the samples is cosine-weighted (defensive mixture,
Hesterberg 1995), so every direction above the horizon has a positive density whatever the table says.

The tables depend on ``θ_v`` only (isotropy): they are built for the centres of 90 bins of ``θ_v``, once per
bin, and cached.  ``pdf`` uses the same view bin, the same bins of ``h`` and the same mixture as ``sample``,
so it is exactly the density of the drawn directions, on the whole sphere (directions below the horizon
included: a bin straddling the horizon sends some half vectors there, as the microfacet samplers do).

References
----------
B. Walter, S. R. Marschner, H. Li, K. E. Torrance, "Microfacet models for refraction through rough
surfaces", EGSR 2007.  T. Hesterberg, "Weighted average importance sampling and defensive mixture
distributions", Technometrics 37(2), 1995.  M. Pharr, W. Jakob, G. Humphreys, *Physically Based
Rendering*, 3rd ed., §13.6.7 (piecewise-constant 2D distributions).
"""

from __future__ import annotations

import math

import numpy as np

from .._budget import check_budget
from .._validate import check_count, check_range
from ..models.base import BRDF
from ..models.lambert import cosine_hemisphere_pdf, square_to_cosine_hemisphere
from ..numerics import safe_div
from ..vec import _dot, normalize
from .base import Sampler, Samples, _upper

__all__ = ["MerlSampler"]

_HALF_PI = 0.5 * math.pi
_TWO_PI = 2.0 * math.pi


class _Table:
    """The half-vector distribution of one view bin: CDFs and the density per steradian of ``h``."""

    __slots__ = ("marginal", "conditional", "flat", "last", "density", "tab_weight")

    def __init__(self, marginal, conditional, density, tab_weight):
        nt, m = conditional.shape
        self.marginal = marginal  # (nt + 1,) CDF over θ_h bins
        self.conditional = conditional  # (nt, np + 1) CDF over φ bins, per θ_h bin
        # All rows in one increasing array (row r shifted by 2r): one searchsorted for rows that differ.
        self.flat = (conditional + 2.0 * np.arange(nt)[:, None]).ravel()
        # Per row, the last φ bin with mass (where u = 1 or rounding lands past the end).
        self.last = np.argmax(conditional >= 1.0, axis=1) - 1
        self.density = density  # (nt, np) q(h) per steradian of h
        self.tab_weight = tab_weight  # 1 − cosine_weight, or 0 for a table without mass


class MerlSampler(Sampler):
    r"""Importance sampler of a tabulated isotropic BRDF: binned half vectors mixed with the cosine.

    Parameters
    ----------
    brdf : lighting.models.base.BRDF
        An isotropic model, usually a :class:`~lighting.files.merl.MerlBRDF`.
    cosine_weight : float in (0, 1], optional
        Fraction of cosine-weighted samples (default 0.15): the density is at least
        ``cosine_weight · cos θ_l / π`` above the horizon.
    theta_h_bins : int, optional
        Bins of ``θ_h``, spaced like MERL's: bin ``i`` is ``[(i/n)², ((i+1)/n)²] · π/2`` (default 90).
    phi_h_bins : int, optional
        Bins of the half vector's azimuth relative to the viewer's, over ``[0, 2π)`` (default 360).
    view_bins : int, optional
        Bins of ``θ_v`` over ``[0, π/2)``; one table per bin, built at its centre (default 90).

    Notes
    -----
    A table is ``theta_h_bins · phi_h_bins`` BRDF evaluations (32 400 by default) and ~0.5 MB;
    all 90 together ~45 MB, estimated against the memory budget before each is built.  Views at or below
    the horizon (and a table whose mass is 0, e.g. black) use the cosine alone, with the same rule in
    ``pdf``.  See the module docstring for the density.

    References
    ----------
    B. Walter et al., "Microfacet models for refraction through rough surfaces", EGSR 2007 (the Jacobian).
    T. Hesterberg, "Weighted average importance sampling and defensive mixture distributions", 1995.

    Examples
    --------
    >>> import numpy as np
    >>> from lighting.brdf import Lambert
    >>> s = MerlSampler(Lambert(0.5))
    >>> v = np.array([0.6, 0.0, 0.8])
    >>> out = s.sample(np.random.default_rng(1).random((4, 2)), v)
    >>> bool(np.allclose(s.pdf(out.directions, v), out.pdf))
    True
    """

    name = "merl"

    def __init__(self, brdf: BRDF, *, cosine_weight: float = 0.15, theta_h_bins: int = 90,
                 phi_h_bins: int = 360, view_bins: int = 90):  # fmt: skip
        if not isinstance(brdf, BRDF):
            raise TypeError(f"MerlSampler: brdf must be a BRDF model; got {type(brdf).__name__}")
        self.brdf = brdf
        self.cosine_weight = check_range("cosine_weight", cosine_weight, 0.0, 1.0, lo_open=True)
        self.theta_h_bins = check_count("theta_h_bins", theta_h_bins, 1, 1024)
        self.phi_h_bins = check_count("phi_h_bins", phi_h_bins, 1, 4096)
        self.view_bins = check_count("view_bins", view_bins, 1, 1024)
        t = (np.arange(self.theta_h_bins + 1) / self.theta_h_bins) ** 2 * _HALF_PI
        self._theta_edges = t
        self._cos_edges = np.cos(t)
        self._cos_edges[-1] = 0.0
        self._dphi = _TWO_PI / self.phi_h_bins
        # Solid angle of bin (i, k): (cos θ_i − cos θ_{i+1}) Δφ.
        self._solid = (self._cos_edges[:-1] - self._cos_edges[1:]) * self._dphi
        self._tables: dict[int, _Table] = {}

    def __repr__(self):
        bins = f"theta_h_bins={self.theta_h_bins}, phi_h_bins={self.phi_h_bins}, view_bins={self.view_bins}"
        return f"MerlSampler({self.brdf!r}, cosine_weight={self.cosine_weight!r}, {bins})"

    # -- tables -------------------------------------------------------------------------------
    def table(self, view_bin: int) -> _Table:
        """The (cached) half-vector distribution for view bin ``view_bin`` (``θ_v`` at its centre)."""
        tab = self._tables.get(view_bin)
        if tab is None:
            tab = self._tables[view_bin] = self._build(view_bin)
        return tab

    def _build(self, b: int) -> _Table:
        nt, nph = self.theta_h_bins, self.phi_h_bins
        # Peak: the pairs' directions and the model's temporaries (~1 KiB per pair, as MerlBRDF._f's chunks).
        check_budget("MerlSampler table", nt * nph * 1024, what=f"{nt * nph} direction pairs")
        theta_v = (b + 0.5) * _HALF_PI / self.view_bins
        v = np.array([math.sin(theta_v), 0.0, math.cos(theta_v)])
        # The θ of each bin's solid-angle midpoint, the azimuth of its middle.
        ct = 0.5 * (self._cos_edges[:-1] + self._cos_edges[1:])
        st = np.sqrt(np.clip(1.0 - ct * ct, 0.0, None))
        ph = (np.arange(nph) + 0.5) * self._dphi
        h = np.stack(np.broadcast_arrays(st[:, None] * np.cos(ph), st[:, None] * np.sin(ph), ct[:, None]), axis=-1)
        vh = _dot(h, v)
        l = 2.0 * vh[..., None] * h - v  # noqa: E741
        f = np.asarray(self.brdf.eval(np.array([0.0, 0.0, 1.0]), l, v), dtype=np.float64)
        f = f.mean(axis=-1) if f.ndim == 3 else f
        w = np.maximum(f, 0.0) * np.maximum(l[..., 2], 0.0) * 4.0 * np.maximum(vh, 0.0) * self._solid[:, None]
        w = np.where(np.isfinite(w), w, 0.0)
        row = w.sum(axis=1)
        total = row.sum()
        if not (total > 0 and np.isfinite(total)):
            return _Table(np.linspace(0.0, 1.0, nt + 1), np.tile(np.linspace(0.0, 1.0, nph + 1), (nt, 1)),
                          np.zeros((nt, nph)), 0.0)  # fmt: skip
        # Cumulative sums divided by their own last element: monotone rounding keeps them non-decreasing
        # and ending at exactly 1, so no bin gets a negative probability.
        marginal = np.concatenate([[0.0], np.cumsum(row)])
        marginal /= marginal[-1]
        cond = np.concatenate([np.zeros((nt, 1)), np.cumsum(w, axis=1)], axis=1)
        cond /= np.where(row > 0, cond[:, -1], 1.0)[:, None]
        # An empty row is never chosen; give it a uniform conditional so its CDF stays increasing.
        cond[row <= 0] = np.linspace(0.0, 1.0, nph + 1)
        # The probabilities are the CDFs' differences, so that pdf is exactly what sampling draws.
        mass = np.diff(marginal)[:, None] * np.diff(cond, axis=1)
        return _Table(marginal, cond, mass / self._solid[:, None], 1.0 - self.cosine_weight)

    def _view(self, v):
        """Unit view, its view bin (−1 at or below the horizon) and azimuth."""
        v = normalize(np.asarray(v, dtype=np.float64))
        theta = np.arccos(np.clip(v[..., 2], -1.0, 1.0))
        b = np.minimum((theta / _HALF_PI * self.view_bins).astype(np.int64), self.view_bins - 1)
        b = np.where(v[..., 2] > 0, b, -1)
        phi_v = np.arctan2(v[..., 1], v[..., 0])
        return v, b, phi_v

    # -- sampling and density ------------------------------------------------------------------
    def _sample(self, u, v):
        v, b, phi_v = self._view(v)
        shape = np.broadcast_shapes(u.shape[:-1], v.shape[:-1])
        u = np.broadcast_to(u, shape + (2,)).reshape(-1, 2)
        v = np.broadcast_to(v, shape + (3,)).reshape(-1, 3)
        b = np.broadcast_to(b, shape).reshape(-1)
        phi_v = np.broadcast_to(phi_v, shape).reshape(-1)
        out = np.empty((u.shape[0], 3))
        for vb in np.unique(b):
            sel = np.flatnonzero(b == vb)
            tab = self.table(int(vb)) if vb >= 0 else None
            a = 1.0 - tab.tab_weight if tab is not None else 1.0
            u0, u1 = u[sel, 0], u[sel, 1]
            cos_part = u0 < a if a < 1.0 else np.ones(sel.size, dtype=bool)
            d = np.empty((sel.size, 3))
            if cos_part.any():
                # Remap the selecting coordinate to [0, 1] so the cosine warp gets a uniform point.
                uc = np.stack([np.minimum(u0[cos_part] / a, 1.0), u1[cos_part]], axis=-1)
                d[cos_part] = square_to_cosine_hemisphere(uc).directions
            tab_part = ~cos_part
            if tab_part.any():
                ut = np.minimum((u0[tab_part] - a) / (1.0 - a), 1.0)
                h = self._draw_h(tab, ut, u1[tab_part], phi_v[sel][tab_part])
                vv = v[sel][tab_part]
                d[tab_part] = 2.0 * _dot(vv, h)[..., None] * h - vv
            out[sel] = d
        out = out.reshape(shape + (3,))
        return Samples(out, self._pdf(out, v.reshape(shape + (3,))))

    def _draw_h(self, tab: _Table, u0, u1, phi_v):
        """Half vectors: a θ bin from the marginal, a φ bin from its conditional, uniform in solid angle."""
        nt, nph = self.theta_h_bins, self.phi_h_bins
        i = np.clip(np.searchsorted(tab.marginal, u0, side="right") - 1, 0, nt - 1)
        lo, hi = tab.marginal[i], tab.marginal[i + 1]
        # u0 = 1 (or rounding) can land in a trailing empty bin: step back to the last bin with mass.
        i = np.where(hi > lo, i, np.searchsorted(tab.marginal, 1.0, side="left") - 1)
        lo, hi = tab.marginal[i], tab.marginal[i + 1]
        fa = np.clip(safe_div(u0 - lo, hi - lo), 0.0, 1.0)
        cc = tab.conditional
        k = np.searchsorted(tab.flat, u1 + 2.0 * i, side="right") - 1 - i * (nph + 1)
        k = np.clip(k, 0, nph - 1)
        clo, chi = cc[i, k], cc[i, k + 1]
        k = np.where(chi > clo, k, tab.last[i])
        clo, chi = cc[i, k], cc[i, k + 1]
        fc = np.clip(safe_div(u1 - clo, chi - clo), 0.0, 1.0)
        c0, c1 = self._cos_edges[i], self._cos_edges[i + 1]
        cos_t = c0 - fa * (c0 - c1)
        sin_t = np.sqrt(np.clip((1.0 - cos_t) * (1.0 + cos_t), 0.0, None))
        phi = (k + fc) * self._dphi + phi_v
        return np.stack([sin_t * np.cos(phi), sin_t * np.sin(phi), cos_t], axis=-1)

    def _pdf(self, l, v):  # noqa: E741
        l = np.asarray(l, dtype=np.float64)  # noqa: E741
        v, b, phi_v = self._view(v)
        shape = np.broadcast_shapes(l.shape[:-1], v.shape[:-1])
        l = np.broadcast_to(l, shape + (3,)).reshape(-1, 3)  # noqa: E741
        v = np.broadcast_to(v, shape + (3,)).reshape(-1, 3)
        b = np.broadcast_to(b, shape).reshape(-1)
        phi_v = np.broadcast_to(phi_v, shape).reshape(-1)
        cos_pdf = cosine_hemisphere_pdf(l)
        out = cos_pdf.copy()  # views at or below the horizon: the cosine alone
        s = l + v
        h = normalize(s)
        h = _upper(h)  # the sampled h lies in the upper hemisphere
        ok = _dot(s, s) > 0
        theta_h = np.arccos(np.clip(h[..., 2], -1.0, 1.0))
        i = np.clip((np.sqrt(theta_h / _HALF_PI) * self.theta_h_bins).astype(np.int64), 0, self.theta_h_bins - 1)
        rel = np.mod(np.arctan2(h[..., 1], h[..., 0]) - phi_v, _TWO_PI)
        k = np.clip((rel / self._dphi).astype(np.int64), 0, self.phi_h_bins - 1)
        vh = np.abs(_dot(v, h))
        for vb in np.unique(b):
            if vb < 0:
                continue
            sel = np.flatnonzero(b == vb)
            tab = self.table(int(vb))
            q = tab.density[i[sel], k[sel]]
            p_tab = np.where(ok[sel], safe_div(q, 4.0 * vh[sel]), 0.0)
            out[sel] = tab.tab_weight * p_tab + (1.0 - tab.tab_weight) * cos_pdf[sel]
        return out.reshape(shape)
