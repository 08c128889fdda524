"""Density profiles: the tabulated form (Python and GLSL), the layered form left as it was, and
the shipped U.S. Standard Atmosphere 1976."""

import json
import math
from dataclasses import dataclass

import numpy as np
import pytest

from skydome.atmosphere import PRESETS, DensityLayer, DensityProfile, preset
from skydome.atmosphere.inputs import AirGeometry, geometry_inputs, profile_table_grid
from skydome.atmosphere.params import MAX_TABLE_SAMPLES
from skydome.atmosphere.precompute_config import PrecomputeConfig
from skydome.atmosphere.standard_atmosphere import air_density_profile, us_standard_1976
from skydome.atmosphere.tables import tables_key
from skydome.atmosphere.transmittance import TransmittanceTable
from skydome.core.cameras import DirectionsCamera, direction_from_angles
from skydome.errors import ParameterError
from skydome.gpu import FullscreenPass
from skydome.gpu.inputs import ShaderInputs
from skydome.reference import single as ref
from tests.air_frames import AirFrames
from tests.conftest import TINY_TABLES


def layered_earth():
    """Bruneton's layered Earth profiles (seed 001 appendix B: air an 8 km exponential, aerosol
    1.2 km, ozone a tent at 25 +- 15 km, top at 100 km) on the spectra of the ``earth_nishita``
    preset: a fixed layered atmosphere, whatever the presets become."""
    return preset("earth_nishita").with_(
        top_radius_m=6_460_000.0,
        rayleigh_density=DensityProfile.exponential(8000.0),
        mie_density=DensityProfile.exponential(1200.0),
        absorption_density=DensityProfile.tent(25_000.0, 15_000.0),
    )


# --------------------------------------------------------------------------------------------
# The shipped table against the published standard
# --------------------------------------------------------------------------------------------

# U.S. Standard Atmosphere, 1976 (NOAA-S/T 76-1562), Table I, at geometric altitudes that are
# samples of the shipped table: Z (m), T (K), P (Pa), rho (kg/m^3).
TABLE_I = [
    (0.0, 288.150, 1.01325e5, 1.2250),
    (10_000.0, 223.252, 2.6500e4, 4.1351e-1),
    (20_000.0, 216.650, 5.5293e3, 8.8910e-2),
    (30_000.0, 226.509, 1.1970e3, 1.8410e-2),
    (40_000.0, 250.350, 2.8714e2, 3.9957e-3),
    (50_000.0, 270.650, 7.9779e1, 1.0269e-3),
    (60_000.0, 247.021, 2.1959e1, 3.0968e-4),
    (70_000.0, 219.585, 5.2209, 8.2829e-5),
    (80_000.0, 198.639, 1.0524, 1.8458e-5),
    (86_000.0, 186.87, 3.7338e-1, 6.958e-6),
    (90_000.0, 186.87, 1.8359e-1, 3.416e-6),
    (95_000.0, 188.42, 7.5966e-2, 1.393e-6),
    (100_000.0, 195.08, 3.2011e-2, 5.604e-7),
]
# Sea-level number density, Table I: 2.5470e25 m^-3.
N_SEA_LEVEL = 2.5470e25


def _row(std, z_m):
    (k,) = np.flatnonzero(std.altitude_m == z_m)
    return k


def test_table_reproduces_the_standard_at_its_own_altitudes():
    # The bound, 0.5 %; the values printed in Table I have 5 digits (4 above 86 km),
    # so agreement is expected to their rounding (measured: 8e-5 at most, at 86 km).
    std = us_standard_1976()
    assert std.altitude_m[0] == 0.0 and std.altitude_m[-1] == 100_000.0
    np.testing.assert_array_equal(np.diff(std.altitude_m), 500.0)
    for z, t, p, rho in TABLE_I:
        k = _row(std, z)
        assert std.temperature_K[k] == pytest.approx(t, rel=5e-3), z
        assert std.pressure_Pa[k] == pytest.approx(p, rel=5e-3), z
        assert std.density_kg_m3[k] == pytest.approx(rho, rel=5e-3), z
    assert std.number_density_m3[0] == pytest.approx(N_SEA_LEVEL, rel=5e-3)
    # The lower stratosphere is isothermal at 216.65 K from 11 to 20 km' geopotential
    # (11.019 to 20.063 km geometric): every sample in between, to the table's rounding.
    iso = (std.altitude_m >= 11_500.0) & (std.altitude_m <= 20_000.0)
    np.testing.assert_allclose(std.temperature_K[iso], 216.65, rtol=1e-6)


