r"""Spherical-harmonic irradiance (Ramamoorthi & Hanrahan 2001): nine numbers per environment.

A distant environment ``L(ω)`` is projected onto the nine real spherical harmonics of bands 0–2
(:func:`sh_coefficients`), and the irradiance ``E(n) = ∫ L(ω) max(n·ω, 0) dω`` of a surface of normal
``n`` is a quadratic polynomial in ``n`` (:func:`sh_irradiance`): the clamped cosine's transfer is
almost entirely in those bands, so a Lambertian surface reflects ``L_o = k_d/π · E(n)`` within about
1 % for typical environments.  :func:`lighting.integrate.outgoing_radiance` offers it as
``method="sh"``, with an error bound for the bands it leaves out.

References
----------
R. Ramamoorthi and P. Hanrahan, "An efficient representation for irradiance environment maps",
SIGGRAPH 2001, pp. 497–500.
"""

from __future__ import annotations

import math
import time

import numpy as np

from .._budget import check_budget
from .._validate import check_bool, check_vectors, real_array
from ..lights.environment import Environment, as_environment
from ..numerics import working_dtype
from ..vec import orthonormal_basis
from ._checks import _out, _samples, _unit_rows
from .estimate import Estimate
from .quadrature import _TWO_PI, _split, _star

__all__ = ["SH_CONSTANTS", "sh_basis", "sh_coefficients", "sh_irradiance"]

# Ramamoorthi & Hanrahan (2001), eq. 13: Â_l times the real SH normalizations.
# Written from their derivation (Â0 = π, Â1 = 2π/3, Â2 = π/4); they round to the
# paper's 0.429043, 0.511664, 0.743125, 0.886227, 0.247708.
_C1 = (math.pi / 4) * 0.25 * math.sqrt(15 / math.pi)
_C2 = 0.5 * (2 * math.pi / 3) * math.sqrt(3 / (4 * math.pi))
_C3 = 3 * (math.pi / 4) * 0.25 * math.sqrt(5 / math.pi)
_C4 = math.pi * 0.5 / math.sqrt(math.pi)
_C5 = (math.pi / 4) * 0.25 * math.sqrt(5 / math.pi)
#: ``(c1, c2, c3, c4, c5)`` of the irradiance formula, exact to double precision.
SH_CONSTANTS = (_C1, _C2, _C3, _C4, _C5)


def sh_basis(directions) -> np.ndarray:
    r"""The nine real spherical harmonics of bands 0–2 at unit ``directions`` ``(..., 3)`` → ``(..., 9)``.

    Order ``Y00, Y1−1, Y10, Y11, Y2−2, Y2−1, Y20, Y21, Y22`` with
    ``Y00 = 1/(2√π)``, ``(Y1−1, Y10, Y11) = √(3/4π) (y, z, x)``,
    ``(Y2−2, Y2−1, Y21) = ½√(15/π) (xy, yz, xz)``, ``Y20 = ¼√(5/π)(3z² − 1)``,
    ``Y22 = ¼√(15/π)(x² − y²)`` (Ramamoorthi & Hanrahan 2001, eq. 3).

    Parameters
    ----------
    directions : array_like, (..., 3)
        Unit directions (finite).

    Returns
    -------
    ndarray, (..., 9), float64
        The nine harmonics at each direction.

    Examples
    --------
    >>> sh_basis(np.array([0.0, 0.0, 1.0])).round(6).tolist()
    [0.282095, 0.0, 0.488603, 0.0, 0.0, 0.0, 0.630783, 0.0, 0.0]
    """
    d = check_vectors("directions", directions, dtype=np.float64)
    check_budget("directions", d.size * 8 * 8, what=f"{d.size // 3} directions x 9 harmonics")
    return _sh_basis(d)


def _sh_basis(d: np.ndarray) -> np.ndarray:
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    k0 = 0.5 / math.sqrt(math.pi)
    k1 = math.sqrt(3 / (4 * math.pi))
    k2 = 0.5 * math.sqrt(15 / math.pi)
    k20 = 0.25 * math.sqrt(5 / math.pi)
    k22 = 0.25 * math.sqrt(15 / math.pi)
    return np.stack(
        [
            np.full_like(x, k0),
            k1 * y,
            k1 * z,
            k1 * x,
            k2 * x * y,
            k2 * y * z,
            k20 * (3 * z * z - 1),
            k2 * x * z,
            k22 * (x * x - y * y),
        ],
        axis=-1,
    )


