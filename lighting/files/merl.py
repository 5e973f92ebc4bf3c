r"""MERL measured isotropic BRDFs: the ``.binary`` files of Matusik et al. (2003).

The format
----------
Three little-endian ``int32`` dimensions ``90 90 180`` (product ``N = 1 458 000``), then ``3 N``
little-endian ``float64`` values: all red, then all green, then all blue.  A value's place in a
channel is ``k + 180 j + 180·90 i`` for the bins

* ``i`` of the half angle ``θ_h`` (non-linear: ``i = ⌊90 √(θ_h / (π/2))⌋``, so bin ``i`` starts at
  ``θ_h = (i/90)² π/2`` and the bins crowd where specular peaks live),
* ``j`` of the difference angle ``θ_d`` (linear over ``[0, π/2)``),
* ``k`` of the difference azimuth ``φ_d`` (linear over ``[0, π)``, after folding ``φ_d`` by ``π``:
  reciprocity, swapping ``l`` and ``v``, turns ``φ_d`` into ``φ_d + π``).

The angles are Rusinkiewicz's half/difference angles (:mod:`lighting.analysis.halfdiff`).  A stored
value times the channel's scale (``1/1500``, ``1.15/1500``, ``1.66/1500`` for R, G, B) is ``f_r`` in
1/sr; negative values mark bins that were not measured.

Lookup and missing bins
-----------------------
``interpolation="nearest"`` (the default) is the reference reader's lookup: the value of the bin
that contains the direction pair.  ``"linear"`` is trilinear in the bin coordinates
``(90 √(θ_h/(π/2)), 90 θ_d/(π/2), 180 φ_d/π)`` with each bin's value sited at its centre: clamped at
the ends of ``θ_h`` and ``θ_d`` and periodic in ``φ_d`` (the folded BRDF has period ``π`` there).
Missing bins (negative values) are replaced once, when the model is built, by the nearest measured
bin along ``φ_d`` in the same ``(θ_h, θ_d)`` row (circularly; the earlier one on a tie), and by 0
where the whole row is missing: ``φ_d`` is the direction along which an isotropic BRDF varies least,
so the neighbour there is the best guess the table itself offers.  Below the horizon ``f_r`` is 0,
as for every model.

References
----------
W. Matusik, H. Pfister, M. Brand, L. McMillan, "A Data-Driven Reflectance Model",
ACM Transactions on Graphics 22(3) (SIGGRAPH 2003), 759–769.
S. Rusinkiewicz, "A New Change of Variables for Efficient BRDF Representation",
Rendering Techniques '98 (Eurographics Workshop on Rendering), 1998.
"""

from __future__ import annotations

import math
import os
import stat
import tempfile

import numpy as np

from .._budget import check_budget
from .._validate import check_choice
from ..analysis.halfdiff import _HORIZON_TOL, dirs_to_half_diff, half_diff_to_dirs
from ..models.base import BRDF, BRDFFlags
from ..models.protocol import Parameter
from ..numerics import saturate_to

__all__ = ["MerlBRDF", "read_merl", "write_merl", "tabulate_merl", "bin_centres", "load", "DIMS", "SCALE"]

#: The table's dimensions as the header stores them: θ_h bins, θ_d bins, φ_d bins.
DIMS = (90, 90, 180)
#: Values per channel.
BINS = math.prod(DIMS)
#: Stored value × scale = ``f_r`` in 1/sr, per channel (R, G, B).
SCALE = np.array([1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0])
_HEADER = 12
_FILE_SIZE = _HEADER + 8 * 3 * BINS
_INTERPOLATIONS = ("nearest", "linear")
#: Direction pairs looked up per pass: bounds the temporaries of the half/difference angles and the
#: eight trilinear gathers (about 1 KiB per pair) independently of the number of shading points.
_CHUNK = 1 << 16


def _refuse(path, where: str, what: str):
    return ValueError(f"MERL file {os.fspath(path)!r}: {where}: {what}")


