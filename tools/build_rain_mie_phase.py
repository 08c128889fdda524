"""Build the rain's bows by Lorenz-Mie theory: skydome/data/rain_drop_mie_phase.npz (what the
renderer scatters rain with over 125-145 deg: skydome.clouds.phase.rain_channel_phases,
elsewhere the rays of tools/build_rain_phase.py).

Usage::

    python tools/build_rain_mie_phase.py          # about 4 minutes on 2 cores

Rays draw each bow as a caustic at Descartes' angle; waves give it its width, the
supernumerary arcs inside the primary (outside the secondary), and both set by the drops'
sizes (Airy 1838; van de Hulst 1957 ch. 13): small drops (drizzle) draw broad, pale bows with
supernumeraries, large ones (showers) narrow, saturated bows. So the bows are tabulated from
Mie theory, integrated over the drop sizes of each rain rate.

Model (each input's source)
---------------------------
- Mie theory: skydome.atmosphere.mie.mie_coefficients (Bohren & Huffman 1983, ch. 4), the
  amplitude functions summed here in chunks of terms (a 1 mm drop at 400 nm needs 15 800);
  within 1e-8 of miepython at x = 5700 (tests/test_mie.py; tests/test_rain_mie.py against
  tools/make_rain_mie_reference.py). Water's index: Hale & Querry (1973).
- Drops: Marshall & Palmer (1948), N(D) = N0 exp(-Lambda D), Lambda = 4.1 R^-0.21 /mm, at the
  rain rates RATES_MM_H (their spread of sizes washes the supernumeraries out); and drops of
  one size, gamma distributions (Hansen & Travis 1974 eq. 2.56) of effective radius
  NARROW_RADII_UM and variance NARROW_V_EFF (a 10 % spread: the supernumeraries stay); Mie for radii RADII_UM (25-1000 um, MIE_RADII of them, log-spaced and
  jittered within their steps by a fixed seed: the bows' fine ripple, which depends on the
  radius to within a fraction of a micrometre, averages out instead of aliasing); larger drops
  by their rays (the packaged geometric table: their Airy shift is < 0.15 deg).
- Normalisation: as the rays' table: the light a drop refracts and reflects, its geometric
  cross-section pi r^2 (the other half of its extinction is diffraction, in the forward peak):
  phase = sum N dC/dOmega / sum N pi r^2 with dC/dOmega = (|S1|^2 + |S2|^2) / (2 k^2).
- Angles: bins of 0.05 deg over 125-145 deg (the rays' table's), each the mean of 4 angles.
- Wavelengths: 400-760 nm every 20 nm.

Arrays: ``phase`` (R, W, A; 1/sr: Marshall-Palmer by rain rate), ``narrow`` (N, W, A; drops of
one size by radius) and ``meta_json``: the format version, the rain rates (mm/h), the radii
(um), the wavelengths (nm), the angles (deg, the bins' centres) and this provenance.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np

from skydome.atmosphere.mie import gamma_size_distribution, mie_coefficients
from skydome.clouds.phase import RAIN_PHASES
from skydome.io.packaged import write_packaged_npz
from skydome.physics.sphere_optics import water_index

OUTPUT = (
    Path(__file__).resolve().parents[1] / "src" / "skydome" / "data" / "rain_drop_mie_phase.npz"
)
RATES_MM_H = (0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0)
NARROW_RADII_UM = (100.0, 150.0, 200.0, 300.0, 500.0)
NARROW_V_EFF = 0.01
WAVELENGTHS_NM = np.arange(400.0, 761.0, 20.0)
BIN_DEG = 0.05
EDGES_DEG = np.round(np.arange(125.0, 145.0 + BIN_DEG / 2, BIN_DEG), 6)
SAMPLES_PER_BIN = 4
MIE_RADII = 400
RADIUS_RANGE_UM = (25.0, 1000.0)
SEED = 20261205

#: The file's layout (skydome.clouds.phase.RAIN_MIE_FORMAT).
FORMAT_VERSION = 1


def radii_um(count: int = MIE_RADII, seed: int = SEED) -> tuple[np.ndarray, np.ndarray]:
    """The Mie radii (um), log-spaced over RADIUS_RANGE_UM and jittered within their steps,
    and each one's step (um: the width it stands for in the size integral)."""
    lo, hi = np.log(RADIUS_RANGE_UM[0]), np.log(RADIUS_RANGE_UM[1])
    edges = np.exp(np.linspace(lo, hi, count + 1))
    u = np.random.default_rng(seed).random(count)
    return edges[:-1] + u * np.diff(edges), np.diff(edges)


def sample_angles_deg(edges_deg=EDGES_DEG, samples: int = SAMPLES_PER_BIN) -> np.ndarray:
    """The angles each bin is the mean of: ``samples`` evenly inside it (bins, samples)."""
    width = np.diff(edges_deg)[:, None]
    return edges_deg[:-1, None] + (np.arange(samples) + 0.5)[None, :] / samples * width


