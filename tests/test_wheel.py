"""The distribution as users get it: sdist and wheel build, and the wheel runs the main job.

The wheel is installed into a fresh virtual environment (no access to this checkout, pip's
cache only) and the README's main job (calibrate the default scene, then the FE upsetting
with that law, on a coarse FE mesh to save time) runs from a folder outside the repository.
"""

import os
import re
import subprocess
import sys
import tarfile
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

pytestmark = pytest.mark.slow


def _run(cmd, **kw):
    res = subprocess.run(cmd, capture_output=True, text=True, **kw)
    assert res.returncode == 0, f"{cmd} failed ({res.returncode}):\n{res.stdout}\n{res.stderr}"
    return res


@pytest.fixture(scope="module")
def dist(tmp_path_factory):
    pytest.importorskip("build")
    out = tmp_path_factory.mktemp("dist")
    _run([sys.executable, "-m", "build", "--sdist", "--wheel", "--outdir", str(out), str(ROOT)])
    wheels = sorted(out.glob("*.whl"))
    sdists = sorted(out.glob("*.tar.gz"))
    assert len(wheels) == 1 and len(sdists) == 1, sorted(p.name for p in out.iterdir())
    return wheels[0], sdists[0]


def test_wheel_and_sdist_carry_data_licence_and_type_marker(dist):
    wheel, sdist = dist
    names = set(zipfile.ZipFile(wheel).namelist())
    for member in (
        "frictionlaw/py.typed",
        "frictionlaw/data/limit_rates.csv",  # the two-state flattening's rate table
        "fe_demo/data/sbmf_example.json",
        "fe_demo/data/sbmf_example_flattening.json",
        "sbmf_cli/__init__.py",  # the command layer every console script imports
        "sbmf_cli/htmlpage.py",
    ):
        assert member in names, member
    assert any(n.endswith(".dist-info/LICENSE") or "/licenses/LICENSE" in n for n in names)
    assert not any(n.startswith("tests/") for n in names)
    with tarfile.open(sdist) as tf:
        snames = {n.split("/", 1)[1] for n in tf.getnames() if "/" in n}
    for member in ("LICENSE", "README.md", "pyproject.toml", "frictionlaw/py.typed"):
        assert member in snames, member


def test_wheel_carries_every_export_template(dist):
    """frictionlaw-export renders from template files: each one, and each file a target's record
    names or a template includes, must be in the wheel."""
    from frictionlaw.export import REGISTRY

    wheel, _ = dist
    names = set(zipfile.ZipFile(wheel).namelist())
    export = ROOT / "frictionlaw" / "export"
    templates = {
        p
        for p in export.rglob("*")
        if p.is_file() and p.suffix not in (".py", ".pyc") and "__pycache__" not in p.parts
    }
    assert {p.relative_to(export).parts[0] for p in templates} >= {"core", "abaqus", "shims"}
    named = {p for record in REGISTRY.values() for p in record.templates()}
    included = {
        export / m
        for p in templates
        for m in re.findall(r'{%\s*include\s+"([^"]+)"', p.read_text(encoding="utf-8"))
    }
    assert named | included <= templates, sorted(map(str, (named | included) - templates))
    missing = sorted({p.relative_to(ROOT).as_posix() for p in templates} - names)
    assert not missing, missing


def test_wheel_runs_the_main_job_from_outside_the_repository(dist, tmp_path):
    wheel, _ = dist
    venv = tmp_path / "venv"
    _run([sys.executable, "-m", "venv", str(venv)])
    bin_ = venv / "bin"
    _run([str(bin_ / "python"), "-m", "pip", "install", "-q", str(wheel)])
    work = tmp_path / "work"
    work.mkdir()
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    env["PATH"] = f"{bin_}{os.pathsep}{env.get('PATH', '')}"
    # the installed package, not this checkout, must be the one imported
    res = _run(
        [str(bin_ / "python"), "-c", "import frictionlaw, fe_demo; print(fe_demo.__file__)"],
        cwd=work,
        env=env,
    )
    assert str(venv) in res.stdout and str(ROOT) not in res.stdout
    _run([str(bin_ / "halfspace-calib"), "--quiet", "--out", "calibration"], cwd=work, env=env)
    assert (work / "calibration" / "params.json").is_file()
    _run(
        [
            str(bin_ / "fe-demo"),
            "upsetting",
            "--law",
            "sbmf",
            "--params",
            "calibration/params.json",
            "--nr",
            "8",
            "--increments",
            "10",
            "--quiet",
            "--out",
            "upsetting",
        ],
        cwd=work,
        env=env,
    )
    history = (work / "upsetting" / "history.csv").read_text().splitlines()
    assert len(history) >= 11  # a header and one row per increment