class MerlBRDF(BRDF):
    """A measured isotropic BRDF tabulated over Rusinkiewicz's angles (MERL layout).

    Parameters
    ----------
    table : array_like, shape (3, 90, 90, 180) or (3 * 1458000,)
        ``f_r`` in 1/sr per channel, indexed ``[channel, θ_h bin, θ_d bin, φ_d bin]``; negative
        entries mark missing bins.  Finite real values.
    interpolation : {"nearest", "linear"}, optional
        The lookup (module docstring): the reference reader's nearest bin (default) or trilinear in
        the bin coordinates (√-spaced ``θ_h`` index, ``θ_d``, ``φ_d``).
    source : str, optional
        Where the table came from (a file name), shown by ``repr``.

    Notes
    -----
    Missing bins take the value of the nearest measured bin along ``φ_d`` (0 if the whole row is
    missing); the table as given stays available as :attr:`table`.  Unregistered (``name = None``):
    scene files name models, not measurements.

    References
    ----------
    W. Matusik, H. Pfister, M. Brand, L. McMillan, "A Data-Driven Reflectance Model", SIGGRAPH 2003.

    Examples
    --------
    >>> import numpy as np
    >>> m = MerlBRDF(np.full((3, 90, 90, 180), 0.5 / np.pi))
    >>> m.eval((0, 0, 1), (0.3, 0.0, 0.9), (0.0, 0.2, 0.9)).round(4).tolist()
    [0.1592, 0.1592, 0.1592]
    """

    flags = BRDFFlags.SPECULAR | BRDFFlags.OWN_DIFFUSE  # measured data holds the diffuse part: no Lambert term added

    def __init__(self, table, *, interpolation: str = "nearest", source: str | None = None):
        arr = np.asarray(table)
        if arr.dtype.kind not in "fiu" or arr.size != 3 * BINS:
            raise ValueError(
                f"table must be real, shape (3, 90, 90, 180) or (4374000,); got dtype {arr.dtype}, shape {arr.shape}"
            )
        arr = arr.astype(np.float64).reshape(3, BINS)
        if not np.all(np.isfinite(arr)):
            raise ValueError("table must be finite; got NaN or infinite entries")
        self._setup(arr / SCALE[:, None], interpolation, source)

    @classmethod
    def _from_raw(cls, raw: np.ndarray, interpolation: str, source: str | None) -> MerlBRDF:
        self = cls.__new__(cls)
        self._setup(raw, interpolation, source)
        return self

    def _setup(self, raw, interpolation, source, lut=None):
        self.interpolation = check_choice("interpolation", interpolation, _INTERPOLATIONS)
        self.source = source
        self._raw = raw.reshape(3, BINS)  # the stored values, kept bitwise for write_merl
        if lut is None:  # channel-last f_r with missing bins filled: one gather gives the RGB triple
            lut = np.ascontiguousarray(_fill_missing(self._raw.reshape(3, -1, DIMS[2])).reshape(3, BINS).T)
            lut *= SCALE
        self._lut = lut

    @property
    def raw(self) -> np.ndarray:
        """The stored values (before the channel scales), shape ``(3, 90, 90, 180)``, read-only view."""
        out = self._raw.reshape(3, *DIMS).view()
        out.flags.writeable = False
        return out

    @property
    def table(self) -> np.ndarray:
        """``f_r`` in 1/sr as given (missing bins still negative), shape ``(3, 90, 90, 180)``, a new array."""
        return (self._raw * SCALE[:, None]).reshape(3, *DIMS)

    @property
    def missing(self) -> int:
        """The number of missing (negative) values over the three channels."""
        return int(np.count_nonzero(self._raw < 0))

    def _f(self, g):
        dt = g.dtype
        shape = np.broadcast_shapes(g.n.shape, g.l.shape, g.v.shape)[:-1]
        above = np.broadcast_to(g.above, shape).reshape(-1)
        l_loc = np.broadcast_to(g.l_local, shape + (3,)).reshape(-1, 3)
        v_loc = np.broadcast_to(g.v_local, shape + (3,)).reshape(-1, 3)
        out = np.zeros((above.size, 3), dtype=dt)
        rows = np.flatnonzero(above)
        for s in range(0, rows.size, _CHUNK):
            r = rows[s : s + _CHUNK]
            th, _, td, pd = dirs_to_half_diff(l_loc[r].astype(np.float64), v_loc[r].astype(np.float64))
            out[r] = saturate_to(self._lookup(th, td, pd), dt)
        return out.reshape(shape + (3,))

    def _f_cos(self, g):
        return self._f(g) * np.maximum(g.n_dot_l, 0)[..., None]

    def _lookup(self, theta_h, theta_d, phi_d) -> np.ndarray:
        """``f_r`` (P, 3) float64 at half/difference angles (P,) with the model's interpolation."""
        uh = DIMS[0] * np.sqrt(np.maximum(theta_h, 0) / (np.pi / 2))
        ud = DIMS[1] * theta_d / (np.pi / 2)
        up = DIMS[2] * np.mod(phi_d, np.pi) / np.pi
        if self.interpolation == "nearest":
            i = np.clip(uh.astype(np.int64), 0, DIMS[0] - 1)
            j = np.clip(ud.astype(np.int64), 0, DIMS[1] - 1)
            k = np.clip(up.astype(np.int64), 0, DIMS[2] - 1)
            return self._lut[k + DIMS[2] * (j + DIMS[1] * i)]
        # Bin centres at integer + 1/2: shift so that nodes are at integers.
        i0, wi = _clamped(uh - 0.5, DIMS[0])
        j0, wj = _clamped(ud - 0.5, DIMS[1])
        kf = np.floor(up - 0.5)
        wk = (up - 0.5) - kf
        k0 = kf.astype(np.int64) % DIMS[2]
        k1 = (k0 + 1) % DIMS[2]
        out = np.zeros((theta_h.size, 3))
        with np.errstate(over="ignore"):  # weights sum to 1: only rounding can pass the largest float
            for di, a in ((0, 1 - wi), (1, wi)):
                for dj, b in ((0, 1 - wj), (1, wj)):
                    base = DIMS[2] * (j0 + dj + DIMS[1] * (i0 + di))
                    ab = a * b
                    out += (ab * (1 - wk))[:, None] * self._lut[base + k0]
                    out += (ab * wk)[:, None] * self._lut[base + k1]
        return np.minimum(out, np.finfo(np.float64).max)

    def _params(self):
        return {"source": self.source, "interpolation": self.interpolation}

    def sampler(self):
        """The importance sampler of this table: binned half vectors mixed with 15 % cosine.

        Returns
        -------
        lighting.sampling.merl.MerlSampler
            One instance per model, so its per-view tables are built once (:mod:`lighting.sampling.merl`).
        """
        from ..sampling.merl import MerlSampler

        # The instances of one file's model class (model_class) share its table, so those with the same lookup
        # share one sampler and its per-view tables: a material whose parts name one file builds them once.
        shared = getattr(type(self), "_samplers", None)
        cache, key = (self.__dict__, "_sampler") if shared is None else (shared, self.interpolation)
        s = cache.get(key)
        if s is None:
            s = cache[key] = MerlSampler(self)
        return s


