"""Fresnel reflectance: the fraction of light a smooth interface reflects.

The functions broadcast, keep the float dtype of ``cos_theta`` and take RGB
parameters as a trailing axis of length 3 when given a triple.
"""

from __future__ import annotations

import difflib
import math
from types import MappingProxyType

import numpy as np

from .._budget import check_budget
from .._text import quote
from .._validate import ArgumentTypeError, real_array
from ..numerics import safe_div, working_dtype
from .protocol import Parameter

__all__ = [
    "schlick",
    "dielectric",
    "conductor",
    "conductor_f0",
    "f0_from_eta",
    "eta_from_f0",
    "METALS",
    "METAL_SOURCES",
    "METAL_WAVELENGTHS_NM",
    "metal_index",
]

#: How far a cosine may stray beyond [−1, 1] by rounding (clamped); anything further is refused.
COS_SLACK = 1e-6


def _cosines(name: str, value, lo: float = -1.0) -> np.ndarray:
    """A public function's cosine argument: finite real numbers in ``[lo, 1]`` (rounding slack clamped), float64."""
    allowed = f"finite real cosines in [{lo:g}, 1]"
    arr = real_array(name, value, allowed=allowed, dtype=np.float64)
    if arr.size and (np.min(arr) < lo - COS_SLACK or np.max(arr) > 1 + COS_SLACK):
        bad = arr[(arr < lo - COS_SLACK) | (arr > 1 + COS_SLACK)]
        raise ValueError(f"{name} must be {allowed}; got {quote(bad.flat[0])} in {quote(value)}")
    return np.clip(arr, lo, 1)


def _param(name: str, value, allowed: str, ok) -> np.ndarray:
    """A scalar or RGB-triple parameter as float64: real, finite, shape () or (3,), and ``ok(arr)`` everywhere."""
    arr = real_array(name, value, allowed=allowed, dtype=np.float64)
    if arr.shape not in ((), (3,)):
        raise ValueError(f"{name} must be {allowed}; got shape {arr.shape}: {quote(value)}")
    if not np.all(ok(arr)):
        raise ValueError(f"{name} must be {allowed}; got {quote(value)}")
    return arr


def _budget(name: str, c: np.ndarray, p: np.ndarray) -> None:
    n = c.size * (3 if p.ndim else 1)
    check_budget(name, n * 12 * 8, what=f"{n} values")


def schlick(cos_theta, f0) -> np.ndarray:
    """Schlick's approximation ``F = F0 + (1 - F0) (1 - cos θ)^5``.

    ``cos_theta`` is the cosine between the incident direction and the
    (micro)normal, in [−1, 1] and clamped to [0, 1].  ``f0`` (reflectance at
    normal incidence, in [0, 1]) is a scalar or an RGB triple; with a triple
    the result has a trailing axis 3.

    Raises ``ValueError`` naming the argument (``ArgumentTypeError``, also a
    ``TypeError``, for text, complex, booleans or None).

    Parameters
    ----------
    cos_theta : array_like
        Cosines in [−1, 1] (rounding up to :data:`COS_SLACK` beyond is tolerated), any shape.
    f0 : float or array_like, shape (3,)
        Reflectance at normal incidence, in [0, 1]: a scalar or an RGB triple.

    Returns
    -------
    ndarray
        ``F`` in ``[f0, 1]``, of ``cos_theta``'s shape (plus a trailing axis 3 for a triple ``f0``), in
        the float dtype of ``cos_theta`` (float64 for Python numbers).

    References
    ----------
    C. Schlick, "An inexpensive BRDF model for physically-based rendering", Computer
    Graphics Forum 13(3), 1994.

    Examples
    --------
    >>> float(schlick(1.0, 0.04))
    0.04
    >>> float(schlick(0.0, 0.04))
    1.0
    """
    dt = working_dtype(cos_theta)
    c = np.clip(_cosines("cos_theta", cos_theta), 0, 1).astype(dt)
    f0 = _param("f0", f0, "a scalar or RGB triple in [0, 1]", lambda a: (a >= 0) & (a <= 1)).astype(dt)
    _budget("cos_theta", c, f0)
    m = (1 - c) ** 5
    if f0.ndim:
        m = m[..., None]
    return (f0 + (1 - f0) * m).astype(dt, copy=False)


