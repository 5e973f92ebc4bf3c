"""Every file the command line writes goes through here: checked first, written atomically, format by extension.

One writer for ``render``, ``sphere``, ``explore --screenshot``, the figures and the reports:

* **Checked before the work.**  :func:`check_output_path` refuses, in one line naming the flag and the
  user's path, an empty path, an unknown extension (with the list of formats), a directory, a missing or
  read-only folder — before anything is rendered.
* **Atomic.**  The bytes go to a temporary file in the target folder, which is renamed over the target
  only when complete: a reader sees the old file or the whole new one, never half of one.  The temporary
  file is removed on any exception, on Ctrl-C (``KeyboardInterrupt``) and on ``SIGTERM`` (see
  :func:`signals_as_exceptions`); error messages name the user's path, never the temporary one.  The
  temporary file and the formats' bytes come from :mod:`lighting.files.images`, the engine's home of
  image files; this module adds the flags, the checks before the work and the signals.
* **Permissions.**  A new file gets ``0o666`` minus the user's umask, as ``open()`` would give it; a
  replaced file keeps its mode.  (``tempfile.mkstemp`` alone would leave ``0o600``.)
* **Format from the extension** (:data:`IMAGE_FORMATS`): ``.png`` (always), ``.jpg``/``.jpeg``,
  ``.tif``/``.tiff`` and ``.webp`` through Pillow when it is installed, and the *linear* float image as
  ``.npy`` (NumPy), ``.pfm`` (portable float map) and ``.exr`` (when the ``OpenEXR`` module is installed).
  Linear formats store the engine's radiance as computed, without exposure or tone map.

Examples
--------
>>> import tempfile, numpy as np
>>> d = tempfile.mkdtemp()
>>> write_image(os.path.join(d, "a.npy"), rgb8=None, linear=np.ones((2, 3, 3)))
'npy'
>>> np.load(os.path.join(d, "a.npy")).shape, sorted(os.listdir(d))
((2, 3, 3), ['a.npy'])
>>> check_output_path(os.path.join(d, "a.svg"))
Traceback (most recent call last):
...
explorer.output.OutputError: -o: cannot write '....svg': unknown image format '.svg'; formats: ...
"""

from __future__ import annotations

import contextlib
import io
import os
import signal
import sys
import threading

import numpy as np

from lighting.files.images import exr_writer, file_mode, npy_bytes, pfm_bytes, png_bytes, write_temporary

__all__ = [
    "OutputError",
    "Terminated",
    "IMAGE_FORMATS",
    "available_formats",
    "check_output_path",
    "check_output_dir",
    "atomic_write",
    "atomic_write_many",
    "write_image",
    "encode_image",
    "file_mode",
    "signals_as_exceptions",
    "program_stops",
    "deferred_signals",
    "on_signal",
    "received_signal",
    "raise_if_signalled",
]


class OutputError(ValueError):
    """An output that cannot be written (a ValueError: the command exits with status 2)."""


class Terminated(BaseException):
    """Raised in the main thread when ``SIGTERM`` arrives (see :func:`signals_as_exceptions`).

    A ``BaseException``, like ``KeyboardInterrupt``, so that ``except Exception`` does not swallow it
    and every ``finally`` on the way out runs (the writer's clean-up of its temporary file among them).
    """

    def __init__(self, signum: int = signal.SIGTERM):
        super().__init__(f"terminated by signal {signum}")
        self.signum = signum


# extension -> (format name, kind): kind "rgb8" takes the encoded 8-bit picture, "linear" the float image.
_EXTENSIONS = {
    ".png": ("png", "rgb8"),
    ".jpg": ("jpeg", "rgb8"),
    ".jpeg": ("jpeg", "rgb8"),
    ".tif": ("tiff", "rgb8"),
    ".tiff": ("tiff", "rgb8"),
    ".webp": ("webp", "rgb8"),
    ".npy": ("npy", "linear"),
    ".pfm": ("pfm", "linear"),
    ".exr": ("exr", "linear"),
}
#: Every image format the writer knows, by extension (some need an optional package: see available_formats).
IMAGE_FORMATS = tuple(_EXTENSIONS)


def _has_module(name: str) -> bool:
    import importlib.util

    try:
        return importlib.util.find_spec(name) is not None
    except (ImportError, ValueError):
        return False


