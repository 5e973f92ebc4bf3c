"""A scene's memory and time budget: the names of :mod:`lighting._budget`, where the estimates, the limits and
the refusal live (re-exported here for the scene package and the code that imports them from it)."""

from __future__ import annotations

from .._budget import (  # noqa: F401  (re-exports, the private helpers included: the loader charges with them)
    BRDF_FILE_BYTES,
    BYTES_PER_MESH_FILE_BYTE,
    BYTES_PER_PIXEL,
    BYTES_PER_PIXEL_PER_OBJECT,
    BYTES_PER_SAMPLE_EVALUATION,
    BYTES_PER_SCENE_FILE_BYTE,
    BYTES_PER_TRIANGLE,
    DOMINANT_BYTES,
    DOMINANT_BYTES_PER_PIXEL,
    ENVIRONMENT_BYTES_PER_PIXEL,
    ENVIRONMENT_HELD_BYTES_PER_PIXEL,
    MEASURED_SAMPLER_BYTES,
    MEASURED_TABLE_BYTES,
    PREFILTER_BYTES_PER_PIXEL,
    PREFILTER_LARGE_BYTES_PER_PIXEL,
    PREFILTER_LEVEL_PIXELS,
    SECONDS_PER,
    TIME_LIMIT,
    _charge_file,
    _clamp,
    _environment_lights,
    _monte_carlo,
    check_scene_budget,
    environment_setup_bytes,
    explain_lines,
    prefilter_size,
    scene_estimate,
)

__all__ = ["scene_estimate", "check_scene_budget", "prefilter_size", "explain_lines", "TIME_LIMIT"]
