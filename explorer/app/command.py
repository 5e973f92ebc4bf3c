"""The ``explore`` command: its options (:func:`add_parser`, :func:`build_parser`), :func:`run` and :func:`main`."""

from __future__ import annotations

import argparse
import os
import sys

import numpy as np

from ..compare import BRDFList
from .display import display_problem, no_display_message
from .state import (
    ATTENUATIONS,
    CHANNELS,
    CONTROLS,
    DEFAULTS,
    ENVIRONMENTS,
    FIT_MODELS,
    FORMS,
    LIGHT_TYPES,
    MAX_ENTRIES,
    MODELS,
    NDFS,
    VIEWS_3D,
    AppState,
)

#: Smallest and largest window the explorer lays out.
# The smallest window whose views, captions and controls all still fit (checked by the window's tests).
MIN_WINDOW, MAX_WINDOW = (800, 500), (8192, 8192)
#: The window's size when ``--size`` is not given.
DEFAULT_WINDOW_SIZE = (1280, 768)


def _shown(value) -> str:
    if isinstance(value, bool):
        return "on" if value else "off"
    if isinstance(value, (tuple, list)):
        return ",".join(_shown(v) for v in value)
    return f"{value:g}" if isinstance(value, float) else str(value)


__all__ = ["add_parser", "build_parser", "run", "main"]


DESCRIPTION = (
    "Open the explorer window: a lit sphere, Gouraud against Phong, BRDF lobe, polar and angle "
    "plots, all computed by the engine. Every option sets the starting value of a control."
)


