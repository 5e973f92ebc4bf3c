r"""Image-based lighting within a few percent: the dominant lights shaded exactly, the rest filtered.

The split sum (:func:`lighting.integrate.ibl.split_sum_radiance`) reads one prefiltered value per lobe: a
round lobe about the mirror direction, which is far off where the sky holds a small, very bright source
(a sun) or where the lobe is wide and bent toward the normal at grazing views.  The method of this module
(``EnvironmentLight(method="dominant")``) splits the environment in two:

* **the dominant lights** — the brightest connected regions of the map, found by
  :func:`~lighting.integrate.extraction.find_dominant_lights` (luminance above ``DOMINANT_THRESHOLD`` times the
  map's mean, at most ``DOMINANT_MAX_SOLID_ANGLE`` each, the ``DOMINANT_MAX_LIGHTS`` most powerful kept) — each
  replaced by a disk light of the same solid angle, direction (the power-weighted mean) and power (the region's
  radiance above its surroundings' level), shaded with the model's own BRDF: ``f_r(v, l) (n·l) E`` at stratified
  points of the disk;
* **the residual** — the map with those regions filled with their surroundings' level — is read through
  its own prefiltered levels: a diffuse lobe by the exact irradiance map of the residual
  (:func:`lighting.integrate.prefilter.irradiance_map`, not SH9), a glossy lobe by *filtered importance
  sampling* (Colbert & Křivánek 2007): ``samples`` directions drawn from the part's own sampler at fixed
  stratified points (tabulated per view angle), each reading the level whose width matches its share of
  the lobe, ``σ_k = c_σ √(1 / (2π N p_k))``, weighted by ``f_r (n·l) / p`` and normalized, times the
  part's exact directional albedo ``ρ(μ_v)`` (the tables of the split sum).  The lobe's true shape —
  stretched at grazing views, bent toward the normal, cut by the horizon — is what the samples follow;
* **the areas of light** — what is still bright in the residual (above ``AREA_THRESHOLD`` times its mean: a
  studio's soft boxes, a sky's glow; :func:`~lighting.integrate.extraction.find_area_cells`) — are, for a lobe at
  least :data:`WIDE_LOBE` wide, cut into the cells of a coarse lat-long grid (``AREA_CELL_ROWS`` rows), each shaded
  like a small light with the BRDF (read from a table of the part's ``f_r (n·l)`` over the view's and the light's
  angles, :mod:`lighting.integrate._cells`), and only the calm rest is filtered; a narrower lobe reads them by its
  filtered samples.

A lobe narrower than :data:`WIDE_LOBE` reads everything by its samples, :data:`NARROW_FACTOR` times as many
(:data:`MID_FACTOR` from :data:`MID_LOBE`: :func:`sample_count`): the sharp edges of large bright areas (a studio's
boxes) and what its long tails gather from them over a dark ground need them.  A narrow GGX or Beckmann lobe's
half vectors (``D(h)(n·h)`` sampling, which does not depend on the view) stay fixed in a frame turning smoothly
with the normal, and each pixel reflects its own view about them: samples turning with the plane of incidence would
spin about the point facing the viewer and draw a pinwheel there.  Where it errs most is there, and on coarse
maps; the accuracy report gives the numbers.

An ideal mirror part reflects ``R(μ_v) L(r)`` of the whole map, exactly as in the split sum.

The extraction, the residual's levels and its irradiance map are computed once per environment (cached
on the prefiltered environment's base: a turned or scaled light reuses them), and the sample tables once per
part; a re-shade is then, for the pixels that face the viewer, the lights' BRDF evaluations, the cells' table
reads and ``samples`` lookups per glossy part and pixel, each a few multiply-adds and four gathers of texels
that hold both levels a sample blends (:mod:`lighting.integrate._fis`).  How close it comes to the
Monte-Carlo reference, and at what cost, is measured by ``lighting-explorer report accuracy --only ibl``
and ``lighting-explorer bench --ibl``.

References
----------
M. Colbert and J. Křivánek, "GPU-based importance sampling", GPU Gems 3, ch. 20, 2007.
B. Karis, "Real Shading in Unreal Engine 4", SIGGRAPH 2013 course notes.
"""

from __future__ import annotations

import functools
import math
import weakref

import numpy as np

