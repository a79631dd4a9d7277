"""Several samples in one calibration: pooled law, bootstrap band, edge laws, CLI, report.

Ground truth: the 16 patches (32 x 32 elements each) of one synthetic Table 1 surface of
4 x 2.11 mm are samples of one population. The pooled law of the patches (mirror-symmetric
boundary) is checked against the periodic calibration of the whole (periodic) surface; the band against repeated sub-samplings of the
patches (its coverage); the report against summary.json.
"""

import dataclasses
import json
import math

import numpy as np
import pytest
from realfiles import needs_shared, real_file
from reportcells import Cells, assert_page_agrees

from frictionlaw import FrictionParams, alpha_first, alpha_reload
from frictionlaw.uncertainty import UNCERTAINTY_VERSION
from halfspace_calib.cli import main
from halfspace_calib.pipeline.band.samples import (
    SampleSpec,
    calibrate_samples,
    load_samples,
    pair_files,
    synthetic_population,
)
from halfspace_calib.pipeline.band.uncertainty import bootstrap_uncertainty, curves_of, pooled_law
from halfspace_calib.pipeline.calibration import Scene, calibrate
from halfspace_calib.pipeline.law.first_table import monotone_increasing

K, GRID = 4, 32
PROBES = (100e6, 300e6, 600e6)


@pytest.fixture(scope="module")
def population():
    """16 patch calibrations with their band (100 resamples) and the whole-surface calibration.

    At the fixed default levels (issue 39's refinement follows the 32^2 patches' noise: 78 s
    for this fixture against 39 s; the pooling is under test here, not the levels).
    """
    scene = Scene(grid=GRID, adaptive_levels=False)
    spec = SampleSpec(patches=K * K, n_bootstrap=100)
    mc = calibrate_samples(scene, spec, progress=False)
    whole = calibrate(  # periodic: the synthetic surface is one period, this is its exact solve
        Scene(grid=K * GRID, adaptive_levels=False),
        surfaces=synthetic_population(scene, K, GRID),
        progress=False,
    )
    return mc, whole


def _tau1(P, p):
    return P.tau_max * float(alpha_first(p, P))


def test_patches_are_disjoint_pieces_of_one_surface():
    scene = Scene(grid=GRID)
    samples = load_samples(scene, SampleSpec(patches=4))
    whole = synthetic_population(scene, 2, GRID)
    assert [s.name for s in samples] == [f"synthetic#p{i}{j}" for i in (0, 1) for j in (0, 1)]
    for s in samples:
        i, j = int(s.name[-2]), int(s.name[-1])
        piece = whole.workpiece.heights[i * GRID : (i + 1) * GRID, j * GRID : (j + 1) * GRID]
        # a patch is its piece of the large surface with the least-squares plane removed
        diff = s.surfaces.workpiece.heights - piece
        x, y = np.meshgrid(np.arange(GRID), np.arange(GRID), indexing="ij")
        coef, *_ = np.linalg.lstsq(
            np.column_stack([np.ones(x.size), x.ravel(), y.ravel()]), diff.ravel(), rcond=None
        )
        plane = (coef[0] + coef[1] * x + coef[2] * y).ravel()
        assert np.allclose(diff.ravel(), plane, atol=1e-12 * np.ptp(piece))
        assert s.scene.boundary == "mirror" and s.surfaces.grid == GRID


def test_pairing_policy():
    assert pair_files(["a", "b"], ["t"]) == [("a", "t"), ("b", "t")]
    assert pair_files(["a", "b"], []) == [("a", None), ("b", None)]
    assert pair_files(["a", "b"], ["t", "u"]) == [("a", "t"), ("b", "u")]
    with pytest.raises(ValueError, match="one tool file per workpiece"):
        pair_files(["a", "b", "c"], ["t", "u"])


