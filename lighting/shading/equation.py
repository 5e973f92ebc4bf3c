r"""The illumination equation, in the slides' classic form and in physical form.

Classic form (UBC deck, "Illumination Equation")::

    I = k_e + I_a k_a + Σ_p  I_p / A(d_p) · (k_d (n·l_p) + k_s (r_p·v)^n)

with every product taken per RGB channel ("red light on a green surface is
black").  The bracket is, for any model, its :meth:`~lighting.models.brdf.BRDF.classic`
term ``π f_r (n·l)``, so Blinn–Phong, normalized Blinn–Phong or Cook–Torrance
drop into the same sum.

Physical form (CMSC 435 deck, "Rendering Equation for Point Lights")::

    L_o(v) = Σ_i f_r(v, l_i) E_i (n·l_i)

where ``E_i = I_p / A(d_p)`` is the irradiance the light delivers on a surface
facing it.  The engine's single π relation (conventions.md) ties the two:
``I_classic = π L_o`` term by term, the ambient and emission terms included
(ambient light is a uniform irradiance ``I_a``, which a surface of albedo
``k_a`` turns into radiance ``k_a I_a / π``).  The two forms are computed by
two code paths (:meth:`classic` and :meth:`eval_cos`) and agree to rounding.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from .._numeric import ArgumentTypeError, _fmt, as_float, check_choice, check_color, check_vectors, working_dtype
from ..lights.punctual import AmbientLight, DirectionalLight, Light
from ..models.brdf import BRDF, Geometry, StackedGeometry
from ..vec import length, normalize

__all__ = ["Material", "shade", "shade_terms", "shade_prepared", "view_vectors", "TERMS", "FORMS"]

TERMS = ("emission", "ambient", "diffuse", "specular")
FORMS = ("classic", "physical")


@dataclass(frozen=True)
class Material:
    """A surface: a reflectance model plus the slides' ambient and emission coefficients.

    Parameters
    ----------
    brdf : BRDF
        The reflectance model (``Lambert(kd) + Phong(ks, e)`` is the slides' surface).
    ambient : scalar or RGB, optional
        ``k_a``, the fraction of ambient light reflected.  Defaults to the
        model's diffuse albedo (``k_a = k_d``), which is the usual choice: ambient
        light then shows the object's own colour.
    emission : scalar or RGB
        ``k_e``, light the surface gives off itself (classic units).
    """

    brdf: BRDF
    ambient: object = None
    emission: object = 0.0

    def __post_init__(self):
        if not isinstance(self.brdf, BRDF):
            raise ArgumentTypeError(
                f"brdf must be a lighting.models.brdf model (Lambert, Phong, ...); got {type(self.brdf).__name__} "
                f"{_fmt(self.brdf)}"
            )
        ka = self.brdf.diffuse_albedo if self.ambient is None else self.ambient
        object.__setattr__(self, "ambient", check_color("ambient", ka))
        object.__setattr__(self, "emission", check_color("emission", self.emission))


class _Planes:
    """Accumulates ``Σ_k s_k c_k`` (scalar fields × RGB constants) one channel plane at a time.

    Working on 1-D planes and interleaving RGB once at the end is many times
    faster than multiplying ``(N, 3)`` arrays per term (measured 0.6 ms against
    32 ms for three terms at 512×512 in float32).
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
        """Add ``Σ_k field[k] · weights[k]``: a ``(K, N)`` field of ``K`` lights, their RGB weights ``(K, 3)``."""
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
        """The three channel planes ``(3, ...)`` (the constant included), saturated at the dtype's maximum."""
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
        with np.errstate(over="ignore"):
            self.constant = np.minimum(self.constant + rgb, self.big)

    def total(self):
        return np.moveaxis(self.channels(), 0, -1).copy()


def view_vectors(points, *, eye=None, view_dir=None, dtype=None):
    """The slides' ``v`` at ``points`` and the eye distances (None for a distant viewer).

    Exactly one of ``eye`` (a viewer position) or ``view_dir`` (the direction
    toward a viewer at infinity) must be given.  The eye distances are float64,
    saturated at its largest finite value.  The inputs are taken as checked
    (:func:`shade` checks them); this is also the renderer's path.
    """
    dt = dtype or working_dtype(points)
    if (eye is None) == (view_dir is None):
        raise ValueError("give exactly one of eye (viewer position) or view_dir (direction toward a distant viewer)")
    if view_dir is not None:
        # Normalized in float64 first: a direction beyond float32's range (1e300, -1e300, 1e300) is
        # still a direction, and only its unit vector is cast.
        return normalize(as_float(view_dir, np.float64)).astype(dt), None
    e = as_float(eye, np.float64)
    if np.ndim(points) == 2 and np.shape(points)[1] == 3 and e.shape == (3,) and dt == np.float32:
        # A float32 renderer's view vectors, in float32 and one contiguous plane per component
        # (several times faster than float64 rows): the positions themselves carry float32
        # rounding, so this adds about one ulp to v's direction.
        p = as_float(points, dt)
        fi = np.finfo(dt)
        # Points far from the eye (1e30 in float32) overflow these squares: they take the float64 path below.
        with np.errstate(over="ignore", under="ignore", invalid="ignore"):
            d = [dt(e[k]) - p[:, k] for k in range(3)] if np.all(np.abs(e) < fi.max) else None
            len2 = None if d is None else d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
        if len2 is not None and np.all((len2 > fi.tiny * 1e4) & (len2 < fi.max * 1e-4)):
            dist = np.sqrt(len2)
            inv = 1 / dist
            v = np.empty(p.shape, dtype=dt, order="F")
            for k in range(3):
                np.multiply(d[k], inv, out=v[:, k])
            return v, dist.astype(np.float64)
    p = as_float(points, np.float64)
    with np.errstate(over="ignore", invalid="ignore"):
        d = e - p
    factor = 1.0
    if not np.all(np.isfinite(d)):
        # The difference of two finite positions overflowed (1e308 − (−1e308)): halves keep the direction.
        d, factor = 0.5 * e - 0.5 * p, 2.0
    with np.errstate(over="ignore"):
        dist = np.minimum(factor * length(d), np.finfo(np.float64).max)
    return normalize(d).astype(dt), dist


def _check_lights(lights, name: str = "lights") -> list:
    """``lights`` as a list of lights (ambient, directional, point, spot, area); O(number of lights)."""
    if isinstance(lights, (Light, AmbientLight)):
        raise ArgumentTypeError(f"{name} must be a sequence of lights; got a single {type(lights).__name__}: "
                                f"{_fmt(lights)} (wrap it in a list)")  # fmt: skip
    if isinstance(lights, (str, bytes, dict)) or not hasattr(lights, "__iter__"):
        raise ArgumentTypeError(f"{name} must be a sequence of lights (AmbientLight, DirectionalLight, ...); "
                                f"got {type(lights).__name__} {_fmt(lights)}")  # fmt: skip
    out = list(lights)
    for i, lt in enumerate(out):
        if not isinstance(lt, (Light, AmbientLight)):
            raise ArgumentTypeError(f"{name}[{i}] must be a light (AmbientLight, DirectionalLight, PointLight, "
                                    f"SpotLight, RectLight, DiskLight); got {type(lt).__name__} "
                                    f"{_fmt(lt)}")  # fmt: skip
    return out


def _check_material(material) -> None:
    if not isinstance(material, Material):
        raise ArgumentTypeError(f"material must be a lighting.Material; got {type(material).__name__} {_fmt(material)}")


def _points_needed(light) -> ArgumentTypeError:
    i = type(light).__name__
    return ArgumentTypeError(f"points=None is allowed only for ambient and directional lights; {i} needs the "
                             f"surface positions (points: finite real vectors of shape (..., 3)): {_fmt(light)}")


def _positional(lights) -> list:
    return [lt for lt in lights if not isinstance(lt, (AmbientLight, DirectionalLight))]


def _evaluate(p, n, v, eye_dist, material, lights, *, form, attenuation_distance, wanted, summed, dt, prune=True,
              view_cache=None):  # fmt: skip
    """The illumination equation on prepared inputs: unit ``n`` and ``v`` in the working dtype.

    Returns ``{term: _Planes}``, or one ``_Planes`` holding the sum when ``summed``.
    ``prune=False`` evaluates black lights and zero colours too (the reference
    "nothing skipped" path that :mod:`lighting.render.plan` is measured against).
    """
    shape = n.shape[:-1] if p is None else np.broadcast_shapes(p.shape, n.shape)[:-1]
    scale = 1.0 if form == "classic" else 1.0 / math.pi
    lights = list(lights)
    one = _Planes(shape, dt, prune) if summed else None
    acc = {t: one or _Planes(shape, dt, prune) for t in wanted}
    if "emission" in wanted:
        acc["emission"].add_constant(material.emission * scale)
    if "ambient" in wanted:
        with np.errstate(over="ignore"):  # finite or +inf, saturated by add_constant()
            total = sum((lt.radiant for lt in lights if isinstance(lt, AmbientLight)), np.zeros(3))
            ambient = np.minimum(total, np.finfo(np.float64).max) * material.ambient * scale
        acc["ambient"].add_constant(ambient)
    want_parts = [t for t in ("diffuse", "specular") if t in wanted]
    parts = {t: [m for m in material.brdf.parts if m.term == t] for t in want_parts}
    if prune and not any(parts.values()):
        return one if summed else acc
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
        and all(m.stackable for t in want_parts for m in parts[t])
    )
    uniform = []
    for light in lights:
        if isinstance(light, AmbientLight) or (prune and light.is_black):
            continue
        for inc in light._incident(p, dtype=dt, extra_distance=extra):
            if stack and np.ndim(inc.direction) == 1 and np.ndim(inc.scale) == 0:
                uniform.append(inc)
                continue
            g = Geometry(n, inc.direction, v, unit=True, dtype=dt)
            if not prune:
                # The textbook loop: every vector of the slides at every sample, whether a model uses it or not.
                g.h, g.n_dot_h, g.v_dot_h, g.one_minus_n_dot_h, g.one_minus_r_dot_v, g.above  # noqa: B018
            radiant = inc.radiant.astype(np.float64)
            for t in want_parts:
                for model in parts[t]:
                    fields = model.separable_classic(g) if form == "classic" else model.separable_cos(g)
                    for field, colour in fields:
                        with np.errstate(over="ignore"):  # saturated in add(): finite or +inf, never NaN
                            weight = colour * radiant
                        acc[t].add(field, inc.scale, weight)
    if uniform:
        g = StackedGeometry(n, np.stack([inc.direction for inc in uniform]), v, dtype=dt, view_cache=view_cache)
        radiant = np.stack([inc.radiant.astype(np.float64) * float(inc.scale) for inc in uniform])
        for t in want_parts:
            for model in parts[t]:
                fields = model.separable_classic(g) if form == "classic" else model.separable_cos(g)
                for field, colour in fields:
                    with np.errstate(over="ignore"):  # saturated in add_stacked(): finite or +inf, never NaN
                        weights = colour * radiant
                    acc[t].add_stacked(field, weights)
    return one if summed else acc


