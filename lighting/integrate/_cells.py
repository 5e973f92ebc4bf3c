r"""The areas of light of the dominant-light method, cell by cell: ``Σ_c f_r(v, l_c) (n·l_c) Φ_c`` per pixel.

Every pixel meets every cell, so the BRDF is read from a table rather than evaluated: an isotropic part's
``f_r (n·l)`` depends only on the view's and the light's angles from the normal, ``θ_v`` and ``θ_l``, and on the
azimuth ``φ`` between them, ``cos φ = (v·l − cos θ_v cos θ_l) / (sin θ_v sin θ_l)``.  The table holds it at
:data:`VIEW_ROWS` × :data:`LIGHT_ROWS` × :data:`AZIMUTH_ROWS` points (once per part), the azimuth evenly in
``cos(φ/2) = √((1 + cos φ)/2)``: finest toward ``φ = π``, the plane of the mirror direction where a glossy
lobe peaks, and no arc cosine to take.  A pixel–cell pair reads it trilinearly: eight gathers of 16-byte
RGBA texels and a weighted sum, where the model's own evaluation costs tens of passes over the pairs.  An
anisotropic part (``BRDFFlags.ANISOTROPIC``) is evaluated pair by pair.
"""

from __future__ import annotations

import math

import numpy as np

from .._recent import Recent
from ..models.base import BRDFFlags
from ..shading.batch import in_blocks

#: Rows of the cosine-weighted BRDF table in ``θ_v`` (0 to :data:`VIEW_LIMIT`) and ``θ_l`` (0 to 90°), each evenly
#: spaced, and in ``cos(φ/2)`` (1 to 0: ``φ`` from 0 to 180°).
VIEW_ROWS, LIGHT_ROWS, AZIMUTH_ROWS = 91, 65, 129
#: The largest view angle of the table (radians); a grazing pixel reads this row (the BRDF is 0 at 90°).
VIEW_LIMIT = math.radians(89.5)
#: Pixel–cell pairs whose table reads are made at once: a block's arrays stay within the processor's cache.
_BLOCK = 1 << 14
#: The tables of the parts met last (each holds ``VIEW_ROWS × LIGHT_ROWS × AZIMUTH_ROWS`` texels of 16 bytes).
_tables = Recent(8)
#: View rows of a table evaluated at once (:func:`cosine_table`).
_VIEW_BLOCK = 8


def cosine_table(part):
    """``f_r (n·l)`` of an isotropic part over ``(θ_v, θ_l, φ)`` (module notes): flat RGBA texels, complex128."""
    key = (type(part).__qualname__, repr(part))
    found = _tables.get(key)
    if found is not None:
        return found
    views = np.linspace(0.0, VIEW_LIMIT, VIEW_ROWS)
    tl = np.linspace(0.0, math.pi / 2, LIGHT_ROWS)[None, :, None]
    ph = 2 * np.arccos(np.linspace(1.0, 0.0, AZIMUTH_ROWS))[None, None, :]
    l = np.stack(np.broadcast_arrays(np.sin(tl) * np.cos(ph), np.sin(tl) * np.sin(ph), np.cos(tl)), axis=-1)  # noqa: E741
    rgba = np.zeros((VIEW_ROWS, LIGHT_ROWS, AZIMUTH_ROWS, 4), dtype=np.float32)
    # A few view rows at a time: the model's evaluation over the whole table at once would hold a hundred MiB of
    # temporaries; each value is the same computed either way.
    for start in range(0, VIEW_ROWS, _VIEW_BLOCK):
        tv = views[start : start + _VIEW_BLOCK, None, None]
        v = np.stack(np.broadcast_arrays(np.sin(tv), 0 * tv, np.cos(tv)), axis=-1)
        g = np.asarray(part.eval_cos(np.array([0.0, 0.0, 1.0]), l, v), dtype=np.float64)
        g[:, -1] = 0.0  # l on the horizon
        rgba[start : start + len(tv), ..., :3] = g
    return _tables.put(key, rgba.reshape(-1, 4).view(np.complex128).reshape(-1))


