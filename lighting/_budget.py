"""The memory and time budget: requests estimate their peak memory and their time, and are refused above them.

One home for every budget of the engine:

* **memory**: every allocation-heavy entry point calls :func:`check_budget` with its estimate of the peak
  bytes, before allocating; the limit is :func:`memory_budget` (the command line's ``--memory-budget``,
  :func:`set_memory_budget`);
* **a scene**: :func:`scene_estimate` estimates a render's peak memory and its time from the scene alone
  (the image, the meshes, the lights' samples, the models' kinds, the environments) and
  :func:`check_scene_budget` refuses a scene over the memory budget or over :data:`TIME_LIMIT` seconds, in one
  line naming the key that costs most and the flag that allows a slow render.

The time is a sum of units of work, each with its cost in :data:`SECONDS_PER`, measured by
``python -m explorer.bench.costs``.  The names are also importable from :mod:`lighting.numerics` (memory) and
:mod:`lighting.scene.budget` (a scene).
"""

from __future__ import annotations

import math

__all__ = [
    "DEFAULT_MEMORY_BUDGET",
    "BudgetError",
    "memory_budget",
    "set_memory_budget",
    "check_budget",
    "TIME_LIMIT",
    "SECONDS_PER",
    "scene_estimate",
    "check_scene_budget",
    "explain_lines",
    "prefilter_size",
    "environment_setup_bytes",
]

# ---------------------------------------------------------------------------------------------------- memory

#: Default budget for one allocation-heavy request (an image, a sample set, a mesh), in bytes.
DEFAULT_MEMORY_BUDGET = 2 * 1024**3
_memory_budget = [DEFAULT_MEMORY_BUDGET]


def memory_budget() -> int:
    """The memory budget in force, in bytes (2 GiB unless :func:`set_memory_budget` raised it).

    Returns
    -------
    int
        The budget in bytes.
    """
    return _memory_budget[0]


def set_memory_budget(nbytes: int) -> int:
    """Set the memory budget (bytes); returns the previous one.  The command line's ``--memory-budget``.

    Parameters
    ----------
    nbytes : int
        The new budget in bytes, an integer >= 1.

    Returns
    -------
    int
        The budget in force before the call, in bytes.

    Raises
    ------
    ValueError
        For ``nbytes < 1`` (``ArgumentTypeError`` for a value that is not an integer).
    """
    from ._validate import check_count

    previous = _memory_budget[0]
    _memory_budget[0] = check_count("memory budget", nbytes, 1)
    return previous


def _bytes(n: float) -> str:
    for unit, size in (("GiB", 1024**3), ("MiB", 1024**2), ("KiB", 1024)):
        if n >= size:
            return f"{n / size:.1f} {unit}"
    return f"{int(n)} bytes"


class BudgetError(ValueError):
    """A request whose estimated memory or time is over the budget (a ValueError, so callers catch it as bad input)."""


def check_budget(name: str, estimate_bytes: float, *, what: str = "", budget: int | None = None) -> None:
    """Refuse a request whose estimated memory exceeds the budget, naming ``name`` and the estimate.

    Call it *before* allocating, with an estimate of the peak bytes the request needs.

    Parameters
    ----------
    name : str
        What the request is, for the error message (the arguments that set its size).
    estimate_bytes : float
        The estimated peak memory in bytes; NaN is refused like an estimate over the budget.
    what : str, optional
        A detail shown in parentheses after the estimate (``"1000 shading points"``).
    budget : int or None, optional
        The limit in bytes; ``None`` (default): :func:`memory_budget`.

    Raises
    ------
    BudgetError
        Where ``estimate_bytes`` is not <= the limit.
    """
    limit = memory_budget() if budget is None else budget
    if not estimate_bytes <= limit:  # also refuses NaN estimates
        detail = f" ({what})" if what else ""
        raise BudgetError(
            f"{name} needs about {_bytes(float(estimate_bytes))}{detail}, over the memory budget of "
            f"{_bytes(limit)}; reduce it or raise the budget (--memory-budget)"
        )


