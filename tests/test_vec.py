import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from lighting import vec


def test_normalize_values_and_zero():
    np.testing.assert_allclose(vec.normalize((3.0, 0.0, 4.0)), [0.6, 0.0, 0.8], rtol=0, atol=1e-16)
    assert vec.normalize(np.zeros(3)).tolist() == [0.0, 0.0, 0.0]
    batch = np.array([[0.0, 0.0, 0.0], [0.0, 2.0, 0.0]])
    np.testing.assert_array_equal(vec.normalize(batch), [[0, 0, 0], [0, 1, 0]])


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("scale", [1e-30, 1e-20, 1.0, 1e15, 1e30])
def test_normalize_tiny_and_huge_keep_dtype(dtype, scale):
    if dtype is np.float64:
        scale = scale**8 if scale != 1.0 else 1.0  # 1e-240 … 1e240: beyond the squared range
    a = np.array([3.0, 0.0, 4.0], dtype=dtype) * dtype(scale)
    out = vec.normalize(a)
    assert out.dtype == dtype
    np.testing.assert_allclose(out, [0.6, 0.0, 0.8], rtol=4 * np.finfo(dtype).eps)


def test_length_no_overflow():
    assert vec.length(np.array([3e30, 4e30, 0], np.float32)) == pytest.approx(5e30, rel=1e-6)
    assert vec.length(np.array([3e-30, 4e-30, 0], np.float32)) == pytest.approx(5e-30, rel=1e-6)


def test_dot_cross_reflect_broadcast():
    n = np.array([0.0, 0.0, 1.0])
    d = np.array([[1.0, 0.0, 1.0], [0.0, -1.0, 2.0]])
    np.testing.assert_array_equal(vec.dot(d, n), [1.0, 2.0])
    np.testing.assert_array_equal(vec.reflect(d, n), [[-1.0, 0.0, 1.0], [0.0, 1.0, 2.0]])
    np.testing.assert_array_equal(vec.cross((1.0, 0, 0), (0, 1.0, 0)), [0, 0, 1])


def test_reflect_is_the_slides_formula():
    rng = np.random.default_rng(1)
    n = vec.normalize(rng.normal(size=(100, 3)))
    l = vec.normalize(rng.normal(size=(100, 3)))  # noqa: E741
    r = vec.reflect(l, n)
    expected = 2 * n * np.sum(n * l, -1, keepdims=True) - l
    np.testing.assert_allclose(r, expected, atol=1e-15)
    # Mirror: same angle with n, unit length, l + r parallel to n.
    np.testing.assert_allclose(vec.dot(r, n), vec.dot(l, n), atol=1e-15)
    np.testing.assert_allclose(np.linalg.norm(np.cross(l + r, n), axis=-1), 0, atol=1e-14)


