r"""Numerical stability of the shading formulas on stiff and extreme inputs.

Every model of :mod:`lighting.models.brdf` and the point and spot lights of
:mod:`lighting.lights.punctual` are evaluated, in float32 and in float64, on the inputs
where shading formulas go wrong — shininess up to 1e6, roughness down to 1e-6,
directions near the lobe peak, light and view within 1e-8 rad of the horizon,
``l = −v``, ``l = v = n``, zero and non-unit normals, point lights at distance
0, 1e-12 and 1e12, spot cutoffs 0, 90 and 180, huge and tiny intensities — and
each value is compared with a reference computed by mpmath at 80 significant
digits from **the same binary inputs** (the float32 or float64 vector
components, converted exactly).

The error measure and the bound
-------------------------------
For a value ``f`` whose true value is a normal number of the type::

    relative error  = |f_engine − f_true| / |f_true|
    bound           = 8 · max(κ, 1) · u,      u = 2^-24 (float32), 2^-53 (float64)

``κ`` is the componentwise relative condition number of the formula at that
point with respect to every input it is given: the nine vector components
(``n``, ``l``, ``v``; for lights the surface point, the light position and the
spot axis) and the model's shape parameters (shininess ``e``, roughness ``α``,
``f0``; for lights the falloff coefficients and the spot exponent)::

    κ = Σ_i max_± |f(x with x_i → x_i (1 ± δ)) − f(x)| / (|f(x)| δ),   δ = 1e-30,

evaluated in mpmath.  It is the worst-case amplification of simultaneous
relative perturbations of one unit each in every input: rounding the inputs to
the type already costs ``κ u``, so no algorithm can promise less.  A
shininess-1e6 lobe seen 1e-3 rad from its peak has ``κ ≈ 2000``; ``κ`` near 1
means the formula must be accurate to a few units in the last place.  The
parameters count because the engine must round functions of them (``α²``,
``π α²``, ``√f0``): one ulp of ``α`` is two ulps of a GGX peak ``1/(π α²)``.
The pure scale factors ``k_d``, ``k_s`` and the light intensity are left out
(``f`` is proportional to them).  Where ``8 κ u >= 1`` the linear bound allows
100 % and stops describing the error; there the same first-order statement is
applied to the logarithm, ``|ln(f_engine / f_true)| <= 8 κ u``.

Where the formula has a discontinuity — the horizon mask ``n·l > 0``, the
clamp ``max(R·v, 0)`` of Phong, the spot cone test — a point whose decision
flips under relative perturbations of ``8 u`` of its inputs is an *edge point*:
both sides are acceptable there, and only finiteness and sign are required.
Where the true value is zero (below the horizon, a zero normal, a point at the
light) the engine must return exactly 0; where it exceeds the type's largest
finite value the engine must return that value (saturation, never ``inf``);
where it underflows the normal range the engine may differ from it by at most
the smallest normal number.

The behaviour that must hold is checked too: no negative values; lobes
non-increasing away from their peak along sweeps of the viewing direction
(for every pair whose true difference exceeds the two error bounds);
reciprocity ``f(l, v) = f(v, l)`` within the sum of the two bounds for the
reciprocal models (Lambert, normalized Blinn–Phong, Cook–Torrance); falloff
non-increasing with distance and the spot factor with the angle from its axis.

:func:`run` computes it all; :mod:`explorer.report_stability` prints the table,
writes the CSV and draws the figure.  mpmath is imported inside the functions
that need it, so ``import lighting`` stays NumPy-only.
"""

from __future__ import annotations

import functools
import math
import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

__all__ = [
    "SHININESS",
    "ROUGHNESS",
    "BOUND_FACTOR",
    "REFERENCE_DPS",
    "CASE_FAMILIES",
    "LIGHT_CASE_FAMILIES",
    "unit_roundoff",
    "BrdfCase",
    "LightCase",
    "ModelSpec",
    "LightSpec",
    "SummaryRow",
    "StabilityResult",
    "brdf_cases",
    "light_cases",
    "brdf_specs",
    "light_specs",
    "reference_brdf",
    "reference_light",
    "run",
]

SHININESS = (0.0, 1.0, 1e2, 1e4, 1e6)
ROUGHNESS = (1.0, 0.1, 1e-3, 1e-6)
BOUND_FACTOR = 8.0
REFERENCE_DPS = 80
DELTA = 1e-30
KS = 1.0
KD = 1.0
F0 = 0.04

CASE_FAMILIES = ("generic", "lobe peak", "grazing l", "grazing v", "l = -v", "l = v = n", "normals")
LIGHT_CASE_FAMILIES = ("distance", "spot cone", "intensity")
BRDF_FORMS = ("eval", "eval_cos", "classic")
LIGHT_FORMS = ("scale", "irradiance")


def unit_roundoff(dtype) -> float:
    """``u`` of a float type: 2^-24 for float32, 2^-53 for float64."""
    return float(np.finfo(dtype).eps) / 2


# ============================================================================ cases
@dataclass(frozen=True)
class BrdfCase:
    """One ``(n, l, v)`` input, given as float64 components (rounded to the dtype when evaluated).

    ``sweep`` names the sweep this point belongs to (``""`` for none) and
    ``step`` its position: the true lobe value decreases with ``step``.
    """

    family: str
    label: str
    n: tuple
    l: tuple
    v: tuple
    sweep: str = ""
    step: int = 0


@dataclass(frozen=True)
class LightCase:
    """A surface point lit by light spec ``spec`` (an index into :func:`light_specs`)."""

    family: str
    label: str
    spec: int
    point: tuple
    sweep: str = ""
    step: int = 0


