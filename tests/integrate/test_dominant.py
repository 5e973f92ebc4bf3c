"""The dominant-light method of image-based lighting (lighting.integrate.dominant): closed forms, frames, accuracy."""

import math

import numpy as np
import pytest

from lighting.integrate.dominant import DominantEnvironment, dominant_radiance
from lighting.integrate.extraction import find_dominant_lights
from lighting.integrate.ibl import lobe_albedo, split_sum_radiance
from lighting.integrate.prefilter import prefilter_environment
from lighting.lights.envfiles import TransformedEnvironment
from lighting.lights.environment import ConstantEnvironment, LatLongEnvironment
from lighting.models.brdf import CookTorrance, Lambert

H = 128
UNIFORM = np.array([0.5, 0.4, 0.3])
DISK = np.array([2000.0, 1800.0, 1500.0])
GAMMA = math.radians(2.0)  # the disk's angular radius
CENTRE = np.array([0.3, -0.4, 0.866])
CENTRE = CENTRE / np.linalg.norm(CENTRE)


def _disk_image(h=H, supersample=16):
    """A uniform sky with one disk, each pixel holding the disk's share of its solid angle (equal-area points)."""
    w = 2 * h
    img = np.broadcast_to(UNIFORM, (h, w, 3)).copy()
    d = LatLongEnvironment.pixel_directions(h, w)
    k = (np.arange(supersample) + 0.5) / supersample
    for i, j in np.argwhere(d @ CENTRE >= math.cos(GAMMA + 2 * math.pi / h)):
        z = math.cos(i * math.pi / h) + (math.cos((i + 1) * math.pi / h) - math.cos(i * math.pi / h)) * k
        phi = math.pi - (j + k) * (2 * math.pi / w)  # the column angle's azimuth
        r = np.sqrt(1 - z * z)
        pts = np.stack(np.broadcast_arrays(r[:, None] * np.cos(phi), r[:, None] * np.sin(phi), z[:, None]), -1)
        img[i, j] += (DISK - UNIFORM) * float(np.mean(pts @ CENTRE >= math.cos(GAMMA)))
    return img


@pytest.fixture(scope="module")
def disk_pre():
    return prefilter_environment(LatLongEnvironment(_disk_image()))


def _normals_facing_the_disk():
    """Normals at 0° to 70° from the disk's centre, each with a view 40° off it."""
    t = np.cross(CENTRE, [0.0, 0.0, 1.0])
    t /= np.linalg.norm(t)
    b = np.cross(CENTRE, t)
    out_n, out_v = [], []
    for k, ang in enumerate(np.radians([0.0, 15.0, 30.0, 45.0, 60.0, 70.0])):
        axis = t if k % 2 else b
        n = math.cos(ang) * CENTRE + math.sin(ang) * axis
        v = math.cos(0.7) * n + math.sin(0.7) * np.cross(n, axis) / np.linalg.norm(np.cross(n, axis))
        out_n.append(n)
        out_v.append(v)
    return np.array(out_n), np.array(out_v)


def test_the_disk_is_found_with_its_direction_solid_angle_and_power():
    lights, rest = find_dominant_lights(_disk_image())
    assert len(lights) == 1
    omega = 2 * math.pi * (1 - math.cos(GAMMA))
    assert math.degrees(math.acos(min(1.0, float(lights.directions[0] @ CENTRE)))) < 0.05
    # Its power: the disk's excess over the sky, L Ω, within the image's supersampling (0.3 %).
    np.testing.assert_allclose(lights.power[0], (DISK - UNIFORM) * omega, rtol=3e-3)
    # Its solid angle: its power over its radiance (the fully covered pixels hold L_d).
    assert lights.solid_angles[0] == pytest.approx(omega, rel=1e-2)
    assert np.all(rest >= UNIFORM - 1e-12) and rest.mean(axis=-1).max() < 16 * UNIFORM.mean() * 1.2


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_lambert_is_the_closed_form_uniform_sky_plus_the_disk(disk_pre, dtype):
    kd = np.array([0.8, 0.6, 0.4])
    n, v = _normals_facing_the_disk()
    out = dominant_radiance(Lambert(kd), disk_pre, n.astype(dtype), v.astype(dtype))
    assert out.dtype == dtype
    # k_d L_u (the uniform sky, π L_u k_d / π) plus the disk's irradiance (L_d − L_u) π sin²γ cos θ times k_d / π.
    cos_c = n @ CENTRE
    expected = kd * UNIFORM + kd / math.pi * (DISK - UNIFORM) * (math.pi * math.sin(GAMMA) ** 2) * cos_c[:, None]
    np.testing.assert_allclose(out, expected, rtol=1e-2)
    # The split sum's SH9 irradiance cannot hold the disk: it is far off on the same normals.
    ss = split_sum_radiance(Lambert(kd), disk_pre, n, v)
    assert np.max(np.abs(ss - expected) / expected) > 0.05