def build_parser() -> argparse.ArgumentParser:
    """The parser of ``lighting-explorer [options]`` (the ``explore`` command on its own).

    Returns
    -------
    argparse.ArgumentParser
        A :class:`explorer.cli.OneLineParser` with the options of :func:`add_options`.
    """
    from ..cli import OneLineParser

    p = OneLineParser(prog="lighting-explorer", description=DESCRIPTION)
    add_options(p)
    return p


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Add the ``explore`` command to a command line's sub-parsers; it runs :func:`run`.

    Parameters
    ----------
    subparsers : explorer.cli.SubCommands
        What ``add_subparsers`` of the ``lighting-explorer`` parser returned.

    Returns
    -------
    argparse.ArgumentParser
        The ``explore`` parser (its ``func`` default is :func:`run`).
    """
    # Named as the program: explore is what runs with no sub-command, so its usage and errors say
    # ``lighting-explorer [options]`` either way.
    p = subparsers.add_parser("explore", help="the explorer window (the default: no sub-command)",
                              description=DESCRIPTION, prog="lighting-explorer")  # fmt: skip
    add_options(p)
    p.set_defaults(func=run)
    return p


def add_options(p) -> None:
    """The options of the ``explore`` command: one per control (its starting value), and the window's.

    Parameters
    ----------
    p : argparse.ArgumentParser
        The parser to add them to.
    """
    from ..cli import OptionGroup, size_type

    # The options default to None ("keep the control's starting value"); the help states that value.
    h = {
        name: f"{spec.help} (default: {_shown(DEFAULTS[name])})" if name in DEFAULTS else spec.help
        for name, spec in CONTROLS.items()
    }
    g = OptionGroup(p, "material")
    g.add_argument("--model", choices=MODELS, help=h["model"])
    g.add_argument(
        "--kd", help=f"diffuse albedo: one number (times --color) or r,g,b (default: {_shown(DEFAULTS['kd'])})"
    )
    g.add_argument("--color", help=h["color"])
    g.add_argument("--ks", type=float, help="the model's specular coefficient k_s (default: the model's own)")
    g.add_argument("--shininess", type=float, help="the Phong / Blinn-Phong exponent e (default: the model's own)")
    g.add_argument(
        "--roughness", type=float, help="the roughness, Cook-Torrance's α or Disney's r (default: the model's)"
    )
    g.add_argument(
        "--f0", type=float, help="Cook-Torrance's Fresnel reflectance F0 at normal incidence (default: the model's)"
    )
    g.add_argument("--ndf", choices=NDFS, help="Cook-Torrance's normal distribution (default: the model's)")
    g.add_argument("--param", action="append", metavar="NAME=VALUE",
                   help="any parameter of the model, e.g. --param sigma=0.3 (repeat for more)")  # fmt: skip
    g.add_argument("--phi", type=float, help=h["phi"])
    g.add_argument("--lock", action=argparse.BooleanOptionalAction, default=None, help=h["lock"])
    g = OptionGroup(p, "light")
    g.add_argument("--light", choices=LIGHT_TYPES, help=h["light"])
    g.add_argument("--elevation", type=float, help=h["elevation"])
    g.add_argument("--azimuth", type=float, help=h["azimuth"])
    g.add_argument("--intensity", type=float, help=h["intensity"])
    g.add_argument("--light-color", dest="light_color", help=h["light_color"])
    g.add_argument("--ambient", type=float, help=h["ambient"])
    g.add_argument("--distance", type=float, help=h["distance"])
    g.add_argument("--attenuation", choices=tuple(ATTENUATIONS), help=h["attenuation"])
    g.add_argument("--cutoff", type=float, help=h["cutoff"])
    g.add_argument("--spot-exponent", dest="spot_exponent", type=float, help=h["spot_exponent"])
    g = OptionGroup(p, "shading and plots")
    g.add_argument("--mode", choices=("flat", "gouraud", "phong"), help=h["mode"])
    g.add_argument("--form", choices=FORMS, help=h["form"])
    g.add_argument("--terms", help=f"terms shown, comma-separated from {_shown(DEFAULTS['terms'])} (default: all)")
    g.add_argument("--tessellation", type=int, help=h["tessellation"])
    g.add_argument("--channel", choices=CHANNELS, help=h["channel"])
    g.add_argument("--log", action=argparse.BooleanOptionalAction, default=None, help=h["log"])
    g.add_argument("--times-cos", dest="times_cos", action=argparse.BooleanOptionalAction, default=None,
                   help=h["times_cos"])  # fmt: skip
    g.add_argument("--exposure", type=float, help=h["exposure"])
    g.add_argument("--scanline", type=float, help=h["scanline"])
    g = OptionGroup(p, "comparing BRDFs")
    g.add_argument(
        "--brdf",
        action="append",
        metavar="FILE",
        help="open a BRDF file (.brdf: BRDF Explorer's format; .binary: MERL data) as a model; the first "
        "becomes the current model, the others entries of the Compare list (repeat for more)",
    )
    g.add_argument("--panel", choices=("angles", "albedo"), help=h["panel"])
    g.add_argument("--split", action=argparse.BooleanOptionalAction, default=None, help=h["split"])
    g.add_argument("--fit", choices=tuple(FIT_MODELS), help=h["fit"])
    g.add_argument(
        "--fit-now",
        dest="fit_now",
        action="store_true",
        help="fit that model to the current one at start and add it to the Compare list",
    )
    g = OptionGroup(p, "image-based lighting")
    names = ", ".join(e for e in ENVIRONMENTS if e != "file")
    g.add_argument("--environment", metavar="NAME|FILE",
                   help=f"{CONTROLS['environment'].help}: {names}, or an environment image "
                        f"(.hdr .pfm .npy .exr, lat-long) (default: {DEFAULTS['environment']})")  # fmt: skip
    g.add_argument("--env-rotation", dest="env_rotation", type=float, help=h["env_rotation"])
    g.add_argument("--env-intensity", dest="env_intensity", type=float, help=h["env_intensity"])
    g.add_argument("--view3d", choices=VIEWS_3D, help=h["view3d"])
    g.add_argument("--reference", action=argparse.BooleanOptionalAction, default=None, help=h["reference"])
    g.add_argument(
        "--mesh",
        metavar="FILE",
        help="the lit object's mesh (.obj .ply .stl .glb .gltf .off, +y up) (default: a generated blob)",
    )
    g = OptionGroup(p, "window")
    g.add_argument(
        "--scene",
        metavar="SCENE",
        help="start from a scene file (TOML) or an example scene (render --list): its first object's "
        "material and its lights",
    )
    g.add_argument(
        "--size",
        type=size_type("--size", minimum=MIN_WINDOW, maximum=MAX_WINDOW, example="1280x768"),
        default=DEFAULT_WINDOW_SIZE,
        metavar="WxH",
        help="window size in pixels, WIDTHxHEIGHT or N for a square",
    )
    g.add_argument("--off-screen", dest="off_screen", action="store_true", help="render without a window")
    g.add_argument("--opengl-3d", dest="opengl_3d", action="store_true",
                   help="draw the 3D lobe in an OpenGL widget (pyvistaqt) instead of VTK's off-screen images: smoother "
                   "turning with a GPU, but Qt then composes every repaint of the window through OpenGL")  # fmt: skip
    g.add_argument("--screenshot", metavar="PATH",
                   help="render the window to an image (.png; .jpg .tif .webp with Pillow) and exit "
                        "(implies --off-screen)")  # fmt: skip


def main(argv=None) -> int:
    """``lighting-explorer [options]``: open the window, or with ``--screenshot`` write it to an image.

    Parameters
    ----------
    argv : list of str, optional
        The options (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status: 0 done, 1 no display to open a window on, 2 a bad option or output path.
    """
    from ..cli import parse_and_run

    return parse_and_run(build_parser, run, argv, errors=(ValueError, OSError))


def run(args) -> int:
    """Run the ``explore`` command from parsed options (what :func:`main` and the CLI tree call).

    Parameters
    ----------
    args : argparse.Namespace
        Options as :func:`add_options` defines them.

    Returns
    -------
    int
        The exit status, as :func:`main`.
    """
    from ..cli import print_error, require, resolve_scene
    from ..output import check_output_path, write_image
    from . import ExplorerApp  # through the package, so that a test can stand in for the window

    try:
        if args.screenshot is not None:  # checked before the window is built: no work for a file we cannot write
            check_output_path(args.screenshot, flag="--screenshot", kinds=("rgb8",))
        model_params = ("ks", "shininess", "roughness", "f0", "ndf", "param")
        values = {k: v for k, v in vars(args).items() if k in CONTROLS or k in ("kd", "scene") + model_params}
        if values.get("scene"):  # a file, or an example's name as ``render NAME`` takes it
            values["scene"] = resolve_scene(values["scene"], flag="--scene")
        files = list(getattr(args, "brdf", None) or ())
        classes = []
        if files:
            # Each file becomes a registered model (the reader's one-line error names a bad file); the
            # first is the current model, so its parameters (--param) are read against its own table.
            from lighting.files import file_model

            classes = [file_model(path, register=True) for path in files]
            values["model"] = values.get("model") or classes[0].name
        env_file = scene_env = None
        env = values.get("environment")
        if env is not None and env.strip().lower().replace("_", "-") not in ENVIRONMENTS:
            env_file, values["environment"] = env, "file"  # a file, read (and checked) below
        elif env is not None and env.strip().lower() == "file":
            raise ValueError("--environment file needs the file itself: --environment PATH")
        elif env is None and values.get("scene"):
            from .scenes import scene_environment_file

            scene_env = scene_environment_file(values["scene"])  # the scene's own environment file, read once
        mesh = None
        if getattr(args, "mesh", None) is not None:
            from lighting.render.mesh import load_mesh

            mesh = load_mesh(args.mesh)  # a bad file: its one-line error, before the window is built
        if env_file is not None:
            from lighting.lights import load_environment

            env_file = (env_file, load_environment(env_file))
        elif scene_env is not None:
            env_file = scene_env
        state = AppState.from_args(values)
        compare = BRDFList(max_entries=MAX_ENTRIES)
        for path, cls in zip(files[1:], classes[1:], strict=True):
            compare.add(cls(), os.path.basename(path))
    except (ValueError, OSError) as exc:
        return print_error(exc)
    off_screen = bool(args.off_screen or args.screenshot)
    problem = None if off_screen else display_problem()  # before loading Qt and VTK: said at once
    if problem:
        print(no_display_message(problem), file=sys.stderr)
        return 1
    try:
        # The window is Qt's, its 3D view VTK's: the one line names the extra to install.
        require("explore", "PySide6", "pyvista", "pyvistaqt")
    except ValueError as exc:
        return print_error(exc)
    from ..qt.app import qt_application, run_window

    qt_application(off_screen=off_screen)
    try:
        extra = {"interactive_3d": True} if getattr(args, "opengl_3d", False) and not off_screen else {}
        window = ExplorerApp(state, window_size=args.size, compare=compare, mesh=mesh, environment_file=env_file,
                             **extra)  # fmt: skip
        if getattr(args, "fit_now", False):
            window.fit()
    except ValueError as exc:
        return print_error(exc)
    if args.screenshot is not None:
        try:
            rgb8 = np.ascontiguousarray(window.image(), dtype=np.uint8)
        finally:
            window.close()
        try:
            write_image(args.screenshot, rgb8=rgb8, flag="--screenshot")
        except ValueError as exc:
            return print_error(exc)
        print(f"lighting-explorer: wrote {args.screenshot} ({rgb8.shape[1]}x{rgb8.shape[0]})")
        return 0
    if off_screen:
        window.close()
        print("lighting-explorer: rendered off-screen (add --screenshot PATH to keep the picture)")
        return 0
    return run_window(window)
