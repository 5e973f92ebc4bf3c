r"""Energy compensation for rough microfacet lobes (Kulla and Conty 2017): albedo tables and the missing lobe.

A microfacet BRDF counts light that leaves the surface after **one** bounce on the microfacets.
Light that hits a second facet is shadowed away, so a rough white metal (``F = 1``) reflects less
than all the light it receives: its directional albedo with ``F = 1``,

$$
E(μ_o, α) = ∫_Ω \frac{D(h)\, G(v, l)}{4\, μ_o μ_i}\, μ_i\, dω_i,\qquad μ = \cos θ,
$$

falls to ``1 − ln 2 ≈ 0.307`` at normal incidence for GGX with ``α = 1``.  Kulla and Conty add the
lobe that gives the lost energy back, with the same symmetric, separable shape for every view:

    f_ms(l, v) = (1 − E(μ_o)) (1 − E(μ_i)) / (π (1 − E_avg)),     E_avg = 2 ∫_0^1 E(μ) μ dμ,

whose directional albedo is exactly ``1 − E(μ_o)`` (so ``E + ∫ f_ms μ_i dω_i = 1``), and scale it by
the colour of the light that survives the extra bounces (``F_avg`` the cosine-weighted mean of ``F``):

    F_ms = F_avg² E_avg / (1 − F_avg (1 − E_avg)),

the sum over ``k >= 2`` bounces of ``F_avg^k E_avg (1 − E_avg)^{k−1}`` divided by the energy of
``f_ms`` (``1 − E_avg``); ``F_ms = 1`` for ``F = 1``.

What this module holds:

* :func:`albedo_table` — ``E(μ, α)`` and ``E_avg(α)`` of one NDF and Smith geometry, computed by the
  engine's deterministic quadrature (below; shipped precomputed at the default resolution, and checked against
  it by the tests) and cached in memory; an
  :class:`AlbedoTable` interpolates them;
* :func:`fresnel_average` and :func:`multiple_scattering_colour` — ``F_avg`` and ``F_ms``;
* :class:`MultipleScattering` — the lobe ``f_ms`` of one model, which
  :class:`~lighting.models.cook_torrance.CookTorrance` adds with ``energy_compensation=True``.

The table
---------
Grid: :data:`RESOLUTION` ``= 32`` nodes uniform in ``μ ∈ [0, 1]`` times 32 nodes uniform in ``√α`` for
``α ∈ [0, 1]`` (``α = r²``, Kulla and Conty's own variable), so the small roughnesses, where ``E`` moves
fastest with ``α``, get most rows.  Interpolation is bilinear in ``(μ, √α)``, clamped to the grid: an
``α > 1`` reads the ``α = 1`` row.  The ``α = 0`` row is the mirror's ``E = 1``.  ``E_avg`` at each ``α``
node is the integral ``2 ∫ E μ dμ`` of the piecewise-linear interpolant itself, and is interpolated
linearly in ``√α``, so it is exactly ``2 ∫ E(μ, α) μ dμ`` of the interpolated ``E`` at every ``α``: the
compensated white furnace is then ``1`` up to the table's own error at ``μ_o`` (``E − E_table``).

Quadrature (per node): the integral over half vectors, ``E = ∫ D(h) G vh / μ_o dω_h`` (with
``dω_i = 4 (v·h) dω_h``), in polar coordinates ``(θ_h, φ_h)`` about the normal, each ray stopped
exactly where ``l`` reaches the horizon (``n·l = 2 (v·h)(n·h) − μ_o = 0`` at
``θ_h = (β + π/2)/2``, ``β = atan2(sin θ_o cos φ, μ_o)``), so the integrand left is smooth.  Radially,
Gauss–Legendre on panels of ``θ_h = α sinh(B t)`` (the lobe at its own scale) with breaks at
``2α, 8α, 32α`` and, toward the horizon, at ``(½, 2, 8, 32) λ`` with ``λ = min(μ_o, α)/(2 A)`` (the layer
where Smith's ``G1(l)`` falls to 0; ``A`` the amplitude of ``n·l`` along the ray); in azimuth, two
Gauss–Legendre panels meeting at ``φ = π/2``, graded toward it over ``cot θ_o`` (where the horizon cut
turns at grazing views).  The ``μ = 0`` column is the limit ``μ_o → 0⁺``.  Measured against a rule with
three times the nodes each way: at most 2e-8 for ``μ >= 0.1`` (GGX) and 7e-5 (Beckmann); the columns
with ``μ < 0.05`` get a rule twice as fine each way.

Accuracy of the interpolated table against direct high-accuracy integrals at random off-grid points
(``μ ∈ [0.087, 1]``, i.e. ``θ_v <= 85°``, ``α ∈ [0.01, 1]``): at most 1.8e-3 in ``E`` (rms 3e-4), for
every NDF and geometry; see ``tests/models/test_energy.py``.

References
----------
C. Kulla and A. Conty, "Revisiting Physically Based Shading at Imageworks", SIGGRAPH 2017 course
*Physically Based Shading in Theory and Practice* (the lobe ``f_ms``, ``E_avg`` and ``F_ms``).
E. Heitz, "Understanding the masking-shadowing function in microfacet-based BRDFs", JCGT 3(2), 2014
(Smith ``G1``, ``Λ`` and the height-correlated ``G2``).

Examples
--------
>>> t = albedo_table("ggx", "smith-correlated")
>>> round(float(t.E(1.0, 1.0)), 6)  # 1 − ln 2 at normal incidence, α = 1
0.306853
>>> float(t.E(0.5, 0.0))  # the mirror loses nothing
1.0
"""