def test_table_interpolates_to_the_layer_bases():
    # Table 4 of the standard: pressure and density at the layer bases H_b = 11, 20, 32, 47,
    # 51, 71 km' and at 84.852 km' (Z = 86 km), geometric Z = r0 H / (r0 - H), r0 = 6356.766 km.
    # These fall between samples (except 86 km), where the table is log-linear: the slope of
    # ln(rho) jumps by at most 3e-5 /m there (at the tropopause), so a 500 m gap errs by at
    # most 3e-5 * 500 / 4 = 0.4 %, inside the 0.5 % (measured: 6e-4 at most).
    bases = [  # H_b (m'), P_b (Pa), rho_b (kg/m^3)
        (11_000.0, 22_632.06, 0.36392),
        (20_000.0, 5_474.889, 0.088035),
        (32_000.0, 868.0187, 0.013225),
        (47_000.0, 110.9063, 1.4275e-3),
        (51_000.0, 66.93887, 8.6160e-4),
        (71_000.0, 3.956420, 6.4211e-5),
        (84_852.0, 0.3733836, 6.958e-6),
    ]
    std = us_standard_1976()
    r0 = 6_356_766.0
    for h, p, rho in bases:
        z = r0 * h / (r0 - h)
        got_p = math.exp(np.interp(z, std.altitude_m, np.log(std.pressure_Pa)))
        got_rho = math.exp(np.interp(z, std.altitude_m, np.log(std.density_kg_m3)))
        assert got_p == pytest.approx(p, rel=5e-3), h
        assert got_rho == pytest.approx(rho, rel=5e-3), h


def test_air_density_profile_is_the_normalised_number_density():
    std = us_standard_1976()
    prof = air_density_profile()
    assert prof.is_tabulated and prof.density(0.0) == 1.0
    np.testing.assert_allclose(
        prof.density(std.altitude_m), std.number_density_m3 / std.number_density_m3[0], rtol=1e-12
    )
    # The motivation: the 8 km exponential of the seeds holds 2-3x too much air
    # between 40 and 80 km (measured 2.21x).
    exp8 = DensityProfile.exponential(8000.0)
    layer = prof.column_m(80e3) - prof.column_m(40e3)
    layer_exp = exp8.column_m(80e3) - exp8.column_m(40e3)
    assert 2.0 < layer_exp / layer < 3.0


# --------------------------------------------------------------------------------------------
# The tabulated form in Python
# --------------------------------------------------------------------------------------------


def test_tabulated_interpolation_rules():
    # Log-linear between positive samples: the geometric mean at the middle; linear next to a
    # zero; constant below the first sample; above the last, the last gap's exponential when it
    # decreases, the last value otherwise.
    p = DensityProfile.tabulated([0.0, 1000.0, 2000.0, 3000.0], [1.0, 0.25, 0.0, 0.5])
    np.testing.assert_allclose(p.density([-50.0, 500.0, 1500.0, 2500.0]), [1.0, 0.5, 0.125, 0.25])
    q = DensityProfile.tabulated([0.0, 1000.0], [1.0, 0.5])
    np.testing.assert_allclose(q.density([3000.0]), [0.125], rtol=1e-12)
    np.testing.assert_allclose(p.density([5000.0]), [0.5])  # rising last gap: held
    z = DensityProfile.tabulated([0.0, 1000.0], [1.0, 0.0])
    assert z.density(5000.0) == 0.0


def test_sampled_exponential_is_the_exponential():
    # A log-linear table of exp(-h/H) is that exponential everywhere, so its density and
    # column are the closed forms (to float64 rounding: 1e-12).
    h = np.arange(0.0, 100_001.0, 500.0)
    tab = DensityProfile.tabulated(h, np.exp(-h / 8000.0))
    x = np.random.default_rng(3).uniform(0.0, 120_000.0, 1000)
    np.testing.assert_allclose(tab.density(x), np.exp(-x / 8000.0), rtol=1e-12)
    for top in (100_000.0, 60_000.0, 123_456.0):
        want = 8000.0 * (1.0 - math.exp(-top / 8000.0))
        assert tab.column_m(top) == pytest.approx(want, rel=1e-12)


