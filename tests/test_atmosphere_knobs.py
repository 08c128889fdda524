"""Atmosphere knobs (ground albedo, AOD at 550 nm, Ångström exponent, total ozone, SSA):
read back by independent integrals, ranges, the ``hazy`` preset as a knob setting, cache
keys, and the physical direction of a change of AOD in a render."""

import math

import numpy as np
import pytest

from skydome.atmosphere import (
    HAZY_AEROSOL,
    PRESETS,
    DensityLayer,
    DensityProfile,
    Spectrum,
    earth,
    hazy,
    preset,
)
from skydome.errors import ParameterError
from skydome.spectra import ozone_cross_section

DU = 2.687e20  # molecules per m^2 (WMO definition of the Dobson unit)


def altitude_grid(params, step_m: float = 0.5) -> np.ndarray:
    """A fine altitude grid, ground to top, for trapezoid integrals (0.5 m steps: for the
    steepest profile here, e^(-h/1200 m), the trapezoid error is (dh/H)^2/12 = 1.4e-8)."""
    return np.linspace(
        0.0, params.atmosphere_height_m, int(params.atmosphere_height_m / step_m) + 1
    )


def aerosol_tau(params, wavelength_nm: float) -> float:
    """Vertical Mie extinction optical depth: ∫ β_ext(λ) · density(h) dh by trapezoid."""
    h = altitude_grid(params)
    beta = params.coefficients([wavelength_nm])["mie_extinction"][0]
    return float(np.trapezoid(beta * params.mie_density.density(h), h))


def ozone_column_du(params, wavelength_nm: float = 600.0) -> float:
    """Ozone column from the absorption at one wavelength: number density k(λ)/σ(λ) at the
    profile's peak, integrated over the profile by trapezoid, in Dobson units."""
    h = altitude_grid(params)
    k = params.coefficients([wavelength_nm])["absorption_extinction"][0]
    n_peak = k / ozone_cross_section(wavelength_nm)
    return float(np.trapezoid(n_peak * params.absorption_density.density(h), h)) / DU


@pytest.mark.parametrize("name", ["earth", "earth_nishita", "mars"])
@pytest.mark.parametrize(("aod", "alpha"), [(0.02, 0.0), (0.1, 1.3), (0.8, 2.5), (3.0, -0.4)])
def test_aod_and_angstrom_read_back(name, aod, alpha):
    # Bound 0.5 % (the brief's); the integral's own error is < 1e-7 (see altitude_grid).
    p = preset(name).with_knobs(aod_550=aod, angstrom=alpha)
    assert aerosol_tau(p, 550.0) == pytest.approx(aod, rel=5e-3)
    # Ångström exponent back from the AERONET pair: ln(τ440/τ870) / ln(870/440), to 0.005.
    ratio = aerosol_tau(p, 440.0) / aerosol_tau(p, 870.0)
    assert math.log(ratio) / math.log(870.0 / 440.0) == pytest.approx(alpha, abs=5e-3)
    # Between the 5 nm samples the power law is interpolated linearly: at 442.5 nm the
    # relative error is <= α(α+1)/8 (Δλ/λ)^2 = 1.2e-4 for α = 2.5; bound 5e-4.
    expected = aod * (442.5 / 550.0) ** -alpha
    assert aerosol_tau(p, 442.5) == pytest.approx(expected, rel=5e-4)
    # The read-back properties agree with the independent integral.
    assert p.aod_550 == pytest.approx(aod, rel=1e-6)
    assert p.angstrom_exponent == pytest.approx(alpha, abs=1e-6)


def test_preset_aerosol_depths_match_their_sources():
    # earth: seed 001 appendix B, Mie extinction 4.440e-3 /km with scale height 1.2 km:
    # τ = 0.005328, wavelength-independent (Ångström exponent 0). hazy: AOD 0.272 at 550 nm
    # (README "AOD 0.27"), α 1.3; mars: dust optical depth ~0.5 (its docstring), 1 %.
    assert aerosol_tau(earth(), 550.0) == pytest.approx(4.44e-6 * 1200.0, rel=5e-3)
    assert earth().angstrom_exponent == 0.0
    assert aerosol_tau(hazy(), 550.0) == pytest.approx(0.272, rel=5e-3)
    assert hazy().angstrom_exponent == pytest.approx(1.3, abs=1e-6)
    assert aerosol_tau(preset("mars"), 550.0) == pytest.approx(0.5, rel=0.01)


