"""One record per host target: a new target is one record and its templates, nothing else.

A dummy host is registered as one :class:`frictionlaw.export.Target` with a trivial Fortran entry
template (it includes the law core), a README section, a stick text and a shim with its driver,
all written here in a temporary folder. With no other edit, ``render``/``export`` and the command
write its routine and README, and its harness compiles the routine and runs it against the
runtime. The shipped records are checked for what they name.
"""

import ctypes
import re

import numpy as np
import pytest
from default_params import DEFAULT

import frictionlaw as fl
import frictionlaw.export as exp
from frictionlaw.export import harness
from frictionlaw.export.cli import main
from sbmf_cli import MARKER

ENTRY = """\
C     Dummy host: the shear limit tau(P, PH) and the trial history.
      SUBROUTINE DUMMY(P, PH, TAU, PHNEW)
      IMPLICIT NONE
      DOUBLE PRECISION P, PH, TAU, PHNEW, G1H, DTAU, G1NEW
      G1H = -1.0D0
      CALL SBMF_SHEAR(P, PH, G1H, TAU, DTAU, G1NEW)
      PHNEW = MAX(PH, P)
      RETURN
      END
C
{% include "core/sbmf_core.f" %}
"""

SHIM = """\
subroutine h_dummy(n, p, ph, tau, phnew) bind(c, name='h_dummy')
  use iso_c_binding
  implicit none
  integer(c_int), value :: n
  real(c_double), intent(in) :: p(n), ph(n)
  real(c_double), intent(out) :: tau(n), phnew(n)
  integer :: i
  do i = 1, n
    call dummy(p(i), ph(i), tau(i), phnew(i))
  end do
end subroutine h_dummy
"""

SECTION = """\
## Use in the dummy host

Link `{{ name }}` and call `DUMMY(P, PH, TAU, PHNEW)` once per contact point.
"""

STICK = "Stick: the dummy host has none (stiffness source: {{ kt.kind }}).\n"


class DummyDriver:
    """Calls ``h_dummy`` with NumPy arrays: returns ``(tau, p_hist_new)``."""

    def __init__(self, lib):
        self._fn = lib.h_dummy
        self._fn.restype = None

    def __call__(self, p, p_hist):
        p, ph = (np.ascontiguousarray(a, dtype=np.float64) for a in (p, p_hist))
        tau, ph_new = np.empty_like(p), np.empty_like(p)
        ptrs = (a.ctypes.data_as(ctypes.c_void_p) for a in (p, ph, tau, ph_new))
        self._fn(ctypes.c_int(p.size), *ptrs)
        return tau, ph_new


def _record(folder, name="dummy", entry=ENTRY):
    """The dummy target: one record, its templates written into ``folder``."""
    files = {"dummy.f": entry, "dummy.f90": SHIM, "dummy.md": SECTION, "stick.md": STICK}
    for fname, text in files.items():
        (folder / fname).write_text(text)
    return exp.Target(
        name=name,
        host=exp.Host("Dummy FE", "DUMMY_EXIT", "DUMMY_MESSAGE", "this test"),
        file="sbmf_dummy.f",
        template=str(folder / "dummy.f"),
        readme=str(folder / "dummy.md"),
        form=exp.Routine(stick=str(folder / "stick.md"), state=("H(", ")")),
        harness=harness.Harness(str(folder / "dummy.f90"), DummyDriver),
    )


@pytest.fixture
def registered(tmp_path):
    """Register the dummy target for one test (and only then)."""
    folder = tmp_path / "templates"
    folder.mkdir()
    names = set(exp.REGISTRY)
    yield lambda **kw: exp.register(_record(folder, **kw))
    for name in set(exp.REGISTRY) - names:
        del exp.REGISTRY[name]


@pytest.fixture(scope="module")
def params_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("p") / "params.json"
    fl.FrictionParams(**DEFAULT, geo_ratio=0.2).to_json(path)
    return path