from .._budget import check_budget
from .._recent import Recent
from .._validate import check_bool, check_count, check_vectors
from ..models.base import BRDFFlags
from ..numerics import working_dtype
from ..sampling.brdf import _check_brdf
from ..shading.batch import _threads, in_blocks
from ..vec import _dot
from ._cells import cell_sum
from ._delta import delta_albedo, split_delta
from ._fis import BLOCK_BYTES, LevelStack, OneLevel, half_vector_mean, view_table_mean
from ._normalgrid import GRID_DENSITY, GRID_SHARE, NormalGrid, grid_points, grid_spacing
from .extraction import (
    AREA_CELL_ROWS,
    AREA_THRESHOLD,
    DOMINANT_MAX_LIGHTS,
    DOMINANT_MAX_SOLID_ANGLE,
    DOMINANT_THRESHOLD,
    find_area_cells,
    find_dominant_lights,
)
from .ibl import _albedo_columns, _check_prefiltered, lobe_albedo, lobe_sigma
from .prefilter import kernel_of_lobe

__all__ = [
    "DOMINANT_SAMPLES",
    "NARROW_FACTOR",
    "MID_LOBE",
    "MID_FACTOR",
    "sample_count",
    "DominantEnvironment",
    "dominant_environment",
    "dominant_radiance",
]

#: Filtered-importance samples per glossy part and pixel (the default of :func:`dominant_radiance`).
DOMINANT_SAMPLES = 16
#: A glossy lobe at least this wide (``σ`` of :func:`lighting.integrate.ibl.lobe_sigma`, radians) reads the areas
#: of light cell by cell, and filtered samples only the rest; a narrower one reads everything by filtered samples.
#: Under the studio's sharp-edged boxes the samples of a lobe just below this width spread the boxes' edges (each
#: sample in its tail reads a wide level), where the cells hold the edge: from GGX α ≈ 0.13 the cells are the closer
#: of the two (``report accuracy --only ibl`` measures the method's lobes).
WIDE_LOBE = 0.18
#: A glossy lobe narrower than :data:`MID_LOBE` takes this many times ``samples`` filtered samples.
NARROW_FACTOR = 4
#: A glossy lobe from this width (radians) up to :data:`WIDE_LOBE` takes :data:`MID_FACTOR` times ``samples``.  Each
#: sample's blur grows with the lobe's width over the square root of the samples' count, and a box's edge is sharp
#: in absolute angle: under the studio the lobes just below :data:`WIDE_LOBE` spread its edges past the targets with
#: the narrow lobes' count (``report accuracy --only ibl`` measures the method).
MID_LOBE = 0.09
#: The factor of the lobes from :data:`MID_LOBE` to :data:`WIDE_LOBE`.
MID_FACTOR = 8
#: Rows of the grid of normals per lobe width ``σ`` for a lobe narrower than :data:`WIDE_LOBE` (a wider one:
#: :data:`~lighting.integrate._normalgrid.GRID_DENSITY`; a narrow microfacet lobe: :data:`HALF_GRID_DENSITY`).  Its
#: points cost :data:`NARROW_FACTOR` times as many samples each; at this density the grid reads what the pixels
#: compute within a fraction of the method's own error (``report accuracy --only ibl``, the ``normal grid`` rows).
NARROW_GRID_DENSITY = 4
#: A narrow microfacet lobe (its half vectors fixed to the surface: :func:`~lighting.integrate._fis.half_vector_mean`)
#: puts on the grid of normals its filtered mean less the split sum's round lobe of this many times its width ``σ``,
#: and each pixel adds that round lobe back at its own normal: the difference is smooth where the mean itself is sharp
#: (a studio box's edge through the lobe), so :data:`HALF_GRID_DENSITY` rows per ``σ`` read it within a fraction of
#: the method's own error (``report accuracy --only ibl``, the ``normal grid`` rows).  A round lobe a little narrower
#: than the whole ``σ`` follows the filtered mean's core more closely: against the exact pixel sum under the studio
#: (GGX α = 0.05, the lit pixels of 2,048) 0.75 σ left the smallest 95th percentile on the grid of 0.75, 0.9 and
#: 1.0 σ, and 0.5 or 0.6 σ a larger median.
ROUND_LOBE_WIDTH = 0.75
#: Rows of the grid of normals per ``σ`` for a narrow microfacet lobe, its round lobe read per pixel
#: (:data:`ROUND_LOBE_WIDTH`).  Other lobes' filtered samples turn with the plane of incidence and differ more from
#: one normal to the next, and keep :data:`NARROW_GRID_DENSITY` without a round lobe: under the studio a Ward lobe's
#: 95th percentile against the reference grew from 14 to 20 % at this density, a Phong lobe's from 13 to 14 %.
HALF_GRID_DENSITY = 2
#: Pixels per block of the per-pixel finish (a multiple of 64; the blocks are balanced between the shading threads,
#: each pixel computed on its own).  Each of a block's NumPy passes runs long enough that the shading threads seldom
#: wait on each other for the interpreter between them, which many short passes do (``lighting-explorer bench --ibl``
#: measures the re-shades; half this size was measurably slower on two threads, and no faster on one).
FINISH_BLOCK = 1 << 16
#: Rows of the residual's irradiance map (E is smooth once the small sources are out).
IRRADIANCE_HEIGHT = 64
#: The irradiance map integrates the residual at most this many rows high (a larger map is averaged down first).
IRRADIANCE_SOURCE_HEIGHT = 256


