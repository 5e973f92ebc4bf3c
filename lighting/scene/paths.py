"""Where a scene file may write: output paths it names stay inside its folder or the current folder."""

from __future__ import annotations

import os

from .._text import abbreviate
from .errors import SceneError, _describe, _fmt_value
from .examples import scene_label

__all__ = ["scene_output_path"]


def _within(path: str, folder: str) -> bool:
    """Whether ``path`` is ``folder`` or lies inside it (both resolved)."""
    return path == folder or path.startswith(folder.rstrip(os.sep) + os.sep)


def scene_output_path(output, scene_file, *, key: str = "image.output", cwd=None) -> str:
    """Where a scene-named output may be written: the resolved path, or :class:`SceneError`.

    A scene file is untrusted input (conventions.md): an output path it names stays inside the scene
    file's folder or the current folder.  Relative paths start from the current folder; the path is
    resolved with :func:`os.path.realpath` (symbolic links followed, ``..`` applied), and refused when
    it lands anywhere else, when it is itself a symbolic link (writing would replace the link or its
    target), or when it is a directory.  The command line's ``-o`` is not checked: the user chose it.

    Parameters
    ----------
    output : str
        The path the scene names (e.g. its ``[image].output``).
    scene_file : path
        The scene file that names it.
    key : str
        The key path named in the error.
    cwd : path, optional
        The current folder (default: :func:`os.getcwd`).

    Returns
    -------
    str
        The resolved path, which is what the caller writes (the place that was checked).

    Raises
    ------
    SceneError
        For a path outside both folders, a symbolic link, a directory or a missing folder; it names the
        scene file as :func:`~lighting.scene.examples.scene_label` does.
    """
    scene_file = os.fspath(scene_file)
    label = scene_label(scene_file)  # a shipped example by its name, as the loader names it
    cwd = os.getcwd() if cwd is None else os.fspath(cwd)
    folders = [os.path.realpath(os.path.dirname(os.path.abspath(scene_file))), os.path.realpath(cwd)]
    allowed = f"a path inside the scene's folder {folders[0]} or the current folder {folders[1]} " \
              "(give -o on the command line to write elsewhere)"  # fmt: skip
    if not isinstance(output, str) or not output.strip() or "\0" in output:
        raise SceneError(label, key, f"must be {allowed}; got {_describe(output)}")
    given = os.path.join(cwd, output)
    if os.path.islink(given):
        raise SceneError(label, key, f"{_fmt_value(output)} is a symbolic link; a scene may not write "
                                          f"through one: it must be {allowed}")  # fmt: skip
    real = os.path.realpath(given)
    if not any(_within(real, f) for f in folders):
        shown = abbreviate(real, keep_end=True)
        raise SceneError(label, key, f"{_fmt_value(output)} resolves to {shown}; it must be {allowed}")
    if os.path.isdir(real):
        raise SceneError(label, key, f"{_fmt_value(output)} is a directory; it must be a file name, {allowed}")
    if not os.path.isdir(os.path.dirname(real)):
        raise SceneError(label, key, f"{_fmt_value(output)}: folder {abbreviate(os.path.dirname(real))} does "
                                          f"not exist; the output must be {allowed}")  # fmt: skip
    return real
