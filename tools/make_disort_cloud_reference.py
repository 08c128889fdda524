"""Generate ``tests/data/disort_cloud_decks.json``: DISORT radiances and fluxes under uniform
plane-parallel cloud decks in skydome's ``earth`` atmosphere, an independent reference.

Offline only: it needs a C compiler and a throwaway environment with the ``pydisort`` wheel
(and PyTorch, which that wheel requires); never run it from CI or the test suite. To run it::

    python3 -m venv /tmp/disort-venv
    /tmp/disort-venv/bin/pip install /opt/wheels/torch-2.13.0+cpu-cp311-cp311-manylinux_2_28_x86_64.whl \
        pydisort miepython numpy
    # (or `pip install torch==2.13.0 ...` where the CPU wheel is on the index; plain `torch`
    #  pulls a multi-GB CUDA build)
    PYTHONPATH=src /tmp/disort-venv/bin/python tools/make_disort_cloud_reference.py [--workers 2]

pip resolves ``pydisort`` to 1.6.0 with torch 2.13 (1.8.x pins torch 2.10 and links CUDA).

**Which DISORT.** The radiative transfer is DISORT 2.1.3 in C (``cdisort``: Stamnes et al.
1988 ported to C by T. Dowling; the version in libRadtran), the source that the ``pydisort``
wheel ships in ``pydisort/cdisort213/``. pydisort 1.6.0's PyTorch wrapper does not work with
the torch 2.13 CPU wheel (it was compiled against another libtorch: ``Disort.forward``
rejects well-formed 4-d tensors with "prop.dim() != 4"), so this script compiles the wheel's
``cdisort.c`` and ``locate.c`` with a 40-line C driver (:data:`_DRIVER_C`) into a shared
library in a temporary folder and calls it through ctypes. The physics is DISORT's alone;
skydome supplies only the atmosphere's coefficient profiles (the model's input).

**Normalisation, verified** (:func:`check_normalisation`, run first, recorded in the
provenance): with ``fbeam = 1`` the direct flux at the top is ``umu0`` and at optical depth τ
``umu0 exp(-τ/umu0)`` (Beer's law), and the upward intensity over a Lambertian ground under a
pure absorber is ``A umu0 exp(-τ/umu0) / π``: intensities are per unit ``fbeam`` and fluxes
are horizontal fluxes per unit ``fbeam``. So with a beam of unit irradiance normal to it,
``uu`` is L/E0 (sr^-1) and ``rfldir``, ``rfldn``, ``flup`` are E/E0 (no extra π or umu0).

**What it computes.** A plane-parallel atmosphere, 24 layers from 0 to 100 km (boundaries
:data:`LEVELS_M`: 250 m steps to 2 km, coarser above), each layer's optical depths the
integrals of skydome's ``earth`` coefficients times their density profiles (U.S. Standard
1976 air with Bodhaine Rayleigh, OPAC clean continental aerosol of AOD 0.1 at 550 nm with
its spectral single-scattering albedo and a Cornette-Shanks phase function of
``mie_g``, 300 DU of AFGL ozone with Serdyuchenko cross-sections; Rayleigh phase 3(1+μ²)/16π
as skydome's). The cloud fills 1000-2000 m (four layers) with optical depth τ_c, the same at
every wavelength (extinction efficiency ≈ 2 for r_eff = 10 µm), single-scattering albedo 1
(m = 1.333 + 0i, the same at every wavelength), and a Mie phase function computed at each
wavelength for a gamma distribution of effective radius 10 µm and effective variance 0.1
(n(r) ∝ r^7 exp(-r / 1 µm)), its Legendre moments by Gauss-Legendre projection. Cloud, air,
aerosol and ozone mix in a layer by optical depth: ω = Σ τ_sca / Σ τ_ext, χ_l = Σ τ_sca,i
χ_l,i / Σ τ_sca,i. DISORT: 64 streams, 1000 phase moments, delta-M (always on in cdisort),
Nakajima-Tanaka intensity correction (the moment-based one), accuracy 0 (all azimuth
terms), Lambertian ground, beam of unit flux normal to it at the top, plane-parallel (no
pseudo-spherical correction).

Wavelengths 380-780 nm every 20 nm; luminous quantities are Σ w_i X_i / Σ w_i with
w_i = V(λ_i) E_sun(λ_i) Δλ_i (trapezoid weights; skydome's CIE 1924 V and ASTM G-173 tables),
i.e. L_v/E_v0 and E_v/E_v0 where E_v0 = 683 ∫ V E_sun dλ is the extraterrestrial luminous
irradiance normal to the beam. The per-wavelength values are stored too.

Cases: τ_c ∈ {5, 20, 40} × Sun elevation ∈ {60, 45, 20}° × ground albedo ∈ {0, 0.3}, the
same six clear ones (τ_c = 0), and τ_c = 37.5 at 45° over albedo 0.3 (``earth``'s). Outputs
at the ground: radiance looking up at elevations 10-90° and relative azimuths 0 (towards the
Sun), 90 and 180°; global, direct and diffuse horizontal illuminance; the upward flux at the
cloud top (2000 m) and at the top of the atmosphere; the downward flux at the cloud base.
About 6 minutes with 2 workers on a 2-core machine.
"""