def dielectric(cos_theta_i, eta) -> np.ndarray:
    """Exact unpolarized Fresnel reflectance of a dielectric interface.

    ``eta = n_t / n_i`` is the relative index of refraction seen from the side
    the light arrives on.  With ``cos_theta_i < 0`` the light arrives from the
    other side, so ``eta`` is inverted and ``|cos|`` used.  Past the critical
    angle (``sin θ_t > 1``) the reflectance is 1 (total internal reflection).

        F = (r_par² + r_perp²) / 2,
        r_par  = (η cos θ_i − cos θ_t) / (η cos θ_i + cos θ_t),
        r_perp = (cos θ_i − η cos θ_t) / (cos θ_i + η cos θ_t).

    At normal incidence this is ``((η − 1) / (η + 1))²``.

    Parameters
    ----------
    cos_theta_i : array_like
        Cosines of the angle of incidence in [−1, 1] (rounding up to :data:`COS_SLACK` beyond is
        tolerated), any shape.
    eta : float or array_like, shape (3,)
        ``n_t / n_i``, finite and > 0: a scalar or an RGB triple.

    Returns
    -------
    ndarray
        ``F`` in [0, 1], of ``cos_theta_i``'s shape (plus a trailing axis 3 for a triple ``eta``),
        computed in float64 and returned in the float dtype of ``cos_theta_i``.

    Examples
    --------
    >>> round(float(dielectric(1.0, 1.5)), 6)
    0.04
    """
    dt = working_dtype(cos_theta_i)
    ci = _cosines("cos_theta_i", cos_theta_i)
    eta = _param("eta", eta, "a finite scalar or RGB triple > 0", lambda a: a > 0)
    _budget("cos_theta_i", ci, eta)
    if eta.ndim:
        ci = ci[..., None]
    big = np.finfo(np.float64).max
    with np.errstate(divide="ignore", over="ignore", under="ignore", invalid="ignore"):
        # Any finite η > 0 stays finite: 1/η of a subnormal η is clamped to the largest float
        # (then η c <= η and η c + c_t rounds to η: no overflow), and η² may overflow (sin²θ_t
        # is then 0, its limit) or underflow (inf: total internal reflection; 0/0 only at
        # normal incidence, where sin²θ_t is 0).
        eta = np.minimum(np.where(ci < 0, 1 / eta, eta), big)
        ci = np.abs(ci)
        # sin²θ_t from Snell's law; (1 - c)(1 + c) keeps 1 - cos² accurate near normal incidence.
        sin2_t = (1 - ci) * (1 + ci) / (eta * eta)
        sin2_t = np.where(np.isnan(sin2_t), 0.0, sin2_t)
        tir = sin2_t >= 1
        ct = np.sqrt(np.clip((1 - sin2_t), 0, None))
        d_par = eta * ci + ct
        d_perp = ci + eta * ct
        r_par = safe_div(eta * ci - ct, d_par)
        r_perp = safe_div(ci - eta * ct, d_perp)
        f = np.where(tir, 1.0, 0.5 * (r_par * r_par + r_perp * r_perp))
    return f.astype(dt, copy=False)