def test_aod_alone_keeps_the_spectral_shape_and_ssa():
    # mars: wavelength-dependent single-scattering albedo (0.62 at 440 nm to 0.97 at 700 nm,
    # Wolff et al. 2009); scaling its AOD must keep both spectra's shapes (to rounding).
    mars = preset("mars")
    p = mars.with_knobs(aod_550=1.5)
    wl = np.arange(380.0, 760.0, 25.0)
    c0, c1 = mars.coefficients(wl), p.coefficients(wl)
    np.testing.assert_allclose(c1["mie_extinction"] / c0["mie_extinction"], 1.5 / mars.aod_550)
    np.testing.assert_allclose(
        c1["mie_scattering"] / c1["mie_extinction"],
        c0["mie_scattering"] / c0["mie_extinction"],
        rtol=1e-12,
    )
    np.testing.assert_allclose(c1["mie_scattering"][[0]] / c1["mie_extinction"][[0]], 0.62)
    # The Ångström exponent alone keeps the AOD at 550 nm; ssa alone keeps the extinction.
    q = earth().with_knobs(angstrom=1.8)
    assert aerosol_tau(q, 550.0) == pytest.approx(4.44e-6 * 1200.0, rel=5e-3)
    r = earth().with_knobs(ssa=0.5)
    c = r.coefficients([450.0, 650.0])
    np.testing.assert_allclose(c["mie_extinction"], 4.44e-6, rtol=1e-12)
    np.testing.assert_allclose(c["mie_scattering"], 0.5 * 4.44e-6, rtol=1e-12)


def test_extinction_follows_from_the_profile_column():
    # β_ext = τ / ∫ density dh: for an exponential profile of scale height H reaching 100 km
    # that is τ / H; for a constant density up to 3 km (a box), τ / 3000 m.
    p = earth().with_aerosol(aod_550=0.3, scale_height_m=2500.0)
    assert p.coefficients([550.0])["mie_extinction"][0] == pytest.approx(0.3 / 2500.0, rel=1e-9)
    box = DensityProfile((DensityLayer(width_m=3000.0, constant=1.0), DensityLayer()))
    q = earth().with_(mie_density=box).with_knobs(aod_550=0.3)
    assert q.coefficients([550.0])["mie_extinction"][0] == pytest.approx(1e-4, rel=1e-9)
    assert aerosol_tau(q, 550.0) == pytest.approx(0.3, rel=5e-3)


@pytest.mark.parametrize("dobson", [0.0, 90.0, 300.0, 650.0])
def test_ozone_read_back(dobson):
    # 0.5 % bound; 600 nm is near the Chappuis band's peak. The tent's kinks (10, 25, 40 km)
    # lie on the 0.5 m grid, so the trapezoid is exact there up to rounding.
    p = earth().with_knobs(ozone_du=dobson)
    assert ozone_column_du(p) == pytest.approx(dobson, rel=5e-3, abs=1e-9)
    assert p.ozone_du == pytest.approx(dobson, rel=1e-6, abs=1e-9)
    # On another profile (mars: exponential, scale height 11.1 km) the same column.
    m = preset("mars").with_knobs(ozone_du=dobson)
    assert ozone_column_du(m, 550.0) == pytest.approx(dobson, rel=5e-3, abs=1e-9)


def test_earth_ozone_is_300_du_with_seed_001_coefficients():
    # Bruneton 2017 / seed 001 appendix B: 300 DU, ozone (0.650, 1.881, 0.085)e-3 /km in the
    # 10 nm bins at 685, 555 and 445 nm (0.2 %, as in test_atmosphere_params).
    p = earth()
    assert ozone_column_du(p) == pytest.approx(300.0, rel=5e-3)
    np.testing.assert_allclose(
        p.absorption_extinction.at([685.0, 555.0, 445.0]),
        [0.650e-6, 1.881e-6, 0.085e-6],
        rtol=2e-3,
    )