class DominantEnvironment:
    """What the dominant-light method precomputes for one environment (see the module notes).

    Attributes
    ----------
    lights : ~lighting.integrate.extraction.DiskLights
        The dominant lights, in the frame of the prefiltered environment's base.
    residual : PrefilteredEnvironment
        The map without them, prefiltered (the input itself when no light was taken out).
    irradiance : LatLongEnvironment
        The residual's exact irradiance map.
    cell_directions, cell_power : ndarray, (C, 3)
        The residual's areas of light as cells (:func:`~lighting.integrate.extraction.find_area_cells`).
    calm : PrefilteredEnvironment
        The residual without its areas of light, prefiltered (the residual itself when it has none).
    """

    def __init__(self, prefiltered, *, threshold=DOMINANT_THRESHOLD, max_lights=DOMINANT_MAX_LIGHTS,
                 max_solid_angle=DOMINANT_MAX_SOLID_ANGLE, area_threshold=AREA_THRESHOLD,
                 cell_rows=AREA_CELL_ROWS):  # fmt: skip
        from ..lights.environment import LatLongEnvironment
        from .prefilter import irradiance_map, prefilter_environment

        base = np.asarray(prefiltered.levels[0], dtype=np.float64)
        self.lights, rest = find_dominant_lights(base, threshold=threshold, max_lights=max_lights,
                                                 max_solid_angle=max_solid_angle)  # fmt: skip
        if len(self.lights):
            env = LatLongEnvironment(rest)
            self.residual = prefilter_environment(env, sigmas=prefiltered.sigmas)
        else:
            env = LatLongEnvironment(base)
            self.residual = prefiltered.for_environment(prefiltered.environment)  # unturned, unscaled
        self.levels = LevelStack(self.residual)
        # The round lobes of the narrow parts met last (a roughness slider makes a new width at every step) and the
        # irradiance at the points of the grids met last.
        self._one_levels, self._grid_irradiance = Recent(8), Recent(4)
        rest = np.asarray(self.residual.levels[0], dtype=np.float64)
        self.cell_directions, self.cell_power, calm = find_area_cells(rest, threshold=area_threshold,
                                                                      cell_rows=cell_rows)  # fmt: skip
        if len(self.cell_power):
            self.calm = prefilter_environment(LatLongEnvironment(calm), sigmas=prefiltered.sigmas)
            self.calm_levels = LevelStack(self.calm)
        else:
            self.calm, self.calm_levels = self.residual, self.levels
        # E is smooth: the residual averaged down to IRRADIANCE_SOURCE_HEIGHT rows (each 2 × 2 block weighted by
        # its solid angle, which keeps the power) integrates to within the quadrature's own O((π/H)²) of the full
        # map, and the row convolution's work grows as the cube of the height.
        h0 = min(base.shape[0], IRRADIANCE_SOURCE_HEIGHT)
        h = min(IRRADIANCE_HEIGHT, h0)
        irr = irradiance_map(env, h, source_height=h0)
        # The map's quadrature errs by O((π/H)²) on each row alike: divided by what it gives for a uniform sky
        # (π exactly), a uniform sky's irradiance is exact — the furnace — and smooth ones gain too.
        self.irradiance = LatLongEnvironment(irr.image * (math.pi / _uniform_irradiance(h0, 2 * h0, h)))

    def grid_irradiance(self, grid) -> np.ndarray:
        """``E(n)/π`` of the residual at the points of a grid of normals, ``(size, 3)`` float64 (read-only), made
        once per grid (the grids met last).

        Parameters
        ----------
        grid : NormalGrid
            In the frame of the environment's base.

        Returns
        -------
        ndarray
        """
        key = (grid.view.tobytes(), grid.spacing)
        found = self._grid_irradiance.get(key)
        if found is None:
            found = self.irradiance.radiance(grid.normals) / math.pi
            found.setflags(write=False)
            self._grid_irradiance.put(key, found)
        return found

    def one_level(self, kernel: str, sigma: float) -> OneLevel:
        """The residual's ``kernel`` family at the width ``sigma`` (:class:`~lighting.integrate._fis.OneLevel`),
        made once per family and width (the widths met last).

        Parameters
        ----------
        kernel : str
            A prefiltered family (:func:`~lighting.integrate.prefilter.kernel_of_lobe`).
        sigma : float
            The lobe width, radians.

        Returns
        -------
        OneLevel
        """
        key = (kernel, float(sigma))
        return self._one_levels.get(key) or self._one_levels.put(key, OneLevel(self.residual, kernel, sigma))

    def __repr__(self):
        return f"DominantEnvironment({len(self.lights)} lights, residual {self.residual!r})"


