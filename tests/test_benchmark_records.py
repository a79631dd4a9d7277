"""The benchmarks' run records (benchmarks/_provenance.py): a run writes one, ``--help`` or a
usage error (an exit before any result) keeps the earlier run's record."""

import importlib.util
import json
import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture
def prov(tmp_path, monkeypatch):
    spec = importlib.util.spec_from_file_location("_prov", ROOT / "benchmarks" / "_provenance.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    monkeypatch.setattr(mod, "RESULTS", tmp_path / "results")
    monkeypatch.setattr(mod, "ROOT", tmp_path)
    return mod


def test_a_run_writes_its_record_and_help_keeps_it(prov, tmp_path):
    with prov.run_record("demo.py"):
        prov.RESULTS.mkdir()
        (prov.RESULTS / "demo.csv").write_text("a\n1\n")
    path = prov.RESULTS / "demo.run.json"
    rec = json.loads(path.read_text())
    assert rec["status"] == "completed" and rec["files_written"] == ["demo.csv"]
    old = path.stat().st_mtime - 60  # the results as an earlier run left them
    os.utime(prov.RESULTS / "demo.csv", (old, old))
    before = path.read_text()
    for code in (0, 2):  # --help, a usage error: nothing ran
        with pytest.raises(SystemExit), prov.run_record("demo.py"):
            raise SystemExit(code)
        assert path.read_text() == before
    with pytest.raises(RuntimeError), prov.run_record("demo.py"):
        raise RuntimeError("a failed run is recorded as such")
    assert json.loads(path.read_text())["status"] == "failed"
