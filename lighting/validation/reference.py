"""The mpmath references of the stability sweep: values and condition numbers at 80 digits."""

from __future__ import annotations

import numpy as np

from .cases import (
    DELTA,
    F0,
    KD,
    KS,
    REFERENCE_DPS,
    ROUGHNESS,
    SHININESS,
    LightSpec,
    perturbed_inputs,
)


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
    for i, j, xp in perturbed_inputs(x, d):
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
    for i, j, xp in perturbed_inputs(x, d):
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

    Parameters
    ----------
    n, l, v : sequence of float
        The components, exactly as the engine sees them.
    dps : int
        Decimal digits of the mpmath arithmetic.
    delta : float
        The relative perturbation of the condition numbers.

    Returns
    -------
    dict
    """
    mp = _mp()
    with mp.workdps(dps):
        x = [mp.mpf(float(c)) for c in (*n, *l, *v)]
        above, values, grads = _brdf_gradients(mp, x, delta)
        return {"above": above, "values": values, "grad": grads}


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

    Parameters
    ----------
    spec : LightSpec
    point : sequence of float
        The surface point.
    dps : int
    delta : float

    Returns
    -------
    dict
    """
    mp = _mp()
    with mp.workdps(dps):
        S = spec.direction if spec.direction is not None else (0.0, 0.0, 0.0)
        x = [mp.mpf(float(c)) for c in (*point, *spec.position, *S)]
        base, grads = _light_gradients(mp, x, spec, delta)
        return {"above": True, "values": {k: v for k, v in base.items() if k != "above"}, "grad": grads}
