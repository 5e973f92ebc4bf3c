"""``lighting-explorer render``: render a scene file to a PNG, headless.

    lighting-explorer render SCENE [-o OUT.png] [--size WxH|N] [-D KEY=VALUE ...]
                             [--exposure STOPS] [--tonemap clamp|reinhard] [--explain]
    lighting-explorer render --list

``SCENE`` is a scene file (format: ``docs/scenes.md``) or the name of a scene
shipped with the package (``lighting-explorer render spotlight``).  One summary
line is printed: the output, the size, how many objects and lights, the time,
and how many pixels clipped when encoding.  Any problem — a malformed scene, a
missing mesh, an unwritable output — prints ``lighting-explorer: error: …`` on
standard error and returns 2; the PNG is written to a temporary file and renamed
into place only when complete, so a failed run never leaves a partial or
overwritten file.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

__all__ = ["add_parser", "run", "main"]

PROG = "lighting-explorer render"
DESCRIPTION = (
    "Render a scene file (TOML, see docs/scenes.md) or an example scene (--list) to an image; "
    "-D KEY=VALUE changes a value of the scene first."
)


def _finite(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number; got {_short(text)}") from None
    if v != v or v in (float("inf"), float("-inf")):
        raise argparse.ArgumentTypeError(f"expected a finite number; got {_short(text)}")
    return v


def _exposure(text: str) -> float:
    v = _finite(text)
    if not -100 <= v <= 100:  # 2**±100 already saturates or blackens every pixel; 2**1e308 overflows
        raise argparse.ArgumentTypeError(f"must be a number of stops in [-100, 100]; got {_short(text)}")
    return v


def add_parser(subparsers):
    """Add ``render`` and its options to the sub-commands of ``lighting-explorer``.

    Parameters
    ----------
    subparsers : explorer.cli.SubCommands
        The sub-parsers of the ``lighting-explorer`` command.

    Returns
    -------
    argparse.ArgumentParser
        The new sub-parser (its ``func`` default is :func:`run`).
    """
    from ..cli import size_type

    p = subparsers.add_parser(
        "render",
        help="a scene file or an example scene to an image",
        description=DESCRIPTION,
    )
    p.add_argument("scene", nargs="?", metavar="SCENE", help="scene file, or the name of an example scene (--list)")
    p.add_argument(
        "-o",
        "--out",
        help="output image: .png; .jpg .tif .webp (with Pillow); the linear image as "
        ".npy .pfm (.exr with OpenEXR) (default: the scene's [image].output, else SCENE-NAME.png)",
    )
    p.add_argument(
        "--size",
        type=size_type("--size"),
        metavar="WxH",
        help="image size in pixels, WIDTHxHEIGHT or N for a square (default: the scene's [image] size)",
    )
    p.add_argument(
        "-D",
        dest="defines",
        action="append",
        metavar="KEY=VALUE",
        default=[],
        help="override a value of the scene: a dotted key into its TOML and a TOML value, e.g. "
        "-D image.width=320, -D lights[0].intensity=2, -D materials.red.parts[0].kd=[0.9,0.1,0.1] "
        "(repeat for more)",
    )
    p.add_argument(
        "--exposure",
        type=_exposure,
        metavar="STOPS",
        help="exposure in stops, -100 to 100 (default: the scene's [image].exposure)",
    )
    p.add_argument("--tonemap", choices=("clamp", "reinhard"), help="tone map (default: the scene's [image].tonemap)")
    p.add_argument(
        "--explain",
        action="store_true",
        help="print the evaluation plan (what the scene needs) and stop; with -o, also render and write",
    )
    p.add_argument("--allow-slow", action="store_true",
                   help="render even when its estimated time is over the time budget (--explain prints the estimate)")
    p.add_argument("--list", action="store_true", help="list the example scenes with their descriptions")
    p.set_defaults(func=run)
    return p


def _short(text) -> str:
    from lighting._text import abbreviate

    return abbreviate(repr(text))


def examples() -> list[tuple[str, str]]:
    """The example scenes shipped with the package and the one-line ``description`` each file gives.

    Returns
    -------
    list of (str, str)
        ``(name, description)``, sorted by name (the description is empty if the file gives none).
    """
    import tomllib

    from lighting.scene import example_path, list_examples

    out = []
    for name in list_examples():
        with open(example_path(name), "rb") as f:
            description = tomllib.load(f).get("description", "")
        out.append((name, " ".join(str(description).split())))
    return out


def load_with_defines(path: str, defines=()):
    """Load a scene file, with ``-D KEY=VALUE`` overrides applied to its TOML before the checks.

    Parameters
    ----------
    path : str
        The scene file.
    defines : sequence of str
        ``KEY=VALUE`` overrides (:mod:`explorer.commands.defines`).

    Returns
    -------
    lighting.scene.Scene
        The scene, every value (given or overridden) checked as the loader checks a file.

    Raises
    ------
    ValueError
        The file's own problem as the loader reports it; a malformed ``-D``; or a value the overrides made
        wrong, reported by the loader with the scene named as given (a shipped example by its name) and
        followed by the ``-D`` that set the key at fault, else every ``-D`` given
        (``spotlight: image.width: … (with -D image.width=0)``).
    """
    import tomllib

    from lighting.scene import SceneError, load_scene, parse_scene, scene_label

    from .defines import apply_defines, key_label, parse_define

    parsed = [parse_define(d) for d in defines]  # a malformed -D is refused before the file is read
    scene = load_scene(path)  # the file as written: its own errors are named as its own
    if not parsed:
        return scene
    with open(path, "rb") as f:  # read and checked just above
        data = tomllib.load(f)
    apply_defines(data, parsed)
    try:
        return parse_scene(data, source=scene_label(path), base_dir=os.path.dirname(os.path.abspath(path)))
    except ValueError as exc:
        from lighting._text import abbreviate

        key = exc.key if isinstance(exc, SceneError) else ""
        # The -D that set the key at fault (or a table above it, or a value below it); the last one wins.
        at_fault = [d for d in parsed if _overlaps(key_label(d.path), key)][-1:] or parsed
        given = " ".join(f"-D {abbreviate(d.text)}" for d in at_fault)
        raise ValueError(f"{exc} (with {given})") from None


def _overlaps(a: str, b: str) -> bool:
    """Whether key paths ``a`` and ``b`` are the same or one holds the other (``lights[0]``, ``lights[0].x``)."""
    if not a or not b:
        return False
    short, long = sorted((a, b), key=len)
    return long == short or long.startswith(short + ".") or long.startswith(short + "[")


def _check_size(size) -> None:
    """Refuse a ``--size`` before the scene is read: a side longer than a scene's image may have (which no
    budget lifts, so it is named first), or an image of one object over the memory budget."""
    from lighting._budget import check_budget
    from lighting.scene import MAX_SCENE_IMAGE_SIDE
    from lighting.scene.budget import BYTES_PER_PIXEL, BYTES_PER_PIXEL_PER_OBJECT

    width, height = size
    if max(width, height) > MAX_SCENE_IMAGE_SIDE:
        side = MAX_SCENE_IMAGE_SIDE
        raise ValueError(f"--size must be at most {side}x{side} pixels (a scene's largest image); got {width}x{height}")
    check_budget(f"--size {width}x{height}: the image", (BYTES_PER_PIXEL + BYTES_PER_PIXEL_PER_OBJECT) * width * height,
                 what=f"{width}x{height} pixels of one object; more with more objects")  # fmt: skip


def _run(args) -> int:
    from lighting._text import plural
    from lighting.scene import SceneRenderer, check_scene_budget, scene_output_path

    from ..cli import UsageError, resolve_scene
    from ..output import check_output_path, write_image

    if args.list:
        rows = examples()
        width = max(len(name) for name, _ in rows)
        for name, description in rows:
            print(f"{name:{width}s}  {description}".rstrip())
        return 0
    if not args.scene:
        raise UsageError("the following arguments are required: SCENE (a scene file or an example name; see --list) "
                         f"(see {PROG} --help)")  # fmt: skip
    path = resolve_scene(args.scene, flag="SCENE")
    if args.size:
        _check_size(args.size)
    t0 = time.perf_counter()
    scene = load_with_defines(path, args.defines)
    if args.size:
        scene = scene.with_size(*args.size)
    if args.allow_slow:
        from dataclasses import replace

        scene = replace(scene, allow_slow=True)
    check_scene_budget(scene, size_flag=f"--size {args.size[0]}x{args.size[1]}" if args.size else None)
    write = not args.explain or args.out is not None
    if write:
        flag = "-o" if args.out is not None else "[image].output"
        if args.out is not None:  # the user's own choice: anywhere (an empty -o is refused below, not replaced)
            out = shown = args.out
        elif scene.image.output is not None:  # the scene file's: only inside its folder or the current one
            shown = scene.image.output
            out = scene_output_path(shown, path)
        else:
            out = shown = os.path.splitext(os.path.basename(path))[0] + ".png"
        check_output_path(out, flag=flag)  # format, folder and permissions before any rendering
    renderer = SceneRenderer(scene)
    if args.explain:
        print(renderer.explain())
        if not write:  # the plan only: nothing rendered, nothing written
            return 0
    image, info = renderer.render()
    rgb8, report = renderer.encode(image, exposure=args.exposure, tonemap=args.tonemap)
    write_image(out, rgb8=rgb8, linear=image, flag=flag)
    seconds = time.perf_counter() - t0
    print(
        f"wrote {shown} ({info['width']}x{info['height']}, {plural(info['objects'], 'object')}, "
        f"{plural(info['lights'], 'light')}, {seconds:.2f} s); {report}"
    )
    return 0


def run(args) -> int:
    """Render the scene the options name and write the image; report any problem in one line.

    Parameters
    ----------
    args : argparse.Namespace
        The options of :func:`add_parser`.

    Returns
    -------
    int
        0 on success, 2 on any error (``lighting-explorer: error: …`` on standard error).
    """
    from ..cli import print_error

    try:
        return _run(args)
    except (ValueError, OSError) as exc:
        return print_error(exc)
    except MemoryError:
        return print_error("out of memory (try a smaller --size)")


def main(argv=None) -> int:
    """``lighting-explorer render`` run alone (see :func:`explorer.cli.run_alone`).

    Parameters
    ----------
    argv : list of str, optional
        The scene and the options (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status: 0 on success, 2 on any error.
    """
    from ..cli import run_alone

    return run_alone("render", argv)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
