"""Build the Moon's series: skydome/data/moon_elpmpp02.npz (what skydome.astro.moon sums).

Usage::

    python tools/build_moon_elpmpp02.py SOURCE [--output PATH] [--threshold-arcsec X]
        [--threshold-km Y]     # about 30 s

``SOURCE`` is a folder holding the 14 ELP/MPP02 data files (``elp_main.long``, ``.lat``,
``.dist``, ``elp_pert.longT0..T3``, ``latT0..T2``, ``distT0..T3``) or the git directory of
a clone of https://github.com/ytliu0/ElpMpp02 (the files are then read with
``git --git-dir=SOURCE show HEAD:NAME``).

Theory and data
---------------
ELP/MPP02: J. Chapront & G. Francou, "The lunar theory ELP revisited. Introduction of new
planetary perturbations", A&A 404, 735-742 (2003); the series and the fitted constants
are IMCCE's public distribution of the theory (ftp://cyrano-se.obspm.fr/pub/
2_lunar_solutions/2_elpmpp02/: ELP_MAIN.S1-S3, ELP_PERT.S1-S3 and the Fortran
ELPMPP02.for with its documentation elpmpp02.pdf). The 14 files read here are Y. T. Liu's
conversion of those files (https://github.com/ytliu0/ElpMpp02: same terms, amplitudes of
longitude and latitude in radians, the perturbations' multipliers reordered to D, F, l,
l', Me, Ve, EM, Ma, Ju, Sa, Ur, Ne, zeta; documented in its docs/ElpMpp02.tex, which
also gives the DE405 test positions checked below). Only numbers are taken from there
(the theory's coefficients, as IMCCE publishes them; Liu's code, GPL-3.0, is not used):
this script is written from the formulation (Chapront & Francou 2003 and the tex).

What is built
-------------
1. The constants fitted to DE405/DE406 (the tex's table: Delta W1..W3, Gamma, E, T, pi',
   e' and the six long-range terms fitted to DE406) give the arguments' polynomials
   (``arg_poly``: D, F, l, l', the planets' mean longitudes Me..Ne, zeta; ``w1_poly``: the
   Moon's mean longitude W1 from the fixed departure point of J2000) and the corrections
   of the main problem's amplitudes, A + sum_j f_Bj B_j (longitude, latitude) and
   f_A A + sum_j f_Bj B_j (distance), with the distance scaled by
   a0(DE405)/a0(ELP) = 384747.961370173/384747.980674318.
2. Every term becomes A T^n sin(phi0 + i . args) (the main problem's distance terms, cosines,
   get phi0 = pi/2), T in Julian centuries TDB from J2000.0.
3. Truncation: a term of power n is kept when |A| T_MAX^n >= the coordinate's threshold
   (THRESHOLDS below; T_MAX = TRUNCATION_CENTURIES). The script prints the sum of the
   dropped amplitudes (the worst case, every dropped term in phase) and the measured
   largest and RMS difference from the complete series over 1900-2100 and 1500-2500.

V (longitude from the departure point gamma'2000 on the mean ecliptic of date, rad), U
(latitude, rad) and r (km) follow as V = W1 + sum, U = sum, r = sum; skydome.astro.moon adds
the precession in longitude p_A to V (see its docstring).

Arrays: ``terms`` (T, 17): coordinate (0 V, 1 U, 2 r), power n of T, amplitude A (rad or km),
phase phi0 (rad) and the 13 integer multipliers; ``args`` (14, 5): the polynomials (rad per
T^k, k = 0..4) of D, F, l, l', Me, Ve, EM, Ma, Ju, Sa, Ur, Ne, zeta and (last row) W1; and
``meta_json`` (format version, thresholds, measured truncation errors, provenance).
"""

from __future__ import annotations

import argparse
import subprocess
from pathlib import Path

import numpy as np

from skydome.io.packaged import write_packaged_npz

OUTPUT = Path(__file__).resolve().parents[1] / "src" / "skydome" / "data" / "moon_elpmpp02.npz"
FORMAT_VERSION = 1  # skydome.astro.moon.ELP_FORMAT

SEC = np.pi / 648000.0  # radians per arcsecond
DEG = np.pi / 180.0