def _frame(n):
    """Orthonormal ``(t, b, n̂)`` in float64 around the raw normal ``n``."""
    n = np.asarray(n, dtype=np.float64)
    nh = n / np.linalg.norm(n)
    a = np.array([1.0, 0.0, 0.0]) if abs(nh[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    t = a - nh * (a @ nh)
    t /= np.linalg.norm(t)
    return t, np.cross(nh, t), nh


def _direction(n, theta, phi=0.0, scale=1.0):
    """Direction at polar angle ``theta`` from the raw normal ``n`` (azimuth ``phi``), times ``scale``."""
    t, b, nh = _frame(n)
    d = math.sin(theta) * (math.cos(phi) * t + math.sin(phi) * b) + math.cos(theta) * nh
    if np.array_equal(nh, [0.0, 0.0, 1.0]):  # exact components in the canonical frame
        d = np.array([math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)])
    return tuple(float(x) for x in d * scale)


def _grazing(n, eps, phi=0.0):
    """Direction ``eps`` rad above the horizon of ``n`` (``sin eps`` and ``cos eps`` computed directly)."""
    t, b, nh = _frame(n)
    if np.array_equal(nh, [0.0, 0.0, 1.0]):
        return (math.cos(eps) * math.cos(phi), math.cos(eps) * math.sin(phi), math.sin(eps))
    d = math.cos(eps) * (math.cos(phi) * t + math.sin(phi) * b) + math.sin(eps) * nh
    return tuple(float(x) for x in d)


N_AXIS = (0.0, 0.0, 1.0)
N_TILT = (0.3, -0.5, 0.81)  # generic, not unit length


def brdf_cases(quick: bool = False) -> list[BrdfCase]:
    """The ``(n, l, v)`` inputs of the sweep, grouped by case family (see :data:`CASE_FAMILIES`)."""
    cases: list[BrdfCase] = []
    normals = (N_AXIS, N_TILT)

    # Generic directions: the baseline.
    for ni, n in enumerate(normals):
        pairs = [(0.2, 0.0, 0.7, 2.0), (1.2, -1.0, 0.4, 1.5), (0.5, 0.0, 0.5, math.pi)]
        if not quick:
            pairs.append((0.7, 0.3, 1.2, 2.9))
            pairs += [(0.9, 0.1, 0.9, 3.0), (1.4, 0.0, 0.1, 0.7), (0.3, 2.0, 1.3, -2.0), (1.0, 0.0, 1.0, 1.0)]
        for tl, pl, tv, pv in pairs:
            cases.append(BrdfCase("generic", f"n{ni} θl={tl} θv={tv}", n, _direction(n, tl, pl), _direction(n, tv, pv)))

    # Near the lobe peak: v swept away from the mirror direction R_l by offsets t·s,
    # s = 1/√e (Phong/Blinn–Phong exponents) or s = α (microfacet roughness).
    scales = [(f"1/√{e:g}", 1 / math.sqrt(e)) for e in (1e2, 1e4, 1e6)] + [(f"α={a:g}", a) for a in (0.1, 1e-3, 1e-6)]
    steps = (0.0, 1.0, 2.0, 4.0) if quick else (0.0, 0.25, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0)
    thetas = (1.0,) if quick else (0.4, 1.0)
    planes = ("in",) if quick else ("in", "out")
    for ni, n in enumerate(normals):
        for tl in thetas:
            l = _direction(n, tl, 0.0)  # noqa: E741
            for sname, s in scales:
                for plane in planes:
                    sweep = f"n{ni} θl={tl} {plane}-plane s={sname}"
                    for k, t in enumerate(steps):
                        o = t * s
                        v = (
                            _direction(n, tl - o, math.pi)
                            if plane == "in"
                            else _direction(n, tl, math.pi + o / math.sin(tl))
                        )
                        cases.append(BrdfCase("lobe peak", f"{sweep} t={t}", n, l, v, sweep, k))

    # Grazing light (and, symmetrically, grazing view) down to 1e-8 rad above the horizon.
    epsilons = (1e-2, 1e-4, 1e-6, 1e-8) if not quick else (1e-4, 1e-8)
    for ni, n in enumerate(normals):
        for eps in epsilons:
            g = _grazing(n, eps, 0.0)
            others = {
                "θ=0.5": _direction(n, 0.5, math.pi),
                "θ=1.2 φ=2": _direction(n, 1.2, 2.0),
                "mirror": _grazing(n, eps, math.pi),
                "mirror+1e-3": _grazing(n, eps + 1e-3, math.pi),
            }
            if quick:
                others.pop("θ=1.2 φ=2")
            for lab, o in others.items():
                cases.append(BrdfCase("grazing l", f"n{ni} l at {eps:g} rad, v {lab}", n, g, o))
                cases.append(BrdfCase("grazing v", f"n{ni} v at {eps:g} rad, l {lab}", n, o, g))
        for lab, eps in (("on", 0.0), ("below", -1e-8)):
            g = _grazing(n, eps, 0.0)
            o = _direction(n, 0.5, math.pi)
            cases.append(BrdfCase("grazing l", f"n{ni} l {lab} the horizon", n, g, o))
            cases.append(BrdfCase("grazing v", f"n{ni} v {lab} the horizon", n, o, g))

    # l = −v exactly (one of them is below the horizon, or both on it), and nearly so with both just above.
    for ni, n in enumerate(normals):
        for lab, d in (
            ("normal", _direction(n, 0.0)),
            ("θ=0.6", _direction(n, 0.6, 0.5)),
            ("grazing", _grazing(n, 1e-8)),
        ):
            cases.append(BrdfCase("l = -v", f"n{ni} l=-v, l {lab}", n, d, tuple(-x for x in d)))
        near = [(1e-8, 1e-8, 0.0), (1e-8, 1e-4, 0.0), (1e-4, 1e-4, 1e-3)]
        if not quick:
            near += [(1e-6, 1e-2, 0.0), (1e-4, 2e-4, 0.0), (1e-8, 1e-6, 1e-6), (1e-2, 1e-2, 1e-2), (1e-3, 1e-8, 0.0)]
        for el, ev, dphi in near:
            cases.append(
                BrdfCase(
                    "l = -v",
                    f"n{ni} l, v grazing at {el:g}, {ev:g} rad, opposite{'' if not dphi else f' ±{dphi:g}'}",
                    n,
                    _grazing(n, el, 0.0),
                    _grazing(n, ev, math.pi + dphi),
                )
            )

    # l = v = n (scaled copies too) and l = v.
    for ni, n in enumerate(normals):
        cases.append(BrdfCase("l = v = n", f"n{ni} l = v = n", n, n, n))
        cases.append(
            BrdfCase("l = v = n", f"n{ni} l = 2n, v = n/4", n, tuple(2 * x for x in n), tuple(x / 4 for x in n))
        )
        thetas_lv = (0.3, 1.0, 1.5) if not quick else (0.3, 1.5)
        for tl in thetas_lv:
            d = _direction(n, tl, 0.4)
            cases.append(BrdfCase("l = v = n", f"n{ni} l = v at θ={tl}", n, d, d))
        cases.append(BrdfCase("l = v = n", f"n{ni} l = v grazing 1e-8", n, _grazing(n, 1e-8), _grazing(n, 1e-8)))

    # Zero, tiny, huge, non-unit and slightly tilted normals; non-unit l and v.
    odd_normals = [(0.0, 0.0, 0.0), (0.0, 0.0, 7.5), (0.0, 0.0, 1e-20), (1e-3, 0.0, 1.0)]
    if not quick:
        odd_normals += [(0.0, 0.0, 1e20), (3e-3, -2e-3, 1e-3), (-1e-25, 3e-25, 4e-25)]
    for n in odd_normals:
        nn = n if any(n) else N_AXIS
        pairs = {
            "θl=0.5 θv=0.9": (_direction(nn, 0.5, 0.0), _direction(nn, 0.9, 2.5)),
            "mirror": (_direction(nn, 0.7, 0.0), _direction(nn, 0.7, math.pi)),
            "near mirror": (_direction(nn, 0.7, 0.0), _direction(nn, 0.7 - 1e-3, math.pi)),
            "l×1e-20, v×3e5": (_direction(nn, 0.5, 0.0, 1e-20), _direction(nn, 0.9, 2.5, 3e5)),
        }
        for lab, (l, v) in pairs.items():  # noqa: E741
            cases.append(BrdfCase("normals", f"n={n} {lab}", n, l, v))
    return cases


# ============================================================================ models
@dataclass(frozen=True)
class ModelSpec:
    """A model to sweep, and how its reference value is built from the reference factors.

    ``terms[form] = (constant, ((factor, power), ...))``: the reference of that
    form is ``constant × Π factor^power`` where both directions are above the
    horizon, 0 elsewhere.  ``lobe`` is the form (or ``"D"``) that must be
    non-increasing along the peak sweeps.
    """

    family: str
    label: str
    model: object
    terms: dict
    reciprocal: bool
    lobe: str
    predicates: tuple = ("nl", "nv")


def _fmt_param(x: float) -> str:
    return f"{x:g}"


def brdf_specs() -> list[ModelSpec]:
    """Every model variant of the sweep with its reference terms."""
    from ..models.brdf import BlinnPhong, CookTorrance, Lambert, Phong

    specs = [
        ModelSpec(
            "Lambert",
            "Lambert",
            Lambert(KD),
            {"eval": ("kd/pi", ()), "eval_cos": ("kd/pi", (("nl", 1),)), "classic": ("kd", (("nl", 1),))},
            True,
            "",
        )
    ]
    for e in SHININESS:
        k = f"phong:{e!r}"
        specs.append(
            ModelSpec(
                "Phong",
                f"Phong e={_fmt_param(e)}",
                Phong(KS, e),
                {
                    "eval": ("ks/pi", ((k, 1), ("nl", -1))),
                    "eval_cos": ("ks/pi", ((k, 1),)),
                    "classic": ("ks", ((k, 1),)),
                },
                False,
                "classic",
                ("nl", "nv", "rv") if e > 0 else ("nl", "nv"),
            )
        )
    for e in SHININESS:
        k = f"bp:{e!r}"
        specs.append(
            ModelSpec(
                "Blinn-Phong",
                f"Blinn-Phong e={_fmt_param(e)}",
                BlinnPhong(KS, e),
                {
                    "eval": ("ks/pi", ((k, 1), ("nl", -1))),
                    "eval_cos": ("ks/pi", ((k, 1),)),
                    "classic": ("ks", ((k, 1),)),
                },
                False,
                "classic",
            )
        )
    for e in SHININESS:
        k = f"bp:{e!r}"
        c = f"bpnorm:{e!r}"
        specs.append(
            ModelSpec(
                "Blinn-Phong norm.",
                f"Blinn-Phong norm. e={_fmt_param(e)}",
                BlinnPhong(KS, e, normalized=True),
                {
                    "eval": ("ks", ((c, 1), (k, 1))),
                    "eval_cos": ("ks", ((c, 1), (k, 1), ("nl", 1))),
                    "classic": ("pi*ks", ((c, 1), (k, 1), ("nl", 1))),
                },
                True,
                "eval",
            )
        )
    names = {"beckmann": "CT Beckmann", "ggx": "CT GGX", "blinn-phong": "CT Blinn-Phong NDF"}
    for ndf in ("beckmann", "ggx", "blinn-phong"):
        for geo in ("v-cavity", "smith"):
            for fr in ("schlick", "dielectric", "none"):
                for den in ("4", "pi"):
                    for a in ROUGHNESS:
                        d = f"D:{ndf}:{a!r}"
                        if geo == "v-cavity":
                            g = "G:v-cavity"
                        else:
                            g = f"G:smith-{'ggx' if ndf == 'ggx' else 'beckmann'}:{a!r}"
                        fac = [(d, 1), (g, 1)]
                        if fr != "none":
                            fac.append((f"F:{fr}", 1))
                        fac.append(("nv", -1))
                        c = f"ks/{den}"
                        specs.append(
                            ModelSpec(
                                names[ndf],
                                f"CT {ndf} {geo} {fr} den={den} α={_fmt_param(a)}",
                                CookTorrance(KS, a, F0, ndf=ndf, geometry=geo, fresnel=fr, denominator=den),
                                {
                                    "eval": (c, tuple(fac) + (("nl", -1),)),
                                    "eval_cos": (c, tuple(fac)),
                                    "classic": ("pi*" + c, tuple(fac)),
                                    "D": ("1", ((d, 1),)),
                                },
                                True,
                                "D",
                            )
                        )
    return specs


def _constant(mp, name: str):
    """The exact constant a reference term is multiplied by: ``"ks/pi"``, ``"pi*ks"`` …"""
    if name.startswith("pi*"):
        return mp.pi * _constant(mp, name[3:])
    if name == "1":
        return mp.mpf(1)
    if name == "ks":
        return mp.mpf(KS)
    if name == "kd":
        return mp.mpf(KD)
    if name == "kd/pi":
        return mp.mpf(KD) / mp.pi
    if name == "ks/pi":
        return mp.mpf(KS) / mp.pi
    if name == "ks/4":
        return mp.mpf(KS) / 4
    return mp.mpf(name)


# ============================================================================ reference (mpmath)
def _mp():
    import mpmath

    return mpmath.mp


def _dot_exact(mp, a, b):
    # Products of binary inputs are exact at this precision, so the sign of n·l is exact too.
    with mp.workprec(2400):
        s = a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    return +s


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


#: Scalar quantities every reference factor is a function of (``tvc = 2 (n·h) min(n·v, n·l) / (v·h)``).
INTERMEDIATES = ("nl", "nv", "rv", "nh", "tan2h", "vh", "tan2v", "tan2l", "tvc")
_NONNEGATIVE = ("tan2h", "tan2v", "tan2l")


def _brdf_geometry(mp, x) -> dict:
    """The intermediates at raw inputs ``x = (N, L, V)`` (nine mpf components), textbook definitions.

    ``n·l = N·L / (|N||L|)`` with ``N·L`` exact (so its sign is); ``R_l·v = 2 (n·l)(n·v) − l·v``;
    ``h = (l + v)/|l + v|``; tangents squared from cross products (``|n × h|² / (n·h)²`` …).
    """
    N, L, V = x[0:3], x[3:6], x[6:9]
    nn, ll, vv = _dot_exact(mp, N, N), _dot_exact(mp, L, L), _dot_exact(mp, V, V)
    if nn == 0 or ll == 0 or vv == 0:
        return {"above": False}
    rn, rl, rv_ = mp.sqrt(nn), mp.sqrt(ll), mp.sqrt(vv)
    nl = _dot_exact(mp, N, L) / (rn * rl)
    nv = _dot_exact(mp, N, V) / (rn * rv_)
    q = {"nl": nl, "nv": nv, "above": bool(nl > 0 and nv > 0)}
    n = [c / rn for c in N]
    l = [c / rl for c in L]  # noqa: E741
    v = [c / rv_ for c in V]
    q["rv"] = 2 * nl * nv - (l[0] * v[0] + l[1] * v[1] + l[2] * v[2])
    if not q["above"]:
        return q
    H = [l[i] + v[i] for i in range(3)]
    hh = H[0] ** 2 + H[1] ** 2 + H[2] ** 2
    rh = mp.sqrt(hh)
    nh = (n[0] * H[0] + n[1] * H[1] + n[2] * H[2]) / rh
    cx = _cross(n, H)
    q["nh"] = nh
    q["tan2h"] = (cx[0] ** 2 + cx[1] ** 2 + cx[2] ** 2) / hh / nh**2
    q["vh"] = vh = (v[0] * H[0] + v[1] * H[1] + v[2] * H[2]) / rh
    cvx, clx = _cross(n, v), _cross(n, l)
    q["tan2v"] = (cvx[0] ** 2 + cvx[1] ** 2 + cvx[2] ** 2) / nv**2
    q["tan2l"] = (clx[0] ** 2 + clx[1] ** 2 + clx[2] ** 2) / nl**2
    q["tvc"] = 2 * nh * min(nv, nl) / vh
    return q


#: Scalar model parameters counted as inputs of the formulas (rows 9, 10, 11 of the gradients).
BRDF_PARAMETERS = ("e", "alpha", "f0")


def _brdf_factor_table() -> dict:
    """``factor key -> (intermediates, parameters, function(mp, q, prm))``: the mathematical models.

    ``q`` holds the intermediates, ``prm`` the parameter values (``e``, ``alpha``, ``f0``).
    Phong ``max(R_l·v, 0)^e`` and Blinn–Phong ``(n·h)^e`` (``0^0 = 1``) with the
    normalization ``(e+2)/(2π)``; Beckmann ``exp(−tan²θ/α²) / (π α² cos⁴θ)``, GGX
    ``α² / (π cos⁴θ (α² + tan²θ)²)`` (with ``1/cos⁴θ = (1 + tan²θ)²``), Blinn–Phong NDF
    ``(e+2)/(2π) (n·h)^e``, ``e = 2/α² − 2``; V-cavity ``min(1, 2 (n·h) min(n·v, n·l) / (v·h))``;
    Smith ``G1(v) G1(l)`` with ``G1 = 2 / (1 + erf a + exp(−a²)/(a√π))``, ``a = 1/(α tan θ)``
    (Beckmann) and ``G1 = 2 / (1 + sqrt(1 + α² tan²θ))`` (GGX); Schlick
    ``f0 + (1 − f0)(1 − v·h)^5`` and the exact unpolarized dielectric Fresnel with
    ``η = (1 + √f0)/(1 − √f0)``.
    """
    t = {}

    def power(qname, e_):
        if e_ == 0:
            return lambda mp, q, p: mp.one
        if qname == "rv":
            return lambda mp, q, p: mp.power(q["rv"], p["e"]) if q["rv"] > 0 else mp.zero
        return lambda mp, q, p: mp.power(q[qname], p["e"])

    for e in SHININESS:
        t[f"phong:{e!r}"] = (("rv",), ("e",), power("rv", e), {"e": e})
        t[f"bp:{e!r}"] = (("nh",), ("e",), power("nh", e), {"e": e})
        t[f"bpnorm:{e!r}"] = ((), ("e",), lambda mp, q, p: (p["e"] + 2) / (2 * mp.pi), {"e": e})

    memo: dict = {}

    def g1_beckmann(mp, t2, a):
        if t2 <= 0:
            return mp.one
        key = (t2, a, mp.prec)  # G1(v) is unchanged when only l is perturbed, and vice versa
        if key not in memo:
            if len(memo) > 4096:
                memo.clear()
            b = 1 / (a * mp.sqrt(t2))
            memo[key] = 2 / (1 + mp.erf(b) + mp.exp(-b * b) / (b * mp.sqrt(mp.pi)))
        return memo[key]

    def g1_ggx(mp, t2, a):
        return 2 / (1 + mp.sqrt(1 + a * a * t2))

    def beck(mp, q, p):
        a2 = p["alpha"] ** 2
        return mp.exp(-q["tan2h"] / a2) * (1 + q["tan2h"]) ** 2 / (mp.pi * a2)

    def ggx(mp, q, p):
        a2 = p["alpha"] ** 2
        return a2 * (1 + q["tan2h"]) ** 2 / (mp.pi * (a2 + q["tan2h"]) ** 2)

    def bpn(mp, q, p):
        e = max(2 / p["alpha"] ** 2 - 2, mp.zero)
        return (e + 2) / (2 * mp.pi) * (mp.power(q["nh"], e) if e > 0 else 1)

    def sb(mp, q, p):
        return g1_beckmann(mp, q["tan2v"], p["alpha"]) * g1_beckmann(mp, q["tan2l"], p["alpha"])

    def sg(mp, q, p):
        return g1_ggx(mp, q["tan2v"], p["alpha"]) * g1_ggx(mp, q["tan2l"], p["alpha"])

    for a_ in ROUGHNESS:
        pa = {"alpha": a_}
        t[f"D:beckmann:{a_!r}"] = (("tan2h",), ("alpha",), beck, pa)
        t[f"D:ggx:{a_!r}"] = (("tan2h",), ("alpha",), ggx, pa)
        t[f"D:blinn-phong:{a_!r}"] = (("nh",), ("alpha",), bpn, pa)
        t[f"G:smith-beckmann:{a_!r}"] = (("tan2v", "tan2l"), ("alpha",), sb, pa)
        t[f"G:smith-ggx:{a_!r}"] = (("tan2v", "tan2l"), ("alpha",), sg, pa)
    t["G:v-cavity"] = (("tvc",), (), lambda mp, q, p: min(mp.one, q["tvc"]), {})

    def schlick(mp, q, p):
        f0 = p["f0"]
        return f0 + (1 - f0) * (1 - q["vh"]) ** 5

    def dielectric(mp, q, p):
        vh, g = q["vh"], mp.sqrt(p["f0"])
        eta = (1 + g) / (1 - g)
        ct = mp.sqrt(1 - (1 - vh * vh) / (eta * eta))
        r_par = (eta * vh - ct) / (eta * vh + ct)
        r_perp = (vh - eta * ct) / (vh + eta * ct)
        return (r_par**2 + r_perp**2) / 2

    t["F:schlick"] = (("vh",), ("f0",), schlick, {"f0": F0})
    t["F:dielectric"] = (("vh",), ("f0",), dielectric, {"f0": F0})
    return t


_FACTOR_TABLE: dict = {}


def _brdf_factors(mp, x) -> dict:
    """Every reference factor at raw inputs ``x = (N, L, V)``, plus ``nl``, ``nv``, ``rv`` and ``above``."""
    if not _FACTOR_TABLE:
        _FACTOR_TABLE.update(_brdf_factor_table())
    q = _brdf_geometry(mp, x)
    out = {k: q[k] for k in ("above", "nl", "nv", "rv") if k in q}
    if q["above"]:
        for key, (_, _, fn, prm) in _FACTOR_TABLE.items():
            out[key] = fn(mp, q, {k: mp.mpf(v) for k, v in prm.items()})
    return out


def _brdf_gradients(mp, x, delta):
    """Factor values and their relative changes under ``x_i → x_i (1 ± δ)``, by the chain rule.

    The intermediates (:data:`INTERMEDIATES`) are recomputed at each of the perturbed
    inputs; each factor is differentiated in its own one or two intermediates from either
    side (one-sided differences, so the kinks of ``min`` and ``max`` are honoured), and
    ``Δ ln F = Σ_q (∂ ln F / ∂q)_± Δq``, to first order in δ = 1e-30.  The model
    parameters (:data:`BRDF_PARAMETERS`) are perturbed directly.
    Returns ``(above, values, grads)`` with ``grads[key]`` of shape ``(12, 2)`` holding
    ``(F(x') − F(x)) / (F(x) δ)``: rows 0–8 the components of ``n``, ``l``, ``v``,
    rows 9–11 the parameters ``e``, ``α``, ``f0``.
    """
    if not _FACTOR_TABLE:
        _FACTOR_TABLE.update(_brdf_factor_table())
    d = mp.mpf(delta)
    nrow = len(x) + len(BRDF_PARAMETERS)
    q0 = _brdf_geometry(mp, x)
    names = [k for k in INTERMEDIATES if k in q0]
    dq = {k: np.zeros((nrow, 2)) for k in names}  # Δq / δ (absolute change of the intermediate)
    flipped = np.zeros((nrow, 2), dtype=bool)
    for i, xi in enumerate(x):
        if xi == 0:
            continue
        for j, sgn in enumerate((1, -1)):
            xp = list(x)
            xp[i] = xi * (1 + sgn * d)
            qp = _brdf_geometry(mp, xp)
            if qp["above"] != q0["above"]:
                flipped[i, j] = True
                continue
            for k in names:
                dq[k][i, j] = float((qp[k] - q0[k]) / d)
    values = {k: q0[k] for k in ("nl", "nv", "rv") if k in q0}
    grads = {}
    for k in list(values):
        v0 = values[k]
        grads[k] = np.where(flipped, np.inf, dq[k] / float(v0)) if v0 != 0 else np.where(dq[k] != 0, np.inf, 0.0)
    if not q0["above"]:
        return q0["above"], values, grads
    for key, (deps, params, fn, prm0) in _FACTOR_TABLE.items():
        prm = {k: mp.mpf(v) for k, v in prm0.items()}
        f0 = fn(mp, q0, prm)
        values[key] = f0
        g = np.zeros((nrow, 2))
        if f0 != 0:
            for k in deps:
                h = d * abs(q0[k]) if q0[k] != 0 else d
                qp, qm = dict(q0), dict(q0)
                qp[k] = q0[k] + h
                qm[k] = q0[k] - h
                sp = float((fn(mp, qp, prm) - f0) / (f0 * h))
                sm = sp if (k in _NONNEGATIVE and qm[k] < 0) else float((f0 - fn(mp, qm, prm)) / (f0 * h))
                g += np.where(dq[k] > 0, sp, sm) * dq[k]
            for name in params:
                row = len(x) + BRDF_PARAMETERS.index(name)
                for j, sgn in enumerate((1, -1)):
                    pp = dict(prm)
                    pp[name] = prm[name] * (1 + sgn * d)
                    g[row, j] = float((fn(mp, q0, pp) - f0) / (f0 * d))
        grads[key] = np.where(flipped, np.inf, g)
    return q0["above"], values, grads


def _gradient(mp, fn, x, base, keys, delta):
    """Relative changes ``(F(x') − F(x)) / (F(x) δ)`` for every factor, ``x_i → x_i(1 ± δ)``.

    Shape ``(len(keys), len(x), 2)``; the last axis is the sign of the perturbation.
    """
    g = np.zeros((len(keys), len(x), 2))
    d = mp.mpf(delta)
    for i, xi in enumerate(x):
        if xi == 0:
            continue
        for j, sgn in enumerate((1, -1)):
            xp = list(x)
            xp[i] = xi * (1 + sgn * d)
            f = fn(mp, xp)
            for k, key in enumerate(keys):
                b = base.get(key)
                if b is None or key not in f:
                    g[k, i, j] = np.nan
                elif b == 0:
                    g[k, i, j] = 0.0 if f[key] == 0 else np.inf
                else:
                    g[k, i, j] = float((f[key] - b) / (b * d))
            if f.get("above") != base.get("above"):
                g[:, i, j] = np.inf
    return g


def reference_brdf(n, l, v, dps: int = REFERENCE_DPS, delta: float = DELTA) -> dict:  # noqa: E741
    """Reference factors at the binary inputs ``n, l, v`` (sequences of Python floats).

    Returns ``{"above": bool, "values": {key: mpf}, "grad": {key: (12, 2) array}}``:
    the 80-digit factor values (``nl``, ``nv``, ``rv`` = ``R_l·v``, the Phong and
    Blinn–Phong lobes ``phong:e``, ``bp:e``, the NDFs ``D:ndf:α``, ``G:…``,
    ``F:…``) and their relative changes ``(F(x') − F(x)) / (F(x) δ)`` under
    ``x_i → x_i (1 ± δ)`` (rows: the nine components of ``n``, ``l``, ``v``, then the
    parameters ``e``, ``α``, ``f0`` of :data:`BRDF_PARAMETERS`).
    """
    mp = _mp()
    with mp.workdps(dps):
        x = [mp.mpf(float(c)) for c in (*n, *l, *v)]
        above, values, grads = _brdf_gradients(mp, x, delta)
        return {"above": above, "values": values, "grad": grads}


# ============================================================================ lights
@dataclass(frozen=True)
class LightSpec:
    """A light configuration of the sweep (engine object plus the parameters the reference needs)."""

    family: str
    label: str
    light: object
    position: tuple
    direction: tuple | None
    attenuation: tuple
    intensity: float
    cutoff_deg: float | None = None
    exponent: float = 0.0


_SPOT_GEOMETRY = (((0.0, 0.0, 2.0), (0.0, 0.0, -1.0)), ((0.5, -0.25, 2.0), (0.25, -0.5, -1.0)))
_DIST_POSITIONS = ((0.0, 0.0, 0.0), (1.5, -2.25, 3.0))
_ATTENUATIONS = ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0), (1.0, 1.0, 1.0))
_INTENSITIES = (1e-30, 1e30, 1e38)
SPOT_CUTOFFS = (0.0, 30.0, 90.0, 180.0)
SPOT_EXPONENTS = (0.0, 1.0, 128.0, 1e4)


