"""Microfacet building blocks: normal distributions (D) and shadowing–masking (G).

A microfacet surface is a field of tiny mirrors whose normals ``h`` follow a
distribution ``D(h)``; ``G`` is the fraction of them that is neither shadowed
(light blocked) nor masked (view blocked).  Every NDF here is normalized so that
its projected area integrates to one:

    ∫_Ω D(h) (n·h) dω_h = 1.

Numerical care (the same rules as Mitsuba 3 and pbrt-v4, pushed further because
this engine must stay finite down to α = 1e-6 and at exact grazing):

* ``tan²θ`` is formed from the tangential part (``sin²θ / cos²θ``, with
  ``sin²θ = |n × h|²`` when the caller has it) and never as ``1/cos² − 1``,
  which cancels catastrophically at the lobe peak.
* GGX is written ``α² / (π (sin²θ + α² cos²θ)²)``: the denominator only vanishes
  where the true value is infinite, and there the result saturates.
* The computations run in float64 and are cast back to the input dtype,
  saturating at the type's largest finite value (a Beckmann lobe of α = 1e-6
  peaks at ``1/(π α²) ≈ 3.2e11``, which float32 holds).

Arguments: the public functions check theirs once, at the boundary — real,
finite, cosines in [−1, 1] and squared sines in [0, 1] (rounding up to
:data:`COS_SLACK` beyond is clamped), α > 0, exponents >= 0, shapes that
broadcast, a result within the memory budget — and raise ``ValueError``
(``ArgumentTypeError``, also a ``TypeError``, for a wrong type) naming the
argument.  The reflectance models call the unchecked ``_`` variants
(:func:`_beckmann_ndf` …) on values they have already checked, so the
renderer's inner loop does not pay for it.

References: Beckmann & Spizzichino (1963); Cook & Torrance (1982); Walter,
Marschner, Li & Torrance, "Microfacet Models for Refraction through Rough
Surfaces" (EGSR 2007), eqs. 27 and 33 for Smith G1.
"""

from __future__ import annotations

import math

import numpy as np

from .._budget import check_budget
from .._text import quote
from .._validate import real_array
from ..numerics import safe_div, working_dtype

__all__ = [
    "beckmann_ndf",
    "ggx_ndf",
    "blinn_phong_ndf",
    "blinn_phong_exponent",
    "smith_g1_beckmann",
    "smith_g1_ggx",
    "smith_lambda_beckmann",
    "smith_lambda_ggx",
    "vcavity_g",
    "check_alpha",
]

_EXP_CUTOFF = 745.0  # exp(-745) is the last nonzero float64


def check_alpha(alpha, name: str = "alpha") -> np.ndarray:
    """Validate a roughness α (scalar or array): real, finite and > 0; returns it as float64.

    Raises ``ArgumentTypeError`` (a ``TypeError`` and ``ValueError``) for text, complex, booleans
    or ``None``, and ``ValueError`` for NaN, infinities or values <= 0, naming ``name``.

    Parameters
    ----------
    alpha : float or array_like
        Roughness values, any shape.
    name : str, optional
        The parameter's name, for the error message (default ``"alpha"``).

    Returns
    -------
    ndarray
        ``alpha`` as float64, same shape (0-d for a scalar).
    """
    allowed = "a finite number > 0 (the roughness α), or an array of them"
    a = real_array(name, alpha, allowed=allowed, dtype=np.float64)
    if np.any(a <= 0):
        raise ValueError(f"{name} must be {allowed}; got {quote(alpha)}")
    return a


#: How far beyond [−1, 1] a cosine (and beyond [0, 1] a squared sine) may stray by rounding; such
#: values are clamped into the range, anything further is refused.
COS_SLACK = 1e-6

#: Peak bytes per output element of one public call (float64 temporaries), for the memory budget.
_BYTES_PER_ELEMENT = 16 * 8


