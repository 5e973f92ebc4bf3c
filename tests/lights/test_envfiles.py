"""Environment files (RGBE, PFM, NPY, EXR), rotated/scaled environments and the one loader."""

import math
import os
import re
import struct
import sys

import numpy as np
import pytest
from chi2 import chi2_sf

from explorer.output import encode_image
from lighting import Lambert
from lighting._budget import BudgetError, set_memory_budget
from lighting.files import rgbe
from lighting.integrate import outgoing_radiance
from lighting.lights.envfiles import (
    TransformedEnvironment,
    load_environment,
    read_environment_image,
    write_hdr,
)
from lighting.lights.environment import (
    ConstantEnvironment,
    FunctionEnvironment,
    LatLongEnvironment,
    SmallPatchEnvironment,
    latlong_angles,
)


def _rand_dirs(k, seed):
    d = np.random.default_rng(seed).normal(size=(k, 3))
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def _hdr_header(h, w, extra=b"", res=None):
    res = res if res is not None else f"-Y {h} +X {w}".encode()
    return b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n" + extra + b"\n" + res + b"\n"


def _hdr_image(h=16, w=32, seed=0):
    """Radiance over twelve decades with flat runs (the RLE path) and some black pixels."""
    rng = np.random.default_rng(seed)
    img = 10.0 ** rng.uniform(-6, 6, (h, w, 1)) * rng.uniform(0, 1, (h, w, 3))
    img[:, w // 4 : w // 2] = (0.25, 0.5, 1.0)  # runs
    img[0, :3] = 0.0
    return img


# ---------------------------------------------------------------- RGBE
@pytest.mark.parametrize("rle", [True, False])
def test_rgbe_round_trip_within_eight_bits_of_the_brightest_channel(tmp_path, rle):
    img = _hdr_image()
    p = tmp_path / "e.hdr"
    write_hdr(p, img, rle=rle)
    back = read_environment_image(p)
    assert back.dtype == np.float32 and back.shape == img.shape
    err = np.abs(back.astype(np.float64) - img)
    bound = 2.0**-8 * img.max(axis=-1, keepdims=True) * (1 + 1e-6)
    assert np.all(err <= bound)
    # Black stays exactly black; the centred mantissa is not biased: errors of both signs.
    assert np.all(back[0, :3] == 0)
    d = back - img
    assert (d > 0).any() and (d < 0).any()


def test_rle_and_flat_files_decode_to_the_same_image(tmp_path):
    img = _hdr_image(32, 64, seed=3)
    write_hdr(tmp_path / "rle.hdr", img, rle=True)
    write_hdr(tmp_path / "flat.hdr", img, rle=False)
    a, b = read_environment_image(tmp_path / "rle.hdr"), read_environment_image(tmp_path / "flat.hdr")
    np.testing.assert_array_equal(a, b)
    # The flat file holds 4 bytes per pixel; the runs make the RLE file smaller.
    header = len(_hdr_header(32, 64).replace(b"FORMAT", b"# lighting.lights.envfiles\nFORMAT"))
    assert os.path.getsize(tmp_path / "flat.hdr") == header + 32 * 64 * 4
    assert os.path.getsize(tmp_path / "rle.hdr") < os.path.getsize(tmp_path / "flat.hdr")


def test_hand_made_flat_2x4_file_decodes_to_known_values(tmp_path):
    # Radiance's colr_color: (c + 1/2) 2^(e - 136); e = 0 is black.
    pixels = [
        (128, 64, 0, 129), (0, 0, 0, 0), (255, 255, 255, 136), (100, 200, 50, 120),
        (2, 4, 8, 140), (16, 32, 64, 128), (0, 0, 0, 0), (200, 100, 50, 130),
    ]  # fmt: skip
    p = tmp_path / "known.hdr"
    p.write_bytes(_hdr_header(2, 4) + bytes(b for px in pixels for b in px))
    got = read_environment_image(p)
    want = np.array(
        [
            [[1.00390625, 0.50390625, 0.00390625], [0, 0, 0], [255.5, 255.5, 255.5],
             [100.5 / 65536, 200.5 / 65536, 50.5 / 65536]],
            [[40.0, 72.0, 136.0], [16.5 / 256, 32.5 / 256, 64.5 / 256], [0, 0, 0],
             [200.5 / 64, 100.5 / 64, 50.5 / 64]],
        ]
    )  # fmt: skip
    np.testing.assert_array_equal(got, want.astype(np.float32))


def test_hand_made_rle_scanlines_decode_to_known_values(tmp_path):
    # Width 16: one scanline per row, each channel a run and/or a literal dump.
    w, h = 16, 8
    body = b""
    for y in range(h):
        body += bytes([2, 2, 0, w])
        body += bytes([128 + 16, 64 + y])  # red: one run of 16
        body += bytes([16]) + bytes(range(16))  # green: a dump of 16 literals
        body += bytes([128 + 10, 32, 6, 1, 2, 3, 4, 5, 6])  # blue: run of 10, dump of 6
        body += bytes([128 + 16, 129])  # exponent 129: values (c + 1/2) / 128
    p = tmp_path / "rle.hdr"
    p.write_bytes(_hdr_header(h, w) + body)
    got = read_environment_image(p).astype(np.float64)
    y = np.arange(h)[:, None]
    np.testing.assert_array_equal(got[..., 0], np.broadcast_to((64 + y + 0.5) / 128, (h, w)))
    np.testing.assert_array_equal(got[..., 1], np.broadcast_to((np.arange(16) + 0.5) / 128, (h, w)))
    blue = np.array([32] * 10 + [1, 2, 3, 4, 5, 6]) + 0.5
    np.testing.assert_array_equal(got[..., 2], np.broadcast_to(blue / 128, (h, w)))


def test_exposure_lines_divide_the_pixels_by_their_product(tmp_path):
    img = _hdr_image(4, 8, seed=1)
    write_hdr(tmp_path / "plain.hdr", img)
    data = (tmp_path / "plain.hdr").read_bytes()
    exposed = data.replace(b"FORMAT=", b"EXPOSURE=2.5\nEXPOSURE= 0.8\nFORMAT=", 1)
    (tmp_path / "exposed.hdr").write_bytes(exposed)
    plain = read_environment_image(tmp_path / "plain.hdr").astype(np.float64)
    got = read_environment_image(tmp_path / "exposed.hdr").astype(np.float64)
    np.testing.assert_allclose(got, plain / 2.0, rtol=1e-7)


def test_plus_y_and_minus_x_orientations_are_turned_back(tmp_path):
    img = _hdr_image(4, 8, seed=2)
    write_hdr(tmp_path / "a.hdr", img, rle=False)
    data = (tmp_path / "a.hdr").read_bytes()
    head, pixels = data[: data.index(b"-Y 4 +X 8\n")], data[data.index(b"-Y 4 +X 8\n") + 10 :]
    px = np.frombuffer(pixels, np.uint8).reshape(4, 8, 4)
    ref = read_environment_image(tmp_path / "a.hdr")
    (tmp_path / "b.hdr").write_bytes(head + b"+Y 4 +X 8\n" + px[::-1].tobytes())
    (tmp_path / "c.hdr").write_bytes(head + b"-Y 4 -X 8\n" + px[:, ::-1].tobytes())
    np.testing.assert_array_equal(read_environment_image(tmp_path / "b.hdr"), ref)
    np.testing.assert_array_equal(read_environment_image(tmp_path / "c.hdr"), ref)


def test_write_hdr_refuses_bad_images_and_writes_atomically(tmp_path):
    for bad in (np.full((2, 4, 3), np.nan), -np.ones((2, 4, 3)), np.full((2, 4, 3), 2.0**127), np.ones((2, 4))):
        with pytest.raises(ValueError, match="image must be"):
            write_hdr(tmp_path / "x.hdr", bad)
    assert not list(tmp_path.iterdir())  # nothing half-written
    write_hdr(tmp_path / "x.hdr", np.ones((2, 4, 3)))
    assert [f.name for f in tmp_path.iterdir()] == ["x.hdr"]


# ---------------------------------------------------------------- PFM and NPY
def test_pfm_rows_are_stored_bottom_up_and_read_top_down(tmp_path):
    img = np.zeros((4, 8, 3), np.float32)
    img[0] = (4.0, 2.0, 1.0)  # a bright top row (the zenith)
    p = tmp_path / "sky.pfm"
    p.write_bytes(encode_image("pfm", linear=img))  # the command line's writer (little-endian)
    got = read_environment_image(p)
    np.testing.assert_array_equal(got, img)
    # Big-endian (positive scale) and grey ("Pf") files, written by hand.
    grey = np.arange(32, dtype=np.float32).reshape(4, 8)
    (tmp_path / "be.pfm").write_bytes(b"Pf\n8 4\n1.0\n" + grey[::-1].astype(">f4").tobytes())
    got = read_environment_image(tmp_path / "be.pfm")
    np.testing.assert_array_equal(got, np.repeat(grey[..., None], 3, axis=-1))


def test_npy_grey_rgb_fortran_and_integer_arrays(tmp_path):
    rgb = np.random.default_rng(0).random((4, 8, 3))
    np.save(tmp_path / "a.npy", rgb)
    np.save(tmp_path / "f.npy", np.asfortranarray(rgb))
    np.save(tmp_path / "g.npy", rgb[..., 1])
    np.save(tmp_path / "i.npy", np.arange(32, dtype=np.int16).reshape(4, 8))
    np.testing.assert_array_equal(read_environment_image(tmp_path / "a.npy"), rgb.astype(np.float32))
    np.testing.assert_array_equal(read_environment_image(tmp_path / "f.npy"), rgb.astype(np.float32))
    np.testing.assert_array_equal(read_environment_image(tmp_path / "g.npy")[..., 2], rgb[..., 1].astype(np.float32))
    assert read_environment_image(tmp_path / "i.npy")[3, 7].tolist() == [31.0, 31.0, 31.0]


@pytest.mark.parametrize(
    "value, word", [(np.nan, "NaN"), (-1.0, "negative"), (np.inf, "infinite"), (1e300, "beyond float32")]
)
def test_bad_radiance_is_refused_naming_the_pixel(tmp_path, value, word):
    img = np.ones((4, 8, 3))
    img[2, 5, 1] = value
    p = tmp_path / "bad.npy"
    np.save(p, img)
    with pytest.raises(ValueError) as e:
        read_environment_image(p)
    msg = str(e.value)
    assert msg.startswith(f"{p}: ") and "row 2, column 5" in msg and word in msg and "\n" not in msg


def test_exposure_overflowing_float32_is_refused(tmp_path):
    write_hdr(tmp_path / "a.hdr", np.full((2, 4, 3), 1e38))
    data = (tmp_path / "a.hdr").read_bytes().replace(b"FORMAT=", b"EXPOSURE=1e-3\nFORMAT=")
    (tmp_path / "b.hdr").write_bytes(data)
    with pytest.raises(ValueError, match=r"radiance 1\.0\d*e\+41 \(beyond float32\) at row 0, column 0"):
        read_environment_image(tmp_path / "b.hdr")


# ---------------------------------------------------------------- refusals
def _one_line_error(path, match):
    with pytest.raises(ValueError) as e:
        read_environment_image(path)
    msg = str(e.value)
    assert msg.startswith(f"{path}: ") and "\n" not in msg and "; " in msg, msg
    assert re.search(match, msg), msg
    return msg


@pytest.mark.parametrize(
    "name, data, match",
    [
        ("wide.hdr", _hdr_header(2, 8) + bytes(64), r"8x2 is not 2:1; allowed: a latitude-longitude image"),
        ("zero.hdr", _hdr_header(0, 0), r"0x0 is empty"),
        ("huge.hdr", _hdr_header(100000, 200000), r"too large; allowed: at most 16384x8192"),
        ("garbage.hdr", b"GIF89a\x00\x01", r"not a Radiance file"),
        ("noend.hdr", b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n", r"header does not end"),
        ("xyze.hdr", b"#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 2 +X 4\n", r"line 2: FORMAT='32-bit_rle_xyze'"),
        ("exp.hdr", _hdr_header(2, 4, b"EXPOSURE=-1\n"), r"EXPOSURE= a finite number > 0"),
        ("xmajor.hdr", _hdr_header(2, 4, res=b"+X 4 -Y 2"), r"resolution line '\+X 4 -Y 2'"),
        ("trunc.hdr", _hdr_header(2, 4) + bytes([5, 5, 5, 130]) * 5, r"ends inside scanline 1"),
        ("extra.hdr", _hdr_header(2, 4) + bytes([5, 5, 5, 130]) * 9, r"4 bytes after the last scanline"),
        ("old.hdr", _hdr_header(2, 4) + bytes([5, 5, 5, 130, 1, 1, 1, 3]) * 4, r"old-style run-length"),
        ("run.hdr", _hdr_header(4, 8) + bytes([2, 2, 0, 8, 128 + 9, 7]), r"scanline 0: a run overruns"),
        ("zero_run.hdr", _hdr_header(4, 8) + bytes([2, 2, 0, 8, 0]), r"scanline 0: bad run length 0"),
        ("width.hdr", _hdr_header(4, 8) + bytes([2, 2, 0, 9]) + bytes(100), r"header for width 9"),
        ("a.pfm", b"P6\n4 2\n255\n", r"not a PFM header"),
        ("scale.pfm", b"PF\n4 2\nnan\n" + bytes(96), r"scale 'nan'"),
        ("short.pfm", b"PF\n4 2\n-1\n" + bytes(95), r"truncated: 95 bytes"),
        ("long.pfm", b"PF\n4 2\n-1\n" + bytes(97), r"1 extra bytes"),
        ("square.pfm", b"PF\n4 4\n-1\n" + bytes(192), r"4x4 is not 2:1"),
        ("a.npy", b"\x93NUMPY\x01\x00garbage", r"not a NumPy \.npy file"),
        ("sky.png", b"\x89PNG", r"unknown extension '\.png'; allowed: \.hdr, \.pic, \.pfm, \.npy, \.exr"),
    ],
)
def test_malformed_files_are_one_line_errors(tmp_path, name, data, match):
    p = tmp_path / name
    p.write_bytes(data)
    _one_line_error(p, match)


def test_npy_shapes_dtypes_truncation(tmp_path):
    np.save(tmp_path / "s.npy", np.zeros((4, 8, 4)))
    _one_line_error(tmp_path / "s.npy", r"shape \(4, 8, 4\); allowed: a real array of shape \(H, W, 3\)")
    np.save(tmp_path / "c.npy", np.zeros((4, 8, 3), complex))
    _one_line_error(tmp_path / "c.npy", r"dtype complex128")
    np.save(tmp_path / "o.npy", np.array([[None] * 8] * 4, dtype=object), allow_pickle=True)
    _one_line_error(tmp_path / "o.npy", r"dtype object")
    np.save(tmp_path / "t.npy", np.zeros((4, 8, 3)))
    data = (tmp_path / "t.npy").read_bytes()
    (tmp_path / "t.npy").write_bytes(data[:-8])
    _one_line_error(tmp_path / "t.npy", r"truncated")


def test_missing_directory_and_fifo_are_refused_without_waiting(tmp_path):
    _one_line_error(tmp_path / "none.hdr", "no such file")
    (tmp_path / "dir.hdr").mkdir()
    _one_line_error(tmp_path / "dir.hdr", "is a directory")
    os.mkfifo(tmp_path / "pipe.hdr")  # opening it for reading would block: refused from its stat
    _one_line_error(tmp_path / "pipe.hdr", "not a regular file")


def test_exr_without_openexr_names_the_package(tmp_path, monkeypatch):
    import builtins

    real_import = builtins.__import__

    def no_exr(name, *args, **kwargs):
        if name in ("OpenEXR", "Imath"):
            raise ImportError(name)
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_exr)
    p = tmp_path / "sky.exr"
    p.write_bytes(b"v/1\x01")
    _one_line_error(p, r"needs the OpenEXR Python package, which is not installed; allowed here: \.hdr")


def _fake_openexr(monkeypatch, planes, channels="RGB"):
    """Stand-ins for the OpenEXR and Imath modules (legacy API) serving ``planes`` (H, W, C) float32."""
    import types

    h, w = planes.shape[:2]
    box = types.SimpleNamespace(min=types.SimpleNamespace(x=0, y=0), max=types.SimpleNamespace(x=w - 1, y=h - 1))

    class InputFile:
        def __init__(self, name):
            self.closed = False

        def header(self):
            return {"dataWindow": box, "channels": dict.fromkeys(channels)}

        def channel(self, c, pt):
            assert pt == "FLOAT"
            return np.ascontiguousarray(planes[..., channels.index(c)], dtype=np.float32).tobytes()

        def close(self):
            self.closed = True

    exr = types.ModuleType("OpenEXR")
    exr.InputFile = InputFile
    imath = types.ModuleType("Imath")
    imath.PixelType = type("PixelType", (), {"FLOAT": "FLOAT", "__new__": lambda cls, v: v})
    monkeypatch.setitem(sys.modules, "OpenEXR", exr)
    monkeypatch.setitem(sys.modules, "Imath", imath)


def test_exr_channels_are_assembled_and_checked(tmp_path, monkeypatch):
    rgb = np.random.default_rng(1).random((4, 8, 3)).astype(np.float32)
    p = tmp_path / "sky.exr"
    p.write_bytes(b"\x76\x2f\x31\x01" + bytes(16))
    _fake_openexr(monkeypatch, rgb)
    np.testing.assert_array_equal(read_environment_image(p), rgb)
    _fake_openexr(monkeypatch, rgb[..., :1], channels="Y")
    np.testing.assert_array_equal(read_environment_image(p), np.repeat(rgb[..., :1], 3, axis=-1))
    _fake_openexr(monkeypatch, rgb[..., :2], channels="RA")
    _one_line_error(p, r"channels \['A', 'R'\]; allowed: R, G, B \(or Y\)")
    _fake_openexr(monkeypatch, rgb[:, :4])
    _one_line_error(p, r"4x4 is not 2:1")
    bad = rgb.copy()
    bad[1, 2, 0] = -0.5
    _fake_openexr(monkeypatch, bad)
    _one_line_error(p, r"radiance -0\.5 \(negative\) at row 1, column 2")
    (tmp_path / "fake.exr").write_bytes(b"#?RADIANCE\n")
    _one_line_error(tmp_path / "fake.exr", r"not an OpenEXR file")


def test_budget_is_charged_before_the_pixels_are_decoded(tmp_path, monkeypatch):
    decoded = []
    real = rgbe._rgbe_scanlines  # the RGBE decoder (lighting.files.rgbe)
    monkeypatch.setattr(rgbe, "_rgbe_scanlines", lambda *a: decoded.append(a[2:]) or real(*a))
    # A 34-byte file declaring the largest allowed image: refused by the default budget, unread.
    p = tmp_path / "big.hdr"
    p.write_bytes(_hdr_header(8192, 16384))
    with pytest.raises(BudgetError, match="16384x8192"):
        read_environment_image(p)
    # A valid small image under a budget too small for it.
    write_hdr(tmp_path / "ok.hdr", np.ones((64, 128, 3)))
    previous = set_memory_budget(64 * 128 * 20)
    try:
        with pytest.raises(BudgetError, match="128x64"):
            read_environment_image(tmp_path / "ok.hdr")
    finally:
        set_memory_budget(previous)
    assert decoded == []
    assert read_environment_image(tmp_path / "ok.hdr").shape == (64, 128, 3) and decoded == [(64, 128)]


def _seeds(tmp_path):
    img = _hdr_image(8, 16, seed=9)
    write_hdr(tmp_path / "s.hdr", img, rle=True)
    write_hdr(tmp_path / "s2.hdr", img, rle=False)
    np.save(tmp_path / "s.npy", img.astype(np.float32))
    return {
        ".hdr": (tmp_path / "s.hdr").read_bytes(),
        ".pic": (tmp_path / "s2.hdr").read_bytes(),
        ".pfm": encode_image("pfm", linear=img.astype(np.float32)),
        ".npy": (tmp_path / "s.npy").read_bytes(),
    }


def test_fuzz_mutated_and_truncated_files_only_raise_one_line_value_errors(tmp_path):
    rng = np.random.default_rng(2024)
    seeds = _seeds(tmp_path)
    outcomes = {"read": 0, "refused": 0}
    for k in range(400):
        ext = list(seeds)[k % 4]
        data = bytearray(seeds[ext])
        kind = rng.integers(5)
        if kind == 0:  # truncate
            data = data[: rng.integers(0, len(data))]
        elif kind == 1:  # flip a few bytes
            for _ in range(rng.integers(1, 6)):
                data[rng.integers(len(data))] = rng.integers(256)
        elif kind == 2:  # flip bytes in the header
            for _ in range(rng.integers(1, 4)):
                data[rng.integers(min(len(data), 80))] = rng.integers(256)
        elif kind == 3:  # insert or delete a block
            at = rng.integers(len(data))
            if rng.random() < 0.5:
                data[at:at] = rng.integers(0, 256, rng.integers(1, 40)).astype(np.uint8).tobytes()
            else:
                del data[at : at + rng.integers(1, 40)]
        else:  # a declared size rewritten to something else
            size = str(int(rng.choice([0, 1, 7, 8, 99999, 10**9]))).encode()
            data = bytearray(re.sub(rb"\d+", size, bytes(data), count=1))
        p = tmp_path / f"f{k}{ext}"
        p.write_bytes(bytes(data))
        try:
            img = read_environment_image(p)
        except ValueError as e:
            msg = str(e)
            assert msg.startswith(f"{p}: ") and "\n" not in msg, msg
            outcomes["refused"] += 1
        else:
            assert img.dtype == np.float32 and img.shape[1] == 2 * img.shape[0] and img.shape[2] == 3
            assert np.all(np.isfinite(img)) and np.all(img >= 0)
            outcomes["read"] += 1
    # Both outcomes occur: the mutations reach the decoders, not only the signature checks.
    assert outcomes["refused"] > 150 and outcomes["read"] > 20, outcomes


# ---------------------------------------------------------------- TransformedEnvironment
def test_rotation_by_90_degrees_moves_phi_0_to_phi_90():
    spot = SmallPatchEnvironment((1.0, 0.0, 0.0), 0.05, 3.0)
    env = TransformedEnvironment(spot, rotation=90.0)
    np.testing.assert_array_equal(env.radiance([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0]]), [[3.0] * 3, [0.0] * 3])
    # The cap's support turns with it (exactly: cos 90° = 0).
    np.testing.assert_array_equal(env.support[0], [0.0, 1.0, 0.0])
    assert env.support[1] == spot.half_angle
    # An image: a bright column at φ = 0 (the image's centre) appears at φ = 90°.
    img = np.zeros((8, 16, 3))
    img[:, 7] = img[:, 8] = 1.0
    env = TransformedEnvironment(LatLongEnvironment(img), rotation=90.0)
    assert env.radiance([0.0, 1.0, 0.0])[0] == 1.0 and env.radiance([1.0, 0.0, 0.0])[0] == 0.0
    np.testing.assert_allclose(env.to_base([[0.0, 1.0, 0.5]]), [[1.0, 0.0, 0.5]], atol=0)
    np.testing.assert_allclose(env.from_base(env.to_base(_rand_dirs(50, 1))), _rand_dirs(50, 1), atol=1e-15)


