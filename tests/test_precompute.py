"""Precomputed multiple scattering (Bruneton 2017 on the GPU): the lookups against the
single-scattering renderer, the Monte Carlo reference, energy conservation, twilight, the
convergence over orders, and the table I/O."""

from __future__ import annotations

import functools
import math
from pathlib import Path

import numpy as np
import pytest

from skydome.atmosphere import DensityProfile, Spectrum, preset
from skydome.atmosphere import precompute as precompute_module
from skydome.atmosphere import precompute_probe as probe
from skydome.atmosphere.columns import densities
from skydome.atmosphere.inputs import broadened_lobe_uniforms, mie_lobe_uniforms
from skydome.atmosphere.precompute import PrecomputedAtmosphere, gauss_legendre, precompute
from skydome.atmosphere.precompute_config import PrecomputeConfig
from skydome.core.cameras import DirectionsCamera, direction_from_angles
from skydome.errors import CacheError, ParameterError
from skydome.physics.phase import henyey_greenstein
from skydome.reference import ms as mc
from skydome.spectra import LINEAR_SRGB_TO_XYZ

MC_FILE = Path(__file__).parent / "data" / "ms_reference_earth.npz"
#: Small tables for the checks that do not need accuracy (structure, monotonicity, I/O).
SMALL = dict(
    wavelengths="fast",
    scattering_size=(16, 64, 16, 8),
    multiple_size=(16, 32, 16, 4),
    ms_size=(8, 32, 8, 4),
    irradiance_size=(32, 8),
    transmittance_size=(256, 64),
    dtype="f4",
    ms_dtype="f4",
)


@functools.cache
def tables(atmosphere="earth", **kwargs) -> PrecomputedAtmosphere:
    from skydome.gpu import shared_context

    params = kwargs.pop("params", None) or preset(atmosphere)
    return precompute(shared_context(), params, PrecomputeConfig(**kwargs))


def to_xyzs(rgbs: np.ndarray) -> np.ndarray:
    """(R, G, B, S) -> (X, Y, Z, S): non-negative quantities, meaningful relative errors."""
    return np.concatenate([rgbs[:, :3] @ LINEAR_SRGB_TO_XYZ.T, rgbs[:, 3:]], axis=1)


def sphere(n: int, seed: int, upper: bool = False) -> np.ndarray:
    d = np.random.default_rng(seed).normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    if upper:
        d[:, 2] = np.abs(d[:, 2])
    return d


def away_from(dirs: np.ndarray, sun: np.ndarray, deg: float) -> np.ndarray:
    return dirs[np.degrees(np.arccos(np.clip(dirs @ sun, -1, 1))) > deg]


# ------------------------------------------------------------------------------------------
# Single scattering: the tables against the ray-marching renderer
# ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("atmosphere", ["earth_bruneton", "earth"])
@pytest.mark.parametrize("altitude_m", [0.0, 10_000.0])
def test_single_order_matches_single_scattering_renderer(ctx, altitude_m, atmosphere):
    # Same params and wavelengths; the renderer with 256 samples per ray is converged (its
    # 16-sample default is 0.6% off). The tables interpolate (r, mu, mu_s, nu) from a
    # 32 x 128 x 32 x 8 grid: measured 0.02-0.15% RMS, 0.6% at worst over 1200 directions in
    # the day. Bound: 0.5% RMS and 1.5% at worst, on X, Y, Z and scotopic (relative to the
    # value plus 1% of the frame's mean, for directions whose radiance is ~0). At 10 km the
    # directions below the horizon include the ground lit by the Sun (the renderer's model of
    # it), through the tables' direct-irradiance path. The Sun's disk (and 1 degree around it,
    # where a float32 cosine decides in or out) is left out.
    # `earth`'s aerosol stops at a 2 km mixing-layer top with a kink in ln density; the ray
    # quadrature splits there (split_node in atmosphere/precompute_common.glsl: a quarter of
    # the nodes below it, 3/4 above). Before the split 16 nodes left it 1.2-1.6% RMS low;
    # measured now 0.21-0.43% RMS, 0.86% at worst (the seeds' earth_bruneton 0.03-0.22%).
    from tests.air_frames import AirFrames

    pa = tables(atmosphere, orders=1)
    ref = AirFrames(
        pa.params, model="single", spectral="accurate", samples=256, jitter=False, ctx=ctx
    )
    for i, sun_el in enumerate((60.0, 20.0, 5.0)):
        sun = direction_from_angles(sun_el, 90.0 + 40 * i)
        dirs = away_from(sphere(400, 11 + i, upper=altitude_m == 0.0), sun, 1.0)
        got, _ = probe.sky_radiance(pa, dirs, sun, altitude_m=altitude_m, ground="sun")
        want = ref.render(
            DirectionsCamera(dirs), 0, 0, sun_direction=sun, altitude_m=altitude_m
        ).data[0]
        g, w = to_xyzs(got), to_xyzs(want.astype(np.float64))
        rel = (g - w) / (np.abs(w) + 0.01 * np.abs(w).mean(axis=0))
        rms = np.sqrt(np.mean(rel**2, axis=0))
        assert rms.max() < 5e-3, (sun_el, rms)
        assert np.abs(rel).max() < 1.5e-2, (sun_el, dirs[np.argmax(np.abs(rel).max(axis=1))])