def _clamped(u, n):
    """Lower node and weight of a clamped linear interpolation over nodes ``0 .. n-1``."""
    u = np.clip(u, 0, n - 1)
    i0 = np.minimum(np.floor(u).astype(np.int64), n - 2)
    return i0, u - i0


def _fill_missing(rows: np.ndarray) -> np.ndarray:
    """Negative entries of each row (last axis, circular) → the nearest non-negative one; 0 if none.

    Ties go to the earlier azimuth.  Returns a new float64 array: the same as :func:`_fill_missing_reference`
    (a value is copied, so the same choice of neighbour is the same bits), each missing entry's neighbours found
    by a binary search among the good entries of the rows laid end to end, instead of a pass over three copies
    of every row.
    """
    out = np.array(rows, dtype=np.float64)
    flat = out.reshape(-1)
    n = out.shape[-1]
    ok = flat >= 0
    missing = np.flatnonzero(~ok)
    if not missing.size:
        return out
    good = np.flatnonzero(ok)
    if not good.size:
        flat[:] = 0.0
        return out
    start = missing - missing % n
    # Each missing entry's good neighbours in the rows laid end to end; where one falls in another row (or there
    # is none), the row's own last good entry one turn earlier, or its first one turn later.
    k = np.searchsorted(good, missing)
    row_first = np.searchsorted(good, start)
    row_last = np.searchsorted(good, start + n) - 1
    top = good.size - 1
    has_good = row_last >= row_first  # the row has a good entry
    first, last = good[np.minimum(row_first, top)], good[np.maximum(row_last, 0)]
    prev = np.where(k > row_first, good[np.maximum(k - 1, 0)], last - n)
    nxt = np.where(k <= row_last, good[np.minimum(k, top)], first + n)
    src = np.where(missing - prev <= nxt - missing, prev, nxt)
    src = start + (src - start) % n  # back into the row
    flat[missing] = np.where(has_good, flat[src], 0.0)
    return out