# ---------------------------------------------------------------------------------------------------- a scene's memory
# Measured with tracemalloc on the example scenes and generated spheres (peak bytes of a render):
#: the renderer's images and buffers, per pixel (270–420 bytes with one to four objects) …
BYTES_PER_PIXEL = 256
#: … and per pixel and object (each object keeps its own geometry buffer; 625 bytes with five objects);
BYTES_PER_PIXEL_PER_OBJECT = 96
#: a triangle of a mesh held by the scene: the mesh (about 170 bytes) and its rasterization and shading (240–370);
BYTES_PER_TRIANGLE = 640
#: reading a mesh file, per byte of the file (trimesh: 5–23 times the file size for OBJ, PLY, STL, OFF, GLB);
BYTES_PER_MESH_FILE_BYTE = 32
#: reading a scene file, per byte (tomllib's objects for short numbers: about 20 times the text).
BYTES_PER_SCENE_FILE_BYTE = 64
#: reading a BRDF file named by a material, per byte and a fixed part (measured: a MERL table peaks at 3.1 times
#: its 35 MB and keeps 2.0; a ``.brdf`` file's tokens and syntax tree at 79 times its text, plus about 1 MB for
#: checking the shader on a few direction pairs).
BRDF_FILE_BYTES = {".binary": (4, 0), ".brdf": (128, 4 << 20)}
#: a measured (MERL) table held while rendering (its stored values and its filled RGB table), and its importance
#: sampler's tables under a Monte-Carlo environment (90 view bins of 90 x 360 half-vector bins: two CDFs and a
#: density), each once per file and lookup however many parts name it.
MEASURED_TABLE_BYTES = 2 * 8 * 3 * 90 * 90 * 180
MEASURED_SAMPLER_BYTES = 90 * 90 * (2 * 361 + 360) * 8
#: an environment image named by ``[[lights]] source``, per pixel its header declares: reading it and building
#: its sampling tables (measured with tracemalloc: an RLE ``.hdr`` of 1024 x 512 peaks at 132 bytes per pixel to
#: read, the environment at 160 to build its half-pixel cell tables), then holding it (120 measured: the radiance
#: and the tables), and prefiltering it for the split sum, per pixel of the prefiltered source (peak over the three
#: families' levels, computed two at a time on the shading threads: 1002 bytes per pixel at 64 rows, 798 at 128,
#: 639 at 256, 172 at 512, where the levels stop at 256 rows; a lat-long image is prefiltered at its largest
#: power-of-two height up to 1024, a sky at 512 x 256): PREFILTER_BYTES_PER_PIXEL for the pixels of a source up to
#: PREFILTER_LEVEL_PIXELS, PREFILTER_LARGE_BYTES_PER_PIXEL for each pixel beyond (halved down to the levels; a
#: 1024-row file peaks at 125 MB over a 64-row one, the process measured whole).  The dominant lights (the default
#: method) add their tables and the residual's levels: DOMINANT_BYTES and DOMINANT_BYTES_PER_PIXEL of the
#: prefiltered source (the process's peak over the split sum's, a sphere of one glossy part: 36 MB at 64 rows, 91
#: at 256, 639 at 1024).
ENVIRONMENT_BYTES_PER_PIXEL = 168
ENVIRONMENT_HELD_BYTES_PER_PIXEL = 128
PREFILTER_BYTES_PER_PIXEL = 1024
PREFILTER_LEVEL_PIXELS = 512 * 256
PREFILTER_LARGE_BYTES_PER_PIXEL = 96
DOMINANT_BYTES = 48 * 2**20
DOMINANT_BYTES_PER_PIXEL = 384
#: Work is counted against the memory budget too: one light sample at one shading point counts as 8 bytes, so
#: the 2 GiB default allows 268 million light-sample evaluations.  The time limit below is the finer bound.
BYTES_PER_SAMPLE_EVALUATION = 8

