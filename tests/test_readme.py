"""The README's first screen and CI run the same commands."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _readme_commands():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    return re.findall(r"```bash\n(.+?)\n```", text, flags=re.S)[:2]


def test_ci_runs_the_readme_test_command():
    main_job, tests = _readme_commands()
    ci = [ln for ln in (ROOT / ".ci/run").read_text().splitlines() if ln and ln[0] != "#"]
    assert tests in ci, f"README test command {tests!r} is not a line of .ci/run"


def test_readme_commands_make_their_own_virtual_environment():
    for cmd in _readme_commands():
        assert cmd.startswith("python3 -m venv .venv && . .venv/bin/activate && pip install -e ")
    main_job, _ = _readme_commands()
    assert "halfspace-calib --out out/calibration" in main_job
    assert "fe-demo upsetting --law sbmf --params out/calibration/params.json" in main_job