def test_single_order_twilight_matches_single_scattering_renderer(ctx):
    # Sun at 0 and -6 degrees: single scattering falls by 1-3 e-folds per degree of Sun
    # depression as the Earth's shadow rises; the tables carry that by the lit-density
    # normalization F (atmosphere/precomputed_params.glsl). Measured RMS 0.3% (0 deg) and 1.3% (-6 deg);
    # bound 1% and 3% (of the value plus 1% of the sky's mean: shadowed directions are 0).
    # On the seeds' Earth (`earth`: 0.36% RMS at 0 deg with the split at its mixing-layer top,
    # but 5.1% at -6 deg, where the lit part of the rays lies far above that top: not the kink,
    # still open).
    from tests.air_frames import AirFrames

    pa = tables("earth_bruneton", orders=1)
    ref = AirFrames(
        pa.params, model="single", spectral="accurate", samples=256, jitter=False, ctx=ctx
    )
    for sun_el, bound in ((0.0, 0.01), (-6.0, 0.03)):
        sun = direction_from_angles(sun_el, 90.0)
        dirs = away_from(sphere(600, 5, upper=True), sun, 1.0)
        got, _ = probe.sky_radiance(pa, dirs, sun)
        want = (
            ref.render(DirectionsCamera(dirs), 0, 0, sun_direction=sun).data[0].astype(np.float64)
        )
        g, w = to_xyzs(got)[:, 1], to_xyzs(want)[:, 1]
        rel = (g - w) / (w + 0.01 * w.mean())
        assert np.sqrt(np.mean(rel**2)) < bound, (sun_el, np.sqrt(np.mean(rel**2)))


# ------------------------------------------------------------------------------------------
# All orders: Monte Carlo reference and energy conservation
# ------------------------------------------------------------------------------------------


def _load_mc() -> dict:
    if not MC_FILE.exists():
        pytest.skip(f"{MC_FILE.name} not generated yet (tools/make_ms_reference.py)")
    return dict(np.load(MC_FILE, allow_pickle=False))


def test_matches_monte_carlo_reference():
    # The Monte Carlo reference (tools/make_ms_reference.py, reference/ms.py: every order,
    # spectral radiance per unit solar irradiance at 440/550/680 nm, the direct Sun and the
    # ground's own radiance excluded, as sky_radiance; 36k-180k paths per direction). Tables in
    # the spectral debug mode at those wavelengths (+ 700 nm to fill the group), 10 orders.
    # Directions: the reference's valid sky directions (rays that do not hit the ground),
    # more than 3 deg from the Sun. Day (Sun >= 0 deg): relative RMS <= 2% per case and
    # wavelength (measured 0.34-0.72%, including the reference's standard error of 0.3-0.6%;
    # the reference's order 2 matches a deterministic quadrature to 0.1%,
    # test_ms_reference.py; the remaining -0.1..-0.5% bias comes from the coarse grids and
    # shrinks to -0.1..-0.3% with REFERENCE settings). Civil twilight (-6 deg): the
    # reference's standard error is 0.9-1.4% there, so its share is removed in quadrature and
    # the rest bounded by 2% (raw RMS 1.4-2.04%).
    data = _load_mc()
    wl = np.asarray(data["wavelengths_nm"], dtype=np.float64)
    pa = tables(str(data["preset"]), wavelengths=(*wl[:3], 700.0), output="spectral", orders=10)
    dirs = np.asarray(data["view_dirs"], dtype=np.float64)
    for ia, alt in enumerate(np.asarray(data["camera_altitude_m"], dtype=np.float64)):
        for js, el in enumerate(np.asarray(data["sun_elevation_deg"], dtype=np.float64)):
            sun = mc.sun_direction(float(data["sun_zenith_rad"][js]))
            away = np.degrees(np.arccos(np.clip(dirs @ sun, -1, 1))) > 3.0
            r = pa.params.bottom_radius_m + alt
            sky = dirs[:, 2] > -math.sqrt(1.0 - (pa.params.bottom_radius_m / r) ** 2)
            ok = np.asarray(data["view_valid"][ia], dtype=bool) & away & sky
            want = np.asarray(data["radiance"][ia, js], dtype=np.float64)[ok]
            err = np.asarray(data["stderr"][ia, js], dtype=np.float64)[ok]
            got, _ = probe.sky_radiance(pa, dirs[ok], sun, altitude_m=alt)
            rms = np.sqrt(np.mean((got[:, :3] / want - 1.0) ** 2, axis=0))
            if el >= 0.0:
                assert rms.max() <= 0.02, (alt, el, rms)
            else:
                noise = np.sqrt(np.mean((err / want) ** 2, axis=0))
                net = np.sqrt(np.maximum(rms**2 - noise**2, 0.0))
                assert net.max() <= 0.02, (alt, el, rms, noise)