def _public(name_values: dict, *, ranges: dict, scalars: tuple = (),
            optional: tuple = ("sin2_theta_h", "sin2_theta")) -> tuple[type, list[np.ndarray]]:
    """Check the arguments of a public function once, at the boundary: ``(dtype, float64 arrays)``.

    ``name_values`` maps each parameter's name to its value (None for an omitted ``optional`` one);
    ``ranges[name] = (lo, hi)`` gives a closed range that rounding may overstep by
    :data:`COS_SLACK` (clamped), and ``scalars`` the parameters that are validated elsewhere
    (roughness, exponent) but broadcast with the rest.  The dtype is the working dtype of the
    values in ``ranges`` (the directions' cosines), as the dtype policy asks.
    """
    dt = working_dtype(*(v for k, v in name_values.items() if k in ranges and v is not None))
    out = []
    for name, value in name_values.items():
        if (value is None and name in optional) or name in scalars:
            out.append(value)
            continue
        lo, hi = ranges[name]
        allowed = f"finite real numbers in [{lo:g}, {hi:g}]"
        arr = real_array(name, value, allowed=allowed, dtype=np.float64)
        if arr.size and (np.min(arr) < lo - COS_SLACK or np.max(arr) > hi + COS_SLACK):
            bad = arr[(arr < lo - COS_SLACK) | (arr > hi + COS_SLACK)]
            raise ValueError(f"{name} must be {allowed}; got {quote(bad.flat[0])} in {quote(value)}")
        out.append(np.clip(arr, lo, hi))
    shapes = [np.shape(x) for x in out if x is not None]
    try:
        shape = np.broadcast_shapes(*shapes)
    except ValueError:
        names = ", ".join(k for k, v in name_values.items() if v is not None)
        raise ValueError(f"{names} must broadcast together; got shapes {', '.join(map(str, shapes))}") from None
    check_budget(", ".join(k for k in name_values if k not in scalars), math.prod(shape) * _BYTES_PER_ELEMENT,
                 what=f"{math.prod(shape)} values")
    return dt, out


def _cos_sin2(cos_theta, sin2_theta):
    c = np.asarray(cos_theta, dtype=np.float64)
    if sin2_theta is None:
        cc = np.clip(c, -1.0, 1.0)
        s2 = (1.0 - cc) * (1.0 + cc)
    else:
        s2 = np.clip(np.asarray(sin2_theta, dtype=np.float64), 0.0, 1.0)
    return c, s2


def _finish(x: np.ndarray, dt) -> np.ndarray:
    big = float(np.finfo(dt).max)
    if not np.isfinite(x).all():  # one pass where every value is finite (the usual case), four otherwise
        x = np.nan_to_num(x, nan=0.0, posinf=big, neginf=0.0)
    return np.minimum(x, big).astype(dt)


_COS = (-1.0, 1.0)
_SIN2 = (0.0, 1.0)


def beckmann_ndf(cos_theta_h, alpha, sin2_theta_h=None) -> np.ndarray:
    """Beckmann distribution of microfacet normals (Gaussian slopes).

        D(h) = exp(−tan²θ_h / α²) / (π α² cos⁴θ_h),   0 for cos θ_h <= 0.

    Parameters
    ----------
    cos_theta_h : array_like
        ``n·h``, in [−1, 1] (rounding up to :data:`COS_SLACK` beyond is clamped).
    alpha : float or array_like
        RMS slope α > 0 (the ``roughness`` of :class:`lighting.models.brdf.CookTorrance`).
    sin2_theta_h : array_like, optional
        ``|n × h|²`` in [0, 1]; pass it when available for full accuracy near the peak.

    Returns
    -------
    ndarray
        ``D`` in 1/sr, dtype of ``cos_theta_h``, finite (saturated at the dtype's largest value).

    Raises
    ------
    ValueError
        (``ArgumentTypeError`` for a wrong type) naming the argument that is not allowed.

    References
    ----------
    P. Beckmann and A. Spizzichino, *The Scattering of Electromagnetic Waves from Rough
    Surfaces*, Pergamon, 1963; R. L. Cook and K. E. Torrance, "A reflectance model for
    computer graphics", ACM TOG 1(1), 1982.

    Examples
    --------
    >>> round(float(beckmann_ndf(1.0, 0.5)), 6)  # peak value 1/(π α²)
    1.27324
    """
    a = check_alpha(alpha)
    dt, (c, s2, _) = _public({"cos_theta_h": cos_theta_h, "sin2_theta_h": sin2_theta_h, "alpha": a},
                             ranges={"cos_theta_h": _COS, "sin2_theta_h": _SIN2}, scalars=("alpha",))
    return _beckmann_ndf(c, a, s2, dt)


def _beckmann_ndf(cos_theta_h, a, sin2_theta_h, dt) -> np.ndarray:
    """:func:`beckmann_ndf` on checked arguments (``a`` a float64 α > 0): the renderer's path."""
    c, s2 = _cos_sin2(cos_theta_h, sin2_theta_h)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore", under="ignore"):
        # x = tan²θ / α² = sin²θ / (α cos θ)²; inf where the cosine is tiny.
        ac = a * c
        x = np.where(ac > 0, s2 / (ac * ac), np.inf)
        xc = np.minimum(x, _EXP_CUTOFF)
        t = a * a * xc  # tan²θ, so that 1/cos⁴θ = (1 + tan²θ)²
        d = np.exp(-xc) * (1.0 + t) ** 2 / (math.pi * a * a)
        d = np.where((c > 0) & (x < _EXP_CUTOFF), d, 0.0)
    return _finish(d, dt)