@functools.lru_cache(maxsize=8)
def _uniform_irradiance(height: int, width: int, rows: int) -> np.ndarray:
    """The irradiance map (``rows`` rows) of a uniform sky of radiance 1 sampled at ``height × width`` pixels.

    π everywhere but for the map's quadrature error: what :class:`DominantEnvironment` divides by.  The same for
    every map of that size, so made once (read-only).
    """
    from ..lights.environment import LatLongEnvironment
    from .prefilter import irradiance_map

    one = irradiance_map(LatLongEnvironment(np.ones((height, width, 3))), rows, source_height=height).image
    one.setflags(write=False)
    return one


_cache: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
#: The last few, by the content of their base image (``PrefilteredEnvironment.content_key``).
_by_content = Recent(4)


def dominant_environment(prefiltered) -> DominantEnvironment:
    """The :class:`DominantEnvironment` of a prefiltered environment, made once per base environment and image.

    Parameters
    ----------
    prefiltered : PrefilteredEnvironment or environment

    Returns
    -------
    DominantEnvironment
    """
    pre = _check_prefiltered(prefiltered)
    key = pre.environment
    try:
        found = _cache.get(key)
    except TypeError:  # not weakly referable: no cache by object
        key, found = None, None
    content = getattr(pre, "content_key", None)
    if found is None and content is not None:
        # The same image under another environment object (a scene loaded again): its lights and residual.
        found = _by_content.get(content)
    if found is None:
        found = DominantEnvironment(pre)
    if key is not None:
        _cache[key] = found
    if content is not None:
        _by_content.put(content, found)
    return found


def forget_environments() -> None:
    """Forget the prefiltered images and dominant lights kept by content, so that the next sky is made afresh.

    What a benchmark of a first frame calls before each run (:mod:`explorer.bench.costs`).
    """
    from . import prefilter

    prefilter._recent.clear()
    _by_content.clear()
    _cache.clear()


def _disk_points(half_angle: float, lobe: float) -> tuple[np.ndarray, np.ndarray]:
    """Offsets ``(x, y)`` (radians, tangent plane) and weights of the stratified points shading a disk light.

    One point at the centre when the disk is much narrower than the lobe; else rings of equal area.
    """
    ratio = half_angle / lobe if lobe > 0 else math.inf
    rings = 0 if ratio < 0.05 else (1 if ratio < 0.2 else (2 if ratio < 0.6 else 4))
    xs, ys, ws = [0.0], [0.0], [1.0]
    if rings:
        total = (2 * rings + 1) ** 2  # equal-area cells: the centre disk, then 8 i cells on ring i
        xs, ys, ws = [0.0], [0.0], [1.0 / total]
        for i in range(1, rings + 1):
            count = 8 * i
            r = half_angle * math.sqrt(((2 * i) ** 2 + (2 * i + 1) ** 2) / 2) / (2 * rings + 1)
            a = (np.arange(count) + 0.5 * (i % 2)) * (2 * math.pi / count)
            xs += list(r * np.cos(a))
            ys += list(r * np.sin(a))
            ws += [1.0 / total] * count
    return np.array([xs, ys]).T, np.asarray(ws)


def _to_base_matrix(pre):
    """``M`` with ``d_base = d_world @ M`` (the prefiltered environment's turn), or None when it is not turned."""
    if pre._to_base is None:
        return None
    return np.asarray(pre._to_base(np.eye(3)), dtype=np.float64)


def _finish_bytes(parts: int) -> int:
    """Bytes per pixel of a block of the per-pixel finish at its peak, with a margin, for a model of ``parts`` parts:
    its normals, view angles and albedos, and each part's grid values (six float32 at most) and terms' channels."""
    return 256 + 48 * parts


