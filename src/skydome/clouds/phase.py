"""The phase function of cloud droplets, as a mixture of Henyey-Greenstein lobes.

A water cloud's phase function (Mie theory for droplets of r_eff ~ 10 um in the visible) has a
diffraction peak a degree wide that holds about half of the scattered light, a broad forward
lobe, a minimum near 100 deg, the cloudbow at ~140 deg and the glory at 180 deg. The renderer
and the Monte Carlo reference (:mod:`skydome.reference.clouds_mc`) both use it as

    P(cos theta) = sum_j w_j HG(cos theta, g_j),   w_j >= 0,  sum_j w_j = 1,

(1/sr, normalised to 1 over the sphere), a form that is cheap in GLSL (weights and asymmetries
as uniforms) and exactly sampled by choosing a lobe by weight and inverting its CDF. The HG
lobes are monotone in angle: they keep the peak, the forward lobe and the first moment of the
Mie phase function but not the cloudbow nor the glory (see ``tools/build_cloud_phase.py``).

:data:`CLOUD_PHASE` is the mixture fitted to the Mie phase function of a gamma distribution of
water droplets (r_eff 10 um, v_eff 0.1, m = 1.333, 550 nm), read from the packaged
``cloud_droplet_phase.csv``. :data:`RENDER_PHASE` is what the renderer marches with: that
mixture with its diffraction peak (the lobes of g >= 0.98) taken out as a forward delta
(:meth:`LobePhase.delta_truncated`), the extinction scaled by 1 - :data:`PEAK_FRACTION`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from skydome.errors import ParameterError
from skydome.io.packaged import read_packaged_csv
from skydome.physics.phase import MAX_LOBES, henyey_greenstein, sample_hg

__all__ = [
    "CLOUD_PHASE",
    "LobePhase",
    "PEAK_FRACTION",
    "PHASE_CSV",
    "RENDER_PHASE",
    "load_cloud_phase",
    "sample_hg",
]

#: The packaged table of :data:`CLOUD_PHASE` (built by ``tools/build_cloud_phase.py``).
PHASE_CSV = "cloud_droplet_phase.csv"


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


def load_cloud_phase() -> LobePhase:
    """The cloud droplet phase function from the packaged ``cloud_droplet_phase.csv``."""
    t = read_packaged_csv(PHASE_CSV, ("weight", "g"))
    return LobePhase(tuple(t["weight"]), tuple(t["g"]))


#: The phase function of a water-droplet cloud at 550 nm (r_eff 10 um, v_eff 0.1), HG lobes
#: fitted to Mie theory by ``tools/build_cloud_phase.py``.
CLOUD_PHASE: LobePhase = load_cloud_phase()

#: The phase function the renderer marches with (and the clouds' multiple-scattering table of
#: skydome.clouds.ms_table is computed for): :data:`CLOUD_PHASE` without its diffraction peak,
#: ``CLOUD_PHASE.delta_truncated(0.98)``; :data:`PEAK_FRACTION` is the fraction f of scattering
#: the peak sends straight on (extinction and optical depths scale by 1 - f, ssa stays 1).
RENDER_PHASE, PEAK_FRACTION = CLOUD_PHASE.delta_truncated(PEAK_G)
