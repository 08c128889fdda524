"""Measure ``skydome.clouds.params.WATER_NORMALIZATION``: the factor per cloud type and map
coverage that makes the clouds' water what their parameters ask for.

For each cloud type and each coverage of WATER_COVERAGE_NODES, a sky with a uniform weather
map of that coverage is drawn through ``Sky`` (the user's path) with the normalisation set to
1, and ``CloudLayer.column_optical_depths`` integrates the extinction of 128 x 128 vertical
columns over the weather tile (160 samples each) for seeds 1-3. With the nominal optical
depth tau_n = extinction_per_m(LWC) x thickness:

- at coverage 1 the factor makes the mean of all columns tau_n;
- at a lower coverage c it makes the mean of the cloudy columns (above 1 % of tau_n) what
  it is at coverage 1: the coverage sets the cloudy fraction, not the water per cloud.

Prints the table to paste into params.py (about a minute on a CPU rasterizer)::

    python tools/calibrate_cloud_water.py
"""

from __future__ import annotations

import numpy as np

from skydome import Clouds, Sky
from skydome.clouds import params

SEEDS = (1, 2, 3)
GRID = 128
THICKNESS_M = {"stratus": 1000.0, "stratocumulus": 1000.0, "cumulus": 1500.0,
               "cumulonimbus": 6000.0}  # fmt: skip
CLOUDY = 0.01  # a cloudy column holds more than this fraction of the nominal optical depth


def raw_columns(cloud_type: str, coverage: float, seed: int) -> np.ndarray:
    """Column optical depths over tau_n, with the normalisation at 1."""
    clouds = Clouds(
        cloud_type=cloud_type, coverage=1.0, cirrus=0.0, base_m=1000.0,
        thickness_m=THICKNESS_M[cloud_type], seed=seed,
        weather=np.full((32, 32), coverage),
    )  # fmt: skip
    nominal = params.extinction_per_m(params.LIQUID_WATER_G_M3[cloud_type]) * clouds.thickness_m
    with Sky(sun_elevation_deg=45.0, clouds=clouds) as sky:
        sky.render(width=4, height=4)
        tau = sky.layer("clouds").column_optical_depths(GRID)[..., 0]
    return tau / nominal


def main() -> None:
    for t in params.CLOUD_TYPES:
        params.WATER_NORMALIZATION[t] = (1.0,) * len(params.WATER_COVERAGE_NODES)
    table = {}
    for t in params.CLOUD_TYPES:
        cols = {c: np.concatenate([raw_columns(t, c, s).ravel() for s in SEEDS])
                for c in params.WATER_COVERAGE_NODES}  # fmt: skip
        full = cols[1.0]
        fraction_full = float(np.mean(full > CLOUDY))
        row = []
        for c in params.WATER_COVERAGE_NODES:
            x = cols[c]
            if c == 1.0:
                row.append(1.0 / float(np.mean(full)))
            else:
                row.append(1.0 / (fraction_full * float(np.mean(x[x > CLOUDY]))))
            print(f"{t:14s} coverage {c:4.2f}: mean {x.mean():.4f}, cloudy fraction "
                  f"{np.mean(x > CLOUDY):.3f}, factor {row[-1]:.3f}")  # fmt: skip
        table[t] = tuple(round(v, 3) for v in row)
    print("WATER_NORMALIZATION = {")
    for t, row in table.items():
        print(f'    "{t}": ({", ".join(f"{v:.3f}" for v in row)}),')
    print("}")


if __name__ == "__main__":
    main()