def ggx_ndf(cos_theta_h, alpha, sin2_theta_h=None) -> np.ndarray:
    """GGX / Trowbridge–Reitz distribution.

        D(h) = α² / (π (sin²θ_h + α² cos²θ_h)²)
             = 1 / (π α² cos⁴θ_h (1 + tan²θ_h / α²)²),   0 for cos θ_h <= 0.

    Arguments, result and errors as :func:`beckmann_ndf`.

    Parameters
    ----------
    cos_theta_h : array_like
        ``n·h``, in [−1, 1] (rounding up to :data:`COS_SLACK` beyond is clamped).
    alpha : float or array_like
        Roughness α > 0.
    sin2_theta_h : array_like, optional
        ``|n × h|²`` in [0, 1]; pass it when available for full accuracy near the peak.

    Returns
    -------
    ndarray
        ``D`` >= 0 in 1/sr (0 for ``cos θ_h <= 0``), of the broadcast shape of the arguments, in the float dtype
        of ``cos_theta_h`` and ``sin2_theta_h`` (float64 for Python numbers); finite (saturated at the dtype's
        largest value).

    References
    ----------
    B. Walter, S. R. Marschner, H. Li and K. E. Torrance, "Microfacet models for refraction
    through rough surfaces", EGSR 2007 (eq. 33); T. S. Trowbridge and K. P. Reitz, "Average
    irregularity representation of a rough surface for ray reflection", JOSA 65(5), 1975.

    Examples
    --------
    >>> round(float(ggx_ndf(1.0, 0.5)), 6)  # peak value 1/(π α²)
    1.27324
    """
    a = check_alpha(alpha)
    dt, (c, s2, _) = _public({"cos_theta_h": cos_theta_h, "sin2_theta_h": sin2_theta_h, "alpha": a},
                             ranges={"cos_theta_h": _COS, "sin2_theta_h": _SIN2}, scalars=("alpha",))
    return _ggx_ndf(c, a, s2, dt)


def _ggx_ndf(cos_theta_h, a, sin2_theta_h, dt) -> np.ndarray:
    """:func:`ggx_ndf` on checked arguments."""
    c, s2 = _cos_sin2(cos_theta_h, sin2_theta_h)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore", under="ignore"):
        den = s2 + (a * c) ** 2
        d = np.where(den > 0, (a * a) / (math.pi * den * den), np.inf)
        d = np.where(c > 0, d, 0.0)
    return _finish(d, dt)


def blinn_phong_exponent(alpha) -> np.ndarray:
    """Blinn–Phong exponent equivalent to a Beckmann α: ``e = 2/α² − 2`` (Walter et al. 2007, eq. 30).

    Clamped at 0 for α >= 1 (the flattest Blinn–Phong lobe is ``e = 0``), and at the largest
    float64 for α below 1e-154 (where ``2/α²`` overflows).

    Parameters
    ----------
    alpha : float or array_like
        Beckmann roughness α > 0, any shape.

    Returns
    -------
    ndarray
        ``e >= 0``, float64, of ``alpha``'s shape.

    Raises
    ------
    ValueError
        As :func:`check_alpha`.

    Examples
    --------
    >>> float(blinn_phong_exponent(0.5))
    6.0
    """
    a = check_alpha(alpha)
    with np.errstate(over="ignore"):
        e = 2.0 / (a * a) - 2.0
    return np.clip(e, 0.0, np.finfo(np.float64).max)


def blinn_phong_ndf(cos_theta_h, exponent, sin2_theta_h=None) -> np.ndarray:
    """The slides' normalized Blinn–Phong distribution ``D(h) = (e+2)/(2π) (n·h)^e``.

    ``(n·h)^e`` is evaluated as ``exp(e·log1p(−(1 − n·h)))`` with
    ``1 − n·h = sin²θ_h / (1 + cos θ_h)``, accurate for exponents up to 1e6 and
    beyond; ``0^0 = 1``.  ``exponent`` is a finite number >= 0 (or an array of
    them); the other arguments, the result and the errors are as for
    :func:`beckmann_ndf`.

    Parameters
    ----------
    cos_theta_h : array_like
        ``n·h``, in [−1, 1] (rounding up to :data:`COS_SLACK` beyond is clamped).
    exponent : float or array_like
        ``e``, finite and >= 0.
    sin2_theta_h : array_like, optional
        ``|n × h|²`` in [0, 1]; pass it when available for full accuracy near the peak.

    Returns
    -------
    ndarray
        ``D`` >= 0 in 1/sr (0 for ``cos θ_h <= 0``), of the broadcast shape of the arguments, in the float dtype
        of ``cos_theta_h`` and ``sin2_theta_h`` (float64 for Python numbers); finite (saturated at the dtype's
        largest value).

    Examples
    --------
    >>> round(float(blinn_phong_ndf(1.0, 10.0)), 6)  # (e+2)/(2π)
    1.909859
    """
    allowed = "a finite number >= 0 (the Blinn–Phong exponent), or an array of them"
    e = real_array("exponent", exponent, allowed=allowed, dtype=np.float64)
    if np.any(e < 0):
        raise ValueError(f"exponent must be {allowed}; got {quote(exponent)}")
    dt, (c, s2, _) = _public({"cos_theta_h": cos_theta_h, "sin2_theta_h": sin2_theta_h, "exponent": e},
                             ranges={"cos_theta_h": _COS, "sin2_theta_h": _SIN2}, scalars=("exponent",))
    return _blinn_phong_ndf(c, e, s2, dt)