def light_specs() -> list[LightSpec]:
    """Point lights (three falloffs, two positions, three extreme intensities) and spot lights."""
    from ..lights.punctual import PointLight, SpotLight

    specs = []
    for p in _DIST_POSITIONS:
        for att in _ATTENUATIONS:
            specs.append(
                LightSpec("Point light", f"point at {p} att={att}", PointLight(p, 1.0, 1.0, att), p, None, att, 1.0)
            )
    for inten in _INTENSITIES:
        p, att = (0.0, 0.0, 0.0), (1.0, 0.0, 0.0)
        specs.append(
            LightSpec("Point light", f"point intensity={inten:g}", PointLight(p, 1.0, inten, att), p, None, att, inten)
        )
    for gi, (p, s) in enumerate(_SPOT_GEOMETRY):
        for cut in SPOT_CUTOFFS:
            for ex in SPOT_EXPONENTS:
                att = (0.0, 0.0, 1.0)
                light = SpotLight(p, 1.0, 1.0, att, direction=s, cutoff_deg=cut, exponent=ex)
                specs.append(
                    LightSpec("Spot light", f"spot{gi} cutoff={cut:g} exp={ex:g}", light, p, s, att, 1.0, cut, ex)
                )
    return specs


def _spot_direction(axis, psi):
    """Unit direction at angle ``psi`` from ``axis`` (float64)."""
    t, b, a = _frame(axis)
    return math.cos(psi) * a + math.sin(psi) * t