def test_pooled_law_is_the_fit_to_all_points_and_matches_the_whole_surface(population):
    mc, whole = population
    P = mc.params
    curves = [curves_of(n, c.sweeps) for n, c in mc.calibrations.items()]
    # independent route: fit Eq. 24 to the mean curve of the samples (same pressures each)
    p = curves[0].p
    mean = np.mean([c.alpha for c in curves], axis=0)
    from halfspace_calib.pipeline.law.fit import fit_first_loading

    f = fit_first_loading(p, mean, P.H, floor_to=0.99 * P.H)  # the default bound, as pooled
    eq24 = P.replace(first_loading_form="eq24")  # the header beside the form that runs
    for q in PROBES:
        assert float(alpha_first(q, eq24)) == pytest.approx(
            float(alpha_first(q, eq24.replace(C1=f.C1, n1=f.n1))), rel=2e-3
        )
    # the tabulated first loading that runs is the mean curve itself (a monotone one)
    assert P.first_loading_form == "tabulated" and P.first_loading_table.p == tuple(p)
    np.testing.assert_allclose(P.first_loading_table.alpha, mean, rtol=1e-12)
    # the pooled law of the mirror-bounded patches against the periodic calibration of the
    # whole surface: measured 0.44-0.57 % on first loading, 0.2 % on the reload at half of
    # 600 MPa (against the isolated, DC-FFT, whole: 2.2-2.7 % and 14 %; docs/uncertainty.md);
    # 2 % allowed
    for q in PROBES:
        assert _tau1(P, q) == pytest.approx(_tau1(whole.params, q), rel=0.02)
    ph = 600e6
    assert float(alpha_reload(0.5 * ph, ph, P)) == pytest.approx(
        float(alpha_reload(0.5 * ph, ph, whole.params)), rel=0.02
    )


def test_band_holds_the_pooled_law_is_narrower_than_the_samples_and_edge_laws_follow(population):
    mc, _ = population
    P, u = mc.params, mc.uncertainty
    assert u.level == 0.9 and len(u.samples) == K * K
    b = u.band("tau_first")
    per_sample = {q: [_tau1(L, q) for L in P.sample_laws().values()] for q in PROBES}
    edges = P.edge_laws()
    for q in PROBES:
        c, lo, hi = b.at(q)
        assert lo < c < hi
        assert c == pytest.approx(_tau1(P, q), rel=1e-12)  # the probes are band points
        spread = max(per_sample[q]) - min(per_sample[q])
        # a confidence band of the mean of 16: about spread / sqrt(16) wide, well inside
        assert 0 < hi - lo < 0.8 * spread
        assert min(per_sample[q]) < c < max(per_sample[q])
        # the edge laws are Eq. 24 fitted to the band edges (a pointwise band is not a law):
        # measured within 0.23 of the band width at 100-600 MPa
        assert abs(_tau1(edges["lower"], q) - lo) < 0.3 * (hi - lo)
        assert abs(_tau1(edges["upper"], q) - hi) < 0.3 * (hi - lo)
    mu = u.parameters["mu_eff"]
    assert mu.central == pytest.approx(P.mu_eff, rel=1e-12) and mu.lower < mu.central < mu.upper
    # issue 37: the band, its edge laws and the sample laws run the forms the pooled law runs
    assert u.version == 2 and (P.first_loading_form, P.reload_form) == ("tabulated",) * 2
    for L in [*P.sample_laws().values(), *edges.values()]:
        assert (L.first_loading_form, L.reload_form) == (P.first_loading_form, P.reload_form)
        assert L.reload_table.s2 == P.reload_table.s2  # one exponent for the band
    for e, k in (("lower", 1), ("upper", 2)):  # the edge's table is the band's edge at each level
        got = alpha_first(np.array(P.first_loading_table.p), edges[e])
        band = [u.band("alpha_first").at(q)[k] for q in P.first_loading_table.p]
        levels = np.array(P.first_loading_table.p)
        want = np.clip(monotone_increasing(band), levels / P.H, 1.0)
        np.testing.assert_allclose(got, want, atol=1e-12)
    for ph in {c.p_hist for c in mc.pooled.sweeps.reload_curves()}:
        r = u.band("tau_reload", ph)
        assert all(lo <= c <= hi for c, lo, hi in zip(r.central, r.lower, r.upper, strict=True))


@pytest.mark.slow
def test_band_coverage_over_sub_samplings(population):
    """Draws of 5 of the 16 patches: how often does the 90 % band hold the population's law?

    Measured at 3, 5, 10 and 16 samples with 300 draws each (benchmarks/uncertainty_coverage.py):
    see docs/uncertainty.md. Here 16 draws of 50 resamples with the default (t) band: the
    coverage must be clearly above chance.
    """
    mc, _ = population
    truth = mc.params
    curves = [curves_of(n, c.sweeps) for n, c in mc.calibrations.items()]
    rng = np.random.default_rng(7)
    hits, n = 0, 0
    for r in range(16):
        sub = [curves[i] for i in rng.choice(len(curves), 5, replace=False)]
        scene = mc.pooled.scene  # the truth's forms and the default bound
        cen = pooled_law(scene, sub).apply(truth).replace(uncertainty=None)
        u = bootstrap_uncertainty(sub, cen, n_bootstrap=50, seed=r, floor_to=0.99 * truth.H)
        for q in PROBES:
            _, lo, hi = u.band("tau_first").at(q)
            hits += lo <= _tau1(truth, q) <= hi
            n += 1
    assert 0.55 <= hits / n <= 1.0