def test_intensity_scales_per_channel_and_keeps_the_density():
    base = FunctionEnvironment(lambda d: 1.0 + d[..., 2])
    env = TransformedEnvironment(base, intensity=(1.0, 2.0, 0.5), rotation=33.0)
    d = _rand_dirs(100, 2)
    np.testing.assert_allclose(env.radiance(d), base.radiance(env.to_base(d)) * [1.0, 2.0, 0.5], rtol=1e-15)
    assert env.radiance(d.astype(np.float32)).dtype == np.float32
    assert TransformedEnvironment(base, intensity=3.0).intensity == 3.0
    np.testing.assert_array_equal(env.pdf(d), base.pdf(d))  # uniform either way
    for bad, name in ((-1.0, "intensity"), ((1, np.nan, 1), "intensity")):
        with pytest.raises(ValueError, match=name):
            TransformedEnvironment(base, intensity=bad)
    with pytest.raises(ValueError, match="rotation"):
        TransformedEnvironment(base, rotation=np.inf)
    with pytest.raises(TypeError, match="base must be an Environment"):
        TransformedEnvironment(lambda d: d)


def test_rotated_image_sampling_is_consistent_with_its_density():
    rng = np.random.default_rng(11)
    img = rng.random((6, 12, 3)) ** 3
    base = LatLongEnvironment(img)
    env = TransformedEnvironment(base, intensity=2.0, rotation=37.0)
    d, p = env.sample(rng.random((60000, 2)))
    np.testing.assert_allclose(np.linalg.norm(d, axis=-1), 1.0, atol=1e-12)
    np.testing.assert_allclose(env.pdf(d), p, rtol=1e-12)
    # The density integrates to one: Gauss–Legendre in z (nodes inside each half row of pixels, where the
    # density is linear in z) times a fine midpoint rule in φ.
    c = np.cos(np.linspace(0, math.pi, 13))
    x, wx = np.polynomial.legendre.leggauss(4)
    z = (0.5 * (c[:-1, None] + c[1:, None]) + 0.5 * (c[:-1, None] - c[1:, None]) * x).ravel()
    wz = (0.5 * (c[:-1, None] - c[1:, None]) * wx).ravel()
    phi = (np.arange(4320) + 0.5) * (2 * math.pi / 4320)
    r = np.sqrt(1 - z * z)
    grid = np.stack(np.broadcast_arrays(r[:, None] * np.cos(phi), r[:, None] * np.sin(phi), z[:, None]), axis=-1)
    total = float(np.sum(env.pdf(grid) * wz[:, None]) * (2 * math.pi / 4320))
    assert total == pytest.approx(1.0, abs=2e-3)
    # χ² of the samples over the base's pixels (turned back into the base frame).
    b = env.to_base(d)
    i = np.minimum((np.arccos(np.clip(b[:, 2], -1, 1)) / math.pi * 6).astype(int), 5)
    j = np.minimum((latlong_angles(b)[1] / (2 * math.pi) * 12).astype(int), 11)
    counts = np.bincount(i * 12 + j, minlength=72)
    expected = 60000 * base._pixel_probabilities().ravel()
    keep = expected >= 5
    chi2 = np.sum((counts[keep] - expected[keep]) ** 2 / expected[keep])
    assert chi2_sf(chi2, keep.sum() - 1) > 1e-3