from __future__ import annotations

import argparse
import ctypes
import datetime
import json
import math
import multiprocessing
import platform
import subprocess
import sys
import tempfile
import time
from importlib import metadata
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "tests" / "data" / "disort_cloud_decks.json"

WAVELENGTHS_NM = np.arange(380.0, 781.0, 20.0)
LEVELS_M = np.array(
    [0, 250, 500, 750, 1000, 1250, 1500, 1750, 2000, 2500, 3000, 4000, 5000, 6000, 8000,
     10000, 12500, 15000, 20000, 25000, 30000, 40000, 50000, 70000, 100000],
    dtype=float,
)  # fmt: skip
CLOUD_BASE_M, CLOUD_TOP_M = 1000.0, 2000.0
NSTR = 64
NMOM = 1000
R_EFF_UM, V_EFF = 10.0, 0.1
WATER_INDEX = 1.333
VIEW_ELEVATIONS_DEG = (10.0, 20.0, 30.0, 45.0, 60.0, 75.0, 90.0)
VIEW_AZIMUTHS_DEG = (0.0, 90.0, 180.0)
SUN_ELEVATIONS_DEG = (60.0, 45.0, 20.0)
ALBEDOS = (0.0, 0.3)
CLOUD_TAUS = (5.0, 20.0, 40.0)
N_QUAD = 4000  # Gauss-Legendre nodes in cos(scattering angle) for phase functions
N_RADII = 500
R_RANGE_UM = (0.5, 35.0)