def _light_term(part, lights, n, v, dt, widths, work=np.float64):
    """``Σ_k f_r(v, l) (n·l) L_k dω`` over the disks of ``lights``: stratified points, each its share of ``Ω``.

    Only the pixels that see some of a disk above their horizon evaluate the BRDF for it.  Summed in ``work``.
    """
    out = np.zeros(n.shape, dtype=work)
    for k in range(len(lights)):
        c = lights.directions[k]
        gamma = float(lights.half_angles[k])
        # A Lambertian part's f_r is one constant: the disk's points add up their n·l alone, over every pixel (picking
        # out the lit ones would cost more than the products it saves).
        constant = BRDFFlags.LAMBERTIAN in part.flags
        if constant:
            lit, nl = slice(None), n
        else:
            lit = np.flatnonzero(_dot(n, c.astype(dt)) > -math.sin(gamma))
            if not lit.size:
                continue
            nl, vl = n[lit], v[lit]
        offsets, weights = _disk_points(gamma, widths)
        t = np.cross([0.0, 0.0, 1.0] if abs(c[2]) < 0.9 else [1.0, 0.0, 0.0], c)
        t /= np.linalg.norm(t)
        b = np.cross(c, t)
        irradiance = (lights.radiance[k] * lights.solid_angles[k]).astype(work)  # L Ω
        acc = np.zeros(nl.shape[:1] + ((1,) if constant else (3,)), dtype=work)
        for (x, y), wgt in zip(offsets, weights, strict=True):
            off = math.hypot(x, y)
            ld = c * math.cos(off) + (t * x + b * y) * (math.sin(off) / off if off > 0 else 1.0)
            ld = ld / np.linalg.norm(ld)
            cos_l = np.maximum(_dot(nl, ld.astype(dt)), 0)
            if constant:
                acc[:, 0] += cos_l * wgt
            else:
                f = np.asarray(part.eval(nl, np.broadcast_to(ld.astype(dt), nl.shape), vl), dtype=work)
                acc += f * (cos_l[:, None] * wgt)
        if constant:
            up = np.array([0.0, 0.0, 1.0])
            acc = acc * np.asarray(part.eval(up, up, up), dtype=work)
        out[lit] += acc * irradiance
    return out


def dominant_radiance(brdf, prefiltered, normals, view_dirs, *, samples: int = DOMINANT_SAMPLES,
                      split_terms: bool = False, normal_grid: bool | None = None):  # fmt: skip
    r"""Reflected radiance under an environment: the dominant lights exactly, the residual filtered (module notes).

    Parameters
    ----------
    brdf : BRDF
        Any model (sums included).
    prefiltered : PrefilteredEnvironment or environment
        As :func:`~lighting.integrate.ibl.split_sum_radiance`; its dominant lights and residual are
        computed on first use and kept (:func:`dominant_environment`).
    normals, view_dirs : array_like, (..., 3), world frame
        Unit surface normals and unit directions toward the viewer (broadcast together).
    samples : int >= 1
        Filtered-importance samples per glossy part and pixel (a lobe narrower than :data:`WIDE_LOBE`:
        :data:`NARROW_FACTOR` or :data:`MID_FACTOR` times as many, :func:`sample_count`).
    split_terms : bool
        Return ``{"diffuse": ..., "specular": ...}`` (normal lobes; the others) instead of their sum.
    normal_grid : bool or None
        Shade each glossy lobe's blurred terms at the points of a grid over the normals and read them at each
        pixel (:mod:`lighting.integrate._normalgrid`); only where every pixel shares one view direction.  None
        (default): when they do and the grid has at most :data:`~lighting.integrate._normalgrid.GRID_SHARE` of the
        pixels' count of points; False: pixel by pixel; True: always (refused when the views differ).

    Returns
    -------
    ndarray, (..., 3) or dict
        ``L_o`` in the dtype of the inputs; 0 where ``n·v <= 0``.

    Examples
    --------
    >>> from lighting.models.brdf import Lambert
    >>> from lighting.lights.environment import ConstantEnvironment
    >>> from lighting.integrate.prefilter import prefilter_environment
    >>> pre = prefilter_environment(ConstantEnvironment(2.0), height=16)
    >>> dominant_radiance(Lambert(0.5), pre, (0, 0, 1.0), (0.6, 0, 0.8)).round(6).tolist()  # furnace: k_d L
    [1.0, 1.0, 1.0]
    """
    brdf = _check_brdf(brdf)
    pre = _check_prefiltered(prefiltered)
    samples = check_count("samples", samples, 1, 1024)
    if normal_grid is not None:
        normal_grid = check_bool("normal_grid", normal_grid)
    n = check_vectors("normals", normals)
    v = check_vectors("view_dirs", view_dirs)
    dt = working_dtype(n, v)
    shape = np.broadcast_shapes(n.shape, v.shape)
    pixels = math.prod(shape) // 3
    # The filtered samples are read a block of pixels at a time (lighting.integrate._fis), a block per shading thread.
    # The per-pixel finish's blocks come after the samples' (one of each per thread at a time).
    check_budget("normals", pixels * 512 + _threads() * max(BLOCK_BYTES, FINISH_BLOCK * _finish_bytes(len(brdf.parts))),
                 what=f"{pixels} pixels at {samples} samples")  # fmt: skip
    n = np.broadcast_to(n, shape).reshape(-1, 3).astype(dt, copy=False)
    v = np.broadcast_to(v, shape).reshape(-1, 3).astype(dt, copy=False)
    cos_v = np.einsum("ij,ij->i", n, v)
    # Only the pixels facing the viewer reflect anything (a pixel off the object has a zero normal).
    seen = np.flatnonzero(cos_v > 0)
    out_shape = shape[:-1] + (3,)
    # One view for every pixel (off the object too: an orthographic camera), else pixel by pixel.
    if normal_grid is not False and not (seen.size and _one_view(v)):
        if normal_grid:
            raise ValueError("normal_grid=True needs every pixel to share one view direction; these differ")
        normal_grid = False
    some = seen.size < cos_v.size
    terms = _radiance(brdf, pre, *((n[seen], v[seen], cos_v[seen]) if some else (n, v, cos_v)), dt, samples,
                      normal_grid)  # fmt: skip

    def whole(value):
        """``value`` of the pixels seen, in ``dt``, at every pixel (0 off the object)."""
        value = value.astype(dt, copy=False)
        if some:
            value, seen_value = np.zeros(n.shape, dtype=dt), value
            value[seen] = seen_value
        return value.reshape(out_shape)

    if split_terms:
        return {key: whole(value) for key, value in terms.items()}
    # The terms' sum in their own dtype (float64 pixel by pixel, float32 from the grid: a float32 sum is the float64
    # sum rounded once), then in dt.
    return whole(terms["diffuse"] + terms["specular"])


