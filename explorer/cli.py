"""The ``lighting-explorer`` command.

Every sub-command answers a bad request with one line on standard error,
``lighting-explorer…: error: <what, the value given, what is allowed>``, and exit status 2;
Ctrl-C exits with 130 and ``SIGTERM`` with 143, leaving no temporary file behind (see
:mod:`explorer.output`).  ``--memory-budget SIZE`` (anywhere on the line) sets the budget that
image sizes, sample counts, worker counts and scene files are checked against before anything
is allocated (:func:`lighting._numeric.set_memory_budget`; 2 GiB by default).
"""

from __future__ import annotations

import argparse
import re
import sys

from lighting._numeric import (
    ArgumentTypeError,
    _fmt,
    check_budget,
    check_color,
    check_count,
    check_nonnegative,
    check_range,
    memory_budget,
    set_memory_budget,
)

PROG = "lighting-explorer"

#: Peak bytes per pixel of ``sphere`` (ray casting, shading in float64, encoding): measured 242; this is the
#: engine's own estimate for rendering (``lighting.render.renderer``), so that the flag is named before the
#: engine refuses.
SPHERE_BYTES_PER_PIXEL = 320

#: The smallest ``--memory-budget`` accepted.
MIN_MEMORY_BUDGET = 1024**2


class UsageError(ValueError):
    """A malformed command line (unknown option, missing value): one line, exit status 2."""


class OneLineParser(argparse.ArgumentParser):
    """An ``ArgumentParser`` whose errors are a :class:`UsageError` instead of usage text and ``exit(2)``.

    The caller prints the one line (``lighting-explorer: error: argument --size: invalid int value: 'x'``).
    """

    def error(self, message):
        from lighting._numeric import abbreviate

        # argparse quotes the whole value it refused: a 100,000-character one is cut short.
        message = re.sub(r"'[^']{81,}'", lambda m: abbreviate(m.group(0)), message)
        raise UsageError(f"{message} (see {self.prog} --help)")


def error_line(exc: BaseException) -> str:
    """The one line that reports ``exc`` to the user (no traceback, no temporary file names)."""
    if isinstance(exc, OSError) and exc.strerror:
        name = exc.filename if exc.filename is not None else ""
        text = f"{exc.strerror}: {name}" if name != "" else exc.strerror
    elif isinstance(exc, MemoryError):
        text = "out of memory (reduce the size or the sample count)"
    elif isinstance(exc, RecursionError):
        text = "input nested too deeply"
    else:
        text = str(exc) or type(exc).__name__
    return " ".join(text.split())


# --------------------------------------------------------------------------- sphere
def _rgb(flag: str, text: str):
    """``--kd 0.8,0.25,0.2`` or ``--ks 0.5``: one number or three, finite and >= 0."""
    allowed = "one number or three comma-separated numbers, each finite and >= 0"
    try:
        parts = [float(x) for x in str(text).split(",")]
    except ValueError:
        raise ArgumentTypeError(f"{flag} must be {allowed}; got {_fmt(text)}") from None
    if len(parts) not in (1, 3):
        raise ValueError(f"{flag} must be {allowed}; got {_fmt(text)}")
    value = check_color(flag, parts[0] if len(parts) == 1 else parts)
    return float(value[0]) if len(parts) == 1 else tuple(float(x) for x in value)


def _cmd_sphere(args) -> int:
    from lighting import AmbientLight, BlinnPhong, DirectionalLight, Lambert, Material
    from lighting.render.image import MAX_EXPOSURE, encode_srgb8
    from lighting.render.sphere import render_sphere

    from .output import check_output_path, write_image

    # Every value is checked, in the words of its flag, before anything is allocated or rendered.
    check_output_path(args.out, flag="-o")
    size = check_count("--size", args.size, 1)
    check_budget(f"--size {size}", SPHERE_BYTES_PER_PIXEL * size * size, what=f"a {size}x{size} sphere image")
    kd = _rgb("--kd", args.kd)
    ks = _rgb("--ks", args.ks)
    shininess = check_nonnegative("--shininess", args.shininess)
    ambient = check_nonnegative("--ambient", args.ambient)
    elevation = check_range("--elevation", args.elevation, -90.0, 90.0)
    azimuth = check_range("--azimuth", args.azimuth)
    exposure = check_range("--exposure", args.exposure, -MAX_EXPOSURE, MAX_EXPOSURE)

    material = Material(Lambert(kd) + BlinnPhong(ks, shininess), ambient=kd)
    lights = [AmbientLight(intensity=ambient), DirectionalLight.from_angles(elevation, azimuth)]
    img = render_sphere(material, lights, size=size)
    rgb8, report = encode_srgb8(img, exposure=exposure, tonemap=args.tonemap)
    fmt = write_image(args.out, rgb8=rgb8, linear=img, flag="-o")
    kind = f"linear {img.dtype}" if fmt in ("npy", "pfm", "exr") else fmt.upper()
    print(f"wrote {args.out} ({size}x{size}, {kind}); {report}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    p = OneLineParser(
        prog=PROG,
        description="Explore local illumination models. With no sub-command, opens the explorer window. "
        "--memory-budget SIZE (e.g. 4G, 512M; default 2G) raises or lowers the memory any one request may use.",
    )
    sub = p.add_subparsers(dest="command", required=True, parser_class=OneLineParser)
    s = sub.add_parser("sphere", help="render one lit sphere with the engine and save it (PNG and other formats)")
    s.add_argument("-o", "--out", default="sphere.png",
                   help="output image: .png; .jpg .tif .webp (with Pillow); the linear image as .npy .pfm "
                        "(.exr with OpenEXR) (default: sphere.png)")  # fmt: skip
    s.add_argument("--size", type=int, default=384, help="image width and height in pixels")
    s.add_argument("--kd", default="0.8,0.25,0.2", help="diffuse colour, e.g. 0.8,0.25,0.2")
    s.add_argument("--ks", default="0.5", help="specular coefficient (one number or r,g,b)")
    s.add_argument("--shininess", type=float, default=40.0, help="Blinn-Phong exponent")
    s.add_argument("--ambient", type=float, default=0.1, help="ambient intensity I_a")
    s.add_argument("--elevation", type=float, default=45.0, help="light elevation in degrees, -90 to 90")
    s.add_argument("--azimuth", type=float, default=135.0, help="light azimuth in degrees")
    s.add_argument("--exposure", type=float, default=0.0, help="exposure in stops, -100 to 100 (8-bit formats)")
    s.add_argument("--tonemap", choices=("clamp", "reinhard"), default="clamp", help="tone map (8-bit formats)")
    s.set_defaults(func=_cmd_sphere)

    sub.add_parser("bench", help="time re-shading, rasterizing and VTK rendering side by side (--json, --plan)")
    sub.add_parser("render", help="render a scene file (or an example scene) to an image (--explain shows the plan)")
    sub.add_parser("report", help="accuracy reports: 'report accuracy' (error vs run time), 'report stability'")
    sub.add_parser("explore", help="the interactive explorer window (the default with no sub-command)")
    sub.add_parser("figures", help="write the lecture-note figure set (--out DIR, --format, --only, --dpi, --quick)")
    return p


