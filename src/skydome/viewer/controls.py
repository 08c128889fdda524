"""The viewer's state (camera, time, display) and how input moves it: pure Python, no GL.

The window (``viewer.app``) and the notebook widget (``viewer.widget``) both turn their
events into calls on :class:`Controls`; the tests drive it directly.

Input mapping (a mouse-look camera):

- drag with the left button: turn; a drag across the whole view turns by the horizontal
  field of view (right: yaw increases, up: pitch increases), so the sky follows the mouse
  at any zoom;
- wheel: zoom; each notch multiplies the field of view by ZOOM_PER_NOTCH (up: narrower);
- W/S: walk forward/back along the view's azimuth, A/D: left/right (the place moves over
  the ground, at a speed that grows with the altitude); Q/E or Page Down/Up: descend/climb
  (the altitude changes by the factor CLIMB_RATE_PER_S per second, from the ground to
  space in a few seconds); the arrow keys turn (TURN_RATE_DEG_S, scaled by the zoom);
  +/- zoom; Space: play/pause the time; C: the next projection; 1/2: look at the Sun/Moon.

Every setter clamps to the ranges below: the viewer never fails on a value it shows; the
API behind it (Sky, cameras) rejects out-of-range values with ParameterError as always.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

from skydome.core.cameras import MAX_ALTITUDE_M, EquirectCamera, FisheyeCamera, PerspectiveCamera
from skydome.display import TONEMAPS
from skydome.errors import ParameterError
from skydome.physics.constants import EARTH_MEAN_RADIUS_M as EARTH_RADIUS_M

#: Projections the viewer offers (the cube map's strip is not a view).
PROJECTIONS = ("perspective", "fisheye", "equirect")
#: Field of view the viewer's perspective camera keeps to (deg; the API takes 0.01..179).
VIEW_FOV_RANGE_DEG = (0.5, 170.0)
#: Pitch the viewer keeps to (deg): a hair short of the poles, where yaw is undefined.
VIEW_PITCH_RANGE_DEG = (-89.9, 89.9)
#: Camera altitude above the ground the viewer keeps to (m): to 1000 km, "space".
VIEW_ALTITUDE_RANGE_M = (0.0, min(1.0e6, MAX_ALTITUDE_M))
#: Time-lapse speed, simulated seconds per real second (negative runs backwards): up to
#: ten days a second.
SPEED_RANGE = (-864000.0, 864000.0)
#: Preset speeds offered by the panel (simulated seconds per real second).
SPEED_PRESETS = {
    "real time": 1.0,
    "1 min/s": 60.0,
    "10 min/s": 600.0,
    "1 h/s": 3600.0,
    "6 h/s": 21600.0,
    "1 day/s": 86400.0,
}
#: Exposure: EV100 range and compensation (EV), as the command line's.
EV_RANGE = (-20.0, 40.0)
COMPENSATION_RANGE = (-20.0, 20.0)
EXPOSURE_MODES = ("auto", "ev", "adapt")
#: Julian Dates (UTC) the viewer's time keeps to: years 1000 to 3000 (the astronomy's
#: Delta T model holds well there).
JD_RANGE = (2086302.5, 2816787.5)
#: Latitude, longitude (deg) and ground elevation (m) ranges, as the command line's.
LAT_RANGE = (-90.0, 90.0)
LON_RANGE = (-180.0, 180.0)
ELEVATION_RANGE_M = (-1000.0, 100000.0)

#: Input rates.
ZOOM_PER_NOTCH = 0.9
TURN_RATE_DEG_S = 60.0  # at a 90 deg field of view; proportional to the field of view
CLIMB_RATE_PER_S = 2.0  # d ln(altitude + CLIMB_FLOOR_M) / dt
CLIMB_FLOOR_M = 10.0
WALK_SPEED_FLOOR_M_S = 50.0  # walking speed at the ground; else one altitude per second
DEFAULT_EYE_M = 1.7

#: Key names Controls understands (the front ends map their key codes to these).
KEYS = (
    "w", "a", "s", "d", "q", "e", "page_up", "page_down", "left", "right", "up", "down",
    "plus", "minus", "space", "c", "1", "2",
)  # fmt: skip
_HELD = {"w", "a", "s", "d", "q", "e", "page_up", "page_down", "left", "right", "up", "down",
         "plus", "minus"}  # fmt: skip


def clamp(value: float, lo: float, hi: float) -> float:
    """``value`` clamped to [lo, hi]; NaN becomes lo (a panel never shows a NaN)."""
    v = float(value)
    if not v == v:  # NaN
        return lo
    return min(max(v, lo), hi)


def wrap_deg(angle_deg: float) -> float:
    """An angle in [0, 360) deg."""
    return float(angle_deg) % 360.0


@dataclass
class ViewState:
    """Everything a viewer frame depends on besides the atmosphere's tables.

    Attributes:
        projection: one of PROJECTIONS.
        yaw_deg, pitch_deg, fov_deg: the perspective camera (azimuth from north through
            east, elevation, horizontal field of view).
        altitude_m: camera height above the ground (m); None: the place's ground plus a
            standing eye.
        latitude_deg, longitude_deg, elevation_m: the place (None in the abstract mode).
        jd_utc: the time, a UTC Julian Date (None in the abstract mode).
        sun_elevation_deg, sun_azimuth_deg: the abstract mode's Sun (deg).
        playing: whether the time runs; speed: simulated seconds per real second.
        exposure_mode: "auto" (each frame's log-average), "ev" (``ev100``) or "adapt" (an
            eye adapting over time to the log-average); compensation_ev: EV added.
        tonemap: a tone operator of ``skydome.display.TONEMAPS``.
        night_vision: the display's night vision; overlays: names of the overlays shown.
        layers_off: names of the layers turned off.
        vsync: swap at the display's refresh rate.
    """

    projection: str = "perspective"
    yaw_deg: float = 180.0
    pitch_deg: float = 15.0
    fov_deg: float = 90.0
    altitude_m: float | None = None
    latitude_deg: float | None = None
    longitude_deg: float | None = None
    elevation_m: float = 0.0
    jd_utc: float | None = None
    sun_elevation_deg: float = 30.0
    sun_azimuth_deg: float = 180.0
    playing: bool = False
    speed: float = 60.0
    exposure_mode: str = "auto"
    ev100: float = 14.0
    compensation_ev: float = 0.0
    tonemap: str = "filmic"
    night_vision: bool = False
    overlays: tuple[str, ...] = ()
    layers_off: frozenset[str] = field(default_factory=frozenset)
    vsync: bool = False

    @property
    def abstract(self) -> bool:
        """True when the state has no place or time (a Sun alone)."""
        return self.jd_utc is None

    def camera(self):
        """The camera of this state (a PerspectiveCamera, FisheyeCamera or EquirectCamera)."""
        if self.projection == "fisheye":
            return FisheyeCamera()
        if self.projection == "equirect":
            return EquirectCamera()
        return PerspectiveCamera(
            fov_deg=self.fov_deg, yaw_deg=wrap_deg(self.yaw_deg), pitch_deg=self.pitch_deg
        )

    def exposure(self) -> str | float:
        """What ``Sky.draw``/``Sky.render`` take as ``exposure`` for the auto and EV modes
        ("auto" or an EV100 number); the adapt mode's scale comes from the eye."""
        return self.ev100 if self.exposure_mode == "ev" else "auto"