def conductor(cos_theta_i, eta, k) -> np.ndarray:
    """Exact unpolarized Fresnel reflectance of a conductor of complex relative index ``η + i k``.

    With ``ñ = η + i k`` and ``w = sqrt(ñ² − sin²θ_i)`` (the principal root: ``w = ñ cos θ_t``, whose
    real and imaginary parts are >= 0 for ``k >= 0``), the amplitude reflection coefficients are

        r_perp = (cos θ_i − w) / (cos θ_i + w),
        r_par  = (ñ² cos θ_i − w) / (ñ² cos θ_i + w),

    and ``F = (|r_par|² + |r_perp|²) / 2``.  At normal incidence
    ``F = ((η − 1)² + k²) / ((η + 1)² + k²)``; at grazing incidence ``F = 1``.  With ``k = 0`` this is
    :func:`dielectric` for light arriving from outside (``cos θ_i >= 0``).  A conductor is lit from
    outside only: ``cos_theta_i`` below 0 is taken as ``|cos θ_i|``.

    Written without dividing by ``ñ`` (``w`` instead of ``cos θ_t``), with the real part of ``ñ² − sin²θ_i``
    as ``(η − 1)(η + 1) − k² + cos²θ_i`` or ``η² − k² − (1 − cos θ_i)(1 + cos θ_i)``, whichever has the smaller
    terms, and with ``|x ∓ w|²`` in real arithmetic, so that the result stays accurate at grazing incidence
    for indices near 1 and at normal incidence for small ``η``.  From ``max(η, k) = 2^500`` on, where ``ñ²``
    could overflow, numerators and denominators are divided by ``ñ`` instead, so that a huge index keeps its
    pseudo-Brewster dip near ``cos θ_i = 1/|ñ|``.  The result is finite for any finite ``η > 0``,
    ``k >= 0``; where a coefficient is 0/0 or underflows, ``F`` takes its limit there, 1 (as
    :func:`dielectric` does at grazing incidence for ``η = 1``).

    Parameters
    ----------
    cos_theta_i : array_like
        Cosines of the angle of incidence in [−1, 1] (rounding up to :data:`COS_SLACK` beyond is
        tolerated), any shape.
    eta : float or array_like, shape (3,)
        The real part of the conductor's index relative to the outside medium, finite and > 0: a scalar
        or an RGB triple.
    k : float or array_like, shape (3,)
        The extinction coefficient (imaginary part), finite and >= 0: a scalar or an RGB triple.

    Returns
    -------
    ndarray
        ``F`` in [0, 1], of ``cos_theta_i``'s shape (plus a trailing axis 3 when ``eta`` or ``k`` is a
        triple), computed in float64 and returned in the float dtype of ``cos_theta_i``.

    References
    ----------
    M. Born and E. Wolf, *Principles of Optics*, 7th ed., Cambridge University Press, 1999, §14.2
    (reflection from an absorbing medium).

    Examples
    --------
    >>> round(float(conductor(1.0, 1.5, 0.0)), 6)   # the dielectric's F0
    0.04
    >>> round(float(conductor(1.0, 0.2, 3.0)), 6)   # ((0.2 - 1)^2 + 9) / ((0.2 + 1)^2 + 9)
    0.923372
    """
    dt = working_dtype(cos_theta_i)
    ci = np.abs(_cosines("cos_theta_i", cos_theta_i))
    eta = _param("eta", eta, "a finite scalar or RGB triple > 0", lambda a: a > 0)
    k = _param("k", k, "a finite scalar or RGB triple >= 0", lambda a: a >= 0)
    _budget("cos_theta_i", ci, eta if eta.ndim else k)
    with np.errstate(under="ignore"):  # a reflectance below float32's range rounds to 0
        return _conductor(ci, eta, k).astype(dt, copy=False)


def _conductor(c, eta, k) -> np.ndarray:
    """:func:`conductor` on checked arguments: cosines ``c`` in [0, 1] and float64 ``eta``, ``k`` of shape () or (3,).

    Float64 throughout; a trailing axis 3 when ``eta`` or ``k`` is a triple, computed one channel at a time
    (the complex temporaries of one channel only).  The models' shading path calls it without the checks.
    """
    c = np.asarray(c, dtype=np.float64)
    eta, k = np.asarray(eta, dtype=np.float64), np.asarray(k, dtype=np.float64)
    if eta.ndim or k.ndim:
        eta, k = np.broadcast_to(eta, (3,)), np.broadcast_to(k, (3,))
        return np.stack([_conductor(c, eta[i], k[i]) for i in range(3)], axis=-1)
    eta, k = float(eta), float(k)
    if max(eta, k) >= _HUGE_INDEX:
        return _conductor_huge(c, eta, k)
    with np.errstate(over="ignore", under="ignore", invalid="ignore", divide="ignore"):
        n = np.complex128(complex(eta, k))
        n2 = n * n
        # Re(ñ² − sin²θ_i) + k² = η² − sin²θ_i, from the two terms of smaller magnitude: (η − 1)(η + 1) + cos²θ_i
        # where η² and sin²θ_i are both near 1 (near grazing for indices near 1), η² − (1 − c)(1 + c) where
        # η² − 1 and cos²θ_i are (small η near normal incidence): each term is accurate, and the one sum
        # cancels at most as much as the value itself requires.
        s2 = (1 - c) * (1 + c)
        e2m1 = (eta - 1) * (eta + 1)
        re = np.where(abs(e2m1) + c * c <= eta * eta + s2, e2m1 + c * c, eta * eta - s2)
        w = np.sqrt((re - k * k) + 2j * eta * k)
        ar, ai = n2.real * c, n2.imag * c
        # |x − w|² / |x + w|² in real arithmetic: exactly 1 at grazing incidence (x = 0), no complex division.
        wr, wi = w.real, w.imag
        r_perp2 = ((c - wr) ** 2 + wi**2) / ((c + wr) ** 2 + wi**2)
        r_par2 = ((ar - wr) ** 2 + (ai - wi) ** 2) / ((ar + wr) ** 2 + (ai + wi) ** 2)
        f = 0.5 * (r_par2 + r_perp2)
        # Non-finite only where |ñ| is so large or small, or the incidence so grazing, that F's limit is 1.
        return np.where(np.isfinite(f), np.clip(f, 0, 1), 1.0)