def _blinn_phong_ndf(cos_theta_h, e, sin2_theta_h, dt) -> np.ndarray:
    """:func:`blinn_phong_ndf` on checked arguments (``e`` float64 >= 0)."""
    c, s2 = _cos_sin2(cos_theta_h, sin2_theta_h)
    cp = np.maximum(c, 0.0)
    one_minus = np.where(c > 0, s2 / (1.0 + cp), 1.0)
    with np.errstate(divide="ignore", over="ignore", under="ignore", invalid="ignore"):
        p = np.exp(e * np.log1p(-np.minimum(one_minus, 1.0)))
        # Far from the peak the cosine itself is the accurate input (1 − cos loses its digits).
        p = np.where(cp < 0.5, np.power(cp, e), p)
        p = np.where(one_minus < 1, p, np.where(e == 0, 1.0, 0.0))
        d = np.where(c > 0, (e + 2) / (2 * math.pi) * p, 0.0)
    return _finish(d, dt)


def _erf(x: np.ndarray) -> np.ndarray:
    # SciPy is imported here, not at module load: ``import lighting`` stays NumPy-only.
    from scipy.special import erf

    return erf(x)


def smith_g1_beckmann(cos_theta, alpha, sin2_theta=None) -> np.ndarray:
    """Smith masking for the Beckmann NDF, exact (error-function) form.

        a = 1 / (α tan θ),   G1 = 2 / (1 + erf(a) + exp(−a²) / (a √π)).

    Evaluated as ``2a√π / (a√π (1 + erf a) + exp(−a²))``, which has no division by
    ``a`` and tends to 0 at grazing (``a → 0``) and to 1 at the normal.
    ``cos_theta`` in [−1, 1], ``sin2_theta`` (optional, ``|n × ω|²``) in [0, 1];
    errors as :func:`beckmann_ndf`.

    Parameters
    ----------
    cos_theta : array_like
        ``n·ω`` of the view or light direction ``ω``, in [−1, 1] (rounding up to :data:`COS_SLACK`
        beyond is clamped).
    alpha : float or array_like
        Beckmann roughness α > 0.
    sin2_theta : array_like, optional
        ``|n × ω|²`` in [0, 1]; by default formed from ``cos_theta``.

    Returns
    -------
    ndarray
        ``G1`` in [0, 1] (0 for ``cos θ <= 0``), of the broadcast shape of the arguments, in the float dtype of
        ``cos_theta`` and ``sin2_theta`` (float64 for Python numbers).

    References
    ----------
    B. G. Smith, "Geometrical shadowing of a random rough surface", IEEE Transactions on
    Antennas and Propagation 15(5), 1967; Walter et al., EGSR 2007 (eq. 27); E. Heitz,
    "Understanding the masking-shadowing function in microfacet-based BRDFs", JCGT 3(2), 2014.

    Examples
    --------
    >>> float(smith_g1_beckmann(1.0, 0.3))
    1.0
    """
    al = check_alpha(alpha)
    dt, (c, s2, _) = _public({"cos_theta": cos_theta, "sin2_theta": sin2_theta, "alpha": al},
                             ranges={"cos_theta": _COS, "sin2_theta": _SIN2}, scalars=("alpha",))
    return _smith_g1_beckmann(c, al, s2, dt)


def _smith_g1_beckmann(cos_theta, al, sin2_theta, dt) -> np.ndarray:
    """:func:`smith_g1_beckmann` on checked arguments."""
    c, s2 = _cos_sin2(cos_theta, sin2_theta)
    s = np.sqrt(s2)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        a = np.where(al * s > 0, c / (al * s), np.inf)
    a = np.clip(a, 0.0, 1e8)  # below the horizon G1 is 0; G1 = 1 to double precision long before 1e8
    sp = math.sqrt(math.pi)
    with np.errstate(under="ignore"):
        g = 2 * a * sp / (a * sp * (1 + _erf(a)) + np.exp(-a * a))
    g = np.where(c > 0, np.minimum(g, 1.0), 0.0)
    return _finish(g, dt)


