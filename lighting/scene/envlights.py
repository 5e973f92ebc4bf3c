"""Environment lights in scene files: ``[[lights]] type = "environment"``.

An environment light is a sky around the whole scene (:class:`~lighting.lights.envlight.EnvironmentLight`):
``source`` names a latitude–longitude image file (``.hdr``, ``.pic``, ``.pfm``, ``.npy``, ``.exr``;
relative to the scene's folder, a regular file, as BRDF files are) or a procedural sky
(:data:`lighting.lights.skies.SKIES`); ``radiance`` gives a constant sky instead (neither: radiance 1,
the white furnace).  A name with an image file's extension is a file; anything else is a sky name,
so a scene never reads a file it does not name as one.

An image file is charged to the budget from the size its header declares, before its pixels are
read (:func:`lighting.lights.envfiles.declared_image_size`, :data:`~lighting.scene.budget.ENVIRONMENT_BYTES_PER_PIXEL`).

A light list (the scene's, or an object's own) holds at most one environment light: the
environment is what the camera sees behind the objects, and two of them would be one sky that is
their sum (make that sky one image file).
"""

from __future__ import annotations

import os

from .._budget import BudgetError
from .._validate import check_color
from ..lights.envfiles import IMAGE_EXTENSIONS, declared_image_size, load_environment
from ..lights.envlight import EnvironmentLight
from ..lights.skies import SKIES
from .budget import ENVIRONMENT_BYTES_PER_PIXEL, ENVIRONMENT_HELD_BYTES_PER_PIXEL
from .errors import SceneBudgetError, _fmt_value, _join, _suggest

__all__ = ["declared_image_size", "check_one_environment"]  # declared_image_size: envfiles', re-exported


def _source(ctx, path, spec):
    """``(path, spec)`` of a file (resolved, checked, charged) or ``(name, None)`` of a sky, from ``source = spec``."""
    key = _join(path, "source")
    allowed = (f"an environment image file ({', '.join(IMAGE_EXTENSIONS)}), relative to the scene's folder, "
               f"or a sky name ({', '.join(SKIES)})")  # fmt: skip
    if not spec.strip() or "\0" in spec:
        ctx.fail(key, f"must be {allowed}; got {_fmt_value(spec)}")
    ext = os.path.splitext(spec.strip())[1].lower()
    if ext not in IMAGE_EXTENSIONS:
        name = spec.strip().lower().replace("_", "-")
        if name in SKIES:
            return name, None
        hint = _suggest(name, list(SKIES))
        what = f"has the extension {ext!r}, not an image file's" if ext else "is not a sky name"
        ctx.fail(key, f"{_fmt_value(spec)} {what}; {hint}allowed: {allowed}")
    p = os.path.normpath(os.path.join(ctx.base_dir, os.path.expanduser(spec)))
    if not os.path.isfile(p):
        what = "does not exist" if not os.path.exists(p) else "is not a regular file"
        ctx.fail(key, f"{_fmt_value(spec)}{ctx.resolved(spec, p)} {what}; an environment image must be an existing "
                      "file, relative to the scene's folder")  # fmt: skip
    size = declared_image_size(p)
    if size is not None:
        h, w = size
        ctx.charge(key, h * w * ENVIRONMENT_BYTES_PER_PIXEL, f"reading a {w}x{h} environment image", held=False)
        ctx.charge(key, h * w * ENVIRONMENT_HELD_BYTES_PER_PIXEL, f"holding a {w}x{h} environment image")
    return p, spec


def environment_light(ctx, path: str, params: dict) -> EnvironmentLight:
    """Build the :class:`EnvironmentLight` of a checked ``[[lights]]`` table (``type`` removed).

    Parameters
    ----------
    ctx : lighting.scene.checks._Ctx
        The parse (file name for messages, the scene's folder, the budget charged so far).
    path : str
        The light's key path (``lights[0]``, ``objects[2].lights[0]``).
    params : dict
        The table's values, each type-checked (:data:`lighting.scene.schema.LIGHT_KEYS`).

    Returns
    -------
    EnvironmentLight
        With the values as written in ``_scene_values`` (saving writes them back, a file path as
        the scene gave it).
    """
    if "source" in params and "radiance" in params:
        ctx.fail(path, "an environment light has either source = FILE or SKY, or radiance = VALUE, not both")
    method = params["method"]
    if method != "monte-carlo":
        for k in ("samples", "seed"):
            if k in params:
                ctx.fail(_join(path, k), f"applies to method = 'monte-carlo' only (this light's method is "
                                         f"{method!r}); remove it or set method = 'monte-carlo'")  # fmt: skip
    is_file = False
    if "source" in params:
        environment, written = _source(ctx, path, params["source"])
        is_file = written is not None
    else:
        environment = params.get("radiance", 1.0)
        try:  # the light's own message would offer files and skies too: only a radiance belongs here
            check_color("radiance", environment)
        except ValueError as e:
            ctx.fail(_join(path, "radiance"), str(e))
    kwargs = {k: params[k] for k in ("intensity", "rotation", "background", "method", "samples", "seed") if k in params}
    if is_file:
        # An image file: its reader's messages start with the file's path, not a parameter's name.
        try:
            environment = load_environment(environment)
        except BudgetError as e:
            raise SceneBudgetError(ctx.source, _join(path, "source"), str(e)) from None
        except ValueError as e:
            ctx.fail(_join(path, "source"), str(e))
    light = ctx.build(path, EnvironmentLight, {"environment": environment, **kwargs},
                      {"environment": "source" if "source" in params else "radiance"})  # fmt: skip
    if "source" in params:
        light.source = params["source"]  # as written: the light's own to_dict() gives the scene's text back
    light._scene_values = params
    return light


def check_one_environment(ctx, path: str, lights) -> None:
    """Refuse a light list with more than one environment light, naming the second.

    Parameters
    ----------
    ctx : lighting.scene.checks._Ctx
    path : str
        The list's key path (``lights``, ``objects[1].lights``).
    lights : sequence
        Its lights, built.
    """
    idx = [i for i, lt in enumerate(lights) if getattr(lt, "is_environment", False)]
    if len(idx) > 1:
        ctx.fail(_join(_join(path, idx[1]), "type"),
                 f"a light list holds at most one environment light ({path}[{idx[0]}] is one): it is the sky "
                 "behind the whole scene; make two skies one image file, or give an object its own lights")  # fmt: skip