def light_cases(quick: bool = False) -> list[LightCase]:
    """Surface points for every light spec: distance sweeps, intensity extremes, and angles across the spot cone."""
    specs = light_specs()
    u = np.array([1.0, 2.0, 2.0]) / 3.0
    cases = []
    dists = (0.0, 1e-160, 1e-20, 1e-12, 1e-6, 1.0, 1e6, 1e12, 1e20)
    if quick:
        dists = (0.0, 1e-160, 1e-20, 1e-12, 1.0, 1e12)
    psis = (
        0.0,
        1e-8,
        1e-4,
        1e-2,
        0.25,
        math.pi / 6 - 1e-9,
        math.pi / 6,
        math.pi / 6 + 1e-6,
        1.0,
        math.pi / 2 - 1e-8,
        math.pi / 2,
        2.0,
    )
    if quick:
        psis = (0.0, 1e-8, 1e-4, math.pi / 6, math.pi / 2, 2.0)
    for si, sp in enumerate(specs):
        if sp.family == "Point light" and sp.intensity == 1.0:
            for k, r in enumerate(dists):
                p = tuple(float(x) for x in np.asarray(sp.position) - r * u)
                cases.append(LightCase("distance", f"{sp.label} r={r:g}", si, p, sp.label, k))
        elif sp.family == "Point light":
            for k, r in enumerate((1e-12, 1.0, 1e12)):
                p = tuple(float(x) for x in -r * u)
                cases.append(LightCase("intensity", f"{sp.label} r={r:g}", si, p, sp.label, k))
        else:
            for k, psi in enumerate(psis):
                d = _spot_direction(sp.direction, psi)
                p = tuple(float(x) for x in np.asarray(sp.position) + 2.0 * d)
                cases.append(LightCase("spot cone", f"{sp.label} ψ={psi:.10g}", si, p, sp.label, k))
    return cases


#: Light parameters counted as inputs (rows 9–12 of the light gradients): falloff ``(a, b, c)``, spot exponent.
LIGHT_PARAMETERS = ("a", "b", "c", "exponent")


def _light_factors(mp, x, spec: LightSpec, prm: dict | None = None) -> dict:
    """Reference falloff × spot factor at raw inputs ``x = (point, light position, spot axis)``.

    ``prm`` overrides the parameters of :data:`LIGHT_PARAMETERS` (for their perturbation).
    """
    prm = prm or {}
    p, P, S = x[0:3], x[3:6], x[6:9]
    with mp.workprec(2400):
        d = [P[i] - p[i] for i in range(3)]
    r2 = _dot_exact(mp, d, d)
    out = {"above": True}
    if r2 == 0:
        out["scale"] = mp.zero  # no direction toward the light exists: the engine's documented convention
        out["irradiance"] = mp.zero
        return out
    r = mp.sqrt(r2)
    a, b, c = (prm.get(k, mp.mpf(t)) for k, t in zip("abc", spec.attenuation, strict=True))
    ex = prm.get("exponent", mp.mpf(spec.exponent))
    scale = 1 / (a * r2 + b * r + c)
    if spec.cutoff_deg is not None and spec.cutoff_deg != 180:
        ss = mp.sqrt(_dot_exact(mp, S, S))
        w = [d[i] / r + S[i] / ss for i in range(3)]  # l + ŝ; 1 − cos ψ = |l + ŝ|² / 2
        one_minus = (w[0] ** 2 + w[1] ** 2 + w[2] ** 2) / 2
        cut = spec.cutoff_deg
        one_minus_cut = mp.zero if cut == 0 else (mp.one if cut == 90 else 1 - mp.cos(mp.radians(cut)))
        out["cone"] = one_minus_cut - one_minus  # >= 0 inside the cone
        if out["cone"] >= 0:
            cos_psi = 1 - one_minus
            if spec.exponent == 0:
                spot = mp.one
            else:
                spot = mp.power(cos_psi, ex) if cos_psi > 0 else mp.zero
        else:
            spot = mp.zero
        scale = scale * spot
    out["scale"] = scale
    out["irradiance"] = scale * mp.mpf(spec.intensity)
    return out


def _light_gradients(mp, x, spec: LightSpec, delta):
    """``(values, grads)`` for a light: rows 0–8 the vector components, 9–12 :data:`LIGHT_PARAMETERS`."""

    def fn(mp_, xx):
        return _light_factors(mp_, xx, spec)

    base = fn(mp, x)
    keys = [key for key in base if key != "above"]
    g = _gradient(mp, fn, x, base, keys, delta)
    extra = np.zeros((len(keys), len(LIGHT_PARAMETERS), 2))
    d = mp.mpf(delta)
    values = (*spec.attenuation, spec.exponent)
    for r, (name, val) in enumerate(zip(LIGHT_PARAMETERS, values, strict=True)):
        if val == 0 or (name == "exponent" and (spec.cutoff_deg is None or spec.cutoff_deg == 180)):
            continue
        for j, sgn in enumerate((1, -1)):
            f = _light_factors(mp, x, spec, {name: mp.mpf(val) * (1 + sgn * d)})
            for k, key in enumerate(keys):
                b = base[key]
                if key == "cone":
                    continue
                extra[k, r, j] = 0.0 if b == 0 else float((f[key] - b) / (b * d))
    grads = {key: np.concatenate([g[k], extra[k]]) for k, key in enumerate(keys)}
    return base, grads


def reference_light(spec: LightSpec, point, dps: int = REFERENCE_DPS, delta: float = DELTA) -> dict:
    """Reference ``scale`` (falloff × spot), ``irradiance`` and cone predicate at ``point``.

    Same layout as :func:`reference_brdf`; gradient rows: the point, the light position,
    the spot axis, then :data:`LIGHT_PARAMETERS`.
    """
    mp = _mp()
    with mp.workdps(dps):
        S = spec.direction if spec.direction is not None else (0.0, 0.0, 0.0)
        x = [mp.mpf(float(c)) for c in (*point, *spec.position, *S)]
        base, grads = _light_gradients(mp, x, spec, delta)
        return {"above": True, "values": {k: v for k, v in base.items() if k != "above"}, "grad": grads}


# ============================================================================ reference tables
def _kappa(g: np.ndarray) -> float:
    """``Σ_i max_± |relative change| / δ`` from a ``(rows, 2)`` array of relative changes."""
    if not np.all(np.isfinite(g)):
        return math.inf
    return float(np.sum(np.max(np.abs(g), axis=1)))


def _columns(specs, forms_of) -> list[tuple[int, str]]:
    return [(i, f) for i, s in enumerate(specs) for f in forms_of(s)]


def _brdf_forms(spec: ModelSpec):
    return tuple(spec.terms)


PREDICATES = ("nl", "nv", "rv")


