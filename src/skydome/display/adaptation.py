"""Eye adaptation over time, for time-lapses: the exposure follows an adapted luminance that
moves towards each frame's luminance with the eye's own time constants.

Per-frame automatic exposure (``auto_exposure`` on every frame) flickers and hides the
evening getting darker; an adapted luminance changes smoothly, fast when the scene brightens
and slowly when it darkens, as vision does.

**Model.** One state, the adapted luminance L_a (cd/m^2), filtered in the log of luminance
(the visual system adapts to ratios, not differences): for a target L_t held over dt,

    ln L_a(t + dt) = ln L_a + (ln L_t - ln L_a) (1 - exp(-dt / tau)),

a first-order low-pass filter, the form of Pattanaik et al. 2000 (sec. 4) and Krawczyk et al.
2005 (eq. 5), here applied to ln L rather than L, so that a step of one decade up or down
takes the same time at any level. tau depends on the direction and on the regime:

* **brightening** (light adaptation, L_t > L_a): tau_cone = 0.1 s, tau_rod = 0.4 s
  (Krawczyk, Myszkowski & Seidel, "Perceptual effects in real-time tone mapping", SCCG 2005,
  eq. 6; close to the neural time constants 0.08 s (cones) and 0.15 s (rods) of Pattanaik,
  Tumblin, Yee & Greenberg, "Time-dependent visual adaptation for fast realistic image
  display", SIGGRAPH 2000, sec. 4.1);
* **darkening** (dark adaptation, L_t < L_a): tau_cone = 110 s, tau_rod = 400 s, the time
  constants of cone and rod photopigment regeneration (Pattanaik et al. 2000, sec. 4.2, after
  Hunt, "The Reproduction of Colour"; the same 110 s and 400 s are in the pfstmo / Luminance
  HDR implementation of that paper, tmo_pattanaik00.cpp). Recovery in the dark is limited by
  pigment regeneration (Rushton & Powell, Vision Res. 12, 1972). With these constants a step
  from a daylight sky (1e4 cd/m^2) to a moonless night (2e-4) settles to within 0.1 log unit
  after 23 min, 0.05 after 27 min and 0.01 after 38 min, the span of the classic
  dark-adaptation curve (Hecht, Haig & Chase, J. Gen. Physiol. 20, 1937: a cone branch for
  the first 7 to 10 minutes, then the rod branch, complete after about 30 to 40 minutes).
  Ferwerda et al., "A model
  of visual adaptation for realistic image synthesis", SIGGRAPH 1996, describe the same
  asymmetry: light adaptation within seconds, dark adaptation over tens of minutes.

Between the regimes tau is blended with the rods' share of vision, Krawczyk et al. 2005
eq. 7 and 12,

    w_rod(L_a) = 0.04 / (0.04 + L_a)        (L_a in cd/m^2),
    tau = w_rod tau_rod + (1 - w_rod) tau_cone,

the same 0.04 cd/m^2 as the steady-state unbleached rhodopsin fraction of Pattanaik et al.
2000, sec. 4.2. w_rod is 0.8 at 0.01 cd/m^2, 0.5 at 0.04 and 0.013 at 3 cd/m^2, so the
change-over spans the mesopic range (0.005 to 5 cd/m^2, CIE 191:2010). It is evaluated at the
current adapted luminance, so a darkening eye first follows the cone constant and then, once
it is dim, the slower rod constant: the cone and rod branches of the dark-adaptation curve.
As tau changes with L_a, an update longer than a quarter of tau is integrated in sub-steps.

**Exposure** follows :mod:`skydome.display.exposure`'s key convention (Reinhard et al. 2002
eq. 2): ``scale = 2^compensation * key / L_a``, so an adapted eye maps its adaptation
luminance to ``key`` exactly as ``auto_exposure`` maps a frame's log-average luminance.
"""

from __future__ import annotations

import math

from skydome.display.exposure import COMPENSATION_RANGE, DEFAULT_DELTA, DEFAULT_KEY, eye_key
from skydome.errors import ParameterError, check_range

#: Light-adaptation time constants, s (Krawczyk et al. 2005, eq. 6).
CONE_LIGHT_TAU_S = 0.1
ROD_LIGHT_TAU_S = 0.4
#: Dark-adaptation time constants, s: cone and rod pigment regeneration (Pattanaik et al.
#: 2000, sec. 4.2).
CONE_DARK_TAU_S = 110.0
ROD_DARK_TAU_S = 400.0
#: Luminance at which rods and cones share vision equally, cd/m^2 (Krawczyk et al. 2005
#: eq. 7; Pattanaik et al. 2000 sec. 4.2).
ROD_HALF_LUMINANCE_CD_M2 = 0.04
#: Lowest adapted luminance, cd/m^2: the floor of ``log_average_luminance`` (an all-black
#: frame), far below a moonless night sky (~2e-4 cd/m^2).
MIN_LUMINANCE_CD_M2 = DEFAULT_DELTA
#: Highest target luminance accepted, cd/m^2 (the Sun's disc is ~1.6e9).
MAX_LUMINANCE_CD_M2 = 1e15
#: An update is split into steps of at most this fraction of the current tau ...
SUBSTEP_FRACTION = 0.25
#: ... but into no more than this many steps (steps much longer than tau converge anyway).
MAX_SUBSTEPS = 256


