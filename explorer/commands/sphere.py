"""``lighting-explorer sphere``: render one lit sphere with the engine and save it.

::

    lighting-explorer sphere [-o OUT] [--size WxH|N] [--kd R,G,B] [--ks KS] [--shininess E] [--ambient I_A]
                             [--elevation DEG] [--azimuth DEG] [--exposure STOPS] [--tonemap clamp|reinhard]

The material is Lambert plus Blinn–Phong (ambient colour = ``--kd``), lit by an ambient light and one
directional light; every value is checked, in the words of its flag, before anything is allocated.
"""

from __future__ import annotations

import sys

from lighting._budget import check_budget
from lighting._text import quote
from lighting._validate import ArgumentTypeError, check_color, check_nonnegative, check_range

__all__ = ["SPHERE_BYTES_PER_PIXEL", "add_parser", "run", "main"]

#: Bytes per pixel that ``sphere`` is budgeted (ray casting, shading in float64, encoding; its peak stays below
#: this): the engine's own estimate for rendering (``lighting.render.renderer``), so that the flag is named
#: before the engine refuses.
SPHERE_BYTES_PER_PIXEL = 320


def _rgb(flag: str, text: str):
    """``--kd 0.8,0.25,0.2`` or ``--ks 0.5``: one number or three, finite and >= 0."""
    allowed = "one number or three comma-separated numbers, each finite and >= 0"
    try:
        parts = [float(x) for x in str(text).split(",")]
    except ValueError:
        raise ArgumentTypeError(f"{flag} must be {allowed}; got {quote(text)}") from None
    if len(parts) not in (1, 3):
        raise ValueError(f"{flag} must be {allowed}; got {quote(text)}")
    value = check_color(flag, parts[0] if len(parts) == 1 else parts)
    return float(value[0]) if len(parts) == 1 else tuple(float(x) for x in value)


def add_parser(subparsers):
    """Add ``sphere`` and its options to the sub-commands of ``lighting-explorer``.

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

    s = subparsers.add_parser(
        "sphere",
        help="one lit sphere rendered by the engine, to an image",
        description="Render the exact (ray-cast) unit sphere with Lambert(kd) + BlinnPhong(ks, shininess) under "
        "ambient light and one directional light, and write it. Every value is checked before rendering.",
    )
    s.add_argument(
        "-o",
        "--out",
        default="sphere.png",
        help="output image: .png; .jpg .tif .webp (with Pillow); the linear image as .npy .pfm (.exr with OpenEXR)",
    )
    s.add_argument(
        "--size",
        type=size_type("--size", example="384 or 640x480"),
        default=(384, 384),
        metavar="WxH",
        help="image size in pixels, WIDTHxHEIGHT or N for a square; the sphere fills the shorter side",
    )
    s.add_argument(
        "--kd", default="0.8,0.25,0.2", metavar="R,G,B", help="diffuse colour: one number or r,g,b, each >= 0"
    )
    s.add_argument("--ks", default="0.5", metavar="KS", help="specular coefficient: one number or r,g,b, each >= 0")
    s.add_argument("--shininess", type=float, default=40.0, metavar="E", help="Blinn-Phong exponent, >= 0")
    s.add_argument("--ambient", type=float, default=0.1, metavar="I_A", help="ambient intensity I_a, >= 0")
    s.add_argument("--elevation", type=float, default=45.0, metavar="DEG", help="light elevation in degrees, -90 to 90")
    s.add_argument(
        "--azimuth",
        type=float,
        default=135.0,
        metavar="DEG",
        help="light azimuth in degrees, in the image plane from +x toward +y",
    )
    s.add_argument(
        "--exposure", type=float, default=0.0, metavar="STOPS", help="exposure in stops, -100 to 100 (8-bit formats)"
    )
    s.add_argument("--tonemap", choices=("clamp", "reinhard"), default="clamp", help="tone map (8-bit formats)")
    s.set_defaults(func=run)
    return s


def run(args) -> int:
    """Render the sphere the options describe and write it.

    Parameters
    ----------
    args : argparse.Namespace
        The options of :func:`add_parser`.

    Returns
    -------
    int
        0 when the image is written.

    Raises
    ------
    ValueError
        A bad value, named by its flag (the command prints it as one line and exits with 2).
    """
    import numpy as np

    from lighting import AmbientLight, BlinnPhong, DirectionalLight, Lambert, Material
    from lighting.render.camera import MAX_IMAGE_SIDE
    from lighting.render.image import MAX_EXPOSURE, encode_srgb8
    from lighting.render.sphere import render_sphere

    from ..output import check_output_path, write_image

    # Every value is checked, in the words of its flag, before anything is allocated or rendered.
    check_output_path(args.out, flag="-o")
    width, height = args.size
    shown = f"{width}x{height}" if width != height else str(width)
    if max(width, height) > MAX_IMAGE_SIDE:  # no budget lifts this one: named first
        raise ValueError(f"--size must be at most {MAX_IMAGE_SIDE}x{MAX_IMAGE_SIDE} pixels; got {width}x{height}")
    check_budget(f"--size {shown}", SPHERE_BYTES_PER_PIXEL * width * height, what=f"a {width}x{height} sphere image")
    kd = _rgb("--kd", args.kd)
    ks = _rgb("--ks", args.ks)
    shininess = check_nonnegative("--shininess", args.shininess)
    ambient = check_nonnegative("--ambient", args.ambient)
    elevation = check_range("--elevation", args.elevation, -90.0, 90.0)
    azimuth = check_range("--azimuth", args.azimuth)
    exposure = check_range("--exposure", args.exposure, -MAX_EXPOSURE, MAX_EXPOSURE)

    material = Material(Lambert(kd) + BlinnPhong(ks, shininess), ambient=kd)
    lights = [AmbientLight(intensity=ambient), DirectionalLight.from_angles(elevation, azimuth)]
    side = min(width, height)
    img = render_sphere(material, lights, size=side)
    if (width, height) != (side, side):  # centred on the background (0) of the wider or taller image
        framed = np.zeros((height, width, img.shape[2]), dtype=img.dtype)
        top, left = (height - side) // 2, (width - side) // 2
        framed[top : top + side, left : left + side] = img
        img = framed
    rgb8, report = encode_srgb8(img, exposure=exposure, tonemap=args.tonemap)
    fmt = write_image(args.out, rgb8=rgb8, linear=img, flag="-o")
    kind = f"linear {img.dtype}" if fmt in ("npy", "pfm", "exr") else fmt.upper()
    print(f"wrote {args.out} ({width}x{height}, {kind}); {report}")
    return 0


def main(argv=None) -> int:
    """``lighting-explorer sphere`` run alone (see :func:`explorer.cli.run_alone`).

    Parameters
    ----------
    argv : list of str, optional
        The options (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status: 0 done, 2 a bad request (one line on standard error).
    """
    from ..cli import run_alone

    return run_alone("sphere", argv)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