def _check_terms(terms) -> list:
    """``terms`` as a list of term names; a string, a mapping or a set is refused (order and kind matter)."""
    if isinstance(terms, (str, bytes, dict, set, frozenset)) or not hasattr(terms, "__iter__"):
        raise ArgumentTypeError(f"terms must be a sequence of names from {TERMS}; got {type(terms).__name__} "
                                f"{_fmt(terms)}")  # fmt: skip
    return [check_choice("terms", t, TERMS) for t in terms]


def _check_options(form, attenuation_distance, terms):
    form = check_choice("form", form, FORMS)
    attenuation_distance = check_choice("attenuation_distance", attenuation_distance, ("light", "light+viewer"))
    return form, attenuation_distance, _check_terms(terms)


def shade_terms(
    points,
    normals,
    material: Material,
    lights: Sequence[Light | AmbientLight] | Iterable,
    *,
    eye=None,
    view_dir=None,
    form: str = "classic",
    attenuation_distance: str = "light",
    terms: Iterable[str] = TERMS,
) -> dict[str, np.ndarray]:
    """Each term of the illumination equation separately, as ``{name: (..., 3)}``.

    Parameters
    ----------
    points, normals : array_like, (..., 3)
        Surface positions and normals (normals need not be unit length; a zero
        normal receives only emission and ambient light).
    material : Material
    lights : sequence of lights
        :class:`~lighting.lights.punctual.AmbientLight` adds to the ambient term, every
        other light to the diffuse and specular terms.
    eye, view_dir : 3-vector
        Exactly one: the viewer's position (perspective, ``v`` varies per point)
        or the direction toward a viewer at infinity.
    form : {"classic", "physical"}
        ``classic`` is the slides' ``I``; ``physical`` is radiance ``I / π``.
    attenuation_distance : {"light", "light+viewer"}
        ``d_p`` in ``A(d_p)``: the light's distance (usual), or the UBC slide's
        literal "distance to the light plus distance to the viewer".
    terms : iterable of {"emission", "ambient", "diffuse", "specular"}
        Which terms to compute; the others are not evaluated at all.

    Returns
    -------
    dict
        One ``(..., 3)`` array per requested term, in the working dtype.
    """
    p, n, v, eye_dist, lights = _prepare(points, normals, material, eye, view_dir, lights)
    return shade_prepared(p, n, v, material, lights, eye_distance=eye_dist, form=form,
                          attenuation_distance=attenuation_distance, terms=terms, separate=True)  # fmt: skip