def test_energy_conservation():
    # No absorption anywhere (albedo 0, no ozone, Mie extinction = scattering) and every
    # order (12: the 12th adds < 1e-4): the sunlight entering the atmosphere, pi Rt^2 per unit
    # irradiance, must leave it again: absorbed by the ground (direct + sky irradiance, from
    # the lookups, integrated over the planet), scattered out through the top (the radiance
    # leaving each point of the top, from the lookups at r = Rt looking down, integrated over
    # the hemisphere and the sphere), or transmitted through the limb without scattering (exact
    # chord transmittance, reference.ms.optical_depth). Measured: -0.56%, -0.10%, +0.03%,
    # +0.03% at 440, 550, 680, 700 nm; bound 1.5% (the issue allows 2%).
    base = preset("earth")
    params = base.with_(
        ground_albedo=Spectrum.constant(0.0),
        absorption_extinction=Spectrum.constant(0.0),
        mie_extinction=base.mie_scattering,
    )
    wl = (440.0, 550.0, 680.0, 700.0)
    pa = tables(
        params=params, wavelengths=wl, output="spectral", orders=12, dtype="f4", ms_dtype="f4"
    )
    Rb, Rt = params.bottom_radius_m / 1e3, params.top_radius_m / 1e3
    mu_s = np.concatenate(
        [
            gauss_legendre(32, -1.0, -0.4),
            gauss_legendre(64, -0.4, 0.4),
            gauss_legendre(32, 0.4, 1.0),
        ]
    )
    m, wm = mu_s[:, 0], mu_s[:, 1]
    sun = np.array([0.0, 0.0, 1.0])
    ground = np.stack([np.sqrt(1 - m * m), np.zeros_like(m), m], axis=1)
    _, sky = probe.sun_and_sky_irradiance(pa, ground, sun, points_km=ground * Rb * 1.000001)
    tau = np.stack([mc.optical_depth(params, wl, params.bottom_radius_m, max(x, 0.0)) for x in m])
    direct = np.where(m[:, None] > 0, m[:, None] * np.exp(-tau), 0.0)
    p_ground = 2 * math.pi * Rb**2 * (wm[:, None] * (direct + sky)).sum(0)
    # Outgoing radiance at the top: hemisphere of outward directions w around each zenith z.
    c = gauss_legendre(24, 0.0, 1.0)
    n_phi = 24
    phi = (np.arange(n_phi) + 0.5) * math.pi / n_phi  # half a turn: the other half is the mirror
    C, PH = np.meshgrid(c[:, 0], phi, indexing="ij")
    S = np.sqrt(1 - C * C)
    dirs, pts, weights = [], [], []
    for z, w in zip(ground, wm, strict=True):
        e1 = np.cross([0.0, 1.0, 0.0], z)
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(z, e1)
        out = (S * np.cos(PH))[..., None] * e1 + (S * np.sin(PH))[..., None] * e2 + C[..., None] * z
        dirs.append(-out.reshape(-1, 3))
        pts.append(np.tile(z * Rt * (1 - 1e-7), (out.size // 3, 1)))
        weights.append((w * C * c[:, 1:2] * 2 * math.pi / n_phi).reshape(-1))
    L, _ = probe.sky_radiance(pa, np.concatenate(dirs), sun, points_km=np.concatenate(pts))
    p_out = 2 * math.pi * Rt**2 * (np.concatenate(weights)[:, None] * L).sum(0)
    b = gauss_legendre(48, Rb, Rt)
    chord = np.stack([np.exp(-2 * mc.optical_depth(params, wl, x * 1e3, 0.0)) for x in b[:, 0]])
    p_through = (2 * math.pi * b[:, :1] * b[:, 1:] * chord).sum(0)
    balance = (p_ground + p_out + p_through) / (math.pi * Rt**2) - 1.0
    assert np.all(np.abs(balance) < 0.015), balance


# ------------------------------------------------------------------------------------------
# Physical behaviour
# ------------------------------------------------------------------------------------------


def test_finite_and_non_negative_everywhere():
    # Cameras from the ground to deep space, every direction, Suns from the zenith to below
    # the cut-off: XYZ and scotopic radiance (and irradiance) finite and >= 0 (linear sRGB
    # channels may be negative for colours outside its gamut, as in the renderer).
    pa = tables()
    dirs = sphere(500, 3)
    for alt in (0.0, 1.0, 10_000.0, 60_000.0, 99_000.0, 500_000.0, 4e7):
        pts = probe.camera_points(pa, alt, len(dirs))
        for el in (90.0, 30.0, 2.0, -1.0, -6.0, -15.0, -25.0, -90.0):
            sun = direction_from_angles(el, 30.0)
            L, col = probe.sky_radiance(pa, dirs, sun, points_km=pts, ground="sun_and_sky")
            assert np.all(np.isfinite(L)) and np.all(np.isfinite(col)), (alt, el)
            assert to_xyzs(L).min() >= -1e-3 * max(to_xyzs(L).max(), 1e-30), (alt, el)
            if alt < 100_000.0:
                sun_e, sky_e = probe.sun_and_sky_irradiance(pa, dirs, sun, points_km=pts)
                assert np.all(np.isfinite(sun_e)) and np.all(np.isfinite(sky_e))
                assert to_xyzs(sky_e).min() >= -1e-6 * max(to_xyzs(sky_e).max(), 1e-30)
    arrays = pa.to_arrays()
    assert all(np.all(np.isfinite(a.astype(np.float64))) for a in arrays.values())


def test_twilight_is_blue_and_darkens():
    # Civil twilight (-6 deg) keeps a blue sky (ozone's Chappuis absorption and Rayleigh
    # scattering); it is far brighter than at -12 (nautical), itself brighter than at -18
    # (astronomical), for the zenith and the sky's mean.
    pa = tables()
    dirs = sphere(400, 8, upper=True)
    mean, zen = {}, {}
    for el in (-6.0, -12.0, -18.0):
        sun = direction_from_angles(el, 90.0)
        L, _ = probe.sky_radiance(pa, dirs, sun)
        z, _ = probe.sky_radiance(pa, [[0.0, 0.0, 1.0]], sun)
        mean[el], zen[el] = L.mean(axis=0), z[0]
    r, g, b, _ = zen[-6.0]
    assert b > 1.5 * g > 1.5 * r > 0, zen[-6.0]
    for brighter, darker in ((-6.0, -12.0), (-12.0, -18.0)):
        assert mean[brighter][1] > 5 * mean[darker][1], (brighter, mean)
        assert zen[brighter][1] > 5 * zen[darker][1], (brighter, zen)
        assert zen[darker][3] > 0.0


def test_orders_increase_monotonically_and_converge():
    # Each order adds light (J_n >= 0); the sum converges geometrically: orders 8 -> 10 change
    # the sky by < 0.1% (measured 0.003%) on the seeds' Earth (optical depth 0.11 at 550 nm;
    # `earth`'s 0.23 converges more slowly: 0.36% at Sun -4 deg). Float32 tables so that
    # storage rounding does not blur the comparison.
    dirs = sphere(200, 4, upper=True)
    prev = None
    res = {}
    for n in (1, 2, 3, 4, 6, 8, 10):
        pa = tables("earth_bruneton", orders=n, **SMALL)
        assert pa.orders_computed == n
        for el in (40.0, -4.0):
            L, _ = probe.sky_radiance(pa, dirs, direction_from_angles(el, 90.0))
            res[(n, el)] = to_xyzs(L)
    for el in (40.0, -4.0):
        prev = None
        for n in (1, 2, 3, 4, 6, 8, 10):
            cur = res[(n, el)]
            if prev is not None:
                assert np.all(cur >= prev * (1 - 1e-5) - 1e-12), (n, el)
            prev = cur
        change = np.abs(res[(10, el)] / res[(8, el)] - 1).max()
        assert change < 1e-3, (el, change)
    assert np.mean(res[(4, 40.0)][:, 1]) > 1.2 * np.mean(res[(1, 40.0)][:, 1])


def test_tolerance_stops_early_and_progress_reaches_one(ctx):
    pa = tables(orders=10, tolerance=0.02, **SMALL)
    assert 3 <= pa.orders_computed < 10
    calls = []
    pa = precompute(
        ctx,
        preset("earth"),
        PrecomputeConfig(orders=3, **SMALL),
        progress=lambda stage, f: calls.append((stage, f)),
    )
    fractions = [f for _, f in calls]
    assert fractions == sorted(fractions) and fractions[-1] == 1.0 and len(calls) > 5
    assert {"transmittance", "density", "single_scattering", "irradiance"} <= {s for s, _ in calls}
    assert pa.timings["total"] > 0 and set(pa.timings) >= {"transmittance", "density", "total"}
    pa.release()


@pytest.mark.gl
@pytest.mark.parametrize(
    "atmosphere, changes",
    [
        ("earth", dict(wavelengths="fast")),  # one group: 4 nu per fragment
        # a spectral Mie phase function (MIE_LOBES) and the orders >= 2 at 16 wavelengths (4
        # groups: 2 nu per fragment), 16-bit log table
        ("mars", dict(wavelengths="accurate", ms_wavelengths="same", ms_dtype="u2")),
    ],
)
def test_several_views_per_fragment_give_the_same_tables(ctx, monkeypatch, atmosphere, changes):
    # The density pass, the field of the orders >= 2 and their table's pass compute several nu
    # (azimuths) per fragment, one draw buffer each, reordered on the read-back
    # (precompute.views_per_fragment, interleave_views); with one per fragment they draw the
    # plain layout. They do the same
    # sums in the same order, so every table must be bit-identical (a misplaced nu, group or
    # Sun cosine would move values by percents).
    config = PrecomputeConfig(orders=3, **{**SMALL, **changes})
    params = preset(atmosphere)
    fast = precompute(ctx, params, config).to_arrays()
    monkeypatch.setattr(precompute_module, "views_per_fragment", lambda n_nu, groups: 1)
    plain = precompute(ctx, params, config).to_arrays()
    assert precompute_module.views_per_fragment(4, 1) == 1
    for name, want in plain.items():
        assert np.array_equal(fast[name], want), name
    assert np.ptp(plain["multiple_scattering"].astype(np.float64)) > 0


@pytest.mark.gl
def test_leaving_out_negligible_mie_keeps_the_tables(ctx, monkeypatch):
    # The density pass leaves J's Mie sum out of the layers above the aerosols (NO_MIE, with
    # the Rayleigh sum from the field's moments). SMALL's 8 layers of J lie at 0, 2, 8, 18,
    # 33, 51, 73 and 100 km: the top four are left out. Against every layer with its Mie sum
    # (MIE_NEGLIGIBLE = 0), the tables may move by float32 rounding only: ln J is stored in
    # float32 (2e-6 of J's value per step at ln J ~ -20) and goes through three orders.
    config = PrecomputeConfig(orders=4, **SMALL)
    params = preset("earth")
    runs = precompute_module.mie_runs(params, config.multiple_wavelengths, config.ms_size[0])
    assert runs == [(0, 4, False), (4, 4, True)]
    fast = precompute(ctx, params, config).to_arrays()
    monkeypatch.setattr(precompute_module, "MIE_NEGLIGIBLE", 0.0)
    assert precompute_module.mie_runs(params, config.multiple_wavelengths, 8) == [(0, 8, False)]
    every = precompute(ctx, params, config).to_arrays()
    for name in ("transmittance", "scattering", "single_mie"):
        assert np.array_equal(fast[name], every[name]), name
    got, want = fast["multiple_scattering"], every["multiple_scattering"]  # ln of the values
    assert np.abs(got.astype(np.float64) - want).max() < 2e-5
    irr, irr_want = fast["irradiance_spectral"], every["irradiance_spectral"]
    assert np.abs(irr - irr_want).max() <= 2e-5 * np.abs(irr_want).max()


@pytest.mark.gl
@pytest.mark.parametrize("parts", [1, 3])
def test_sky_irradiance_drawn_in_parts_is_the_same_sum(ctx, monkeypatch, parts):
    # The sky irradiance table is drawn in IRRADIANCE_PARTS copies, in tiles of their own, each
    # summing a share of the directions (a CPU rasterizer draws a tile on one thread), and the
    # copies are summed after the read-back. In one part or three (a count that does not
    # divide the 8 cosines) the sum is the same to float32 rounding: ln E within 1e-5 (a
    # float32 sum of 64 terms in another order; measured 3.8e-6), every other table equal.
    config = PrecomputeConfig(orders=2, **SMALL)
    params = preset("earth")
    drawn = precompute(ctx, params, config).to_arrays()
    monkeypatch.setattr(precompute_module, "IRRADIANCE_PARTS", parts)
    other = precompute(ctx, params, config).to_arrays()
    for name in ("transmittance", "scattering", "single_mie", "multiple_scattering"):
        assert np.array_equal(drawn[name], other[name]), name
    ln_e, ln_e_other = drawn["irradiance_spectral"], other["irradiance_spectral"]
    assert np.abs(ln_e - ln_e_other).max() < 1e-5


def test_broadened_lobes_merged_are_the_same_phase_function():
    # The density pass of the orders >= 2 caps a spectral phase function's lobes at
    # MS_MIE_LOBE_G_MAX; inputs.broadened_lobe_uniforms merges the lobes that then share a g
    # (Mars: 10 lobes -> 6). Summed with physics.phase.henyey_greenstein at 2001 cosines and
    # every multiple-scattering wavelength, the merged lobes give the capped ones' phase
    # function to float64 rounding.
    params = preset("mars")
    wavelengths = PrecomputeConfig().multiple_wavelengths
    g_max = precompute_module.MS_MIE_LOBE_G_MAX
    mu = np.linspace(-1.0, 1.0, 2001)

    def phase(uniforms, cap):
        g = np.minimum(np.asarray(uniforms["u_mie_lobe_g"]), cap)
        weights = np.asarray(uniforms["u_mie_lobe_weight"]).reshape(-1, g.size, 4)
        lobes = np.stack([henyey_greenstein(mu, gj) for gj in g])  # (lobes, cosines)
        return np.einsum("klw,lc->kwc", weights, lobes)

    merged = broadened_lobe_uniforms(params, wavelengths, g_max)
    assert len(merged["u_mie_lobe_g"]) == 6 and max(merged["u_mie_lobe_g"]) == g_max
    want = phase(mie_lobe_uniforms(params, wavelengths), g_max)
    np.testing.assert_allclose(phase(merged, 1.0), want, rtol=1e-12)


def test_mie_is_kept_wherever_aerosols_are():
    # J's Mie sum is left out by layer, where the aerosols are negligible, not above an
    # altitude: a haze that ends at 13 km and a volcanic veil at 21-30 km (zero between and
    # above) keep it in the layers of each and leave it out of those between and above. The
    # layers of 32 lie at (k / 31)^2 x 100 km: k = 11 at 12.7 km (in the haze's fade to its
    # end), 12-13 at 15.1 and 17.7 km (clear), 14-17 at 20.5-30.2 km (the veil and its
    # edges), 18 at 33.9 km (clear).
    params = preset("earth")
    alt_km = [0, 2, 4, 8, 12, 13, 19, 21, 30, 32, 100]
    values = [1, math.exp(-2 / 1.2), math.exp(-4 / 1.2), math.exp(-8 / 1.2), 4.5e-5, 0, 0,
              1e-3, 1e-3, 0, 0]  # fmt: skip
    veiled = params.with_(mie_density=DensityProfile.tabulated(np.array(alt_km) * 1e3, values))
    wl = PrecomputeConfig().multiple_wavelengths
    assert precompute_module.mie_runs(veiled, wl, 32) == [
        (0, 12, False), (12, 2, True), (14, 4, False), (18, 14, True),
    ]  # fmt: skip
    # the default Earth's 1.2 km haze falls below 1e-10 of the air's scattering from 30.2 km
    # (k = 17) up
    assert precompute_module.mie_runs(params, wl, 32) == [(0, 17, False), (17, 15, True)]


@pytest.mark.gl
@pytest.mark.parametrize(
    "atmosphere, changes",
    [
        ("earth", dict(wavelengths="fast")),
        ("mars", dict(directions=(6, 4, 7))),  # a spectral phase function; an odd n_phi
    ],
)
def test_the_field_mirrored_about_the_suns_plane_is_the_field(
    ctx, monkeypatch, atmosphere, changes
):
    # The field pass draws the azimuths on one side of the Sun's vertical plane and mirrors
    # them (drawn_azimuths, mirror_azimuths): the air is spherically symmetric, so a direction
    # and its mirror image have the same radiance, and drawn they come out bit-identical (the
    # same nu, the same rays); every table must be the same as with all azimuths drawn.
    config = PrecomputeConfig(orders=3, **{**SMALL, **changes})
    params = preset(atmosphere)
    half = precompute(ctx, params, config).to_arrays()
    monkeypatch.setattr(precompute_module, "drawn_azimuths", lambda n_phi: n_phi)
    every = precompute(ctx, params, config).to_arrays()
    for name, want in every.items():
        assert np.array_equal(half[name], want), name


@pytest.mark.gl
@pytest.mark.parametrize("directions", [(12, 6, 16), (6, 4, 7)])  # odd: a self-mirrored azimuth
def test_density_of_an_isotropic_field_is_the_scattering_coefficient(ctx, directions):
    # J = integral beta P L dw of a radiance L the same from every direction is beta L: both
    # phase functions integrate to one (the Rayleigh sum's 1 + (v.w)^2 is a polynomial the
    # sphere's product rule integrates exactly; the Mie sum is self-normalized). So a field of
    # L dw = dw must give J = beta_R rho_R + beta_M rho_M in every texel of the grid, layers
    # with the Mie sum and without (NO_MIE, from the moments) alike, and whatever the view:
    # this checks the density pass's sums over the mirrored azimuth pairs and its moments,
    # independently of the field pass.
    params = preset("earth")
    cfg = PrecomputeConfig(**{**SMALL, "ms_size": (8, 16, 8, 8), "directions": directions})
    pc = precompute_module._Precomputation(ctx, params, cfg, None)
    pc.transmittance = precompute_module.TransmittanceTable(
        ctx, params, cfg.transmittance_size, cfg.transmittance_steps
    )
    pc.geometry = precompute_module.geometry_inputs(params)
    pc.transmittance_inputs = precompute_module.TransmittanceInputs(
        pc.transmittance.texture, pc.transmittance.size
    )
    pc._setup_ms()
    n_r, _, n_mu_s, _ = cfg.ms_size
    n_sky, n_ground, n_phi = cfg.directions
    rb, rt = params.bottom_radius_m / 1e3, params.top_radius_m / 1e3
    rho = math.sqrt(rt * rt - rb * rb) * np.arange(n_r) / (n_r - 1)
    r = np.sqrt(rho * rho + rb * rb)
    mu_h = -np.sqrt(np.maximum(1.0 - (rb / r) ** 2, 0.0))
    weights = []  # (n_r, cosines): the solid angle of a direction (precompute_common's mu_node)
    for rule, span in (
        (gauss_legendre(n_sky, -1, 1), 1.0 - mu_h),
        (gauss_legendre(n_ground, -1, 1), 1.0 + mu_h),
    ):
        s = 0.5 * (rule[:, 0] + 1.0)
        weights.append(span[:, None] * s * rule[:, 1] * (2.0 * math.pi / n_phi))
    dw = np.repeat(np.concatenate(weights, axis=1), n_phi, axis=1)  # (n_r, n_dir)
    field = np.repeat(dw[:, None, :, None], n_mu_s, axis=1).reshape(n_r * n_mu_s, -1, 1)
    pc.field.write(np.ascontiguousarray(np.repeat(field, 4, axis=2), dtype="f4").tobytes())
    j = np.exp(pc._density().astype(np.float64))  # (r, mu, nu * mu_s, 4) per km
    # the densities where the shader evaluates them: at float32 radii (km), 0.5 m apart there
    h = (
        np.float32(math.sqrt(rt * rt - rb * rb))
        * np.arange(n_r, dtype=np.float32)
        / np.float32(n_r - 1)
    )
    alt_km = np.sqrt(h * h + np.float32(rb) ** 2) - np.float32(rb)
    rho_r, rho_m, _ = densities(params, alt_km.astype(np.float64) * 1e3).T
    c = params.coefficients(cfg.multiple_wavelengths)
    beta = 1e3 * (np.outer(rho_r, c["rayleigh_scattering"]) + np.outer(rho_m, c["mie_scattering"]))
    runs = precompute_module.mie_runs(params, cfg.multiple_wavelengths, n_r)
    assert runs[-1][2] and not runs[0][2]  # both kinds of layers are drawn
    # within 2 float32 steps of ln J (|ln J| of 2 to 20 here: 2e-7 to 2e-6 of J each; measured
    # 1.4e-6 at most)
    rel = np.abs(j / beta[:, None, None, :] - 1.0)
    assert rel.max() < 4e-6, rel.max(axis=(1, 2, 3))


def test_mirror_azimuths_layout():
    # azimuth n_phi - 1 - j is azimuth j's mirror image, per group and cosine; an odd n_phi's
    # middle azimuth (pi) is its own
    for n_phi, want in ((4, [0, 1, 1, 0]), (5, [0, 1, 2, 1, 0]), (1, [0])):
        drawn = precompute_module.drawn_azimuths(n_phi)
        half = np.arange(3 * drawn, dtype=float).reshape(1, 3 * drawn, 1).repeat(4, axis=2)
        full = precompute_module.mirror_azimuths(half, n_phi)
        assert full.shape == (1, 3 * n_phi, 4)
        blocks = full[0, :, 0].reshape(3, n_phi)
        for b in range(3):
            assert blocks[b].tolist() == [b * drawn + k for k in want]


def test_views_per_fragment_fit_the_draw_buffers():
    # one draw buffer per (group, nu), at most 8 (OpenGL 3.3's guaranteed minimum), and at
    # most MAX_VIEWS (4) views a fragment
    views = precompute_module.views_per_fragment
    assert [views(8, 1), views(8, 2), views(8, 4), views(8, 8), views(6, 1), views(7, 2)] == [
        4, 4, 2, 1, 3, 1,
    ]  # fmt: skip


def test_sky_irradiance_against_monte_carlo():
    # Sky (diffuse) irradiance on the ground at a 60 deg Sun, every order, against the Monte
    # Carlo estimate (reference.ms.ground_irradiance_mc, standard error ~0.6%). Bound 2%.
    pa = tables(wavelengths=(440.0, 550.0, 680.0, 700.0), output="spectral", orders=10)
    zenith = math.radians(30.0)
    want, err = mc.ground_irradiance_mc(
        pa.params, [440.0, 550.0, 680.0], zenith, n_paths=8192, seed=2
    )
    _, sky = probe.sun_and_sky_irradiance(pa, [[0.0, 0.0, 1.0]], mc.sun_direction(zenith))
    assert np.all(np.abs(sky[0, :3] / want - 1) < 0.02 + 2 * err / want), (sky[0, :3], want, err)


# ------------------------------------------------------------------------------------------
# Lookup API details
# ------------------------------------------------------------------------------------------


def test_aerial_perspective_and_shadows_are_consistent():
    pa = tables(**SMALL, orders=3)
    sun = direction_from_angles(25.0, 90.0)
    dirs = np.array([[0.0, 0.7071, 0.7071], [0.9, 0.0, 0.1], [-0.9, 0.3, 0.05]])
    full, _ = probe.sky_radiance(pa, dirs, sun)
    # To a point beyond the atmosphere: the whole ray's in-scatter.
    far = probe.sky_radiance_to_point(pa, dirs, 5000.0, sun)
    np.testing.assert_allclose(far, full, rtol=2e-3, atol=1e-3)
    # Nothing in front of the camera, and more light the further the point.
    near = probe.sky_radiance_to_point(pa, dirs, 1e-6, sun)
    assert np.abs(near).max() < 1e-3 * np.abs(full).max()
    lum = [probe.sky_radiance_to_point(pa, dirs, d, sun)[:, 1] for d in (1.0, 10.0, 50.0)]
    assert np.all(lum[0] < lum[1]) and np.all(lum[1] <= lum[2] * (1 + 1e-3))
    # Light shafts: no shadow changes nothing; a shadow over the whole ray leaves no light.
    same, _ = probe.sky_radiance(pa, dirs, sun, shadow_length_km=0.0)
    np.testing.assert_allclose(same, full, rtol=1e-6)
    dark, _ = probe.sky_radiance(pa, dirs, sun, shadow_length_km=1e4)
    assert np.abs(dark).max() < 1e-3 * np.abs(full).max()
    part, _ = probe.sky_radiance(pa, dirs, sun, shadow_length_km=5.0)
    assert np.all(part[:, 1] < full[:, 1]) and np.all(part[:, 1] > 0)


def test_camera_in_space_sees_the_top_of_the_atmosphere():
    # A camera outside the atmosphere is moved to where its ray enters it; rays that miss it
    # see nothing (no Sun disk in these lookups).
    pa = tables(**SMALL, orders=2)
    sun = direction_from_angles(30.0, 0.0)
    Rt = pa.params.top_radius_m / 1e3
    v = np.array([[0.0, 0.3, -1.0]])
    v /= np.linalg.norm(v)
    entry = np.array([[0.0, 0.0, Rt - 1e-4]])
    a, col_a = probe.sky_radiance(pa, v, sun, points_km=entry - v * 3000.0)
    b, col_b = probe.sky_radiance(pa, v, sun, points_km=entry)
    np.testing.assert_allclose(a, b, rtol=2e-3)
    np.testing.assert_allclose(col_a, col_b, rtol=2e-3)
    miss, col = probe.sky_radiance(pa, [[0.0, 0.0, 1.0]], sun, points_km=[[0.0, 0.0, Rt + 10.0]])
    assert np.all(miss == 0.0) and np.all(col == 0.0)


def test_spectral_debug_mode_matches_luminance_mode():
    # With 4 wavelengths the luminance tables are a linear map of the spectral ones, except for
    # what is interpolated in logarithms (orders >= 2, irradiance), which differs at second
    # order: within 0.3%.
    from skydome.spectra import spectral_to_rgbs_matrix

    wl = (440.0, 510.0, 580.0, 650.0)
    spec = tables(output="spectral", orders=3, **{**SMALL, "wavelengths": wl})
    lum = tables(orders=3, **{**SMALL, "wavelengths": wl})
    dirs = sphere(100, 6, upper=True)
    sun = direction_from_angles(15.0, 45.0)
    s, _ = probe.sky_radiance(spec, dirs, sun)
    y, _ = probe.sky_radiance(lum, dirs, sun)
    want = to_xyzs(s @ spectral_to_rgbs_matrix(np.array(wl)).T)
    np.testing.assert_allclose(to_xyzs(y), want, rtol=3e-3, atol=1e-6 * np.abs(want).max())


def test_arrays_round_trip(ctx):
    for extra in ({}, {"dtype": "f2", "ms_dtype": "u2"}):
        pa = tables(orders=2, **{**SMALL, **extra})
        arrays = pa.to_arrays()
        again = PrecomputedAtmosphere.from_arrays(ctx, pa.params, pa.config, arrays)
        dirs = sphere(64, 9)
        sun = direction_from_angles(10.0, 200.0)
        a, _ = probe.sky_radiance(pa, dirs, sun, altitude_m=500.0, ground="sun_and_sky")
        b, _ = probe.sky_radiance(again, dirs, sun, altitude_m=500.0, ground="sun_and_sky")
        np.testing.assert_array_equal(a, b)
        bad = dict(arrays, scattering=arrays["scattering"][:-1])
        with pytest.raises(CacheError):
            PrecomputedAtmosphere.from_arrays(ctx, pa.params, pa.config, bad)
        again.release()


def test_float16_tables_match_float32():
    # float16 (scaled) single-scattering tables and 16-bit logarithmic multiple scattering:
    # storage steps of 0.05% and 0.07%, so lookups agree to 0.2%.
    dirs = sphere(200, 10, upper=True)
    sun = direction_from_angles(8.0, 100.0)
    a, _ = probe.sky_radiance(tables(orders=3, **SMALL), dirs, sun)
    b, _ = probe.sky_radiance(
        tables(orders=3, **{**SMALL, "dtype": "f2", "ms_dtype": "u2"}), dirs, sun
    )
    np.testing.assert_allclose(to_xyzs(b), to_xyzs(a), rtol=2e-3, atol=1e-6 * np.abs(a).max())


def test_config_validation_and_key():
    a, b = PrecomputeConfig(), PrecomputeConfig(orders=5)
    assert a.key() == PrecomputeConfig().key() and a.key() != b.key()
    assert (
        PrecomputeConfig(wavelengths="fast").key()
        == PrecomputeConfig(wavelengths=(440.0, 510.0, 580.0, 650.0)).key()
    )
    for bad in (
        dict(orders=0),
        dict(scattering_size=(32, 127, 32, 8)),
        dict(output="spectral"),  # 16 wavelengths
        dict(dtype="f8"),
        dict(directions=(0, 4, 16)),
        dict(single_samples=15),
        dict(mu_s_min=0.5),
    ):
        with pytest.raises(ParameterError):
            PrecomputeConfig(**bad)
    # The cut-off covers astronomical twilight (-18 deg) on Earth and on thin atmospheres.
    mu = PrecomputeConfig().resolved_mu_s_min(6_360_000.0, 6_460_000.0, -0.2)
    assert mu < math.sin(math.radians(-18.0))
    mu = PrecomputeConfig().resolved_mu_s_min(6_360_000.0, 6_420_000.0, -0.2)
    assert mu < math.sin(math.radians(-18.0))
    assert PrecomputeConfig().memory_bytes()["scattering"] > 0
    assert sum(PrecomputeConfig().memory_bytes().values()) <= 32 * 2**20


def test_float16_conversion_has_numpys_bits():
    """precompute.to_float16 (the single-scattering tables' float16 encoding, with the values
    below float16's normal range rounded by integer arithmetic) gives the bits of NumPy's
    IEEE conversion: every 37th float32 below 2^-14 (0.9e9 / 37 values, ties to even among
    them), both signs, zero, the normal boundary and a random spread over 20 decades."""
    tiny = np.arange(0, np.float32(2.0**-14).view(np.uint32) + 1, 37, dtype=np.uint32)
    tiny = tiny.view(np.float32)
    ties = (np.arange(0, 2048, dtype=np.float32) + np.float32(0.5)) * np.float32(2.0**-24)
    rng = np.random.default_rng(9)
    spread = (rng.random(200_000) * 10.0 ** rng.uniform(-16, 4, 200_000)).astype(np.float32)
    values = np.concatenate([tiny, -tiny[::5], ties, spread, -spread[::3], [0.0, -0.0]])
    values = values.astype(np.float32)
    with np.errstate(under="ignore"):
        expected = values.astype(np.float16).view(np.uint16)
    assert np.array_equal(precompute_module.to_float16(values).view(np.uint16), expected)