MAIN_FILES = ("elp_main.long", "elp_main.lat", "elp_main.dist")
PERT_FILES = {
    0: ("elp_pert.longT0", "elp_pert.longT1", "elp_pert.longT2", "elp_pert.longT3"),
    1: ("elp_pert.latT0", "elp_pert.latT1", "elp_pert.latT2"),
    2: ("elp_pert.distT0", "elp_pert.distT1", "elp_pert.distT2", "elp_pert.distT3"),
}

# The constants fitted to DE405/DE406 (Chapront & Francou 2003; the tex's table, column
# DE405/DE406), arcsec and arcsec per century^k.
FIT = dict(
    dw1_0=-0.07008, dw2_0=0.20794, dw3_0=-0.07215,
    dw1_1=-0.35106, dw2_1=0.08017, dw3_1=-0.04317,
    dw1_2=-0.03743, dgam=0.00085, de=-0.00006,
    deart_0=-0.00033, deart_1=0.00732, dperi=-0.00749, dep=0.00224,
    dw1_3=-0.00018865, dw1_4=-0.00001024, dw2_2=0.00470602, dw2_3=-0.00025213,
    dw3_2=-0.00261070, dw3_3=-0.00010712,
)  # fmt: skip
# B'_{2,j}, B'_{3,j}, j = 1..5 (partial derivatives of the node's and perigee's mean motions)
BP2 = (0.311079095, -0.004482398, -0.001102485, 0.001056062, 0.000050928)
BP3 = (-0.103837907, 0.000668287, -0.001298072, -0.000178028, -0.000037342)
M_RATIO = 0.074801329  # m = n'/nu
ALPHA = 0.002571881  # a0/a'
DIST_SCALE = 384747.961370173 / 384747.980674318  # a0(DE405)/a0(ELP)

# Truncation (see the module docstring): thresholds of |A| T_MAX^n per coordinate.
TRUNCATION_CENTURIES = 10.0  # 1000-3000 at full weight (the Delta T model: -1999..3000)
THRESHOLDS = {0: 0.003 * SEC, 1: 0.003 * SEC, 2: 0.01}  # V, U in rad (3 mas); r in km
NAMES = ("V", "U", "r")


# --------------------------------------------------------------------------- reading


def read_text(source: Path, name: str) -> str:
    """The text of data file ``name`` from a folder or from a git directory's HEAD."""
    if (source / name).is_file():
        return (source / name).read_text()
    out = subprocess.run(
        ["git", f"--git-dir={source}", "show", f"HEAD:{name}"],
        check=True,
        capture_output=True,
        text=True,
    )
    return out.stdout


def read_table(source: Path, name: str, columns: int) -> np.ndarray:
    """The rows of a data file (the first line holds their count); shape (n, columns)."""
    lines = read_text(source, name).split("\n")
    n = int(lines[0])
    rows = np.array([ln.split() for ln in lines[1 : n + 1]], dtype=float).reshape(n, columns)
    return rows


# --------------------------------------------------------------------------- the fit


def fit_factors() -> dict[str, float]:
    """The corrections of the main problem's amplitudes (f_A, f_B1..f_B5) and of the node's
    and perigee's mean motions (dW2, dW3 in arcsec/cy) from the DE405 fit (the tex,
    section 'Parameters adjusted to fit LLR or DE405/DE406')."""
    f = FIT
    w11 = (1732559343.73604 + f["dw1_1"]) * SEC  # rad/cy
    w21 = (14643420.3171 + f["dw2_1"]) * SEC
    w31 = (-6967919.5383 + f["dw3_1"]) * SEC
    xa = 2.0 * ALPHA / 3.0
    out = {}
    for name, w, bp in (("dw2", w21, BP2), ("dw3", w31, BP3)):
        y = M_RATIO * bp[0] + xa * bp[4]
        out[name] = (
            (w / w11 - y) * f["dw1_1"]
            + (y / M_RATIO) * f["deart_1"]
            + w11 * (bp[1] * f["dgam"] + bp[2] * f["de"] + bp[3] * f["dep"])
        )
    delnu = (0.55604 + f["dw1_1"]) * SEC / w11  # delta nu / nu
    delnp = (-0.06424 + f["deart_1"]) * SEC / w11  # delta n' / nu (ELPMPP02.for's value)
    out["fA"] = 1.0 - 2.0 / 3.0 * delnu
    out["fB"] = np.array(
        [
            delnp - M_RATIO * delnu,
            (-0.08066 + f["dgam"]) * SEC,
            (0.01789 + f["de"]) * SEC,
            (-0.12879 + f["dep"]) * SEC,
            2.0 * ALPHA / (3.0 * M_RATIO) * (delnp - M_RATIO * delnu),
        ]
    )
    return out


