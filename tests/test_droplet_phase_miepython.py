"""The cloud droplets' Mie phase function (skydome.clouds.phase.MIE_PHASE, the packaged table
built by tools/build_cloud_phase.py with skydome's own Mie code) against an independent one
computed with miepython alone (tests/data/droplet_phase_miepython.json, made offline by
tools/make_droplet_phase_reference.py: the same droplets, m = 1.333 at 550 nm, r_eff 10 um,
v_eff 0.1, over the same radii 0.25-80 um, 220000 of them, converged to 0.11 %; miepython is
not imported here). Checked: P(theta) to 1 % at 41 angles from the diffraction peak to the
glory, all of them nodes of the table, and the asymmetry parameter to 1e-3.

The packaged table was 1-8 % off at 18 side and back angles while its build integrated 1000
log-spaced radii (too few for the Mie ripple and interference structure in the size
parameter); tools/build_cloud_phase.py now integrates 16000, and every angle is within 1 %.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from skydome.clouds.phase import MIE_PHASE

REFERENCE = json.loads(
    (Path(__file__).parent / "data" / "droplet_phase_miepython.json").read_text()
)


def _cases() -> list:
    return [
        pytest.param(theta, p, id=f"{theta:g}deg")
        for theta, p in zip(REFERENCE["theta_deg"], REFERENCE["phase_per_sr"], strict=True)
    ]


def test_reference_is_converged_and_normalised():
    prov = REFERENCE["provenance"]
    # The reference must be good to well under the 1 % tested: doubling its radii moved it
    # by 0.11 % at most.
    assert prov["convergence"]["max_relative_change_of_phase"] < 3e-3
    # miepython's norm="qsca" intensity integrates to Q_sca (the normalisation used).
    assert float(prov["normalisation_check"].rsplit(":", 1)[1]) == pytest.approx(1.0, abs=1e-6)


@pytest.mark.parametrize(("theta_deg", "reference"), _cases())
def test_phase_matches_miepython(theta_deg: float, reference: float):
    value = float(MIE_PHASE.value(np.cos(np.radians(theta_deg))))
    # 1 %: the reference is converged to 0.11 %, the table's 6 digits and its renormalisation
    # (1.2e-4) add less; what remains is the build's radius quadrature, which must be better.
    assert value == pytest.approx(reference, rel=0.01)


def test_asymmetry_matches_miepython():
    # 1e-3: the reference's g is exact in angle (from the spheres' g) and converged to 4e-6;
    # the table's trapezoid moment and its radius quadrature differ by 1.4e-4.
    assert MIE_PHASE.asymmetry == pytest.approx(REFERENCE["asymmetry"], abs=1e-3)