def smith_g1_ggx(cos_theta, alpha, sin2_theta=None) -> np.ndarray:
    """Smith masking for GGX: ``G1 = 2 / (1 + sqrt(1 + α² tan²θ))``.

    Evaluated as ``2 cos θ / (cos θ + hypot(cos θ, α sin θ))`` (no ``tan``, no
    overflow at grazing).  Arguments and errors as :func:`smith_g1_beckmann`.

    Parameters
    ----------
    cos_theta : array_like
        ``n·ω`` of the view or light direction ``ω``, in [−1, 1] (rounding up to :data:`COS_SLACK`
        beyond is clamped).
    alpha : float or array_like
        GGX roughness α > 0.
    sin2_theta : array_like, optional
        ``|n × ω|²`` in [0, 1]; by default formed from ``cos_theta``.

    Returns
    -------
    ndarray
        ``G1`` in [0, 1] (0 for ``cos θ <= 0``), of the broadcast shape of the arguments, in the float dtype of
        ``cos_theta`` and ``sin2_theta`` (float64 for Python numbers).

    References
    ----------
    Walter et al., EGSR 2007 (eq. 34); E. Heitz, "Understanding the masking-shadowing
    function in microfacet-based BRDFs", JCGT 3(2), 2014 (Λ and the height-correlated form).

    Examples
    --------
    >>> float(smith_g1_ggx(1.0, 0.3))
    1.0
    """
    al = check_alpha(alpha)
    dt, (c, s2, _) = _public({"cos_theta": cos_theta, "sin2_theta": sin2_theta, "alpha": al},
                             ranges={"cos_theta": _COS, "sin2_theta": _SIN2}, scalars=("alpha",))
    return _smith_g1_ggx(c, al, s2, dt)


def _smith_g1_ggx(cos_theta, al, sin2_theta, dt) -> np.ndarray:
    """:func:`smith_g1_ggx` on checked arguments."""
    c, s2 = _cos_sin2(cos_theta, sin2_theta)
    s = np.sqrt(s2)
    cp = np.maximum(c, 0.0)
    with np.errstate(over="ignore", under="ignore"):
        den = cp + np.hypot(cp, al * s)
    g = safe_div(2 * cp, den)
    g = np.where(c > 0, g, 0.0)
    return _finish(g, dt)


_INV_SQRT_PI = 0.5641895835477563  # 1/√π, correctly rounded


def _smith_g1_den_beckmann(cos_theta, alpha, sin2_theta) -> np.ndarray:
    """``d`` with ``G1 = 2 cos θ / d`` for Beckmann (float64): ``d = cos θ (1 + erf a) + (α sin θ/√π) exp(−a²)``.

    ``a = cos θ / (α sin θ)``.  ``G1 / cos θ = 2 / d`` is then free of the division of
    a small ``G1`` by a small cosine at grazing (where it tends to ``2√π/α``), and
    ``d → 2 cos θ`` at the normal.  ``d`` is 1 (a placeholder) where ``cos θ <= 0``.
    """
    al = float(alpha)  # internal: the model checked it once
    c, s2 = _cos_sin2(cos_theta, sin2_theta)
    s = np.sqrt(s2)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore", under="ignore"):
        a = np.clip(np.where(al * s > 0, c / (al * s), np.inf), 0.0, 1e8)
        d = c * (1 + _erf(a)) + (al * _INV_SQRT_PI) * s * np.exp(-a * a)
    return np.where((c > 0) & (d > 0), d, 1.0)


def _smith_g1_den_ggx(cos_theta, alpha, sin2_theta) -> np.ndarray:
    """``d`` with ``G1 = 2 cos θ / d`` for GGX (float64): ``d = cos θ + sqrt(cos²θ + α² sin²θ)``."""
    al = float(alpha)  # internal: the model checked it once
    c, s2 = _cos_sin2(cos_theta, sin2_theta)
    cp = np.maximum(c, 0.0)
    d = cp + np.hypot(cp, al * np.sqrt(s2))
    return np.where((c > 0) & (d > 0), d, 1.0)


#: Below this ``a = cos θ / (α sin θ)`` the Beckmann Λ is formed directly; above it by Laplace's continued fraction.
_LAMBDA_CF_FROM = 2.0
_LAMBDA_CF_TERMS = 48


def _beckmann_lambda_tail(a) -> np.ndarray:
    """``1 − a √π erfcx(a)`` for ``a >= 2`` (float64) without the cancellation of the two terms.

    Laplace's continued fraction ``√π erfcx(a) = 1/(a + (1/2)/(a + 1/(a + (3/2)/(a + …))))`` gives
    ``√π erfcx(a) = 1/(a + K)`` with ``K = (1/2)/(a + 1/(a + …))``, so ``1 − a √π erfcx(a) = K/(a + K)``
    (≈ ``1/(2a²)``).  48 terms converge to float64 rounding for ``a >= 2``.
    """
    k = np.zeros_like(a)
    ak = np.empty_like(k)
    for j in range(_LAMBDA_CF_TERMS, 0, -1):  # k = (j/2) / (a + k), without new arrays per term
        np.add(a, k, out=ak)
        np.divide(j / 2, ak, out=k)
    return k / (a + k)


