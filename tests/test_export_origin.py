"""Where the exported m and surfaces came from (issue 33, item 6): header and README of each export.

A parameter file written by ``fe-demo ring-fit`` (run here, coarse) carries
``provenance.ring_test``: every export of it says ``m = <m> fitted to ring-compression tests by
fe-demo ring-fit`` with the points, column, band and level, the ring-test file with its sha256,
the ring and the material, and the source calibration's path and sha256; fitted with
``--illustrative``, it says ILLUSTRATIVE, NOT a calibration result. A calibration's own file says
what its ``provenance.inputs.m`` says (input, not fitted). The surfaces: measured files by path
and sha256 (``provenance.extra.files``), synthetic ones by generator, preset and seed
(``provenance.surfaces``).
"""

import hashlib
import json

import numpy as np
import pytest
from default_params import DEFAULT

import frictionlaw as fl
import frictionlaw.export as exp
from fe_demo.analysis.ringfit import ring_curve
from fe_demo.cli import main as fe_main
from fe_demo.scenes.laws import EXAMPLE_PARAMS_PATH

SURFACES = {
    "workpiece": {"source": "generator", "generator": "gen/dc04", "preset": "dc04", "seed": 1},
    "tool": {"source": "generator", "generator": "gen/tool", "preset": "tool_like", "seed": 2},
}
M_NOTE = "input, not fitted: Tresca friction factor of the interface, measured separately"


def _sha(path):
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.fixture(scope="module")
def calibration(tmp_path_factory):
    """A calibration's parameter file: synthetic surfaces, m an input (as halfspace-calib)."""
    path = tmp_path_factory.mktemp("cal") / "params.json"
    prov = {"surfaces": SURFACES, "inputs": {"m": M_NOTE}, "extra": {"files": []}}
    fl.FrictionParams(**DEFAULT, provenance=prov).to_json(path)
    return path


@pytest.fixture(scope="module")
def rings(tmp_path_factory):
    """Ring tests made by the coarse FE model with the example law at m = 0.3."""
    params = fl.FrictionParams.from_json(EXAMPLE_PARAMS_PATH)
    r, d = ring_curve("sbmf", 0.3, params=params, reduction=0.5, nr=8, n_increments=20)
    red = np.array([0.15, 0.25, 0.35, 0.45, 0.5])
    path = tmp_path_factory.mktemp("rings") / "rings.csv"
    rows = "".join(f"{a},{b}\n" for a, b in zip(red, np.interp(red, r, d), strict=True))
    path.write_text("height_reduction,inner_diameter_change\n" + rows)
    return path


def _ring_fit(rings, out, *source):
    argv = ["ring-fit", "--measured", str(rings), "--nr", "8", "--increments", "20"]
    assert fe_main([*argv, *source, "--no-progress", "--quiet", "--out", str(out)]) == 0
    return out / "params.json"


def _texts(params, target="abaqus-fric"):
    """``(header, README)`` of ``target``'s export of ``params``."""
    files, _ = exp.render(target, params, units="mm-t-s")
    record = exp.target(target)
    marker = record.style.comment + " "
    src = files[record.file]
    header = [ln[len(marker) :] for ln in src.splitlines() if ln.startswith(marker)]
    # the header's wrapped lines joined back (continuations are indented by 2)
    joined = []
    for ln in header:
        if ln.startswith("  ") and joined:
            joined[-1] += " " + ln.strip()
        else:
            joined.append(ln)
    return "\n".join(joined), files["README.md"]


@pytest.fixture(scope="module")
def fitted(rings, calibration, tmp_path_factory):
    return _ring_fit(rings, tmp_path_factory.mktemp("fit") / "fit", "--params", str(calibration))