def available_formats(kinds=("rgb8", "linear")) -> tuple[str, ...]:
    """The extensions that can be written here (Pillow's and OpenEXR's only when installed).

    Parameters
    ----------
    kinds : tuple of str, optional
        ``"rgb8"`` (8-bit formats) and/or ``"linear"`` (floating-point formats).

    Returns
    -------
    tuple of str
        Extensions with their dot (``".png"``, ``".npy"`` ...).
    """
    pil = _has_module("PIL")
    exr = _has_module("OpenEXR")
    out = []
    for ext, (fmt, kind) in _EXTENSIONS.items():
        if kind not in kinds:
            continue
        if fmt in ("jpeg", "tiff", "webp") and not pil:
            continue
        if fmt == "exr" and not exr:
            continue
        out.append(ext)
    return tuple(out)


def _show(path) -> str:
    from lighting._text import quote_path

    return quote_path(path)


def _writable_folder(flag: str, path: str, folder: str) -> None:
    what = f"{flag}: cannot write {_show(path)}"
    if not os.path.exists(folder):
        raise OutputError(f"{what}: folder {_show(folder)} does not exist")
    if not os.path.isdir(folder):
        raise OutputError(f"{what}: {_show(folder)} is not a folder")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise OutputError(f"{what}: folder {_show(folder)} is not writable")


def _path_text(path, flag: str, kind: str, empty: str, verb: str) -> str:
    """``path`` as text, refusing what no file system takes: a non-path, an empty name, a NUL character."""
    if not isinstance(path, (str, os.PathLike)):
        raise OutputError(f"{flag} must be {kind}; got {type(path).__name__}")
    path = os.fspath(path)
    if not path.strip():
        raise OutputError(f"{flag}: {empty}")
    if "\0" in path:
        raise OutputError(f"{flag}: {verb} {_show(path)}: the path contains a NUL character")
    return path


def check_output_path(path, *, flag: str = "-o", kinds=("rgb8", "linear")) -> str:
    """Check that an image can be written to ``path``; return its format name (``"png"``, ``"npy"``, …).

    Call it before the work.  Raises :class:`OutputError` (one line naming ``flag`` and the path) for an
    empty path, an extension that is not one of the formats available here (the message lists them), a
    directory, a missing folder, a folder the user cannot write, or an existing target that is not a
    regular file.

    Parameters
    ----------
    path : str or os.PathLike
        The output file.
    flag : str, optional
        The option that gave it, named in the error.
    kinds : tuple of str, optional
        The kinds of format the command writes (``"rgb8"``, ``"linear"``).

    Returns
    -------
    str
        The format name.
    """
    path = _path_text(path, flag, "a file path", "the output path is empty; give a file name such as out.png",
                      "cannot write")  # fmt: skip
    allowed = available_formats(kinds)
    ext = os.path.splitext(path)[1].lower()
    if os.path.isdir(path):
        raise OutputError(f"{flag}: {_show(path)} is a folder; give a file name ending in {', '.join(allowed)}")
    if ext not in allowed:
        if ext in _EXTENSIONS and _EXTENSIONS[ext][1] not in kinds:
            why = f"{ext} holds a linear float image, which {flag} does not make"
        elif ext in _EXTENSIONS:
            why = f"writing {ext} needs {'OpenEXR' if ext == '.exr' else 'Pillow'}, which is not installed"
        else:
            why = f"unknown image format {ext!r}" if ext else "no extension"
        raise OutputError(f"{flag}: cannot write {_show(path)}: {why}; formats: {', '.join(allowed)}")
    target = os.path.realpath(path)
    if os.path.exists(target) and not os.path.isfile(target):
        raise OutputError(f"{flag}: cannot write {_show(path)}: it exists and is not a regular file")
    _writable_folder(flag, path, os.path.dirname(target))
    return _EXTENSIONS[ext][0]


