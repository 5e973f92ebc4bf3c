"""The Monte-Carlo reference's fast paths against their readable forms, bit for bit: the turns between a
point's frame and the world, component by component, and the mean of the multiple-importance weights."""

from __future__ import annotations

import numpy as np

from lighting.integrate.estimate import _mean_err, _ratio
from lighting.integrate.radiance import _pair_mean, _to_local, _to_local_reference, _to_world, _to_world_reference
from lighting.vec import orthonormal_basis


def _same(a, b):
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def _frames(count, seed):
    rng = np.random.default_rng(seed)
    n = rng.normal(size=(count, 3))
    n[:4] = [[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, -1.0, 0.0]]
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    t, b = orthonormal_basis(n)
    return t, b, n


def test_the_turns_component_by_component_are_the_broadcast_ones_bit_for_bit():
    t, b, n = _frames(40, 1)
    rng = np.random.default_rng(2)
    for shape in ((40, 64, 3), (40, 1, 3)):
        l = rng.normal(size=shape)  # noqa: E741
        l[:6, 0] = [[1.0, 0.0, 0.0], [-0.0, -0.0, 1.0], [0.0, -0.0, -0.0], [-1.0, 0.0, -0.0], [0.0, 0.0, 0.0],
                    [-0.0, -0.0, -0.0]]  # fmt: skip  # signed zeros: sums of three -0 products
        assert _same(_to_world(l, t, b, n), _to_world_reference(l, t, b, n))
        assert _same(_to_local(l, t, b, n), _to_local_reference(l, t, b, n))
    axis = np.broadcast_to(np.array([0.3, -0.4, np.sqrt(0.75)]), (40, 1, 3))
    assert _same(_to_local(axis, t, b, n), _to_local_reference(axis, t, b, n))
    negative = -np.eye(3)[None, :, :] * 0.0  # every product −0
    assert _same(_to_local(np.broadcast_to(negative, (40, 3, 3)), t, b, n),
                 _to_local_reference(np.broadcast_to(negative, (40, 3, 3)), t, b, n))  # fmt: skip


def test_the_pair_mean_is_the_mean_of_the_summed_ratios_bit_for_bit():
    rng = np.random.default_rng(3)
    for bsz, m in ((7, 33), (1, 1), (16, 512)):
        ga, gb = rng.random((bsz, m, 3)) ** 4, rng.normal(size=(bsz, m, 3))
        pa, pb = rng.random((bsz, m)) ** 6, rng.random((bsz, m)) - 0.2  # zeros, negatives and tiny densities
        pa.flat[::5], pb.flat[::7] = 0.0, 1e-310
        ga.flat[::11], gb.flat[::13] = np.inf, 1e300
        ga.flat[::17] = np.nan
        with np.errstate(over="ignore", invalid="ignore"):  # the largest floats summed: both overflow alike
            want, _ = _mean_err(_ratio(ga, pa) + _ratio(gb, pb), axis=1)
            got = _pair_mean(ga, pa, gb, pb)
        assert _same(got, want)