def test_rotation_by_one_column_equals_rolling_the_image():
    rng = np.random.default_rng(4)
    h, w = 16, 32
    img = 0.2 + rng.random((h, w, 3))
    rotated = TransformedEnvironment(LatLongEnvironment(img), rotation=360.0 / w)
    # Turning toward +φ moves the picture one column left: the columns run against φ.
    rolled = LatLongEnvironment(np.roll(img, -1, axis=1))
    d = _rand_dirs(2000, 5)
    np.testing.assert_allclose(rotated.radiance(d), rolled.radiance(d), rtol=0, atol=1e-12)
    n = _rand_dirs(6, 6)
    v = n + 0.3 * _rand_dirs(6, 7)
    for method in ("quadrature", "sh"):
        a = outgoing_radiance(Lambert(0.8), rotated, n, v, method=method, samples=4096)
        b = outgoing_radiance(Lambert(0.8), rolled, n, v, method=method, samples=4096)
        np.testing.assert_allclose(a, b, rtol=1e-6)


# ---------------------------------------------------------------- load_environment
def test_load_environment_from_every_kind_of_source(tmp_path):
    img = np.ones((4, 8, 3))
    img[:2] = 3.0
    np.save(tmp_path / "sky.npy", img)
    env = load_environment(tmp_path / "sky.npy")
    assert isinstance(env, LatLongEnvironment) and env.image.shape == (4, 8, 3)
    small = load_environment(str(tmp_path / "sky.npy"), height=2)
    np.testing.assert_array_equal(small.image[..., 0], [[3.0] * 4, [1.0] * 4])
    with pytest.raises(ValueError, match="height 3 does not divide the image's 4 rows"):
        load_environment(tmp_path / "sky.npy", height=3)
    assert isinstance(load_environment("daylight"), FunctionEnvironment)
    tab = load_environment("Band_Limited", height=16)
    assert isinstance(tab, LatLongEnvironment) and tab.image.shape == (16, 32, 3)
    assert isinstance(load_environment(0.5), ConstantEnvironment)
    t = load_environment((1.0, 0.5, 0.25), intensity=2.0, rotation=10.0)
    assert isinstance(t, TransformedEnvironment) and t.rotation == 10.0
    np.testing.assert_array_equal(t.radiance([0.0, 0.0, 1.0]), [2.0, 1.0, 0.5])
    with pytest.raises(ValueError, match=r"unknown sky 'daylite' \(did you mean 'daylight'\?\).*or a path"):
        load_environment("daylite")
    with pytest.raises(ValueError, match="no such file"):
        load_environment(tmp_path / "missing.hdr")
    with pytest.raises(ValueError, match="environment source must be"):
        load_environment(-1.0)


def test_pfm_header_with_single_spaces_is_read(tmp_path):
    img = np.ones((2, 4), np.float32)
    (tmp_path / "a.pfm").write_bytes(b"Pf 4 2 -1.0\n" + struct.pack("<8f", *img.ravel()))
    assert read_environment_image(tmp_path / "a.pfm").shape == (2, 4, 3)