@pytest.mark.parametrize("which", ["us_standard", "with_zeros", "irregular"])
def test_column_m_against_a_fine_trapezoid(which):
    # The exact per-piece integral against the trapezoidal rule on 1 m steps, whose error is
    # h^2/12 |f''| per unit length ~ 1e-8 relative here (f''/f <= 1/(1 km)^2); bound 1e-6.
    if which == "us_standard":
        prof, top = air_density_profile(), 100_000.0
    elif which == "with_zeros":
        prof = DensityProfile.tabulated(
            [0.0, 10e3, 20e3, 25e3, 30e3, 40e3], [0.0, 0.3, 1.0, 0.6, 0.0, 0.0]
        )
        top = 60_000.0
    else:
        rng = np.random.default_rng(5)
        alt = np.concatenate([[-300.0], np.sort(rng.uniform(0.0, 80e3, 60))])
        prof = DensityProfile.tabulated(alt, np.exp(rng.normal(size=61)))
        top = 90_000.0
    h = np.linspace(0.0, top, int(top) + 1)
    assert prof.column_m(top) == pytest.approx(np.trapezoid(prof.density(h), h), rel=1e-6)


@pytest.mark.parametrize(
    "altitudes, values, match",
    [
        ([0.0], [1.0], "2 to"),
        (np.arange(MAX_TABLE_SAMPLES + 1.0), np.ones(MAX_TABLE_SAMPLES + 1), "2 to"),
        ([0.0, 1.0, 2.0], [1.0, 0.5], "as many"),
        ([0.0, 2.0, 1.0], [1.0, 0.5, 0.2], "increase"),
        ([0.0, 1.0, 1.0], [1.0, 0.5, 0.2], "increase"),
        ([0.0, 1.0], [1.0, -0.1], ">= 0"),
        ([0.0, 1.0], [1.0, math.nan], "finite"),
        ([0.0, math.inf], [1.0, 0.5], "finite"),
        ([10.0, 20.0], [1.0, 0.5], "ground"),
        ([0.0, "x"], [1.0, 0.5], "numeric"),
    ],
)
def test_bad_tables_raise(altitudes, values, match):
    with pytest.raises(ParameterError, match=match):
        DensityProfile.tabulated(altitudes, values)


def test_a_profile_is_layered_or_tabulated_not_both():
    with pytest.raises(ParameterError, match="not both"):
        DensityProfile((DensityLayer(constant=1.0),), altitudes_m=(0.0, 1.0), values=(1.0, 1.0))


def test_tabulated_profiles_are_values_in_params_and_cache_keys():
    # Immutable and hashable; equal tables make equal parameters, digests and table cache
    # keys; any changed sample changes them; to_dict is plain JSON.
    a = layered_earth().with_(rayleigh_density=air_density_profile())
    b = layered_earth().with_(rayleigh_density=air_density_profile())
    assert a == b and hash(a) == hash(b) and a.digest() == b.digest()
    with pytest.raises(AttributeError):
        a.rayleigh_density.values = (1.0,)
    values = list(air_density_profile().values)
    values[100] *= 1.0 + 1e-9
    c = layered_earth().with_(
        rayleigh_density=DensityProfile.tabulated(air_density_profile().altitudes_m, values)
    )
    assert c.digest() != a.digest() != layered_earth().digest()
    cfg = PrecomputeConfig()
    assert tables_key(a, cfg) == tables_key(b, cfg) != tables_key(c, cfg)
    d = json.loads(json.dumps(a.to_dict()))
    assert d["rayleigh_density"]["values"] == list(a.rayleigh_density.values)
    assert set(d["mie_density"]) == {"layers"}  # a layered profile keeps its old form


# --------------------------------------------------------------------------------------------
# GLSL against Python
# --------------------------------------------------------------------------------------------

_DENSITY_PASS = """
#include "common/atmosphere_common.glsl"
uniform float u_altitude_scale;  // km per texel
out vec4 frag;
void main() {
    float h = (gl_FragCoord.x - 0.5) * u_altitude_scale - 0.25;
    frag = vec4(densities(h), h);
}
"""


@dataclass(frozen=True)
class AltitudeScale(ShaderInputs):
    """The density test pass's altitude step (km per texel)."""

    u_altitude_scale: float


def glsl_densities(ctx, params, top_km: float, n: int = 4096) -> tuple[np.ndarray, np.ndarray]:
    """Densities (n, 3) that common/atmosphere_common.glsl computes at n altitudes from -0.25 km to
    ``top_km``, and those altitudes (km, as the shader held them in float32)."""
    tex = ctx.texture((n, 1), 4, dtype="f4")
    fbo = ctx.framebuffer(color_attachments=[tex])
    fbo.viewport = (0, 0, n, 1)
    p = FullscreenPass(
        ctx, "density_test.glsl", inputs=(AirGeometry, AltitudeScale), source=_DENSITY_PASS
    )
    p.draw(fbo, geometry_inputs(params), AltitudeScale((top_km + 0.25) / (n - 1)))
    out = np.frombuffer(tex.read(), dtype=np.float32).reshape(n, 4).astype(np.float64)
    p.release()
    fbo.release()
    tex.release()
    return out[:, :3], out[:, 3]