def test_albedo():
    p = earth().with_knobs(albedo=0.62)
    np.testing.assert_array_equal(p.coefficients([400.0, 700.0])["ground_albedo"], 0.62)
    snow = Spectrum.sampled([400.0, 700.0], [0.95, 0.85])
    q = preset("hazy", albedo=snow)
    assert q.coefficients([550.0])["ground_albedo"][0] == pytest.approx(0.90)


@pytest.mark.parametrize(
    ("knob", "value", "message"),
    [
        ("albedo", 1.2, r"albedo = 1.2 is outside the valid range \[0.0, 1.0\]"),
        ("albedo", -0.1, r"albedo = -0.1 .*\[0.0, 1.0\]"),
        ("aod_550", 9.0, r"aod_550 = 9.0 is outside the valid range \[0.0, 5.0\]"),
        ("aod_550", -0.01, r"aod_550 = -0.01 .*\[0.0, 5.0\]"),
        ("aod_550", float("nan"), r"aod_550 = nan .*\[0.0, 5.0\]"),
        ("angstrom", 3.5, r"angstrom = 3.5 is outside the valid range \[-0.5, 3.0\]"),
        ("angstrom", -1.0, r"angstrom = -1.0 .*\[-0.5, 3.0\]"),
        ("ozone_du", 800.0, r"ozone_du = 800.0 DU is outside the valid range \[0.0, 700.0\] DU"),
        ("ozone_du", -5.0, r"ozone_du = -5.0 DU .*\[0.0, 700.0\]"),
        ("ssa", 0.0, r"ssa = 0.0 is outside the valid range \(0.0, 1.0\]"),
        ("ssa", 1.01, r"ssa = 1.01 is outside the valid range \(0.0, 1.0\]"),
        ("aod_550", "thick", r"aod_550 must be a number, got 'thick'"),
    ],
)
def test_bad_knobs_name_the_range(knob, value, message):
    with pytest.raises(ParameterError, match=message):
        preset("earth", **{knob: value})
    with pytest.raises(ParameterError, match=message):
        earth().with_knobs(**{knob: value})


def test_knob_edges_are_valid():
    # The ends of each closed range are accepted (the ranges are inclusive there).
    p = preset("earth", albedo=1.0, aod_550=5.0, angstrom=3.0, ozone_du=700.0, ssa=1.0)
    assert p.aod_550 == pytest.approx(5.0) and p.ozone_du == pytest.approx(700.0)
    q = preset("earth", albedo=0.0, aod_550=0.0, angstrom=-0.5, ozone_du=0.0)
    assert q.aod_550 == 0.0 and q.ozone_du == 0.0 and max(q.ground_albedo.values) == 0.0


def test_no_aerosol_needs_a_spectral_shape():
    clean = earth().with_knobs(aod_550=0.0)
    assert aerosol_tau(clean, 550.0) == 0.0
    with pytest.raises(ParameterError, match="give angstrom"):
        clean.with_knobs(aod_550=0.1)
    with pytest.raises(ParameterError, match="give ssa"):
        clean.with_knobs(aod_550=0.1, angstrom=1.0)
    p = clean.with_knobs(aod_550=0.1, angstrom=1.0, ssa=0.9)
    assert aerosol_tau(p, 550.0) == pytest.approx(0.1, rel=5e-3)


def test_no_knobs_is_the_preset():
    for name in PRESETS:
        assert preset(name) == PRESETS[name]()
        assert preset(name).with_knobs() == preset(name)


