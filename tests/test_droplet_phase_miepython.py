"""The cloud droplets' Mie phase function (skydome.clouds.phase.MIE_PHASE, the packaged table
built by tools/build_cloud_phase.py with skydome's own Mie code) against an independent one
computed with miepython alone (tests/data/droplet_phase_miepython.json, made offline by
tools/make_droplet_phase_reference.py: the same droplets, m = 1.333 at 550 nm, r_eff 10 um,
v_eff 0.1, over the same radii 0.25-80 um, 220000 of them, converged to 0.11 %; miepython is
not imported here). Checked: P(theta) to 1 % at 41 angles from the diffraction peak to the
glory, all of them nodes of the table, and the asymmetry parameter to 1e-3.

The table misses 1 % at the angles of :data:`KNOWN_OFF`, by up to 8 % (179 deg): not the
table's angular resolution (linear interpolation between its nodes is within 0.2 % of the
function anywhere), but its 1000 log-spaced radii, too few for the Mie ripple and
interference structure in the size parameter (skydome's ``bulk_optics`` itself comes within
0.3 % of miepython at every angle here with 16000 radii). They are strict xfails, so that a
rebuilt table fails them until they are taken out.
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

#: Angles (deg) where MIE_PHASE / miepython - 1 exceeds 1 % (measured with the reference's
#: miepython 3.3.0 values; the table from tools/build_cloud_phase.py with RADII = 1000).
KNOWN_OFF = {70.0: 0.0125, 80.0: 0.0240, 90.0: 0.0122, 110.0: 0.0709, 120.0: 0.0340,
             130.0: 0.0231, 135.0: -0.0292, 137.0: -0.0263, 138.0: -0.0184, 140.0: -0.0344,
             144.0: 0.0105, 150.0: 0.0218, 160.0: 0.0198, 170.0: 0.0314, 175.0: 0.0165,
             178.0: 0.0112, 179.0: 0.0813, 179.5: 0.0187}  # fmt: skip


def _cases() -> list:
    cases = []
    for theta, p in zip(REFERENCE["theta_deg"], REFERENCE["phase_per_sr"], strict=True):
        marks = ()
        if theta in KNOWN_OFF:
            reason = f"table off by {KNOWN_OFF[theta]:+.1%}: 1000 radii in the build"
            marks = (pytest.mark.xfail(strict=True, reason=reason),)
        cases.append(pytest.param(theta, p, marks=marks, id=f"{theta:g}deg"))
    return cases


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