#: From this ``max(η, k)`` on, ``ñ² cos θ`` may overflow: :func:`_conductor_huge` divides by ``ñ`` instead.
_HUGE_INDEX = 2.0**500


def _conductor_huge(c, eta: float, k: float) -> np.ndarray:
    """:func:`_conductor` for ``max(η, k) >= 2^500``, where ``ñ²`` would overflow (one channel, float64).

    Numerators and denominators divided by ``ñ``: ``r_perp = (c/ñ − cos θ_t)/(c/ñ + cos θ_t)``,
    ``r_par = (c − cos θ_t/ñ)/(c + cos θ_t/ñ)``, ``cos θ_t = sqrt(1 − sin²θ_i/ñ²)``: every term is at most
    about 2, so nothing overflows, and ``F`` keeps its value between grazing incidence and the
    pseudo-Brewster angle ``cos θ ≈ 1/|ñ|`` (``0.5`` there for a real index) instead of a blanket 1.
    """
    e = math.frexp(max(eta, k))[1]  # ñ 2^-e has its larger part in [1/2, 1): 1/ñ without overflow, exactly scaled
    with np.errstate(under="ignore"):  # 1/ñ, sin²θ/ñ² and products with 1/ñ may underflow to 0, their limit
        inv = np.ldexp(1.0, -e) / np.complex128(complex(math.ldexp(eta, -e), math.ldexp(k, -e)))
        ct = np.sqrt(1 - (1 - c) * (1 + c) * (inv * inv))
        a = c * inv
        b = ct * inv
        # Moduli (hypot) before squaring: c and |b| may be so small that their squares underflow.
        r_perp2 = (np.abs(a - ct) / np.abs(a + ct)) ** 2  # |a + ct| >= Re cos θ_t > 0
        num, den = np.abs(c - b), np.abs(c + b)
        # den is 0 only at grazing incidence (c = 0 and b underflowed): r_par's limit there is −1.
        r_par2 = np.where(den > 0, num / np.where(den > 0, den, 1.0), 1.0) ** 2
    return np.clip(0.5 * (r_par2 + r_perp2), 0, 1)


def conductor_f0(eta, k) -> np.ndarray:
    """A conductor's normal-incidence reflectance ``((η − 1)² + k²) / ((η + 1)² + k²)`` (float64).

    Parameters
    ----------
    eta : float or array_like, shape (3,)
        The real part of the index, finite and > 0: a scalar or an RGB triple.
    k : float or array_like, shape (3,)
        The extinction coefficient, finite and >= 0: a scalar or an RGB triple.

    Returns
    -------
    ndarray
        ``F0`` in [0, 1]: shape () for scalars, (3,) when either is a triple; equal to
        ``conductor(1.0, eta, k)``.

    Examples
    --------
    >>> round(float(conductor_f0(1.5, 0.0)), 6)
    0.04
    """
    eta = _param("eta", eta, "a finite scalar or RGB triple > 0", lambda a: a > 0)
    k = _param("k", k, "a finite scalar or RGB triple >= 0", lambda a: a >= 0)
    return _conductor(1.0, eta, k)


