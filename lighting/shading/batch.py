r"""The fast path of the illumination equation: channel sums, stacked lights, threads.

This module computes exactly what :func:`lighting.shading.reference.shade_reference`
states as a plain loop over lights (the tests hold it to that), organised for speed:

* colours are accumulated as scalar fields times RGB constants, one channel plane at a
  time (:class:`ChannelSums`), from each model's separable form
  (:func:`lighting.shading.separable.terms`: ``[(field, rgb), ...]``, a model's channels when it has none);
* directional lights are lit together through one
  :class:`~lighting.shading.stacked.StackedGeometry` when every model says it is ``stackable``
  (:func:`lighting.shading.separable.stacks`);
* rows are split into chunks shaded on a thread pool (NumPy releases the GIL inside its loops).

Models are consumed only through that protocol: nothing here asks which class a model is.
"""

from __future__ import annotations

import os
import threading

import numpy as np

from ..lights.punctual import AmbientLight
from ..models.base import BRDFFlags
from ..models.geometry import Geometry
from ..numerics import working_dtype
from .inputs import TERMS, Samples, ShadeOptions, check_lights, points_needed_error, positional_lights
from .material import check_material
from .separable import stacks
from .separable import terms as separable_terms
from .stacked import StackedGeometry

__all__ = ["shade_prepared", "shade_prepared_terms", "shade_prepared_into"]


class ChannelSums:
    """Accumulates ``Σ_k s_k c_k`` (scalar fields × RGB constants) one channel plane at a time.

    Working on 1-D planes and interleaving RGB once at the end is many times
    faster than multiplying ``(N, 3)`` arrays per term (docs/plan.md gives the
    numbers).

    Parameters
    ----------
    shape : tuple of int
        Shape of the sample grid (the fields' shape).
    dt : numpy float type
        Working dtype of the planes.
    prune : bool
        Skip zero colours (``False`` adds them like any other).
    """

    def __init__(self, shape, dt, prune=True):
        self.shape, self.dt, self.prune = shape, dt, prune
        self.big = float(np.finfo(dt).max)
        self.planes = [None, None, None]
        self.block = None  # (3, ...) sums of stacked lights
        self.constant = np.zeros(3)

    def add(self, field, light_scale, colour):
        """Add ``field × light_scale × colour``: every factor finite and >= 0, the product saturating.

        A product of finite non-negative numbers is finite or ``+inf``, never NaN; ``inf`` times a
        later zero factor would be.  So the scalar factors are multiplied first, in float64, and
        clamped to the dtype's largest value, and an array light scale is clamped after multiplying
        the field: each multiplication that follows sees finite operands, and a zero factor wins.

        Parameters
        ----------
        field : numpy.ndarray
            A scalar field over the samples, in the working dtype.
        light_scale : float or numpy.ndarray
            The light's scalar factor (falloff × spot factor), one value or one per sample.
        colour : numpy.ndarray, (3,)
            RGB weight (float64).

        Returns
        -------
        None
        """
        if self.prune and not np.any(colour):
            return
        big = self.big
        with np.errstate(over="ignore"):
            if np.ndim(light_scale):
                f = field * light_scale
                np.minimum(f, big, out=f)
                k = np.minimum(colour, big)
            else:
                f = field
                k = np.minimum(colour * float(light_scale), big)
            for ch in range(3):
                c = k[ch]
                if c == 0 and self.prune:
                    continue
                term = f * self.dt(c)
                if self.planes[ch] is None:
                    self.planes[ch] = term
                else:
                    self.planes[ch] += term

    def add_stacked(self, field, weights):
        """Add ``Σ_k field[k] · weights[k]``: a ``(K, N)`` field of ``K`` lights, their RGB weights ``(K, 3)``.

        Parameters
        ----------
        field : numpy.ndarray, (K, N)
            One scalar field per stacked light (broadcast to it).
        weights : numpy.ndarray, (K, 3)
            RGB weights (float64), saturated before the cast to the working dtype.

        Returns
        -------
        None
        """
        field = np.broadcast_to(field, (len(weights),) + self.shape)
        if self.prune and not np.any(weights):
            return
        with np.errstate(over="ignore", invalid="ignore"):
            # Weights saturated before the cast (O(K)): an inf weight times a zero field would be NaN.
            w = np.minimum(weights, self.big).astype(self.dt)
            # One matrix product for all channels and lights: (3, K) @ (K, N).
            term = np.einsum("kc,kn->cn", w, field.reshape(len(weights), -1))
            if self.block is None:
                self.block = term
            else:
                self.block += term

    def channels(self):
        """The three channel planes ``(3, ...)`` (the constant included), saturated at the dtype's maximum.

        Returns
        -------
        numpy.ndarray, (3, ...)
            In the working dtype.
        """
        big = np.finfo(self.dt).max
        if self.block is not None and all(p is None for p in self.planes):
            # Only stacked lights: finish their sums in place (the block is ours alone).
            out = self.block.reshape(3, -1)
            with np.errstate(over="ignore"):
                for ch in range(3):
                    if self.constant[ch]:
                        out[ch] += self.dt(self.constant[ch])
                np.minimum(out, big, out=out)
            self.constant = np.zeros(3)  # now inside the block: a second call returns the same planes
            return out.reshape((3,) + self.shape)
        out = np.empty((3, int(np.prod(self.shape))), dtype=self.dt)
        with np.errstate(over="ignore"):
            for ch in range(3):
                o = out[ch]
                parts = [p.reshape(-1) for p in (None if self.block is None else self.block[ch], self.planes[ch])
                         if p is not None]  # fmt: skip
                c = self.dt(self.constant[ch])
                if not parts:
                    o[...] = c
                    continue
                np.copyto(o, parts[0])
                for p in parts[1:]:
                    o += p
                if c:
                    o += c
                np.minimum(o, big, out=o)
        return out.reshape((3,) + self.shape)

    def add_constant(self, rgb):
        """Add one RGB constant (float64) to every sample, saturating.

        Parameters
        ----------
        rgb : numpy.ndarray, (3,)

        Returns
        -------
        None
        """
        with np.errstate(over="ignore"):
            self.constant = np.minimum(self.constant + rgb, self.big)

    def total(self):
        """The sums as ``(..., 3)`` colours (:meth:`channels` interleaved).

        Returns
        -------
        numpy.ndarray, (..., 3)
        """
        return np.moveaxis(self.channels(), 0, -1).copy()