def _smith_lambda_cos_beckmann(cos_theta, alpha, sin2_theta) -> np.ndarray:
    """``Λ(θ) cos θ`` for Beckmann (float64), finite from the normal (0) to the horizon (``α/(2√π)``).

    ``Λ = (erf(a) − 1)/2 + exp(−a²)/(2 a √π)``, ``a = cos θ / (α sin θ)``, times ``cos θ``:

        Λ cos θ = (α sin θ exp(−a²)/√π − cos θ erfc(a)) / 2             (a < 2)
                = (α sin θ exp(−a²) / (2√π)) (1 − a √π erfcx(a))      (a >= 2, continued fraction)

    The second form avoids the cancellation of the first, in which both terms are about
    ``exp(−a²)/a`` and their difference ``exp(−a²)/(2a³)``.  0 where ``cos θ <= 0`` (the caller masks).
    """
    from scipy.special import erfc

    al = np.asarray(alpha, dtype=np.float64)  # a float from the model, an array from the public function
    c, s2 = _cos_sin2(cos_theta, sin2_theta)
    s = np.sqrt(s2)
    cp = np.maximum(c, 0.0)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore", under="ignore"):
        a = np.clip(np.where(al * s > 0, cp / (al * s), np.inf), 0.0, 1e8)
        near = (al * _INV_SQRT_PI) * s * np.exp(-a * a)
        direct = (near - cp * erfc(a)) / 2
        # The continued fraction (48 passes) only where it is used.
        far = ~(a < _LAMBDA_CF_FROM)
        if np.ndim(far) == 0 or np.all(far):
            lc = np.where(far, near / 2 * _beckmann_lambda_tail(np.maximum(a, _LAMBDA_CF_FROM)), direct)
        else:
            lc = np.array(direct, dtype=np.float64)
            if np.any(far):
                lc[far] = near[far] / 2 * _beckmann_lambda_tail(a[far])
    return np.where(c > 0, np.maximum(lc, 0.0), 0.0)


def _smith_lambda_cos_ggx(cos_theta, alpha, sin2_theta) -> np.ndarray:
    """``Λ(θ) cos θ`` for GGX (float64): ``(sqrt(cos²θ + α² sin²θ) − cos θ)/2 = α² sin²θ / (2 (cos θ + sqrt(…)))``.

    The second form has no cancellation near the normal; at the horizon it tends to ``α sin θ / 2``.
    0 where ``cos θ <= 0`` (the caller masks).
    """
    al = np.asarray(alpha, dtype=np.float64)
    c, s2 = _cos_sin2(cos_theta, sin2_theta)
    cp = np.maximum(c, 0.0)
    with np.errstate(over="ignore", under="ignore", invalid="ignore", divide="ignore"):
        t = al * np.sqrt(s2)
        hyp = np.hypot(cp, t)
        lc = np.where(hyp > 0, t * (t / (2 * (cp + hyp))), 0.0)
    return np.where(c > 0, lc, 0.0)


def _smith_lambda(cos_theta, al, sin2_theta, dt, lambda_cos) -> np.ndarray:
    c, s2 = _cos_sin2(cos_theta, sin2_theta)
    lc = lambda_cos(c, al, s2)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        lam = np.where(c > 0, lc / np.where(c > 0, c, 1.0), np.inf)
    return _finish(lam, dt)


def smith_lambda_beckmann(cos_theta, alpha, sin2_theta=None) -> np.ndarray:
    """Smith's auxiliary function Λ for the Beckmann NDF (``G1 = 1 / (1 + Λ)``).

        a = 1 / (α tan θ),   Λ = (erf(a) − 1)/2 + exp(−a²) / (2 a √π).

    Evaluated as ``Λ cos θ`` (finite at the horizon) divided by ``cos θ``; for ``a >= 2`` through
    Laplace's continued fraction of ``erfc`` (no cancellation between the two terms), so Λ has full
    relative accuracy even where it is ``1e-300``.  Arguments and errors as :func:`smith_g1_beckmann`.

    Parameters
    ----------
    cos_theta : array_like
        ``n·ω`` in [−1, 1] (rounding up to :data:`COS_SLACK` beyond is clamped).
    alpha : float or array_like
        Beckmann roughness α > 0.
    sin2_theta : array_like, optional
        ``|n × ω|²`` in [0, 1]; by default formed from ``cos_theta``.

    Returns
    -------
    ndarray
        Λ >= 0 (0 at the normal, growing as ``α/(2√π cos θ)`` toward the horizon; the dtype's largest
        finite value for ``cos θ <= 0``, where ``G1 = 0``), in the float dtype of ``cos_theta``.

    References
    ----------
    E. Heitz, "Understanding the masking-shadowing function in microfacet-based BRDFs",
    Journal of Computer Graphics Techniques 3(2), 48–107, 2014 (eq. 72).

    Examples
    --------
    >>> float(smith_lambda_beckmann(1.0, 0.3))
    0.0
    """
    al = check_alpha(alpha)
    dt, (c, s2, _) = _public({"cos_theta": cos_theta, "sin2_theta": sin2_theta, "alpha": al},
                             ranges={"cos_theta": _COS, "sin2_theta": _SIN2}, scalars=("alpha",))
    return _smith_lambda(c, al, s2, dt, _smith_lambda_cos_beckmann)