class Controls:
    """A :class:`ViewState` and the input that moves it.

    Args:
        state: the initial state (clamped to the viewer's ranges).
    """

    def __init__(self, state: ViewState | None = None):
        self.state = clamped(state or ViewState())
        self.held: set[str] = set()
        #: "sun" or "moon" after the 1 or 2 key, until the scene aims the camera there.
        self.pending_look: str | None = None
        self._drag_from: tuple[float, float] | None = None

    # ------------------------------------------------------------------ pointer

    def degrees_per_pixel(self, view_width_px: float) -> float:
        """How far a pointer movement of one pixel (of a view ``view_width_px`` wide, in the
        pointer's own units) turns the camera (deg): the field of view across the width."""
        return self.state.fov_deg / max(float(view_width_px), 1.0)

    def press(self, x: float, y: float) -> None:
        """The pointer's button went down at (x, y) (pixels, y down)."""
        self._drag_from = (float(x), float(y))

    def release(self) -> None:
        """The pointer's button went up."""
        self._drag_from = None

    def move(self, x: float, y: float, view_width_px: float) -> None:
        """The pointer moved to (x, y) (pixels, y down): while a button is held, turn."""
        if self._drag_from is None:
            return
        x0, y0 = self._drag_from
        self._drag_from = (float(x), float(y))
        self.drag(float(x) - x0, float(y) - y0, view_width_px)

    def drag(self, dx_px: float, dy_px: float, view_width_px: float) -> None:
        """Turn by a drag of (dx, dy) pixels (y down) over a view ``view_width_px`` wide:
        right turns right (yaw up), up looks up (pitch up)."""
        k = self.degrees_per_pixel(view_width_px)
        s = self.state
        self.set(yaw_deg=s.yaw_deg + k * float(dx_px), pitch_deg=s.pitch_deg - k * float(dy_px))

    def scroll(self, notches: float) -> None:
        """Zoom by ``notches`` of the wheel (positive: in, a narrower field of view)."""
        self.set(fov_deg=self.state.fov_deg * ZOOM_PER_NOTCH ** float(notches))

    # ------------------------------------------------------------------ keys

    def key(self, name: str, down: bool) -> None:
        """A key (one of KEYS) went down or up; unknown names are ignored. Held keys act
        in :meth:`tick`; Space, C, 1 and 2 act once when pressed."""
        if name not in KEYS:
            return
        if name in _HELD:
            if down:
                self.held.add(name)
            else:
                self.held.discard(name)
            return
        if not down:
            return
        if name == "space":
            self.set(playing=not self.state.playing)
        elif name == "c":
            i = PROJECTIONS.index(self.state.projection)
            self.set(projection=PROJECTIONS[(i + 1) % len(PROJECTIONS)])
        elif name in ("1", "2"):
            self.pending_look = "sun" if name == "1" else "moon"

    def tick(self, dt_s: float, *, eye_altitude_m: float = DEFAULT_EYE_M) -> None:
        """Advance ``dt_s`` real seconds: held keys turn, zoom, walk and climb; a playing
        time runs at ``speed``. ``eye_altitude_m``: the altitude in use while the state's
        is None (the place's standing eye)."""
        dt = clamp(dt_s, 0.0, 1.0)  # a stalled frame does not fling the camera
        s = self.state
        h = self.held
        changes: dict = {}
        turn = TURN_RATE_DEG_S * s.fov_deg / 90.0 * dt
        yaw = s.yaw_deg + turn * (("right" in h) - ("left" in h))
        pitch = s.pitch_deg + turn * (("up" in h) - ("down" in h))
        if yaw != s.yaw_deg or pitch != s.pitch_deg:
            changes.update(yaw_deg=yaw, pitch_deg=pitch)
        zoom = ("plus" in h) - ("minus" in h)
        if zoom:
            changes["fov_deg"] = s.fov_deg * ZOOM_PER_NOTCH ** (4.0 * zoom * dt)
        climb = (("e" in h) or ("page_up" in h)) - (("q" in h) or ("page_down" in h))
        altitude = eye_altitude_m if s.altitude_m is None else s.altitude_m
        if climb:
            altitude = (altitude + CLIMB_FLOOR_M) * math.exp(
                CLIMB_RATE_PER_S * climb * dt
            ) - CLIMB_FLOOR_M
            changes["altitude_m"] = altitude
        forward = ("w" in h) - ("s" in h)
        side = ("d" in h) - ("a" in h)
        if (forward or side) and not s.abstract:
            distance = max(WALK_SPEED_FLOOR_M_S, altitude) * dt
            changes.update(self._walked(forward, side, distance))
        if s.playing and not s.abstract:
            changes["jd_utc"] = s.jd_utc + s.speed * dt / 86400.0
        if changes:
            self.set(**changes)

    def _walked(self, forward: int, side: int, distance_m: float) -> dict:
        """The latitude and longitude after walking ``distance_m`` forward/sideways along
        the camera's azimuth (a great-circle step on a sphere of EARTH_RADIUS_M)."""
        s = self.state
        bearing = math.radians(s.yaw_deg) + math.atan2(side, forward)
        d = distance_m * math.hypot(forward, side) / EARTH_RADIUS_M
        lat, lon = math.radians(s.latitude_deg), math.radians(s.longitude_deg)
        lat2 = math.asin(
            math.sin(lat) * math.cos(d) + math.cos(lat) * math.sin(d) * math.cos(bearing)
        )
        lon2 = lon + math.atan2(
            math.sin(bearing) * math.sin(d) * math.cos(lat),
            math.cos(d) - math.sin(lat) * math.sin(lat2),
        )
        return {
            "latitude_deg": math.degrees(lat2),
            "longitude_deg": (math.degrees(lon2) + 180.0) % 360.0 - 180.0,
        }

    # ------------------------------------------------------------------ setting

    def set(self, **changes) -> ViewState:
        """Change fields of the state, clamped to the viewer's ranges; returns the state."""
        unknown = set(changes) - set(ViewState.__dataclass_fields__)
        if unknown:
            raise ParameterError(f"ViewState has no field {sorted(unknown)[0]!r}")
        self.state = clamped(replace(self.state, **changes))
        return self.state

    def look_at(self, elevation_deg: float, azimuth_deg: float) -> None:
        """Aim the perspective camera at a direction (deg): e.g. the Sun's or the Moon's."""
        self.set(projection="perspective", yaw_deg=azimuth_deg, pitch_deg=elevation_deg)