def test_a_dummy_target_is_one_record(registered, params_file, tmp_path):
    record = registered()
    assert exp.target("dummy") is record
    files, table = exp.render("dummy", params_file, units="mm-t-s")
    assert sorted(files) == ["README.md", "sbmf_dummy.f"] and table is None
    src = files["sbmf_dummy.f"]
    assert src.startswith("C SBMF friction law (Eqs. 24-26), target dummy\n")
    assert "SUBROUTINE DUMMY(" in src and "SUBROUTINE SBMF_SHEAR(" in src  # the core included
    h = re.search(r"PARAMETER \(H = ([-+0-9.D]+)\)", src).group(1)
    assert float(h.replace("D", "e")) == DEFAULT["H"] * 1e-6  # constants in the host's units
    assert max(map(len, src.splitlines())) <= 72
    readme = files["README.md"]
    assert readme.startswith("# `dummy`: SBMF friction law as a user subroutine\n")
    assert "## Use in the dummy host" in readme and "Link `sbmf_dummy.f`" in readme
    assert "Stick: the dummy host has none (stiffness source: host)." in readme
    assert "set `H(1)` and leave `H(2) = 0`" in readme and "Units: mm-tonne-s" in readme
    # the command knows it too, and writes its folder whole
    out = tmp_path / "out"
    assert main(["dummy", "--params", str(params_file), "--out", str(out), "--quiet"]) == 0
    assert sorted(p.name for p in out.iterdir() if p.name != MARKER) == sorted(files)


@pytest.mark.skipif(harness.gfortran() is None, reason="gfortran not installed")
def test_the_dummy_target_runs_in_its_harness(registered, params_file, tmp_path):
    record = registered()
    files, _ = exp.render("dummy", params_file)
    run, warnings = record.harness.load(files, tmp_path / "build", name="dummy")
    assert "Error" not in warnings
    params = fl.FrictionParams.from_json(params_file)
    rng = np.random.default_rng(3)
    p_hist = np.where(rng.random(200) < 0.5, rng.uniform(0.1, 2.0, 200) * params.H, 0.0)
    p = np.concatenate([[0.0, -1.0], rng.uniform(1e-3, 3.0, 198) * params.H])
    p[100:] = np.where(p_hist[100:] > 0, p_hist[100:] * rng.random(100), p[100:])  # Eq. 25
    tau, ph_new = run(p, p_hist)
    ref = np.asarray(fl.shear_limit(np.maximum(p, 0.0), p_hist, params))
    np.testing.assert_allclose(tau, ref, rtol=1e-12, atol=0.0)
    assert np.array_equal(ph_new, np.maximum(p_hist, p))
    assert (p[100:] < p_hist[100:]).sum() > 30  # the reload branch was exercised


def test_an_overlong_generated_line_is_bad_input_not_an_assertion(
    registered, params_file, tmp_path, capsys
):
    long_line = "      CALL SBMF_SHEAR(P, PH, G1H, TAU, DTAU, G1NEW)" + " " * 30 + "!\n"
    registered(name="dummy-long", entry=ENTRY.replace("C     Dummy host", long_line + "C"))
    with pytest.raises(ValueError, match="exceeds 72 columns"):
        exp.render("dummy-long", params_file)
    out = tmp_path / "out"
    assert main(["dummy-long", "--params", str(params_file), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "exceeds 72 columns" in err and "Traceback" not in err and not out.exists()


def test_register_refuses_a_taken_name(registered):
    registered()
    with pytest.raises(ValueError, match="registered already"):
        registered()
    with pytest.raises(ValueError, match="target must be one of abaqus-fric, .*dummy"):
        exp.target("nastran")


@pytest.mark.parametrize("name", exp.TARGETS)
def test_every_shipped_record_names_existing_templates(name):
    record = exp.target(name)
    missing = [str(p) for p in record.templates() if not p.is_file()]
    assert missing == []
    # a routine is tested in its host's emulation; a table has no routine to run
    assert (record.harness is None) == isinstance(record.form, exp.Table)
    assert record.host.exit_routine and record.host.message_routine and record.host.reference