def _ref_table(kind: str, dtname: str, inputs: Sequence, dps: int = REFERENCE_DPS) -> dict:
    """Reference values, condition numbers and predicate condition numbers for a batch: worker entry point.

    ``kind`` is ``"brdf"`` (inputs ``(n, l, v)``) or ``"light"`` (inputs ``(spec index,
    point)``), each component already rounded to ``dtname``.  Besides the double-double
    value (``hi + lo``) the natural logarithm of the value is returned (``logref``): it
    stays meaningful beyond the float64 range and serves the logarithmic test of
    ill-conditioned points.
    """
    mp = _mp()
    import mpmath.libmp as _libmp

    if kind == "brdf":
        specs = brdf_specs()
        cols = [specs[si].terms[form] for si, form in _columns(specs, _brdf_forms)]
        preds = PREDICATES
    else:
        lspecs = light_specs()
        cols = [("1", ((form, 1),)) for form in LIGHT_FORMS]
        preds = ("cone",)
    m, k = len(inputs), len(cols)
    out = {
        "hi": np.zeros((m, k)),
        "lo": np.zeros((m, k)),
        "nz": np.zeros((m, k), dtype=bool),
        "kappa": np.full((m, k), np.nan),
        "pred": np.zeros((m, len(preds))),
        "logref": np.full((m, k), np.nan),
    }
    # Every column is  constant × Π factor^power:  its log-gradient is the same combination of
    # the factors' log-gradients (one matrix product), its value a product shared by prefix.
    fkeys = sorted({key for _, factors in cols for key, _ in factors})
    fidx = {key: i for i, key in enumerate(fkeys)}
    powers = np.zeros((k, len(fkeys)))
    for c, (_, factors) in enumerate(cols):
        for key, pw in factors:
            powers[c, fidx[key]] += pw
    # The products as a program: prefix nodes (parent, factor, power) shared between columns.
    prog_nodes: list = []
    node_of: dict = {}
    prog_cols = np.full(k, -1)
    for c, (_, factors) in enumerate(cols):
        parent = -1
        for key, pw in factors:
            nk = (parent, fidx[key], pw)
            if nk not in node_of:
                node_of[nk] = len(prog_nodes)
                prog_nodes.append(nk)
            parent = node_of[nk]
        prog_cols[c] = parent
    col_ok = np.ones(k, dtype=bool)
    is_d = np.array(
        [
            kind == "brdf" and form == "D"
            for _, form in (_columns(specs, _brdf_forms) if kind == "brdf" else [(0, f) for f in LIGHT_FORMS])
        ]
    )

    def item_sweep(item):
        return kind != "brdf" or (len(item) > 3 and bool(item[3]))

    with mp.workdps(dps):
        consts = {name: _constant(mp, name) for name in {cname for cname, _ in cols}}
        logconst = np.array([float(mp.log(consts[cname])) for cname, _ in cols])
        const_raw = [consts[cname]._mpf_ for cname, _ in cols]
        for r, item in enumerate(inputs):
            if kind == "brdf":
                x = [mp.mpf(float(c)) for c in (*item[0], *item[1], *item[2])]
            else:
                sp = lspecs[item[0]]
                axis = sp.direction if sp.direction is not None else (0.0, 0.0, 0.0)
                x = [mp.mpf(float(c)) for c in (*item[1], *sp.position, *axis)]
            if kind == "brdf":
                above, base, grads = _brdf_gradients(mp, x, DELTA)
                base["above"] = above
            else:
                base, grads = _light_gradients(mp, x, lspecs[item[0]], DELTA)
            for j, key in enumerate(preds):
                if key in base:
                    out["pred"][r, j] = math.inf if base[key] == 0 else _kappa(grads[key])
            if not base["above"]:
                continue
            nx = next(iter(grads.values())).shape[0]  # vector components, then parameters
            fg = np.zeros((len(fkeys), nx * 2))
            flog = np.zeros(len(fkeys))
            zero = np.zeros(len(fkeys), dtype=bool)
            for key, i in fidx.items():
                val = base.get(key)
                if val is None or val == 0:
                    zero[i] = True
                    continue
                fg[i] = grads[key].reshape(-1)
                flog[i] = float(mp.log(abs(val)))
            with np.errstate(invalid="ignore"):
                g = (powers @ np.where(np.isfinite(fg), fg, 0.0)).reshape(k, nx, 2)
                bad = (np.abs(powers) > 0) @ ~np.all(np.isfinite(fg), axis=1)
            kap = np.sum(np.max(np.abs(g), axis=2), axis=1)
            kap[bad] = np.inf
            colzero = (np.abs(powers) > 0) @ zero
            # Products on raw mpmath tuples (libmp): the wrappers cost more than the arithmetic here.
            prec = mp.prec
            fac_raw = [None] * len(fkeys)
            for key, i in fidx.items():
                if not zero[i]:
                    fac_raw[i] = base[key]._mpf_
            inv_raw = {}
            pre = [None] * len(prog_nodes)
            for pid, (parent, fi, pw) in enumerate(prog_nodes):
                if zero[fi] or (parent >= 0 and pre[parent] is None):
                    continue  # a zero factor: the columns through this node are 0
                if pw == 1:
                    f = fac_raw[fi]
                else:
                    f = inv_raw.get((fi, pw))
                    if f is None:
                        f = inv_raw[(fi, pw)] = (base[fkeys[fi]] ** pw)._mpf_
                pre[pid] = f if parent < 0 else _libmp.mpf_mul(pre[parent], f, prec, "n")
            logs = logconst + powers @ flog
            wanted = col_ok if item_sweep(item) else col_ok & ~is_d
            for c in np.flatnonzero(wanted & ~colzero):
                t = const_raw[c]
                pid = prog_cols[c]
                val = t if pid < 0 else _libmp.mpf_mul(t, pre[pid], prec, "n")
                hi = _libmp.to_float(val)
                out["hi"][r, c] = hi
                if math.isfinite(hi) and hi != 0:
                    out["lo"][r, c] = _libmp.to_float(_libmp.mpf_sub(val, _libmp.from_float(hi), 64, "n"))
                out["nz"][r, c] = True
                out["kappa"][r, c] = kap[c]
                out["logref"][r, c] = logs[c]
    return out


# ============================================================================ engine side
def _engine_brdf(specs, cols, n, l, v):  # noqa: E741
    """Engine values ``(m, len(cols), 3)`` (float64 copies), reciprocal ``eval(n, v, l)`` per column, warnings.

    ``model.eval(n, l, v)`` is ``model.eval_geometry(Geometry(n, l, v))`` (likewise for
    ``eval_cos`` and ``classic``); one :class:`~lighting.models.brdf.Geometry` is shared by every
    model, which is what a shading pass does too.
    """
    import warnings

    from ..models.brdf import Geometry

    m = n.shape[0]
    vals = np.zeros((m, len(cols), 3))
    swapped = {}
    method = {"eval": "eval_geometry", "eval_cos": "eval_cos_geometry", "classic": "classic_geometry"}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        g, gs = Geometry(n, l, v), Geometry(n, v, l)
        for c, (si, form) in enumerate(cols):
            model = specs[si].model
            out = model.D(g)[:, None] if form == "D" else getattr(model, method[form])(g)
            vals[:, c, :] = np.broadcast_to(out, (m, 3))
            if form == "eval" and specs[si].reciprocal:
                swapped[c] = model.eval_geometry(gs).astype(np.float64)
    return vals, swapped, len(caught)


def _engine_brdf_stacked(specs, cols, n, l, v, eng):  # noqa: E741
    """The image path's values: ``separable_cos`` / ``separable_classic`` on a stacked geometry.

    A renderer lights all directional lights of a frame at once through a
    ``StackedGeometry``; here the ``m`` light directions of the cases are stacked
    over the ``m`` points (an ``(m, m)`` geometry) and the diagonal, case ``i``'s
    own light at its own point, is compared.  Columns the image path does not
    take (``eval``, ``D``, models that do not stack) keep the values of ``eng``.
    Returns the values and the number of warnings.
    """
    import warnings

    from ..models.brdf import StackedGeometry
    from ..vec import normalize

    out = eng.copy()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        g = StackedGeometry(normalize(n), normalize(l), normalize(v))
        idx = np.arange(n.shape[0])
        for c, (si, form) in enumerate(cols):
            model = specs[si].model
            if form not in ("eval_cos", "classic") or not all(p.stackable for p in model.parts):
                continue
            fields = model.separable_cos(g) if form == "eval_cos" else model.separable_classic(g)
            with np.errstate(over="ignore"):
                vals = sum(
                    np.broadcast_to(f, (len(idx), len(idx)))[idx, idx].astype(np.float64)[:, None] * col
                    for f, col in fields
                )
            out[:, c, :] = np.minimum(vals, float(np.finfo(n.dtype).max))
    return out, len(caught)


def _engine_light(specs, cases, dt):
    import warnings

    m = len(cases)
    vals = np.zeros((m, len(LIGHT_FORMS), 3))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for si in sorted({c.spec for c in cases}):
            idx = [i for i, c in enumerate(cases) if c.spec == si]
            pts = np.array([cases[i].point for i in idx], dtype=dt)
            inc = next(specs[si].light.incident(pts, dtype=dt))
            vals[idx, 0, :] = np.asarray(inc.scale, dtype=np.float64)[:, None]
            vals[idx, 1, :] = np.broadcast_to(np.asarray(inc.irradiance, dtype=np.float64), (len(idx), 3))
    return vals, len(caught)


# ============================================================================ classification
NORMAL, ILL, EDGE, ZERO, OVER, UNDER = range(6)
CLASSES = ("normal", "ill", "edge", "zero", "over", "under")


def _classify(hi, lo, nz, kappa, logref, edge, eng, dt):
    """Per point: class code, relative error, ratio, and whether the point passes.

    Arrays of any common shape ``S``; ``eng`` has shape ``S + (3,)`` (RGB: the worst
    channel counts).  Classes (:data:`CLASSES`):

    * ``normal`` — the true value is normal in the dtype: ``err <= 8 max(κ,1) u``;
    * ``ill`` — ``8 κ u >= 1``: the linear bound allows 100 % and no longer describes
      the error (``κ`` is the derivative of ``ln f``; a relative change ``κ u`` of 15
      means a factor ``e^15``), so the same first-order bound is applied to the
      logarithm: ``|ln(f_engine / f_true)| <= 8 κ u`` (or the test of its magnitude
      class below, whichever passes);
    * ``edge`` — a horizon or cone decision flips within ±8u: finite and >= 0 only;
    * ``zero`` — exactly 0 required;
    * ``over`` — beyond the largest finite value: exactly that value (saturation);
    * ``under`` — below the smallest normal: within ``8 κ u f`` plus the smallest normal.

    ``ratio`` is ``err / (max(κ,1) u)`` for normal points and ``|ln(f_e/f)| / (max(κ,1) u)``
    for ill ones (NaN elsewhere).
    """
    u = unit_roundoff(dt)
    fi = np.finfo(dt)
    tiny, big = float(fi.tiny), float(fi.max)
    k1 = np.where(np.isfinite(kappa), np.maximum(np.nan_to_num(kappa, nan=1.0), 1.0), np.inf)
    ref = hi + lo
    emax, emin = eng.max(axis=-1), eng.min(axis=-1)
    with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
        diff = np.abs((eng - hi[..., None]) - lo[..., None]).max(axis=-1)
        err = np.where(ref > 0, diff / np.where(ref > 0, ref, 1.0), np.nan)
        ratio = err / (k1 * u)
        slack = BOUND_FACTOR * k1 * u
        logerr = np.abs(np.log(np.where(eng > 0, eng, 0)) - logref[..., None]).max(axis=-1)
        mag = np.where(ref < tiny, UNDER, np.where(ref > big, OVER, NORMAL))
        near = ref <= big * (1 + slack)
        ok_mag = np.where(
            mag == NORMAL,
            ratio <= BOUND_FACTOR,
            np.where(mag == UNDER, diff <= slack * ref + tiny, np.all(eng == big, axis=-1) | (near & (ratio <= 8))),
        )
        ok_ill = ok_mag | (logerr <= slack)
    cls = np.where(edge, EDGE, np.where(~nz, ZERO, np.where(slack >= 1, ILL, mag))).astype(np.int8)
    ok = np.select(
        [cls == EDGE, cls == ZERO, cls == ILL],
        [True, (emax == 0) & (emin == 0), ok_ill],
        default=ok_mag,
    )
    ok &= np.all(np.isfinite(eng), axis=-1) & (emin >= 0)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(cls == NORMAL, ratio, np.where(cls == ILL, logerr / (k1 * u), np.nan))
    err = np.where((cls == NORMAL) | (cls == ILL), err, np.nan)
    return cls, err, ratio, ok


# ============================================================================ rearrangements
@dataclass
class Rearrangement:
    """A formula the engine evaluates in a rearranged form, and what it bought on this sweep.

    ``before[dtype]`` / ``after[dtype]`` are ``(worst err / (max(κ,1) u), failing values)``
    over the ``f_r`` values (``eval``) of the affected models in every case family, with
    only this one formula put back to its earlier (or textbook) form.  ``existing`` marks rearrangements that were in
    the engine before this sweep was written (they are checked the same way).
    """

    name: str
    where: str
    formula_before: str
    formula_after: str
    existing: bool = False
    before: dict = field(default_factory=dict)
    after: dict = field(default_factory=dict)