def _dielectric_from_f0(cos_theta_i, f0) -> np.ndarray:
    """:func:`dielectric` with ``η = (1 + g)/(1 − g)``, ``g = √F0``, for light arriving from outside.

    Multiplying numerators and denominators by ``1 − g`` removes ``η``:

        r_par  = ((1+g)² c − (1−g) c_t') / ((1+g)² c + (1−g) c_t'),
        r_perp = ((1−g) c − c_t') / ((1−g) c + c_t'),
        c_t'   = (1+g) cos θ_t = sqrt((1+g)² − (1 − c²)(1−g)²),

    so ``F0`` is reproduced exactly at normal incidence (``r = ±g``) instead of through
    a rounded ``η``, whose error the formula amplifies about fivefold at ``F0 = 0.04``.
    ``F0 = 1`` gives ``F = 1`` (the limit ``η → ∞``).  ``cos_theta_i`` in [0, 1]; the
    result has a trailing RGB axis when ``f0`` is a triple.  Float64 throughout.
    """
    c = np.clip(np.asarray(cos_theta_i, dtype=np.float64), 0, 1)
    g = np.sqrt(np.clip(np.asarray(f0, dtype=np.float64), 0, 1))
    if g.ndim:
        c = c[..., None]
    p, m = 1 + g, 1 - g
    ct = np.sqrt(np.maximum(p * p - (1 - c) * (1 + c) * (m * m), 0))  # (1+g) cos θ_t
    pc = p * p * c
    d_par = pc + m * ct
    d_perp = m * c + ct
    # c and g in [0, 1] keep every term below 5, and a zero denominator is replaced by 1: nothing to warn of.
    r_par = np.where(d_par > 0, (pc - m * ct) / np.where(d_par > 0, d_par, 1), 1)
    r_perp = np.where(d_perp > 0, (m * c - ct) / np.where(d_perp > 0, d_perp, 1), 1)
    return 0.5 * (r_par * r_par + r_perp * r_perp)


def f0_from_eta(eta):
    """Normal-incidence reflectance ``((η − 1)/(η + 1))²`` for ``η > 0`` (float64, any shape).

    Parameters
    ----------
    eta : float or array_like
        Relative indices of refraction, finite and > 0, any shape.

    Returns
    -------
    ndarray
        ``F0`` in [0, 1], float64, of ``eta``'s shape.

    Raises
    ------
    ValueError
        For an ``eta`` <= 0, NaN or infinite (``ArgumentTypeError`` for a wrong type).

    Examples
    --------
    >>> round(float(f0_from_eta(1.5)), 6)
    0.04
    """
    allowed = "finite real numbers > 0"
    eta = real_array("eta", eta, allowed=allowed, dtype=np.float64)
    if np.any(eta <= 0):
        raise ValueError(f"eta must be {allowed}; got {quote(eta)}")
    return ((eta - 1) / (eta + 1)) ** 2


def eta_from_f0(f0):
    """Inverse of :func:`f0_from_eta` on the branch ``η >= 1``: ``(1 + √F0)/(1 − √F0)``, for ``F0`` in [0, 1].

    ``F0 = 1`` (a perfect conductor in this approximation) maps to a very large η (2e12).

    Parameters
    ----------
    f0 : float or array_like
        Normal-incidence reflectances in [0, 1], any shape.

    Returns
    -------
    ndarray
        ``η >= 1``, float64, of ``f0``'s shape.

    Raises
    ------
    ValueError
        For an ``f0`` outside [0, 1], NaN or infinite (``ArgumentTypeError`` for a wrong type).

    Examples
    --------
    >>> round(float(eta_from_f0(0.04)), 6)
    1.5
    """
    allowed = "finite real numbers in [0, 1]"
    f0 = real_array("f0", f0, allowed=allowed, dtype=np.float64)
    if np.any((f0 < 0) | (f0 > 1)):
        raise ValueError(f"f0 must be {allowed}; got {quote(f0)}")
    s = np.sqrt(f0)
    return (1 + s) / np.maximum(1 - s, 1e-12)


# --------------------------------------------------------------------------- metals
#: The wavelengths (nm) at which a metal's complex index stands for the R, G and B channels: 630 nm inside the
#: red primary's band, 532 nm inside the green one's (where gold and copper have their absorption edge, so the
#: green channel decides their colour), 465 nm at the blue primary's dominant wavelength.  One wavelength per
#: channel is the usual renderer's shortcut for a spectral integral (it ignores how a metal's reflectance varies
#: within each primary's band).
METAL_WAVELENGTHS_NM = (630.0, 532.0, 465.0)