def accumulate(samples: Samples, material, lights, options: ShadeOptions, *, summed: bool, dtype,
               view_cache=None) -> dict[str, ChannelSums]:  # fmt: skip
    """The illumination equation on prepared inputs, accumulated as channel sums.

    Parameters
    ----------
    samples : Samples
        Unit ``n`` and ``v`` (and points, eye distances) in the working dtype.
    material : Material
    lights : list of lights
        Already checked (:func:`~lighting.shading.inputs.check_lights`).
    options : ShadeOptions
        Form, attenuation distance, terms; ``prune=False`` evaluates black lights and zero colours
        too (the reference "nothing skipped" path that :mod:`lighting.render.plan` is measured against).
    summed : bool
        One sum for all terms (returned under the key ``"total"``) instead of one per term.
    dtype : numpy float type
        The working dtype.
    view_cache : dict, optional
        Quantities of the normals and view vectors alone, kept between calls (see
        :func:`shade_prepared`).

    Returns
    -------
    dict of str to ChannelSums
        ``{term: sums}`` for each wanted term, or ``{"total": sums}`` when ``summed``.
    """
    p, n, v, eye_dist, tangents = samples
    form, attenuation_distance, wanted, prune, dt = (options.form, options.attenuation_distance, options.terms,
                                                      options.prune, dtype)  # fmt: skip
    shape = n.shape[:-1] if p is None else np.broadcast_shapes(p.shape, n.shape)[:-1]
    scale = options.scale
    lights = list(lights)
    one = ChannelSums(shape, dt, prune) if summed else None
    acc = {t: one or ChannelSums(shape, dt, prune) for t in wanted}
    if "emission" in wanted:
        acc["emission"].add_constant(material.emission * scale)
    if "ambient" in wanted:
        with np.errstate(over="ignore"):  # finite or +inf, saturated by add_constant()
            total = sum((lt.radiant for lt in lights if isinstance(lt, AmbientLight)), np.zeros(3))
            ambient = np.minimum(total, np.finfo(np.float64).max) * material.ambient * scale
        acc["ambient"].add_constant(ambient)
    want_parts = [t for t in ("diffuse", "specular") if t in wanted]
    parts = {t: [m for m in material.brdf.parts if BRDFFlags.of_term(t) in m.flags] for t in want_parts}
    if prune and not any(parts.values()):
        return {"total": one} if summed else acc
    if attenuation_distance == "light+viewer" and eye_dist is None:
        raise ValueError("attenuation_distance='light+viewer' needs eye= (a viewer position)")
    extra = eye_dist if attenuation_distance == "light+viewer" else None
    # Lights that arrive from one direction with one strength at every sample (directional lights)
    # are lit together through a StackedGeometry when every model accepts one.
    stack = (
        prune
        and n.ndim == 2
        and n.shape[0] == shape[0]
        and v.shape in ((3,), n.shape)
        and all(stacks(m) for t in want_parts for m in parts[t])
    )
    uniform = []
    for light in lights:
        if isinstance(light, AmbientLight) or (prune and light.is_black):
            continue
        for inc in light._incident(p, dtype=dt, extra_distance=extra):
            if stack and np.ndim(inc.direction) == 1 and np.ndim(inc.scale) == 0:
                uniform.append(inc)
                continue
            g = Geometry(n, inc.direction, v, unit=True, dtype=dt, tangent=tangents)
            if not prune:
                # The textbook loop: every vector of the slides at every sample, whether a model uses it or not.
                g.h, g.n_dot_h, g.v_dot_h, g.one_minus_n_dot_h, g.one_minus_r_dot_v, g.above  # noqa: B018
            radiant = inc.radiant.astype(np.float64)
            for t in want_parts:
                for model in parts[t]:
                    fields = separable_terms(model, g, form)
                    for field, colour in fields:
                        with np.errstate(over="ignore"):  # saturated in add(): finite or +inf, never NaN
                            weight = colour * radiant
                        acc[t].add(field, inc.scale, weight)
    if uniform:
        g = StackedGeometry(n, np.stack([inc.direction for inc in uniform]), v, dtype=dt, view_cache=view_cache)
        radiant = np.stack([inc.radiant.astype(np.float64) * float(inc.scale) for inc in uniform])
        for t in want_parts:
            for model in parts[t]:
                fields = separable_terms(model, g, form)
                for field, colour in fields:
                    with np.errstate(over="ignore"):  # saturated in add_stacked(): finite or +inf, never NaN
                        weights = colour * radiant
                    acc[t].add_stacked(field, weights)
    return {"total": one} if summed else acc