def _random_pairs(seed, count, flip_below):
    """``count`` random unit normals and views, each view turned round (``v → −v``) where ``n·v < flip_below``."""
    rng = np.random.default_rng(seed)
    n = rng.normal(size=(count, 3))
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    v = rng.normal(size=(count, 3))
    v /= np.linalg.norm(v, axis=-1, keepdims=True)
    return n, np.where((np.sum(n * v, -1) < flip_below)[:, None], -v, v)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_the_white_furnace_gives_each_part_its_albedo(dtype):
    pre = prefilter_environment(ConstantEnvironment(1.5), height=32)
    n, v = _random_pairs(3, 300, flip_below=0.0)
    ggx = CookTorrance(1.0, 0.3, 1.0, ndf="ggx", fresnel="none")
    out = dominant_radiance(Lambert(0.6) + ggx, pre, n.astype(dtype), v.astype(dtype), split_terms=True)
    assert out["diffuse"].dtype == dtype
    np.testing.assert_allclose(out["diffuse"], 0.9, rtol=1e-5)
    # The filtered samples' weights sum to one: the glossy part reflects ρ(μ_v) L, as the split sum does.
    theta = np.arccos(np.clip(np.sum(n * v, -1), 0, 1))
    table = lobe_albedo(ggx)
    from lighting.integrate.ibl import ALBEDO_ANGLES

    rho = np.interp(theta, ALBEDO_ANGLES, table[:, 0])
    np.testing.assert_allclose(out["specular"][:, 0], 1.5 * rho, rtol=2e-5)


def test_behind_the_surface_is_black_and_terms_add_up(disk_pre):
    n = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]])
    v = np.array([[0.0, 0.6, 0.8], [0.0, 0.6, -0.8]])
    m = Lambert(0.5) + CookTorrance(1.0, 0.2, 1.0, ndf="ggx", fresnel="none")
    both = dominant_radiance(m, disk_pre, n, v, split_terms=True)
    total = dominant_radiance(m, disk_pre, n, v)
    np.testing.assert_allclose(total, both["diffuse"] + both["specular"], rtol=1e-12)
    assert np.all(total[1] == 0) and np.all(total[0] > 0)


def test_a_turned_and_scaled_environment_is_the_base_seen_from_turned_pixels(disk_pre):
    base_env = disk_pre.environment
    turned = disk_pre.for_environment(TransformedEnvironment(base_env, intensity=2.0, rotation=90.0))
    n, v = _normals_facing_the_disk()
    rz = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # +90° about +z
    m = Lambert(0.7) + CookTorrance(1.0, 0.2, 1.0, ndf="ggx", fresnel="none")
    # What the base shows toward d, the turned light shows toward R d, twice as bright.
    np.testing.assert_allclose(dominant_radiance(m, turned, n @ rz.T, v @ rz.T),
                               2.0 * dominant_radiance(m, disk_pre, n, v), rtol=1e-6)  # fmt: skip


def test_a_narrow_lobe_on_the_grid_under_a_turned_and_scaled_environment_is_the_base_turned(disk_pre):
    # The round lobe is read in the base's frame like the rest of the method: one view for every pixel, turned with
    # the pixels, and the turned light gives twice the base's values on the grid as pixel by pixel.
    from lighting.validation.accuracy import ibl_sphere

    turned = disk_pre.for_environment(TransformedEnvironment(disk_pre.environment, intensity=2.0, rotation=90.0))
    _, n, v = ibl_sphere(160)
    rz = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # +90° about +z
    m = Lambert(0.2) + CookTorrance(1.0, 0.05, 1.0, ndf="ggx", fresnel="none")
    base = dominant_radiance(m, disk_pre, n, v, normal_grid=True)
    np.testing.assert_allclose(dominant_radiance(m, turned, n @ rz.T, v @ rz.T, normal_grid=True), 2.0 * base,
                               rtol=1e-5, atol=1e-6 * base.max())  # fmt: skip


