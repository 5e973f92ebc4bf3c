"""The scene text the model tests render a new model in: one unit sphere under one directional light."""

_TEXT = """
[camera]
eye = [0.0, 0.0, 4.0]
[image]
width = {size}
height = {size}
[materials.m]
parts = [{part}]
[[objects]]
type = "sphere"
center = [0.0, 0.0, 0.0]
radius = 1.0
material = "m"
[[lights]]
type = "directional"
direction = [0.3, 0.5, 1.0]
"""


def one_sphere(part: str, size: int = 24) -> str:
    """Scene text: a ``size`` x ``size`` image of a unit sphere whose material is the one ``part`` given.

    Parameters
    ----------
    part : str
        An inline TOML table of a material part, e.g. ``'{model = "lambert", kd = 0.7}'``.
    size : int, optional
        The image's width and height in pixels.

    Returns
    -------
    str
        The scene as TOML text.
    """
    return _TEXT.format(size=size, part=part)
