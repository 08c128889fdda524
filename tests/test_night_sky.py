"""The night sky as a whole: the default layers of a Sky with a place, the dark zenith's
brightness against measured values, light pollution, and the display passes (night vision,
overlays) that change the image but never the frame's physical data."""

from __future__ import annotations

import numpy as np
import pytest

from skydome import Sky
from skydome.core.cameras import (
    FisheyeCamera,
    PerspectiveCamera,
)
from skydome.errors import ParameterError
from skydome.sky import NIGHT_LAYERS

# Roque de los Muchachos, La Palma (Benn & Ellison 1998 measured its dark sky), on the new
# Moon of 2019-04-05, near the solar minimum of cycle 24/25 (Dec. 2019): at 01:04 UTC the
# north galactic pole (RA 12h51m, Dec +27.1) is 1.7 deg from the zenith, the Sun 55 deg and
# the Moon 62 deg below the horizon.
LA_PALMA = (28.7606, -17.8816, 2396.0)
DARK = "2019-04-05T01:04Z"
ZENITH = PerspectiveCamera(fov_deg=20.0, pitch_deg=90.0)


def mag_arcsec2(luminance_cd_m2: float) -> float:
    """V mag/arcsec^2 of a luminance (the issue's L = 10.8e4 10^(-0.4 m) cd/m^2)."""
    return float(-2.5 * np.log10(luminance_cd_m2 / 10.8e4))


def field_mean(frame, camera, w, h) -> float:
    """Mean luminance over the frame's solid angle (stars' light included: the point sources
    conserve flux, so this is the field's surface brightness)."""
    y, x = np.mgrid[0:h, 0:w] + 0.5
    d, _ = camera.directions(x, y, w, h)
    omega = camera.solid_angle(d, w, h)
    return float((frame.luminance * omega).sum() / omega.sum())


@pytest.fixture(scope="module")
def dark_sky():
    return Sky(LA_PALMA, DARK)


def test_a_sky_with_a_place_has_the_night_layers_and_the_abstract_mode_none(dark_sky):
    names = [layer.name for layer in dark_sky.layers]
    assert names == ["sun", "moon", *NIGHT_LAYERS, "atmosphere"]
    assert [la.name for la in Sky(sun_elevation_deg=10.0).layers] == ["sun", "atmosphere"]
    plain = Sky(LA_PALMA, DARK, night=False)
    assert [la.name for la in plain.layers] == ["sun", "moon", "atmosphere"]
    lit = Sky(LA_PALMA, DARK, light_pollution=8)
    assert lit.layers[-1].name == "light_pollution"
    with pytest.raises(ParameterError, match="Bortle class"):
        Sky(LA_PALMA, DARK, light_pollution="bright")


def test_moonless_zenith_at_a_dark_site_at_solar_minimum(dark_sky):
    # Measured dark-sky zenith brightness at solar minimum: 21.9 V mag/arcsec^2 at La Palma
    # (Benn & Ellison 1998), 21.6-22.0 at the dark observatories Leinert et al. 1998 (table
    # 2) collect. The sum here: airglow (van Rhijn, 145 S10 outside the air), zodiacal light
    # (Leinert table 17), the Milky Way map and the catalogue's stars, each through the
    # atmosphere's own transmittance. Measured 21.76.
    w = h = 256
    frame = dark_sky.render(ZENITH, w, h, exposure=None)
    m = mag_arcsec2(field_mean(frame, ZENITH, w, h))
    assert 21.6 <= m <= 22.0, m


def test_bortle_8_zenith(dark_sky):
    # Bortle 8 skies measure 18.0-18.4 V mag/arcsec^2 at the zenith (the issue; Crumey 2014's
    # table): the class's artificial part on top of the natural sky of the same frame.
    lit = Sky(LA_PALMA, DARK, light_pollution=8)
    w = h = 128
    m = mag_arcsec2(field_mean(lit.render(ZENITH, w, h, exposure=None), ZENITH, w, h))
    assert 18.0 <= m <= 18.4, m


def test_night_layers_off_are_bit_identical_to_a_sky_without_them(dark_sky):
    cam, w, h = FisheyeCamera(), 128, 128
    plain = Sky(LA_PALMA, DARK, night=False).render(cam, w, h, exposure=None).data
    for name in NIGHT_LAYERS:
        dark_sky.layer(name).enabled = False
    try:
        off = dark_sky.render(cam, w, h, exposure=None).data
    finally:
        for name in NIGHT_LAYERS:
            dark_sky.layer(name).enabled = True
    assert np.array_equal(off, plain)
    on = dark_sky.render(cam, w, h, exposure=None).data
    assert on[w // 2, h // 2, 1] > plain[w // 2, h // 2, 1]  # the night sky adds light


def test_display_passes_change_the_image_not_the_frame(dark_sky):
    cam, w, h = PerspectiveCamera(fov_deg=60.0, pitch_deg=60.0), 160, 90
    # the camera's metering ("average"): the frame's physical colours; the default "eye"
    # metering shows the dark-adapted eye's colours already (tests/test_metering.py)
    base = dark_sky.render(cam, w, h, exposure="auto", tonemap="filmic", metering="average")
    dark_sky.night_vision = True
    try:
        seen = dark_sky.render(cam, w, h, exposure="auto", tonemap="filmic", metering="average")
    finally:
        dark_sky.night_vision = False
    assert np.array_equal(seen.data, base.data)
    assert seen.info["night_vision"] is True

    # A dark-adapted eye sees no colour at 2e-4 cd/m^2 (scotopic: one receptor type): every
    # pixel takes the one blue-grey tint of the night-vision pass, red and blue stars alike,
    # so the spread of the pixels' chromaticities collapses.
    def spread(image):
        rgb = image.reshape(-1, 3).astype(float) + 1.0
        rg = rgb[:, :2] / rgb.sum(axis=1, keepdims=True)
        return float(rg.std(axis=0).max())

    assert spread(seen.image) < 0.3 * spread(base.image), (spread(seen.image), spread(base.image))
    again = dark_sky.render(cam, w, h, exposure="auto", tonemap="filmic", metering="average")
    assert np.array_equal(again.image, base.image)  # off again: as before


def test_a_window_draw_shows_what_render_gives_with_every_night_pass(dark_sky):
    # One frame graph for files and windows: Sky.draw into a framebuffer (no frame read
    # back) equals Sky.render's image within 1 code value (render snaps to 8-bit codes in
    # the shader, draw leaves it to the target), with the night layers, night vision and
    # the overlays on, at auto and at a fixed exposure.
    cam, w, h = PerspectiveCamera(fov_deg=70.0, yaw_deg=100.0, pitch_deg=40.0), 200, 120
    ctx = dark_sky.graph.ctx
    tex = ctx.texture((w, h), 4, dtype="f1")
    fbo = ctx.framebuffer(color_attachments=[tex])
    dark_sky.night_vision = True
    dark_sky.overlays = "lines,labels,grid"
    try:
        for exposure in ("auto", -9.0):
            dark_sky.draw(fbo, cam, size=(w, h), exposure=exposure, tonemap="filmic")
            drawn = np.frombuffer(fbo.read(components=3), np.uint8).reshape(h, w, 3)[::-1]
            image = dark_sky.render(cam, w, h, exposure=exposure, tonemap="filmic").image
            assert np.abs(drawn.astype(int) - image.astype(int)).max() <= 1, exposure
            assert image.std() > 5  # a sky with lines and labels, not a flat frame
    finally:
        dark_sky.night_vision = False
        dark_sky.overlays = ()
        fbo.release()
        tex.release()