def check_output_dir(path, *, flag: str = "--out") -> str:
    """Check that ``path`` is, or can be made, a writable folder (a missing one is created later).

    Raises :class:`OutputError` when it names an existing file, is empty, or its nearest existing
    ancestor is not a writable folder.

    Parameters
    ----------
    path : str or os.PathLike
        The output folder.
    flag : str, optional
        The option that gave it, named in the error.

    Returns
    -------
    str
        The path.
    """
    path = _path_text(path, flag, "a folder path", "the output folder is empty; give a folder name", "cannot use")
    if os.path.exists(path):
        if not os.path.isdir(path):
            raise OutputError(f"{flag}: {_show(path)} exists and is not a folder; give a folder for the output")
        if not os.access(path, os.W_OK | os.X_OK):
            raise OutputError(f"{flag}: folder {_show(path)} is not writable")
        return path
    parent = os.path.dirname(os.path.abspath(path))
    while not os.path.exists(parent):
        up = os.path.dirname(parent)
        if up == parent:
            break
        parent = up
    if not os.path.isdir(parent):
        raise OutputError(f"{flag}: cannot create {_show(path)}: {_show(parent)} is not a folder")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise OutputError(f"{flag}: cannot create {_show(path)}: folder {_show(parent)} is not writable")
    return path


# --------------------------------------------------------------------------- signals
_SIGNALS = tuple(s for s in (getattr(signal, "SIGINT", None), getattr(signal, "SIGTERM", None)) if s is not None)


# Signals that arrive inside deferred_signals() wait for its end.  Two layers: the signals are blocked in
# the main thread (pthread_sigmask), and our handlers note a signal instead of raising while a section is
# open -- the kernel may deliver a process-wide signal to another thread (an engine or executor thread),
# whose C handler then makes the main thread run the Python handler inside the section all the same.
# "received" remembers the last signal even after its exception was raised: some libraries swallow it
# (trimesh wraps its optional imports in ``except BaseException``), and a command that was asked to stop
# must not go on to write its output; every write checks it first (_prepare), and so does cli.main.
_deferral = {"depth": 0, "pending": None, "received": None}


def received_signal() -> int | None:
    """The signal that asked this command to stop (within :func:`signals_as_exceptions`).

    Returns
    -------
    int or None
        The signal number, or ``None``.
    """
    return _deferral["received"]


def raise_if_signalled() -> None:
    """Raise ``KeyboardInterrupt`` or :class:`Terminated` again if a stop signal arrived and was swallowed.

    Returns
    -------
    None
        Outside a deferred section, when no stop signal arrived.
    """
    if _deferral["received"] is not None and not _deferral["depth"]:
        _raise_for(_deferral["received"])


def quiet_stop_unraisable(unraisable, fallback=None) -> None:
    """A ``sys.unraisablehook`` that notes a stop signal raised where Python cannot propagate it.

    A signal handler that raises (:func:`on_signal`) may run inside a weak-reference callback or a
    ``__del__`` that the garbage collector calls (Matplotlib's transform tree has such callbacks);
    Python then prints "Exception ignored in ..." with a traceback and goes on.  The signal is already
    noted (:func:`received_signal`), and :func:`raise_if_signalled` raises it again at the next safe
    point, so nothing is printed for it here; any other unraisable exception goes to ``fallback``.

    Parameters
    ----------
    unraisable : object
        What Python passes to ``sys.unraisablehook`` (``exc_value`` and the rest).
    fallback : callable, optional
        The hook for every other exception (default: Python's own).

    Returns
    -------
    None
    """
    if isinstance(unraisable.exc_value, (Terminated, KeyboardInterrupt)):
        return
    (fallback or sys.__unraisablehook__)(unraisable)


def _raise_for(signum: int):
    if signum == signal.SIGINT:
        raise KeyboardInterrupt
    raise Terminated(signum)


def on_signal(signum, frame=None) -> None:
    """The handler :func:`signals_as_exceptions` installs: raise now, or at the end of a deferred section.

    Parameters
    ----------
    signum : int
        The signal.
    frame : frame, optional
        Unused (the signal module passes it).

    Returns
    -------
    None
        Inside a deferred section; otherwise it raises ``KeyboardInterrupt`` or :class:`Terminated`.
    """
    _deferral["received"] = signum
    if _deferral["depth"]:
        _deferral["pending"] = _deferral["pending"] or signum
        return
    _raise_for(signum)


