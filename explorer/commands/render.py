"""``lighting-explorer render``: render a scene file to a PNG, headless.

    lighting-explorer render scene.toml -o out.png [--size WxH] [--exposure STOPS]
                             [--tonemap clamp|reinhard] [--explain]
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
import re
import sys
import time

__all__ = ["add_parser", "run", "main"]

PROG = "lighting-explorer render"
DESCRIPTION = "Render a scene file (TOML, see docs/scenes.md) to a PNG image."


class _UsageError(Exception):
    pass


def _size(text: str):
    m = re.fullmatch(r"\s*(\d+)\s*[xX×]\s*(\d+)\s*", text)
    if not m or int(m.group(1)) < 1 or int(m.group(2)) < 1:
        raise argparse.ArgumentTypeError(
            f"--size must be WIDTHxHEIGHT in pixels, both >= 1 (e.g. 640x480); got {_short(text)}"
        )
    return int(m.group(1)), int(m.group(2))


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
    subparsers : argparse._SubParsersAction
        The sub-parsers of the ``lighting-explorer`` command.

    Returns
    -------
    argparse.ArgumentParser
        The new sub-parser (its ``func`` default is :func:`run`).
    """
    p = subparsers.add_parser(
        "render", help="render a scene file (or an example scene) to an image (--explain shows the plan)",
        description=DESCRIPTION,
    )  # fmt: skip
    p.add_argument("scene", nargs="?", help="scene file, or the name of a shipped example scene")
    p.add_argument("-o", "--out", help="output PNG (default: [image].output of the scene, else SCENE-NAME.png)")
    p.add_argument("--size", type=_size, metavar="WxH", help="image size override, e.g. 640x480")
    p.add_argument("--exposure", type=_exposure, help="exposure override in stops")
    p.add_argument("--tonemap", choices=("clamp", "reinhard"), help="tone map override")
    p.add_argument("--explain", action="store_true", help="print the evaluation plan (what the scene needs)")
    p.add_argument("--list", action="store_true", help="list the example scenes shipped with the package")
    p.set_defaults(func=run)
    return p


def _resolve_scene(arg: str) -> str:
    from lighting.scene import example_path, list_examples

    if os.path.exists(arg) or os.sep in arg or "/" in arg:
        return arg
    stem = arg[:-5] if arg.endswith(".toml") else arg
    if stem in list_examples():
        return example_path(stem)
    return arg  # load_scene reports the missing file


def _short(text) -> str:
    from lighting._numeric import abbreviate

    return abbreviate(repr(text))


def _run(args) -> int:
    from lighting.scene import SceneRenderer, check_scene_budget, list_examples, load_scene, scene_output_path

    from ..output import check_output_path, write_image

    if args.list:
        for name in list_examples():
            print(name)
        return 0
    if not args.scene:
        raise _UsageError("the following arguments are required: scene (a scene file or an example name)")
    path = _resolve_scene(args.scene)
    t0 = time.perf_counter()
    scene = load_scene(path)
    if args.size:
        scene = scene.with_size(*args.size)
    check_scene_budget(scene, size_flag=f"--size {args.size[0]}x{args.size[1]}" if args.size else None)
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
    image, info = renderer.render()
    if args.explain:
        print(renderer.explain())
    rgb8, report = renderer.encode(image, exposure=args.exposure, tonemap=args.tonemap)
    write_image(out, rgb8=rgb8, linear=image, flag=flag)
    seconds = time.perf_counter() - t0
    print(
        f"wrote {shown} ({info['width']}x{info['height']}, {info['objects']} objects, {info['lights']} lights, "
        f"{seconds:.2f} s); {report}"
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
    try:
        return _run(args)
    except _UsageError as e:
        print(f"lighting-explorer: error: {e} (see {PROG} --help)", file=sys.stderr)
        return 2
    except (ValueError, OSError) as e:
        msg = str(e) if not isinstance(e, OSError) or not e.strerror else f"{e.strerror}: {e.filename}"
        print(f"lighting-explorer: error: {msg}", file=sys.stderr)
        return 2
    except MemoryError:
        print("lighting-explorer: error: out of memory (try a smaller --size)", file=sys.stderr)
        return 2


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