def test_the_precomputation_is_made_once_per_base_environment(disk_pre):
    from lighting.integrate.dominant import dominant_environment

    base_env = disk_pre.environment
    turned = disk_pre.for_environment(TransformedEnvironment(base_env, intensity=3.0, rotation=10.0))
    first = dominant_environment(disk_pre)
    assert isinstance(first, DominantEnvironment) and dominant_environment(turned) is first
    assert len(first.lights) == 1


# ------------------------------------------------------------------ against the Monte-Carlo reference, small
def _small_case(sky):
    """48 pixels of the accuracy study's sphere under a 64-row map of ``sky``, with its prefiltered levels."""
    from lighting.validation.accuracy import ibl_environment, ibl_front_pixels

    n, v = ibl_front_pixels(32, 48)
    env = ibl_environment(sky, 64)
    return env, prefilter_environment(env), n, v


MODELS = {"Lambert": Lambert(0.8)} | {
    f"GGX α={a}": CookTorrance(1.0, a, 1.0, ndf="ggx", fresnel="none") for a in (0.05, 0.2, 0.5)
}


def _errors(value, reference):
    from lighting.validation.accuracy import ibl_pixel_errors

    e, _, own = ibl_pixel_errors(value, reference.value, reference.error)
    return float(np.median(e)), float(np.percentile(e, 95)), float(np.median(own))


@pytest.mark.slow  # seconds of work: the full run has it, the fast loop leaves it out
@pytest.mark.parametrize("sky", ["daylight", "sun-gradient", "studio"])
def test_within_a_few_percent_of_the_reference(sky):
    from lighting.integrate.ibl import ProgressiveRadiance

    env, pre, n, v = _small_case(sky)
    for label, m in MODELS.items():
        ref = ProgressiveRadiance(m, env, n, v, seed=11)
        for _ in range(8):
            ref.add(1024)
        med, p95, own = _errors(dominant_radiance(m, pre, n.astype(np.float32), v.astype(np.float32)), ref)
        _, ss_p95, _ = _errors(split_sum_radiance(m, pre, n, v), ref)
        assert own < 0.02, (sky, label)  # the reference's own median error (8,192 samples per pixel)
        # The targets, median 2 % and 95th percentile 10 %, with room for the reference's own noise.
        assert med < 0.02 + own and p95 < 0.10, (sky, label, med, p95)
        if sky == "sun-gradient":  # where the split sum fails: its 95th percentile is over 4 times as large
            assert p95 < ss_p95 / 4, (label, p95, ss_p95)


# ------------------------------------------------------------------ the building blocks of a re-shade
def test_the_level_stack_reads_what_the_lat_long_lookup_reads_blended_between_two_levels():
    # One sample of weight 1 at a fractional level: the engine's bilinear lat-long lookup of the two levels around
    # it, blended linearly (the stack's padded borders standing in for the lookup's wrap and clamp).
    from lighting.integrate._fis import LevelStack
    from lighting.lights.latlong import latlong_lookup

    rng = np.random.default_rng(5)
    pre = prefilter_environment(LatLongEnvironment(rng.random((32, 64, 3))))
    stack = LevelStack(pre)
    d = rng.normal(size=(400, 3))
    d[:8] = [[0, 0, 1], [0, 0, -1], [-1, 0, 0], [-1, 1e-7, 0], [-1, -1e-7, 0], [1, 0, 0], [0, 1, 0], [0, -1, 1e-3]]
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    level = rng.uniform(0, len(pre.sigmas) - 1, 400)
    level[:8] = [0, 0, 0.5, 1, 2, 6.5, 7, 3.25]
    d32 = d.astype(np.float32)
    got = stack.mean(d32[:, 0:1], d32[:, 1:2], d32[:, 2:3], level[:, None].astype(np.float32),
                     np.ones((400, 1), np.float32))  # fmt: skip
    levels = pre.families["mirror"]
    k0 = np.floor(level).astype(int)
    want = np.empty((400, 3))
    for i in range(400):
        k1 = min(k0[i] + 1, len(levels) - 1)
        a, b = (latlong_lookup(levels[k].reshape(-1, 3).astype(np.float64), *levels[k].shape[:2], d[i])
                for k in (k0[i], k1))
        want[i] = a + (level[i] - k0[i]) * (b - a)
    np.testing.assert_allclose(got, want, rtol=2e-4, atol=2e-5)