def _ozone_like() -> DensityProfile:
    # A peaked profile with irregular gaps (whole kilometres, then 2.5 and 5 km) and a zero
    # at the top, like published ozone tables.
    alt = np.concatenate([np.arange(0.0, 26e3, 1e3), np.arange(27.5e3, 50e3, 2.5e3), [55e3, 60e3]])
    values = np.exp(-(((alt - 22e3) / 7e3) ** 2))
    values[-1] = 0.0
    return DensityProfile.tabulated(alt, values)


def test_glsl_tabulated_density_matches_python(ctx):
    # On the table's own grid (500 m for the standard atmosphere, the 500 m common divisor of
    # the irregular one) the shader interpolates as DensityProfile.density does, in float32:
    # ln(density) rounded to 2^-24 relative (|ln| <= 16: 1e-6) and the altitude to 1e-7 km
    # (times the slope of ln rho, <= 0.2 /km: 2e-8). Bound 1e-4 relative, plus 1e-9 absolute
    # for densities that are ~0 (the top of the zero-ended profile, linear there).
    p = layered_earth().with_(
        rayleigh_density=air_density_profile(), absorption_density=_ozone_like()
    )
    assert profile_table_grid(p.absorption_density, p.atmosphere_height_m) == (500.0, 201)
    got, h_km = glsl_densities(ctx, p, p.atmosphere_height_m / 1e3)
    want = ref.densities(p, h_km * 1e3)
    np.testing.assert_allclose(got, want, rtol=1e-4, atol=1e-9)
    assert want[:, 2].max() == pytest.approx(1.0, abs=1e-3) and want[-1, 2] == 0.0


def test_glsl_resampled_irregular_table(ctx):
    # Altitudes that are not whole metres (the standard atmosphere's air sampled every 613.9 m
    # from 0.37 m): resampled onto 256 nodes up to the top, 392 m apart. In a cell of width w
    # the chord of ln(density) misses each table sample k inside it by at most
    # |slope jump_k| w / 4, so |ln(GLSL / Python)| <= w/4 sum_k |jump_k| + 1e-5 (float32), the
    # bound asserted per cell. Overall the worst cell is the tropopause's (11.06 km, where the
    # slope of ln n jumps by 3e-5 /m): measured 1.55e-3, bound 2e-3. (On its own 500 m grid
    # the shipped table is not resampled: 1.7e-6, test above.)
    std = us_standard_1976()
    alt = np.concatenate([[0.0], 0.37 + 613.9 * np.arange(1, 163)])
    n = np.exp(np.interp(alt, std.altitude_m, np.log(std.number_density_m3)))
    prof = DensityProfile.tabulated(alt, n / n[0])
    p = layered_earth().with_(rayleigh_density=prof)
    step, count = profile_table_grid(prof, p.atmosphere_height_m)
    assert count == 256 and step == pytest.approx(100e3 / 255)
    got, h_km = glsl_densities(ctx, p, p.atmosphere_height_m / 1e3)
    h_m = h_km * 1e3
    err = np.abs(np.log(got[:, 0] / prof.density(h_m)))
    slope = np.diff(np.log(prof.values)) / np.diff(alt)
    jumps = np.abs(np.diff(slope))  # at alt[1:-1]
    per_cell = np.bincount(
        np.floor(alt[1:-1] / step).astype(int), weights=jumps, minlength=count
    ) * (step / 4.0)
    cell = np.clip(np.floor(np.maximum(h_m, 0.0) / step).astype(int), 0, count - 2)
    assert np.all(err <= per_cell[cell] + 1e-5)
    assert err.max() < 2e-3


def test_glsl_presets_density_matches_python(ctx):
    # Every preset, whatever its profiles' forms. Layered ones are evaluated as before (exp +
    # linear, clamped): float32 rounding only, bound 1e-5 relative + 1e-6 absolute (the ozone
    # tent's linear terms, a h + c with |a h| and |c| up to 3, cancel to ~0 at its ends: a few
    # float32 ulps of 3, measured 1.7e-7). Tabulated ones as in the test above, 1e-4.
    for name in [*PRESETS, "layered"]:
        p = layered_earth() if name == "layered" else preset(name)
        got, h_km = glsl_densities(ctx, p, p.atmosphere_height_m / 1e3)
        want = ref.densities(p, h_km * 1e3)
        profiles = (p.rayleigh_density, p.mie_density, p.absorption_density)
        for c, prof in enumerate(profiles):
            rtol = 1e-4 if prof.is_tabulated else 1e-5
            np.testing.assert_allclose(got[:, c], want[:, c], rtol=rtol, atol=1e-6, err_msg=name)