# Sub-commands with options of their own: the rest of the command line goes to the module's main().
DELEGATES = {
    "bench": "explorer.bench",
    "render": "explorer.render_cmd",
    "report": "explorer.reports",
    "explore": "explorer.app",
    "figures": "explorer.figures",
}

_UNITS = {"": 1, "k": 1024, "m": 1024**2, "g": 1024**3, "t": 1024**4}


def parse_size(text: str, flag: str = "--memory-budget") -> int:
    """``"2G"``, ``"512M"``, ``"1.5g"``, ``"4GiB"``, ``"1000000"`` → bytes (binary units).

    >>> parse_size("512M"), parse_size("1.5G")
    (536870912, 1610612736)
    """
    allowed = "a size such as 2G, 512M or 1.5G (K, M, G, T are powers of 1024; at least 1M)"
    m = re.fullmatch(r"\s*(\d+(?:\.\d*)?|\.\d+)\s*([kmgt]?)(?:i?b)?\s*", str(text), flags=re.IGNORECASE)
    if not m:
        raise UsageError(f"{flag} must be {allowed}; got {_fmt(text)}")
    value = float(m.group(1)) * _UNITS[m.group(2).lower()]
    if not MIN_MEMORY_BUDGET <= value < 2.0**62:
        raise UsageError(f"{flag} must be {allowed}; got {_fmt(text)}")
    return int(value)


def _take_memory_budget(argv: list[str]):
    """Remove every ``--memory-budget SIZE`` / ``--memory-budget=SIZE`` from ``argv``; the last one wins."""
    rest, budget, i = [], None, 0
    while i < len(argv):
        a = argv[i]
        if a == "--memory-budget":
            if i + 1 >= len(argv):
                raise UsageError("argument --memory-budget: expected one argument, a size such as 2G")
            budget = parse_size(argv[i + 1])
            i += 2
            continue
        if a.startswith("--memory-budget="):
            budget = parse_size(a.split("=", 1)[1])
        else:
            rest.append(a)
        i += 1
    return rest, budget


def _dispatch(argv: list[str]) -> int:
    if not argv or (argv[0].startswith("--") and argv[0] != "--help"):
        # No sub-command: open the explorer window (its own options, e.g. --off-screen --screenshot x.png).
        argv = ["explore", *argv]
    if argv[0] in DELEGATES:
        import importlib

        return importlib.import_module(DELEGATES[argv[0]]).main(argv[1:])
    args = build_parser().parse_args(argv)
    return args.func(args)


def main(argv=None) -> int:
    """Run ``lighting-explorer``; returns the exit status (0 done, 1 a check failed, 2 a bad request,
    130 interrupted by Ctrl-C, 143 by ``SIGTERM``)."""
    from ._allocator import tune_allocator
    from .output import Terminated, raise_if_signalled, signals_as_exceptions

    tune_allocator()  # see explorer/_allocator.py: the image pipeline's temporaries stop page-faulting
    argv = list(sys.argv[1:] if argv is None else argv)
    previous = memory_budget()
    with signals_as_exceptions():
        try:
            argv, budget = _take_memory_budget(argv)
            if budget is not None:
                set_memory_budget(budget)
            status = _dispatch(argv)
            raise_if_signalled()  # a stop signal whose exception a library swallowed still ends as one
            return status
        except SystemExit as exc:  # --help, or a sub-command's own argparse
            return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 2)
        except KeyboardInterrupt:
            print(f"{PROG}: interrupted", file=sys.stderr)
            return 130
        except Terminated:
            print(f"{PROG}: terminated", file=sys.stderr)
            return 143
        except (ValueError, OSError, MemoryError, RecursionError) as exc:
            print(f"{PROG}: error: {error_line(exc)}", file=sys.stderr)
            return 2
        finally:
            set_memory_budget(previous)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