def dms(d: float, m: float, s: float) -> float:
    """Degrees, minutes, seconds (signs on the degrees) in arcsec."""
    return np.copysign(abs(d) * 3600.0 + m * 60.0 + s, d if d != 0 else 1.0)


def argument_polynomials() -> tuple[np.ndarray, np.ndarray]:
    """Polynomials in T (rad per T^k, k = 0..4) of the 13 arguments D, F, l, l', Me, Ve, EM,
    Ma, Ju, Sa, Ur, Ne, zeta and of W1 (the tex, 'Lunar and planetary arguments')."""
    f, c = FIT, fit_factors()
    w1 = np.array(
        [
            dms(218, 18, 59.95571) + f["dw1_0"],
            1732559343.73604 + f["dw1_1"],
            -6.8084 + f["dw1_2"],
            0.006604 + f["dw1_3"],
            -0.00003169 + f["dw1_4"],
        ]
    )
    w2 = np.array(
        [
            dms(83, 21, 11.67475) + f["dw2_0"],
            14643420.3171 + f["dw2_1"] + c["dw2"],
            -38.2631 + f["dw2_2"],
            -0.045047 + f["dw2_3"],
            0.00021301,
        ]
    )
    w3 = np.array(
        [
            dms(125, 2, 40.39816) + f["dw3_0"],
            -6967919.5383 + f["dw3_1"] + c["dw3"],
            6.359 + f["dw3_2"],
            0.007625 + f["dw3_3"],
            -0.00003586,
        ]
    )
    ea = np.array(
        [dms(100, 27, 59.13885) + f["deart_0"], 129597742.293 + f["deart_1"], -0.0202, 9e-6, 1.5e-7]
    )
    peri = np.array(
        [dms(102, 56, 14.45766) + f["dperi"], 1161.24342, 0.529265, -1.1814e-4, 1.1379e-5]
    )
    planets = [
        (dms(252, 15, 3.216919), 538101628.66888),  # Me
        (dms(181, 58, 44.758419), 210664136.45777),  # Ve
        (dms(100, 27, 59.13885), 129597742.293),  # EM
        (dms(355, 26, 3.642778), 68905077.65936),  # Ma
        (dms(34, 21, 5.379392), 10925660.57335),  # Ju
        (dms(50, 4, 38.902495), 4399609.33632),  # Sa
        (dms(314, 3, 4.354234), 1542482.57845),  # Ur
        (dms(304, 20, 56.808371), 786547.897),  # Ne
    ]
    rows = [
        w1 - ea + np.array([180 * 3600.0, 0, 0, 0, 0]),  # D
        w1 - w3,  # F
        w1 - w2,  # l
        ea - peri,  # l'
    ]
    rows += [np.array([p0, p1, 0.0, 0.0, 0.0]) for p0, p1 in planets]
    rows.append(w1 + np.array([0.0, 5028.79695, 0.0, 0.0, 0.0]))  # zeta
    return np.array(rows) * SEC, w1 * SEC


def all_terms(source: Path) -> dict[str, np.ndarray]:
    """Every term of ELP/MPP02 with the DE405 fit: coord, power, mult (13), amp, phase."""
    fac = fit_factors()
    coord, power, mult, amp, phase = [], [], [], [], []
    for c, name in enumerate(MAIN_FILES):
        t = read_table(source, name, 11)
        a = (fac["fA"] if c == 2 else 1.0) * t[:, 4] + t[:, 5:10] @ fac["fB"]
        m = np.zeros((t.shape[0], 13))
        m[:, :4] = t[:, :4]
        coord.append(np.full(t.shape[0], c))
        power.append(np.zeros(t.shape[0]))
        mult.append(m)
        amp.append(a * (DIST_SCALE if c == 2 else 1.0))
        phase.append(np.full(t.shape[0], np.pi / 2 if c == 2 else 0.0))
    for c, names in PERT_FILES.items():
        for n, name in enumerate(names):
            t = read_table(source, name, 15)
            coord.append(np.full(t.shape[0], c))
            power.append(np.full(t.shape[0], n))
            mult.append(t[:, :13])
            amp.append(t[:, 13] * (DIST_SCALE if c == 2 else 1.0))
            phase.append(t[:, 14])
    out = {
        "coord": np.concatenate(coord).astype(np.int8),
        "power": np.concatenate(power).astype(np.int8),
        "mult": np.rint(np.concatenate(mult)).astype(np.int8),
        "amp": np.concatenate(amp),
        "phase": np.concatenate(phase),
    }
    # a negative amplitude becomes a phase shift of pi (|A| for the truncation)
    neg = out["amp"] < 0
    out["amp"] = np.abs(out["amp"])
    out["phase"] = np.mod(out["phase"] + np.pi * neg + np.pi, 2 * np.pi) - np.pi
    return out