def _fill_missing_reference(rows: np.ndarray) -> np.ndarray:
    """:func:`_fill_missing`, the readable reference: each row with a missing entry searched in three copies of
    itself, so that its circular neighbours are in reach."""
    out = np.array(rows, dtype=np.float64)
    bad = out < 0
    if not bad.any():
        return out
    flat = out.reshape(-1, out.shape[-1])
    sel = np.flatnonzero(bad.reshape(flat.shape).any(axis=1))
    sub = flat[sel]
    n = sub.shape[1]
    ok = sub >= 0
    pos = np.arange(3 * n)
    ok3 = np.tile(ok, 3)  # three copies: the circular neighbours of the middle copy are in reach
    prev = np.maximum.accumulate(np.where(ok3, pos, -(4 * n)), axis=1)[:, n : 2 * n]
    nxt = np.minimum.accumulate(np.where(ok3, pos, 8 * n)[:, ::-1], axis=1)[:, ::-1][:, n : 2 * n]
    here = np.arange(n, 2 * n)
    src = np.where(here - prev <= nxt - here, prev, nxt) % n
    filled = np.take_along_axis(sub, src, axis=1)
    filled = np.where(ok.any(axis=1, keepdims=True), filled, 0.0)
    flat[sel] = np.where(ok, sub, filled)
    return out