from __future__ import annotations

import math
import os
from functools import lru_cache

import numpy as np

from .._validate import check_choice, check_color, check_count, real_array
from ..numerics import working_dtype
from . import microfacet as _mf

__all__ = [
    "RESOLUTION",
    "NDFS",
    "GEOMETRIES",
    "AlbedoTable",
    "albedo_table",
    "fresnel_average",
    "multiple_scattering_colour",
    "MultipleScattering",
]

#: Nodes per axis of the default table (``μ`` and ``√α``).
RESOLUTION = 32
#: The NDFs and geometries a table exists for.  Not the Blinn–Phong lobe: the model gives it Beckmann's Smith
#: ``Λ``, which is not the shadowing of a Blinn–Phong microsurface (the projected-area identity fails), so its
#: albedo is no loss to give back: with ``F = 1`` it exceeds 1 at grazing views (1.33 at θ_v = 85°, α = 1).
NDFS = ("beckmann", "ggx")
GEOMETRIES = ("smith", "smith-correlated")

#: Radial panel breaks: multiples of α (the lobe) and of the horizon layer's width.
_LOBE_MARKS = (2.0, 8.0, 32.0)
_LAYER_MARKS = (0.5, 2.0, 8.0, 32.0)
#: Gauss–Legendre nodes per radial panel and azimuth nodes (two graded panels), for μ >= 0.1 and below.
_RULE = (8, 32)
_RULE_GRAZING = (16, 64)
_GRAZING_MU = 0.05


@lru_cache(maxsize=8)
def _gl01(n: int):
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w


def _ndf_values(ndf: str, alpha: float, cos_h, sin2_h):
    """``D(h)`` (float64) of ``ndf`` at roughness ``alpha``."""
    f = _mf._ggx_ndf if ndf == "ggx" else _mf._beckmann_ndf
    return f(cos_h, alpha, sin2_h, np.float64)


