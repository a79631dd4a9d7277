"""Measured files at the wrong lateral scale, corrected sizes and headered text exports (issue 38).

Before any sweep a scan whose field or RMS slope is implausible for a metal surface is refused
(exit 2, nothing written) naming its size, its slope and the likely unit mistake; the size of any
file can be corrected per role (``--workpiece-size``, ``--tool-size``), recorded beside the
file's own; a text export whose header SurfaceTopography understands (a pixel size, a height
conversion factor) is read by it, with the header's units. The wrong-scale cases are the shipped
files with their sizes scaled (``pipeline/sweep/lateral_scale.py`` has the bounds and their sources).
"""

import json

import numpy as np
import pytest
from realfiles import DATA, file_params, real_file

from halfspace_calib import topography as S
from halfspace_calib.cli import main
from halfspace_calib.pipeline.band.samples import SampleSpec, load_samples
from halfspace_calib.pipeline.sweep import lateral_scale as LS
from halfspace_calib.pipeline.sweep.scene import Scene
from halfspace_calib.pipeline.sweep.surface_plan import plan_surfaces
from halfspace_calib.topography import _formats

FAST = ["--grid", "32", "--pressures", "10e6,25e6,100e6,300e6,500e6",
        "--reload-fractions", "0.25,0.5,0.8", "--no-progress"]  # fmt: skip
PHASE = DATA / "phase-export.txt"
#: the export's map: the project's own generator (tests/data/README.md)
PHASE_SURFACE = dict(n=64, size=128e-6, rq=0.3e-6, seed=38)


def _run(capsys, *argv):
    code = main([*argv])
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    return code, out, err


def _nothing_written(tmp_path, *keep):
    """Only the test's own inputs in ``tmp_path``: no output, no temporary folder, no lock."""
    return sorted(p.name for p in tmp_path.iterdir()) == sorted(keep)


# ----------------------------------------------------------------------------- the bounds
@pytest.mark.parametrize(
    "name", file_params(["metropro-1.dat", "mnt-1.mnt", "x3p-2.x3p", "sur-3.sur", "matrix-3.txt"])
)
def test_shipped_files_are_well_inside_and_refused_1000x_too_wide(name):
    path = real_file(name)
    scan = plan_surfaces(Scene(workpiece=str(path), max_undefined=0.95, grid=16)).scans[0]
    s = scan.surface
    slope = s.provenance["rms_slope_scan"]
    assert slope == pytest.approx(S.rms_slope(S.level(s)), rel=1e-12)
    scale = LS.ScanScale(name, "workpiece", s.size, slope)
    lo, hi = LS.FIELD_RANGE
    assert 6 * lo <= scale.field <= hi / 6, scale.words()  # a factor 6.6 or more inside
    lo, hi = LS.SLOPE_RANGE
    assert 3.5 * lo <= slope <= hi / 15, scale.words()  # 3.7x above the floor at least
    wide = LS.ScanScale(name, "workpiece", tuple(1000 * v for v in s.size), slope / 1000)
    narrow = LS.ScanScale(name, "workpiece", tuple(v / 1000 for v in s.size), slope * 1000)
    assert wide.implausible() and narrow.implausible()
    assert wide.factor() > 1 and narrow.factor() < 1


def test_synthetic_presets_are_well_inside():
    for surface in (S.dc04_edt_like(128), S.tool_like(128), S.tool_like(128, rough=True)):
        slope = LS.scan_slope(surface)
        assert 10 * LS.SLOPE_RANGE[0] < slope < LS.SLOPE_RANGE[1] / 10
        assert 10 * LS.FIELD_RANGE[0] < max(surface.size) < LS.FIELD_RANGE[1] / 10


def test_check_scan_names_the_size_the_slope_and_the_mistake():
    wide = LS.ScanScale("tool t.x3p", "tool", (0.7029, 0.5272), 1.84e-6)
    with pytest.raises(ValueError) as info:
        LS.check_scan(wide)
    text = str(info.value)
    assert "tool t.x3p: 0.7029 x 0.5272 m, RMS slope 1.84e-06" in text
    assert "1000x too large" in text and "0.7029 x 0.5272 mm with RMS slope 0.00184" in text
    assert "tool_size" in text and "tool_unit" in text and "smooth_pair=True" in text
    LS.check_scan(wide, smooth_pair=True)  # the user states it is that smooth: only the slope
    huge = LS.ScanScale("workpiece w", "workpiece", (160.0, 160.0), 1.05e-8)
    with pytest.raises(ValueError, match="160 x 160 m") as info:
        LS.check_scan(huge, smooth_pair=True)  # a field of 160 m is never a roughness scan
    assert "smooth_pair" not in str(info.value)
    narrow = LS.ScanScale("workpiece w", "workpiece", (1e-8, 1e-8), 168.0)
    with pytest.raises(ValueError, match="1000x too small") as info:
        LS.check_scan(narrow)
    LS.check_scan(LS.ScanScale("w", "workpiece", (1e-3, 1e-3), 0.05))  # plausible: passes