# ---------------------------------------------------------------------------------------------------- a scene's time

#: The longest render the budget admits without being asked (``--allow-slow`` on the command line,
#: ``allow_slow=True`` when loading a scene), in seconds as :data:`SECONDS_PER` estimates them.
TIME_LIMIT = 30.0

#: Seconds per unit of work, measured by ``python -m explorer.bench.costs`` (each stage renders a scene built to
#: isolate it and keeps its fastest run; the table holds the least of three such measurements: on a busy machine
#: renders take longer than it says, within the 4x that ``python -m explorer.bench.costs --check`` checks):
#: ``render`` and ``pixel``: a render's fixed part and rasterizing, compositing and encoding one pixel of one
#: object; ``shade KIND``: one light at one shading point for one model part of that kind (an area light counts
#: once per sample); ``monte-carlo KIND``: one Monte-Carlo sample of an environment at one shading point per part
#: of that kind; ``measured table``: one view table of a measured BRDF's importance sampler (90 are built at most,
#: once per file); ``prefilter`` and ``prefilter pixel``: prefiltering an environment for the split sum and the
#: dominant lights, once and per pixel of the prefiltered image; ``split-sum`` / ``dominant`` + ``diffuse`` /
#: ``glossy`` / ``narrow`` (a lobe narrower than the dominant method's ``WIDE_LOBE``, measured on one that takes its
#: ``MID_FACTOR`` of samples, the most a narrow lobe takes): one shading point per part under those methods;
#: ``dominant`` and ``dominant pixel``: finding an environment's dominant lights and making the residual's levels,
#: once and per pixel of the prefiltered image; ``dominant narrow table``: a narrow lobe's table of half vectors
#: (once per part).
SECONDS_PER = {
    "pixel": 2.5e-07,
    "render": 0.001,
    "shade lambert": 5.3e-08,
    "shade phong": 7.8e-08,
    "shade blinn-phong": 8.8e-08,
    "shade cook-torrance": 1.1e-07,
    "shade oren-nayar": 8.9e-08,
    "shade ward": 1.1e-07,
    "shade ashikhmin-shirley": 1.9e-07,
    "shade disney": 2.6e-07,
    "shade mirror": 5e-08,
    "shade measured": 4e-07,
    "shade shader": 1.3e-06,
    "monte-carlo lambert": 6.2e-07,
    "monte-carlo phong": 7.1e-07,
    "monte-carlo blinn-phong": 7.7e-07,
    "monte-carlo cook-torrance": 8.3e-07,
    "monte-carlo oren-nayar": 6.7e-07,
    "monte-carlo ward": 8.5e-07,
    "monte-carlo ashikhmin-shirley": 1.3e-06,
    "monte-carlo disney": 1.3e-06,
    "monte-carlo mirror": 9.2e-08,
    "monte-carlo measured": 2.7e-06,
    "monte-carlo shader": 6.6e-06,
    "measured table": 0.0087,
    "prefilter": 0.0041,
    "prefilter pixel": 1.3e-06,
    "split-sum diffuse": 2.9e-07,
    "split-sum glossy": 4.9e-07,
    "dominant diffuse": 3.5e-07,
    "dominant glossy": 3.9e-06,
    "dominant narrow": 1.3e-05,
    "dominant pixel": 3.7e-06,
    "dominant": 0.0006,
    "dominant narrow table": 0.19,
}
#: The registered models whose costs :data:`SECONDS_PER` holds; a model of another kind counts as the dearest
#: analytic kind.
MODEL_KINDS = ("lambert", "phong", "blinn-phong", "cook-torrance", "oren-nayar", "ward", "ashikhmin-shirley",
               "disney", "mirror")  # fmt: skip
_MEASURED_VIEW_TABLES = 90  # a measured BRDF's sampler builds one table per view bin it meets, at most this many


