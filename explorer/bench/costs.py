"""Measure the costs behind the render time budget: ``python -m explorer.bench.costs``.

Renders small scenes built to isolate one stage each (an image of one sphere under ambient light, the same
sphere under four point lights with one model, under a Monte-Carlo sky, under the split sum and the dominant
lights, a measured BRDF's sampler tables, prefiltering a sky) and prints the seconds per unit of work of each
stage, as the table :data:`lighting._budget.SECONDS_PER` keeps them.  Each stage runs ``--repeat`` times and the
fastest run counts (the others wait on the rest of the machine).  The shading stages time a second render of
the same :class:`~lighting.scene.SceneRenderer`, so rasterizing and prefiltering are left out of them.

``--check`` instead renders five small scenes (point lights, a Monte-Carlo sky, measured data under a sky, the
split sum, the dominant lights with two narrow lobes) and prints each one's estimated time against its measured
time, with the target: within a factor of four either way.
"""

from __future__ import annotations

import argparse
import functools
import json
import math
import os
import sys
import tempfile
import time

__all__ = ["measure", "estimate_against_clock", "main"]

_CAMERA = """
[camera]
eye = [0.0, -3.2, 0.0]
target = [0.0, 0.0, 0.0]
up = [0.0, 0.0, 1.0]
fov_y_deg = 40.0
[image]
width = {size}
height = {size}
[render]
form = "physical"
"""
_SPHERE = '[[objects]]\ntype = "sphere"\nmaterial = {{parts = [{parts}]}}\n'
_POINTS = "".join(f'[[lights]]\ntype = "point"\nposition = [{x}, -3.0, {z}]\nintensity = 3.0\n'
                  for x, z in ((2, 2), (-2, 2), (2, -2), (-2, -2)))  # fmt: skip
_SKY = '[[lights]]\ntype = "environment"\nsource = {source}\nbackground = false\nmethod = "{method}"\n'


def _sky(method: str, source: str = "daylight") -> str:
    """A scene file's environment light: ``source`` (a sky's name or an image file) under ``method``."""
    return _SKY.format(method=method, source=json.dumps(source))


def _scene(size: int, parts: str, lights: str = "") -> str:
    """A scene file's text: one sphere of the given parts, seen at ``size`` x ``size``, under ``lights``."""
    return _CAMERA.format(size=size) + _SPHERE.format(parts=parts) + lights


def _part(kind: str, files: dict) -> str:
    if kind in files:
        return f'{{file = "{files[kind]}"}}'
    return f'{{model = "{kind}"}}'


def _best(fn, repeat: int) -> float:
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def _second_render(text: str, base_dir: str, repeat: int) -> tuple[float, int]:
    """Fastest second render of a scene (geometry buffers and prefiltered skies made) and its covered pixels."""
    from lighting.scene import SceneRenderer, parse_scene

    sr = SceneRenderer(parse_scene(text, base_dir=base_dir, allow_slow=True))
    _, info = sr.render()
    return _best(sr.render, repeat), info["covered_pixels"]


def _files(folder: str) -> dict:
    """A measured (MERL) file and a ``.brdf`` shader file in ``folder``: the two kinds of BRDF files."""
    import numpy as np

    from lighting.files.merl import write_merl

    merl = os.path.join(folder, "measured.binary")
    write_merl(merl, np.full((3, 90, 90, 180), 0.25))
    shader = os.path.join(folder, "shader.brdf")
    with open(shader, "w") as f:
        f.write("::begin parameters\nfloat albedo 0 1 0.5\n::end parameters\n::begin shader\n"
                "vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { float c = dot(normalize(L + V), N); "
                "return vec3(albedo / 3.14159265358979 + pow(max(c, 0.0), 20.0)); }\n::end shader\n")  # fmt: skip
    return {"measured": "measured.binary", "shader": "shader.brdf"}