def test_hazy_is_earth_with_its_knobs_and_unchanged():
    h = hazy()
    assert h == earth().with_aerosol(**HAZY_AEROSOL).with_(name="hazy")
    assert HAZY_AEROSOL["aod_550"] == 0.272 and HAZY_AEROSOL["angstrom"] == 1.3
    # The former hand-written preset: Mie scattering 150e-6 and extinction 170e-6 m^-1 at
    # 550 nm times (λ/550)^-1.3, scale height 1600 m, g 0.7, everything else as earth.
    wl = np.arange(380.0, 760.0, 5.0)
    shape = (wl / 550.0) ** -1.3
    c = h.coefficients(wl)
    np.testing.assert_allclose(c["mie_extinction"], 170e-6 * shape, rtol=1e-12)
    np.testing.assert_allclose(c["mie_scattering"], 150e-6 * shape, rtol=1e-12)
    z = np.array([0.0, 800.0, 1600.0, 5000.0, 20e3])
    np.testing.assert_allclose(h.mie_density.density(z), np.exp(-z / 1600.0), rtol=1e-12)
    assert h.mie_g == 0.7
    e = earth()
    for field in ("rayleigh_scattering", "absorption_extinction", "ground_albedo"):
        assert getattr(h, field) == getattr(e, field)
    assert h.rayleigh_density == e.rayleigh_density and h.top_radius_m == e.top_radius_m


def test_knobs_change_the_tables_cache_key():
    from skydome.atmosphere.precompute_config import PrecomputeConfig
    from skydome.atmosphere.tables import tables_key

    config = PrecomputeConfig(wavelengths="fast", orders=2)
    base = tables_key(earth(), config)
    assert tables_key(preset("earth"), config) == base
    keys = {
        tables_key(preset("earth", **{knob: value}), config)
        for knob, value in [
            ("albedo", 0.31),
            ("aod_550", 0.006),
            ("angstrom", 0.01),
            ("ozone_du", 301.0),
            ("ssa", 0.91),
        ]
    }
    assert len(keys) == 5 and base not in keys


def sun_and_sky(params, sun_elevation_deg: float = 30.0) -> np.ndarray:
    """Linear sRGB (cd/m^2), single scattering (GLSL renderer, 4 wavelengths), at the Sun's
    centre, the zenith and 5° below the Sun (the aureole), for the Sun at azimuth 180°."""
    from skydome.render.cameras import DirectionsCamera, direction_from_angles
    from skydome.render.single import SingleScatteringRenderer

    sun = direction_from_angles(sun_elevation_deg, 180.0)
    dirs = np.array([sun, [0.0, 0.0, 1.0], direction_from_angles(sun_elevation_deg - 5.0, 180.0)])
    r = SingleScatteringRenderer(params, spectral="fast", view_samples=32, jitter=False)
    try:
        data = r.render(DirectionsCamera(dirs), 0, 0, sun_direction=sun, altitude_m=0.0).data
    finally:
        r.release()
    return data[0][:, :3]


def test_more_aerosol_dims_the_sun_and_whitens_the_sky(ctx):
    from skydome.spectra import SRGB_LUMINANCE

    clean = sun_and_sky(earth().with_knobs(aod_550=0.05))
    turbid = sun_and_sky(earth().with_knobs(aod_550=0.5))
    lum_clean, lum_turbid = clean @ SRGB_LUMINANCE, turbid @ SRGB_LUMINANCE
    # earth's aerosol is wavelength-independent, so raising its AOD from 0.05 to 0.5 adds
    # Δτ = 0.45 at every wavelength: the Sun's disk at 30° dims by exp(-Δτ / sin 30°) =
    # 0.4066 (Beer-Lambert, plane-parallel air mass 2; the spherical shell's is 0.1 % less).
    # Bound 1 %: the transmittance table's interpolation (~1e-3) and the aureole added to
    # the disk (~1e-4 of it).
    assert lum_turbid[0] / lum_clean[0] == pytest.approx(math.exp(-0.45 / 0.5), rel=0.01)
    # The forward-peaked aerosol phase function (g = 0.8) brightens the aureole 5° from the
    # Sun relative to the zenith: measured 36.6 -> 110 (x3.0); bound: at least x2.
    assert lum_turbid[2] / lum_turbid[1] > 2.0 * (lum_clean[2] / lum_clean[1])
    # Grey aerosol scattering whitens the blue zenith: linear sRGB blue/red 2.54 -> 1.37
    # measured; bound: at least 25 % lower.
    assert turbid[1, 2] / turbid[1, 0] < 0.75 * (clean[1, 2] / clean[1, 0])
