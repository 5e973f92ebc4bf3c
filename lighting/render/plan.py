"""Evaluation plans: do only the work a scene can use, and leave out what it does not need.

A lecturer's scene is often tiny — one sphere, ambient plus one directional
light, a diffuse material — and should cost tiny work.  :func:`compile_plan`
looks at a material, its lights and (optionally) the object's bounding sphere
*before* any pixel is touched, and decides what the illumination equation can
possibly use:

* a light whose colour or intensity is zero, or whose spot cone cannot reach
  the object, is dropped;
* a model part whose coefficient is zero (``k_d = 0``, ``k_s = 0``) is dropped,
  and so is a term left out of ``terms=...``;
* with no direct light left, the image is the constant ``k_e + I_a k_a`` over the
  covered pixels: no normals, no view vectors, no light loop;
* with only diffuse (Lambertian) parts and only directional lights, each light
  is one dot product per sample: no view vectors (only the sign of ``n·v``,
  which decides visibility), no half vectors, no per-pixel light vectors, no
  attenuation;
* otherwise the general path runs on the pruned material and lights (and the
  half vector is still only computed if a remaining model asks for it).

Flat shading evaluates once per face and Gouraud once per vertex (the
:class:`~lighting.render.renderer.Renderer` chooses the samples), and an unchanged
geometry buffer is never re-rasterized.  :meth:`Plan.describe` says in plain
words what was left out and why.  Every plan gives the same image as the
nothing-skipped evaluation (:func:`evaluate_full`) to rounding; the tests check
1e-12 in float64 on every example scene and on random scenes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .._text import plural, quote
from .._validate import ArgumentTypeError, check_choice, check_color, check_nonnegative, real_array
from ..lights.envlight import environment_terms, split_environment_lights
from ..lights.punctual import AmbientLight, DirectionalLight, SpotLight
from ..models.brdf import BRDFSum
from ..numerics import saturate_to
from ..shading.batch import accumulate, shade_prepared
from ..shading.inputs import FORMS, TERMS, Samples, ShadeOptions, check_lights, check_terms, view_vectors
from ..shading.material import Material, check_material
from ..vec import length
from .mesh import TriangleMesh
from .renderer import SHADING_MODES, AnalyticSphere, Renderer, needs_tangents

_BIG64 = float(np.finfo(np.float64).max)


def _check_renderer(renderer) -> Renderer:
    if not isinstance(renderer, Renderer):
        raise ArgumentTypeError(f"renderer must be a lighting.render.renderer.Renderer; got {type(renderer).__name__} "
                                f"{quote(renderer)}")  # fmt: skip
    return renderer


def _check_bounds(bounds):
    """``None`` or ``(centre 3-vector, radius >= 0)``, as :func:`bounding_sphere` returns."""
    allowed = "None or (centre, radius): a finite 3-vector and a finite number >= 0"
    if bounds is None:
        return None
    if isinstance(bounds, (str, bytes)) or not isinstance(bounds, (tuple, list)) or len(bounds) != 2:
        raise ArgumentTypeError(f"bounds must be {allowed}; got {type(bounds).__name__} {quote(bounds)}")
    c = real_array("bounds centre", bounds[0], allowed="a finite 3-vector", dtype=np.float64)
    if c.shape != (3,):
        raise ValueError(f"bounds must be {allowed}; got a centre of shape {c.shape}: {quote(bounds)}")
    return c, check_nonnegative("bounds radius", bounds[1])

__all__ = ["Plan", "Skip", "compile_plan", "evaluate_full", "bounding_sphere"]


@dataclass(frozen=True)
class Skip:
    """One thing the plan leaves out, and why."""

    what: str
    why: str


def _label(obj) -> str:
    r = repr(obj)
    return r if len(r) <= 70 else r[:67] + "..."


def bounding_sphere(geometry) -> tuple[np.ndarray, float]:
    """A sphere that contains ``geometry`` (centre of the bounding box, farthest vertex).

    Parameters
    ----------
    geometry : TriangleMesh or AnalyticSphere

    Returns
    -------
    centre : numpy.ndarray
        ``(3,)`` ``float64`` (the origin for a mesh without vertices).
    radius : float
        ``>= 0``, saturated at the largest finite float64; an analytic sphere returns its own centre and radius.
    """
    if isinstance(geometry, AnalyticSphere):
        return np.asarray(geometry.center, dtype=np.float64), float(geometry.radius)
    if not isinstance(geometry, TriangleMesh):
        raise ArgumentTypeError(f"geometry must be a TriangleMesh or an AnalyticSphere; got {type(geometry).__name__} "
                                f"{quote(geometry)}")  # fmt: skip
    v = np.asarray(geometry.vertices, dtype=np.float64)
    if len(v) == 0:
        return np.zeros(3), 0.0
    c = 0.5 * v.min(axis=0) + 0.5 * v.max(axis=0)  # halves: the sum of two extremes may overflow
    with np.errstate(over="ignore"):
        return c, float(min(np.max(length(v - c)), _BIG64))


def _spot_misses(light: SpotLight, bounds) -> bool:
    """True when no point of the bounding sphere lies inside the spot's cone.

    The directions from the apex that hit a sphere of radius ``R`` at distance
    ``d`` form a cap of angular radius ``asin(R/d)`` around the centre's
    direction; the cone is a cap of angular radius ``cutoff`` around its axis.
    The two caps overlap exactly when the angle between their centres is at most
    the sum of the radii.
    """
    if light.cutoff_deg == 180 or bounds is None:
        return False
    c, r = bounds
    with np.errstate(over="ignore", invalid="ignore"):
        d = c - light.position
    if not np.all(np.isfinite(d)):
        return False  # too far apart to decide in float64: keep the light (the plan stays exact)
    dist = float(length(d))
    if not dist > r:
        return False
    cos_axis = float(np.dot(d / dist, light.direction))
    angle = math.acos(max(-1.0, min(1.0, cos_axis)))
    return angle > math.radians(light.cutoff_deg) + math.asin(r / dist) + 1e-9


@dataclass
class Plan:
    """What to evaluate for one material under one set of lights (see the module docs)."""

    material: Material
    lights: list
    mode: str
    form: str
    terms: tuple
    strategy: str  # "constant" | "diffuse-directional" | "general"
    kept_parts: list = field(default_factory=list)
    kept_lights: list = field(default_factory=list)
    constant: np.ndarray = field(default_factory=lambda: np.zeros(3))
    skipped: list = field(default_factory=list)
    environments: list = field(default_factory=list)  # EnvironmentLights reflected by the kept parts

    # ------------------------------------------------------------------ words
    def describe(self) -> str:
        """The plan in plain words: what is evaluated, and everything left out with its reason.

        Returns
        -------
        str
            Several lines: the strategy, what is evaluated, then one ``left out:`` line per :class:`Skip`.
        """
        where = {"phong": "per pixel", "gouraud": "per vertex", "flat": "per triangle"}[self.mode]
        lines = [f"Plan ({self.mode} shading, {self.form} form): strategy '{self.strategy}'."]
        if np.any(self.constant):
            lines.append(f"  evaluate: constant emission + ambient = {np.round(self.constant, 6).tolist()}")
        if self.strategy == "diffuse-directional":
            lines.append(
                f"  evaluate: k_d (n·l) {where} for {plural(len(self.kept_lights), 'directional light')}: "
                "one dot product per light and sample"
            )
        elif self.strategy == "general":
            names = ", ".join(_label(p) for p in self.kept_parts)
            n = len(self.kept_lights)
            under = f"under {plural(n, 'light')}" if n else "under the environment alone"
            lines.append(f"  evaluate: {names} {where} {under}")
        for light in self.environments:
            lines.append(f"  evaluate: {_environment_words(light, where)}")
        for s in self.skipped:
            lines.append(f"  left out: {s.what} — {s.why}")
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.describe()

    # ------------------------------------------------------------------ execution
    def shade_samples(self, renderer: Renderer) -> np.ndarray:
        """Colours ``(N, 3)`` at the renderer's samples for this plan's mode.

        ``renderer`` is a :class:`~lighting.render.renderer.Renderer` or any object with its sample methods
        (a scene's group of renderers sharing one plan).

        Parameters
        ----------
        renderer : Renderer
            Supplies the samples, the camera and the working dtype.

        Returns
        -------
        numpy.ndarray
            ``(N, 3)`` linear RGB in the renderer's dtype, one row per sample of :meth:`Renderer.sample_points`
            (per lit pixel in ``"phong"`` mode).
        """
        mode, dt = self.mode, renderer.dtype
        if self.strategy == "constant":
            n = len(renderer.sample_points(mode)) if mode != "phong" else len(renderer.lit_pixels())
            return np.broadcast_to(saturate_to(self.constant, dt), (n, 3)).copy()
        nrm = renderer.sample_normals(mode)
        if self.strategy == "diffuse-directional":
            out = self._diffuse_directional(renderer, nrm)
            v = renderer.sample_view(mode)[0] if self.environments else None
        else:
            v, dist = renderer.sample_view(mode)
            material = Material(BRDFSum(*self.kept_parts), self.material.ambient, self.material.emission)
            # Tangents for anisotropic parts; a group of renderers without them leaves each model its default frame.
            tangents = getattr(renderer, "sample_tangents", None)
            tangents = tangents(mode) if tangents is not None and needs_tangents(material) else None
            out = shade_prepared(
                renderer.sample_points(mode), nrm, v, material, self.kept_lights + [AmbientLight(
                self._ambient_colour(), 1.0)], eye_distance=dist, form=self.form, terms=self.terms, tangents=tangents,
            )  # fmt: skip
        if self.environments:
            terms = environment_terms(self.environments, BRDFSum(*self.kept_parts), nrm, v, form=self.form,
                                      terms=self.terms, dtype=dt)  # fmt: skip
            out = out + sum(terms.values(), np.zeros(nrm.shape, dtype=dt))
        return out

    def _ambient_colour(self):
        # The ambient lights are folded into one with the same total (their sum is all that matters).
        with np.errstate(over="ignore"):
            return np.minimum(sum((lt.radiant for lt in self.lights if isinstance(lt, AmbientLight)), np.zeros(3)),
                              _BIG64)  # fmt: skip

    def _diffuse_directional(self, renderer: Renderer, nrm: np.ndarray) -> np.ndarray:
        dt = renderer.dtype
        cam = renderer.camera
        if cam.is_perspective:
            # Only the sign of n·v matters to a Lambertian surface: n·(eye − p) has it without normalizing.
            pts = renderer.sample_points(self.mode)
            e = cam.eye.astype(dt)
            front = (
                nrm[:, 0] * (e[0] - pts[:, 0]) + nrm[:, 1] * (e[1] - pts[:, 1]) + nrm[:, 2] * (e[2] - pts[:, 2])
            ) > 0
        else:
            vd = (-cam.forward).astype(dt)
            front = (nrm[:, 0] * vd[0] + nrm[:, 1] * vd[1] + nrm[:, 2] * vd[2]) > 0
        scale = 1.0 if self.form == "classic" else 1.0 / math.pi
        planes = [None, None, None]
        big = float(np.finfo(dt).max)
        out = np.empty((len(nrm), 3), dtype=dt)
        # The albedo sum, the colours and the planes saturate (finite or +inf, clamped; the unit-vector
        # dot products in between cannot overflow): one errstate for the whole evaluation.
        with np.errstate(over="ignore"):
            kd = np.minimum(sum((p.diffuse_albedo for p in self.kept_parts), np.zeros(3)), _BIG64)
            for light in self.kept_lights:
                ld = light.direction.astype(dt)
                nl = nrm[:, 0] * ld[0] + nrm[:, 1] * ld[1] + nrm[:, 2] * ld[2]
                w = np.where(front & (nl > 0), nl, 0).astype(dt, copy=False)
                # The colour saturates at the dtype's largest value before the cast (a weight of 0 must give 0,
                # not 0 · inf).
                colour = np.minimum(kd * light.radiant * scale, big)
                for ch in range(3):
                    if colour[ch] == 0:
                        continue
                    term = w * dt(colour[ch])
                    planes[ch] = term if planes[ch] is None else planes[ch] + term
            constant = saturate_to(self.constant, dt)
            for ch in range(3):
                c = constant[ch]
                out[:, ch] = c if planes[ch] is None else planes[ch] + c
        np.minimum(out, big, out=out)
        return out

    def execute(self, renderer: Renderer, background=None) -> np.ndarray:
        """The ``(H, W, 3)`` image of ``renderer``'s geometry under this plan.

        Parameters
        ----------
        renderer : Renderer
        background : scalar or RGB >= 0, optional
            Colour of the pixels the geometry does not cover; ``None`` (the default) or black leaves them 0.

        Returns
        -------
        numpy.ndarray
            ``(H, W, 3)`` linear RGB in the renderer's dtype.
        """
        _check_renderer(renderer)
        bg = None if background is None else check_color("background", background)
        if self.strategy == "constant":
            cov = renderer.gbuffer.coverage
            img = np.empty(cov.shape + (3,), dtype=renderer.dtype)
            constant = saturate_to(self.constant, renderer.dtype)
            for ch in range(3):  # per channel into strided views: 6x faster than broadcasting (H, W, 1) × (3,)
                np.multiply(cov, constant[ch], out=img[..., ch])
        else:
            img = renderer.spread(self.mode, self.shade_samples(renderer))
        if bg is not None and np.any(bg):
            img = np.where(renderer.gbuffer.coverage[..., None], img, saturate_to(bg, img.dtype))
        return img


def compile_plan(
    material: Material,
    lights,
    *,
    mode: str = "phong",
    form: str = "classic",
    terms=TERMS,
    bounds=None,
) -> Plan:
    """Decide what the illumination equation needs for ``material`` under ``lights``.

    Parameters
    ----------
    material : Material
    lights : sequence of lights
    mode : {"flat", "gouraud", "phong"}
    form : {"classic", "physical"}
    terms : iterable of {"emission", "ambient", "diffuse", "specular"}
    bounds : (centre, radius), optional
        A sphere containing the object (:func:`bounding_sphere`); lets the plan
        drop spot lights whose cone cannot reach it.

    Returns
    -------
    Plan
        With ``strategy`` ``"constant"``, ``"diffuse-directional"`` or ``"general"``, the kept parts and lights
        and the list of what was skipped.

    Examples
    --------
    >>> from lighting import Lambert, Phong, DirectionalLight, AmbientLight
    >>> plan = compile_plan(Material(Lambert(0.8) + Phong(0.0, 10)), [AmbientLight(), DirectionalLight()])
    >>> plan.strategy
    'diffuse-directional'
    >>> print(plan.describe())  # doctest: +NORMALIZE_WHITESPACE
    Plan (phong shading, classic form): strategy 'diffuse-directional'.
      evaluate: constant emission + ambient = [0.16, 0.16, 0.16]
      evaluate: k_d (n·l) per pixel for 1 directional light: one dot product per light and sample
      left out: emission term — the material emits nothing (k_e = 0)
      left out: Phong(ks=0, shininess=10) — its coefficient is zero
      left out: view vectors and half vectors — a diffuse surface needs only the sign of n·v
      left out: per-sample light vectors and attenuation — every light is directional: one l per light
    """
    check_material(material)
    mode = check_choice("mode", mode, SHADING_MODES)
    form = check_choice("form", form, FORMS)
    terms = tuple(check_terms(terms))
    lights, envs = split_environment_lights(lights)
    lights = check_lights(lights)
    bounds = _check_bounds(bounds)
    skipped: list[Skip] = []
    scale = 1.0 if form == "classic" else 1.0 / math.pi

    constant = np.zeros(3)
    if "emission" in terms:
        if np.any(material.emission):
            constant = constant + material.emission * scale
        else:
            skipped.append(Skip("emission term", "the material emits nothing (k_e = 0)"))
    # Saturating sums and products (finite or +inf, clamped; never inf · 0): light is additive up to the
    # largest float64, like the general path's.
    with np.errstate(over="ignore"):
        ambient = np.minimum(sum((lt.radiant for lt in lights if isinstance(lt, AmbientLight)), np.zeros(3)), _BIG64)
        reflected = ambient * material.ambient if "ambient" in terms else None
        if reflected is not None and np.any(reflected):
            constant = np.minimum(constant + reflected * scale, _BIG64)
    if "ambient" in terms and not np.any(reflected):
        why = "no ambient light" if not np.any(ambient) else "the material reflects no ambient light (k_a = 0)"
        skipped.append(Skip("ambient term", why))

    parts = []
    for part in material.brdf.parts:
        if part.term not in terms:
            skipped.append(Skip(_label(part), f"the {part.term} term was not asked for"))
        elif part.is_black:
            skipped.append(Skip(_label(part), "its coefficient is zero"))
        else:
            parts.append(part)
    direct = []
    for i, light in enumerate(lights):
        if isinstance(light, AmbientLight):
            continue
        if light.is_black:
            skipped.append(Skip(f"light {i} ({type(light).__name__})", "its colour × intensity is zero"))
        elif isinstance(light, SpotLight) and _spot_misses(light, bounds):
            skipped.append(Skip(f"light {i} (SpotLight)", f"its {light.cutoff_deg:g}° cone does not reach the object"))
        else:
            direct.append(light)

    kept_envs = []
    for light in envs:
        if not parts:
            skipped.append(Skip(f"the environment light ({_label(light.source)})", "no diffuse or specular part "
                                "remains to reflect it"))  # fmt: skip
        else:
            kept_envs.append(light)
    plan = Plan(material, lights, mode, form, terms, "general", parts, direct, constant, skipped, kept_envs)
    if not parts or not (direct or kept_envs):
        plan.strategy = "constant"
        why = "no light reaches the surface directly" if not direct else "no diffuse or specular part remains"
        skipped.append(Skip("normals, view vectors and the light loop", f"{why}: the image is one constant colour"))
        return plan
    if direct and all(p.lambertian for p in parts) and all(isinstance(lt, DirectionalLight) for lt in direct):
        plan.strategy = "diffuse-directional"
        skipped.append(Skip("view vectors and half vectors", "a diffuse surface needs only the sign of n·v"))
        skipped.append(Skip("per-sample light vectors and attenuation", "every light is directional: one l per light"))
        return plan
    if not any(p.term == "specular" for p in parts):
        skipped.append(Skip("half vectors", "no specular part remains"))
    if not direct:
        skipped.append(Skip("the light loop", "no punctual or area light: the environment lights the surface alone"))
    elif all(isinstance(lt, DirectionalLight) for lt in direct):
        skipped.append(Skip("per-sample light vectors and attenuation", "every light is directional: one l per light"))
    return plan


def evaluate_full(renderer: Renderer, material: Material, lights, *, mode="phong", form="classic", terms=TERMS):
    """The nothing-skipped reference: every term, light and part at every sample, inputs prepared afresh.

    Normals are normalized and view vectors computed from scratch, black lights
    and zero coefficients are evaluated like any other; the plan must agree with
    this to rounding.

    Parameters
    ----------
    renderer : Renderer
    material : Material
    lights : sequence of lights
    mode : {"flat", "gouraud", "phong"}
    form : {"classic", "physical"}
    terms : iterable of {"emission", "ambient", "diffuse", "specular"}

    Returns
    -------
    numpy.ndarray
        The ``(H, W, 3)`` image in the renderer's dtype.
    """
    _check_renderer(renderer)
    check_material(material)
    lights, envs = split_environment_lights(lights)
    lights = check_lights(lights)
    mode = check_choice("mode", mode, SHADING_MODES)
    form = check_choice("form", form, FORMS)
    terms = check_terms(terms)
    from ..vec import normalize

    pts = renderer.sample_points(mode)
    nrm = normalize(renderer.sample_normals(mode))
    cam = renderer.camera
    if cam.is_perspective:
        v, dist = view_vectors(pts, eye=cam.eye, dtype=renderer.dtype)
    else:
        v, dist = view_vectors(pts, view_dir=-cam.forward, dtype=renderer.dtype)
    options = ShadeOptions(form, "light", tuple(terms), prune=False)
    tangents = renderer.sample_tangents(mode) if needs_tangents(material) else None
    samples = Samples(pts, nrm, v, dist, tangents)
    acc = accumulate(samples, material, lights, options, summed=True, dtype=renderer.dtype)
    total = acc["total"].total()
    if envs:
        parts = environment_terms(envs, material.brdf, nrm, v, form=form, terms=terms, dtype=renderer.dtype)
        total = total + sum(parts.values(), np.zeros(nrm.shape, dtype=renderer.dtype))
    return renderer.spread(mode, total)


def _environment_words(light, where: str) -> str:
    """One line of :meth:`Plan.describe` for an environment light: its source, method and resolution."""
    from ..integrate.prefilter import PREFILTER_SIGMAS, _unwrap, prefilter_height
    from ..lights.environment import LatLongEnvironment

    env = _unwrap(light.environment)[0]
    src = light.source
    what = f"{src!r}" if isinstance(src, str) else type(src).__name__ if hasattr(src, "radiance") else f"radiance {src}"
    if isinstance(env, LatLongEnvironment):
        what += f", a {env.width}x{env.height} image"
    if light.method == "monte-carlo":
        return (f"environment light {what}: Monte Carlo reference, {light.samples} samples {where} "
                f"(importance sampling with MIS, seed {light.seed})")  # fmt: skip
    h = prefilter_height(light.environment)
    state = "already prefiltered" if light._prefiltered is not None else "prefiltered once, on first use"
    if light.method == "dominant":
        from ..integrate.dominant import DOMINANT_SAMPLES, MID_FACTOR, NARROW_FACTOR

        return (f"environment light {what}: dominant lights and filtered importance sampling {where} — the map's "
                "small bright regions as disk lights shaded with the BRDF, the rest by its irradiance map for "
                f"diffuse parts and {DOMINANT_SAMPLES} filtered samples per glossy part "
                f"({NARROW_FACTOR * DOMINANT_SAMPLES} or {MID_FACTOR * DOMINANT_SAMPLES} for a narrow lobe), "
                f"prefiltered at {2 * h}x{h} "
                f"for {len(PREFILTER_SIGMAS)} lobe widths ({state})")  # fmt: skip
    return (f"environment light {what}: split sum {where} — SH9 irradiance for diffuse parts, the environment "
            f"prefiltered at {2 * h}x{h} for {len(PREFILTER_SIGMAS)} lobe widths ({state}) times each glossy "
            "part's albedo")  # fmt: skip