def _legacy_normalize(a):
    """The earlier :func:`lighting.vec.normalize`: one path (fast or scaled) for the whole batch."""
    from ..vec import _scaled

    fi = np.finfo(a.dtype)
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        len2 = a[..., 0] * a[..., 0] + a[..., 1] * a[..., 1] + a[..., 2] * a[..., 2]
    lo, hi = float(fi.tiny) * 1e4, float(fi.max) * 1e-4
    if np.all((len2 > lo) & (len2 < hi)):
        return a / np.sqrt(len2)[..., None]
    sc, _ = _scaled(a)
    len_s = np.sqrt(sc[..., 0] ** 2 + sc[..., 1] ** 2 + sc[..., 2] ** 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.where(len_s[..., None] > 0, sc / np.where(len_s > 0, len_s, 1)[..., None], 0)
    return out.astype(a.dtype, copy=False)


@functools.lru_cache(maxsize=1)
def _legacy_classes():
    """Engine classes with one formula each put back to its earlier or textbook form."""
    from functools import cached_property

    from .._numeric import saturate_to
    from ..lights.punctual import SpotLight, _cos_deg
    from ..models import fresnel as fr
    from ..models.brdf import BRDF, BlinnPhong, CookTorrance, Geometry, Phong, cos_power

    class PlainSum(Geometry):
        @cached_property
        def _l_plus_v(self):
            s = self.l + self.v
            return s, self._dot(s, s)

    class CosSquared(Geometry):  # textbook sin²θ_h = 1 − cos²θ_h
        @cached_property
        def sin2_h(self):
            c = np.clip(self.n_dot_h, -1, 1)
            return np.clip(1 - c * c, 0, 1)

        @cached_property
        def one_minus_n_dot_h(self):
            return 1 - np.minimum(self.n_dot_h, 1)

    class TextbookRv(Geometry):  # 1 − R_l·v with R_l·v = 2 (n·l)(n·v) − l·v, as the slides compute it
        @cached_property
        def one_minus_r_dot_v(self):
            return np.clip(1 - self.r_dot_v, 0, 2)

    class BPPeakOnly(BlinnPhong):  # (n·h)^e from 1 − n·h everywhere
        def _lobe(self, g, dtype=None, scale=1.0):
            dt = dtype or g.dtype
            lobe = cos_power(g.one_minus_n_dot_h.astype(dt), self.shininess)
            if scale != 1:  # the normalization multiplied on, as it was
                with np.errstate(over="ignore", under="ignore"):
                    lobe = saturate_to(lobe * scale, dt)
            return np.where(g.above, lobe, 0).astype(dt, copy=False)

    class PhongDtypeDivision(Phong):  # f_r = (k_s lobe/π) / (n·l) with the lobe rounded to the dtype first
        def _f(self, g):
            return BRDF._f(self, g)

    class BPDtypeDivision(BlinnPhong):
        def _f(self, g):
            return BRDF._f(self, g) if not self.normalized else super()._f(g)

    class LegacyCT(CookTorrance):
        legacy: frozenset = frozenset()

        def _separable(self, g, with_n_dot_l):
            if not self.legacy:
                return super()._separable(g, with_n_dot_l)
            wide = np.float32 if "float32" in self.legacy else np.float64
            d = self.D(g) if self.legacy & {"d-dtype", "float32"} else self._D(g, np.float64)
            if self.legacy & {"visibility", "float32"}:
                dg = d.astype(wide) * self.G(g).astype(wide)
                dg = np.where(g.above, dg, 0)
                den = wide(self._den_const()) * g.n_dot_v.astype(wide)
                if with_n_dot_l:
                    den = den * g.n_dot_l.astype(wide)
                with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
                    sv = np.where(den > 0, dg / np.where(den > 0, den, 1), 0)
            else:
                with np.errstate(over="ignore", invalid="ignore"):
                    dv = d.astype(np.float64) * self._visibility(g, with_n_dot_l)
                sv = np.where(g.above & ~np.isnan(dv), dv, 0) / self._den_const()
            sv = np.minimum(sv, np.finfo(wide).max).astype(np.float64)
            if self.fresnel == "none":
                return [(sv, self.ks)]
            vh = np.clip(g.v_dot_h.astype(wide), 0, 1)
            if self.fresnel == "schlick":
                m = ((1 - vh) ** 5).astype(np.float64)
                return [(sv, self.ks * self.f0), (sv * m, self.ks * (1.0 - self.f0))]
            if self.legacy & {"dielectric", "float32"}:
                f = fr.dielectric(vh, fr.eta_from_f0(self.f0)).astype(g.dtype).astype(np.float64)
            else:
                f = fr._dielectric_from_f0(vh, self.f0)
            return [(sv * f[..., i], self.ks * np.eye(3)[i]) for i in range(3)]

    class LegacySpot(SpotLight):
        def _spot(self, l):  # noqa: E741
            d = self.direction
            c = -(l[..., 0] * d[0] + l[..., 1] * d[1] + l[..., 2] * d[2])
            if self.cutoff_deg == 180:
                return np.ones_like(c)
            inside = c >= _cos_deg(self.cutoff_deg)
            with np.errstate(under="ignore"):
                pw = np.ones_like(c) if self.exponent == 0 else np.maximum(c, 0.0) ** self.exponent
            return np.where(inside, pw, 0.0)

    return {
        "PlainSum": PlainSum,
        "CosSquared": CosSquared,
        "TextbookRv": TextbookRv,
        "BPPeakOnly": BPPeakOnly,
        "PhongDtypeDivision": PhongDtypeDivision,
        "BPDtypeDivision": BPDtypeDivision,
        "LegacyCT": LegacyCT,
        "LegacySpot": LegacySpot,
    }


def _ct_variant(model, legacy):
    cls = _legacy_classes()["LegacyCT"]
    m = cls(**model._params())
    m.legacy = frozenset(legacy)
    return m


def rearrangement_list() -> list[Rearrangement]:
    """The rearranged formulas checked by :func:`run` (new ones first, then those the engine already had)."""
    return [
        Rearrangement(
            "half vector near l = −v",
            "brdf.Geometry._l_plus_v, brdf._unit_sum",
            "l + v from the normalized vectors",
            "where l·v < −1/2, components that cancel from (l_i²|v|² − v_i²|l|²)/(|l||v|(l_i|v| − v_i|l|)),"
            " with l_i²|v|² − v_i²|l|² = Σ_j (l_i v_j − v_i l_j)(l_i v_j + v_i l_j)",
        ),
        Rearrangement(
            "normalization path chosen per vector",
            "vec.normalize",
            "fast or scaled path for the whole batch",
            "per vector (a mirror pair l, R_l stays bit-symmetric whatever else is in the batch)",
        ),
        Rearrangement(
            "Blinn–Phong power far from the peak",
            "brdf.BlinnPhong._lobe, microfacet.blinn_phong_ndf",
            "exp(e log1p(−(1 − n·h))) everywhere",
            "(n·h)^e directly (pow) where n·h < 1/2",
        ),
        Rearrangement(
            "Phong / Blinn–Phong f_r divided in float64",
            "brdf.Phong._f, brdf.BlinnPhong._f, brdf._lobe_over_cos",
            "(k_s lobe / π) / (n·l) with the lobe rounded to the dtype (subnormal in float32)",
            "k_s lobe / (π n·l) in float64; exp(ln lobe − ln(π n·l)) where the lobe is subnormal in float64",
        ),
        Rearrangement(
            "Cook–Torrance D in float64 before the division",
            "brdf.CookTorrance._separable",
            "D rounded to the dtype, then D G F / (c (n·v)(n·l))",
            "D in float64 (its tail may be subnormal in float32 where f_r is not)",
        ),
        Rearrangement(
            "visibility G/((n·v)(n·l)) formed directly",
            "brdf.CookTorrance._visibility, microfacet._smith_g1_den_*",
            "D G / (c (n·v)(n·l))",
            "Smith: 4 / (d_v d_l), G1 = 2 cos/d;  V-cavity: min(1/((n·v)(n·l)), (2 n·h/v·h)/max(n·v, n·l))",
        ),
        Rearrangement(
            "dielectric Fresnel without a rounded η",
            "fresnel._dielectric_from_f0",
            "dielectric(v·h, η), η = (1 + √f0)/(1 − √f0) rounded",
            "r_par, r_perp multiplied through by (1 ∓ √f0): F(1) = f0 exactly",
        ),
        Rearrangement(
            "spot cone near its axis",
            "lights.SpotLight._spot",
            "cos ψ ≥ cos(cutoff),  (cos ψ)^e",
            "1 − cos ψ = |l + ŝ|²/2 ≤ 2 sin²(cutoff/2),  exp(e log1p(−(1 − cos ψ)))",
        ),
        Rearrangement(
            "Phong lobe from |R_l − v|²/2",
            "brdf.Geometry.one_minus_r_dot_v",
            "(R_l·v)^e, R_l·v = 2 (n·l)(n·v) − l·v",
            "exp(e log1p(−|R_l − v|²/2))",
            existing=True,
        ),
        Rearrangement(
            "tan²θ_h from the cross product",
            "brdf.Geometry.sin2_h, one_minus_n_dot_h",
            "sin²θ_h = 1 − cos²θ_h,  1 − n·h",
            "sin²θ_h = |n × h|²,  1 − n·h = sin²θ_h / (1 + n·h)",
            existing=True,
        ),
        Rearrangement(
            "microfacet terms in float64",
            "brdf.CookTorrance._separable",
            "D G F / (c (n·v)(n·l)) in float32 for float32 inputs",
            "in float64, rounded once at the end",
            existing=True,
        ),
    ]


def _legacy_engine(name, specs, cols, n, l, v):  # noqa: E741
    """Engine ``f_r`` values ``(m, len(cols), 3)`` with rearrangement ``name`` undone (NaN in other columns)."""
    import warnings

    from ..models.brdf import BlinnPhong, CookTorrance, Geometry, Phong

    lc = _legacy_classes()
    out = np.full((n.shape[0], len(cols), 3), np.nan)
    geom_cls = {
        "half vector near l = −v": lc["PlainSum"],
        "tan²θ_h from the cross product": lc["CosSquared"],
        "Phong lobe from |R_l − v|²/2": lc["TextbookRv"],
    }.get(name)
    ct_flag = {
        "Cook–Torrance D in float64 before the division": "d-dtype",
        "visibility G/((n·v)(n·l)) formed directly": "visibility",
        "dielectric Fresnel without a rounded η": "dielectric",
        "microfacet terms in float64": "float32",
    }.get(name)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if name == "normalization path chosen per vector":
            g = Geometry(*(_legacy_normalize(x) for x in (n, l, v)), unit=True)
        geoms: dict = {}
        for c, (si, form) in enumerate(cols):
            if form != "eval":  # f_r itself carries every rearranged formula; the other forms share them
                continue
            model = specs[si].model
            variant, gclass = None, Geometry
            if name == "normalization path chosen per vector":
                variant = model
            elif name == "Phong lobe from |R_l − v|²/2":
                if isinstance(model, Phong):
                    variant, gclass = model, geom_cls
            elif geom_cls is not None and isinstance(model, (BlinnPhong, CookTorrance)):
                variant, gclass = model, geom_cls
            elif name == "Blinn–Phong power far from the peak" and isinstance(model, BlinnPhong):
                variant = lc["BPPeakOnly"](**model._params())
            elif name == "Phong / Blinn–Phong f_r divided in float64" and isinstance(model, (Phong, BlinnPhong)):
                if isinstance(model, BlinnPhong) and model.normalized:
                    continue
                variant = lc["PhongDtypeDivision" if isinstance(model, Phong) else "BPDtypeDivision"](**model._params())
            elif ct_flag is not None and isinstance(model, CookTorrance):
                if ct_flag == "dielectric" and model.fresnel != "dielectric":
                    continue
                if ct_flag in ("float32", "d-dtype") and n.dtype != np.float32:
                    continue
                variant = _ct_variant(model, {ct_flag})
            if variant is None:
                continue
            if name != "normalization path chosen per vector":
                if gclass not in geoms:
                    geoms[gclass] = gclass(n, l, v)
                g = geoms[gclass]
            f = getattr(
                variant, {"eval": "eval_geometry", "eval_cos": "eval_cos_geometry"}.get(form, "classic_geometry")
            )
            out[:, c, :] = np.broadcast_to(f(g), (n.shape[0], 3))
    return out


def _legacy_light(specs, cases, dt):
    import warnings

    lc = _legacy_classes()
    m = len(cases)
    vals = np.full((m, len(LIGHT_FORMS), 3), np.nan)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for si in sorted({c.spec for c in cases}):
            sp = specs[si]
            if sp.cutoff_deg is None:
                continue
            light = lc["LegacySpot"](
                sp.position, 1.0, sp.intensity, sp.attenuation, direction=sp.direction, cutoff_deg=sp.cutoff_deg,
                exponent=sp.exponent,
            )  # fmt: skip
            idx = [i for i, c in enumerate(cases) if c.spec == si]
            pts = np.array([cases[i].point for i in idx], dtype=dt)
            inc = next(light.incident(pts, dtype=dt))
            vals[idx, 0, :] = np.asarray(inc.scale, dtype=np.float64)[:, None]
            vals[idx, 1, :] = np.broadcast_to(np.asarray(inc.irradiance, dtype=np.float64), (len(idx), 3))
    return vals


def _worst(cls, ratio, ok, mask):
    """``(worst ratio over normal points, failing values)`` within ``mask`` (columns that were evaluated)."""
    r = np.where(mask & (cls == NORMAL), ratio, -1.0)
    worst = float(r.max()) if r.size else 0.0
    return max(worst, 0.0), int(np.sum(mask & ~ok))


# ============================================================================ summary
@dataclass
class SummaryRow:
    """One model variant × case family × dtype × form of the sweep.

    ``max_rel_err`` is the largest relative error among the points whose true
    value is a normal number of the dtype (and that are not edge points);
    ``worst_*`` are the inputs of that point (for BRDFs ``n``, ``l``, ``v``; for
    lights the surface point, the light position and the spot axis), each as
    three ``repr`` floats.  ``max_ratio`` is the largest ``err / (max(κ,1) u)``:
    the row meets the bound when it is <= 8.
    """

    model_family: str
    model: str
    case_family: str
    dtype: str
    form: str
    points: int = 0
    nonfinite: int = 0
    negative: int = 0
    warnings: int = 0
    normal: int = 0
    ill: int = 0
    edge: int = 0
    zero: int = 0
    over: int = 0
    under: int = 0
    failures: int = 0
    max_rel_err: float = 0.0
    kappa_at_max_err: float = float("nan")
    max_ratio: float = 0.0
    kappa_at_max_ratio: float = float("nan")
    worst_case: str = ""
    worst_ratio_case: str = ""
    worst_a: str = ""
    worst_b: str = ""
    worst_c: str = ""
    worst_engine: float = float("nan")
    worst_reference: float = float("nan")
    mono_pairs: int = 0
    mono_fail: int = 0
    lobe_monotone: bool = True
    recip_pairs: int = 0
    recip_fail: int = 0
    recip_max_ratio: float = 0.0
    ill_max_ratio: float = 0.0
    first_failure: str = ""

    @property
    def passed(self) -> bool:
        return (
            self.nonfinite == 0
            and self.negative == 0
            and self.warnings == 0
            and self.failures == 0
            and self.mono_fail == 0
            and self.recip_fail == 0
            and not self.max_ratio > BOUND_FACTOR
        )


@dataclass
class StabilityResult:
    """Everything :func:`run` measured (see :class:`SummaryRow`)."""

    rows: list
    points: dict
    dtypes: tuple
    n_brdf_cases: int
    n_light_cases: int
    seconds: dict = field(default_factory=dict)
    rearrangements: list = field(default_factory=list)

    @property
    def passed(self) -> bool:
        return all(r.passed for r in self.rows)


def _vec_str(x) -> str:
    return " ".join(repr(float(c)) for c in x)


def _binary(x, dt) -> list:
    """The components of ``x`` rounded to ``dt``, as exact Python floats."""
    return np.asarray(x, dtype=dt).astype(np.float64).tolist()


def _run_jobs(jobs, workers, progress):
    """Run ``(fn, args, count)`` jobs, in worker processes when ``workers > 1``; results in job order."""
    results = [None] * len(jobs)
    if workers <= 1 or len(jobs) <= 1:
        for i, (fn, args, count) in enumerate(jobs):
            results[i] = fn(*args)
            if progress:
                progress(count)
        return results
    import concurrent.futures as cf
    import multiprocessing
    import warnings

    # The workers only run mpmath on their inputs; fork starts them in milliseconds and, unlike
    # spawn, does not re-import the caller's main module (which may be stdin or a notebook).
    methods = multiprocessing.get_all_start_methods()
    ctx = multiprocessing.get_context("fork" if "fork" in methods else "spawn")
    with warnings.catch_warnings(), cf.ProcessPoolExecutor(max_workers=workers, mp_context=ctx) as ex:
        warnings.simplefilter("ignore", DeprecationWarning)  # Python >= 3.12 warns about fork with threads
        futs = {ex.submit(fn, *args): i for i, (fn, args, _) in enumerate(jobs)}
        for f in cf.as_completed(futs):
            i = futs[f]
            results[i] = f.result()
            if progress:
                progress(jobs[i][2])
    return results


def _batches(items, size):
    return [items[i : i + size] for i in range(0, len(items), size)]


def _sweep_pairs(cases) -> tuple[np.ndarray, np.ndarray]:
    """Index pairs ``(a, b)`` of consecutive points of every sweep (``b`` one step further from the peak)."""
    groups: dict = {}
    for i, c in enumerate(cases):
        if c.sweep:
            groups.setdefault((c.family, c.sweep), []).append(i)
    a, b = [], []
    for idx in groups.values():
        idx = sorted(idx, key=lambda i: cases[i].step)
        a += idx[:-1]
        b += idx[1:]
    return np.array(a, dtype=int), np.array(b, dtype=int)


def _order_stats(pa, pb, ref, k1, eng, cls, u, tiny):
    """Per column: pairs whose true values differ by more than both error bounds, pairs the engine
    orders differently, and whether the true values never increase along the sweep."""
    if not len(pa):
        k = ref.shape[1]
        return np.zeros(k, int), np.zeros(k, int), np.ones(k, bool)
    ra, rb = ref[pa], ref[pb]
    skip = np.isin(cls[pa], (EDGE, ZERO)) | np.isin(cls[pb], (EDGE, ZERO))
    with np.errstate(invalid="ignore", over="ignore"):
        slack = BOUND_FACTOR * u * (k1[pa] * ra + k1[pb] * rb) + 2 * tiny
        sig = ~skip & (np.abs(ra - rb) > slack)
    ea, eb = eng[pa].max(axis=-1), eng[pb].max(axis=-1)
    wrong = sig & (((ra > rb) & ~(ea >= eb)) | ((ra < rb) & ~(ea <= eb)))
    monotone = ~np.any(~skip & (rb > ra * (1 + 1e-40)), axis=0)
    return sig.sum(axis=0), wrong.sum(axis=0), monotone


def _group_rows(rows_out, points_out, sel, meta, cls, err, ratio, ok, eng, ref, kappa, cases, dtname, dt, extra):
    """Append one :class:`SummaryRow` per column for the points ``sel`` (one case family)."""
    c_ = cls[sel]
    e_ = eng[sel]
    finite = np.all(np.isfinite(e_), axis=-1)
    neg = np.any(e_ < 0, axis=-1)
    counts = {name: np.sum(c_ == code, axis=0) for code, name in enumerate(CLASSES)}
    fails = ~ok[sel]
    errn = np.where(c_ == NORMAL, err[sel], -1.0)
    ratn = np.where(c_ == NORMAL, ratio[sel], -1.0)
    rati = np.where((c_ == ILL) & np.isfinite(ratio[sel]), ratio[sel], -1.0)
    ie, ir, ff = errn.argmax(axis=0), ratn.argmax(axis=0), fails.argmax(axis=0)
    big = float(np.finfo(dt).max)
    for c, (family, model, form) in enumerate(meta):
        if form is None:
            continue
        r = SummaryRow(family, model, cases[sel[0]].family, dtname, form)
        r.points = len(sel)
        r.nonfinite = int(np.sum(~finite[:, c]))
        r.negative = int(np.sum(neg[:, c]))
        r.warnings = extra["warnings"]
        for name in CLASSES:
            setattr(r, name, int(counts[name][c]))
        r.failures = int(np.sum(fails[:, c]))
        if r.failures:
            i = sel[ff[c]]
            r.first_failure = (
                f"{cases[i].label} [{CLASSES[cls[i, c]]}: engine {eng[i, c].max():.9g}, true {ref[i, c]:.9g}]"
            )
        if errn[ie[c], c] >= 0:
            i, j = sel[ie[c]], sel[ir[c]]
            r.max_rel_err, r.kappa_at_max_err = float(err[i, c]), float(kappa[i, c])
            r.max_ratio, r.kappa_at_max_ratio = float(ratio[j, c]), float(kappa[j, c])
            r.worst_case, r.worst_ratio_case = cases[i].label, cases[j].label
            cs = cases[i]
            if isinstance(cs, BrdfCase):
                r.worst_a, r.worst_b, r.worst_c = (_vec_str(_binary(x, dt)) for x in (cs.n, cs.l, cs.v))
            else:
                r.worst_a = _vec_str(_binary(cs.point, dt))
            r.worst_engine, r.worst_reference = float(eng[i, c].max()), float(ref[i, c])
        if rati[:, c].max() >= 0:
            r.ill_max_ratio = float(rati[:, c].max())
        keep = (c_[:, c] == NORMAL) | (c_[:, c] == ILL)
        if np.any(keep):
            # The error as judged: relative for normal points, |ln(f/f_true)| for ill-conditioned ones.
            kk = kappa[sel, c][keep]
            judged = ratio[sel, c][keep] * np.maximum(kk, 1.0) * unit_roundoff(dt)
            points_out.append((judged, kk, c_[keep, c] == ILL, dtname, family, r.case_family, form))
        if "mono" in extra and c in extra["mono"]:
            r.mono_pairs, r.mono_fail, r.lobe_monotone = extra["mono"][c]
        if "recip" in extra and c in extra["recip"]:
            q, a, b = extra["recip"][c]
            cc = c_[:, c]
            qs, as_, bs = q[sel], a[sel], b[sel]
            normal = cc == NORMAL
            r.recip_pairs = int(np.sum(normal | (cc == ZERO) | (cc == OVER)))
            r.recip_max_ratio = float(qs[normal].max()) if np.any(normal) else 0.0
            r.recip_fail = int(
                np.sum(normal & (qs > 2 * BOUND_FACTOR))
                + np.sum((cc == ZERO) & ~((as_ == 0) & (bs == 0)))
                + np.sum((cc == OVER) & ~((as_ == big) & (bs == big)))
            )
        rows_out.append(r)


def run(
    quick: bool = False,
    dtypes: Sequence = (np.float32, np.float64),
    *,
    workers: int | None = None,
    progress: Callable[[int], None] | None = None,
    on_start: Callable[[int], None] | None = None,
    rearrangements: bool = True,
) -> StabilityResult:
    """Run the sweep: every model and light, every case family, every dtype.

    Parameters
    ----------
    quick : bool
        Fewer points per case family (every family and extreme is still there).
    dtypes : sequence of {np.float32, np.float64}
    workers : int, optional
        Processes for the mpmath references (default: up to 2, one per core).
    progress : callable, optional
        Called with the number of inputs finished, as references complete.
    on_start : callable, optional
        Called once with the total number of inputs before the work starts.
    rearrangements : bool
        Also evaluate the engine with each rearranged formula of
        :func:`rearrangement_list` put back, one at a time, on the same references
        (``StabilityResult.rearrangements``).

    Returns
    -------
    StabilityResult
    """
    t0 = time.perf_counter()
    dtypes = tuple(np.dtype(d).type for d in dtypes)
    cases = brdf_cases(quick)
    lcases = light_cases(quick)
    specs = brdf_specs()
    lspecs = light_specs()
    cols = _columns(specs, _brdf_forms)
    if workers is None:
        workers = max(1, min(2, os.cpu_count() or 1))
    jobs = []
    for dt in dtypes:
        inputs = [(_binary(c.n, dt), _binary(c.l, dt), _binary(c.v, dt), bool(c.sweep)) for c in cases]
        jobs += [(_ref_table, ("brdf", np.dtype(dt).name, b), len(b)) for b in _batches(inputs, 6)]
    for dt in dtypes:
        inputs = [(c.spec, _binary(c.point, dt)) for c in lcases]
        jobs += [(_ref_table, ("light", np.dtype(dt).name, b), len(b)) for b in _batches(inputs, 40)]
    if on_start:
        on_start(len(cases) * len(dtypes) + len(lcases) * len(dtypes))
    results = _run_jobs(jobs, workers, progress)
    t_ref = time.perf_counter() - t0

    nb = len(_batches(list(range(len(cases))), 6))
    nl = len(_batches(list(range(len(lcases))), 40))

    def merge(parts):
        return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}

    rows: list[SummaryRow] = []
    points: list = []
    t1 = time.perf_counter()
    fam_rows = {f: np.flatnonzero([c.family == f for c in cases]) for f in CASE_FAMILIES}
    pa, pb = _sweep_pairs(cases)
    fam_of = np.array([c.family for c in cases], dtype=object)
    pred_sel = np.array([[p in specs[si].predicates for p in PREDICATES] for si, _ in cols])
    meta = [(specs[si].family, specs[si].label, form if form in BRDF_FORMS else None) for si, form in cols]
    lobe_of = {}  # carrier column -> lobe column (the lobe's order checks are reported on the carrier row)
    for c, (si, form) in enumerate(cols):
        sp = specs[si]
        carrier = "eval" if sp.lobe == "D" else sp.lobe
        if sp.lobe and form == carrier:
            lobe_of[c] = cols.index((si, sp.lobe))
    rearr = rearrangement_list() if rearrangements else []
    for di, dt in enumerate(dtypes):
        dtname = np.dtype(dt).name
        u = unit_roundoff(dt)
        tiny = float(np.finfo(dt).tiny)
        ref = merge(results[di * nb : (di + 1) * nb])
        n = np.array([c.n for c in cases], dtype=dt)
        l = np.array([c.l for c in cases], dtype=dt)  # noqa: E741
        v = np.array([c.v for c in cases], dtype=dt)
        eng, swapped, nwarn = _engine_brdf(specs, cols, n, l, v)
        edge = np.any((ref["pred"][:, None, :] * (BOUND_FACTOR * u) >= 1) & pred_sel[None], axis=-1)
        cls, err, ratio, ok = _classify(ref["hi"], ref["lo"], ref["nz"], ref["kappa"], ref["logref"], edge, eng, dt)
        # The image path (all directional lights at once) is held to the same bound: each
        # point reports the worse of the two paths.
        eng_s, nwarn_s = _engine_brdf_stacked(specs, cols, n, l, v, eng)
        _, err_s, ratio_s, ok_s = _classify(
            ref["hi"], ref["lo"], ref["nz"], ref["kappa"], ref["logref"], edge, eng_s, dt
        )
        ok &= ok_s
        err, ratio = np.fmax(err, err_s), np.fmax(ratio, ratio_s)
        nwarn += nwarn_s
        eng = np.where(np.isfinite(eng_s) & (eng_s >= 0), eng, eng_s)  # a bad stacked value is counted too
        refv = ref["hi"] + ref["lo"]
        k1 = np.maximum(np.nan_to_num(ref["kappa"], nan=1.0), 1.0)
        recip = {}
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            for c, sw in swapped.items():
                a, b = eng[:, c].max(axis=-1), sw.max(axis=-1)
                recip[c] = (np.abs(a - b) / (refv[:, c] * k1[:, c] * u), a, b)
        lobe_cols = sorted(lobe_of)
        for fam in CASE_FAMILIES:
            sel = fam_rows[fam]
            if not len(sel):
                continue
            mono = {}
            fam_pairs = fam_of[pa] == fam if len(pa) else np.zeros(0, bool)
            if np.any(fam_pairs):
                lc = [lobe_of[c] for c in lobe_cols]
                sig, wrong, monotone = _order_stats(
                    pa[fam_pairs], pb[fam_pairs], refv[:, lc], k1[:, lc], eng[:, lc], cls[:, lc], u, tiny
                )
                mono = {c: (int(sig[j]), int(wrong[j]), bool(monotone[j])) for j, c in enumerate(lobe_cols)}
            # Cook–Torrance's D (not masked by the horizon) is checked for finiteness and sign on the eval row.
            extra = {"warnings": nwarn, "mono": mono, "recip": recip}
            start = len(rows)
            _group_rows(rows, points, sel, meta, cls, err, ratio, ok, eng, refv, ref["kappa"], cases, dtname, dt, extra)
            by_col = {(r.model, r.form): r for r in rows[start:]}
            for c, lc in lobe_of.items():
                si, form = cols[c]
                if cols[lc][1] == "D":
                    e = eng[sel, lc]
                    r = by_col[(specs[si].label, form)]
                    r.nonfinite += int(np.sum(~np.all(np.isfinite(e), axis=-1)))
                    r.negative += int(np.sum(np.any(e < 0, axis=-1)))

        if rearrangements:
            form_ok = np.array([form in BRDF_FORMS for _, form in cols])
            for rr in rearr:
                if rr.name == "spot cone near its axis":
                    continue
                leg = _legacy_engine(rr.name, specs, cols, n, l, v)
                mask = np.isfinite(leg).all(axis=-1).any(axis=0) & form_ok
                if not np.any(mask):
                    continue
                mask = np.broadcast_to(mask, cls.shape)
                lcls_, _, lratio_, lok_ = _classify(
                    ref["hi"], ref["lo"], ref["nz"], ref["kappa"], ref["logref"], edge, np.nan_to_num(leg, nan=-1.0), dt
                )
                rr.before[dtname] = _worst(lcls_, lratio_, lok_, mask)
                rr.after[dtname] = _worst(cls, ratio, ok, mask)

        lref = merge(results[len(dtypes) * nb + di * nl : len(dtypes) * nb + (di + 1) * nl])
        leng, lwarn = _engine_light(lspecs, lcases, dt)
        ledge = lref["pred"][:, :1] * (BOUND_FACTOR * u) >= 1
        ledge = np.broadcast_to(ledge, lref["hi"].shape)
        lcls, lerr, lratio, lok = _classify(
            lref["hi"], lref["lo"], lref["nz"], lref["kappa"], lref["logref"], ledge, leng, dt
        )
        lrefv = lref["hi"] + lref["lo"]
        lk1 = np.maximum(np.nan_to_num(lref["kappa"], nan=1.0), 1.0)
        if rearrangements:
            leg = _legacy_light(lspecs, lcases, dt)
            spot = np.isfinite(leg).all(axis=-1)
            c2, _, r2, o2 = _classify(
                lref["hi"],
                lref["lo"],
                lref["nz"],
                lref["kappa"],
                lref["logref"],
                ledge,
                np.nan_to_num(leg, nan=-1.0),
                dt,
            )
            for rr in rearr:
                if rr.name == "spot cone near its axis":
                    rr.before[dtname] = _worst(c2, r2, o2, spot)
                    rr.after[dtname] = _worst(lcls, lratio, lok, spot)
        la, lb = _sweep_pairs(lcases)
        spec_of = np.array([c.spec for c in lcases])
        for si, sp in enumerate(lspecs):
            for fam in LIGHT_CASE_FAMILIES:
                sel = np.flatnonzero((spec_of == si) & np.array([c.family == fam for c in lcases]))
                if not len(sel):
                    continue
                inpair = np.isin(la, sel)
                sig, wrong, monotone = _order_stats(
                    la[inpair], lb[inpair], lrefv[:, :1], lk1[:, :1], leng[:, :1], lcls[:, :1], u, tiny
                )
                extra = {"warnings": lwarn, "mono": {0: (int(sig[0]), int(wrong[0]), bool(monotone[0]))}}
                lmeta = [(sp.family, sp.label, form) for form in LIGHT_FORMS]
                _group_rows(
                    rows, points, sel, lmeta, lcls, lerr, lratio, lok, leng, lrefv, lref["kappa"], lcases, dtname, dt,
                    extra,
                )  # fmt: skip
    pts = {}
    if points:
        pts = {
            "err": np.concatenate([p[0] for p in points]),
            "kappa": np.concatenate([p[1] for p in points]),
            "ill": np.concatenate([p[2] for p in points]),
            "dtype": np.concatenate([np.full(len(p[0]), p[3], dtype=object) for p in points]),
            "model_family": np.concatenate([np.full(len(p[0]), p[4], dtype=object) for p in points]),
            "case_family": np.concatenate([np.full(len(p[0]), p[5], dtype=object) for p in points]),
            "form": np.concatenate([np.full(len(p[0]), p[6], dtype=object) for p in points]),
        }
    t_eng = time.perf_counter() - t1
    return StabilityResult(
        rows,
        pts,
        tuple(np.dtype(d).name for d in dtypes),
        len(cases),
        len(lcases),
        {"reference": t_ref, "engine_and_checks": t_eng, "total": time.perf_counter() - t0},
        [rr for rr in rearr if rr.before],
    )
