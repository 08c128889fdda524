"""Build ``src/skydome/data/ut1_utc.npz``: UT1 - UTC and TAI - UTC, daily, 1962 to the end
of the IERS predictions.

Sources (the files bundled in the PyPI package ``astropy-iers-data``, IERS data are free
to use):

* ``eopc04.1962-now``: IERS EOP 20 C04 series, UT1 - UTC at 0h UTC every day since
  1962-01-01 (IERS Earth Orientation Centre, Paris Observatory);
* ``finals2000A.all``: IERS Rapid Service / Prediction Centre (USNO) Bulletin A values,
  used after the last C04 day, including their one-year prediction;
* ``Leap_Second.dat``: the leap-second table (TAI - UTC steps since 1972).

TAI - UTC before 1972 (the "rubber second" era, piecewise linear offsets) is sampled daily
with ``erfa.dat`` (pyerfa, installed with astropy).

The package reads only the written file at run time. Arrays written:

* ``mjd0``: MJD (UTC) of the first row; rows are consecutive days;
* ``ut1_tai_us``: UT1 - TAI in microseconds (int64; continuous across leap seconds, so it
  can be interpolated linearly);
* ``tai_utc_pre1972_us``: TAI - UTC at 0h UTC in microseconds for the rows before 1972;
* ``leap_mjd``, ``leap_tai_utc``: the leap-second table (MJD of the step, new TAI - UTC s);
* ``last_observed_mjd``: last day that is not a prediction.

Usage: python tools/build_iers_table.py
"""

from __future__ import annotations

from pathlib import Path

import erfa
import numpy as np
from astropy_iers_data import IERS_A_FILE, IERS_B_FILE, IERS_LEAP_SECOND_FILE

OUT = Path(__file__).resolve().parents[1] / "src" / "skydome" / "data" / "ut1_utc.npz"
MJD_1972 = 41317


def read_c04(path: str) -> tuple[np.ndarray, np.ndarray]:
    mjd, dut = [], []
    with open(path) as fh:
        for line in fh:
            if line.startswith("#") or not line.strip():
                continue
            f = line.split()
            mjd.append(float(f[4]))
            dut.append(float(f[7]))
    return np.array(mjd), np.array(dut)


def read_finals(path: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """MJD, UT1-UTC (Bulletin A, columns 59-68) and predicted flag of finals2000A.all."""
    mjd, dut, pred = [], [], []
    with open(path) as fh:
        for line in fh:
            if len(line) < 68 or not line[58:68].strip():
                continue
            mjd.append(float(line[7:15]))
            dut.append(float(line[58:68]))
            pred.append(line[57] == "P")
    return np.array(mjd), np.array(dut), np.array(pred)


def read_leaps(path: str) -> tuple[np.ndarray, np.ndarray]:
    mjd, off = [], []
    with open(path) as fh:
        for line in fh:
            if line.startswith("#") or not line.strip():
                continue
            f = line.split()
            mjd.append(float(f[0]))
            off.append(float(f[4]))
    return np.array(mjd), np.array(off)


def tai_minus_utc(mjd: np.ndarray, leap_mjd: np.ndarray, leap_off: np.ndarray) -> np.ndarray:
    out = np.empty(mjd.size)
    for i, m in enumerate(mjd):
        if m >= MJD_1972:
            out[i] = leap_off[np.searchsorted(leap_mjd, m, side="right") - 1]
        else:
            y, mo, d, fd = erfa.jd2cal(2400000.5, m)
            out[i] = erfa.dat(y, mo, d, fd)
    return out


def main() -> None:
    c04_mjd, c04_dut = read_c04(IERS_B_FILE)
    fin_mjd, fin_dut, fin_pred = read_finals(IERS_A_FILE)
    leap_mjd, leap_off = read_leaps(IERS_LEAP_SECOND_FILE)

    after = fin_mjd > c04_mjd[-1]
    mjd = np.concatenate([c04_mjd, fin_mjd[after]])
    dut = np.concatenate([c04_dut, fin_dut[after]])
    assert np.all(np.diff(mjd) == 1.0), "rows must be consecutive days"
    last_observed = fin_mjd[~fin_pred].max()

    tai_utc = tai_minus_utc(mjd, leap_mjd, leap_off)
    ut1_tai = dut - tai_utc
    pre = mjd < MJD_1972
    np.savez_compressed(
        OUT,
        mjd0=np.int64(mjd[0]),
        ut1_tai_us=np.round(ut1_tai * 1e6).astype(np.int64),
        tai_utc_pre1972_us=np.round(tai_utc[pre] * 1e6).astype(np.int64),
        leap_mjd=leap_mjd.astype(np.int64),
        leap_tai_utc=leap_off,
        last_observed_mjd=np.int64(last_observed),
    )
    print(
        f"wrote {OUT}: MJD {mjd[0]:.0f}-{mjd[-1]:.0f} ({mjd.size} days, observed to "
        f"{last_observed:.0f}), {OUT.stat().st_size / 1024:.0f} KiB"
    )


if __name__ == "__main__":
    main()