_DRIVER_C = r"""
#include <string.h>
#include "cdisort.h"
int skydome_disort(int nlyr, int nstr, int nmom, const double *dtauc, const double *ssalb,
                   const double *pmom, double umu0, double phi0, double albedo,
                   int ntau, const double *utau, int numu, const double *umu,
                   int nphi, const double *phi, int intensity_correction,
                   double *flux_out, double *uu_out) {
  disort_state ds; disort_output out;
  memset(&ds, 0, sizeof ds); memset(&out, 0, sizeof out);
  ds.accur = 0.0;
  ds.flag.ibcnd = GENERAL_BC; ds.flag.usrtau = TRUE; ds.flag.usrang = TRUE;
  ds.flag.lamber = TRUE; ds.flag.planck = FALSE; ds.flag.spher = FALSE; ds.flag.onlyfl = FALSE;
  ds.flag.quiet = QUIET; ds.flag.intensity_correction = intensity_correction ? TRUE : FALSE;
  ds.flag.old_intensity_correction = TRUE; ds.flag.general_source = FALSE;
  ds.flag.output_uum = FALSE; ds.flag.brdf_type = BRDF_NONE;
  ds.nlyr = nlyr; ds.nstr = nstr; ds.nmom = nmom; ds.ntau = ntau; ds.numu = numu;
  ds.nphi = nphi; ds.nphase = 0;
  c_disort_state_alloc(&ds); c_disort_out_alloc(&ds, &out);
  for (int l = 0; l < nlyr; l++) {
    ds.dtauc[l] = dtauc[l]; ds.ssalb[l] = ssalb[l];
    for (int k = 0; k <= nmom; k++)
      ds.pmom[k + l * (ds.nmom_nstr + 1)] = pmom[k + l * (nmom + 1)];
  }
  for (int i = 0; i < ntau; i++) ds.utau[i] = utau[i];
  for (int i = 0; i < numu; i++) ds.umu[i] = umu[i];
  for (int i = 0; i < nphi; i++) ds.phi[i] = phi[i];
  ds.bc.fbeam = 1.0; ds.bc.umu0 = umu0; ds.bc.phi0 = phi0; ds.bc.fisot = 0.0;
  ds.bc.albedo = albedo; ds.wvnmlo = 0.0; ds.wvnmhi = 1.0;
  c_disort(&ds, &out, NULL);
  for (int i = 0; i < ntau; i++) {
    flux_out[3 * i] = out.rad[i].rfldir; flux_out[3 * i + 1] = out.rad[i].rfldn;
    flux_out[3 * i + 2] = out.rad[i].flup;
  }
  for (int j = 0; j < nphi; j++)
    for (int lu = 0; lu < ntau; lu++)
      for (int iu = 0; iu < numu; iu++)
        uu_out[iu + numu * (lu + ntau * j)] = out.uu[iu + ds.numu * (lu + ds.ntau * j)];
  c_disort_out_free(&ds, &out); c_disort_state_free(&ds);
  return 0;
}
"""

_LIB = None


def build_library(folder: Path) -> Path:
    """Compile the wheel's cdisort with the driver into ``folder``; the library's path."""
    import pydisort

    src = Path(pydisort.__file__).parent / "cdisort213"
    (folder / "driver.c").write_text(_DRIVER_C)
    lib = folder / "libskydome_disort.so"
    cmd = ["gcc", "-O2", "-shared", "-fPIC", f"-I{src}", str(folder / "driver.c"),
           str(src / "cdisort.c"), str(src / "locate.c"), "-lm", "-o", str(lib)]  # fmt: skip
    subprocess.run(cmd, check=True, capture_output=True)
    return lib


def _load(path: str):
    global _LIB
    if _LIB is None:
        lib = ctypes.CDLL(path)
        p = np.ctypeslib.ndpointer(dtype=np.float64, flags="C_CONTIGUOUS")
        i, d = ctypes.c_int, ctypes.c_double
        lib.skydome_disort.argtypes = [i, i, i, p, p, p, d, d, d, i, p, i, p, i, p, i, p, p]
        _LIB = lib
    return _LIB


def disort(lib_path, dtauc, ssalb, pmom, umu0, albedo, utau, umu, phi, correction=True):
    """One monochromatic run: fluxes (ntau, 3: direct down, diffuse down, up) and intensities
    (nphi, ntau, numu), per unit beam irradiance normal to the beam."""
    lib = _load(lib_path)
    nlyr, n1 = pmom.shape
    flux = np.zeros((len(utau), 3))
    uu = np.zeros((len(phi), len(utau), len(umu)))
    lib.skydome_disort(nlyr, NSTR, n1 - 1, np.ascontiguousarray(dtauc, float),
                       np.ascontiguousarray(ssalb, float), np.ascontiguousarray(pmom, float),
                       float(umu0), 0.0, float(albedo), len(utau), np.asarray(utau, float),
                       len(umu), np.asarray(umu, float), len(phi), np.asarray(phi, float),
                       int(correction), flux, uu)  # fmt: skip
    return flux, uu