@contextlib.contextmanager
def deferred_signals():
    """Hold ``SIGINT`` and ``SIGTERM`` until the block is done (a few renames that must happen together).

    A signal that arrived meanwhile is raised at the end of the block.  Off the main thread this does
    nothing (Python runs signal handlers in the main thread only).

    Yields
    ------
    None
        Inside the block, ``SIGINT`` and ``SIGTERM`` are held.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    mask = getattr(signal, "pthread_sigmask", None)
    old = mask(signal.SIG_BLOCK, _SIGNALS) if mask is not None else None
    _deferral["depth"] += 1
    try:
        yield
    finally:
        if mask is not None:
            mask(signal.SIG_SETMASK, old)  # a signal held by the mask is handled here, and noted
        _deferral["depth"] -= 1
        pending = _deferral["pending"] if _deferral["depth"] == 0 else None
        if pending is not None:
            _deferral["pending"] = None
            _raise_for(pending)


@contextlib.contextmanager
def signals_as_exceptions():
    """Within the block, ``SIGTERM`` raises :class:`Terminated` and ``SIGINT`` ``KeyboardInterrupt``.

    Python's default for ``SIGTERM`` ends the process at once, skipping every ``finally``: a temporary
    file being written would stay behind.  Both handlers respect :func:`deferred_signals`.  A signal
    that is ignored (``SIG_IGN``, e.g. under ``nohup``) stays ignored.  Off the main thread this does
    nothing (only the main thread may set handlers).

    Yields
    ------
    None
        Inside the block, the handlers are :func:`on_signal`; the previous ones are restored after it.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = {}
    _deferral["received"] = None
    for sig in _SIGNALS:
        if signal.getsignal(sig) is not signal.SIG_IGN:
            old[sig] = signal.signal(sig, on_signal)
    old_hook = sys.unraisablehook
    sys.unraisablehook = lambda unraisable: quiet_stop_unraisable(unraisable, old_hook)
    try:
        yield
    finally:
        sys.unraisablehook = old_hook
        for sig, handler in old.items():
            signal.signal(sig, handler if handler is not None else signal.SIG_DFL)
        _deferral["received"] = None


def program_stops(*, after: bool) -> None:
    """The program's own handlers for ``SIGINT`` and ``SIGTERM``, outside :func:`signals_as_exceptions`' block.

    Before the command (``after`` False) a stop exits at once with the status a shell gives it (``128 +`` the
    signal: 130, 143): nothing is written yet, and the command's block, entered next, restores this handler when it
    ends.  After the command (``after`` True) stops are ignored: its files are in place and it has its status, but
    Python's shutdown (exit handlers, the modules' teardown) still takes a moment, and at its end Python puts the
    default handlers back, under which a ``SIGTERM`` would kill the process by the signal instead of letting it exit
    with that status.  As :func:`signals_as_exceptions`: an ignored signal stays ignored, and off the main thread
    this does nothing.

    Parameters
    ----------
    after : bool
        Whether the command has returned.

    Returns
    -------
    None
    """
    if threading.current_thread() is not threading.main_thread():
        return

    def stop(signum, frame):
        for stream in (sys.stdout, sys.stderr):  # what the command printed is not lost
            try:
                stream.flush()
            except (OSError, ValueError, AttributeError):
                pass  # a closed pipe or no stream: nothing more to say
        os._exit(128 + signum)

    for sig in _SIGNALS:
        if signal.getsignal(sig) is not signal.SIG_IGN:
            signal.signal(sig, signal.SIG_IGN if after else stop)


# --------------------------------------------------------------------------- atomic writing
def _remove(tmp: str) -> None:
    with contextlib.suppress(OSError):
        os.unlink(tmp)


def _prepare(path, data, flag):
    """Write ``data`` (bytes, or a callable taking a file path) to a temporary file beside ``path``."""
    raise_if_signalled()  # asked to stop (and a library swallowed the exception): write nothing
    try:
        # Created with the signals held, so that an interrupt cannot land between the creation and the moment
        # the writer knows the name: a signal held meanwhile is raised as the guard ends, inside
        # write_temporary, which removes the file.
        return write_temporary(path, data, guard=deferred_signals)
    except OSError as exc:
        raise OutputError(f"{flag}: cannot write {_show(path)}: {exc.strerror or exc}") from None


def atomic_write(path, data, *, flag: str = "-o") -> None:
    """Write ``data`` to ``path`` atomically (temporary file in the same folder, renamed into place).

    ``data`` is bytes, or a callable that writes the file at the path it is given (for libraries that
    write files themselves).  The file gets the replaced file's mode, else ``0o666`` minus the umask.  On
    any exception, ``KeyboardInterrupt`` or :class:`Terminated` the temporary file is removed and the
    target is left as it was.  ``OSError`` becomes :class:`OutputError` naming ``flag`` and ``path``.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    data : bytes or callable
        The contents, or ``data(temporary_path)`` writing them.
    flag : str, optional
        The option that named the file, for errors.

    Returns
    -------
    None
    """
    atomic_write_many([(path, data)], flag=flag)


