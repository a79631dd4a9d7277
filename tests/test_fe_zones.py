"""Zones of the die in fe-demo (issue 42): a rim with a law of its own, from a radius outward.

A die whose zones all carry the run's law is the one-law run to the last bit (each node runs the
zoned kernels of its zone, which are the one-law kernels); a zone that starts beyond the
workpiece changes nothing; a rough rim (its law's cap and contact fraction higher) raises the
upsetting force and closes the ring's inner diameter further (more friction at the rim holds the
outward flow back), and the nodes under it are counted per zone; bad zone options are refused
before any run (exit 2).
"""

import csv
import dataclasses
import json

import numpy as np
import pytest

from fe_demo.cli import main
from fe_demo.scenes import run_ring, run_upsetting
from fe_demo.scenes.laws import example_params

EXAMPLE = example_params()
#: a rough rim: the example law with a higher cap (m 0.95) and a steeper first loading (C1 4)
ROUGH = dataclasses.replace(EXAMPLE, m=0.95, C1=4.0)
KW = dict(nr=6, n_increments=6, reduction=0.3)


def test_a_die_of_one_law_in_zones_is_the_one_law_run():
    one = run_upsetting("sbmf", params=EXAMPLE, **KW)
    zoned = run_upsetting("sbmf", params=EXAMPLE, zones=[("rim", EXAMPLE, 6e-3)], **KW)
    assert one.converged and zoned.converged
    for key in ("force", "contact_radius", "n_slip", "n_stick"):
        assert np.array_equal(one.history[key], zoned.history[key]), key
    # both zones were in contact: the run went through the zoned kernels on both laws
    assert zoned.history["n_contact_die"][-1] > 0 and zoned.history["n_contact_rim"][-1] > 0
    far = run_upsetting("sbmf", params=EXAMPLE, zones=[("rim", ROUGH, 0.1)], **KW)
    assert np.array_equal(one.history["force"], far.history["force"])  # never reached
    assert np.all(far.history["n_contact_rim"] == 0)


def test_a_rough_rim_raises_the_force_and_closes_the_ring():
    one = run_upsetting("sbmf", params=EXAMPLE, **KW)
    rim = run_upsetting("sbmf", params=EXAMPLE, zones=[("rim", ROUGH, 6e-3)], **KW)
    assert rim.converged
    assert rim.history["force"][-1] > 1.005 * one.history["force"][-1]
    info = rim.info["law_parameters"]["zones"]
    assert [z["zone"] for z in info] == ["die", "rim"] and info[1]["from_radius_m"] == 6e-3
    assert info[1]["m"] == 0.95
    ring_kw = dict(nr=6, n_increments=8, reduction=0.3)
    r1 = run_ring("sbmf", params=EXAMPLE, **ring_kw)
    r2 = run_ring("sbmf", params=EXAMPLE, zones=[("rim", ROUGH, 6.5e-3)], **ring_kw)
    assert r1.converged and r2.converged
    d1, d2 = r1.history["inner_diameter_change"][-1], r2.history["inner_diameter_change"][-1]
    assert d2 < d1 - 1e-3, (d1, d2)  # more friction at the rim: the hole closes further
    assert r2.history["force"][-1] > r1.history["force"][-1]


def test_cli_zones(tmp_path, capsys):
    rim = tmp_path / "rim.json"
    ROUGH.to_json(rim)
    out = tmp_path / "ups"
    args = ["upsetting", "--nr", "4", "--increments", "3", "--reduction", "0.2", "--no-progress"]
    rc = main([*args, "--out", str(out), "--zone", f"rim={rim}", "--zone-from-radius", "rim=0.008"])
    assert rc == 0
    text = capsys.readouterr().out
    assert "+ rim from r=8 mm" in text and "contact nodes per die zone at the end" in text
    with (out / "history.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert {"n_contact_die", "n_contact_rim"} <= set(rows[0])
    zones = json.loads((out / "summary.json").read_text())["law_parameters"]["zones"]
    assert zones[1]["zone"] == "rim" and zones[1]["from_radius_m"] == 0.008


@pytest.mark.parametrize(
    "extra, match",
    [
        (["--zone", "rim=RIM"], "every --zone needs its --zone-from-radius"),
        (["--zone-from-radius", "rim=0.01"], "every --zone needs"),
        (["--zone", "rim=RIM", "--zone-from-radius", "rim=-1"], "must be finite and > 0"),
        (["--zone", "rim=RIM", "--zone-from-radius", "rim=x"], "a radius in m"),
        (["--zone", "die=RIM", "--zone-from-radius", "die=0.01"], "default law"),
        (["--zone", "r m=RIM", "--zone-from-radius", "r m=0.01"], "letters, digits"),
        (["--zone", "rim=none.json", "--zone-from-radius", "rim=0.01"], "does not exist"),
        (["--zone", "rim=RIM", "--zone-from-radius", "rim=0.01", "--law", "tresca"], "--law sbmf"),
    ],
)
def test_cli_bad_zones_exit_2(tmp_path, capsys, extra, match):
    rim = tmp_path / "rim.json"
    ROUGH.to_json(rim)
    extra = [e.replace("RIM", str(rim)) for e in extra]
    rc = main(["ring", "--nr", "4", "--out", str(tmp_path / "o"), *extra])
    assert rc == 2
    assert match in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("flattening", [False, True])
def test_a_zone_file_with_a_flattening_block_run_without_it_is_warned(tmp_path, capsys, flattening):
    """Like --params's: a zone whose file carries a flattening block, run without --flattening,
    is said once on stderr (it was silently run without it); with --flattening nothing is said."""
    from fe_demo.cli import _check_options, build_parser
    from frictionlaw import Flattening

    rim = tmp_path / "rim.json"
    dataclasses.replace(ROUGH, flattening=Flattening(slope=0.05)).to_json(rim)
    plain = tmp_path / "plain.json"
    ROUGH.to_json(plain)
    argv = ["upsetting", "--zone", f"rim={rim}", "--zone", f"mid={plain}"]
    argv += ["--zone-from-radius", "rim=0.008", "--zone-from-radius", "mid=0.004"]
    args = build_parser().parse_args([*argv, *(["--flattening"] if flattening else [])])
    _check_options(args)
    err = capsys.readouterr().err
    said = f"--zone rim: {rim} carries a flattening block"
    assert (said in err) is not flattening and "--zone mid" not in err
    assert {z[0] for z in args.zones_loaded} >= {"mid", "rim"}