def test_params_file_round_trip_and_versions(population, tmp_path):
    mc, _ = population
    P = mc.params
    path = P.to_json(tmp_path / "params.json")
    Q = FrictionParams.from_json(path)
    assert Q == P and Q.uncertainty == P.uncertainty
    assert Q.edge_laws()["lower"] == P.edge_laws()["lower"]
    doc = json.loads(path.read_text())
    # a newer block version is ignored: the law is read, without a band
    doc["uncertainty"]["version"] = UNCERTAINTY_VERSION + 1
    R = FrictionParams.from_dict(doc)
    assert R == P and R.uncertainty is None
    with pytest.raises(ValueError, match="no uncertainty block"):
        R.edge_laws()
    # a malformed block of the known version is refused, naming the field
    doc["uncertainty"]["version"] = UNCERTAINTY_VERSION
    doc["uncertainty"]["edge_laws"]["lower"]["C1"] = -1.0
    with pytest.raises(ValueError, match=r"edge_laws\.lower\.C1"):
        FrictionParams.from_dict(doc)
    del doc["uncertainty"]  # and a file without one is a plain parameter file
    assert FrictionParams.from_dict(doc).uncertainty is None


# ----------------------------------------------------------------------------- CLI
# grid 16 and four pressures are a toy for the reports' plumbing: the held-out acceptance
# (0.05 in alpha, tested in test_failed_fit and test_measured_files) is not what is checked here
FAST = ["--pressures", "25e6,100e6,300e6,600e6", "--reload-fractions", "0.25,0.5,0.8",
        "--heldout-tol", "0.5"]  # fmt: skip


@pytest.mark.parametrize(
    "argv, match",
    [
        (["--patches", "2", "--grid", "32"], "band needs at least 3"),
        (["--patches", "4", "--grid", "12"], "below the guard of 16"),
        (["--patches", "4", "--grid", "32", "--band-level", "1.5"], "band level"),
        (["--band-level", "0.8"], "apply to several samples"),
        (["--band-method", "percentile"], "apply to several samples"),
        (["--patches", "4", "--grid", "32", "--band-method", "bca"], "--band-method"),
        (["--patches", "4", "--grid", "32", "--bootstrap", "10"], "n_bootstrap"),
        (["--patches", "4", "--grid", "32", "--effects", "tangential"], "not available"),
        (["--patches", "0"], "patches must be"),
        (["--patches", "4", "--grid", "32", "--periodic"], "a patch is not one period"),
        (["--patches", "4", "--grid", "32", "--resolution-check"], "calibrate one sample alone"),
    ],
)
def test_cli_refuses_bad_sample_input_before_any_work(argv, match, tmp_path, capsys):
    out = tmp_path / "c"
    assert main(["--out", str(out), "--quiet", *argv]) == 2
    err = capsys.readouterr().err
    assert match in err and "Traceback" not in err
    assert not out.exists()


def _shared(name):
    return str(real_file(name))


@needs_shared
def test_cli_refuses_mixed_units_and_element_sizes(tmp_path, capsys):
    mnt, mp, mx = _shared("mnt-1.mnt"), _shared("metropro-1.dat"), _shared("matrix-3.txt")
    out = tmp_path / "c"
    assert main(["--out", str(out), "--quiet", "--grid", "16", "--workpiece", mnt, mp, mx]) == 2
    assert "different height units" in capsys.readouterr().err
    x3p = _shared("x3p-2.x3p")
    assert main(["--out", str(out), "--quiet", "--grid", "16", "--workpiece", mp, mx, x3p]) == 2
    assert "element sizes differ" in capsys.readouterr().err
    assert not out.exists()