def check_normalisation(lib_path) -> dict:
    """Beer's law for the direct flux and a Lambertian ground's radiance under a pure
    absorber; raises if DISORT's normalisation is not the one assumed."""
    nl, mu0, alb = 10, 0.5, 0.3
    pm = np.zeros((nl, NSTR + 1))
    pm[:, 0] = 1.0
    tau = np.full(nl, 0.03)
    flux, uu = disort(lib_path, tau, np.zeros(nl), pm, mu0, alb, [0.0, 0.3], [-1.0, 0.5, 1.0],
                      [0.0], correction=False)  # fmt: skip
    direct = mu0 * math.exp(-0.3 / mu0)
    up = alb * direct / math.pi
    res = {
        "direct_flux_top": [float(flux[0, 0]), mu0],
        "direct_flux_tau0.3": [float(flux[1, 0]), direct],
        "up_radiance_ground_mu1": [float(uu[0, 1, 2]), up],
        "up_radiance_top_mu0.5": [float(uu[0, 0, 1]), up * math.exp(-0.3 / 0.5)],
    }
    for k, (got, want) in res.items():
        if abs(got - want) > 1e-6 * max(abs(want), 1e-3):
            raise SystemExit(f"normalisation check {k}: DISORT {got}, expected {want}")
    return {k: {"disort": v[0], "expected": v[1]} for k, v in res.items()}


def legendre_table(mu: np.ndarray, lmax: int) -> np.ndarray:
    """P_l(mu) for l = 0..lmax, shape (lmax + 1, len(mu))."""
    p = np.empty((lmax + 1, mu.size))
    p[0] = 1.0
    p[1] = mu
    for n in range(2, lmax + 1):
        p[n] = ((2 * n - 1) * mu * p[n - 1] - (n - 1) * p[n - 2]) / n
    return p


def moments(phase: np.ndarray, w: np.ndarray, ptab: np.ndarray) -> np.ndarray:
    """DISORT moments χ_0..χ_L of a phase function on the Gauss nodes (χ_0 = 1)."""
    phase = phase / (0.5 * np.sum(w * phase))
    return 0.5 * ptab @ (w * phase)


def cloud_phase(wavelength_nm: float, mu: np.ndarray, w: np.ndarray):
    """Size-averaged Mie phase function (normalised, 1/(4π) units × 4π) of the droplets on
    the nodes ``mu``, their asymmetry parameter and mean extinction efficiency."""
    import miepython

    r, dr = np.linspace(*R_RANGE_UM, N_RADII, retstep=True)
    a = R_EFF_UM * V_EFF
    nr = r ** ((1 - 3 * V_EFF) / V_EFF) * np.exp(-r / a) * dr
    x = 2 * math.pi * r / (wavelength_nm / 1000.0)
    coefs = [miepython.an_bn(WATER_INDEX, xi) for xi in x]
    nmax = max(len(c[0]) for c in coefs)
    n = np.arange(1, nmax + 1)
    an = np.zeros((r.size, nmax), complex)
    bn = np.zeros((r.size, nmax), complex)
    for i, (ai, bi) in enumerate(coefs):
        an[i, : len(ai)] = ai
        bn[i, : len(bi)] = bi
    # Angular functions pi_n, tau_n (Bohren & Huffman 4.47).
    pi = np.zeros((nmax, mu.size))
    tau = np.zeros((nmax, mu.size))
    pi[0] = 1.0
    if nmax > 1:
        pi[1] = 3.0 * mu
    for k in range(2, nmax):
        m = k + 1
        pi[k] = ((2 * m - 1) * mu * pi[k - 1] - m * pi[k - 2]) / (m - 1)
    tau[0] = mu * pi[0]
    tau[1:] = n[1:, None] * mu * pi[1:] - (n[1:, None] + 1) * pi[:-1]
    f = (2 * n + 1) / (n * (n + 1))
    s1 = (an * f) @ pi + (bn * f) @ tau
    s2 = (an * f) @ tau + (bn * f) @ pi
    intensity = nr @ (0.5 * (np.abs(s1) ** 2 + np.abs(s2) ** 2))
    csca = (2 * n + 1) @ (np.abs(an) ** 2 + np.abs(bn) ** 2).T / x**2 * 2  # Q_sca per radius
    cext = (2 * n + 1) @ (an + bn).real.T / x**2 * 2
    g_phase = intensity / (0.5 * np.sum(w * intensity))
    g = 0.5 * np.sum(w * g_phase * mu)
    area = nr * r**2
    return (
        intensity,
        float(g),
        float(np.sum(area * cext) / np.sum(area)),
        float(np.sum(area * csca) / np.sum(area)),
    )