def measure(repeat: int = 3) -> dict:
    """Seconds per unit of work of every stage the time budget counts (see the module docstring).

    Parameters
    ----------
    repeat : int
        Runs per stage; the fastest counts.

    Returns
    -------
    dict
        ``{stage: seconds}`` with the keys of :data:`lighting._budget.SECONDS_PER`.
    """
    from lighting import _budget
    from lighting.files.merl import read_merl
    from lighting.integrate.dominant import forget_environments
    from lighting.integrate.prefilter import prefilter_environment, prefilter_height
    from lighting.models.protocol import model_names
    from lighting.sampling.merl import MerlSampler
    from lighting.scene import SceneRenderer, example_path, parse_scene

    out = {}
    with tempfile.TemporaryDirectory() as folder:
        files = _files(folder)
        kinds = [k for k in model_names() if k in _budget.MODEL_KINDS] + ["measured", "shader"]

        # An image: rasterizing, compositing and the ambient constant: a fixed part and one per pixel of one object.
        timed = []
        for size in (64, 384):
            text = _scene(size, _part("lambert", files))
            text += '[[lights]]\ntype = "ambient"\nintensity = 0.2\n'
            timed.append((size**2, _best(lambda text=text: SceneRenderer(parse_scene(text)).render(), repeat)))
        (n0, t0), (n1, t1) = timed
        out["pixel"] = (t1 - t0) / (n1 - n0)
        out["render"] = max(t0 - out["pixel"] * n0, 0.0)

        # One light at one shading point, per model part of each kind.
        for kind in kinds:
            size = 24 if kind == "shader" else 96
            text = _scene(size, _part(kind, files), _POINTS)
            seconds, covered = _second_render(text, folder, repeat)
            out[f"shade {kind}"] = seconds / (covered * 4)

        # One Monte-Carlo sample at one shading point, per part of each kind (sampler tables built already).  A
        # sample costs more where an object covers few pixels (each pass's fixed work is shared by fewer points),
        # and under a sky read from a file (the example's) than under a procedural one: measured under the file,
        # on a sphere of about 650 pixels, between a small object's cost and a large one's.
        sky_file = os.path.join(os.path.dirname(example_path("environment")), "daylight_sky.hdr")
        for kind in kinds:
            size, samples = (12, 4) if kind == "shader" else (32, 16)
            text = _scene(size, _part(kind, files))
            text += _sky("monte-carlo", sky_file)
            text += f"samples = {samples}\n"
            seconds, covered = _second_render(text, folder, repeat)
            out[f"monte-carlo {kind}"] = seconds / (covered * samples)

        # One view table of a measured BRDF's sampler (its half-vector bins, one lookup each).
        sampler = MerlSampler(read_merl(os.path.join(folder, files["measured"])))
        bins = iter(range(0, 90, 7))
        out["measured table"] = _best(lambda: sampler._build(next(bins)), min(repeat * 3, 12))

        # Prefiltering an environment for the split sum and the dominant lights: a fixed part and one per pixel of
        # the prefiltered image, from a sky (prefiltered at 256 rows) and the example's 128 x 64 image file.
        from lighting.scene import load_scene

        timed = []
        for light in (parse_scene(_scene(8, _part("lambert", files), _sky("split-sum"))).lights[0],
                      load_scene(example_path("environment")).lights[0]):  # fmt: skip
            h = prefilter_height(light.environment)
            fresh = functools.partial(prefilter_environment, light.environment, reuse=False)
            timed.append((2 * h * h, _best(fresh, repeat)))
        (n0, t0), (n1, t1) = sorted(timed)
        per_pixel = max((t1 - t0) / (n1 - n0), 0.0)
        out["prefilter"] = max(t0 - per_pixel * n0, 0.0)
        out["prefilter pixel"] = per_pixel

        # A shading point per part under the split sum and under the dominant lights (prefiltered already): a
        # diffuse part, a wide glossy lobe and a narrow one (the dominant lights sample it four times as much).
        parts = {"diffuse": '{model = "lambert"}',
                 "glossy": '{model = "cook-torrance", ndf = "ggx", roughness = 0.5}',
                 "narrow": '{model = "cook-torrance", ndf = "ggx", roughness = 0.1}'}  # fmt: skip
        for method in ("split-sum", "dominant"):
            for lobe, part in parts.items():
                if method == "split-sum" and lobe == "narrow":
                    continue
                text = _scene(64, part, _sky(method))
                seconds, covered = _second_render(text, folder, repeat)
                out[f"{method} {lobe}"] = seconds / covered

        # The dominant lights' first frame: finding the lights in a sky and making the residual's levels (once per
        # environment: a fixed part and one per pixel of the prefiltered image, from the sky at 256 rows and the
        # example's 64-row file), and a narrow lobe's table of half vectors (once per part), beyond prefiltering
        # and the frame itself.
        def first(part, roughness=None, source="daylight"):
            text = _scene(8, part, _sky("dominant", source))
            if roughness is not None:  # a lobe not met before: its table is not cached yet
                text = text.replace("roughness = 0.1", f"roughness = {roughness}")
            forget_environments()  # the sky made afresh, not the one the last run left
            return SceneRenderer(parse_scene(text, base_dir=folder)).render()

        def before(source):
            """A first frame's time before the dominant lights' own, and the pixels of the prefiltered image."""
            text = _scene(8, parts["diffuse"], _sky("split-sum", source))
            pixels = 2 * prefilter_height(parse_scene(text, base_dir=folder).lights[0].environment) ** 2
            return out["render"] + out["prefilter"] + pixels * out["prefilter pixel"], pixels

        bases = {source: before(source) for source in ("daylight", sky_file)}
        timed = [(pixels, max(_best(lambda s=source: first(parts["diffuse"], source=s), repeat) - base, 0.0))
                 for source, (base, pixels) in bases.items()]  # fmt: skip
        (n0, t0), (n1, t1) = sorted(timed)
        out["dominant pixel"] = max((t1 - t0) / (n1 - n0), 0.0)
        out["dominant"] = max(t0 - out["dominant pixel"] * n0, 0.0)
        base, pixels = bases["daylight"]
        rough = iter(0.1 + 0.001 * k for k in range(1, 100))
        narrow = _best(lambda: first(parts["narrow"], next(rough)), repeat)
        out["dominant narrow table"] = max(narrow - base - out["dominant"] - pixels * out["dominant pixel"], 0.0)
    return out