def _run(samples: Samples, material, lights, options: ShadeOptions, *, view_cache, summed: bool, finish, sink=None):
    """Check the O(1) arguments, then shade ``samples`` chunk by chunk: ``finish(sums)`` per chunk.

    Returns the list of per-chunk results (``[]`` when ``sink`` took them).
    """
    # O(1) checks only (and O(number of lights)): this is the re-shade path of every frame.
    check_material(material)
    points, unit_normals = samples.points, samples.unit_normals
    dt = working_dtype(unit_normals) if points is None else working_dtype(points, unit_normals)
    lights = check_lights(lights)
    if points is None:
        positional = positional_lights(lights)
        if positional:
            raise points_needed_error(positional[0])
    rows = unit_normals if points is None else points
    n_rows = np.shape(rows)[0] if np.ndim(rows) == 2 else 0

    def run(sl):
        def part(x, ndim=2):
            return x if x is None or np.ndim(x) < ndim or x.shape[0] != n_rows else x[sl]

        cache = None if view_cache is None else view_cache.setdefault((sl.start, sl.stop), {})
        chunk = Samples(part(points), part(unit_normals), part(samples.view), part(samples.eye_distance, ndim=1),
                        part(samples.tangents))  # fmt: skip
        out = finish(accumulate(chunk, material, lights, options, summed=summed, dtype=dt, view_cache=cache))
        return out if sink is None else sink(sl, out)

    if sink is not None:
        each_chunk(n_rows, run)
        return []
    chunks = _chunks(n_rows)
    if len(chunks) == 1:
        return [run(slice(None))]
    # NumPy releases the GIL inside its loops, so the chunks shade in parallel on separate cores.
    return list(_pool().map(run, chunks))