def layer_optics():
    """Per wavelength and layer: (τ_rayleigh, τ_aerosol_ext, τ_aerosol_sca, τ_ozone), and the
    aerosol's Cornette-Shanks parameter."""
    from skydome.atmosphere.presets import preset

    p = preset("earth")
    c = p.coefficients(WAVELENGTHS_NM)
    cols = []
    for prof in (p.rayleigh_density, p.mie_density, p.absorption_density):
        col = []
        for lo, hi in zip(LEVELS_M[:-1], LEVELS_M[1:], strict=True):
            h, dh = np.linspace(lo, hi, 401, retstep=True)
            d = prof.density(h)
            col.append(dh * (np.sum(d) - 0.5 * (d[0] + d[-1])))
        cols.append(np.array(col))
    ray, mie, ozo = cols
    return {
        "rayleigh": np.outer(c["rayleigh_scattering"], ray),
        "aerosol_ext": np.outer(c["mie_extinction"], mie),
        "aerosol_sca": np.outer(c["mie_scattering"], mie),
        "ozone": np.outer(c["absorption_extinction"], ozo),
        "mie_g": p.mie_g,
        "params": p,
    }


def _task(args):
    lib_path, dtauc, ssalb, pmom, umu0, albedo, utau, umu, phi = args
    return disort(lib_path, dtauc, ssalb, pmom, umu0, albedo, utau, umu, phi)