def test_m_fitted_to_ring_tests_is_named_with_its_inputs(fitted, rings, calibration):
    rt = json.loads(fitted.read_text())["provenance"]["ring_test"]
    m = fl.FrictionParams.from_json(fitted).m
    for target in exp.TARGETS:  # every export says it, routines and tables alike
        header, readme = _texts(fitted, target)
        first = (
            f"m = {m:.6g} fitted to ring-compression tests by fe-demo ring-fit: 5 points of "
            f"inner_diameter_change, band [{rt['m_lower']:.4f}, {rt['m_upper']:.4f}] at "
            f"{100 * rt['band_level']:g} %"
        )
        assert first in header and f"- {first}\n" in readme, target
        for text in (header, readme):
            assert f"ring tests: {rings.resolve()} (sha256 {_sha(rings)})" in text
            assert "ring: OD 18 mm, ID 9 mm, H 6 mm (standard 6:3:2 ring" in text
            assert "ring material: E 210 GPa, nu 0.3, K 530 MPa, eps0 0.006, n 0.24" in text
            assert f"source calibration: {calibration.resolve()} (sha256 {_sha(calibration)})" in (
                text
            )
            assert "ILLUSTRATIVE" not in text
            # the surfaces that shaped C1 .. n2: the calibration's, carried by the fit
            assert "surface workpiece: synthetic, generator gen/dc04, preset dc04, seed 1" in text
            assert "surface tool: synthetic, generator gen/tool, preset tool_like, seed 2" in text
    assert rt["m"] == m


def test_an_illustrative_ring_fit_says_so(rings, tmp_path):
    params = _ring_fit(rings, tmp_path / "fit", "--illustrative")
    for target in ("abaqus-fric", "calculix", "lsdyna-table"):
        header, readme = _texts(params, target)
        assert "ILLUSTRATIVE, NOT a calibration result" in header
        assert "**ILLUSTRATIVE, NOT a calibration result**" in readme
        assert "fitted to ring-compression tests by fe-demo ring-fit" in header
        assert "source calibration: " in header


def test_a_calibrations_m_is_an_input(calibration):
    header, readme = _texts(calibration)
    assert f"m = 0.5: {M_NOTE}" in header and f"- m = 0.5: {M_NOTE}" in readme
    assert "ring-fit" not in header and "ILLUSTRATIVE" not in readme


def test_measured_surfaces_are_named_by_file_and_sha256(tmp_path):
    files = [
        {"role": "workpiece", "path": "/lab/scans/sheet_A.sdf", "sha256": "a" * 64},
        {"role": "tool", "path": "/lab/scans/die_B.x3p", "sha256": "b" * 64},
    ]
    prov = {"surfaces": {"workpiece": {"source": "file"}}, "extra": {"files": files}}
    path = tmp_path / "params.json"
    fl.FrictionParams(**DEFAULT, provenance=prov).to_json(path)
    header, readme = _texts(path)
    for f in files:
        line = f"surface {f['role']}: {f['path']} (sha256 {f['sha256']})"
        assert line in header and f"- {line}\n" in readme
    assert "synthetic" not in header
    # several samples: each file with its sample's name
    prov = {
        "surfaces": {"note": "several samples"},
        "extra": {
            "files": [
                {"sample": "s1", "role": "workpiece", "path": "/lab/s1.sdf", "sha256": "c" * 64}
            ]
        },
    }
    fl.FrictionParams(**DEFAULT, provenance=prov).to_json(path)
    assert f"surface s1 workpiece: /lab/s1.sdf (sha256 {'c' * 64})" in _texts(path)[0]


def test_nothing_recorded_is_said_plainly(tmp_path):
    """The shipped example records neither: said so, and its note (NOT a calibration result)."""
    header, readme = _texts(EXAMPLE_PARAMS_PATH)
    assert "m = 0.6: its origin is not recorded in the parameter file" in header
    assert "NOT a calibration result" in header and "**ILLUSTRATIVE" in readme
    assert "surfaces: not recorded in the parameter file" in header
    # odd entries never stop an export
    path = tmp_path / "odd.json"
    prov = {"ring_test": {"measured_files": "x", "geometry_m": 3}, "surfaces": [1], "extra": 2}
    fl.FrictionParams(**DEFAULT, provenance=prov).to_json(path)
    header, _ = _texts(path)
    assert "ring tests: not recorded" in header and "ring: not recorded" in header