def _azimuth_rule(c, s, n_phi: int):
    """Azimuths ``(M, P)`` over ``[0, π]`` and weights: two panels graded toward ``π/2`` over ``cot θ_o``."""
    x, wx = _gl01(n_phi // 2)
    with np.errstate(divide="ignore"):
        eps = np.clip(c / s, 1e-9, 10.0)[:, None]
    a = np.arcsinh((math.pi / 2) / eps)
    d = eps * np.sinh(a * x)
    dd = eps * a * np.cosh(a * x) * wx
    return np.concatenate([math.pi / 2 - d, math.pi / 2 + d], axis=-1), np.concatenate([dd, dd], axis=-1)


def _albedo_nodes(ndf: str, geometry: str, mu: np.ndarray, alpha: float, n_r: int, n_phi: int) -> np.ndarray:
    """``E(μ, α)`` with ``F = 1`` at each ``μ`` ``(M,)`` for one ``α > 0`` by the module's quadrature (float64)."""
    c = np.maximum(np.asarray(mu, dtype=np.float64), 1e-9)[:, None]  # μ = 0: the limit from above
    s = np.sqrt((1 - c) * (1 + c))
    phi, wphi = _azimuth_rule(c[:, 0], s[:, 0], n_phi)
    cp, sp = np.cos(phi), np.sin(phi)
    # n·l along the ray at azimuth φ is A cos(2θ_h − β): the horizon is at θ_h = (β + π/2)/2.
    beta = np.arctan2(s * cp, c)
    tmax = 0.5 * (beta + math.pi / 2)
    amp = np.hypot(s * cp, c)
    b = np.arcsinh(tmax / alpha)
    layer = np.minimum(c, alpha) / (2 * amp)  # where G1(l) falls from ~1 to 0, in θ_h
    # Lobe marks beyond every ray's end would only make empty panels.
    marks = [np.full_like(tmax, k * alpha) for k in _LOBE_MARKS if k * alpha < math.pi / 2]
    marks += [tmax - k * layer for k in _LAYER_MARKS]
    th_b = np.clip(np.stack(marks, axis=-1), 0.0, tmax[..., None])
    tb = np.sort(np.arcsinh(th_b / alpha) / b[..., None], axis=-1)
    edges = np.concatenate([np.zeros_like(tb[..., :1]), tb, np.ones_like(tb[..., :1])], axis=-1)
    x, wx = _gl01(n_r)
    lo, span = edges[..., :-1, None], np.diff(edges, axis=-1)[..., None]
    t = (lo + span * x).reshape(tmax.shape + (-1,))
    wt = (span * wx).reshape(tmax.shape + (-1,))
    bb = b[..., None]
    th = alpha * np.sinh(bb * t)
    w = alpha * bb * np.cosh(bb * t) * wt * wphi[..., None]
    ch, sh = np.cos(th), np.sin(th)
    c3, s3, cp3, sp3 = c[..., None], s[..., None], cp[..., None], sp[..., None]
    vh = s3 * sh * cp3 + c3 * ch
    nl = 2 * vh * ch - c3
    lx = 2 * vh * sh * cp3 - s3
    ly = 2 * vh * sh * sp3
    # G1 = 2 cos θ / d (microfacet._smith_g1_den_*): no small G divided by a small cosine at grazing.
    den = _mf._smith_g1_den_ggx if ndf == "ggx" else _mf._smith_g1_den_beckmann
    dv = den(c3, alpha, s3 * s3)
    dl = den(nl, alpha, lx * lx + ly * ly)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore", under="ignore"):
        if geometry == "smith-correlated":
            # G2 (v·h)/μ_o = 2 (v·h) μ_i / (μ_i d_v + μ_o d_l − 2 μ_o μ_i):
            # G2 = 1/(1 + Λ_v + Λ_l) with Λ = d/(2 cos θ) − 1.
            g = 2 * vh * nl / (nl * dv + c3 * dl - 2 * c3 * nl)
        else:
            g = 4 * vh * nl / (dv * dl)  # G1(v) G1(l) (v·h)/μ_o
        f = np.where(nl > 0, _ndf_values(ndf, alpha, ch, sh * sh) * g * sh, 0.0)
    # ∫ over φ ∈ [0, 2π] is twice the half by the symmetry about the plane of incidence.
    return 2 * np.sum(f * w, axis=(-2, -1))


def microfacet_albedo(ndf: str, geometry: str, mu, alpha) -> np.ndarray:
    r"""``E(μ, α)``: the directional albedo of a microfacet lobe with ``F = 1``, by direct quadrature.

    The function the tables hold, computed afresh (the rule of the module's Notes, the finer one at
    every ``μ``): ``∫ D G / (4 μ_o μ_i) μ_i dω_i`` for the normal distribution ``ndf`` and Smith
    ``geometry`` (``k_s = 1``, denominator 4).

    Parameters
    ----------
    ndf : {"beckmann", "ggx"}
    geometry : {"smith", "smith-correlated"}
    mu : float or array_like
        ``μ_o = cos θ_o`` in [0, 1] (0: the limit from above).
    alpha : float or array_like
        Roughness ``α >= 0`` (0: the mirror, ``E = 1``); broadcasts with ``mu``.

    Returns
    -------
    ndarray
        ``E`` in float64, of the broadcast shape.

    Examples
    --------
    >>> round(float(microfacet_albedo("ggx", "smith", 1.0, 1.0)), 10)  # 1 − ln 2
    0.3068528194
    """
    ndf, geometry = check_choice("ndf", ndf, NDFS), check_choice("geometry", geometry, GEOMETRIES)
    m = real_array("mu", mu, allowed="cosines in [0, 1]", dtype=np.float64)
    a = real_array("alpha", alpha, allowed="roughnesses >= 0", dtype=np.float64)
    if m.size and (m.min() < 0 or m.max() > 1):
        raise ValueError(f"mu must be cosines in [0, 1]; got values in [{m.min():.6g}, {m.max():.6g}]")
    if a.size and a.min() < 0:
        raise ValueError(f"alpha must be roughnesses >= 0; got {a.min():.6g}")
    m, a = np.broadcast_arrays(m, a)
    out = np.ones(m.shape)
    for idx in np.ndindex(m.shape):
        if a[idx] > 0:
            out[idx] = _albedo_nodes(ndf, geometry, m[idx][None], float(a[idx]), *_RULE_GRAZING)[0]
    return out


class AlbedoTable:
    r"""``E(μ, α)`` and ``E_avg(α)`` of one microfacet lobe (``F = 1``), interpolated bilinearly in ``(μ, √α)``.

    Made by :func:`albedo_table` (which caches it); the arrays are read-only.

    Attributes
    ----------
    ndf, geometry : str
        What the table is for.
    mu : ndarray, shape (M,)
        The ``μ`` nodes, uniform in [0, 1].
    sqrt_alpha : ndarray, shape (A,)
        The ``√α`` nodes, uniform in [0, 1].
    values : ndarray, shape (A, M)
        ``E`` at the nodes.
    average : ndarray, shape (A,)
        ``E_avg = 2 ∫ E μ dμ`` of the interpolant at each ``α`` node.
    """

    def __init__(self, ndf: str, geometry: str, mu, sqrt_alpha, values, average):
        self.ndf, self.geometry = ndf, geometry
        self.mu, self.sqrt_alpha, self.values, self.average = (
            np.array(x, dtype=np.float64) for x in (mu, sqrt_alpha, values, average)
        )
        for x in (self.mu, self.sqrt_alpha, self.values, self.average):
            x.flags.writeable = False

    def __repr__(self):
        return f"AlbedoTable({self.ndf!r}, {self.geometry!r}, {len(self.mu)}×{len(self.sqrt_alpha)})"

    @staticmethod
    def _cell(nodes, x):
        """Index of the cell holding ``x`` (clamped to the grid) and the weight of its right node."""
        x = np.clip(x, nodes[0], nodes[-1])
        i = np.clip(np.searchsorted(nodes, x, side="right") - 1, 0, len(nodes) - 2)
        return i, (x - nodes[i]) / (nodes[i + 1] - nodes[i])

    def _alpha_cell(self, alpha):
        return self._cell(self.sqrt_alpha, np.sqrt(np.maximum(alpha, 0.0)))

    def E(self, mu, alpha):  # noqa: N802 - the paper's name
        """``E(μ, α)``, bilinear in ``(μ, √α)``, clamped to ``μ ∈ [0, 1]``, ``α ∈ [0, 1]``.

        Parameters
        ----------
        mu : float or array_like
            Cosines of the view (or light) angle; values outside [0, 1] read the nearest edge.
        alpha : float or array_like
            Roughness; broadcasts with ``mu``.

        Returns
        -------
        ndarray
            ``E`` in [0, 1], of the broadcast shape, in the float dtype of the array inputs (float64
            for Python numbers).
        """
        dt = working_dtype(mu, alpha)
        m = real_array("mu", mu, dtype=np.float64)
        a = real_array("alpha", alpha, dtype=np.float64)
        i, tm = self._cell(self.mu, m)
        j, ta = self._alpha_cell(a)
        v = self.values
        e = (1 - ta) * ((1 - tm) * v[j, i] + tm * v[j, i + 1]) + ta * ((1 - tm) * v[j + 1, i] + tm * v[j + 1, i + 1])
        return np.asarray(e, dtype=dt)

    def E_avg(self, alpha):  # noqa: N802 - the paper's name
        """``E_avg(α) = 2 ∫_0^1 E(μ, α) μ dμ`` of the interpolated ``E`` (linear in ``√α``, clamped).

        Parameters
        ----------
        alpha : float or array_like
            Roughness.

        Returns
        -------
        ndarray
            ``E_avg`` in (0, 1], of ``alpha``'s shape, in its float dtype (float64 for Python numbers).
        """
        dt = working_dtype(alpha)
        return np.asarray(self._e_avg(real_array("alpha", alpha, dtype=np.float64)), dtype=dt)

    def _e_avg(self, a) -> np.ndarray:
        """:meth:`E_avg` of a checked float64 roughness (the models' path), float64."""
        j, ta = self._alpha_cell(np.asarray(a, dtype=np.float64))
        return (1 - ta) * self.average[j] + ta * self.average[j + 1]

    def row(self, alpha: float) -> np.ndarray:
        """``E`` at every ``μ`` node for one roughness: what a model interpolates in ``μ``.

        Parameters
        ----------
        alpha : float
            The roughness (clamped to the table's range).

        Returns
        -------
        numpy.ndarray
            float64 ``(M,)``, one value per ``μ`` node of the table.
        """
        (j,), (ta,) = self._alpha_cell(np.array([float(alpha)]))
        return (1 - ta) * self.values[j] + ta * self.values[j + 1]


def _linear_moment_weights(nodes: np.ndarray) -> np.ndarray:
    """Weights ``w_i`` with ``2 ∫_0^1 p(μ) μ dμ = Σ w_i p(μ_i)`` for ``p`` piecewise linear on ``nodes``."""
    w = np.zeros(len(nodes))
    for i in range(len(nodes) - 1):
        a, b = nodes[i], nodes[i + 1]
        h = b - a
        # 2 ∫_a^b ((b − μ)/h) μ dμ and 2 ∫_a^b ((μ − a)/h) μ dμ.
        w[i] += h * (2 * a + b) / 3
        w[i + 1] += h * (a + 2 * b) / 3
    return w


def _computed_table(ndf: str, geometry: str, resolution: int) -> AlbedoTable:
    """The table by the module's quadrature: the reference the shipped tables are checked against."""
    mu = np.linspace(0.0, 1.0, resolution)
    r = np.linspace(0.0, 1.0, resolution)
    values = np.ones((resolution, resolution))
    grazing = mu < _GRAZING_MU
    for j, rj in enumerate(r[1:], start=1):
        alpha = rj * rj
        values[j, ~grazing] = _albedo_nodes(ndf, geometry, mu[~grazing], alpha, *_RULE)
        values[j, grazing] = _albedo_nodes(ndf, geometry, mu[grazing], alpha, *_RULE_GRAZING)
    values = np.clip(values, 0.0, 1.0)
    # Through the loss 1 − E: exact (1) on the mirror's row, and no cancellation where E is near 1.
    average = 1.0 - (1.0 - values) @ _linear_moment_weights(mu)
    return AlbedoTable(ndf, geometry, mu, r, values, average)


#: The tables of every NDF and geometry at :data:`RESOLUTION`, as :func:`_computed_table` makes them, shipped
#: with the package: the quadrature costs a noticeable fraction of a second per table in every process that
#: first shades a compensated lobe (each test worker, each command).  ``tests/models/test_energy_tables.py``
#: recomputes them and compares; :func:`_write_shipped_tables` rewrites the file.
_SHIPPED_TABLES = os.path.join(os.path.dirname(__file__), "energy_tables.npz")


def _write_shipped_tables(path: str = _SHIPPED_TABLES) -> None:
    """Compute every table at :data:`RESOLUTION` and write them to ``path`` (for the package's maintainers)."""
    arrays = {}
    for ndf in NDFS:
        for geometry in GEOMETRIES:
            t = _computed_table(ndf, geometry, RESOLUTION)
            arrays[f"{ndf}/{geometry}/values"] = t.values
            arrays[f"{ndf}/{geometry}/average"] = t.average
    np.savez(path, **arrays)


@lru_cache(maxsize=16)
def _table(ndf: str, geometry: str, resolution: int) -> AlbedoTable:
    if resolution == RESOLUTION:
        try:
            with np.load(_SHIPPED_TABLES, allow_pickle=False) as data:
                values, average = data[f"{ndf}/{geometry}/values"], data[f"{ndf}/{geometry}/average"]
        except (OSError, KeyError, ValueError):
            pass  # a package without its data file still works, at the quadrature's cost
        else:
            nodes = np.linspace(0.0, 1.0, resolution)
            return AlbedoTable(ndf, geometry, nodes, nodes, values, average)
    return _computed_table(ndf, geometry, resolution)


def albedo_table(ndf: str, geometry: str, resolution: int = RESOLUTION) -> AlbedoTable:
    r"""The albedo table ``E(μ, α)``, ``E_avg(α)`` of a microfacet lobe with ``F = 1``, made on first use.

    Computed by the quadrature of the module's Notes (read from the package's copy of that computation at the
    default resolution) and kept in memory for the session, one per
    ``(ndf, geometry, resolution)``.

    Parameters
    ----------
    ndf : {"beckmann", "ggx"}
        The normal distribution (see :data:`NDFS` for why not ``"blinn-phong"``).
    geometry : {"smith", "smith-correlated"}
        Separable ``G1(v) G1(l)`` or height-correlated ``1/(1 + Λ(v) + Λ(l))`` (the V-cavity term has no
        table: it is not the shadowing of a microsurface whose lost light could be accounted for).
    resolution : int, optional
        Nodes per axis (at least 4), uniform in ``μ`` and in ``√α``.

    Returns
    -------
    AlbedoTable

    Examples
    --------
    >>> t = albedo_table("beckmann", "smith")
    >>> t.values.shape, round(float(t.E_avg(0.0)), 12)
    ((32, 32), 1.0)
    """
    ndf, geometry = check_choice("ndf", ndf, NDFS), check_choice("geometry", geometry, GEOMETRIES)
    return _table(ndf, geometry, check_count("resolution", resolution, 4, 512))


# --------------------------------------------------------------------------- Fresnel averages
def fresnel_average(fresnel: str, f0, eta=None, k=None) -> np.ndarray:
    r"""``F_avg = 2 ∫_0^1 F(μ) μ dμ``, the cosine-weighted hemispherical mean of a Fresnel term, per channel.

    Parameters
    ----------
    fresnel : {"schlick", "dielectric", "none", "conductor"}
        Schlick's ``f0 + (1 − f0)(1 − μ)⁵``: ``F_avg = f0 + (1 − f0)/21`` (``2 ∫ (1 − μ)⁵ μ dμ = 1/21``);
        the exact dielectric with ``η`` from ``f0``: 64-point Gauss–Legendre in ``μ`` (error below 1e-9);
        ``"none"``: 1; the conductor of index ``η + i k``: 64-point Gauss–Legendre in ``μ``, or, where
        ``μ_c = sqrt(1 − η² + k²)`` lies in (0, 1) (the critical angle of ``k = 0``, ``η < 1``, and the bend
        of ``F`` for small ``k``), 64 points on each side of it in ``s`` with ``μ = μ_c ± (width) s²``;
        cached per ``(η, k)``.
    f0 : float or RGB triple in [0, 1]
        Not read for ``"conductor"`` (its ``F0`` follows from ``η`` and ``k``).
    eta, k : float or RGB triple, optional
        The conductor's index (``η > 0``, ``k >= 0``, finite); needed for ``"conductor"`` only.

    Returns
    -------
    ndarray, shape (3,)
        float64.

    Examples
    --------
    >>> fresnel_average("schlick", 0.04).round(6).tolist()
    [0.085714, 0.085714, 0.085714]
    >>> fresnel_average("conductor", 0.04, eta=1.5, k=0.0).round(6).tolist()   # the dielectric η = 1.5
    [0.091778, 0.091778, 0.091778]
    """
    fresnel = check_choice("fresnel", fresnel, ("schlick", "dielectric", "none", "conductor"))
    if fresnel == "conductor":
        from .fresnel import _param

        if eta is None or k is None:
            raise ValueError(f"fresnel_average: fresnel 'conductor' needs eta and k; got eta={eta!r}, k={k!r}")
        eta = _param("eta", eta, "a finite scalar or RGB triple > 0", lambda a: a > 0)
        k = _param("k", k, "a finite scalar or RGB triple >= 0", lambda a: a >= 0)
        return _fresnel_average(fresnel, None, eta, k)
    return _fresnel_average(fresnel, check_color("f0", f0), None, None)


def _fresnel_average(fresnel: str, f0, eta, k) -> np.ndarray:
    """:func:`fresnel_average` of checked values (a model's own): ``eta`` and ``k`` for ``"conductor"``, else ``f0``."""
    if fresnel == "conductor":
        eta = np.broadcast_to(np.asarray(eta, dtype=np.float64), (3,))
        k = np.broadcast_to(np.asarray(k, dtype=np.float64), (3,))
        return np.array([_conductor_average(float(e), float(kk)) for e, kk in zip(eta, k, strict=True)])
    f0 = np.broadcast_to(np.asarray(f0, dtype=np.float64), (3,)).astype(np.float64)
    if fresnel == "none":
        return np.ones(3)
    if fresnel == "schlick":
        return f0 + (1.0 - f0) / 21.0
    from .fresnel import _dielectric_from_f0

    x, w = _gl01(64)
    # F(μ) has a square-root point at μ = 0 (cos θ_t): nodes in s with μ = s², 2 μ dμ = 4 s³ ds.
    mu = x * x
    return np.einsum("i,ic->c", 4 * x**3 * w, _dielectric_from_f0(mu, f0))


@lru_cache(maxsize=256)
def _conductor_average(eta: float, k: float) -> float:
    """``2 ∫ F μ dμ`` of one channel's conductor Fresnel term (:func:`fresnel_average`)."""
    from .fresnel import _conductor

    x, w = _gl01(64)
    c2 = 1.0 - eta * eta + k * k  # where Re(ñ² − sin²θ) = 0: w's real part turns there
    if not 0.0 < c2 < 1.0:
        return float(np.sum(2 * x * w * _conductor(x, eta, k)))
    # F has a square-root point at μ_c (exactly so for k = 0): nodes in s with μ = μ_c ± (width) s² on each side.
    mc = math.sqrt(c2)
    total = 0.0
    for width, sign in ((mc, -1.0), (1.0 - mc, 1.0)):
        mu = mc + sign * width * x * x
        total += float(np.sum(2 * mu * 2 * width * x * w * _conductor(mu, eta, k)))
    return total


def multiple_scattering_colour(f_avg, e_avg) -> np.ndarray:
    r"""Kulla and Conty's colour of the multiple-scattering lobe: ``F_avg² E_avg / (1 − F_avg (1 − E_avg))``.

    Parameters
    ----------
    f_avg : float or array_like
        ``F_avg`` in [0, 1] (:func:`fresnel_average`).
    e_avg : float or array_like
        ``E_avg`` in (0, 1] (:meth:`AlbedoTable.E_avg`); broadcasts with ``f_avg``.

    Returns
    -------
    ndarray
        float64 in [0, 1]; 1 for ``F_avg = 1``.

    Notes
    -----
    Each further bounce leaves with probability ``E_avg`` and keeps ``F_avg`` of its energy, so after
    the single-scattering lobe the surface returns ``Σ_{k>=2} F_avg^k E_avg (1 − E_avg)^{k−1}
    = F_avg² E_avg (1 − E_avg) / (1 − F_avg (1 − E_avg))``; ``f_ms`` carries ``1 − E_avg`` of energy, hence
    the quotient.  The denominator is at least ``E_avg > 0``.

    Examples
    --------
    >>> float(multiple_scattering_colour(1.0, 0.6))
    1.0
    """
    f = np.asarray(f_avg, dtype=np.float64)
    e = np.asarray(e_avg, dtype=np.float64)
    return f * f * e / (1.0 - f * (1.0 - e))


class MultipleScattering:
    r"""The multiple-scattering lobe of one microfacet model, ``c F_ms (1 − E(μ_o))(1 − E(μ_i)) / (π (1 − E_avg))``.

    A product of a function of ``μ_o = n·v`` and one of ``μ_i = n·l``: symmetric (reciprocal) and
    separable, so the stacked shading path takes it as one more term.

    Parameters
    ----------
    table : AlbedoTable
        The lobe's ``E`` (its NDF and geometry).
    alpha : float > 0
        The roughness.
    colour : array_like, shape (3,)
        ``k_s F_ms`` (:func:`multiple_scattering_colour`), the lobe's RGB colour.

    Notes
    -----
    As ``α → 0``, ``E → 1`` and both ``1 − E`` and ``1 − E_avg`` vanish (linearly in ``√α`` below the
    first table row): the quotient is then ``O(√α)`` and is formed as ``(1 − E_o)(1 − E_i)/(1 − E_avg)``
    with the scale ``1/(1 − E_avg)`` taken once, 0 where ``1 − E_avg`` is 0 (no 0/0).
    """

    def __init__(self, table: AlbedoTable, alpha: float, colour):
        self.table = table
        self.alpha = float(alpha)
        self.colour = np.asarray(colour, dtype=np.float64)
        self._row = 1.0 - table.row(self.alpha)  # 1 − E at the μ nodes
        self.e_avg = float(table._e_avg(self.alpha))
        loss = 1.0 - self.e_avg
        self._scale = 1.0 / (math.pi * loss) if loss > 0 else 0.0

    def loss(self, mu) -> np.ndarray:
        """``1 − E(μ)`` at this roughness: the energy single scattering loses.

        Parameters
        ----------
        mu : array_like
            Cosines ``μ`` (clamped to [0, 1]).

        Returns
        -------
        numpy.ndarray
            float64, the shape of ``mu``.
        """
        return np.interp(np.asarray(mu, dtype=np.float64), self.table.mu, self._row)

    def field(self, n_dot_v, n_dot_l, above, *, times_n_dot_l: bool = True) -> np.ndarray:
        """``(1 − E(μ_o))(1 − E(μ_i)) / (π (1 − E_avg))`` (float64), times ``μ_i`` if asked, 0 where not ``above``.

        Parameters
        ----------
        n_dot_v, n_dot_l : ndarray
            ``μ_o`` and ``μ_i``, broadcasting together (a stacked geometry's planes included).
        above : ndarray of bool
            Where both are above the horizon.
        times_n_dot_l : bool
            Multiply by ``μ_i`` (the ``f_r (n·l)`` form).

        Returns
        -------
        ndarray
            float64, the broadcast shape; without the lobe's colour.
        """
        nl = np.asarray(n_dot_l, dtype=np.float64)
        s = self.loss(n_dot_v) * self.loss(nl) * self._scale
        if times_n_dot_l:
            s = s * np.maximum(nl, 0.0)
        return np.where(above, s, 0.0)

    def albedo(self, mu) -> np.ndarray:
        """The lobe's directional albedo without its colour: ``∫ f_ms μ_i dω_i = 1 − E(μ_o)``.

        Parameters
        ----------
        mu : array_like
            Cosines ``μ_o`` of the view.

        Returns
        -------
        numpy.ndarray
            float64, the shape of ``mu`` (0 where the table has no loss to give back).
        """
        return self.loss(mu) * (1.0 if self._scale > 0 else 0.0)
