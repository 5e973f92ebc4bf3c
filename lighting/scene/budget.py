"""The memory and work budget of a scene: estimates made before anything is allocated, and the refusal.

The constants below are peak bytes measured with ``tracemalloc`` on the example scenes and
generated spheres; ``docs/scenes.md`` lists them with what they cover.
"""

from __future__ import annotations

from .._numeric import BudgetError, check_budget
from .._text import plural
from ..lights import AreaLight
from ..render.mesh import TriangleMesh
from .errors import SceneBudgetError
from .model import Scene

__all__ = ["scene_estimate", "check_scene_budget", "prefilter_size"]

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
#: an environment image named by ``[[lights]] source``, per pixel its header declares: reading it and building
#: its sampling tables (measured with tracemalloc: an RLE ``.hdr`` of 1024 x 512 peaks at 132 bytes per pixel to
#: read, the environment at 160 to build its half-pixel cell tables), then holding it (120 measured: the radiance
#: and the tables), and prefiltering it for the split sum, per pixel of the prefiltered source (peak over the three
#: families' levels, computed two at a time on the shading threads: 1002 bytes per pixel at 64 rows, 798 at 128,
#: 639 at 256, 172 at 512, where the levels stop at 256 rows; a lat-long image is prefiltered at its largest
#: power-of-two height up to 1024, a sky at 512 x 256).
ENVIRONMENT_BYTES_PER_PIXEL = 168
ENVIRONMENT_HELD_BYTES_PER_PIXEL = 128
PREFILTER_BYTES_PER_PIXEL = 1024
#: Work is counted against the same budget: one light sample at one shading point counts as 8 bytes, so the
#: 2 GiB default allows 268 million light-sample evaluations (docs/scenes.md says how long that takes).
BYTES_PER_SAMPLE_EVALUATION = 8


def _clamp(n) -> float:
    """An estimate as a float (a scene's integers can exceed the float range: 4**level, n_lat * n_lon)."""
    return float(min(n, 10**300))


def _charge_file(label: str, size: int) -> None:
    """Refuse (:class:`~lighting._numeric.BudgetError`) scene text of ``size`` bytes too large to parse."""
    check_budget(f"the scene text ({size} bytes)", _clamp(size * BYTES_PER_SCENE_FILE_BYTE), what="reading it")


def scene_estimate(scene: Scene) -> dict:
    """Estimated peak memory and work of rendering ``scene``, before anything is allocated.

    The constants (``BYTES_PER_PIXEL`` and the others in this module) were measured on the
    example scenes.

    Parameters
    ----------
    scene : Scene
        The scene to estimate.

    Returns
    -------
    dict
        ``bytes`` (memory), ``evaluations`` (light samples times shading points), ``parts``
        (``[(key, bytes, what)]``, the memory by cause) and ``work_key`` (the key that drives the
        work: the area light with the most samples, else ``"lights"``).
    """
    cam = scene.camera
    pixels = cam.width * cam.height
    n = len(scene.objects)
    parts = [("image.width × image.height", pixels * (BYTES_PER_PIXEL + BYTES_PER_PIXEL_PER_OBJECT * n),
              f"{cam.width}x{cam.height} pixels, {plural(n, 'object')}")]  # fmt: skip
    phong_samples, evaluations = 0, 0
    best = (0, "lights")
    for i, ob in enumerate(scene.objects):
        geo = ob.geometry
        if isinstance(geo, TriangleMesh):
            parts.append((f"objects[{i}]", geo.n_triangles * BYTES_PER_TRIANGLE, f"{geo.n_triangles} triangles"))
        own = ob.lights is not None
        samples = 0
        for j, lt in enumerate(scene.object_lights(i)):
            k = int(lt.samples) if isinstance(lt, AreaLight) or _monte_carlo(lt) else 1
            samples += k
            if k > best[0]:
                best = (k, f"objects[{i}].lights[{j}].samples" if own else f"lights[{j}].samples")
        mode = scene.object_mode(i)
        if mode == "phong" or not isinstance(geo, TriangleMesh):
            phong_samples = max(phong_samples, samples)  # each pixel is shaded for the one object it shows
        else:
            evaluations += samples * (geo.n_vertices if mode == "gouraud" else geo.n_triangles)
    evaluations += pixels * phong_samples
    for key, lt in _environment_lights(scene):
        if lt.method != "monte-carlo":
            h, w = prefilter_size(lt)
            parts.append((key, h * w * PREFILTER_BYTES_PER_PIXEL, f"prefiltering a {w}x{h} environment"))
    if best[0] <= 1:
        best = (best[0], "lights")
    return {"bytes": sum(p[1] for p in parts), "evaluations": evaluations, "parts": parts, "work_key": best[1]}


def _monte_carlo(light) -> bool:
    return getattr(light, "is_environment", False) and light.method == "monte-carlo"


def _environment_lights(scene: Scene):
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
    from ..integrate.prefilter import prefilter_height

    h = prefilter_height(light.environment)
    return h, 2 * h


def check_scene_budget(scene: Scene, *, size_flag: str | None = None) -> dict:
    """Refuse a scene whose estimated memory or work (:func:`scene_estimate`) is over the budget.

    :class:`~lighting.scene.renderer.SceneRenderer` calls this before it allocates anything.

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
        Naming the file and the key that weighs most: the image size, an object's mesh or a
        light's ``samples``.
    """
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
    return est