def rod_weight(luminance_cd_m2: float) -> float:
    """Share of the rods in vision at an adapted luminance (cd/m^2), from 1 (dark) to 0
    (bright): ``0.04 / (0.04 + L)`` (Krawczyk et al. 2005 eq. 7). Raises ParameterError for
    a negative or non-finite luminance."""
    lum = check_range("luminance_cd_m2", luminance_cd_m2, 0.0, math.inf, "cd/m^2")
    if math.isinf(lum):
        return 0.0
    return ROD_HALF_LUMINANCE_CD_M2 / (ROD_HALF_LUMINANCE_CD_M2 + lum)


def time_constant_s(adapted_luminance_cd_m2: float, brightening: bool) -> float:
    """Adaptation time constant tau (s) of an eye adapted to ``adapted_luminance_cd_m2``
    (cd/m^2): light adaptation (0.1 s cones to 0.4 s rods) when ``brightening``, dark
    adaptation (110 s cones to 400 s rods) otherwise, blended by :func:`rod_weight`."""
    w = rod_weight(adapted_luminance_cd_m2)
    if brightening:
        return w * ROD_LIGHT_TAU_S + (1.0 - w) * CONE_LIGHT_TAU_S
    return w * ROD_DARK_TAU_S + (1.0 - w) * CONE_DARK_TAU_S


class EyeAdaptation:
    """The adapted luminance of an eye watching a sequence of frames, and its exposure.

    Typical use, once per frame (``dt_s`` is scene time: a 1-minute time-lapse step is 60 s)::

        eye = EyeAdaptation()
        for frame in frames:
            eye.update(log_average_luminance(frame, clip_percentile=99.5), dt_s=60.0)
            image = tonemap(frame, "filmic", eye.exposure_scale())

    Args:
        key: exposed value of the adapted luminance, in (0, 1]; 0.18 (middle grey) as in
            ``auto_exposure``; or "eye": the key of the metering ``eye``,
            ``skydome.display.exposure.eye_key`` of the adapted luminance (Krawczyk et al.
            2005: lower in the dark).
        speed: how many times faster than a real eye adaptation runs (every tau divided by
            it), > 0. 1 is the eye in scene time; e.g. 60 lets a 1-minute step of a
            time-lapse act like one second of adaptation.
    Attributes:
        adapted_luminance: the current adapted luminance, cd/m^2 (None before the first
            update).
    """

    def __init__(self, key: float | str = DEFAULT_KEY, *, speed: float = 1.0) -> None:
        self.key = "eye" if key == "eye" else check_range("key", key, 1e-6, 1.0)
        self.speed = check_range("speed", speed, 1e-6, 1e6)
        self._log_la: float | None = None

    @property
    def adapted_luminance(self) -> float | None:
        """The adapted luminance L_a, cd/m^2, or None before the first update."""
        return None if self._log_la is None else math.exp(self._log_la)

    def reset(self) -> None:
        """Forget the state: the next update adopts its target directly."""
        self._log_la = None

    def update(self, target_luminance_cd_m2: float, dt_s: float) -> float:
        """Adapt towards ``target_luminance_cd_m2`` (cd/m^2, e.g. the frame's log-average
        luminance) for ``dt_s`` seconds of scene time; return the adapted luminance (cd/m^2).

        The first update (and the first after :meth:`reset`) adopts the target at once;
        ``dt_s = 0`` changes nothing after that. The adapted luminance moves monotonically
        towards the target and never passes it. Targets below 1e-6 cd/m^2 (a black frame)
        count as 1e-6. Raises ParameterError for a negative or non-finite target or dt.
        """
        target = check_range(
            "target_luminance_cd_m2", target_luminance_cd_m2, 0.0, MAX_LUMINANCE_CD_M2, "cd/m^2"
        )
        dt = check_range("dt_s", dt_s, 0.0, 1e12, "s")
        x_target = math.log(max(target, MIN_LUMINANCE_CD_M2))
        if self._log_la is None:
            self._log_la = x_target
            return math.exp(x_target)
        x = self._log_la
        remaining = dt * self.speed  # time in the eye's own seconds (tau / speed)
        min_step = remaining / MAX_SUBSTEPS
        while remaining > 0.0 and x != x_target:
            tau = time_constant_s(math.exp(x), brightening=x_target > x)
            h = min(remaining, max(SUBSTEP_FRACTION * tau, min_step))
            # -expm1(-h/tau) = 1 - exp(-h/tau), accurate for h << tau too.
            x += (x_target - x) * -math.expm1(-h / tau)
            remaining -= h
            if abs(x_target - x) <= 1e-12 * max(1.0, abs(x_target)):
                x = x_target
        self._log_la = x
        return math.exp(x)

    def exposure_scale(self, compensation_ev: float = 0.0) -> float:
        """Exposure scale (m^2/cd) for the adapted luminance: ``2^compensation * key / L_a``
        (the convention of ``skydome.display.exposure.auto_exposure``). Raises ParameterError
        before the first update or for a compensation outside [-20, 20] EV."""
        comp = check_range("exposure compensation", compensation_ev, *COMPENSATION_RANGE, "EV")
        if self._log_la is None:
            raise ParameterError(
                "EyeAdaptation has no adapted luminance yet: call update() with the first "
                "frame's luminance first"
            )
        la = math.exp(self._log_la)
        key = eye_key(la) if self.key == "eye" else self.key
        return 2.0**comp * key / la