def _one_view(v) -> bool:
    """Whether every row of ``v`` (P, 3), finite, is the same vector: each row equal to the one before it, compared
    as one contiguous run of values (a broadcast of ``v[0]`` over the rows would compare three values at a time)."""
    flat = v.reshape(-1)
    return bool(np.array_equal(flat[3:], flat[:-3]))


def _radiance(brdf, pre, n, v, cos_v, dt, samples, normal_grid):
    """:func:`dominant_radiance` of pixels that face the viewer, ``n``, ``v`` (P, 3) in ``dt``: ``{term: (P, 3)}``."""
    smooth, deltas = split_delta(brdf)
    mirror = None  # a mirror's reflection, in float64
    if deltas:
        reflectance = delta_albedo(deltas, np.clip(cos_v, 0, 1).astype(np.float64))
        mirror = np.zeros(n.shape, dtype=np.float64)
        mirror += reflectance * pre._lookup(2 * cos_v[:, None] * n - v, 0.0, "mirror")
    parts = () if smooth is None else smooth.parts
    if not parts:
        return {"diffuse": np.zeros(n.shape, dtype=np.float64),
                "specular": np.zeros(n.shape, dtype=np.float64) if mirror is None else mirror}  # fmt: skip
    dom = dominant_environment(pre)
    # The lights, the residual and its irradiance are in the frame of the environment's base: turn the
    # pixels into it (an isotropic BRDF does not change under a turn of n, v and l together).
    turn = _to_base_matrix(pre)
    nb = n if turn is None else (n.astype(np.float64) @ turn).astype(dt)
    vb = v if turn is None else (v.astype(np.float64) @ turn).astype(dt)
    scale = np.asarray(pre._scale, dtype=np.float64)
    sigmas = [lobe_sigma(part.lobe()) for part in parts]
    grid = _grid_for([_spacing(part, sigma) for part, sigma in zip(parts, sigmas, strict=True)], normal_grid,
                     n.shape[0], vb)  # fmt: skip
    # Pixel by pixel the terms add up in float64; read from the grid (float32 already), in the pixels' dtype.
    work = np.float64 if grid is None else dt
    # What a lobe blurs, per part: the diffuse parts' irradiance E(n)/π (RGB, one for all of them); a glossy part's
    # areas of light and residual mean (6 channels, :func:`_glossy_terms`).  On the grid when there is one: each
    # part's channels made at its points (a glossy part's dominant lights added to its areas'), then all of them read
    # at the pixels at once.
    if grid is not None:  # the grid's points as pixels of the one view
        gn = grid.normals
        gn_dt = gn.astype(dt)
        gv = np.broadcast_to(vb[0], gn.shape)
        gc = gn_dt @ vb[0]
    blurred, on_grid, round_lobes = {}, {}, {}
    for i, (part, sigma) in enumerate(zip(parts, sigmas, strict=True)):
        if math.isinf(sigma):
            if "irradiance" in blurred or "irradiance" in on_grid:
                continue
            if grid is None:
                blurred["irradiance"] = dom.irradiance.radiance(nb) / math.pi
            else:
                on_grid["irradiance"] = dom.grid_irradiance(grid)
        elif grid is not None and _spacing(part, sigma) >= grid.spacing:
            terms = _glossy_terms(part, sigma, dom, gn_dt, gv, gc, 2 * gc[:, None] * gn_dt - gv, samples)
            if _half_vector_lobe(part, sigma):
                # A narrow microfacet lobe's grid holds its filtered mean less the round lobe's read, which each pixel
                # adds back at its own normal (ROUND_LOBE_WIDTH); its dominant lights, sharp through it, stay per pixel.
                round_lobes[i] = _round_lobe(part, sigma, dom)
                terms = terms[:, 3:] - round_lobes[i](gn_dt, gv, gc)
            elif len(dom.lights):  # the lights through a lobe that the grid's spacing resolves, with the areas' cells
                terms[:, :3] += _light_term(part, dom.lights, gn_dt, gv, dt, sigma)
            on_grid[i] = terms
        else:
            blurred[i] = _glossy_terms(part, sigma, dom, nb, vb, cos_v, 2 * cos_v[:, None] * nb - vb, samples)
    if on_grid:
        # The grid's terms rounded to float32, then held in float64 for the bilinear reads (once, not per block).
        stacked = np.concatenate([value.astype(np.float32) for value in on_grid.values()], axis=-1, dtype=np.float64)
    diffuse = np.zeros(n.shape, dtype=work)
    specular = np.zeros(n.shape, dtype=work) if mirror is None else mirror.astype(work, copy=False)
    albedos = [lobe_albedo(part) for part in parts]

    def finish(rows):
        """The pixels ``rows``: the grid's terms read, the dominant lights shaded, each lobe weighted by its albedo."""
        here = {key: value[rows] for key, value in blurred.items()}
        if on_grid:
            read = grid.interpolate(stacked, nb[rows])
            start = 0
            for key, value in on_grid.items():
                here[key] = read[:, start : start + value.shape[-1]]
                start += value.shape[-1]
        theta_v = np.arccos(np.clip(cos_v[rows].astype(work), 0.0, 1.0))
        dif, spec = diffuse[rows], specular[rows]
        for i, (part, sigma, table) in enumerate(zip(parts, sigmas, albedos, strict=True)):
            # Each term as its three channels (1-D arrays, or a channel's constant), added up in this order (the
            # dominant lights first), scaled and added to the pixels channel by channel: the operations of the same
            # sums on (P, 3) arrays on each value, without NumPy's broadcasts over the three channels of a pixel
            # (inner loops three values long).
            terms = []
            if len(dom.lights) and (math.isinf(sigma) or i not in on_grid or i in round_lobes):  # else the grid's
                terms.append(_channels(_light_term(part, dom.lights, nb[rows], vb[rows], dt, sigma, work)))
            # A constant albedo (Lambert's k_d) is what the interpolation would give at every angle, exactly.
            rho = list(table[0].astype(work)) if np.all(table == table[0]) else _albedo_columns(table, theta_v, work)
            if math.isinf(sigma):
                terms.append([r * e for r, e in zip(rho, _channels(here["irradiance"]), strict=True)])
            elif i in round_lobes:
                lobe = _channels(round_lobes[i](nb[rows], vb[rows], cos_v[rows]).astype(work, copy=False))
                terms.append([r * (g + b) for r, g, b in zip(rho, _channels(here[i]), lobe, strict=True)])
            else:
                terms += [_channels(here[i][:, :3]), [r * m for r, m in zip(rho, _channels(here[i][:, 3:]),
                                                                            strict=True)]]  # fmt: skip
            target = dif if math.isinf(sigma) else spec
            for c, factor in enumerate(scale.astype(work)):
                value = np.array(terms[0][c], dtype=work)
                for term in terms[1:]:
                    value += term[c]
                value *= factor
                target[:, c] += value

    # Every pixel on its own from here, in blocks shared evenly between the shading threads (FINISH_BLOCK).
    in_blocks(n.shape[0], FINISH_BLOCK, finish, balanced=True)
    return {"diffuse": diffuse, "specular": specular}