def atomic_write_many(items, *, flag: str = "-o") -> None:
    """Write several files as a unit: all are written to temporary files first, then renamed together.

    The renames happen with ``SIGINT``/``SIGTERM`` held, so an interrupt leaves all of the new files or
    none of them (a figure never without its sidecar).

    Parameters
    ----------
    items : list of tuple
        ``(path, data)`` pairs, as :func:`atomic_write` takes them.
    flag : str, optional
        The option that named the files, for errors.

    Returns
    -------
    None
    """
    done = []
    try:
        for path, data in items:
            done.append((*_prepare(path, data, flag), os.fspath(path)))
        with deferred_signals():
            for i, (tmp, target, path) in enumerate(done):
                try:
                    os.replace(tmp, target)
                except OSError as exc:
                    for t, _, _ in done[i:]:
                        _remove(t)
                    done.clear()
                    raise OutputError(f"{flag}: cannot write {_show(path)}: {exc.strerror or exc}") from None
            done.clear()
    finally:
        for tmp, _, _ in done:
            _remove(tmp)


# --------------------------------------------------------------------------- image formats
def encode_image(fmt: str, *, rgb8=None, linear=None):
    """The file contents for ``fmt``.

    Parameters
    ----------
    fmt : str
        A format name (``"png"``, ``"npy"`` ...).
    rgb8 : numpy.ndarray, optional
        The 8-bit image, for 8-bit formats.
    linear : numpy.ndarray, optional
        The linear image, for floating-point formats.

    Returns
    -------
    bytes or callable
        The bytes, or a callable writing the file at a path (OpenEXR writes its own).
    """
    if _kind(fmt) == "linear":
        if linear is None:
            raise OutputError(f"the {fmt} format stores the linear float image, which this command does not have")
        a = np.asarray(linear)
        if a.ndim != 3 or a.shape[-1] != 3 or a.dtype.kind != "f":
            raise OutputError(f"a linear image must be a float array of shape (H, W, 3); got {a.dtype} {a.shape}")
        if fmt == "npy":
            return npy_bytes(a)
        if fmt == "pfm":
            return pfm_bytes(a)
        return exr_writer(a)
    a = np.asarray(rgb8)
    if a.dtype != np.uint8 or a.ndim != 3 or a.shape[-1] not in (3, 4):
        raise OutputError(f"an 8-bit image must be uint8 of shape (H, W, 3|4); got {a.dtype} {a.shape}")
    if fmt == "png":
        return png_bytes(np.ascontiguousarray(a))
    from PIL import Image

    im = Image.fromarray(np.ascontiguousarray(a))
    if fmt == "jpeg" and im.mode == "RGBA":
        im = im.convert("RGB")
    buf = io.BytesIO()
    options = {
        "jpeg": {"quality": 95, "subsampling": 0},  # full-resolution colour: renders have sharp colour edges
        "webp": {"lossless": True},
        "tiff": {"compression": "tiff_deflate"},
    }[fmt]
    im.save(buf, format=fmt.upper(), **options)
    return buf.getvalue()


def _kind(fmt: str) -> str:
    return next(kind for f, kind in _EXTENSIONS.values() if f == fmt)


def write_image(path, *, rgb8=None, linear=None, flag: str = "-o") -> str:
    """Write an image to ``path`` in the format its extension names; returns the format name.

    Parameters
    ----------
    path : str or path-like
        The output; its extension chooses the format (:func:`available_formats`).
    rgb8 : array_like, (H, W, 3|4) uint8, optional
        The encoded picture, for PNG, JPEG, TIFF and WebP.
    linear : array_like, (H, W, 3) float, optional
        The linear image, for ``.npy`` (dtype kept), ``.pfm`` and ``.exr`` (float32).
    flag : str
        The command-line flag that named ``path``, for messages.

    Returns
    -------
    str
        The format written (``"png"``, ``"npy"``, ...).

    Notes
    -----
    The path is checked (:func:`check_output_path`) and the file written atomically
    (:func:`atomic_write`); errors are :class:`OutputError` naming ``flag`` and ``path``.
    """
    fmt = check_output_path(path, flag=flag)
    atomic_write(path, encode_image(fmt, rgb8=rgb8, linear=linear), flag=flag)
    return fmt