def _prepare(points, normals, material, eye, view_dir, lights):
    """Check every argument once; points, unit normals, view vectors and eye distances in the working dtype.

    ``points`` may be ``None`` only when every light is ambient or directional (they do not depend on
    where the surface is) and the viewer is at infinity (``view_dir``).
    """
    _check_material(material)
    lights = _check_lights(lights)
    if (eye is None) == (view_dir is None):
        raise ValueError(
            "give exactly one of eye (viewer position) or view_dir (direction toward a distant viewer); "
            f"got eye={_fmt(eye)}, view_dir={_fmt(view_dir)}"
        )
    n = check_vectors("normals", normals)
    if points is None:
        positional = _positional(lights)
        if positional:
            raise _points_needed(positional[0])
        if eye is not None:
            raise ArgumentTypeError("points must be finite real vectors of shape (..., 3) when eye= is given "
                                    "(v depends on the position); got None")  # fmt: skip
        p = None
        dt = working_dtype(n)
    else:
        p = check_vectors("points", points)
        dt = working_dtype(p, n)
    if eye is not None:
        e = check_vectors("eye", eye, dtype=np.float64)
        if e.shape != (3,):
            raise ValueError(f"eye must be one finite 3-vector (the viewer's position); got shape {e.shape}: "
                             f"{_fmt(eye)}")  # fmt: skip
    else:
        vd = check_vectors("view_dir", view_dir, nonzero=True)
    shapes = {"points": None if p is None else p.shape, "normals": n.shape,
              "view_dir": None if view_dir is None else vd.shape}  # fmt: skip
    try:
        np.broadcast_shapes(*(s for s in shapes.values() if s is not None))
    except ValueError:
        given = ", ".join(f"{k} {s}" for k, s in shapes.items() if s is not None)
        raise ValueError(f"points, normals and view_dir must broadcast together (shapes (..., 3)); "
                         f"got {given}") from None
    p = None if p is None else as_float(p, dt)
    n = normalize(as_float(n, dt))
    v, eye_dist = view_vectors(p, eye=eye, view_dir=None if view_dir is None else vd, dtype=dt)
    return p, n, v, eye_dist, lights