def drop_light(radii, wavelength_nm: float, theta_deg, chunk: int = 2048) -> np.ndarray:
    """Each drop's scattered light per unit solid angle, dC/dOmega (um^2/sr), at
    ``theta_deg`` (A,) for ``radii`` (um, R,): (R, A). The amplitude functions S1, S2 summed
    over the Mie terms in chunks (the angular functions pi_n, tau_n by their recurrence)."""
    r = np.asarray(radii, dtype=float)
    wl_um = wavelength_nm / 1e3
    k = 2.0 * math.pi / wl_um
    x = k * r
    m = complex(float(water_index(wavelength_nm)), 0.0)
    a, b = mie_coefficients(m, x)
    n_max = a.shape[0]
    nstop = np.floor(x + 4.0 * np.cbrt(x) + 2.0).astype(int)
    mu = np.cos(np.radians(np.asarray(theta_deg, dtype=float)))
    s1 = np.zeros((r.size, mu.size), complex)
    s2 = np.zeros((r.size, mu.size), complex)
    p_prev, p = np.zeros_like(mu), np.ones_like(mu)
    for start in range(0, n_max, chunk):
        rows = min(chunk, n_max - start)
        pi = np.empty((rows, mu.size))
        tau = np.empty((rows, mu.size))
        for j in range(rows):
            n = start + j + 1
            if n > 1:
                p_prev, p = p, ((2 * n - 1) * mu * p - n * p_prev) / (n - 1)
            pi[j] = p
            tau[j] = n * mu * p - (n + 1) * p_prev
        live = nstop > start  # drops with terms in this chunk
        n = np.arange(start + 1, start + rows + 1, dtype=float)[:, None]
        c = (2 * n + 1) / (n * (n + 1))
        ca = (c * a[start : start + rows][:, live]).T
        cb = (c * b[start : start + rows][:, live]).T
        for s, first, second in ((s1, pi, tau), (s2, tau, pi)):
            s[live] += (ca.real @ first + cb.real @ second) + 1j * (
                ca.imag @ first + cb.imag @ second
            )
    return (np.abs(s1) ** 2 + np.abs(s2) ** 2) / (2.0 * k * k)


def marshall_palmer(diameter_mm, rain_mm_h: float) -> np.ndarray:
    """Marshall & Palmer's number of drops per unit diameter, to a constant (N0 cancels)."""
    return np.exp(-4.1 * rain_mm_h**-0.21 * np.asarray(diameter_mm, dtype=float))


def bow_phase(light, radii, steps, geometric_row, rain_mm_h: float) -> np.ndarray:
    """The bows' phase function (1/sr) of Marshall-Palmer rain at ``rain_mm_h``: the Mie drops'
    ``light`` (R, bins; dC/dOmega at ``radii`` of widths ``steps``, um) and, beyond the largest,
    their rays' phase function ``geometric_row`` (bins), each drop counted by its geometric
    cross-section."""
    r = np.asarray(radii, dtype=float)
    weight = marshall_palmer(2.0 * r / 1e3, rain_mm_h) * np.asarray(steps) / 1e3 * 2.0
    # drops larger than the Mie range: their cross-section, integrated in closed form
    lam = 4.1 * rain_mm_h**-0.21
    d0 = 2.0 * RADIUS_RANGE_UM[1] / 1e3  # mm
    # int_{d0}^inf exp(-lam D) pi (D / 2)^2 dD, D in mm, as um^2: x 1e6
    tail = math.pi / 4.0 * math.exp(-lam * d0) * (d0**2 / lam + 2 * d0 / lam**2 + 2 / lam**3)
    tail *= 1e6
    area = weight @ (math.pi * r * r) + tail
    return (weight @ light + tail * np.asarray(geometric_row)) / area


def narrow_phase(light, radii, steps, radius_um: float) -> np.ndarray:
    """The bows' phase function (1/sr) of drops of about one size: a gamma distribution of
    effective radius ``radius_um`` and variance NARROW_V_EFF over the Mie drops."""
    r = np.asarray(radii, dtype=float)
    weight = gamma_size_distribution(radius_um, NARROW_V_EFF, r) * np.asarray(steps)
    return (weight @ light) / (weight @ (math.pi * r * r))


def build(wavelengths_nm=WAVELENGTHS_NM, rates=RATES_MM_H, narrow=NARROW_RADII_UM,
          radii=None) -> dict:  # fmt: skip
    r, steps = radii_um() if radii is None else radii
    angles = sample_angles_deg()
    centres = 0.5 * (EDGES_DEG[1:] + EDGES_DEG[:-1])
    geometric = RAIN_PHASES.at(wavelengths_nm)
    phase = np.empty((len(rates), len(wavelengths_nm), centres.size))
    one_size = np.empty((len(narrow), len(wavelengths_nm), centres.size))
    for w, wl in enumerate(wavelengths_nm):
        light = drop_light(r, float(wl), angles.ravel()).reshape(r.size, *angles.shape).mean(-1)
        geo = np.interp(centres, RAIN_PHASES.theta_deg, geometric[w])
        for i, rate in enumerate(rates):
            phase[i, w] = bow_phase(light, r, steps, geo, rate)
        for i, radius in enumerate(narrow):
            one_size[i, w] = narrow_phase(light, r, steps, radius)
        print(f"  {wl:.0f} nm", flush=True)
    meta = {
        "format_version": FORMAT_VERSION,
        "about": "Rain's bows (1/sr; axes: rain rate, wavelength, angle) by Lorenz-Mie theory "
        f"over Marshall-Palmer drops ({r.size} radii {RADIUS_RANGE_UM[0]:g}-"
        f"{RADIUS_RANGE_UM[1]:g} um, larger by their rays), normalised by the drops' "
        "geometric cross-section (the light they refract and reflect); index Hale & Querry "
        "(1973). Built by tools/build_rain_mie_phase.py.",
        "rain_mm_h": [float(v) for v in rates],
        "narrow_radius_um": [float(v) for v in narrow],
        "narrow_v_eff": NARROW_V_EFF,
        "wavelength_nm": [float(w) for w in wavelengths_nm],
        "theta_deg": [round(float(t), 4) for t in centres],
    }
    return {"phase": phase.astype(np.float32), "narrow": one_size.astype(np.float32), "meta": meta}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--output", type=Path, default=OUTPUT)
    args = ap.parse_args()
    table = build()
    write_packaged_npz(args.output, table.pop("meta"), **table)
    print(f"wrote {args.output} ({args.output.stat().st_size / 1e3:.0f} kB)")


if __name__ == "__main__":
    main()