def read_merl(path, *, interpolation: str = "nearest") -> MerlBRDF:
    """Read a MERL ``.binary`` file.

    Parameters
    ----------
    path : str or os.PathLike
        The file: 12-byte header ``90 90 180`` (little-endian int32), then ``3 · 1458000``
        little-endian float64 values, exactly ``34 992 012`` bytes.
    interpolation : {"nearest", "linear"}, optional
        The lookup of :class:`MerlBRDF`.

    Returns
    -------
    MerlBRDF

    Raises
    ------
    ValueError
        One per bad file, naming the file, the byte offset and what is allowed: a missing file, a
        directory, an unreadable file, a short or wrong header, a size other than 34 992 012 bytes,
        NaN or infinite values; or a table over the memory budget (:class:`~lighting._budget.BudgetError`).

    Notes
    -----
    The size is checked from the file system before anything is read, and the memory (about 140 MB
    at the peak: the values, the filled RGB table and one temporary) against the engine's budget
    before anything is allocated.  The values are read with one ``np.fromfile``.

    References
    ----------
    W. Matusik, H. Pfister, M. Brand, L. McMillan, "A Data-Driven Reflectance Model", SIGGRAPH 2003.

    Examples
    --------
    >>> import tempfile, os, numpy as np
    >>> p = os.path.join(tempfile.mkdtemp(), "grey.binary")
    >>> write_merl(p, np.full((3, 90, 90, 180), 0.25))
    >>> float(read_merl(p).eval((0, 0, 1), (0, 0.6, 0.8), (0, 0, 1))[1])
    0.25
    """
    if not isinstance(path, str | os.PathLike):
        raise TypeError(f"read_merl: path must be a str or os.PathLike; got {type(path).__name__}")
    name = os.fspath(path)
    interpolation = check_choice("interpolation", interpolation, _INTERPOLATIONS)
    try:
        f = open(name, "rb")  # noqa: SIM115 (closed below; the open itself is what may fail)
    except FileNotFoundError:
        raise _refuse(name, "byte 0", "no such file; allowed: an existing MERL .binary file") from None
    except IsADirectoryError:
        raise _refuse(name, "byte 0", "is a directory; allowed: a regular file") from None
    except OSError as e:
        raise _refuse(name, "byte 0", f"cannot be opened ({e.strerror}); allowed: a readable file") from None
    with f:
        try:
            st = os.fstat(f.fileno())
            if not stat.S_ISREG(st.st_mode):
                raise _refuse(name, "byte 0", "is not a regular file; allowed: a regular file")
            size = st.st_size
            if size < _HEADER:
                raise _refuse(name, f"byte {size}", f"the file ends inside the 12-byte header ({size} bytes)")
            dims = np.frombuffer(f.read(_HEADER), dtype="<i4")
            if dims.size != 3:
                raise _refuse(name, "byte 0", "the header could not be read")
            got = tuple(int(d) for d in dims)
            for at, d in enumerate(got):
                if d <= 0:
                    raise _refuse(name, f"byte {4 * at}", f"dimension {d} in the header; allowed: 90 90 180")
            if math.prod(got) != BINS:
                raise _refuse(
                    name,
                    "byte 0",
                    f"header dimensions {got} have product {math.prod(got)}; allowed: 90 90 180 ({BINS})",
                )
            if got != DIMS:
                raise _refuse(name, "byte 0", f"header dimensions {got}; allowed: 90 90 180")
            if size < _FILE_SIZE:
                raise _refuse(
                    name, f"byte {size}", f"the file is truncated: {size} bytes; a MERL file has {_FILE_SIZE}"
                )
            if size > _FILE_SIZE:
                raise _refuse(
                    name,
                    f"byte {_FILE_SIZE}",
                    f"{size - _FILE_SIZE} extra bytes after the table; a MERL file has {_FILE_SIZE}",
                )
            check_budget(f"MERL file {name!r}", 4 * 8 * 3 * BINS, what=f"{3 * BINS} values")
            raw = np.fromfile(f, dtype="<f8", count=3 * BINS)
        except OSError as e:
            raise _refuse(name, "byte 0", f"cannot be read ({e.strerror})") from None
    if raw.size != 3 * BINS:  # the file shrank between the size check and the read
        raise _refuse(
            name, f"byte {_HEADER + 8 * raw.size}", f"the file is truncated; a MERL file has {_FILE_SIZE} bytes"
        )
    finite = np.isfinite(raw)
    if not finite.all():
        at = int(np.argmin(finite))
        c, rest = divmod(at, BINS)
        i, rest = divmod(rest, DIMS[1] * DIMS[2])
        j, k = divmod(rest, DIMS[2])
        raise _refuse(
            name,
            f"byte {_HEADER + 8 * at}",
            f"value {float(raw[at])!r} (channel {'RGB'[c]}, θ_h bin {i}, θ_d bin {j}, φ_d bin {k}); "
            "allowed: finite numbers",
        )
    return MerlBRDF._from_raw(raw.astype(np.float64, copy=False).reshape(3, BINS), interpolation, name)


def write_merl(path, table) -> None:
    """Write a MERL ``.binary`` file atomically (a temporary file beside it, then ``os.replace``).

    Parameters
    ----------
    path : str or os.PathLike
        The file to write (replaced if it exists).
    table : MerlBRDF or array_like, shape (3, 90, 90, 180)
        A :class:`MerlBRDF` (its stored values are written bitwise, so read → write reproduces
        the file) or ``f_r`` in 1/sr per channel (divided by the channel scales; negative = missing).

    Raises
    ------
    ValueError
        For a table of another size or with NaN/infinite entries.

    Examples
    --------
    >>> import tempfile, os, numpy as np
    >>> p = os.path.join(tempfile.mkdtemp(), "t.binary")
    >>> write_merl(p, np.zeros((3, 90, 90, 180)))
    >>> os.path.getsize(p)
    34992012
    """
    raw = table._raw if isinstance(table, MerlBRDF) else MerlBRDF(table)._raw
    name = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(name))
    fd, tmp = tempfile.mkstemp(prefix=".merl-", suffix=".tmp", dir=folder)
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(np.asarray(DIMS, dtype="<i4").tobytes())
            np.ascontiguousarray(raw, dtype="<f8").tofile(f)
        os.replace(tmp, name)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def bin_centres(dtype=np.float64):
    """The half/difference angles of every bin centre, each of shape ``(90, 90, 180)``.

    Parameters
    ----------
    dtype : numpy float dtype, optional

    Returns
    -------
    theta_h, theta_d, phi_d : ndarray
        ``θ_h = ((i + ½)/90)² π/2``, ``θ_d = (j + ½) π/180``, ``φ_d = (k + ½) π/180``.

    Examples
    --------
    >>> th, td, pd = bin_centres()
    >>> th.shape, round(float(td[0, 1, 0]), 6)
    ((90, 90, 180), 0.02618)
    """
    i, j, k = (np.arange(n, dtype=np.float64) + 0.5 for n in DIMS)
    th = (i / DIMS[0]) ** 2 * (np.pi / 2)
    td = j * (np.pi / 2) / DIMS[1]
    pd = k * np.pi / DIMS[2]
    return tuple(a.astype(dtype) for a in np.meshgrid(th, td, pd, indexing="ij"))