def _channels(rgb):
    """The three channels of ``(P, 3)`` values, as three 1-D views."""
    return [rgb[:, 0], rgb[:, 1], rgb[:, 2]]


def _round_lobe(part, sigma, dom):
    """The residual's round-lobe read of a glossy part, ``(n, v, cos_v) -> (P, 3)`` float32 (:data:`ROUND_LOBE_WIDTH`).

    The split sum's value of the part's prefiltered family at ``ROUND_LOBE_WIDTH σ`` about the mirror direction; its
    two levels blended once per environment, family and width (:class:`~lighting.integrate._fis.OneLevel`).
    """
    kernel = kernel_of_lobe(part.lobe())
    width = min(ROUND_LOBE_WIDTH * sigma, dom.residual.sigmas[-1])
    one = dom.one_level(kernel, width)

    def read(n, v, cos_v):
        n, v, cos_v = (a.astype(np.float32, copy=False) for a in (n, v, cos_v))
        return one.read((cos_v + cos_v)[:, None] * n - v)

    return read


#: The grids of normals made last, by view and spacing.
_grids = Recent(8)


def _grid_for(spacings, normal_grid, pixels, vb):
    """The :class:`~lighting.integrate._normalgrid.NormalGrid` that the parts' blurred terms are shaded on, or None.

    Its spacing is the finest of the parts' ``spacings`` (:func:`_spacing`) whose own grid would qualify:
    ``normal_grid`` False, none; True, every part; None, those whose grid has at most :data:`GRID_SHARE` of
    ``pixels``' count of points.  Every pixel shares the view ``vb[0]`` unless ``normal_grid`` is False.  A part
    whose spacing is finer than the grid's is shaded pixel by pixel.
    """
    if normal_grid is False or not pixels:
        return None
    best = None
    for spacing in sorted(set(spacings), reverse=True):
        if normal_grid is None and grid_points(spacing) > GRID_SHARE * pixels:
            break
        best = spacing
    if best is None:
        return None
    # The same view and spacing (an explorer's sphere re-shaded under a moving light) reuse the grid.
    key = (np.asarray(vb[0], dtype=np.float64).tobytes(), best)
    return _grids.get(key) or _grids.put(key, NormalGrid(vb[0], best))