@pytest.mark.parametrize("kernel", ["mirror", "ggx", "beckmann"])
def test_one_level_reads_what_the_split_sum_reads_at_that_width(kernel):
    # A narrow microfacet lobe's round lobe, read per pixel: the family at one width, its two levels blended once, is
    # the split sum's own lookup (bilinear in each level, linear between them) in float32, the coarser level read at
    # the finer one's texel centres as in the level stack (hence its tolerance) — away from the poles, where the
    # lookup runs linearly to the edge row's mean and the padded level repeats the edge row instead; there it stays
    # within the levels' range.
    from lighting.integrate._fis import OneLevel

    rng = np.random.default_rng(11)
    pre = prefilter_environment(LatLongEnvironment(rng.random((32, 64, 3)) * [1.0, 2.0, 3.0]))
    d = rng.normal(size=(600, 3))
    d[:6] = [[-1, 0, 0], [-1, 1e-7, 0], [-1, -1e-7, 0], [1, 0, 0], [0, 1, 0], [0, -1, 1e-3]]  # the seam, the axes
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    for sigma in (0.0, 0.03, 0.07, 0.2, 0.9, 5.0):  # the map itself, between levels, past the last one
        one = OneLevel(pre, kernel, sigma)
        got = one.read(d.astype(np.float32))
        assert got.dtype == np.float32 and got.shape == (600, 3)
        want = pre._lookup(d, sigma, kernel)
        h = pre.families[kernel][min(int(pre.level_of(sigma)), len(pre.sigmas) - 1)].shape[0]
        inside = np.abs(d[:, 2]) < np.cos(0.5 * math.pi / h)  # more than half a row from either pole
        np.testing.assert_allclose(got[inside], want[inside], rtol=2e-4, atol=2e-5)
        lo, hi = (np.stack([f(im.reshape(-1, 3), axis=0) for im in pre.families[kernel]]) for f in (np.min, np.max))
        assert np.all(got >= lo.min(axis=0) - 1e-6) and np.all(got <= hi.max(axis=0) + 1e-6)


def test_the_round_lobes_are_kept_for_the_widths_met_last(disk_pre):
    # A roughness slider meets a new width at every step: each width's blended level is made once while it is in
    # use, and the widths met longest ago are let go, so that memory stays bounded.
    from lighting.integrate.dominant import dominant_environment

    dom = dominant_environment(disk_pre)
    first = dom.one_level("ggx", 0.05)
    assert dom.one_level("ggx", 0.05) is first and dom.one_level("beckmann", 0.05) is not first
    for k in range(16):
        dom.one_level("ggx", 0.06 + 0.001 * k)
    assert len(dom._one_levels) <= 16 and dom.one_level("ggx", 0.05) is not first


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_a_narrow_lobe_on_the_grid_is_a_white_furnace_with_its_round_lobe_taken_out_and_put_back(dtype):
    # Under a uniform sky the filtered mean and the round lobe are both L: the grid holds 0, each pixel adds L back,
    # and the lobe reflects its albedo times L at every pixel, as pixel by pixel.
    from lighting.integrate.dominant import HALF_GRID_DENSITY, _half_vector_lobe
    from lighting.integrate.ibl import ALBEDO_ANGLES, lobe_albedo, lobe_sigma

    pre = prefilter_environment(ConstantEnvironment(1.5), height=32)
    ggx = CookTorrance(1.0, 0.05, 1.0, ndf="ggx", fresnel="none")
    assert _half_vector_lobe(ggx, lobe_sigma(ggx.lobe())) and HALF_GRID_DENSITY == 2
    view = np.array([0.48, -0.6, 0.64])
    rng = np.random.default_rng(3)
    n = rng.normal(size=(30000, 3))
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    n = np.where((n @ view < 0)[:, None], -n, n)
    v = np.broadcast_to(view, n.shape)
    on, off = (dominant_radiance(ggx, pre, n.astype(dtype), v.astype(dtype), normal_grid=g) for g in (True, False))
    assert on.dtype == off.dtype == dtype
    rho = np.interp(np.arccos(np.clip(n @ view, 0, 1)), ALBEDO_ANGLES, lobe_albedo(ggx)[:, 0])
    lit = n @ view > 0
    np.testing.assert_allclose(on[lit, 0], 1.5 * rho[lit], rtol=2e-5, atol=1e-6)
    np.testing.assert_allclose(on[lit], off[lit], rtol=2e-5, atol=1e-6)