def test_transmittance_table_with_tabulated_profiles(ctx):
    # The transmittance (column density) table of the standard-atmosphere air and a tabulated
    # ozone against the float64 Gauss-Legendre columns of reference.single (exact to 1e-12
    # vertically: column_m). Air and Mie as for the layered presets (test_single_scattering),
    # 2e-4 relative (float32, Simpson's rule over 300 intervals); the ozone-like table bends
    # at each of its ~40 samples, where Simpson's rule (333 m steps vertically) errs by
    # O(slope jump x step^2): measured 3.2e-4 at the zenith, bound 5e-4. Plus 1e-6 km.
    p = layered_earth().with_(
        rayleigh_density=air_density_profile(), absorption_density=_ozone_like()
    )
    table = TransmittanceTable(ctx, p, size=(256, 64))
    t = table.read().astype(np.float64)
    table.release()
    Rb, Rt = p.bottom_radius_m / 1e3, p.top_radius_m / 1e3
    H = math.sqrt(Rt * Rt - Rb * Rb)
    h_tex, w_tex = t.shape[:2]
    for i, j in [(0, 0), (0, w_tex - 1), (h_tex // 2, w_tex // 3), (7, w_tex - 2), (20, 100)]:
        x_mu, x_r = j / (w_tex - 1), i / (h_tex - 1)
        rho = H * x_r
        rr = math.sqrt(rho * rho + Rb * Rb)
        d = (Rt - rr) + x_mu * (rho + H - (Rt - rr))
        mu = 1.0 if d == 0 else (H * H - rho * rho - d * d) / (2 * rr * d)
        want = ref.column_to_top(p, rr * 1e3, max(-1.0, min(1.0, mu))) / 1e3
        rtol = np.array([2e-4, 2e-4, 5e-4])
        assert np.all(np.abs(t[i, j] - want) <= rtol * want + 1e-6), (i, j, t[i, j], want)


# --------------------------------------------------------------------------------------------
# Frames: a tabulated exponential renders like the exponential
# --------------------------------------------------------------------------------------------

SMALL = TINY_TABLES  # (tests/conftest.py)


def _sampled(profile: DensityProfile, top_m: float) -> DensityProfile:
    h = np.arange(0.0, top_m + 1.0, 500.0)
    return DensityProfile.tabulated(h, profile.density(h))


def _sky_directions() -> np.ndarray:
    rng = np.random.default_rng(2)
    d = rng.normal(size=(400, 3))
    d[:, 2] = np.abs(d[:, 2]) + 0.02
    return d / np.linalg.norm(d, axis=1, keepdims=True)


@pytest.mark.parametrize("model", ["single", "precomputed"])
def test_tabulated_exponentials_reproduce_the_exponential_frame(model):
    # earth with its Rayleigh (8 km) and Mie (1.2 km) exponentials replaced by 500 m tables of
    # themselves, which are the same functions (test above), so the frames differ only by
    # float32 rounding (measured: 1e-7 single scattering, 6e-5 precomputed tables, whose
    # log-encoded entries amplify it): the bound, 0.5 %.
    base = layered_earth()
    top = base.atmosphere_height_m
    tab = base.with_(
        rayleigh_density=_sampled(base.rayleigh_density, top),
        mie_density=_sampled(base.mie_density, top),
    )
    dirs = _sky_directions()
    frames = []
    for p in (base, tab):
        if model == "single":
            r = AirFrames(p, model="single", spectral="fast", jitter=False)
        else:
            r = AirFrames(p, config=SMALL, cache=False, sky_view=False)
        for el in (30.0, 2.0, -4.0):
            sun = direction_from_angles(el, 90.0)
            frames.append(
                r.render(DirectionsCamera(dirs), 0, 0, sun_direction=sun).data[0].astype(float)
            )
        r.release()
    n = len(frames) // 2
    for a, b in zip(frames[:n], frames[n:], strict=True):
        y_a, y_b = a[:, 1], b[:, 1]
        np.testing.assert_allclose(y_b, y_a, rtol=5e-3, atol=1e-6 * y_a.max())