def shade_prepared(points, unit_normals, view, material, lights, *, eye_distance=None, form="classic",
                   attenuation_distance="light", terms=TERMS, view_cache=None,
                   tangents=None) -> np.ndarray:  # fmt: skip
    """:func:`~lighting.shading.equation.shade` on inputs a caller has prepared once and reuses for many lights.

    ``unit_normals`` must be unit (or zero) and ``view`` the unit view vectors
    (or one shared direction), all of one float dtype; nothing is normalized or
    copied here.  This is the path of :class:`lighting.render.renderer.Renderer`, whose
    geometry and viewer stay fixed while lights and materials change.

    Parameters
    ----------
    points : numpy.ndarray, (N, 3) or None
        Surface positions; ``None`` when every light is ambient or directional (they
        are the same at every point; a renderer then skips interpolating positions).
    unit_normals, view : numpy.ndarray, (N, 3)
        Unit normals and unit view vectors (``view`` may be one shared ``(3,)`` direction).
    material : Material
    lights : sequence of lights
    eye_distance : numpy.ndarray, optional
        Float64 distances to the eye (needed by ``attenuation_distance="light+viewer"``).
    form, attenuation_distance, terms
        As :func:`~lighting.shading.equation.shade`.
    view_cache : dict, optional
        A dict the caller keeps (empty at first) holding quantities of the normals and view
        vectors alone (``n·v``, ``n × v``) between calls; valid only while ``unit_normals`` and
        ``view`` stay the same.
    tangents : numpy.ndarray, (N, 3), optional
        Surface tangents in the working dtype, passed to every model (``Geometry(..., tangent=)``):
        anisotropic ones orient their lobe by them, isotropic ones never read them.  ``None``: each
        model's default frame.

    Returns
    -------
    numpy.ndarray
        Colours ``(N, 3)`` in the working dtype.
    """
    options = ShadeOptions.checked(form, attenuation_distance, terms)
    samples = Samples(points, unit_normals, view, eye_distance, tangents)
    results = _run(samples, material, lights, options, view_cache=view_cache, summed=True,
                   finish=lambda acc: acc["total"].total())  # fmt: skip
    return results[0] if len(results) == 1 else np.concatenate(results, axis=0)


def shade_prepared_terms(
    points, unit_normals, view, material, lights, *, eye_distance=None, form="classic", attenuation_distance="light",
    terms=TERMS, view_cache=None, tangents=None,
) -> dict[str, np.ndarray]:  # fmt: skip
    """Each term of the illumination equation separately, on prepared inputs.

    Parameters
    ----------
    points, unit_normals, view, material, lights, eye_distance, form, attenuation_distance, terms, view_cache, tangents
        As :func:`shade_prepared`.

    Returns
    -------
    dict of str to numpy.ndarray
        One ``(N, 3)`` array per requested term (like :func:`~lighting.shading.equation.shade_terms`).
    """
    options = ShadeOptions.checked(form, attenuation_distance, terms)
    samples = Samples(points, unit_normals, view, eye_distance, tangents)
    results = _run(samples, material, lights, options, view_cache=view_cache, summed=False,
                   finish=lambda acc: {t: acc[t].total() for t in options.terms})  # fmt: skip
    if len(results) == 1:
        return results[0]
    return {t: np.concatenate([r[t] for r in results], axis=0) for t in options.terms}