def sig(x, digits=6):
    """Rounded to ``digits`` significant digits (nested lists)."""
    a = np.asarray(x, float)
    out = np.vectorize(lambda v: float(f"{v:.{digits}g}"))(a) if a.size else a
    return np.asarray(out).tolist()


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args(argv)
    t0 = time.time()

    import pydisort  # noqa: F401  (the source of cdisort; its version goes in the provenance)

    from skydome.physics.phase import cornette_shanks
    from skydome.spectra import photopic_efficiency, solar_irradiance

    tmp = tempfile.TemporaryDirectory()
    lib_path = str(build_library(Path(tmp.name)))
    norm = check_normalisation(lib_path)

    nw = WAVELENGTHS_NM.size
    opt = layer_optics()
    mu, w = np.polynomial.legendre.leggauss(N_QUAD)
    ptab = legendre_table(mu, NMOM)
    chi_ray = np.zeros(NMOM + 1)
    chi_ray[0], chi_ray[2] = 1.0, 0.1
    chi_aer = moments(cornette_shanks(mu, opt["mie_g"]), w, ptab)
    cloud_chi, cloud_info = [], []
    for wl in WAVELENGTHS_NM:
        ph, g, qext, qsca = cloud_phase(wl, mu, w)
        chi = moments(ph, w, ptab)
        cloud_chi.append(chi)
        cloud_info.append({"wavelength_nm": float(wl), "g": g, "Q_ext": qext, "Q_sca": qsca,
                           "chi_64": float(chi[64]), "chi_1000": float(chi[NMOM])})  # fmt: skip
    t_mie = time.time() - t0
    in_cloud = (LEVELS_M[:-1] >= CLOUD_BASE_M) & (LEVELS_M[1:] <= CLOUD_TOP_M)
    n_cloud = int(in_cloud.sum())
    # DISORT's layer 0 is the top: reverse the bottom-up layers.
    top_down = slice(None, None, -1)

    def column(wi: int, tau_c: float):
        tr = opt["rayleigh"][wi][top_down]
        tae = opt["aerosol_ext"][wi][top_down]
        tas = opt["aerosol_sca"][wi][top_down]
        toz = opt["ozone"][wi][top_down]
        tc = np.where(in_cloud[top_down], tau_c / n_cloud, 0.0)
        ext = tr + tae + toz + tc
        sca = tr + tas + tc
        pm = np.outer(tr, chi_ray) + np.outer(tas, chi_aer) + np.outer(tc, cloud_chi[wi])
        pm = np.clip(pm / sca[:, None], -1.0, 1.0)
        pm[:, 0] = 1.0  # exactly: DISORT rejects moments outside [-1, 1], and 1 + 1e-16
        return ext, np.minimum(sca / ext, 1.0), pm

    umu = -np.sin(np.radians(VIEW_ELEVATIONS_DEG[::-1]))  # increasing: zenith first
    phi = np.array(VIEW_AZIMUTHS_DEG)
    cases = [(tc, el, a) for tc in (0.0, *CLOUD_TAUS) for el in SUN_ELEVATIONS_DEG for a in ALBEDOS]
    cases.append((37.5, 45.0, 0.3))
    level_top_down = LEVELS_M[::-1]
    names = {"top": 100000.0, "cloud_top": CLOUD_TOP_M, "cloud_base": CLOUD_BASE_M, "ground": 0.0}
    tasks = []
    for tc, el, a in cases:
        for wi in range(nw):
            ext, ssa, pm = column(wi, tc)
            cum = np.concatenate([[0.0], np.cumsum(ext)])
            utau = [cum[int(np.nonzero(level_top_down == h)[0][0])] for h in names.values()]
            tasks.append((lib_path, ext, ssa, pm, math.sin(math.radians(el)), a, utau, umu, phi))
    with multiprocessing.Pool(args.workers) as pool:
        results = pool.map(_task, tasks, chunksize=1)
    t_rt = time.time() - t0 - t_mie

    # Luminous weights: V(λ) E_sun(λ) Δλ, trapezoid.
    dl = np.full(nw, 20.0)
    dl[0] = dl[-1] = 10.0
    wts = photopic_efficiency(WAVELENGTHS_NM) * solar_irradiance(WAVELENGTHS_NM) * dl
    wn = wts / wts.sum()
    out_cases = []
    for ci, (tc, el, a) in enumerate(cases):
        flux = np.array([results[ci * nw + wi][0] for wi in range(nw)])  # (W, 4 levels, 3)
        uu = np.array([results[ci * nw + wi][1] for wi in range(nw)])  # (W, phi, 4, umu)
        rad = uu[:, :, 3, ::-1]  # ground, (W, azimuth, elevation ascending)
        rad = np.transpose(rad, (0, 2, 1))  # (W, elevation, azimuth)
        direct, diffuse = flux[:, 3, 0], flux[:, 3, 1]
        spectral = {
            "radiance_per_sr": sig(rad),
            "direct_horizontal": sig(direct),
            "diffuse_horizontal": sig(diffuse),
            "global_horizontal": sig(direct + diffuse),
            "cloud_top_upward": sig(flux[:, 1, 2]),
            "cloud_top_downward": sig(flux[:, 1, 0] + flux[:, 1, 1]),
            "cloud_base_downward": sig(flux[:, 2, 0] + flux[:, 2, 1]),
            "toa_upward": sig(flux[:, 0, 2]),
            "ground_upward": sig(flux[:, 3, 2]),
        }
        lum = np.einsum("w,wea->ea", wn, rad)
        out_cases.append({
            "cloud_optical_depth": tc,
            "sun_elevation_deg": el,
            "ground_albedo": a,
            "L_over_E0_per_sr": sig(lum),
            "zenith_L_over_E0_per_sr": sig(lum[-1, 0]),
            "E_global_horizontal_over_E0": sig(wn @ (direct + diffuse)),
            "E_direct_horizontal_over_E0": sig(wn @ direct),
            "E_diffuse_horizontal_over_E0": sig(wn @ diffuse),
            "E_cloud_top_upward_over_E0": sig(wn @ flux[:, 1, 2]),
            "E_cloud_top_downward_over_E0": sig(wn @ (flux[:, 1, 0] + flux[:, 1, 1])),
            "E_cloud_base_downward_over_E0": sig(wn @ (flux[:, 2, 0] + flux[:, 2, 1])),
            "E_toa_upward_over_E0": sig(wn @ flux[:, 0, 2]),
            "E_transmitted_to_ground_over_E0": sig(wn @ (direct + diffuse)),
            "spectral": spectral,
        })  # fmt: skip

    p = opt["params"]
    tau_tot = {k: opt[k].sum(axis=1) for k in ("rayleigh", "aerosol_ext", "aerosol_sca", "ozone")}
    doc = {
        "description": (
            "DISORT (cdisort 2.1.3, 64 streams) radiances and fluxes at the ground under a "
            "uniform plane-parallel cloud deck from 1000 to 2000 m in skydome's 'earth' "
            "atmosphere, per unit solar irradiance normal to the beam at the top. Generated by "
            "tools/make_disort_cloud_reference.py; see its docstring."
        ),
        "units_and_layout": {
            "L_over_E0_per_sr": "luminance / E_v0, sr^-1, [view elevation][relative azimuth]",
            "E_*_over_E0": "horizontal illuminance (or luminous flux density) / E_v0, "
            "dimensionless; E_v0 = 683 lm/W * integral V E_sun, normal to the beam",
            "relative_azimuth": "0 = towards the Sun (forward scattering), 180 = away from it",
            "spectral": "the same per wavelength (per unit spectral irradiance normal to the "
            "beam): radiance_per_sr [wavelength][view elevation][relative azimuth], fluxes "
            "[wavelength]; downward fluxes are direct + diffuse",
            "diffuse radiance": "DISORT's diffuse intensity: the direct Sun is excluded; the "
            "entries whose view direction is the Sun's (elevation = sun elevation, azimuth "
            "0) are the diffuse radiance in the Sun's direction, dominated by the forward "
            "peak: do not test against them",
            "E_transmitted_to_ground_over_E0": "= E_global_horizontal_over_E0",
        },
        "view_elevations_deg": list(VIEW_ELEVATIONS_DEG),
        "relative_azimuths_deg": list(VIEW_AZIMUTHS_DEG),
        "wavelengths_nm": WAVELENGTHS_NM.tolist(),
        "luminous_weights": sig(wn),
        "cases": out_cases,
        "provenance": {
            "date": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
            "command": "PYTHONPATH=src /tmp/disort-venv/bin/python "
            "tools/make_disort_cloud_reference.py " + " ".join(argv or sys.argv[1:]),
            "versions": {
                "pydisort": metadata.version("pydisort"),
                "torch": metadata.version("torch"),
                "miepython": metadata.version("miepython"),
                "numpy": np.__version__,
                "python": platform.python_version(),
                "gcc": subprocess.run(
                    ["gcc", "-dumpfullversion"], capture_output=True, text=True
                ).stdout.strip(),  # fmt: skip
            },
            "disort": {
                "code": "cdisort 2.1.3 C source shipped in the pydisort wheel "
                "(pydisort/cdisort213/cdisort.c, locate.c), compiled with gcc -O2 with a "
                "ctypes driver; pydisort's torch wrapper is unusable with the torch 2.13 CPU "
                "wheel (built against another libtorch)",
                "streams": NSTR,
                "phase_moments": NMOM,
                "delta_m": True,
                "intensity_correction": "Nakajima-Tanaka, moment-based (old_intensity_correction)",
                "accur": 0.0,
                "geometry": "plane-parallel, no pseudo-spherical correction",
                "ground": "Lambertian",
                "beam": "fbeam = 1 (irradiance normal to the beam), phi0 = 0",
                "normalisation_check": norm,
            },
            "atmosphere": {
                "preset": "earth",
                "digest": p.digest(),
                "layer_boundaries_m": LEVELS_M.tolist(),
                "layer_integration": "density profiles integrated by the trapezoid rule, "
                "401 points per layer",
                "rayleigh": "skydome rayleigh_scattering (Bodhaine, US 1976 sea level) x "
                "rayleigh_density; phase 3(1+mu^2)/(16 pi): chi_2 = 0.1",
                "aerosol": "OPAC clean continental, AOD 0.1 at 550 nm, skydome "
                "mie_extinction/mie_scattering x mie_density; Cornette-Shanks phase, "
                f"g_CS = {opt['mie_g']:.6f} (mean cosine {float(chi_aer[1]):.4f}), same "
                "at every wavelength (as skydome's 'earth')",
                "ozone": "300 DU, skydome absorption_extinction x absorption_density (AFGL)",
                "column_optical_depths": {k: sig(v, 5) for k, v in tau_tot.items()},
                "ground_albedo": "replaced by the case's spectrally flat albedo ('earth' has 0.3)",
            },
            "cloud": {
                "base_m": CLOUD_BASE_M,
                "top_m": CLOUD_TOP_M,
                "layers": n_cloud,
                "optical_depth": "the case's tau_c, the same at every wavelength, split "
                "equally over its layers",
                "single_scattering_albedo": 1.0,
                "refractive_index": f"{WATER_INDEX} + 0i at every wavelength",
                "size_distribution": "gamma, r_eff 10 um, v_eff 0.1: n(r) ~ r^7 exp(-r/1um), "
                f"{N_RADII} radii uniform over {R_RANGE_UM[0]}-{R_RANGE_UM[1]} um",
                "phase_function": "Mie (miepython an_bn; S1, S2 summed here) size-averaged "
                "at each wavelength, Legendre moments by "
                f"{N_QUAD}-node Gauss-Legendre projection, {NMOM} moments",
                "mixing": "omega = sum tau_sca / sum tau_ext; chi_l = sum tau_sca,i chi_l,i "
                "/ sum tau_sca,i (air, aerosol, cloud)",
                "mie_per_wavelength": [{k: sig(v, 5) for k, v in c.items()} for c in cloud_info],
            },
            "luminous_weighting": "w = V(lambda) E_sun(lambda) d lambda (trapezoid, 20 nm), "
            "skydome.spectra photopic_efficiency (CIE 1924) and solar_irradiance (ASTM G-173 "
            "10 nm bin means at bin centres)",
            "run_time_s": {
                "mie": round(t_mie, 1),
                "disort": round(t_rt, 1),
                "total": round(time.time() - t0, 1),
            },  # fmt: skip
            "workers": args.workers,
            "machine": platform.machine() + " " + platform.platform(),
        },
    }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(doc, indent=1) + "\n")
    print(f"wrote {args.out} ({args.out.stat().st_size / 1024:.0f} KiB) in "
          f"{time.time() - t0:.0f} s")  # fmt: skip
    for c in out_cases:
        print(c["cloud_optical_depth"], c["sun_elevation_deg"], c["ground_albedo"],
              c["zenith_L_over_E0_per_sr"], c["E_global_horizontal_over_E0"],
              c["E_diffuse_horizontal_over_E0"], c["E_cloud_top_upward_over_E0"])  # fmt: skip


if __name__ == "__main__":
    main()