def _kind(part) -> str:
    """The cost kind of a model part: a registered name, ``"measured"`` (MERL data) or ``"shader"`` (a ``.brdf``)."""
    for cls in type(part).__mro__:
        if cls.__name__ == "MerlBRDF":
            return "measured"
        if cls.__name__ == "FileBRDF":
            return "shader"
        name = cls.__dict__.get("name")
        if isinstance(name, str) and name in MODEL_KINDS:
            return name
    return max(MODEL_KINDS, key=lambda k: SECONDS_PER[f"shade {k}"])


def _lobe(part, method: str) -> str:
    """``"diffuse"``, ``"glossy"`` or (under the dominant lights, narrower than their ``WIDE_LOBE``) ``"narrow"``."""
    if part.term == "diffuse":
        return "diffuse"
    if method != "dominant":
        return "glossy"
    from .integrate.dominant import WIDE_LOBE
    from .integrate.ibl import lobe_sigma

    sigma = lobe_sigma(part.lobe())
    return "diffuse" if math.isinf(sigma) else "glossy" if sigma >= WIDE_LOBE else "narrow"


def _seconds(n: float) -> str:
    return f"{n:.2g} s" if n < 10 else f"{n:.0f} s"


def _clamp(n) -> float:
    """An estimate as a float (a scene's integers can exceed the float range: 4**level, n_lat * n_lon)."""
    return float(min(n, 10**300))


def _charge_file(label: str, size: int) -> None:
    """Refuse (:class:`BudgetError`) scene text of ``size`` bytes too large to parse."""
    check_budget(f"the scene text ({size} bytes)", _clamp(size * BYTES_PER_SCENE_FILE_BYTE), what="reading it")


def _monte_carlo(light) -> bool:
    return getattr(light, "is_environment", False) and light.method == "monte-carlo"


def _environment_lights(scene):
    """``(key, light)`` of every environment light: the scene's, then each object's own (each light once)."""
    seen = set()
    lists = [("lights", scene.lights)] + [(f"objects[{i}].lights", ob.lights) for i, ob in enumerate(scene.objects)
                                          if ob.lights is not None]  # fmt: skip
    for path, lights in lists:
        for j, lt in enumerate(lights):
            if getattr(lt, "is_environment", False) and id(lt) not in seen:
                seen.add(id(lt))
                yield f"{path}[{j}]", lt


def prefilter_size(light) -> tuple[int, int]:
    """``(height, width)`` of the image an environment light's split sum prefilters (before it is made).

    Parameters
    ----------
    light : EnvironmentLight

    Returns
    -------
    tuple of int
        What :func:`lighting.integrate.prefilter.prefilter_environment` chooses: a lat-long image at its
        largest power-of-two height up to 1024, a sky at 256 rows, a constant at the smallest height; width twice
        the height.
    """
    from .integrate.prefilter import prefilter_height

    h = prefilter_height(light.environment)
    return h, 2 * h


def environment_setup_bytes(light) -> int:
    """Peak bytes of making an environment light ready to shade (prefiltering, and the dominant lights' setup).

    Parameters
    ----------
    light : EnvironmentLight
        A light whose method is not Monte Carlo.

    Returns
    -------
    int
        :data:`PREFILTER_BYTES_PER_PIXEL` per pixel of the prefiltered source up to :data:`PREFILTER_LEVEL_PIXELS`
        and :data:`PREFILTER_LARGE_BYTES_PER_PIXEL` per pixel beyond; under the dominant lights, plus
        :data:`DOMINANT_BYTES` and :data:`DOMINANT_BYTES_PER_PIXEL` per pixel.
    """
    h, w = prefilter_size(light)
    pixels = h * w
    total = PREFILTER_BYTES_PER_PIXEL * min(pixels, PREFILTER_LEVEL_PIXELS)
    total += PREFILTER_LARGE_BYTES_PER_PIXEL * max(pixels - PREFILTER_LEVEL_PIXELS, 0)
    if light.method == "dominant":
        total += DOMINANT_BYTES + DOMINANT_BYTES_PER_PIXEL * pixels
    return total


