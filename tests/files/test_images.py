"""Image files (lighting.files.images): PNG, RGBE, PFM and NPY bytes, the checks before allocation, atomic writes.

The environment's own use of the readers (2:1, its size limits, the fuzzed files) is tested in
tests/lights/test_envfiles.py.
"""

from __future__ import annotations

import contextlib
import os
import re
import struct
import zlib

import numpy as np
import pytest

from lighting._budget import BudgetError, set_memory_budget
from lighting.files import images, png
from lighting.files.images import (
    atomic_write,
    declared_size,
    npy_bytes,
    pfm_bytes,
    png_bytes,
    read_linear,
    read_png,
    rgbe_bytes,
    write_hdr,
    write_png,
    write_temporary,
)


def _one_line(call, path, match, error=ValueError):
    with pytest.raises(error) as e:
        call(path)
    msg = str(e.value)
    assert msg.startswith(f"{path}: ") and "\n" not in msg and "; " in msg, msg
    assert re.search(match, msg), msg
    return msg


def _chunk(tag: bytes, body: bytes) -> bytes:
    return struct.pack(">I", len(body)) + tag + body + struct.pack(">I", zlib.crc32(tag + body) & 0xFFFFFFFF)


def _png(w, h, rows: bytes, *, depth=8, ctype=2) -> bytes:
    ihdr = struct.pack(">IIBBBBB", w, h, depth, ctype, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + _chunk(b"IHDR", ihdr) + _chunk(b"IDAT", zlib.compress(rows)) + _chunk(b"IEND", b"")


# ---------------------------------------------------------------- PNG
@pytest.mark.parametrize("channels", [3, 4])
def test_png_round_trip_is_exact_and_its_bytes_are_the_format(tmp_path, channels):
    rgb8 = np.random.default_rng(channels).integers(0, 256, (5, 7, channels), dtype=np.uint8)
    write_png(tmp_path / "a.png", rgb8)
    data = (tmp_path / "a.png").read_bytes()
    assert data == png_bytes(rgb8)
    # Signature, a 13-byte IHDR (7x5, 8 bits, colour type 2 or 6), one IDAT of filter-0 rows, IEND.
    assert data[:16] == b"\x89PNG\r\n\x1a\n\x00\x00\x00\x0dIHDR"
    assert struct.unpack(">IIBBBBB", data[16:29]) == (7, 5, 8, {3: 2, 4: 6}[channels], 0, 0, 0)
    assert data.endswith(_chunk(b"IEND", b""))
    rows = np.frombuffer(zlib.decompress(data[41:-16]), np.uint8).reshape(5, 1 + 7 * channels)
    assert not rows[:, 0].any() and np.array_equal(rows[:, 1:].reshape(5, 7, channels), rgb8)
    back = read_png(tmp_path / "a.png")
    assert back.dtype == np.uint8 and np.array_equal(back, rgb8) and back.flags.writeable
    assert declared_size(tmp_path / "a.png") == (5, 7)


def test_a_hand_made_png_reads_to_its_pixels(tmp_path):
    p = tmp_path / "two.png"
    p.write_bytes(_png(2, 1, bytes([0, 255, 0, 0, 1, 2, 3])))
    assert read_png(p).tolist() == [[[255, 0, 0], [1, 2, 3]]]


def test_bad_png_files_are_one_line_errors_naming_the_file(tmp_path):
    good = png_bytes(np.zeros((2, 3, 3), np.uint8))
    cases = {
        "sig.png": (b"GIF89a" + good[6:], r"not a PNG file"),
        "ihdr.png": (good[:8] + _chunk(b"tEXt", b"x") + good[8:], r"first chunk is not a 13-byte IHDR"),
        "crc.png": (good[:20] + b"\xff" + good[21:], r"IHDR chunk's CRC does not match"),
        "idatcrc.png": (good[:-14] + bytes([good[-14] ^ 1]) + good[-13:], r"chunk 'IDAT' has a CRC that does not"),
        "short.png": (good[:-12], r"ends before its IEND chunk"),
        "cut.png": (good[:-12] + struct.pack(">I", 1000) + b"tEXtabcd", r"chunk 'tEXt' is truncated"),
        "depth.png": (_png(2, 2, bytes(2 * 13), depth=16), r"bit depth 16, colour type 2.*allowed: 8-bit RGB or RGBA"),
        "grey.png": (_png(2, 2, bytes(2 * 3), ctype=0), r"colour type 0"),
        "filter.png": (_png(2, 2, bytes(7) + bytes([1]) + bytes(6)), r"row 1 uses PNG filter 1"),
        "less.png": (_png(2, 2, bytes(7)), r"holds less than 2x2 pixels"),
        "more.png": (_png(2, 2, bytes(15)), r"holds more than 2x2 pixels"),
        "zero.png": (_png(0, 2, b""), r"image size 0x2 is empty"),
    }
    for name, (data, match) in cases.items():
        (tmp_path / name).write_bytes(data)
        _one_line(read_png, tmp_path / name, match)
    _one_line(read_png, tmp_path / "none.png", r"no such file; allowed: an existing PNG image")
    _one_line(read_png, tmp_path, r"is a directory")


def test_png_size_is_checked_before_the_pixels_are_decompressed(tmp_path, monkeypatch):
    # A 100-byte file declaring 70000 x 1 pixels, and a 1 x 1 image whose stream inflates to 10 MB.
    big = tmp_path / "wide.png"
    big.write_bytes(_png(70000, 1, b""))
    _one_line(read_png, big, r"image size 70000x1 is too large; allowed: at most 65536x65536")
    bomb = tmp_path / "bomb.png"
    bomb.write_bytes(_png(1, 1, bytes(10_000_000)))
    assert bomb.stat().st_size < 20_000
    seen = []
    real = zlib.decompressobj

    class Recording:
        def __init__(self):
            self.z = real()

        def decompress(self, data, max_length=0):
            out = self.z.decompress(data, max_length)
            seen.append((max_length, len(out)))
            return out

        @property
        def eof(self):
            return self.z.eof

    monkeypatch.setattr(png.zlib, "decompressobj", Recording)  # the PNG reader's zlib
    _one_line(read_png, bomb, r"holds more than 1x1 pixels")
    assert seen == [(5, 5)]  # one row of 1 + 3 bytes, plus one byte to see that more follows
    monkeypatch.undo()
    ok = tmp_path / "ok.png"
    write_png(ok, np.zeros((64, 128, 3), np.uint8))
    charged = 64 * 128 * (2 * 3 + 1)  # the rows (a filter byte and 3 a pixel) and the pixels' copy, at most
    previous = set_memory_budget(charged - 1)
    try:
        with pytest.raises(BudgetError, match=r"PNG image '.*ok\.png' needs about .* \(a 128x64 image and its"):
            read_png(ok)
        set_memory_budget(charged)
        assert read_png(ok).shape == (64, 128, 3)
    finally:
        set_memory_budget(previous)
    # The largest side's image is refused by the default budget, not by a failed allocation.
    wide = tmp_path / "huge.png"
    wide.write_bytes(_png(65536, 65536, b""))
    with pytest.raises(BudgetError, match="65536x65536"):
        read_png(wide)


# ---------------------------------------------------------------- linear formats
def test_pfm_bytes_store_rows_bottom_up_little_endian_and_read_back_exactly(tmp_path):
    img = np.arange(2 * 3 * 3, dtype=np.float32).reshape(2, 3, 3) / 4
    data = pfm_bytes(img)
    assert data.startswith(b"PF\n3 2\n-1.0\n")
    body = np.frombuffer(data[12:], "<f4").reshape(2, 3, 3)
    assert len(data) == 12 + 2 * 3 * 3 * 4 and np.array_equal(body[::-1], img)
    (tmp_path / "a.pfm").write_bytes(data)
    # Not 2:1: a plain image file, read as it is; an environment would refuse it.
    back = read_linear(tmp_path / "a.pfm")
    assert back.dtype == np.float32 and np.array_equal(back, img)
    as_environment = lambda p: read_linear(p, aspect=2, shape="w = 2 h")  # noqa: E731
    _one_line(as_environment, tmp_path / "a.pfm", r"3x2 is not 2:1; allowed: w = 2 h")
    narrow = lambda p: read_linear(p, max_width=2)  # noqa: E731
    _one_line(narrow, tmp_path / "a.pfm", r"3x2 is too large; allowed: at most 2x65536")
    assert declared_size(tmp_path / "a.pfm") == (2, 3)


def test_npy_bytes_are_numpys_and_read_back_as_float32(tmp_path):
    img = np.linspace(0, 3, 5 * 4 * 3).reshape(5, 4, 3)
    data = npy_bytes(img)
    np.save(tmp_path / "ref.npy", img, allow_pickle=False)
    assert data == (tmp_path / "ref.npy").read_bytes()
    assert np.array_equal(read_linear(tmp_path / "ref.npy"), img.astype(np.float32))
    assert declared_size(tmp_path / "ref.npy") == (5, 4)


def test_rgbe_bytes_of_a_known_pixel(tmp_path):
    # 0.75 = 0.75 x 2^0: mantissa 192, exponent 128; 0.375 half of it: 96; 0 stays 0.
    data = rgbe_bytes(np.array([[[0.75, 0.375, 0.0]]]), rle=False)
    assert data == b"#?RADIANCE\n# lighting.lights.envfiles\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 1\n" + bytes(
        [192, 96, 0, 128]
    )
    write_hdr(tmp_path / "p.hdr", np.array([[[0.75, 0.375, 0.0]]]), rle=False)
    assert (tmp_path / "p.hdr").read_bytes() == data
    assert read_linear(tmp_path / "p.hdr").tolist() == [[[192.5 / 256, 96.5 / 256, 0.5 / 256]]]
    assert declared_size(tmp_path / "p.hdr") == (1, 1)
    assert declared_size(tmp_path / "missing.hdr") is None and declared_size(tmp_path / "x.gif") is None


def test_unknown_extensions_and_non_paths_are_refused(tmp_path):
    _one_line(read_linear, tmp_path / "a.gif", r"unknown extension '\.gif'; allowed: \.hdr, \.pic, \.pfm, \.npy, \.exr")
    with pytest.raises(TypeError, match=r"path must be a str or os.PathLike; got int"):
        read_linear(3)


# ---------------------------------------------------------------- atomic writing
def _library_writes(path, data):
    with open(path, "wb") as f:
        f.write(data)


def test_atomic_write_flushes_renames_and_keeps_modes(tmp_path, monkeypatch):
    synced = []
    real_fsync = os.fsync
    monkeypatch.setattr(images.os, "fsync", lambda fd: synced.append(fd) or real_fsync(fd))
    old = os.umask(0o027)
    try:
        atomic_write(tmp_path / "new.bin", b"abc")
        atomic_write(tmp_path / "lib.bin", lambda p: _library_writes(p, b"written by a library"))
    finally:
        os.umask(old)
    assert (tmp_path / "new.bin").read_bytes() == b"abc" and (tmp_path / "new.bin").stat().st_mode & 0o777 == 0o640
    assert (tmp_path / "lib.bin").read_bytes() == b"written by a library"
    assert len(synced) == 2  # both flushed to disk before the rename
    os.chmod(tmp_path / "new.bin", 0o600)
    atomic_write(tmp_path / "new.bin", b"de")
    assert (tmp_path / "new.bin").read_bytes() == b"de" and (tmp_path / "new.bin").stat().st_mode & 0o777 == 0o600
    # Through a symbolic link: the file it points to is replaced, the link stays.
    os.symlink(tmp_path / "new.bin", tmp_path / "link.bin")
    atomic_write(tmp_path / "link.bin", b"via link")
    assert os.path.islink(tmp_path / "link.bin") and (tmp_path / "new.bin").read_bytes() == b"via link"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["lib.bin", "link.bin", "new.bin"]


@pytest.mark.parametrize("error", [RuntimeError, KeyboardInterrupt])
def test_a_failed_write_leaves_no_temporary_file_and_the_old_file(tmp_path, monkeypatch, error):
    (tmp_path / "a.png").write_bytes(b"old")

    def fail(path):
        _library_writes(path, b"half")
        raise error("stop")

    with pytest.raises(error):
        atomic_write(tmp_path / "a.png", fail)
    monkeypatch.setattr(images.os, "replace", lambda *a: (_ for _ in ()).throw(OSError(28, "No space left")))
    with pytest.raises(OSError, match="No space left"):
        write_png(tmp_path / "a.png", np.zeros((1, 1, 3), np.uint8))
    assert [p.name for p in tmp_path.iterdir()] == ["a.png"] and (tmp_path / "a.png").read_bytes() == b"old"


def test_write_temporary_creates_its_file_inside_the_guard(tmp_path):
    events = []

    @contextlib.contextmanager
    def guard():
        events.append(("enter", sorted(os.listdir(tmp_path))))
        yield
        events.append(("exit", sorted(os.listdir(tmp_path))))

    tmp, target = write_temporary(tmp_path / "x.pfm", b"data", guard=guard)
    name = os.path.basename(tmp)
    assert events == [("enter", []), ("exit", [name])]
    assert name.startswith(".x.pfm.") and name.endswith(".part") and target == str(tmp_path / "x.pfm")
    with open(tmp, "rb") as f:
        assert f.read() == b"data" and (os.stat(tmp).st_mode & 0o777) == images.file_mode(target)
