"""Atomic file writing: a temporary file beside the target, flushed to disk, then renamed into place.

Every image writer of the engine (:mod:`lighting.files.images`) goes through :func:`atomic_write`, so a
reader sees the old file or the whole new one; the command line's writer (:mod:`explorer.output`)
builds on :func:`write_temporary` and adds its flags and signal handling.
"""

from __future__ import annotations

import contextlib
import os
import stat
import tempfile

__all__ = ["file_mode", "write_temporary", "atomic_write"]


def _umask() -> int:
    try:  # Linux >= 4.7 reports it without changing it (os.umask would, for every thread, for a moment)
        with open("/proc/self/status", encoding="ascii") as f:
            for line in f:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError):
        pass
    old = os.umask(0o022)
    os.umask(old)
    return old


def file_mode(target) -> int:
    """Permission bits for a file written to ``target``: the replaced file's, else ``0o666`` minus the umask.

    What ``open(target, "w")`` would give; ``tempfile.mkstemp`` alone gives ``0o600``.

    Parameters
    ----------
    target : str or os.PathLike
        Path of the file about to be written (it may not exist yet).

    Returns
    -------
    int
        Permission bits (``stat.S_IMODE``), e.g. ``0o644``.
    """
    try:
        st = os.stat(target)
    except OSError:
        return 0o666 & ~_umask()
    return stat.S_IMODE(st.st_mode)


def write_temporary(path, data, *, guard=None) -> tuple[str, str]:
    """Write ``data`` to a new temporary file beside ``path``'s target, flushed to disk; the first half of a write.

    The file is named ``.<name>.<random>.part`` in the target's folder and gets :func:`file_mode`'s
    permissions.  On any exception (``KeyboardInterrupt`` too) it is removed before the exception
    goes on.  :func:`atomic_write` renames it into place; a caller writing several files as a unit
    renames them together.

    Parameters
    ----------
    path : str or os.PathLike
        The file to be written; a symbolic link is followed (its target is the file replaced).
    data : bytes or callable
        The contents, or ``data(temporary_path)`` writing them (for libraries that write files themselves).
    guard : callable, optional
        A context manager factory held while the temporary file is created (the command line holds
        its stop signals there, so that the file is never created without its name being known here).

    Returns
    -------
    tuple of str
        ``(temporary path, target path)``.
    """
    path = os.fspath(path)
    target = os.path.realpath(path) if os.path.islink(path) else os.path.abspath(path)
    mode = file_mode(target)
    hold = guard if guard is not None else contextlib.nullcontext
    fd, tmp, f = -1, None, None
    try:
        # The descriptor is owned by a file object before the guard lets a stop signal in: a signal landing
        # between a bare descriptor and the object made from it would leave one of them open or closed twice.
        with hold():
            fd, tmp = tempfile.mkstemp(prefix=f".{os.path.basename(target)}.", suffix=".part",
                                       dir=os.path.dirname(target))  # fmt: skip
            f = os.fdopen(fd, "wb")
        os.fchmod(f.fileno(), mode)
        if callable(data):
            f.close()
            data(tmp)
            with hold():
                f = open(tmp, "rb")  # closed below, or on the way out
            os.fsync(f.fileno())
        else:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        f.close()
    except BaseException:
        if f is not None:
            with contextlib.suppress(OSError):  # closing twice is allowed; a failed flush must not hide the cause
                f.close()
        elif fd >= 0:
            os.close(fd)
        if tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
        raise
    return tmp, target


def atomic_write(path, data) -> None:
    """Write ``data`` to ``path`` atomically: a temporary file beside it, flushed, then renamed into place.

    A reader sees the old file or the whole new one.  On any exception the temporary file is removed
    and the target is left as it was.

    Parameters
    ----------
    path : str or os.PathLike
        The file; a symbolic link is followed and its target replaced.
    data : bytes or callable
        The contents, or ``data(temporary_path)`` writing them (:func:`exr_writer`).

    Examples
    --------
    >>> import os, tempfile
    >>> d = tempfile.mkdtemp()
    >>> atomic_write(os.path.join(d, "a.pfm"), b"PF\\n1 1\\n-1.0\\n" + bytes(12))   # a one-pixel PFM
    >>> os.listdir(d), os.path.getsize(os.path.join(d, "a.pfm"))
    (['a.pfm'], 24)
    """
    tmp, target = write_temporary(path, data)
    try:
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