#: Rows ``(wavelength µm, n, k)`` of the published tables, copied unchanged: for each channel the two rows that
#: bracket its wavelength, from the refractiveindex.info database (public domain, CC0), files
#: ``database/data/main/<element>/nk/<file>.yml``.
_METAL_ROWS = {
    # Au/nk/Johnson.yml: Johnson and Christy (1972), room temperature.
    "gold": ((0.4509, 1.38, 1.914), (0.4714, 1.31, 1.849), (0.5209, 0.62, 2.081), (0.5486, 0.43, 2.455),
             (0.6168, 0.21, 3.272), (0.6595, 0.14, 3.697)),
    # Ag/nk/Johnson.yml: Johnson and Christy (1972), room temperature.
    "silver": ((0.4509, 0.04, 2.657), (0.4714, 0.05, 2.869), (0.5209, 0.05, 3.324), (0.5486, 0.06, 3.586),
               (0.6168, 0.06, 4.152), (0.6595, 0.05, 4.483)),
    # Cu/nk/Johnson.yml: Johnson and Christy (1972), room temperature.
    "copper": ((0.4509, 1.24, 2.397), (0.4714, 1.25, 2.483), (0.5209, 1.18, 2.608), (0.5486, 1.02, 2.577),
               (0.6168, 0.30, 3.205), (0.6595, 0.22, 3.747)),
    # Al/nk/Rakic-LD.yml: Rakić et al. (1998), their Lorentz–Drude fit, as the database tabulates it.
    "aluminium": ((0.46228, 0.62844, 5.4574), (0.46614, 0.64104, 5.5033), (0.53236, 0.89038, 6.2655),
                  (0.53680, 0.90904, 6.3144), (0.62852, 1.3198, 7.2578), (0.63376, 1.3441, 7.3089)),
    # Cr/nk/Rakic-LD.yml: Rakić et al. (1998), their Lorentz–Drude fit, as the database tabulates it.
    "chromium": ((0.46306, 2.2460, 3.9282), (0.46562, 2.2659, 3.9404), (0.53167, 2.7680, 4.1856),
                 (0.53462, 2.7896, 4.1935), (0.62756, 3.4078, 4.3375), (0.63104, 3.4281, 4.3395)),
}  # fmt: skip

#: Where each metal's optical constants come from.
METAL_SOURCES = MappingProxyType({
    "gold": "P. B. Johnson and R. W. Christy, Phys. Rev. B 6, 4370 (1972)",
    "silver": "P. B. Johnson and R. W. Christy, Phys. Rev. B 6, 4370 (1972)",
    "copper": "P. B. Johnson and R. W. Christy, Phys. Rev. B 6, 4370 (1972)",
    "aluminium": "A. D. Rakić, A. B. Djurišić, J. M. Elazar and M. L. Majewski, Appl. Opt. 37, 5271 (1998), "
                 "Lorentz–Drude model",
    "chromium": "A. D. Rakić, A. B. Djurišić, J. M. Elazar and M. L. Majewski, Appl. Opt. 37, 5271 (1998), "
                "Lorentz–Drude model",
})  # fmt: skip


def _interpolated(rows) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """``(η_rgb, k_rgb)`` at :data:`METAL_WAVELENGTHS_NM`, linear in wavelength between the tabulated rows."""
    rows = np.array(rows, dtype=np.float64)
    wl = np.array(METAL_WAVELENGTHS_NM) / 1000.0
    eta = np.interp(wl, rows[:, 0], rows[:, 1])
    k = np.interp(wl, rows[:, 0], rows[:, 2])
    return tuple(float(x) for x in eta), tuple(float(x) for x in k)


#: Named metals: name → ``(η, k)``, each an RGB triple (R, G, B at :data:`METAL_WAVELENGTHS_NM`), the index
#: relative to air (taken as 1) interpolated linearly in wavelength in the tables of :data:`METAL_SOURCES`.
METALS = MappingProxyType({name: _interpolated(rows) for name, rows in _METAL_ROWS.items()})


def metal_index(name) -> tuple[np.ndarray, np.ndarray]:
    """A named metal's complex index ``(η, k)`` per RGB channel (:data:`METALS`).

    Parameters
    ----------
    name : str
        One of :data:`METALS` (``"gold"``, ``"silver"``, ``"copper"``, ``"aluminium"``, ``"chromium"``);
        case and surrounding blanks are ignored.

    Returns
    -------
    (ndarray, ndarray)
        ``η`` and ``k``, float64 arrays of shape (3,) (new arrays: the table stays as it is).

    Raises
    ------
    ValueError
        For any other name, naming the metals and the nearest one ("did you mean").

    Examples
    --------
    >>> eta, k = metal_index("gold")
    >>> conductor_f0(eta, k).round(3).tolist()
    [0.942, 0.704, 0.404]
    """
    return tuple(np.array(x) for x in METALS[_metal_name("metal", name)])


