"""The split lit sphere: one half the current model, the other a comparison entry, divided along the light.

The divider runs through the image centre along the light's azimuth in the image (:func:`split_angle`), so
each half holds one side of the highlight; :func:`split_mask` is the current model's half and
:func:`split_render` puts the other model into the rest.  No toolkit is imported here.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["split_angle", "split_mask", "split_render"]


def split_angle(state) -> float:
    """The split sphere's divider: the light's azimuth in the image (degrees), or 90° (vertical) for ambient light.

    The highlight lies on the line from the centre toward the projected light direction, so a divider
    along it gives each half one side of the highlight (a vertical divider puts the whole highlight of a
    light from the upper left into the left half).

    Parameters
    ----------
    state : AppState
        The controls (``light``, ``azimuth``).

    Returns
    -------
    float
        Degrees from image right toward image up.

    Examples
    --------
    >>> from explorer.app.state import AppState
    >>> split_angle(AppState()), split_angle(AppState(light="ambient"))
    (135.0, 90.0)
    """
    return 90.0 if state.light == "ambient" else float(state.azimuth)


def split_mask(shape, angle_deg: float) -> np.ndarray:
    """The current model's half of a split image: the pixels counter-clockwise of the divider.

    The divider runs through the image centre along ``angle_deg`` (from image right toward image up);
    at 90° the current model is on the left, as a vertical split reads.

    Parameters
    ----------
    shape : (int, int)
        Rows and columns.
    angle_deg : float
        The divider's direction.

    Returns
    -------
    ndarray of bool, shape shape
        True on the current model's half.

    Examples
    --------
    >>> split_mask((2, 4), 90.0).astype(int).tolist()
    [[1, 1, 0, 0], [1, 1, 0, 0]]
    >>> split_mask((2, 2), 0.0).astype(int).tolist()  # a horizontal divider: the current model on top
    [[1, 1], [0, 0]]
    """
    h, w = int(shape[0]), int(shape[1])
    x = np.arange(w) + 0.5 - 0.5 * w  # image right
    y = 0.5 * h - np.arange(h) - 0.5  # image up
    a = math.radians(angle_deg)
    # Counter-clockwise of the direction (cos a, sin a): the cross product d × p is positive.
    return (math.cos(a) * y[:, None] - math.sin(a) * x[None, :]) > 0


def split_render(renderer, img, material, lights, state):
    """``img`` with one half rendered again with ``material`` (the split sphere): the same lights,
    shading mode, form and terms, so only the BRDF differs between the halves.

    The halves meet along :func:`split_angle` (the current model keeps :func:`split_mask`'s half)."""
    other = renderer.render(material, lights, mode=state.mode, form=state.form, terms=state.terms)
    img = np.array(img, copy=True)
    keep = split_mask(img.shape[:2], split_angle(state))
    img[~keep] = np.asarray(other)[~keep]
    return img