# ----------------------------------------------------------------------------- the CLI
def test_cli_a_file_typed_1000x_too_wide_is_refused_then_corrected(tmp_path, capsys):
    path = str(real_file("metropro-1.dat"))  # the optical flat against itself
    pair = ["--workpiece", path, "--tool", path, "--out", str(tmp_path / "o"), *FAST]
    wrong = ["--workpiece-size", "0.7029", "0.5272", "--tool-size", "0.7029", "0.5272"]
    code, _, err = _run(capsys, *pair, *wrong)
    assert code == 2
    assert "0.7029 x 0.5272 m, RMS slope 1.84e-06" in err and "1000x too large" in err
    assert "--workpiece-size" in err and _nothing_written(tmp_path)
    right = ["--workpiece-size", "0.7029e-3", "0.5272e-3", "--tool-size", "0.7029e-3", "0.5272e-3"]
    code, text, err = _run(capsys, *pair, *right)
    assert code == 0, err
    assert "702.9 x 527.2 um (--workpiece-size, overriding the file's own: it says 702.9" in text
    assert "702.9 x 527.2 um (--tool-size, overriding" in text
    files = json.loads((tmp_path / "o" / "params.json").read_text())["provenance"]["extra"]["files"]
    for f in files:
        assert f["size_source"] == "override"
        assert f["native_size"] == pytest.approx([7.029e-4, 5.272e-4])
        assert f["file_size"] == pytest.approx([7.0288e-4, 5.2716e-4], rel=1e-4)  # the file's own


def test_cli_a_plain_matrix_typed_1000x_too_wide_is_refused_then_corrected(tmp_path, capsys):
    heights = np.loadtxt(DATA / "matrix-3.txt", comments="#")  # 10 um AFM scan, heights in m
    np.save(tmp_path / "afm.npy", heights)
    base = ["--workpiece", str(tmp_path / "afm.npy"), "--unit", "m", "--out", str(tmp_path / "o")]
    code, _, err = _run(capsys, *base, "--size", "1e-2", *FAST)
    assert code == 2 and "10 x 10 mm, RMS slope 0.000168" in err and "1000x too large" in err
    assert _nothing_written(tmp_path, "afm.npy")
    code, _, err = _run(capsys, *base, "--size", "1e-5", *FAST)
    assert code == 0, err
    f = json.loads((tmp_path / "o" / "summary.json").read_text())["files"][0]
    assert f["size_source"] == "option" and f["rms_slope_scan"] == pytest.approx(0.168, rel=0.01)


def _phase_export(tmp_path, pixel):
    """The shipped export with its header's pixel size replaced (a header that lies)."""
    text = PHASE.read_text().replace("pixel size = 2e-06 m", f"pixel size = {pixel}")
    path = tmp_path / "phase-wrong.txt"
    path.write_text(text)
    return path


def test_cli_a_header_160_m_wide_is_refused_then_corrected(tmp_path, capsys):
    pytest.importorskip("SurfaceTopography")
    path = _phase_export(tmp_path, "2.5 m")  # 64 pixels of 2.5 m: the header makes it 160 m
    out = ["--workpiece", str(path), "--out", str(tmp_path / "o"), *FAST]
    code, _, err = _run(capsys, *out)
    assert code == 2 and "160 x 160 m, RMS slope" in err and "--workpiece-size" in err
    assert _nothing_written(tmp_path, path.name)
    code, text, err = _run(capsys, *out, "--workpiece-size", "128e-6")
    assert code == 0, err
    f = json.loads((tmp_path / "o" / "params.json").read_text())["provenance"]["extra"]["files"][0]
    assert f["file_size"] == pytest.approx([160.0, 160.0]) and f["size_source"] == "override"
    assert f["pitch"] == pytest.approx([2e-6, 2e-6])
    assert f["rms_slope_scan"] == pytest.approx(S.rms_slope(S.level(_phase_surface())), rel=1e-4)


def test_cli_a_headered_text_export_calibrates(tmp_path, capsys):
    pytest.importorskip("SurfaceTopography")
    code, text, err = _run(capsys, "--workpiece", str(PHASE), "--out", str(tmp_path / "o"), *FAST)
    assert code == 0, err
    assert "[AscReader]" in text and "128 x 128 um (file)" in text and "heights in m (file)" in text
    f = json.loads((tmp_path / "o" / "summary.json").read_text())["files"][0]
    assert f["layout"] == "instrument" and f["unit_source"] == "file"