@pytest.mark.parametrize("part", [
    CookTorrance(1.0, 0.2, 1.0, ndf="ggx", fresnel="none"),
    CookTorrance(1.0, 0.5, (0.95, 0.64, 0.54), ndf="beckmann", fresnel="schlick"),
    Lambert(0.7),
], ids=["ggx-0.2", "beckmann-0.5-gold", "lambert"])  # fmt: skip
def test_the_cells_table_gives_the_models_own_sum_over_the_cells(part):
    # Σ_c f_r(v, l_c)(n·l_c) Φ_c read from the (θ_v, θ_l, φ) table against the model's own evaluation of every pair.
    from lighting.integrate._cells import _cell_exact, cell_sum

    rng = np.random.default_rng(8)
    n, v = _random_pairs(rng, 2000, flip_below=0.02)
    keep = np.sum(n * v, -1) > 0.02
    n, v = n[keep], v[keep]
    cells = rng.normal(size=(30, 3))
    cells /= np.linalg.norm(cells, axis=-1, keepdims=True)
    power = rng.uniform(0.1, 1.0, (30, 3))
    n32, v32 = n.astype(np.float32), v.astype(np.float32)
    got = cell_sum(part.parts[0], cells, power, n32, v32, np.sum(n32 * v32, -1))
    want = _cell_exact(part.parts[0], cells, power, n, v)
    rel = np.max(np.abs(got - want), axis=-1) / np.max(want, axis=-1)
    # Trilinear between table points 1° (θ_v), 1.4° (θ_l) and at most 1.8° (φ, near the mirror plane) apart: the
    # median pixel within 0.2 %, the 99th percentile within 3 %; away from grazing views (n·v > 0.2, θ_v < 78°),
    # where the lobe changes fastest with the view, within 1 % and at most 5 %.
    front = np.sum(n * v, -1) > 0.2
    assert np.median(rel) < 0.002 and np.percentile(rel, 99) < 0.03, (np.median(rel), np.percentile(rel, 99))
    assert np.percentile(rel[front], 99) < 0.01 and rel[front].max() < 0.05