def test_halfway_defined_for_opposite_vectors():
    l = np.array([0.3, -0.4, 0.5])  # noqa: E741
    h = vec.halfway(l, -l)
    assert h.tolist() == [0.0, 0.0, 0.0]
    h2 = vec.halfway((1.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    np.testing.assert_allclose(h2, [2**-0.5, 0, 2**-0.5], atol=1e-16)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_dtype_preserved_with_tuples(dtype):
    l = np.ones((4, 3), dtype)  # noqa: E741
    assert vec.halfway(l, (0.0, 0.0, 1.0)).dtype == dtype
    assert vec.reflect(l, (0.0, 0.0, 1.0)).dtype == dtype
    assert vec.dot(l, (0.0, 0.0, 1.0)).dtype == dtype


def test_orthonormal_basis_is_orthonormal():
    rng = np.random.default_rng(2)
    n = vec.normalize(rng.normal(size=(500, 3)))
    n[0] = (0, 0, -1)
    n[1] = (0, 0, 1)
    t, b = vec.orthonormal_basis(n)
    for a, c in ((t, b), (t, n), (b, n)):
        np.testing.assert_allclose(vec.dot(a, c), 0, atol=1e-14)
    np.testing.assert_allclose(vec.cross(t, b), n, atol=1e-14)
    d = vec.normalize(rng.normal(size=(500, 3)))
    np.testing.assert_allclose(vec.from_local(vec.to_local(d, n), n), d, atol=1e-14)


finite = st.floats(min_value=-1e150, max_value=1e150, allow_nan=False)


@given(st.tuples(finite, finite, finite))
def test_normalize_unit_or_zero(v):
    out = vec.normalize(np.array(v))
    norm = np.linalg.norm(out)
    if any(v):
        assert abs(norm - 1) < 1e-14
    else:
        assert norm == 0


# ------------------------------------------------------------------------------------------------- illegal input
NAN3 = (float("nan"), 0.0, 1.0)
INF3 = np.array([0.0, np.inf, 1.0])
ILLEGAL_VEC = [
    # (call, parameter named in the message)
    (lambda x: vec.normalize(x), "a"),
    (lambda x: vec.length(x), "a"),
    (lambda x: vec.dot(x, (0.0, 0.0, 1.0)), "a"),
    (lambda x: vec.dot((0.0, 0.0, 1.0), x), "b"),
    (lambda x: vec.cross(x, (0.0, 0.0, 1.0)), "a"),
    (lambda x: vec.reflect(x, (0.0, 0.0, 1.0)), "d"),
    (lambda x: vec.reflect((0.0, 0.0, 1.0), x), "n"),
    (lambda x: vec.halfway(x, (0.0, 0.0, 1.0)), "l"),
    (lambda x: vec.halfway((0.0, 0.0, 1.0), x), "v"),
    (lambda x: vec.orthonormal_basis(x), "n"),
    (lambda x: vec.to_local(x, (0.0, 0.0, 1.0)), "d"),
    (lambda x: vec.to_local((1.0, 0.0, 0.0), x), "n"),
    (lambda x: vec.from_local(x, (0.0, 0.0, 1.0)), "d_local"),
    (lambda x: vec.from_local((1.0, 0.0, 0.0), x), "n"),
]
BAD_VECTORS = [
    (NAN3, ValueError),
    (INF3, ValueError),
    (np.array([[0.0, 0.0, 1.0], [np.nan, 0.0, 0.0]], np.float32), ValueError),  # one bad vector in a batch
    (np.full(3, np.inf, np.float32), ValueError),
    ((1j, 0.0, 1.0), TypeError),
    (np.array([0.0, 0.0, 1.0 + 0j]), TypeError),
    (b"1", TypeError),
    ("0,0,1", TypeError),
    (("0", 0.0, 1.0), TypeError),
    (None, TypeError),
    ({"x": 1.0}, TypeError),
    ((True, False, True), TypeError),
    ((1.0, 0.0), ValueError),  # shape
]


@pytest.mark.parametrize(("bad", "kind"), BAD_VECTORS, ids=lambda x: repr(x)[:30])
@pytest.mark.parametrize(("call", "name"), ILLEGAL_VEC, ids=lambda x: x if isinstance(x, str) else "")
def test_illegal_vectors_raise_a_named_error(call, name, bad, kind):
    # NaN, inf, complex, text and objects were taken silently before: normalize returned 0 for a NaN vector.
    with pytest.raises(kind) as info:
        call(bad)
    msg = str(info.value)
    assert msg.startswith(f"{name} must be ") and "\n" not in msg and len(msg) < 300, msg
    assert isinstance(info.value, ValueError)  # wrong types are ArgumentTypeError: a ValueError too


@pytest.mark.parametrize(
    ("call", "name", "kind"),
    [
        (lambda: vec.spherical_direction(float("nan"), 0.0), "theta", ValueError),
        (lambda: vec.spherical_direction(0.5, "1"), "phi", TypeError),
        (lambda: vec.spherical_direction(b"1", 0.0), "theta", TypeError),
        (lambda: vec.spherical_direction(1j, 0.0), "theta", TypeError),
        (lambda: vec.spherical_direction(np.zeros(2), np.zeros(3)), "theta and phi", ValueError),
        (lambda: vec.spherical_direction(0.5, 0.0, dtype=np.int32), "dtype", ValueError),
        (lambda: vec.spherical_direction(0.5, 0.0, dtype="bogus"), "dtype", TypeError),
        (lambda: vec.direction_from_elevation(np.inf), "elevation_deg", ValueError),
        (lambda: vec.direction_from_elevation(10.0, None), "azimuth_deg", TypeError),
        (lambda: vec.direction_from_elevation("45"), "elevation_deg", TypeError),
    ],
)
def test_illegal_angles_raise_a_named_error(call, name, kind):
    with pytest.raises(kind) as info:
        call()
    assert str(info.value).startswith(f"{name} must ") and isinstance(info.value, ValueError), str(info.value)


def test_long_values_are_abbreviated_in_messages():
    big = np.full((10000, 3), np.nan)
    with pytest.raises(ValueError) as info:
        vec.normalize(big)
    assert len(str(info.value)) < 250


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_checked_inputs_still_keep_dtype_and_values(dtype):
    a = np.array([[3.0, 0.0, 4.0], [0.0, 0.0, 0.0]], dtype)
    out = vec.normalize(a)
    assert out.dtype == dtype and out[1].tolist() == [0.0, 0.0, 0.0]
    np.testing.assert_allclose(out[0], [0.6, 0.0, 0.8], rtol=4 * np.finfo(dtype).eps)
    d = vec.spherical_direction(np.array([0.0, np.pi / 2], dtype), dtype(0.0))
    assert d.dtype == dtype and d[1].tolist() == [1.0, 0.0, 0.0]
    assert vec.direction_from_elevation(dtype(0.0), 90.0).tolist() == [0.0, 1.0, 0.0]