# ----------------------------------------------------------------------------- reading
def _phase_surface():
    p = PHASE_SURFACE
    return S.self_affine(p["n"], p["size"], rq=p["rq"], seed=p["seed"])


def test_text_export_goes_to_surface_topography_with_the_header_units(tmp_path):
    pytest.importorskip("SurfaceTopography")
    assert _formats.layout_for(PHASE) == "instrument"
    assert _formats.text_export_line(PHASE) == "# pixel size = 2e-06 m"
    s = S.read_surface(PHASE)
    assert s.provenance["format"] == "AscReader" and s.provenance["unit"] == "m"
    assert s.size == pytest.approx((128e-6, 128e-6)) and s.dx == pytest.approx(2e-6)
    # the phase in rad times the header's factor is the height in m, x along each line
    ref = _phase_surface().heights
    np.testing.assert_allclose(s.heights, ref, rtol=0, atol=1e-5 * np.abs(ref).max())
    with pytest.raises(S.SizeContradiction):
        S.read_raw(PHASE, size=1e-4)
    with pytest.raises(S.UnitContradiction):
        S.read_raw(PHASE, unit="um")


def test_the_plain_matrix_keeps_its_own_header(tmp_path):
    assert _formats.text_export_line(DATA / "matrix-3.txt") is None  # Channel, Width, Height
    assert _formats.layout_for(DATA / "matrix-3.txt") == "matrix"
    written = S.write_surface(S.self_affine(8, 8e-6, rq=1e-7, seed=1), tmp_path / "w.txt")
    assert _formats.text_export_line(written) is None  # '# heights in um': no key
    assert _formats.layout_for(written) == "matrix"
    spip = tmp_path / "spip.txt"
    spip.write_text("# File Format = ASCII\n# x-length = 100\n1 2 3\n4 5 6\n7 8 9\n")
    assert _formats.text_export_line(spip) == "# File Format = ASCII"
    bare = tmp_path / "wyko.asc"
    bare.write_text("Wyko ASCII Data File Format 0 1 1\n1 2\n3 4\n")
    assert _formats.layout_for(bare) == "instrument"


def test_without_surface_topography_an_export_is_refused_naming_its_header(monkeypatch):
    def missing():
        raise ImportError(_formats.TOPOGRAPHY_EXTRA_HINT)

    monkeypatch.setattr(_formats, "import_surface_topography", missing)
    with pytest.raises(ImportError) as info:
        S.read_raw(PHASE)
    text = str(info.value)
    assert "'# pixel size = 2e-06 m'" in text and "pip install" in text
    assert S.read_raw(DATA / "matrix-3.txt")[3]["layout"] == "matrix"  # still read without it


def test_override_size_replaces_what_the_file_carries(tmp_path):
    h, dx, dy, prov = S.read_raw(DATA / "matrix-3.txt", override_size=(2e-5, 1e-5))
    assert (dx, dy) == pytest.approx((2e-5 / 256, 1e-5 / 256))
    assert prov["size_source"] == "override" and prov["file_size"] == pytest.approx([1e-5, 1e-5])
    np.save(tmp_path / "h.npy", np.ones((8, 4)))
    h, dx, dy, prov = S.read_raw(tmp_path / "h.npy", unit="um", override_size=8e-6)
    assert (dx, dy) == pytest.approx((1e-6, 2e-6)) and prov["file_size"] is None
    with pytest.raises(ValueError, match="override_size replaces"):
        S.read_raw(tmp_path / "h.npy", unit="um", size=8e-6, override_size=8e-6)
    with pytest.raises(ValueError, match="override_size"):
        S.read_raw(tmp_path / "h.npy", unit="um", override_size=-1.0)


def test_a_role_size_applies_to_every_file_of_the_role(tmp_path):
    # several samples (--workpiece A B C): the one --workpiece-size corrects each workpiece
    files = []
    for seed in (1, 2, 3):
        f = tmp_path / f"w{seed}.npy"
        S.write_surface(S.self_affine(32, 64e-6, rq=2e-7, seed=seed), f, unit="um")  # no size kept
        files.append(str(f))
    scene = Scene(workpiece=files[0], unit="um", workpiece_size=64e-6, grid=16, lambda_s=0.0)
    samples = load_samples(scene, SampleSpec(workpieces=tuple(files)))
    assert len(samples) == 3
    for smp in samples:
        (rec,) = smp.surfaces.files
        assert rec.size_source == "override" and rec.native_size == pytest.approx((64e-6, 64e-6))
    with pytest.raises(ValueError, match="tool_size is given but the tool is synthetic"):
        Scene(workpiece=files[0], unit="um", tool_size=1e-3)