def clamped(s: ViewState) -> ViewState:
    """``s`` with every number in the viewer's ranges and every choice a valid one."""

    jd = None if s.jd_utc is None else clamp(s.jd_utc, *JD_RANGE)
    lat = None if s.latitude_deg is None else clamp(s.latitude_deg, *LAT_RANGE)
    lon = None
    if s.longitude_deg is not None:
        lon = clamp(s.longitude_deg, -1e9, 1e9)
        lon = (lon + 180.0) % 360.0 - 180.0 if not -180.0 <= lon <= 180.0 else lon
    return replace(
        s,
        projection=s.projection if s.projection in PROJECTIONS else "perspective",
        yaw_deg=wrap_deg(clamp(s.yaw_deg, -1e9, 1e9)),
        pitch_deg=clamp(s.pitch_deg, *VIEW_PITCH_RANGE_DEG),
        fov_deg=clamp(s.fov_deg, *VIEW_FOV_RANGE_DEG),
        altitude_m=None if s.altitude_m is None else clamp(s.altitude_m, *VIEW_ALTITUDE_RANGE_M),
        latitude_deg=lat,
        longitude_deg=lon,
        elevation_m=clamp(s.elevation_m, *ELEVATION_RANGE_M),
        jd_utc=jd,
        sun_elevation_deg=clamp(s.sun_elevation_deg, -90.0, 90.0),
        sun_azimuth_deg=wrap_deg(clamp(s.sun_azimuth_deg, -1e9, 1e9)),
        speed=clamp(s.speed, *SPEED_RANGE),
        exposure_mode=s.exposure_mode if s.exposure_mode in EXPOSURE_MODES else "auto",
        ev100=clamp(s.ev100, *EV_RANGE),
        compensation_ev=clamp(s.compensation_ev, *COMPENSATION_RANGE),
        tonemap=s.tonemap if s.tonemap in TONEMAPS else "filmic",
        playing=bool(s.playing) and jd is not None,
        night_vision=bool(s.night_vision),
        overlays=tuple(s.overlays),
        layers_off=frozenset(s.layers_off),
        vsync=bool(s.vsync),
    )