def _sphere_rule(samples: int, env: Environment):
    """Nodes and weights over the whole sphere: on the cap for a patch, else Gauss–Legendre × trapezoid."""
    if env.support is not None:
        axis, cap = env.support
        (nr, nph), _ = _split(samples, 1)
        t1, t2 = orthonormal_basis(axis[None, :])
        d, w = _star(axis[None, :], t1, t2, lambda phi: np.full(phi.shape, cap), None, nr, nph)
        return d[0], w[0]
    n_t = max(2, int(round(math.sqrt(samples / 2))))
    n_p = max(1, samples // n_t)
    z, wz = np.polynomial.legendre.leggauss(n_t)
    phi = (np.arange(n_p) + 0.5) * (_TWO_PI / n_p)
    r = np.sqrt((1 - z) * (1 + z))
    d = np.stack(np.broadcast_arrays(r[:, None] * np.cos(phi), r[:, None] * np.sin(phi), z[:, None]), axis=-1)
    w = np.broadcast_to((wz * (_TWO_PI / n_p))[:, None], (n_t, n_p))
    return d.reshape(-1, 3), w.reshape(-1)


def sh_coefficients(environment, samples: int = 4096, *, return_error: bool = False):
    r"""Project an environment onto the first nine spherical harmonics: ``L_lm = ∫ L(ω) Y_lm(ω) dω``.

    Quadrature: Gauss–Legendre in ``cos θ`` × trapezoid in ``φ`` over the
    sphere (exact for radiance that is a polynomial of low degree in the
    direction), or a polar rule over the cap of a
    :class:`~lighting.lights.environment.SmallPatchEnvironment`.  The error estimate
    is the difference to the rule with a quarter of the nodes.

    Parameters
    ----------
    environment : Environment, scalar/RGB radiance or callable
        As in :func:`lighting.integrate.outgoing_radiance`.
    samples : int >= 8
        Quadrature nodes of the projection (the fine and the error-estimating coarse rule together).
    return_error : bool
        Return an :class:`~lighting.integrate.estimate.Estimate` instead of the bare coefficients.

    Returns
    -------
    ndarray, (9, 3)
        Coefficients per RGB channel, in :func:`sh_basis` order (or an
        :class:`Estimate` with ``return_error``).

    Examples
    --------
    >>> from lighting.lights.environment import ConstantEnvironment
    >>> c = sh_coefficients(ConstantEnvironment(1.0))
    >>> round(float(c[0, 0]), 12) == round(2 * math.sqrt(math.pi), 12), float(np.abs(c[1:]).max()) < 1e-12
    (True, True)
    """
    t0 = time.perf_counter()
    env = as_environment(environment)
    samples = _samples(samples, 8)
    return_error = check_bool("return_error", return_error)
    return _sh_coefficients(env, samples, return_error, t0)


def _sh_coefficients(env, samples: int, return_error: bool, t0: float):
    """:func:`sh_coefficients` of a checked environment and sample count; ``t0`` starts the clock."""
    vals = []
    used = 0
    for s in (samples * 4 // 5, max(8, samples // 5)):
        d, w = _sphere_rule(s, env)
        vals.append(np.einsum("m,mj,mk->jk", w, _sh_basis(d), env._radiance(d).astype(np.float64)))
        used += d.shape[0]
    if not return_error:
        return vals[0]
    return Estimate(vals[0], np.abs(vals[0] - vals[1]), used, time.perf_counter() - t0, "quadrature")


def _irradiance_poly(coeffs, d):
    x, y, z = d[..., 0:1], d[..., 1:2], d[..., 2:3]
    c = coeffs
    return (
        _C1 * c[8] * (x * x - y * y)
        + _C3 * c[6] * z * z
        + _C4 * c[0]
        - _C5 * c[6]
        + 2 * _C1 * (c[4] * x * y + c[7] * x * z + c[5] * y * z)
        + 2 * _C2 * (c[3] * x + c[1] * y + c[2] * z)
    )


def sh_irradiance(coeffs, normals, *, clamp: bool = True) -> np.ndarray:
    r"""Irradiance ``E(n)`` from nine SH coefficients (Ramamoorthi & Hanrahan 2001, eq. 13).

        E(n) = c1 L22 (x² − y²) + c3 L20 z² + c4 L00 − c5 L20
               + 2 c1 (L2−2 xy + L21 xz + L2−1 yz) + 2 c2 (L11 x + L1−1 y + L10 z)

    with ``c1..c5 = 0.429043, 0.511664, 0.743125, 0.886227, 0.247708``
    (:data:`SH_CONSTANTS`, computed exactly).  Bands 0–2 hold the clamped
    cosine's transfer almost entirely, so the result is within about 1 % for
    typical environments; for a single small light the truncated fit rings and
    dips below zero on the far side.  **Negative values are clamped to 0**
    (``clamp=True``, the default) because irradiance cannot be negative; pass
    ``clamp=False`` to see the raw fit.  A Lambertian surface reflects
    ``L_o = k_d/π · E``.

    Parameters
    ----------
    coeffs : array_like, (9, 3) or (9,)
    normals : array_like, (..., 3)
        Unit normals (normalized here; zero normals give 0).
    clamp : bool
        Clamp negative irradiance to 0 (default).

    Returns
    -------
    ndarray, (..., 3) (or (...) for scalar coefficients), dtype of normals

    References
    ----------
    R. Ramamoorthi and P. Hanrahan, "An efficient representation for irradiance environment maps",
    SIGGRAPH 2001, eq. 13.

    Examples
    --------
    >>> from lighting.lights.environment import ConstantEnvironment
    >>> c = sh_coefficients(ConstantEnvironment(1.0))
    >>> round(float(sh_irradiance(c, (0, 0, 1.0))[0]), 12) == round(math.pi, 12)  # E = π L
    True
    """
    allowed = "nine finite SH coefficients, shape (9,) or (9, 3)"
    c = real_array("coeffs", coeffs, allowed=allowed, dtype=np.float64)
    if c.shape not in ((9,), (9, 3)):
        raise ValueError(f"coeffs must be {allowed}; got shape {c.shape}")
    d = check_vectors("normals", normals)
    clamp = check_bool("clamp", clamp)
    check_budget("normals", d.size * 8 * 12, what=f"{d.size // 3} normals")
    return _sh_irradiance(c, d, clamp)


def _sh_irradiance(c: np.ndarray, d: np.ndarray, clamp: bool) -> np.ndarray:
    """:func:`sh_irradiance` of checked float64 coefficients ``(9,)``/``(9, 3)`` and finite float normals."""
    dt = working_dtype(d)
    scalar = c.ndim == 1
    c = c.reshape(9, -1)
    d, length = _unit_rows(d.astype(np.float64), 0.0)
    e = _irradiance_poly(c, d)
    e = np.where(length > 0, e, 0.0)
    if clamp:
        e = np.maximum(e, 0.0)
    if scalar:
        e = e[..., 0]
    return _out(e, dt)


def _a_hat(l: int) -> float:  # noqa: E741
    """Ramamoorthi & Hanrahan's ``Â_l`` of the clamped cosine (0 for odd ``l > 1``)."""
    if l == 1:
        return 2 * math.pi / 3
    if l % 2:
        return 0.0
    log_ratio = math.lgamma(l + 1) - l * math.log(2) - 2 * math.lgamma(l // 2 + 1)
    return 2 * math.pi * (-1) ** (l // 2 - 1) / ((l + 2) * (l - 1)) * math.exp(log_ratio)


_SH_EXACT_BANDS = (4, 6, 8)  # bands the SH error evaluates exactly; beyond them, a bound


def _tail_constant(first: int) -> float:
    """``sqrt(Σ_{l >= first} Â_l² (2l + 1)/(4π))`` (terms fall as l^-4; summed to l = 20000, +1 % margin)."""
    return 1.01 * math.sqrt(sum(_a_hat(k) ** 2 * (2 * k + 1) / (4 * math.pi) for k in range(first, 20001)))


_SH_TAIL = _tail_constant(_SH_EXACT_BANDS[-1] + 1)


def _band_basis(d: np.ndarray, l: int) -> np.ndarray:  # noqa: E741
    """Real orthonormal spherical harmonics of band ``l`` at unit ``d`` ``(M, 3)``: ``(M, 2l + 1)``.

    ``Y_l^m ∝ P_l^|m|(z)/sin^|m|θ · Re/Im (x + i y)^|m|``, by the three-term recurrence in ``l``; the
    sign convention does not matter here, only that the band is orthonormal.
    """
    x, y, z = d[:, 0], d[:, 1], d[:, 2]
    xy = x + 1j * y
    out = []
    for m in range(l + 1):
        q_prev, q = 0.0, np.full_like(z, float(np.prod(np.arange(1, 2 * m, 2))))  # (2m − 1)!!
        for k in range(m + 1, l + 1):
            q_prev, q = q, ((2 * k - 1) * z * q - (k + m - 1) * q_prev) / (k - m)
        norm = math.sqrt((2 * l + 1) / (4 * math.pi) * math.exp(math.lgamma(l - m + 1) - math.lgamma(l + m + 1)))
        if m == 0:
            out.append(norm * q)
        else:
            c = xy**m
            out.append(math.sqrt(2) * norm * q * c.real)
            out.append(math.sqrt(2) * norm * q * c.imag)
    return np.stack(out, axis=-1)


def _sh_truncation_error(env: Environment, coeffs: np.ndarray, n: np.ndarray, samples: int) -> np.ndarray:
    """What the bands above 2 add to the irradiance at normals ``n`` ``(B, 3)``, per RGB channel ``(B, 3)``.

    ``E − E₂ = Σ_{l >= 4 even} Â_l Σ_m L_lm Y_lm(n)`` (``Â_l = 0`` for odd ``l > 1``).  Bands 4, 6 and 8
    are projected (same quadrature as the nine coefficients; its coarse/fine difference counted) and
    evaluated exactly; the rest is bounded by Cauchy–Schwarz in ``m`` (``Σ_m Y_lm² = (2l+1)/(4π)``) and
    in ``l``: ``|Σ_{l>=10} …| <= K sqrt(Σ_{l>=9} Σ_m L_lm²)``, ``K = sqrt(Σ_{l>=10} Â_l² (2l+1)/(4π))``,
    with the energy beyond band 8 from Parseval, ``∫ L² dω − Σ_{l<=8} Σ_m L_lm²``.
    """
    bands = (3, 4, 5, 6, 7, 8)
    proj, energy = [], []
    for s in (samples * 4 // 5, max(8, samples // 5)):
        d, w = _sphere_rule(s, env)
        rad = env._radiance(d).astype(np.float64)
        proj.append([np.einsum("m,mj,mk->jk", w, _band_basis(d, band), rad) for band in bands])
        energy.append(np.einsum("m,mk->k", w, rad * rad))
    total = np.zeros((n.shape[0], 3))
    known = np.sum(coeffs * coeffs, axis=0)
    for band, c_f, c_c in zip(bands, proj[0], proj[1], strict=True):
        known = known + np.sum(c_f * c_f, axis=0)
        if band in _SH_EXACT_BANDS:
            y = _band_basis(n, band)
            a = abs(_a_hat(band))
            total += a * (np.abs(y @ c_f) + np.abs(y) @ np.abs(c_f - c_c))
    e = energy[0] + np.abs(energy[0] - energy[1])  # the quadrature's own error counted against us
    return total + _SH_TAIL * np.sqrt(np.maximum(e - known, 0.0))


def _sh_error_bound(coeff_err, n):
    """Irradiance error from coefficient errors: ``Σ Â_l |δL_lm| |Y_lm(n)|`` (E is linear in them)."""
    a_hat = np.array([math.pi] + [2 * math.pi / 3] * 3 + [math.pi / 4] * 5)
    return np.abs(_sh_basis(n)) @ (a_hat[:, None] * np.abs(coeff_err))