def shade_prepared_into(sink, points, unit_normals, view, material, lights, *, eye_distance=None, form="classic",
                        attenuation_distance="light", terms=TERMS, view_cache=None, tangents=None) -> None:  # fmt: skip
    """:func:`shade_prepared`, handing each chunk of rows to ``sink`` as channel planes.

    Each chunk is handed over as ``sink(row_slice, planes)``, ``planes`` of shape ``(3, m)``,
    by the thread that shaded it: an image can take its pixels while the other chunk is
    still shading.

    Parameters
    ----------
    sink : callable
        ``sink(row_slice, planes)``; called once per disjoint slice of rows, possibly concurrently.
    points, unit_normals, view, material, lights, eye_distance, form, attenuation_distance, terms, view_cache, tangents
        As :func:`shade_prepared`.

    Returns
    -------
    None
    """
    options = ShadeOptions.checked(form, attenuation_distance, terms)
    samples = Samples(points, unit_normals, view, eye_distance, tangents)
    _run(samples, material, lights, options, view_cache=view_cache, summed=True,
         finish=lambda acc: acc["total"].channels(), sink=sink)  # fmt: skip


_MIN_ROWS_PER_THREAD = 32768
#: The names of the shading threads begin so.
_THREAD_PREFIX = "lighting-shade"
_POOL = None


def _threads() -> int:
    return max(1, min(os.cpu_count() or 1, 8))


def _chunks(n_rows: int, min_rows: int | None = None) -> list[slice]:
    k = min(_threads(), n_rows // (_MIN_ROWS_PER_THREAD if min_rows is None else min_rows))
    if k <= 1:
        return [slice(None)]
    edges = np.linspace(0, n_rows, k + 1).astype(int)
    return [slice(a, b) for a, b in zip(edges[:-1], edges[1:], strict=True)]


def each_chunk(n_rows: int, fn, *, min_rows: int | None = None) -> None:
    """``fn(row_slice)`` for the chunks of ``n_rows`` rows, on the shading threads when there are several.

    Parameters
    ----------
    n_rows : int
        Number of rows (samples) to cover.
    fn : callable
        Called once per disjoint ``slice`` of rows; chunks may run concurrently.
    min_rows : int, optional
        The fewest rows worth a thread of their own (default: the shading's; a row of costly work, such as a
        whole pixel's quadrature, is worth one).

    Returns
    -------
    None
    """
    chunks = _chunks(n_rows, min_rows)
    if len(chunks) == 1:
        fn(chunks[0])
        return
    if threading.current_thread().name.startswith(_THREAD_PREFIX):
        # Called from a shading thread: the pool's threads may all be waiting here, none left to run the chunks.
        for chunk in chunks:
            fn(chunk)
        return
    for _ in _pool().map(fn, chunks):
        pass


def in_blocks(count: int, step: int, fn, *, balanced: bool = False) -> None:
    """``fn(rows)`` for consecutive slices of ``step`` of ``count`` rows; each shading thread takes a run of them.

    The blocks start at the multiples of ``step`` whatever the number of threads, and each is a thread's worth of
    work however few its rows (a grid's few thousand points, each with dozens of samples or cells): every thread
    gets a run of blocks as soon as there are two.  The blocks write disjoint rows, so the result does not depend
    on which thread computed which block; a multiple of 64 rows per block also gives each row the bits that one
    call over every row would (BLAS's products treat rows in groups).

    ``balanced``: the blocks are made a little smaller (a multiple of 64 rows, at most ``step``) so that each
    thread gets the same number of them, where three blocks on two threads would leave one thread idle for a
    third of the time, and one block of fewer than ``step`` rows (but more than 64) is cut in one per thread.
    Only for a ``fn`` whose rows get the same bits whatever block they are in (each row computed on its own, or
    blocks of a multiple of 64 rows: ``step`` one too).
    """
    if balanced and count > 64:
        threads = _threads()
        blocks = -(-count // step)
        blocks = -(-blocks // threads) * threads
        step = min(step, -(-count // (64 * blocks)) * 64)  # count / blocks, rounded up to a multiple of 64
    starts = range(0, count, step)

    def run(blocks):
        for i in starts[blocks]:
            fn(slice(i, min(i + step, count)))

    each_chunk(len(starts), run, min_rows=1)


def _pool():
    global _POOL
    if _POOL is None:
        from concurrent.futures import ThreadPoolExecutor

        _POOL = ThreadPoolExecutor(max_workers=_threads(), thread_name_prefix=_THREAD_PREFIX)
    return _POOL