def evaluate(terms: dict[str, np.ndarray], jd_tdb: np.ndarray) -> np.ndarray:
    """(V, U, r) of the series ``terms`` at ``jd_tdb`` (N,), term by term; shape (3, N).
    V in rad from the departure point gamma'2000 on the mean ecliptic of date."""
    arg_poly, w1_poly = argument_polynomials()
    t = (np.asarray(jd_tdb, dtype=float) - 2451545.0) / 36525.0
    tp = t[None, :] ** np.arange(5)[:, None]  # (5, N)
    args = arg_poly @ tp  # (13, N)
    out = np.zeros((3, t.size))
    out[0] = w1_poly @ tp
    for start in range(0, terms["amp"].size, 2000):
        s = slice(start, start + 2000)
        phi = terms["phase"][s, None] + terms["mult"][s].astype(float) @ args
        val = terms["amp"][s, None] * t[None, :] ** terms["power"][s, None] * np.sin(phi)
        np.add.at(out, terms["coord"][s], val)
    return out


def laskar_pq_matrix(t: float) -> np.ndarray:
    """Mean ecliptic of date (from the departure point) to the mean ecliptic and equinox of
    J2000 (Laskar 1986, the P and Q of the tex)."""
    p = t * (0.10180391e-4 + t * (0.47020439e-6 + t * (-0.5417367e-9 + t * (-0.2507948e-11 + t * 0.463486e-14))))  # fmt: skip
    q = t * (-0.113469002e-3 + t * (0.12372674e-6 + t * (0.1265417e-8 + t * (-0.1371808e-11 + t * -0.320334e-14))))  # fmt: skip
    s = np.sqrt(1 - p * p - q * q)
    return np.array(
        [
            [1 - 2 * p * p, 2 * p * q, 2 * p * s],
            [2 * p * q, 1 - 2 * q * q, -2 * q * s],
            [-2 * p * s, 2 * q * s, 1 - 2 * p * p - 2 * q * q],
        ]
    )


def to_j2000(vur: np.ndarray, jd_tdb: np.ndarray) -> np.ndarray:
    """Rectangular coordinates (km), mean ecliptic and equinox of J2000; shape (N, 3)."""
    v, u, r = vur
    xyz = np.stack([r * np.cos(v) * np.cos(u), r * np.sin(v) * np.cos(u), r * np.sin(u)], 1)
    t = (np.asarray(jd_tdb, dtype=float) - 2451545.0) / 36525.0
    return np.array([laskar_pq_matrix(tk) @ x for tk, x in zip(t, xyz, strict=True)])


# The tex's test positions for the DE405 fit (TDB JD; X, Y, Z km, ecliptic J2000)
DE405_TESTS = {
    2521835.67: (-184108.21468, 345893.25529, 30395.06868),
    2265621.33: (-298024.37832, -213909.67132, -23263.21426),
    2009406.99: (350041.24745, -201093.28987, 1643.33539),
    1753192.65: (90272.39894, 351997.39617, 13417.01712),
    1496978.31: (-403018.01560, -2639.93889, -28463.89733),
}