def tabulate_merl(brdf: BRDF) -> np.ndarray:
    """Sample an engine BRDF at every bin centre of the MERL table.

    Parameters
    ----------
    brdf : lighting.models.base.BRDF
        Any model (isotropic; an anisotropic one is sampled at ``φ_h = 0``).

    Returns
    -------
    ndarray, shape (3, 90, 90, 180)
        ``f_r`` in 1/sr at the centres of :func:`bin_centres` (0 where ``l`` or ``v`` is within
        rounding of the horizon or below it), ready for :func:`write_merl` or :class:`MerlBRDF`.

    Notes
    -----
    Vectorised over one ``θ_h`` row block at a time (about 160 000 direction pairs) to keep the
    model's temporaries within a few hundred MB.

    Examples
    --------
    >>> from lighting.brdf import Lambert
    >>> t = tabulate_merl(Lambert(0.5))
    >>> t.shape, round(float(t[0, 10, 10, 10]), 6)
    ((3, 90, 90, 180), 0.159155)
    """
    if not isinstance(brdf, BRDF):
        raise TypeError(f"tabulate_merl: brdf must be a BRDF model; got {type(brdf).__name__}")
    th, td, pd = bin_centres()
    out = np.zeros((3, *DIMS))
    step = 10
    for s in range(0, DIMS[0], step):
        l, v = half_diff_to_dirs(th[s : s + step], 0.0, td[s : s + step], pd[s : s + step])  # noqa: E741
        valid = (l[..., 2] > _HORIZON_TOL) & (v[..., 2] > _HORIZON_TOL)
        f = brdf.eval(np.array([0.0, 0.0, 1.0]), l, v)
        out[:, s : s + step] = np.moveaxis(np.where(valid[..., None], f, 0.0), -1, 0)
    return out


def model_class(path) -> type:
    """A model class from a MERL file: read once, each instance choosing the lookup.

    What :func:`lighting.files.file_model` calls for ``.binary`` files.

    Parameters
    ----------
    path : str or os.PathLike
        The file (as :func:`read_merl`).

    Returns
    -------
    type
        A :class:`MerlBRDF` subclass with one parameter, ``interpolation`` (a choice); its instances
        share the table read here (about 70 MB: the stored values and the filled RGB table).

    Raises
    ------
    ValueError
        A bad file (:func:`read_merl`).
    """
    read = read_merl(path)

    def __init__(self, interpolation: str = "nearest"):
        self._setup(read._raw, interpolation, read.source, lut=read._lut)  # the table read once, shared

    lookup = Parameter("interpolation", "choice", "nearest", choices=_INTERPOLATIONS,
                       description="nearest bin (as the reference reader) or trilinear in bin coordinates")  # fmt: skip
    return type("MerlFileModel", (MerlBRDF,), {"parameters": (lookup,), "__init__": __init__, "_samplers": {},
                                              "__doc__": f"The measured BRDF of {read.source!r}."})  # fmt: skip


def load(path, **params) -> MerlBRDF:
    """The reader :func:`lighting.load_brdf` calls for ``.binary`` files.

    Parameters
    ----------
    path : str
        The file.
    **params
        ``interpolation`` (``"nearest"`` or ``"linear"``); nothing else.

    Returns
    -------
    MerlBRDF

    Raises
    ------
    ValueError
        For another keyword, or a bad file (:func:`read_merl`).
    """
    extra = sorted(set(params) - {"interpolation"})
    if extra:
        raise ValueError(f"MERL file {os.fspath(path)!r}: no parameter {extra[0]!r}; allowed: interpolation")
    return read_merl(path, **params)