def _material_key(scene, i: int) -> str:
    """The key of object ``i``'s material parts: ``materials.NAME.parts`` for a named material, else its own."""
    material = scene.objects[i].material
    for name, m in scene.materials.items():
        if m is material:
            from .scene.errors import _join

            return _join(_join("materials", name), "parts")
    return f"objects[{i}].material.parts"


def _covered_pixels(scene, i: int) -> float:
    """How many pixels object ``i`` covers at most: its bounding sphere's projection (an ellipse, a pixel wider
    each way), clipped to the image by its bounding square."""
    import numpy as np

    from .render.plan import bounding_sphere

    cam = scene.camera
    w, h = cam.width, cam.height
    try:
        c, r = bounding_sphere(scene.objects[i].geometry)
    except ValueError:
        return float(w * h)
    d = np.asarray(c, dtype=np.float64) - cam.eye
    x, y, z = float(d @ cam.right), float(d @ cam.true_up), float(d @ cam.forward)
    if cam.is_perspective:
        dist = math.sqrt(x * x + y * y + z * z)
        if not (math.isfinite(dist) and dist > r) or z <= 0:
            return float(w * h)  # the camera inside or beside the sphere: the whole image, at most
        beta, alpha = math.acos(min(1.0, z / dist)), math.asin(r / dist)
        if beta + alpha >= 0.5 * math.pi - 1e-3:
            return float(w * h)
        f = cam.focal_px
        lo, hi = math.tan(beta - alpha), math.tan(beta + alpha)
        squeeze = math.cos(beta) ** 2 - math.sin(alpha) ** 2  # the projected ellipse's axes (> 0: beta + alpha < π/2)
        major = f * math.sin(alpha) * math.cos(alpha) / squeeze + 1  # a pixel's margin each way
        minor = f * math.sin(alpha) / math.sqrt(squeeze) + 1
        centre = f * 0.5 * (hi + lo)
        u = (x, y) if beta > 0 else (1.0, 0.0)
        norm = math.hypot(*u) or 1.0
        cx, cy = w / 2 + centre * u[0] / norm, h / 2 - centre * u[1] / norm
    else:
        s = cam.pixels_per_unit
        major = minor = r * s + 1
        cx, cy = w / 2 + x * s, h / 2 - y * s
    side_x = max(0.0, min(w, cx + major) - max(0.0, cx - major))
    side_y = max(0.0, min(h, cy + major) - max(0.0, cy - major))
    return min(side_x * side_y, math.pi * major * minor, float(w * h))


class _Costs:
    """The time of a render by key: ``add(key, seconds, what)``, the largest contributions first."""

    def __init__(self):
        self.by_key: dict[str, list] = {}

    def add(self, key: str, seconds: float, what: str) -> None:
        if seconds <= 0:
            return
        entry = self.by_key.setdefault(key, [0.0, what, 0.0])
        entry[0] += seconds
        if seconds > entry[2]:  # the largest contribution describes the key
            entry[1], entry[2] = what, seconds

    def parts(self) -> list:
        return sorted(((k, s, what) for k, (s, what, _) in self.by_key.items()), key=lambda p: -p[1])


def _points(scene, i: int, mode: str, scale: float) -> float:
    """Shading points of object ``i``: its vertices (Gouraud), triangles (flat) or covered pixels (per pixel)."""
    from .render.mesh import TriangleMesh

    geo = scene.objects[i].geometry
    if isinstance(geo, TriangleMesh) and mode == "gouraud":
        return float(geo.n_vertices)
    if isinstance(geo, TriangleMesh) and mode == "flat":
        return float(geo.n_triangles)
    return _covered_pixels(scene, i) * scale