def _metal_name(param: str, value, allowed_extra: tuple = ()) -> str:
    """``value`` as a key of :data:`METALS` (or of ``allowed_extra``); a one-line ValueError with a suggestion."""
    choices = (*allowed_extra, *METALS)
    key = value.strip().lower().replace("_", "-") if isinstance(value, str) else None
    if key in choices:
        return key
    allowed = ", ".join(repr(c) for c in choices)
    if key is None:
        raise ArgumentTypeError(f"{param} must be one of {allowed}; got {type(value).__name__} {quote(value)}")
    near = difflib.get_close_matches(key, list(choices), n=1)
    hint = f" (did you mean {near[0]!r}?)" if near else ""
    raise ValueError(f"{param} must be one of {allowed}; got {quote(value)}{hint}")


#: The ``metal`` choices of the models: ``"none"`` (the index from ``eta`` and ``k``) or a named metal.
METAL_CHOICES = ("none", *METALS)


#: The parameters a model with ``fresnel="conductor"`` adds to its table (:class:`~lighting.models.protocol.Parameter`):
#: the index ``eta``, the extinction ``k`` and a named ``metal`` (one home for the models that offer a conductor).
CONDUCTOR_PARAMETERS = (
    Parameter("eta", "color", None, low_open=True, slider=(0.03, 4.0), log=True,
              description="conductor index, real part η (fresnel conductor); None: f0's η or the metal's"),
    Parameter("k", "color", None, slider=(0.0, 8.0),
              description="conductor index, extinction k (fresnel conductor); None: 0 or the metal's"),
    Parameter("metal", "choice", "none", choices=METAL_CHOICES,
              description="a metal's η and k (fresnel conductor): none, gold, silver, copper, aluminium, chromium"),
)  # fmt: skip


def _conductor_setup(fresnel: str, f0, eta, k, metal):
    """The Fresnel parameters of a model as used: ``(eta, k, metal, f0)``.

    ``fresnel`` other than ``"conductor"``: ``eta`` and ``k`` must be None and ``metal`` ``"none"`` (they would
    be ignored); the result is ``(None, None, "none", f0)``.  ``"conductor"``: a named metal gives its
    :data:`METALS` index (``eta`` and ``k`` must then be None), else ``eta`` (None: ``η`` of ``f0``,
    :func:`eta_from_f0`) and ``k`` (None: 0); the returned ``f0`` is the conductor's normal-incidence
    reflectance (:func:`conductor_f0`), RGB.  ``f0`` is the model's checked float64 colour.
    """
    metal = _metal_name("metal", metal, ("none",))
    if fresnel != "conductor":
        for name, value in (("eta", eta), ("k", k), ("metal", None if metal == "none" else metal)):
            if value is not None:
                raise ValueError(f"{name} applies to fresnel 'conductor' only; got {name}={quote(value)} with fresnel "
                                 f"{fresnel!r} (set fresnel='conductor', or leave {name} unset)")  # fmt: skip
        return None, None, "none", f0
    if metal != "none":
        if eta is not None or k is not None:
            given = ", ".join(f"{n}={quote(v)}" for n, v in (("eta", eta), ("k", k)) if v is not None)
            raise ValueError(f"metal={metal!r} sets eta and k; got {given} as well (give a metal, or eta and k)")
        e, kk = metal_index(metal)
    else:
        e = eta_from_f0(f0) if eta is None else _param("eta", eta, "a finite scalar or RGB triple > 0", lambda a: a > 0)
        kk = np.zeros(3) if k is None else _param("k", k, "a finite scalar or RGB triple >= 0", lambda a: a >= 0)
    e = np.array(np.broadcast_to(e, (3,)), dtype=np.float64)
    kk = np.array(np.broadcast_to(kk, (3,)), dtype=np.float64)
    return e, kk, metal, _conductor(1.0, e, kk)


def _conductor_table(model, plain: bool = True) -> dict:
    """The conductor's entries of a model's scene table (``to_dict``) or repr: ``{}``, ``{"metal": name}`` or
    ``{"eta": ..., "k": ...}`` (lists of floats when ``plain``, else the arrays)."""
    if model.fresnel != "conductor":
        return {}
    if model.metal != "none":
        return {"metal": model.metal}
    if plain:
        return {"eta": [float(x) for x in model.eta], "k": [float(x) for x in model.k]}
    return {"eta": model.eta, "k": model.k}