def smith_lambda_ggx(cos_theta, alpha, sin2_theta=None) -> np.ndarray:
    """Smith's auxiliary function Λ for GGX (``G1 = 1 / (1 + Λ)``).

        Λ = (−1 + sqrt(1 + α² tan²θ)) / 2 = α² sin²θ / (2 cos θ (cos θ + sqrt(cos²θ + α² sin²θ))).

    The second form (no ``tan``, no cancellation near the normal) is the one evaluated.
    Arguments, result and errors as :func:`smith_lambda_beckmann`.

    Parameters
    ----------
    cos_theta : array_like
        ``n·ω`` in [−1, 1] (rounding up to :data:`COS_SLACK` beyond is clamped).
    alpha : float or array_like
        GGX roughness α > 0.
    sin2_theta : array_like, optional
        ``|n × ω|²`` in [0, 1]; by default formed from ``cos_theta``.

    Returns
    -------
    ndarray
        Λ >= 0, in the float dtype of ``cos_theta`` (the largest finite value for ``cos θ <= 0``).

    References
    ----------
    E. Heitz, "Understanding the masking-shadowing function in microfacet-based BRDFs",
    Journal of Computer Graphics Techniques 3(2), 48–107, 2014 (eq. 86).

    Examples
    --------
    >>> round(float(smith_lambda_ggx(0.5, 1.0)), 12)  # tan²θ = 3: (−1 + 2)/2
    0.5
    """
    al = check_alpha(alpha)
    dt, (c, s2, _) = _public({"cos_theta": cos_theta, "sin2_theta": sin2_theta, "alpha": al},
                             ranges={"cos_theta": _COS, "sin2_theta": _SIN2}, scalars=("alpha",))
    return _smith_lambda(c, al, s2, dt, _smith_lambda_cos_ggx)


# --------------------------------------------------------------------------- anisotropic (α_x, α_y)
def _aniso_slope2(x, y, z, ax, ay):
    """``tan²θ (cos²φ/α_x² + sin²φ/α_y²) = ((x/α_x)² + (y/α_y)²) / z²`` numerator: ``(x/α_x)² + (y/α_y)²`` (float64)."""
    x, y = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    with np.errstate(over="ignore", under="ignore"):
        return (x / ax) ** 2 + (y / ay) ** 2


def _ggx_ndf_aniso(x, y, z, ax, ay, dt) -> np.ndarray:
    """Anisotropic GGX from the local components ``(h·t, h·b, h·n)`` of a unit ``h``.

        D(h) = 1 / (π α_x α_y ((h·t/α_x)² + (h·b/α_y)² + (h·n)²)²),   0 for h·n <= 0,

    ``α_x`` along the tangent ``t``, ``α_y`` along the bitangent ``b``; with ``α_x = α_y = α`` it is
    the isotropic ``α² / (π (sin²θ + α² cos²θ)²)`` (the same value, another rounding).
    """
    z = np.asarray(z, dtype=np.float64)
    q = _aniso_slope2(x, y, z, ax, ay)
    with np.errstate(over="ignore", under="ignore", divide="ignore"):
        den = q + z * z
        d = np.where((z > 0) & (den > 0), 1 / (math.pi * ax * ay * np.where(den > 0, den, 1.0) ** 2), 0.0)
        d = np.where((z > 0) & (den == 0), np.inf, d)
    return _finish(d, dt)