def cell_sum(part, directions, power, n, v, cos_v):
    """``Σ_c f_r(v, l_c) (n·l_c) Φ_c`` per pixel: cells toward ``directions`` (C, 3) of ``power`` (C, 3).

    ``n``, ``v`` (P, 3) and ``cos_v`` (P,) float32 (``n·v > 0`` where it matters); returns (P, 3) float64.
    """
    if BRDFFlags.ANISOTROPIC in part.flags:
        return _cell_exact(part, directions, power, n, v)
    table = cosine_table(part)
    lc = directions.astype(np.float32)
    cells = lc.shape[0]
    # The cells' powers beside each of a pair's eight taps, as the taps are laid out below.
    pw = np.zeros((8 * cells, 4), dtype=np.float32)
    pw[:, :3] = np.tile(power.astype(np.float32), (8, 1))
    fv = np.minimum(np.arccos(np.clip(cos_v, 0, 1)), np.float32(VIEW_LIMIT)) * np.float32((VIEW_ROWS - 1) / VIEW_LIMIT)
    iv = np.minimum(fv.astype(np.int32), VIEW_ROWS - 2)
    tv = (fv - iv)[:, None]
    sin_v = np.sqrt(np.maximum(1 - cos_v * cos_v, 0))[:, None]
    cos_v = cos_v[:, None]
    kl = np.float32((LIGHT_ROWS - 1) / (math.pi / 2))
    kp = np.float32(AZIMUTH_ROWS - 1)
    one, tiny = np.float32(1), np.float32(1e-12)
    out = np.zeros(n.shape, dtype=np.float64)
    plane, row = LIGHT_ROWS * AZIMUTH_ROWS, AZIMUTH_ROWS

    def block(s):
        mu_l = n[s] @ lc.T  # (p, C)
        vl = v[s] @ lc.T
        sin_l = np.sqrt(np.maximum(one - mu_l * mu_l, 0))
        cos_p = np.clip((vl - cos_v[s] * mu_l) / np.maximum(sin_v[s] * sin_l, tiny), -one, one)
        fl = np.arccos(np.clip(mu_l, 0, one)) * kl
        fp = (one - np.sqrt((one + cos_p) * np.float32(0.5))) * kp  # 1 − cos(φ/2): the rows run from φ = 0
        il = np.minimum(fl.astype(np.int32), LIGHT_ROWS - 2)
        ip = np.minimum(fp.astype(np.int32), AZIMUTH_ROWS - 2)
        tl, tp = fl - il, fp - ip
        base = iv[s, None] * plane + il * row + ip
        up = np.where(mu_l > 0, one, np.float32(0))  # below the horizon: nothing
        w0, w1 = up * (one - tv[s]), up * tv[s]
        p = base.shape[0]
        # The eight taps' indices and weights written in place, tap after tap.
        index = np.empty((p, 8, cells), dtype=base.dtype)
        weight = np.empty((p, 8, cells), dtype=np.result_type(w0, tl, tp))
        tp0 = one - tp
        tap = 0
        for dv, wv in ((0, w0), (plane, w1)):
            for dl, wl in ((0, one - tl), (row, tl)):
                wvl = wv * wl
                np.add(base, dv + dl, out=index[:, tap])
                np.add(base, dv + dl + 1, out=index[:, tap + 1])
                np.multiply(wvl, tp0, out=weight[:, tap])
                np.multiply(wvl, tp, out=weight[:, tap + 1])
                tap += 2
        texel = np.take(table, index.reshape(p, -1)).view(np.float32).reshape(p, 8 * cells, 4)
        # Each tap times its cell's power in float32, held in the dtype of the weighted sum that reads it.
        texel = np.multiply(texel, pw, out=np.empty(texel.shape, dtype=weight.dtype), dtype=np.float32)
        out[s] = np.matmul(weight.reshape(p, 1, -1), texel)[:, 0, :3]

    in_blocks(n.shape[0], max(1, _BLOCK // max(cells, 1)), block)
    return out


def _cell_exact(part, directions, power, n, v, chunk=1 << 16):
    """:func:`cell_sum` by the part's own evaluation, for the (pixel, cell) pairs above the pixel's horizon."""
    out = np.zeros(n.shape, dtype=np.float64)
    lc = directions.astype(n.dtype)
    pc = power.astype(np.float64)
    step = max(1, chunk // max(len(lc), 1))
    for i in range(0, n.shape[0], step):
        nn, vv = n[i : i + step], v[i : i + step]
        cos_l = nn @ lc.T
        p_idx, c_idx = np.nonzero(cos_l > 0)
        if not p_idx.size:
            continue
        f = np.asarray(part.eval(nn[p_idx], lc[c_idx], vv[p_idx]), dtype=np.float64)
        contrib = f * (cos_l[p_idx, c_idx].astype(np.float64)[:, None] * pc[c_idx])
        for c in range(3):
            out[i : i + step, c] += np.bincount(p_idx, contrib[:, c], nn.shape[0])
    return out