def _time_estimate(scene) -> _Costs:
    """The render's time by the key that costs it (see :data:`SECONDS_PER`)."""
    from .lights import AreaLight
    from .render.mesh import TriangleMesh
    from .render.plan import compile_plan

    cam = scene.camera
    pixels = cam.width * cam.height
    n = len(scene.objects)
    costs = _Costs()
    costs.add("image.width × image.height", SECONDS_PER["render"] + pixels * n * SECONDS_PER["pixel"],
              f"{cam.width}x{cam.height} pixels, {n} object{'s' * (n != 1)}")  # fmt: skip
    modes = [scene.object_mode(i) for i in range(n)]
    per_pixel = [i for i in range(n) if modes[i] == "phong" or not isinstance(scene.objects[i].geometry, TriangleMesh)]
    covered = sum(_covered_pixels(scene, i) for i in per_pixel)
    scale = min(1.0, pixels / covered) if covered > 0 else 1.0  # a pixel is shaded for the one object it shows
    tables, prefiltered, narrow = set(), set(), set()
    env_keys = {id(lt): key for key, lt in _environment_lights(scene)}
    for i, ob in enumerate(scene.objects):
        points = _points(scene, i, modes[i], scale)
        lights = scene.object_lights(i)
        own = ob.lights is not None
        light_key = {id(lt): (f"objects[{i}].lights[{j}]" if own else f"lights[{j}]") for j, lt in enumerate(lights)}
        if scene.is_opengl_lit(i):
            costs.add(f"objects[{i}]", points * len(lights) * SECONDS_PER["shade blinn-phong"],
                      f"OpenGL lighting at about {points:.0f} shading points")  # fmt: skip
            continue
        try:
            plan = compile_plan(ob.material, lights, mode=modes[i], form=scene.render.form, terms=scene.render.terms)
        except ValueError:
            continue
        if plan.strategy == "constant":
            continue
        parts = plan.kept_parts
        kinds = [_kind(p) for p in parts]
        mat_key = _material_key(scene, i)
        many = f" × {len(parts)} parts of {mat_key}" if len(parts) > 1 else ""
        per_light = sum(SECONDS_PER[f"shade {k}"] for k in kinds)
        for lt in plan.kept_lights:
            samples = int(lt.samples) if isinstance(lt, AreaLight) else 1
            key = f"{light_key.get(id(lt), 'lights')}.samples" if samples > 1 else mat_key
            what = (f"{samples} area-light samples{many} at about {points:.0f} shading points" if samples > 1 else
                    f"{len(parts)} model part{'s' * (len(parts) != 1)} under a light at about {points:.0f} "
                    "shading points")  # fmt: skip
            costs.add(key, points * samples * per_light, what)
        for lt in plan.environments:
            key = env_keys.get(id(lt), light_key.get(id(lt), "lights"))
            if lt.method == "monte-carlo":
                seconds = points * lt.samples * sum(SECONDS_PER[f"monte-carlo {k}"] for k in kinds)
                costs.add(f"{key}.samples", seconds,
                          f"{lt.samples} Monte-Carlo samples{many} at about {points:.0f} shading points")  # fmt: skip
                for p, k in zip(parts, kinds, strict=True):
                    if k == "measured" and (type(p), getattr(p, "interpolation", None)) not in tables:
                        tables.add((type(p), getattr(p, "interpolation", None)))
                        costs.add(mat_key, _MEASURED_VIEW_TABLES * SECONDS_PER["measured table"],
                                  "a measured BRDF's sampler tables")  # fmt: skip
            else:
                lobes = [_lobe(p, lt.method) for p in parts]
                per_point = sum(SECONDS_PER[f"{lt.method} {lobe}"] for lobe in lobes)
                costs.add(key, points * per_point, f"the {lt.method} method{many} at about {points:.0f} shading "
                          "points")  # fmt: skip
                for p, lobe in zip(parts, lobes, strict=True):
                    if lobe == "narrow" and repr(p) not in narrow:  # the dominant method's table, once per lobe
                        narrow.add(repr(p))
                        costs.add(mat_key, SECONDS_PER["dominant narrow table"], "a narrow lobe's half-vector table")
                if id(lt) not in prefiltered:
                    prefiltered.add(id(lt))
                    h, w = prefilter_size(lt)
                    first = 0.0
                    if lt.method == "dominant":
                        first = SECONDS_PER["dominant"] + h * w * SECONDS_PER["dominant pixel"]
                    costs.add(key, first + SECONDS_PER["prefilter"] + h * w * SECONDS_PER["prefilter pixel"],
                              f"prefiltering a {w}x{h} environment")  # fmt: skip
    return costs