def test_a_block_of_filtered_samples_stays_within_its_share_of_the_memory_estimate(disk_pre, monkeypatch):
    # One block of a narrow lobe's filtered samples (512 pixels at 64 samples, one shading thread): traced, under
    # the bytes dominant_radiance's budget sets aside per thread, and not far under them.
    import tracemalloc

    import lighting.shading.batch as batch
    from lighting.integrate._fis import _BLOCK, BLOCK_BYTES

    monkeypatch.setattr(batch, "_threads", lambda: 1)  # on more threads the block's rows are cut among them

    pre = disk_pre
    model = CookTorrance(1.0, 0.05, 1.0, ndf="ggx", fresnel="none")
    rng = np.random.default_rng(4)
    n = rng.normal(size=(_BLOCK // 64, 3))
    n[:, 2] = np.abs(n[:, 2]) + 0.2
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    v = np.broadcast_to(np.array([0.0, 0.6, 0.8]), n.shape)
    n32, v32 = n.astype(np.float32), v.astype(np.float32)
    dominant_radiance(model, pre, n32, v32, normal_grid=False)  # the tables, once
    tracemalloc.start()
    try:
        dominant_radiance(model, pre, n32, v32, normal_grid=False)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert BLOCK_BYTES / 2 < peak < n.shape[0] * 512 + BLOCK_BYTES, (peak, BLOCK_BYTES)


@pytest.mark.parametrize("model", [Lambert(0.3) + CookTorrance(1.0, 0.3, 1.0, ndf="ggx"),
                                   Lambert(0.3) + CookTorrance(1.0, 0.05, 1.0, ndf="ggx", fresnel="none")])
def test_a_block_of_the_per_pixel_finish_stays_within_its_share_of_the_memory_estimate(disk_pre, monkeypatch, model):
    # Each block of the per-pixel finish (one shading thread, on the grid of normals): traced, under the bytes per
    # pixel that dominant_radiance's budget sets aside for it, and not far under them.
    import tracemalloc

    import lighting.integrate.dominant as dominant_module
    import lighting.shading.batch as batch
    from lighting.validation.accuracy import ibl_sphere

    monkeypatch.setattr(batch, "_threads", lambda: 1)
    monkeypatch.setattr(dominant_module, "FINISH_BLOCK", 8192)
    _, n, v = ibl_sphere(200)
    n32, v32 = n.astype(np.float32), v.astype(np.float32)
    per_pixel = []
    in_blocks = dominant_module.in_blocks

    def traced(count, step, fn, **kwargs):
        if fn.__name__ != "finish":
            return in_blocks(count, step, fn, **kwargs)

        def block(rows):
            tracemalloc.reset_peak()
            before = tracemalloc.get_traced_memory()[0]
            fn(rows)
            per_pixel.append((tracemalloc.get_traced_memory()[1] - before) / (rows.stop - rows.start))

        return in_blocks(count, step, block, **kwargs)

    dominant_radiance(model, disk_pre, n32, v32)  # the tables and the grid, once
    monkeypatch.setattr(dominant_module, "in_blocks", traced)
    tracemalloc.start()
    try:
        dominant_radiance(model, disk_pre, n32, v32, normal_grid=True)
    finally:
        tracemalloc.stop()
    estimate = dominant_module._finish_bytes(len(model.parts))
    assert len(per_pixel) >= 3 and all(estimate / 2 < b < estimate for b in per_pixel), (per_pixel, estimate)


@pytest.mark.parametrize("threads", [1, 2, 3, 8])
@pytest.mark.parametrize("count, step", [(5328, 2048), (176544, 32768), (72360, 512), (100, 2048), (3000, 1024)])
def test_balanced_blocks_cover_the_rows_once_in_multiples_of_64_and_an_equal_run_per_thread(monkeypatch, threads,
                                                                                            count, step):
    # 5,328 rows in blocks of 2,048 are three blocks: on two threads one would wait a third of the time.
    import threading

    import lighting.shading.batch as batch

    monkeypatch.setattr(batch, "_threads", lambda: threads)
    seen, lock = [], threading.Lock()

    def record(rows):
        with lock:
            seen.append((rows.start, rows.stop))

    batch.in_blocks(count, step, record, balanced=True)
    seen.sort()
    assert seen[0][0] == 0 and seen[-1][1] == count
    assert all(a[1] == b[0] for a, b in zip(seen[:-1], seen[1:], strict=True))  # consecutive, disjoint, every row once
    sizes = [b - a for a, b in seen]
    assert max(sizes) <= step and all(size % 64 == 0 for size in sizes[:-1])
    if count > step:
        assert len(seen) >= -(-count // step)  # never fewer blocks than asked for
        if -(-count // step) < 4 * threads:  # few blocks, where a thread's last one matters: a whole run each
            assert len(seen) % threads == 0, len(seen)
    elif count > 64 and threads > 1:  # fewer rows than a block, but worth a thread each: one block per thread at most
        assert 2 <= len(seen) <= threads, seen
    else:
        assert seen == [(0, count)]


@pytest.mark.slow
@pytest.mark.parametrize("model", [
    CookTorrance(1.0, 0.1, ndf="ggx", geometry="smith-correlated", fresnel="conductor", metal="gold"),
    CookTorrance(0.7, 0.08, ndf="beckmann", geometry="smith", fresnel="schlick"),
    CookTorrance(1.0, 0.15, ndf="ggx", geometry="smith-correlated", fresnel="dielectric", energy_compensation=True),
])  # fmt: skip
def test_the_half_vector_table_evaluates_the_views_read_with_the_bits_of_the_whole_table(model):
    # A small image reads a few of the table's views: HalfTable evaluates those, in any order and any number at once,
    # and each holds the weights of half_table, the readable reference that evaluates every view.
    from lighting.integrate import _fis

    h, d, want = _fis.half_table(model, 16)
    table = _fis.HalfTable(model, 16)
    rng = np.random.default_rng(7)
    rows, cols = rng.integers(0, len(_fis.TABLE_ANGLES), 900), rng.integers(0, _fis.AZIMUTHS, 900)
    table.fill(rows, cols)
    assert table.filled.sum() == len(set(zip(rows.tolist(), cols.tolist(), strict=True)))
    assert np.array_equal(table.weights[rows, cols].view(np.uint32), want[rows, cols].view(np.uint32))
    everything = np.indices(table.filled.shape)
    table.fill(everything[0], everything[1])
    assert table.filled.all()
    assert np.array_equal(table.weights.view(np.uint32), want.view(np.uint32))
    assert np.array_equal(table.h, h) and np.array_equal(table.d, d)