#: A render's estimate should be within this factor of its measured time, either way.
CHECK_FACTOR = 4.0


def estimate_against_clock(repeat: int = 2) -> list[dict]:
    """Five small renders' estimated time (:func:`lighting._budget.scene_estimate`) against their measured time.

    Each scene is made afresh for every run (rasterized, prefiltered and shaded anew), and the fastest of
    ``repeat`` runs counts.  A clock on a shared machine is no test: this is the bench's check, not the suite's.

    Parameters
    ----------
    repeat : int, optional
        Runs per scene (default 2).

    Returns
    -------
    list of dict
        ``{"scene", "estimate_s", "measured_s", "ratio", "within"}`` per scene; ``within`` says whether the ratio
        is inside ``[1/CHECK_FACTOR, CHECK_FACTOR]``.
    """
    import numpy as np

    from lighting._budget import scene_estimate
    from lighting.files.merl import write_merl
    from lighting.integrate.dominant import forget_environments
    from lighting.scene import SceneRenderer, parse_scene

    mc = '[[lights]]\ntype = "environment"\nsource = "daylight"\nmethod = "monte-carlo"\nsamples = {samples}\n'
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        merl = os.path.join(tmp, "m.binary")
        write_merl(merl, np.full((3, 90, 90, 180), 0.05))

        two, mc32 = '{model = "lambert"}, {model = "cook-torrance"}', mc.format(samples=32)
        makers = {
            "point lights": lambda: parse_scene(_scene(160, two, _POINTS)),
            "Monte Carlo": lambda: parse_scene(_scene(48, '{model = "lambert"}, {model = "phong"}', mc32)),
            "measured": lambda: parse_scene(_scene(32, ", ".join(['{file = "m.binary"}'] * 4), mc.format(samples=8)),
                                            base_dir=tmp),
            "split sum": _split_sum_environment,
            "dominant lights": _dominant_environment,
        }  # fmt: skip
        for label, make in makers.items():
            estimate = scene_estimate(make())["seconds"]
            seconds = _best(lambda make=make: (forget_environments(), SceneRenderer(make()).render()), repeat)
            ratio = estimate / seconds
            rows.append({"scene": label, "estimate_s": estimate, "measured_s": seconds, "ratio": ratio,
                         "within": 1 / CHECK_FACTOR <= ratio <= CHECK_FACTOR})  # fmt: skip
    return rows


def _example_environment(method=None, roughness_step=0.0):
    """The ``environment`` example at 280x160, under ``method`` (default: its own, the dominant lights), each
    glossy part's roughness raised by ``roughness_step``."""
    import tomllib

    from lighting.scene import example_path, parse_scene

    path = example_path("environment")
    with open(path, "rb") as f:
        data = tomllib.load(f)
    if method is not None:
        data["lights"][0]["method"] = method
    for ob in data["objects"]:
        for part in ob["material"]["parts"]:
            if "roughness" in part:
                part["roughness"] += roughness_step
    data["image"].update(width=280, height=160)
    return parse_scene(data, base_dir=os.path.dirname(path))


def _split_sum_environment():
    """The ``environment`` example at 280x160 under the split sum."""
    return _example_environment("split-sum")


#: Each run of :func:`_dominant_environment` makes lobes not met before.
_fresh_lobes = iter(range(1, 1 << 30))


def _dominant_environment():
    """The ``environment`` example at 280x160 under its own method, the dominant lights (the default), as a first
    frame: its two narrow lobes a little rougher at each call, so that their tables are made anew."""
    return _example_environment(roughness_step=1e-4 * next(_fresh_lobes))


def main(argv=None) -> int:
    """Print the measured costs, one ``"stage": seconds,`` line each (``--json``: one JSON object).

    Parameters
    ----------
    argv : list of str, optional
        ``[--repeat N] [--json]`` (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        0.
    """
    p = argparse.ArgumentParser(prog="python -m explorer.bench.costs", description=__doc__.splitlines()[0])
    p.add_argument("--repeat", type=int, default=3, help="runs per stage; the fastest counts (default 3)")
    p.add_argument("--json", action="store_true", help="one JSON object instead of the table's lines")
    p.add_argument("--check", action="store_true",
                   help="estimated against measured time of five small renders, with the target (within 4x)")
    args = p.parse_args(argv)
    if args.check:
        rows = estimate_against_clock(max(1, args.repeat))
        if args.json:
            print(json.dumps(rows))
        for r in rows if not args.json else ():
            verdict = "within" if r["within"] else "OUTSIDE"
            print(f"{r['scene']:15s} estimate {r['estimate_s']:8.3f} s  measured {r['measured_s']:8.3f} s  "
                  f"ratio {r['ratio']:5.2f}  {verdict} 1/{CHECK_FACTOR:g}..{CHECK_FACTOR:g}")
        return 0
    costs = measure(max(1, args.repeat))
    if args.json:
        print(json.dumps(costs))
    else:
        for k, v in costs.items():
            print(f"    {k!r}: {v:.3g},".replace("'", '"'))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