def scene_estimate(scene) -> dict:
    """Estimated peak memory, work and time of rendering ``scene``, before anything is allocated.

    The constants (``BYTES_PER_PIXEL``, :data:`SECONDS_PER` and the others in this module) were measured on the
    example scenes and on scenes built to isolate one stage each.

    Parameters
    ----------
    scene : Scene
        The scene to estimate.

    Returns
    -------
    dict
        ``bytes`` (memory), ``evaluations`` (light samples times shading points), ``parts``
        (``[(key, bytes, what)]``, the memory by cause), ``work_key`` (the key that drives the
        work: the area light with the most samples, else ``"lights"``), ``seconds`` (the estimated time)
        and ``time_parts`` (``[(key, seconds, what)]``, the time by the key that costs it, largest first).
    """
    from ._text import plural
    from .lights import AreaLight
    from .render.mesh import TriangleMesh

    cam = scene.camera
    pixels = cam.width * cam.height
    n = len(scene.objects)
    parts = [("image.width × image.height", pixels * (BYTES_PER_PIXEL + BYTES_PER_PIXEL_PER_OBJECT * n),
              f"{cam.width}x{cam.height} pixels, {plural(n, 'object')}")]  # fmt: skip
    phong_samples, evaluations = 0, 0
    best = (0, "lights")
    measured = {}
    for i, ob in enumerate(scene.objects):
        geo = ob.geometry
        if isinstance(geo, TriangleMesh):
            parts.append((f"objects[{i}]", geo.n_triangles * BYTES_PER_TRIANGLE, f"{geo.n_triangles} triangles"))
        own = ob.lights is not None
        samples = 0
        lights = scene.object_lights(i)
        for j, lt in enumerate(lights):
            k = int(lt.samples) if isinstance(lt, AreaLight) or _monte_carlo(lt) else 1
            samples += k
            if k > best[0]:
                best = (k, f"objects[{i}].lights[{j}].samples" if own else f"lights[{j}].samples")
        mode = scene.object_mode(i)
        if mode == "phong" or not isinstance(geo, TriangleMesh):
            phong_samples = max(phong_samples, samples)  # each pixel is shaded for the one object it shows
        else:
            evaluations += samples * (geo.n_vertices if mode == "gouraud" else geo.n_triangles)
        material = getattr(ob, "material", None)
        for p in getattr(getattr(material, "brdf", None), "parts", ()):
            if _kind(p) == "measured":
                entry = measured.setdefault(type(p), [_material_key(scene, i), set(), False])
                entry[1].add(getattr(p, "interpolation", None))
                entry[2] = entry[2] or any(_monte_carlo(lt) for lt in lights)
    evaluations += pixels * phong_samples
    for key, tables, sampled in measured.values():
        nbytes = MEASURED_TABLE_BYTES + (len(tables) * MEASURED_SAMPLER_BYTES if sampled else 0)
        parts.append((key, nbytes, "a measured BRDF's table" + (" and its sampler's tables" if sampled else "")))
    for key, lt in _environment_lights(scene):
        if lt.method != "monte-carlo":
            h, w = prefilter_size(lt)
            parts.append((key, environment_setup_bytes(lt), f"prefiltering a {w}x{h} environment"))
    if best[0] <= 1:
        best = (best[0], "lights")
    time_parts = _time_estimate(scene).parts()
    return {"bytes": sum(p[1] for p in parts), "evaluations": evaluations, "parts": parts, "work_key": best[1],
            "seconds": sum(p[1] for p in time_parts), "time_parts": time_parts}  # fmt: skip


