"""The phase function of cloud droplets: the Mie table itself, and a mixture of HG lobes.

A water cloud's phase function (Mie theory for droplets of r_eff ~ 10 um in the visible) has a
diffraction peak a degree wide that holds about half of the scattered light, a broad forward
lobe, a minimum near 100 deg, the cloudbow at ~140 deg and the glory at 180 deg. Two forms:

* :class:`TabulatedPhase`: P tabulated in the scattering angle, linear between the nodes.
  :data:`MIE_PHASE` is the Mie phase function of a gamma distribution of water droplets
  (r_eff 10 um, v_eff 0.1, m = 1.333, 550 nm; the packaged ``cloud_droplet_mie_phase.csv``).
  :data:`RENDER_PHASE` is what the renderer scatters with (a texture of
  :data:`RENDER_PHASE_TEXELS` nodes uniform in angle, linear filtering: the same function):
  the Mie table with its diffraction peak cut flat at :data:`TRUNCATION_DEG` (the peak's light,
  :data:`PEAK_FRACTION` of all, counted as unscattered: extinction scales by 1 - f), so that
  single scattering keeps the forward lobe, the side minimum, the cloudbow and the glory.
* :class:`LobePhase`: sum_j w_j HG(g_j), cheap and exactly sampled. :data:`CLOUD_PHASE` is the
  mixture fitted to the same Mie function (``cloud_droplet_phase.csv``): monotone lobes keep
  the peak and the first moment but neither the cloudbow nor the glory, and are 0.6 of Mie at
  30-45 deg (``tools/build_cloud_phase.py``); the Monte Carlo tests use it as an analytic form.

Both are normalised to 1 over the sphere (1/sr) and offer ``value``, ``sample``,
``asymmetry``, ``second_moment`` and ``delta_truncated``.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache, cached_property

import numpy as np

from skydome.errors import ParameterError
from skydome.io.packaged import read_packaged_csv, read_packaged_npz
from skydome.physics.phase import MAX_LOBES, henyey_greenstein, sample_hg

__all__ = [
    "CLOUD_PHASE",
    "LobePhase",
    "MIE_PHASE",
    "MIE_PHASE_CSV",
    "PEAK_FRACTION",
    "PHASE_CSV",
    "RAIN_PEAK_FRACTION",
    "RAIN_RENDER_PHASE",
    "RENDER_PHASE",
    "RENDER_PHASE_TEXELS",
    "TRUNCATION_DEG",
    "TabulatedPhase",
    "load_cloud_phase",
    "load_mie_phase",
    "RAIN_PHASES",
    "SpectralPhases",
    "DROPLET_PHASES",
    "droplet_channel_phases",
    "load_droplet_phases",
    "load_rain_phases",
    "rain_channel_phases",
    "rain_phases_with_bows",
    "RainBows",
    "rain_bows",
    "DEFAULT_RAIN_MM_H",
    "CLOUD_R_EFF_UM",
    "load_rain_bows",
    "disk_smoothed",
    "SUN_RADIUS_DEG",
    "render_grid_deg",
    "sample_hg",
]

#: The packaged tables of :data:`CLOUD_PHASE` and :data:`MIE_PHASE` (built by
#: ``tools/build_cloud_phase.py``).
PHASE_CSV = "cloud_droplet_phase.csv"
MIE_PHASE_CSV = "cloud_droplet_mie_phase.csv"
#: The renderer's phase texture: nodes uniform in the scattering angle from 0 to 180 deg.
RENDER_PHASE_TEXELS = 2048
#: Where the Mie phase function's diffraction peak is cut flat (deg): inside it the light is
#: counted as unscattered (it leaves within a few degrees of its direction).
TRUNCATION_DEG = 5.0
#: Sub-intervals per table interval of the quadrature (moments, normalisation, sampling).
_REFINE = 16


#: Lobes at least this forward are the droplets' diffraction peak (delta-M takes them out).
PEAK_G = 0.98


@dataclass(frozen=True)
class LobePhase:
    """A phase function sum_j w_j HG(g_j): non-negative ``weights`` summing to 1 (within 1e-9;
    stored normalised) and asymmetries ``g`` in (-1, 1), 1 to ``MAX_LOBES`` (12) lobes."""

    weights: tuple[float, ...]
    g: tuple[float, ...]

    def __post_init__(self):
        w = np.asarray(self.weights, float).ravel()
        g = np.asarray(self.g, float).ravel()
        if w.size != g.size or not 1 <= w.size <= MAX_LOBES:
            raise ParameterError(
                f"a lobe phase function needs 1 to {MAX_LOBES} weights and as many asymmetries, "
                f"got {w.size} weights and {g.size} asymmetries"
            )
        if not np.all(np.isfinite(w)) or np.any(w < 0.0):
            raise ParameterError(f"lobe weights must be finite and >= 0, got {tuple(w)}")
        if abs(w.sum() - 1.0) > 1e-9:
            raise ParameterError(f"lobe weights must sum to 1 (within 1e-9), got {w.sum()!r}")
        if not np.all(np.isfinite(g)) or np.any(np.abs(g) >= 1.0):
            raise ParameterError(f"lobe asymmetries must lie in (-1, 1), got {tuple(g)}")
        object.__setattr__(self, "weights", tuple(float(v) for v in w / w.sum()))
        object.__setattr__(self, "g", tuple(float(v) for v in g))

    @classmethod
    def henyey_greenstein(cls, g: float) -> LobePhase:
        """One HG lobe of asymmetry ``g`` (g = 0: isotropic, 1/(4 pi) sr^-1)."""
        return cls((1.0,), (float(g),))

    @property
    def asymmetry(self) -> float:
        """First moment <cos theta> = sum_j w_j g_j (the HG lobe's Legendre moments are g^l)."""
        return float(np.dot(self.weights, self.g))

    @property
    def second_moment(self) -> float:
        """Second Legendre moment sum_j w_j g_j^2: the fraction f that the delta-M method
        (Wiscombe 1977) moves into the forward delta peak at its lowest (Eddington) order."""
        return float(np.dot(self.weights, np.square(self.g)))

    def delta_truncated(self, peak_g: float | None = None) -> tuple[LobePhase, float]:
        """The phase function with its forward peak taken out (delta-M, Wiscombe 1977, J.
        Atmos. Sci. 34, 1408, keeping the first moment): each lobe with g_j >= ``peak_g`` is
        split as g_j delta + (1 - g_j) HG(0). Returns (the remaining lobes plus the
        isotropic part, renormalised; f = sum of w_j g_j over those lobes, the fraction of
        scattering the peak sends straight on: extinction scales by 1 - f at albedo 1)."""
        peak_g = PEAK_G if peak_g is None else peak_g
        w = np.asarray(self.weights)
        g = np.asarray(self.g)
        peak = g >= peak_g
        f = float(np.sum(w[peak] * g[peak]))
        if f <= 0.0:
            return self, 0.0
        iso = float(np.sum(w[peak] * (1.0 - g[peak])))
        rest_w = np.append(w[~peak], iso)
        rest_g = np.append(g[~peak], 0.0)
        return LobePhase(tuple(rest_w / rest_w.sum()), tuple(rest_g)), f

    def value(self, cos_theta) -> np.ndarray:
        """P(cos theta) in 1/sr (integrates to 1 over the sphere), the shape of ``cos_theta``."""
        mu = np.asarray(cos_theta, float)
        out = np.zeros_like(mu)
        for w, g in zip(self.weights, self.g, strict=True):
            if w > 0.0:
                out += w * henyey_greenstein(mu, g)
        return out

    def sample(self, rng: np.random.Generator, n: int) -> np.ndarray:
        """``n`` cosines of scattering angles drawn from P: a lobe chosen by weight, then its
        HG CDF inverted (:func:`sample_hg`)."""
        lobe = np.searchsorted(np.cumsum(self.weights)[:-1], rng.random(n), side="right")
        return sample_hg(np.asarray(self.g)[lobe], rng.random(n))


def render_grid_deg() -> np.ndarray:
    """The renderer's phase-texture nodes (deg): :data:`RENDER_PHASE_TEXELS` from 0 to 180."""
    return np.linspace(0.0, 180.0, RENDER_PHASE_TEXELS)


@dataclass(frozen=True)
class TabulatedPhase:
    """A phase function tabulated at scattering angles ``theta_deg`` (increasing, from 0 to
    180 deg, at least 2 nodes), linear in the angle between them; ``values`` (1/sr, >= 0) are
    stored normalised to 1 over the sphere (the integral by the trapezoid rule on the table
    refined 16-fold, which also gives the moments and the sampling CDF)."""

    theta_deg: np.ndarray
    values: np.ndarray

    def __post_init__(self):
        t = np.array(self.theta_deg, dtype=float).ravel()
        v = np.array(self.values, dtype=float).ravel()
        if t.size != v.size or t.size < 2:
            raise ParameterError(
                f"a tabulated phase function needs as many angles as values (>= 2), got "
                f"{t.size} and {v.size}"
            )
        if t[0] != 0.0 or t[-1] != 180.0 or np.any(np.diff(t) <= 0.0):
            raise ParameterError("the phase table's angles must rise from 0 to 180 deg")
        if not np.all(np.isfinite(v)) or np.any(v < 0.0) or not np.any(v > 0.0):
            raise ParameterError("the phase table's values must be finite, >= 0, not all 0")
        theta, weight = self._quadrature(t, v)
        norm = float(np.trapezoid(weight, theta))
        t.flags.writeable = False
        v = v / norm
        v.flags.writeable = False
        object.__setattr__(self, "theta_deg", t)
        object.__setattr__(self, "values", v)

    @staticmethod
    def _quadrature(theta_deg, values) -> tuple[np.ndarray, np.ndarray]:
        """(angles in rad refined :data:`_REFINE`-fold, P 2 pi sin theta there)."""
        sub = np.linspace(0.0, 1.0, _REFINE, endpoint=False)
        t = theta_deg[:-1, None] + sub[None, :] * np.diff(theta_deg)[:, None]
        t = np.append(t.ravel(), theta_deg[-1])
        p = np.interp(t, theta_deg, values)
        rad = np.radians(t)
        return rad, p * 2.0 * np.pi * np.sin(rad)

    @classmethod
    def of(cls, phase, theta_deg: np.ndarray | None = None) -> TabulatedPhase:
        """Any phase function with ``value(cos theta)`` tabulated at ``theta_deg`` (default:
        the renderer's grid, :func:`render_grid_deg`)."""
        t = render_grid_deg() if theta_deg is None else np.asarray(theta_deg, float)
        return cls(t, phase.value(np.cos(np.radians(t))))

    def value(self, cos_theta) -> np.ndarray:
        """P(cos theta) in 1/sr, the shape of ``cos_theta`` (linear in the angle)."""
        mu = np.clip(np.asarray(cos_theta, float), -1.0, 1.0)
        return np.interp(np.degrees(np.arccos(mu)), self.theta_deg, self.values)

    @cached_property
    def _nodes(self) -> tuple[np.ndarray, np.ndarray]:
        """The refined quadrature of the stored table (computed once: the moments and the CDF
        are read every frame and every scattering)."""
        return self._quadrature(self.theta_deg, self.values)

    def _moment(self, fn) -> float:
        rad, weight = self._nodes
        return float(np.trapezoid(weight * fn(np.cos(rad)), rad))

    @cached_property
    def asymmetry(self) -> float:
        """First moment <cos theta>."""
        return self._moment(lambda mu: mu)

    @cached_property
    def second_moment(self) -> float:
        """Second Legendre moment <P2(cos theta)> = <(3 cos^2 - 1) / 2>: delta-M's fraction f
        at its lowest (Eddington) order (for an HG lobe it is g^2, as :class:`LobePhase`)."""
        return self._moment(lambda mu: 1.5 * mu * mu - 0.5)

    @cached_property
    def _cdf(self) -> tuple[np.ndarray, np.ndarray]:
        """(angles in rad of the refined table, the CDF there): the trapezoid rule."""
        rad, weight = self._nodes
        cdf = np.concatenate([[0.0], np.cumsum(0.5 * (weight[1:] + weight[:-1]) * np.diff(rad))])
        return rad, cdf / cdf[-1]

    def sample(self, rng: np.random.Generator, n: int) -> np.ndarray:
        """``n`` cosines of scattering angles drawn from P: the CDF in angle (the trapezoid
        rule on the refined table) inverted linearly."""
        rad, cdf = self._cdf
        return np.cos(np.interp(rng.random(n), cdf, rad))

    def delta_truncated(self, truncation_deg: float | None = None) -> tuple[TabulatedPhase, float]:
        """The phase function with its forward peak cut flat at ``truncation_deg`` (default
        :data:`TRUNCATION_DEG`): P(theta < theta_c) = P(theta_c), tabulated on the renderer's
        grid. Returns (that, renormalised; f = 1 - its integral before renormalising, the
        fraction of scattering counted as going straight on: extinction scales by 1 - f at
        albedo 1). A flat cut keeps the function exact beyond theta_c (what single
        scattering sees) where delta-M's lobe split would change it (Potter 1970, J. Atmos.
        Sci. 27, 943, cuts the peak the same way, extrapolating in log P)."""
        tc = TRUNCATION_DEG if truncation_deg is None else float(truncation_deg)
        if not 0.0 <= tc < 90.0:
            raise ParameterError(f"the truncation angle must be in [0, 90) deg, got {tc}")
        t = render_grid_deg()
        p = np.interp(np.maximum(t, tc), self.theta_deg, self.values)
        rad, weight = self._quadrature(t, p)
        f = 1.0 - float(np.trapezoid(weight, rad))
        return TabulatedPhase(t, p), max(f, 0.0)


def load_mie_phase() -> TabulatedPhase:
    """The droplets' Mie phase function from the packaged ``cloud_droplet_mie_phase.csv``."""
    t = read_packaged_csv(MIE_PHASE_CSV, ("theta_deg", "phase"))
    return TabulatedPhase(t["theta_deg"], t["phase"])


def load_cloud_phase() -> LobePhase:
    """The cloud droplet phase function from the packaged ``cloud_droplet_phase.csv``."""
    t = read_packaged_csv(PHASE_CSV, ("weight", "g"))
    return LobePhase(tuple(t["weight"]), tuple(t["g"]))


#: The phase function of a water-droplet cloud at 550 nm (r_eff 10 um, v_eff 0.1), HG lobes
#: fitted to Mie theory by ``tools/build_cloud_phase.py``.
CLOUD_PHASE: LobePhase = load_cloud_phase()

#: The Mie phase function of the same droplets, tabulated (0.025 deg steps over the peak).
MIE_PHASE: TabulatedPhase = load_mie_phase()

#: The rain drops' packaged phase functions (``tools/build_rain_phase.py``): geometric optics
#: per wavelength, and the file's format version.
RAIN_PHASE_NPZ = "rain_drop_phase.npz"
RAIN_PHASE_FORMAT = 1


@dataclass(frozen=True)
class SpectralPhases:
    """Phase functions (1/sr) by wavelength: at ``wavelength_nm`` (W), tabulated at
    ``theta_deg`` (A; 0 to 180 deg): ``phase`` (W, A). The rain drops' (:data:`RAIN_PHASES`:
    the light their rays refract and reflect, diffraction apart, each row normalised over the
    sphere) and the cloud droplets' (:data:`DROPLET_PHASES`: Mie theory, normalised with their
    diffraction peak, tabulated from 5 deg and held flat below)."""

    wavelength_nm: np.ndarray
    theta_deg: np.ndarray
    phase: np.ndarray

    def at(self, wavelengths_nm) -> np.ndarray:
        """The phase functions at ``wavelengths_nm`` (N, A): linear between the table's
        wavelengths (held beyond them)."""
        grid = self.wavelength_nm
        wl = np.clip(np.atleast_1d(np.asarray(wavelengths_nm, dtype=float)), grid[0], grid[-1])
        i = np.clip(np.searchsorted(grid, wl) - 1, 0, grid.size - 2)
        f = ((wl - grid[i]) / (grid[i + 1] - grid[i]))[:, None]
        return (1.0 - f) * self.phase[i] + f * self.phase[i + 1]

    def white(self, weights_wavelength_nm, weights) -> TabulatedPhase:
        """The phase function of light of spectral ``weights`` at ``weights_wavelength_nm``."""
        w = np.asarray(weights, dtype=float)
        return TabulatedPhase(self.theta_deg, w @ self.at(weights_wavelength_nm) / w.sum())


def load_rain_phases() -> SpectralPhases:
    """Rain drops' phase functions from the packaged ``rain_drop_phase.npz`` (bin centres,
    extended to 0 and 180 deg with the end bins' values)."""
    phase, meta = read_packaged_npz(
        RAIN_PHASE_NPZ, "phase", RAIN_PHASE_FORMAT, "rain phase functions",
        "tools/build_rain_phase.py",
    )  # fmt: skip
    theta = np.concatenate([[0.0], meta["theta_deg"], [180.0]])
    phase = np.asarray(phase, dtype=float)
    phase = np.concatenate([phase[:, :1], phase, phase[:, -1:]], axis=1)
    return SpectralPhases(np.asarray(meta["wavelength_nm"], float), theta, phase)


#: The Sun's mean apparent angular radius (deg: the IAU's nominal 695 700 km at 1 au, 959.6").
SUN_RADIUS_DEG = 0.26656


def disk_smoothed(theta_deg, values, radius_deg: float = SUN_RADIUS_DEG):
    """Phase functions ``values`` (..., A) at ``theta_deg`` as seen in the light of a uniform
    disk of angular ``radius_deg`` (the Sun's: it smooths the bows' caustics over its
    diameter): each averaged over the disk's chords, weights sqrt(R^2 - x^2) at offsets x in
    scattering angle (mirrored at 0 and 180 deg), on a 0.01 deg grid. Returns (the grid, the
    smoothed values)."""
    step = 0.01
    fine = np.arange(0.0, 180.0 + step / 2, step)
    rows = np.atleast_2d(np.asarray(values, dtype=float))
    x = np.arange(-radius_deg, radius_deg + step / 2, step)
    kernel = np.sqrt(np.maximum(radius_deg**2 - x**2, 0.0))
    kernel /= kernel.sum()
    half = x.size // 2
    out = np.empty((rows.shape[0], fine.size))
    for k, row in enumerate(rows):
        v = np.pad(np.interp(fine, theta_deg, row), half, mode="reflect")
        out[k] = np.convolve(v, kernel, mode="valid")[: fine.size]
    return fine, out.reshape(*np.shape(values)[:-1], fine.size)


#: The rain's bows by Lorenz-Mie theory (``tools/build_rain_mie_phase.py``), the file's format
#: version, where they replace the rays' table (deg) and over how many degrees at each end
#: they take over from it.
RAIN_MIE_NPZ = "rain_drop_mie_phase.npz"
RAIN_MIE_FORMAT = 1
BOWS_DEG = (125.0, 145.0)
BOWS_BLEND_DEG = 1.0
#: The rain rate (mm/h) a cloud layer's rain has unless told (moderate rain).
DEFAULT_RAIN_MM_H = 4.0


def _log_step(axis: np.ndarray, value: float) -> tuple[int, float]:
    """Where ``value`` falls on the rising ``axis``, linear in the logarithm and held beyond
    its ends: the node below (i) and the fraction of the way to the next (0-1)."""
    log_axis = np.log(axis)
    u = float(np.clip(np.log(float(value)), log_axis[0], log_axis[-1]))
    i = int(np.clip(np.searchsorted(log_axis, u) - 1, 0, axis.size - 2))
    return i, (u - log_axis[i]) / (log_axis[i + 1] - log_axis[i])


@dataclass(frozen=True)
class RainBows:
    """The rain's bows by Mie theory (1/sr, normalised as :data:`RAIN_PHASES`: by the drops'
    geometric cross-section), at ``theta_deg`` (A; BOWS_DEG in 0.05 deg bins) and
    ``wavelength_nm`` (W): Marshall-Palmer rain by ``rain_mm_h`` (R; ``by_rate`` (R, W, A)) and
    drops of one size by ``radius_um`` (N; ``by_radius`` (N, W, A), a 10 % spread)."""

    rain_mm_h: np.ndarray
    radius_um: np.ndarray
    wavelength_nm: np.ndarray
    theta_deg: np.ndarray
    by_rate: np.ndarray
    by_radius: np.ndarray

    def at(self, wavelengths_nm, rain_mm_h: float = DEFAULT_RAIN_MM_H,
           drop_radius_um: float | None = None) -> np.ndarray:  # fmt: skip
        """The bows (N, A) at ``wavelengths_nm`` (linear between the table's, held beyond) of
        rain at ``rain_mm_h``, or of drops of one radius ``drop_radius_um`` (um); both
        linear in their logarithm between the table's, held beyond."""
        if drop_radius_um is None:
            axis, table, value = self.rain_mm_h, self.by_rate, rain_mm_h
        else:
            axis, table, value = self.radius_um, self.by_radius, drop_radius_um
        i, f = _log_step(axis, value)
        rows = (1.0 - f) * table[i] + f * table[i + 1]  # (W, A)
        return SpectralPhases(self.wavelength_nm, self.theta_deg, rows).at(wavelengths_nm)


def load_rain_bows() -> RainBows:
    """The rain's Mie bows from the packaged ``rain_drop_mie_phase.npz``."""
    phase, meta = read_packaged_npz(
        RAIN_MIE_NPZ, "phase", RAIN_MIE_FORMAT, "rain bows", "tools/build_rain_mie_phase.py",
    )  # fmt: skip
    narrow, _ = read_packaged_npz(
        RAIN_MIE_NPZ, "narrow", RAIN_MIE_FORMAT, "rain bows", "tools/build_rain_mie_phase.py",
    )  # fmt: skip
    return RainBows(
        np.asarray(meta["rain_mm_h"], float), np.asarray(meta["narrow_radius_um"], float),
        np.asarray(meta["wavelength_nm"], float), np.asarray(meta["theta_deg"], float),
        np.asarray(phase, float), np.asarray(narrow, float),
    )  # fmt: skip


@cache
def rain_bows() -> RainBows:
    """The rain's bows by Mie theory (:func:`load_rain_bows`, read at first use: the tool that
    builds them imports this module)."""
    return load_rain_bows()


def rain_phases_with_bows(wavelengths_nm, rain_mm_h: float = DEFAULT_RAIN_MM_H,
                          drop_radius_um: float | None = None) -> np.ndarray:  # fmt: skip
    """Rain's phase functions (N, A) at ``wavelengths_nm`` on :data:`RAIN_PHASES`' angles: its
    rays', with the bows (BOWS_DEG) from Mie theory for the drops of ``rain_mm_h`` or of
    ``drop_radius_um`` (:class:`RainBows`), taking over linearly within BOWS_BLEND_DEG of
    each end."""
    rows = RAIN_PHASES.at(wavelengths_nm)
    theta = RAIN_PHASES.theta_deg
    lo, hi = BOWS_DEG
    inside = (theta > lo) & (theta < hi)
    w = np.clip(np.minimum(theta - lo, hi - theta) / BOWS_BLEND_DEG, 0.0, 1.0)[inside]
    table = rain_bows()
    bows = table.at(wavelengths_nm, rain_mm_h, drop_radius_um)
    mie = np.stack([np.interp(theta[inside], table.theta_deg, row) for row in bows])
    rows[:, inside] = (1.0 - w) * rows[:, inside] + w * mie
    return rows


def rain_channel_phases(wavelengths_nm, to_output, rain_mm_h: float = DEFAULT_RAIN_MM_H,
                        drop_radius_um: float | None = None) -> np.ndarray:  # fmt: skip
    """Rain's phase function per output channel (4, RENDER_PHASE_TEXELS) on the renderer's
    grid: the wavelengths' phase functions (:func:`rain_phases_with_bows`: the rays', the
    bows by Mie theory for the drops of ``rain_mm_h`` or ``drop_radius_um``) seen in the
    Sun's disk (:func:`disk_smoothed`), weighted as sunlight's share of each channel
    (``to_output`` (4, N): a SpectralBasis's, per unit of the solar spectrum at
    ``wavelengths_nm``), cut flat at :data:`TRUNCATION_DEG` as :data:`RAIN_RENDER_PHASE` and
    divided by the same kept share, held >= 0 (a channel's weights may be negative)."""
    m = np.asarray(to_output, dtype=float)
    rows = rain_phases_with_bows(wavelengths_nm, rain_mm_h, drop_radius_um)
    fine, per_wavelength = disk_smoothed(RAIN_PHASES.theta_deg, rows)
    t = render_grid_deg()
    table = np.stack([np.interp(np.maximum(t, TRUNCATION_DEG), fine, row)
                      for row in per_wavelength])  # fmt: skip
    kept = 1.0 - _rays_within
    channels = (m @ table) / m.sum(axis=1, keepdims=True) / kept
    return np.maximum(channels, 0.0)


#: The rain drops' phase functions per wavelength.
RAIN_PHASES: SpectralPhases = load_rain_phases()

#: The cloud and fog droplets' Mie phase functions by effective radius and wavelength
#: (``tools/build_droplet_spectral_phase.py``), the file's format version, and the clouds'
#: droplets' effective radius (um: the one every cloud has).
DROPLET_PHASE_NPZ = "cloud_droplet_spectral_phase.npz"
DROPLET_PHASE_FORMAT = 2
CLOUD_R_EFF_UM = 10.0


@cache
def _droplet_family() -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(effective radii (K,) um, wavelengths (W,) nm, angles (A + 1,) deg, phase (K, W, A + 1))
    from the packaged file (from 5 deg; held flat below it, as the renderer cuts them)."""
    phase, meta = read_packaged_npz(
        DROPLET_PHASE_NPZ, "phase", DROPLET_PHASE_FORMAT, "droplet phase functions",
        "tools/build_droplet_spectral_phase.py",
    )  # fmt: skip
    theta = np.concatenate([[0.0], meta["theta_deg"]])
    phase = np.asarray(phase, dtype=float)
    return (np.asarray(meta["r_eff_um"], float), np.asarray(meta["wavelength_nm"], float),
            theta, np.concatenate([phase[..., :1], phase], -1))  # fmt: skip


def load_droplet_phases(r_eff_um: float = CLOUD_R_EFF_UM) -> SpectralPhases:
    """The phase functions of droplets of effective radius ``r_eff_um`` (linear in its
    logarithm between the packaged ones, held beyond: 5-20 um) by wavelength."""
    r_eff, wavelength, theta, phase = _droplet_family()
    i, f = _log_step(r_eff, r_eff_um)
    return SpectralPhases(wavelength, theta, (1.0 - f) * phase[i] + f * phase[i + 1])


#: The clouds' droplets' phase functions by wavelength (r_eff 10 um).
DROPLET_PHASES: SpectralPhases = load_droplet_phases()


def droplet_channel_phases(wavelengths_nm, to_output,
                           r_eff_um: float = CLOUD_R_EFF_UM) -> np.ndarray:  # fmt: skip
    """The droplets' phase function per output channel (4, RENDER_PHASE_TEXELS) on the
    renderer's grid: the Mie phase functions of droplets of ``r_eff_um`` (the clouds', or a
    fog's: :func:`load_droplet_phases`) at the wavelengths, cut flat at
    :data:`TRUNCATION_DEG`, weighted as sunlight's share of each channel (``to_output``
    (4, N) of a SpectralBasis at ``wavelengths_nm``), held >= 0 and each normalised over the
    sphere as :data:`RENDER_PHASE` (whose extinction scale they share): the cloudbow's, the
    fogbow's and the glory's colours."""
    m = np.asarray(to_output, dtype=float)
    t = render_grid_deg()
    phases = DROPLET_PHASES if r_eff_um == CLOUD_R_EFF_UM else load_droplet_phases(r_eff_um)
    rows = phases.at(wavelengths_nm)
    table = np.stack([np.interp(np.maximum(t, TRUNCATION_DEG), phases.theta_deg, r)
                      for r in rows])  # fmt: skip
    channels = np.maximum(m @ table, 0.0)
    return np.stack([TabulatedPhase(t, c).values for c in channels])


#: The phase function the renderer marches with (and the clouds' multiple-scattering table of
#: skydome.clouds.ms_table is computed for): :data:`MIE_PHASE` with its diffraction peak cut
#: flat at :data:`TRUNCATION_DEG`, on the renderer's grid; :data:`PEAK_FRACTION` is the
#: fraction f of scattering the peak sends straight on (extinction and optical depths scale
#: by 1 - f, ssa stays 1).
RENDER_PHASE, PEAK_FRACTION = MIE_PHASE.delta_truncated()

#: Rain's in white light (sunlight seen by the eye: the wavelengths weighted by V(lambda)),
#: the same way: its rays' phase function cut flat at :data:`TRUNCATION_DEG`;
#: :data:`RAIN_PEAK_FRACTION` is what goes straight on of the drops' extinction (efficiency 2):
#: the diffraction's half and the share of their rays' half within the truncation angle.
#: (The march scatters with :func:`rain_channel_phases`, each channel its own colours.)
_V = read_packaged_csv("cie_luminous_efficiency_5nm.csv")
RAIN_RENDER_PHASE, _rays_within = RAIN_PHASES.white(
    _V["wavelength_nm"], _V["V_photopic"]
).delta_truncated()
RAIN_PEAK_FRACTION = 0.5 + 0.5 * _rays_within
