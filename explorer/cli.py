"""The ``lighting-explorer`` command."""

from __future__ import annotations

import argparse
import sys

from lighting import AmbientLight, BlinnPhong, DirectionalLight, Lambert, Material
from lighting.analytic import render_sphere
from lighting.image import encode_srgb8, write_png


def _cmd_sphere(args) -> int:
    material = Material(Lambert(args.kd) + BlinnPhong(args.ks, args.shininess), ambient=args.kd)
    lights = [
        AmbientLight(intensity=args.ambient),
        DirectionalLight.from_angles(args.elevation, args.azimuth),
    ]
    img = render_sphere(material, lights, size=args.size)
    rgb8, report = encode_srgb8(img, exposure=args.exposure, tonemap=args.tonemap)
    write_png(args.out, rgb8)
    print(f"wrote {args.out} ({args.size}x{args.size}); {report}")
    return 0


def _rgb(text: str):
    parts = [float(x) for x in text.split(",")]
    if len(parts) not in (1, 3):
        raise argparse.ArgumentTypeError(f"expected one number or three comma-separated numbers; got {text!r}")
    return parts[0] if len(parts) == 1 else tuple(parts)


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="lighting-explorer",
        description="Explore local illumination models. With no sub-command, opens the explorer window.",
    )
    sub = p.add_subparsers(dest="command", required=True)
    s = sub.add_parser("sphere", help="render one lit sphere with the engine and save it as PNG")
    s.add_argument("-o", "--out", default="sphere.png", help="output PNG path (default: sphere.png)")
    s.add_argument("--size", type=int, default=384, help="image width and height in pixels")
    s.add_argument("--kd", type=_rgb, default=(0.8, 0.25, 0.2), help="diffuse colour, e.g. 0.8,0.25,0.2")
    s.add_argument("--ks", type=_rgb, default=0.5, help="specular coefficient")
    s.add_argument("--shininess", type=float, default=40.0, help="Blinn-Phong exponent")
    s.add_argument("--ambient", type=float, default=0.1, help="ambient intensity I_a")
    s.add_argument("--elevation", type=float, default=45.0, help="light elevation in degrees")
    s.add_argument("--azimuth", type=float, default=135.0, help="light azimuth in degrees")
    s.add_argument("--exposure", type=float, default=0.0, help="exposure in stops")
    s.add_argument("--tonemap", choices=("clamp", "reinhard"), default="clamp")
    s.set_defaults(func=_cmd_sphere)

    sub.add_parser("bench", help="time re-shading, rasterizing and VTK rendering side by side (--json, --plan)")
    sub.add_parser("render", help="render a scene file (or an example scene) to PNG (--explain shows the plan)")
    sub.add_parser("report", help="accuracy reports: 'report accuracy' (error vs run time), 'report stability'")
    sub.add_parser("explore", help="the interactive explorer window (the default with no sub-command)")
    sub.add_parser("figures", help="write the lecture-note figure set (--out DIR, --format, --only, --dpi, --quick)")
    return p


# Sub-commands with options of their own: the rest of the command line goes to the module's main().
DELEGATES = {
    "bench": "explorer.bench",
    "render": "explorer.render_cmd",
    "report": "explorer.report",
    "explore": "explorer.app",
    "figures": "explorer.figures",
}


def main(argv=None) -> int:
    from ._allocator import tune_allocator

    tune_allocator()  # see explorer/_allocator.py: the image pipeline's temporaries stop page-faulting
    argv = list(sys.argv[1:] if argv is None else argv)
    if not argv or (argv[0].startswith("--") and argv[0] != "--help"):
        # No sub-command: open the explorer window (its own options, e.g. --off-screen --screenshot x.png).
        argv = ["explore", *argv]
    if argv and argv[0] in DELEGATES:
        import importlib

        return importlib.import_module(DELEGATES[argv[0]]).main(argv[1:])
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except ValueError as exc:
        print(f"lighting-explorer: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