def test_cli_multi_sample_run_writes_band_and_a_report_that_agrees(tmp_path, capsys):
    out = tmp_path / "c"
    argv = [
        "--out",
        str(out),
        "--no-progress",
        "--patches",
        "4",
        "--grid",
        "16",
        "--bootstrap",
        "60",
    ]
    assert main(argv + FAST) == 0
    text = capsys.readouterr().out
    assert "pooled law and 90 % bootstrap band (60 resamples, t band)" in text
    P = FrictionParams.from_json(out / "params.json")
    assert P.uncertainty is not None and len(P.uncertainty.samples) == 4
    for f in ("samples.csv", "bands.csv", "band_tau_first.png", "band_reload.png", "report.html"):
        assert (out / f).is_file(), f
    summary = json.loads((out / "summary.json").read_text())
    assert summary["C1"] == P.C1 and summary["uncertainty"]["level"] == 0.9
    page = Cells((out / "report.html").read_text(encoding="utf-8"))
    assert page.images >= 5 and page.remote == []
    law = "law.branches.first_loading.forms.eq24.parameters"
    for key in (
        f"{law}.C1.value",
        f"{law}.n1.value",
        "law.derived.mu_eff.value",
        "uncertainty.parameters.C1.lower",
        "uncertainty.parameters.mu_eff.upper",
        "samples.per_sample.3.n2",
        "uncertainty.tau_first_at.300 MPa.upper",
    ):
        assert key in page.cells, key
    assert_page_agrees(page, summary)


def test_single_calibration_report_agrees_with_summary(tmp_path):
    out = tmp_path / "c"
    assert main(["--out", str(out), "--quiet", "--grid", "16", *FAST]) == 0
    summary = json.loads((out / "summary.json").read_text())
    page = Cells((out / "report.html").read_text(encoding="utf-8"))
    law = "law.branches.first_loading.forms.eq24"
    assert {f"{law}.parameters.C1.value", f"{law}.r_squared", "max_jump_relative"} <= set(
        page.cells
    )
    assert_page_agrees(page, summary)
    assert page.images == 4 and not math.isnan(summary["C1"])


def test_spec_validation():
    with pytest.raises(ValueError, match="band level"):
        SampleSpec(level=0.2)
    with pytest.raises(ValueError, match="band method must be one of t, percentile"):
        SampleSpec(band_method="bca")
    assert not SampleSpec().multi and SampleSpec(patches=2).multi
    assert dataclasses.replace(SampleSpec(), workpieces=["a", "b"]).multi


def test_scene_file_lists_samples(tmp_path, capsys):
    from halfspace_calib.pipeline.band.samples import read_samples_table

    scene = tmp_path / "s.toml"
    scene.write_text(
        '[scene]\ngrid = 32\n[samples]\nworkpieces = ["a.npy", "/abs/b.npy"]\npatches = 2\n'
        'band_level = 0.8\nbootstrap = 60\nband_method = "percentile"\n'
    )
    kw = read_samples_table(scene)
    assert kw["workpieces"] == (str(tmp_path / "a.npy"), "/abs/b.npy")
    assert (kw["patches"], kw["level"], kw["n_bootstrap"]) == (2, 0.8, 60)
    assert kw["band_method"] == "percentile"
    # the scene file alone makes a multi-sample run: 2 patches of a synthetic pair are too few
    scene.write_text("[scene]\ngrid = 32\n[samples]\npatches = 2\n")
    assert main(["--scene", str(scene), "--out", str(tmp_path / "o"), "--quiet"]) == 2
    assert "band needs at least 3" in capsys.readouterr().err
    scene.write_text("[scene]\ngrid = 32\n[samples]\npatchez = 4\n")
    assert main(["--scene", str(scene), "--out", str(tmp_path / "o"), "--quiet"]) == 2
    assert "unknown [samples] keys ['patchez']" in capsys.readouterr().err


def test_files_of_one_name_stay_apart_and_pair_with_one_tool(tmp_path):
    from halfspace_calib import topography as T

    paths = []
    for sub, seed in (("a", 3), ("b", 4), ("c", 5)):
        (tmp_path / sub).mkdir()
        p = tmp_path / sub / "scan.npy"
        np.save(p, T.dc04_edt_like(64, seed=seed).heights * 1e6)  # in um
        paths.append(str(p))
    scene = Scene(workpiece=paths[0], unit="um", size=2.11e-3, grid=32)
    samples = load_samples(scene, SampleSpec(workpieces=paths))
    assert [s.name for s in samples] == ["scan", "scan@2", "scan@3"]
    assert [s.scene.workpiece for s in samples] == paths
    # every workpiece against the one (synthetic) tool, the files' own heights
    for s in samples:
        assert s.surfaces.grid == 32 and s.surfaces.files[0].path == s.scene.workpiece
        assert s.surfaces.workpiece.heights.std() > 1e-7
    a, b = samples[0].surfaces.workpiece.heights, samples[1].surfaces.workpiece.heights
    assert not np.allclose(a, b)