def check_scene_budget(scene, *, size_flag: str | None = None) -> dict:
    """Refuse a scene whose render would need more memory than the budget, or more time than :data:`TIME_LIMIT`.

    A scene loaded with ``allow_slow=True`` (the command line's ``--allow-slow``) may take longer.

    Parameters
    ----------
    scene : Scene
        The scene to check.
    size_flag : str, optional
        The command-line flag that set the image size (e.g. ``"--size 640x480"``): named
        instead of the file's image size when the size is what weighs most.

    Returns
    -------
    dict
        The estimate (:func:`scene_estimate`).

    Raises
    ------
    SceneBudgetError
        Naming the file and the key that weighs most: the image size, an object's mesh, a
        light's ``samples`` or a material's parts.
    """
    from .scene.errors import SceneBudgetError

    est = scene_estimate(scene)
    key, _, _ = max(est["parts"], key=lambda p: p[1])
    whats = "; ".join(w for _, b, w in est["parts"] if b)
    try:
        check_budget("the scene", _clamp(est["bytes"]), what=whats)
    except BudgetError as e:
        if size_flag and key.startswith("image."):
            raise SceneBudgetError(size_flag, "", str(e)) from None
        raise SceneBudgetError(scene.source, key, str(e)) from None
    evaluations = est["evaluations"]
    try:
        check_budget("the lighting", _clamp(evaluations * BYTES_PER_SAMPLE_EVALUATION),
                     what=f"{evaluations:.3g} light-sample evaluations, counted as {BYTES_PER_SAMPLE_EVALUATION} "
                     "bytes each")  # fmt: skip
    except BudgetError as e:
        raise SceneBudgetError(scene.source, est["work_key"], str(e)) from None
    seconds = est["seconds"]
    if not (seconds <= TIME_LIMIT or getattr(scene, "allow_slow", False)):
        key, _, what = est["time_parts"][0]
        detail = (f"the render needs about {_seconds(seconds)} ({what}), over the time limit of "
                  f"{_seconds(TIME_LIMIT)}; reduce it, or allow a slow render with --allow-slow (allow_slow=True "
                  "when loading the scene)")  # fmt: skip
        if size_flag and key.startswith("image."):
            raise SceneBudgetError(size_flag, "", detail)
        raise SceneBudgetError(scene.source, key, detail)
    return est


def explain_lines(scene) -> list:
    """What the budget says about a scene's render, for ``--explain``: each environment's cost and the time.

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    list of str
        One line per environment light (the prefilter's size and memory, or its Monte-Carlo samples), then
        the estimated time with the keys that cost most.
    """
    lines = []
    for key, lt in _environment_lights(scene):
        shown = "; drawn behind the objects" if lt.background and key.startswith("lights[") else ""
        if lt.method != "monte-carlo":
            h, w = prefilter_size(lt)
            mib = environment_setup_bytes(lt) / 2**20
            lines.append(f"environment {key}: prefiltering {w}x{h} needs about {mib:.1f} MiB at its peak "
                         f"(budget estimate){shown}")  # fmt: skip
        else:
            lines.append(f"environment {key}: {lt.samples} Monte-Carlo samples per shading point, counted in the "
                         f"work budget{shown}")  # fmt: skip
    est = scene_estimate(scene)
    top = "; ".join(f"{k}: {_seconds(s)}, {what}" for k, s, what in est["time_parts"][:3])
    allowed = ", lifted (--allow-slow, allow_slow=True)" if est["seconds"] > TIME_LIMIT else ""
    lines.append(f"estimated time: about {_seconds(est['seconds'])} ({top}); the time limit is "
                 f"{_seconds(TIME_LIMIT)}{allowed}")  # fmt: skip
    return lines