def truncate(terms: dict[str, np.ndarray]) -> np.ndarray:
    """Mask of the terms kept (|A| T_MAX^n >= the coordinate's threshold)."""
    thr = np.array([THRESHOLDS[c] for c in range(3)])[terms["coord"]]
    return terms["amp"] * TRUNCATION_CENTURIES ** terms["power"].astype(float) >= thr


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("source", type=Path, help="folder of the 14 files, or a git directory")
    ap.add_argument("--output", type=Path, default=OUTPUT)
    ap.add_argument("--threshold-arcsec", type=float, default=THRESHOLDS[0] / SEC)
    ap.add_argument("--threshold-km", type=float, default=THRESHOLDS[2])
    args = ap.parse_args()
    THRESHOLDS.update({0: args.threshold_arcsec * SEC, 1: args.threshold_arcsec * SEC})
    THRESHOLDS[2] = args.threshold_km

    terms = all_terms(args.source)
    jd = np.array(list(DE405_TESTS))
    xyz = to_j2000(evaluate(terms, jd), jd)
    err = np.abs(xyz - np.array(list(DE405_TESTS.values()))).max()
    print(f"complete series ({terms['amp'].size} terms) vs the tex's DE405 tests: {err:.2e} km")
    # float64 arguments of 1e5-1e6 rad (T = -26) carry 1e-10 rad: 0.6 m at -614, 0.03 m at
    # 2192 (extended precision reproduces all five to the printed 1e-5 km)
    assert err < 1e-3, "the complete series does not reproduce the published test positions"

    keep = truncate(terms)
    kept = {k: v[keep] for k, v in terms.items()}
    bounds = {}
    rng = np.random.default_rng(1)
    for label, (y0, y1) in {"1900-2100": (1900, 2100), "1500-2500": (1500, 2500)}.items():
        jd = 2451545.0 + (rng.uniform(y0, y1, 3000) - 2000.0) * 365.25
        diff = evaluate(kept, jd) - evaluate(terms, jd)
        tmax = max(abs(y0 - 2000), abs(y1 - 2000)) / 100.0
        dropped = [
            float(
                np.sum(
                    (terms["amp"] * tmax ** terms["power"].astype(float))[
                        ~keep & (terms["coord"] == c)
                    ]
                )
            )  # fmt: skip
            for c in range(3)
        ]
        scale = [1 / SEC, 1 / SEC, 1.0]
        unit = ['"', '"', " km"]
        for c in range(3):
            mx = np.abs(diff[c]).max() * scale[c]
            rms = np.sqrt(np.mean(diff[c] ** 2)) * scale[c]
            print(
                f"{label} {NAMES[c]}: measured max {mx:.4f}{unit[c]}, RMS {rms:.4f}{unit[c]}, "
                f"bound (sum of dropped |A|) {dropped[c] * scale[c]:.3f}{unit[c]}"
            )
            bounds[f"{label} {NAMES[c]}"] = {
                "max": round(mx, 5),
                "rms": round(rms, 5),
                "bound": round(dropped[c] * scale[c], 4),
            }
    counts = {NAMES[c]: int(np.sum(kept["coord"] == c)) for c in range(3)}
    print(f"kept {keep.sum()} of {keep.size} terms: {counts}")

    arg_poly, w1_poly = argument_polynomials()
    meta = {
        "format_version": FORMAT_VERSION,
        "about": "ELP/MPP02 (Chapront & Francou 2003, A&A 404, 735) with the constants fitted "
        "to DE405/DE406, from IMCCE's distribution of the theory (ftp://cyrano-se.obspm.fr/"
        "pub/2_lunar_solutions/2_elpmpp02/) as converted by Y. T. Liu "
        "(github.com/ytliu0/ElpMpp02); terms A T^n sin(phase + mult . args), T in Julian "
        "centuries TDB from J2000; args D, F, l, l', Me, Ve, EM, Ma, Ju, Sa, Ur, Ne, zeta "
        "(arg_poly, rad per T^k); V = W1 (w1_poly) + sum (rad, from the departure point on "
        "the mean ecliptic of date), U = sum (rad), r = sum (km). Built by "
        "tools/build_moon_elpmpp02.py.",
        "truncation": {
            "rule": "|A| T_max^n >= threshold",
            "t_max_centuries": TRUNCATION_CENTURIES,
            "threshold_arcsec_V_U": THRESHOLDS[0] / SEC,
            "threshold_km_r": THRESHOLDS[2],
            "terms": counts,
            "error_vs_complete_series": bounds,
        },
    }
    order = np.lexsort((kept["power"], kept["coord"]))
    table = np.column_stack(
        [kept["coord"], kept["power"], kept["amp"], kept["phase"], kept["mult"]]
    )[order]
    write_packaged_npz(args.output, meta, terms=table, args=np.vstack([arg_poly, w1_poly]))
    print(f"wrote {args.output} ({args.output.stat().st_size} bytes)")


if __name__ == "__main__":
    main()
