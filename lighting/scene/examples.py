"""The example scenes shipped in ``lighting/scene/examples/``, by name."""

from __future__ import annotations

import os

from .errors import _suggest

__all__ = ["example_path", "list_examples", "scene_label"]

#: The folder of the shipped example scenes (and the mesh they use).
EXAMPLES_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "examples")


def list_examples() -> list[str]:
    """Names of the example scenes shipped with the package (``lighting/scene/examples/*.toml``).

    Returns
    -------
    list of str
        The names, sorted, without ``.toml``.
    """
    return sorted(f[:-5] for f in os.listdir(EXAMPLES_DIR) if f.endswith(".toml"))


def example_path(name: str) -> str:
    """Path of a shipped example scene, by name.

    Parameters
    ----------
    name : str
        ``"spotlight"`` or ``"spotlight.toml"``.

    Returns
    -------
    str
        The file's path.

    Raises
    ------
    ValueError
        For an unknown name, with the nearest one and the list.
    """
    stem = name[:-5] if name.endswith(".toml") else name
    if stem not in list_examples():
        raise ValueError(
            f"no example scene named {name!r}; {_suggest(stem, list_examples())}available: {', '.join(list_examples())}"
        )
    return os.path.join(EXAMPLES_DIR, stem + ".toml")


def scene_label(path) -> str:
    """The name messages give a scene file: a shipped example's name (``spotlight``), else the path as given.

    A shipped example is asked for by its name (``lighting-explorer render spotlight``), so its errors
    say that name rather than the folder the package happens to be installed in.

    Parameters
    ----------
    path : path-like
        The scene file.

    Returns
    -------
    str
        The label.

    Examples
    --------
    >>> scene_label(example_path("spotlight")), scene_label("scenes/my.toml")
    ('spotlight', 'scenes/my.toml')
    """
    label = os.fsdecode(os.fspath(path))
    folder, name = os.path.split(os.path.abspath(label))
    if name.endswith(".toml") and os.path.normcase(folder) == os.path.normcase(EXAMPLES_DIR):
        return name[:-5]
    return label