def shade(
    points,
    normals,
    material,
    lights,
    *,
    eye=None,
    view_dir=None,
    form="classic",
    attenuation_distance="light",
    terms=TERMS,
) -> np.ndarray:
    """Colour of surface points under lights: the slides' illumination equation.

    The sum of the :func:`shade_terms` (see there for the parameters),
    accumulated directly.

    Examples
    --------
    Red light on a green surface is black:

    >>> from lighting.models.brdf import Lambert
    >>> from lighting.lights.punctual import DirectionalLight
    >>> shade((0, 0, 0.0), (0, 0, 1.0), Material(Lambert((0, 1, 0))),
    ...       [DirectionalLight((0, 0, 1.0), color=(1, 0, 0))], view_dir=(0, 0, 1.0)).tolist()
    [0.0, 0.0, 0.0]
    """
    p, n, v, eye_dist, lights = _prepare(points, normals, material, eye, view_dir, lights)
    return shade_prepared(p, n, v, material, lights, eye_distance=eye_dist, form=form,
                          attenuation_distance=attenuation_distance, terms=terms)  # fmt: skip


def shade_prepared(
    points, unit_normals, view, material, lights, *, eye_distance=None, form="classic",
    attenuation_distance="light", terms=TERMS, separate=False, view_cache=None, channels=False, sink=None,
):  # fmt: skip
    """:func:`shade` on inputs a caller has prepared once and reuses for many lights.

    ``unit_normals`` must be unit (or zero) and ``view`` the unit view vectors
    (or one shared direction), all of one float dtype; nothing is normalized or
    copied here.  This is the path of :class:`lighting.render.renderer.Renderer`, whose
    geometry and viewer stay fixed while lights and materials change.  With
    ``separate=True`` returns ``{term: (..., 3)}`` like :func:`shade_terms`.

    ``points`` may be ``None`` when every light is ambient or directional (they
    are the same at every point; a renderer then skips interpolating positions).

    ``view_cache`` (a dict the caller keeps, empty at first) holds quantities of
    the normals and view vectors alone (``n·v``, ``n × v``) between calls; it is
    valid only while ``unit_normals`` and ``view`` stay the same.  With
    ``channels=True`` the colours come back as channel planes ``(3, ...)``
    instead of ``(..., 3)`` (what an image scatter reads fastest).  With a
    ``sink`` (and ``channels=True``, ``separate=False``) each chunk of rows is
    handed over as ``sink(row_slice, planes)`` by the thread that shaded it, and
    nothing is returned: an image can take its pixels while the other chunk is
    still shading.
    """
    if sink is not None and (separate or not channels):
        raise ValueError("sink needs channels=True and separate=False")
    # O(1) checks only (and O(number of lights)): this is the re-shade path of every frame.
    form, attenuation_distance, wanted = _check_options(form, attenuation_distance, terms)
    _check_material(material)
    dt = working_dtype(unit_normals) if points is None else working_dtype(points, unit_normals)
    lights = _check_lights(lights)
    if points is None:
        positional = _positional(lights)
        if positional:
            raise _points_needed(positional[0])

    def run(sl):
        def part(x, ndim=2):
            return x if x is None or np.ndim(x) < ndim or x.shape[0] != n_rows else x[sl]

        dist = part(eye_distance, ndim=1)
        cache = None if view_cache is None else view_cache.setdefault((sl.start, sl.stop), {})
        acc = _evaluate(
            part(points), part(unit_normals), part(view), dist, material, lights, form=form,
            attenuation_distance=attenuation_distance, wanted=wanted, summed=not separate, dt=dt,
            view_cache=cache,
        )  # fmt: skip
        out = (lambda a: a.channels()) if channels else (lambda a: a.total())
        if sink is not None:
            return sink(sl, out(acc))
        return {t: out(acc[t]) for t in wanted} if separate else out(acc)

    rows = unit_normals if points is None else points
    n_rows = np.shape(rows)[0] if np.ndim(rows) == 2 else 0
    if sink is not None:
        _each_chunk(n_rows, run)
        return None
    chunks = _chunks(n_rows)
    if len(chunks) == 1:
        return run(slice(None))
    # NumPy releases the GIL inside its loops, so the chunks shade in parallel on separate cores.
    results = list(_pool().map(run, chunks))
    axis = -1 if channels else 0
    if separate:
        return {t: np.concatenate([r[t] for r in results], axis=axis) for t in wanted}
    return np.concatenate(results, axis=axis)


_MIN_ROWS_PER_THREAD = 32768
_POOL = None


def _threads() -> int:
    return max(1, min(os.cpu_count() or 1, 8))


def _chunks(n_rows: int) -> list[slice]:
    k = min(_threads(), n_rows // _MIN_ROWS_PER_THREAD)
    if k <= 1:
        return [slice(None)]
    edges = np.linspace(0, n_rows, k + 1).astype(int)
    return [slice(a, b) for a, b in zip(edges[:-1], edges[1:], strict=True)]


def _each_chunk(n_rows: int, fn) -> None:
    """``fn(row_slice)`` for the :func:`_chunks` of ``n_rows``, on the shading threads when there are several."""
    chunks = _chunks(n_rows)
    if len(chunks) == 1:
        fn(chunks[0])
        return
    for _ in _pool().map(fn, chunks):
        pass


def _pool():
    global _POOL
    if _POOL is None:
        from concurrent.futures import ThreadPoolExecutor

        _POOL = ThreadPoolExecutor(max_workers=_threads(), thread_name_prefix="lighting-shade")
    return _POOL
