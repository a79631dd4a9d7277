"""The same inputs give the same ``params.json``, byte for byte (issue 41, item 5).

``ring-fit`` and every export record the parameter file's sha256; a rerun of the same calibration
(the same files at the same paths, the same options) must give the same hash. Wall times are the
run's, not the law's: they are in ``summary.json`` (``timings``), never in the parameter file.
"""

import hashlib
import json
from pathlib import Path

import pytest

from halfspace_calib.cli import main
from halfspace_calib.pipeline.law.params import timeless, timings_of

DATA = Path(__file__).parent / "data"
TOY = [
    "--pressures", "2e7,1e8,3e8,5e8",
    "--reload-fractions", "0.25,0.5,0.8",
    "--heldout-tol", "0.5",  # a toy grid: the acceptance is tested elsewhere
    "--quiet",
]  # fmt: skip


def _timing_keys(obj, where=""):
    """Every key of ``obj`` (any depth) that names a wall time or a date."""
    out = []
    if isinstance(obj, dict):
        for k, v in obj.items():
            path = f"{where}.{k}"
            low = k.lower()
            timing = low in ("seconds", "timings", "date", "time", "pid", "started")
            if timing or low.endswith(("_seconds", "_time", "_date")) or "wall_time" in low:
                out.append(path)
            out += _timing_keys(v, path)
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            out += _timing_keys(v, f"{where}[{i}]")
    return out


def _twice(tmp_path, args):
    outs = []
    for name in ("first", "second"):
        out = tmp_path / name
        assert main([*args, *TOY, "--out", str(out)]) == 0
        outs.append(out)
    return outs


@pytest.mark.parametrize(
    "case, args",
    [
        # the synthetic scene with every record that carries a wall time: the two effects', the
        # resolution check's, the tabulated reload fit's
        (
            "synthetic",
            ["--grid", "32", "--effects", "tangential,inclined", "--resolution-check"],
        ),
        # a measured file: its records (path, sha256, preparation steps)
        (
            "file",
            [
                "--workpiece",
                str(DATA / "matrix-3.txt"),
                "--tool",
                str(DATA / "matrix-3.txt"),
                "--grid",
                "16",
            ],
        ),
    ],
)
def test_two_calibrations_write_the_same_params_json(tmp_path, case, args):
    first, second = _twice(tmp_path, args)
    a, b = (o.joinpath("params.json").read_bytes() for o in (first, second))
    assert a == b, f"{case}: params.json differs between two runs of the same inputs"
    assert hashlib.sha256(a).hexdigest() == hashlib.sha256(b).hexdigest()
    doc = json.loads(a)
    assert _timing_keys(doc) == [], _timing_keys(doc)
    text = a.decode()
    assert str(tmp_path) not in text.replace(str(DATA), "")  # no temporary folder of the run
    # the times went to summary.json, and they are the run's (they differ between the runs)
    s1, s2 = (json.loads(o.joinpath("summary.json").read_text()) for o in (first, second))
    assert s1["timings"]["calibration"] > 0 and s1["timings"]["sweeps"] > 0
    if case == "synthetic":
        assert {"extra.effects.tangential.seconds", "extra.effects.inclined.seconds"} <= set(
            s1["timings"]
        )
        assert "fit.reload_tabulated.seconds" in s1["timings"]
        assert "extra.resolution_check.seconds" in s1["timings"]
    else:
        assert doc["provenance"]["extra"]["files"][0]["sha256"]
    assert s1["timings"] != s2["timings"]


def test_timeless_leaves_out_every_wall_time_and_timings_of_finds_them():
    rec = {
        "fit": {"reload": {"s2": 0.7, "seconds": 1.5}},
        "effects": [{"sweep_seconds": 2.0, "k": 1}],
        "timings": {"total": 3.0, "bootstrap": {"a": 1.0}},
        "n": 4,
    }
    assert timeless(rec) == {"fit": {"reload": {"s2": 0.7}}, "effects": [{"k": 1}], "n": 4}
    assert timings_of(rec) == {
        "fit.reload.seconds": 1.5,
        "effects.0.sweep_seconds": 2.0,
        "timings.total": 3.0,
        "timings.bootstrap.a": 1.0,
    }