def sample_count(sigma: float, samples: int = DOMINANT_SAMPLES) -> int:
    """The filtered samples per point of a glossy lobe ``σ`` wide (:data:`NARROW_FACTOR`, :data:`MID_FACTOR`).

    Parameters
    ----------
    sigma : float
        The lobe's width (:func:`lighting.integrate.ibl.lobe_sigma`, radians).
    samples : int, optional
        The samples of a wide lobe (:func:`dominant_radiance`'s ``samples``).

    Returns
    -------
    int

    Examples
    --------
    >>> sample_count(0.5), sample_count(0.12), sample_count(0.07)
    (16, 128, 64)
    """
    if sigma >= WIDE_LOBE:
        return samples
    return (MID_FACTOR if sigma >= MID_LOBE else NARROW_FACTOR) * samples


def _spacing(part, sigma: float) -> float:
    """The grid spacing of a glossy part ``σ`` wide (``inf``: a diffuse one): :data:`HALF_GRID_DENSITY` rows per ``σ``
    for a narrow microfacet lobe (:func:`_half_vector_lobe`), :data:`NARROW_GRID_DENSITY` for another lobe below
    :data:`WIDE_LOBE`, :data:`~lighting.integrate._normalgrid.GRID_DENSITY` from there."""
    if sigma >= WIDE_LOBE:
        return grid_spacing(sigma, GRID_DENSITY)
    return grid_spacing(sigma, HALF_GRID_DENSITY if _half_vector_lobe(part, sigma) else NARROW_GRID_DENSITY)


def _half_vector_lobe(part, sigma: float) -> bool:
    """Whether a glossy part is read by half vectors fixed to the surface
    (:func:`~lighting.integrate._fis.half_vector_mean`): an isotropic GGX or Beckmann lobe narrower than
    :data:`WIDE_LOBE`."""
    if sigma >= WIDE_LOBE:
        return False
    mf = part.microfacet()
    return mf is not None and mf.ndf in ("ggx", "beckmann") and mf.isotropic


def _glossy_terms(part, sigma, dom, n, v, cos_v, r, samples):
    """A glossy part's terms that its lobe blurs, ``(P, 6)`` float64: the areas of light cell by cell (RGB), then
    the residual's filtered mean over the lobe (RGB, to be weighted by the part's albedo).  ``n``, ``v``, ``r`` in
    the frame of the environment's base."""
    lobe = part.lobe()
    out = np.zeros((n.shape[0], 6), dtype=np.float64)
    wide = sigma >= WIDE_LOBE and len(dom.cell_power)
    n32, v32, c32 = n.astype(np.float32), v.astype(np.float32), cos_v.astype(np.float32)
    if wide:  # the areas of light cell by cell; the calm rest by filtered samples
        out[:, :3] = cell_sum(part, dom.cell_directions, dom.cell_power, n32, v32, c32)
    rest, levels = (dom.calm, dom.calm_levels) if wide else (dom.residual, dom.levels)
    # A narrow lobe reads sharp areas of light (a box's edge, its long tails over a dark ground) by its samples
    # alone: it takes NARROW_FACTOR or MID_FACTOR times as many.
    count = sample_count(sigma, samples)
    fis = half_vector_mean if _half_vector_lobe(part, sigma) else view_table_mean
    mean, ok = fis(part, levels, n32, v32, c32, count, rest.sigmas)
    out[:, 3:] = mean
    if not np.all(ok):  # every sample below the horizon (grazing views): the lobe's prefiltered value
        miss = ~ok
        out[miss, 3:] = rest._lookup(r[miss], min(sigma, rest.sigmas[-1]), kernel_of_lobe(lobe))
    return out