def _beckmann_ndf_aniso(x, y, z, ax, ay, dt) -> np.ndarray:
    """Anisotropic Beckmann from the local components of a unit ``h``.

        D(h) = exp(−((h·t/α_x)² + (h·b/α_y)²) / (h·n)²) / (π α_x α_y (h·n)⁴),   0 for h·n <= 0,

    written as ``exp(−X) (1 + tan²θ)² / (π α_x α_y)`` with ``X`` the exponent and ``tan²θ`` from the
    tangential part (the isotropic function's form).
    """
    z = np.asarray(z, dtype=np.float64)
    q = _aniso_slope2(x, y, z, ax, ay)
    xx, yy = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore", under="ignore"):
        up = z > 0
        zz = np.where(up, z * z, 1.0)
        ex = np.where(up, q / zz, np.inf)
        t2 = np.where(up, (xx * xx + yy * yy) / zz, np.inf)
        # d = exp(−X) (1 + tan²θ)² / (π α_x α_y), X = min(ex, cutoff): the same operations in place
        # (out= keeps a 0-d result an array).
        d = np.minimum(ex, _EXP_CUTOFF, out=np.empty_like(ex))
        np.negative(d, out=d)
        np.exp(d, out=d)
        t2 += 1.0
        np.square(t2, out=t2)
        d *= t2
        d /= math.pi * ax * ay
        d = np.where(up & (ex < _EXP_CUTOFF) & np.isfinite(d), d, 0.0)
    return _finish(d, dt)


def _alpha_along(x, y, ax, ay):
    """``α(φ) = sqrt(cos²φ α_x² + sin²φ α_y²)`` of a direction with tangential components ``(x, y)`` (float64).

    Where the direction is the normal (``x = y = 0``, no azimuth) any value serves: ``α_x``.
    """
    x, y = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    with np.errstate(over="ignore", under="ignore", invalid="ignore", divide="ignore"):
        r = np.hypot(x, y)
        a = np.hypot(ax * x, ay * y) / np.where(r > 0, r, 1.0)
    return np.where(r > 0, a, ax)


def _smith_lambda_cos_aniso(ndf, x, y, z, ax, ay) -> np.ndarray:
    """``Λ cos θ`` (float64) of the anisotropic NDF for a unit direction with local components ``(x, y, z)``.

    Smith's Λ of a stretch-invariant NDF is the isotropic one with ``α(φ) = sqrt(cos²φ α_x² + sin²φ α_y²)``
    (Heitz 2014, sec. 5.2), i.e. ``α tan θ → sqrt((α_x x)² + (α_y y)²) / z``.
    """
    x, y = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    al = _alpha_along(x, y, ax, ay)
    s2 = np.clip(x * x + y * y, 0.0, 1.0)
    lam = _smith_lambda_cos_ggx if ndf == "ggx" else _smith_lambda_cos_beckmann
    return lam(z, al, s2)


def vcavity_g(n_dot_h, n_dot_v, n_dot_l, v_dot_h) -> np.ndarray:
    """Cook–Torrance shadowing/masking from symmetric V-shaped grooves.

        G = min(1, 2 (n·h)(n·v) / (v·h), 2 (n·h)(n·l) / (v·h)),

    0 where any cosine is <= 0 (``v·h = l·h`` by construction of ``h``).  Every
    argument is a cosine in [−1, 1]; errors as :func:`beckmann_ndf`.

    Parameters
    ----------
    n_dot_h, n_dot_v, n_dot_l, v_dot_h : array_like
        The four cosines, in [−1, 1] (rounding up to :data:`COS_SLACK` beyond is clamped),
        broadcasting together.

    Returns
    -------
    ndarray
        ``G`` in [0, 1], of the broadcast shape of the arguments, in the float dtype of the four cosines
        (float64 for Python numbers).

    References
    ----------
    R. L. Cook and K. E. Torrance, "A reflectance model for computer graphics", ACM TOG
    1(1), 1982 (after Torrance and Sparrow, 1967).

    Examples
    --------
    >>> float(vcavity_g(1.0, 1.0, 1.0, 1.0))
    1.0
    """
    names = {"n_dot_h": n_dot_h, "n_dot_v": n_dot_v, "n_dot_l": n_dot_l, "v_dot_h": v_dot_h}
    dt, arrays = _public(names, ranges=dict.fromkeys(names, _COS))
    return _vcavity_g(*arrays, dt=dt)


def _vcavity_g(n_dot_h, n_dot_v, n_dot_l, v_dot_h, dt=None) -> np.ndarray:
    """:func:`vcavity_g` on checked arguments (the dtype of the cosines unless ``dt`` is given)."""
    dt = dt or working_dtype(n_dot_h, n_dot_v, n_dot_l, v_dot_h)
    nh, nv, nl, vh = (np.asarray(x, dtype=np.float64) for x in (n_dot_h, n_dot_v, n_dot_l, v_dot_h))
    m = np.minimum(nv, nl)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore", under="ignore"):
        g = np.where(vh > 0, 2 * nh * m / np.where(vh > 0, vh, 1.0), 0.0)
    g = np.where((nh > 0) & (nv > 0) & (nl > 0), np.clip(g, 0.0, 1.0), 0.0)
    return _finish(g, dt)
