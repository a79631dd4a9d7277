"""The forms of the law's branches as records: a new form is one record and no other edit.

A dummy first-loading form, a log-log straight line through two points (the lowest and the top
level), is registered with its runtime record (frictionlaw.forms); it lowers to the tabulated
kernel form with two knots, so no kernel is edited. It then runs in the runtime law, round-trips
through params.json, is described in every report (its label and symbols are part of the
record: frictionlaw.describe reads them from there), and is refused by the export (no Fortran
template). The calibration side registers its fit, prediction and held-out refit, and the form
is calibrated, chosen, written and described with its measured errors.
"""

import json
import math
from dataclasses import dataclass

import numpy as np
import pytest

from frictionlaw import FrictionParams, alpha_first, alpha_reload, shear_limit_dp
from frictionlaw import forms as F
from frictionlaw.describe import describe_law
from frictionlaw.first_loading import FirstLoadingTable

H = 800e6


@dataclass(frozen=True)
class TwoPoints:
    """The dummy form's data: ``alpha`` at two pressures (Pa), a power law between them."""

    p: tuple
    alpha: tuple

    def check_hardness(self, H):
        if self.p[1] >= H:
            raise ValueError(f"two-point first loading p must lie below H = {H:g} Pa")

    def to_dict(self, form):
        return {"form": form, "version": 1, "p": list(self.p), "alpha": list(self.alpha)}

    @classmethod
    def from_dict(cls, doc, *, source="<dict>"):
        return cls(tuple(doc["p"]), tuple(doc["alpha"]))

    def exponent(self):
        return math.log(self.alpha[1] / self.alpha[0]) / math.log(self.p[1] / self.p[0])


def _lower(data, H):
    """Onto the tabulated kernel form: a two-knot table is the log-log straight line."""
    return F.branch_form(F.FIRST_LOADING, "tabulated").lower(
        FirstLoadingTable(data.p, data.alpha), H
    )


DUMMY = F.BranchForm(
    "two-points",
    F.FIRST_LOADING,
    "a power law through the lowest and the top level",
    TwoPoints,
    _lower,
    slope0=lambda params: params.first_loading_table.alpha[0] / params.first_loading_table.p[0],
    export_template=None,
    label="a two-point power law",
    describe=lambda P: (
        (F.Quantity("s", P.first_loading_table.exponent(), "1", "exponent of the power law"),),
        F.FormTable(
            (("p", "Pa"), ("alpha", "1")),
            tuple(zip(P.first_loading_table.p, P.first_loading_table.alpha, strict=True)),
            "a power law between the two points, Coulomb below the first",
        ),
    ),
)


@pytest.fixture
def dummy():
    F.register(DUMMY)
    yield DUMMY
    F.unregister(F.FIRST_LOADING, DUMMY.name)


def law(data, **kw):
    return FrictionParams(
        m=0.5,
        sigma_y=H / 2.8,
        H=H,
        C1=1.0,
        n1=2.0,
        C2=3.0,
        n2=1.0,
        first_loading_form="two-points",
        first_loading_table=data,
        **kw,
    )


def test_a_registered_form_runs_in_the_runtime_and_the_file(dummy, tmp_path):
    data = TwoPoints((10e6, 700e6), (0.02, 0.9))
    P = law(data)
    s = data.exponent()
    p = np.array([1e3, 5e6, 10e6, 50e6, 300e6, 700e6])
    want = np.where(p <= 10e6, 0.02 * p / 10e6, 0.02 * (p / 10e6) ** s)
    np.testing.assert_allclose(alpha_first(p, P), want, rtol=1e-13)
    np.testing.assert_allclose(
        shear_limit_dp(p[2:], 0.0, P)[1:], P.tau_max * want[3:] * s / p[3:], rtol=1e-12
    )
    assert P.mu_eff == pytest.approx(P.tau_max * 0.02 / 10e6)
    # the reload branch is scaled by the form's alpha1(p_hist)
    a1h = 0.02 * (300e6 / 10e6) ** s
    want_r = a1h * np.tanh(3.0 * 100e6 / (H * a1h))
    assert alpha_reload(100e6, 300e6, P) == pytest.approx(want_r, rel=1e-12)
    path = P.to_json(tmp_path / "p.json")
    doc = json.loads(path.read_text())
    assert doc["version"] == 3 and doc["first_loading_law"]["form"] == "two-points"
    Q = FrictionParams.from_json(path)
    assert Q == P and Q.first_loading_table == data
    # described from the same record: its label, symbol and table; Eq. 24 beside it (C1, n1),
    # the tabulated form not (the file carries no FirstLoadingTable)
    first = describe_law(Q).branch("first_loading")
    assert [f.form for f in first.forms] == ["two-points", "eq24"]
    run = first.running
    assert run.name == "a two-point power law" and run.errors is None
    assert run.parameters[0].value == pytest.approx(s, rel=1e-15)
    assert run.table.rows == ((10e6, 0.02), (700e6, 0.9))
    assert run.label() == f"a two-point power law: 2 levels 10-700 MPa, alpha 0.02-0.9, s = {s:.4g}"
    eq24 = F.branch_form(F.FIRST_LOADING, "eq24").switch(Q)
    plain = FrictionParams(m=0.5, sigma_y=H / 2.8, H=H, C1=1.0, n1=2.0, C2=3.0, n2=1.0)
    assert eq24.first_loading_form == "eq24"
    assert alpha_first(300e6, eq24) == alpha_first(300e6, plain)


def test_a_registered_form_is_refused_by_the_export_without_a_template(dummy, tmp_path, capsys):
    from frictionlaw.export.cli import main

    path = law(TwoPoints((10e6, 700e6), (0.02, 0.9))).to_json(tmp_path / "p.json")
    assert main(["lsdyna", "--params", str(path), "--out", str(tmp_path / "x")]) == 2
    assert "first loading form 'two-points'" in capsys.readouterr().err


def test_the_registry_checks_its_records(dummy):
    with pytest.raises(ValueError, match="registered already"):
        F.register(DUMMY)
    with pytest.raises(ValueError, match="needs slope0"):
        F.BranchForm("x", F.FIRST_LOADING, "x", None, _lower)
    with pytest.raises(ValueError, match="built-in"):
        F.unregister(F.FIRST_LOADING, "eq24")
    with pytest.raises(ValueError, match="must be a TwoPoints"):
        law(FirstLoadingTable((10e6, 700e6), (0.02, 0.9)))
    assert F.form_names(F.FIRST_LOADING) == ("eq24", "tabulated", "two-points")


def test_without_the_record_the_file_is_refused_naming_the_form(tmp_path):
    F.register(DUMMY)
    try:
        path = law(TwoPoints((10e6, 700e6), (0.02, 0.9))).to_json(tmp_path / "p.json")
    finally:
        F.unregister(F.FIRST_LOADING, DUMMY.name)
    with pytest.raises(ValueError, match="first_loading_law.form must be one of eq24, tabulated"):
        FrictionParams.from_json(path)


# -- the calibration side: the same dummy form fitted, chosen and written ---------------------


class TwoPointsFit:
    """The dummy form's fit: the lowest and the top computed point."""

    success = True
    at_bound = ()

    def __init__(self, p, alpha, H):
        i, j = int(np.argmin(p)), int(np.argmax(p))
        self.data = TwoPoints((float(p[i]), float(p[j])), (float(alpha[i]), float(alpha[j])))
        law = FrictionParams(
            m=1.0, sigma_y=H, H=H, C1=1.0, n1=1.0, C2=1.0, n2=1.0,
            first_loading_form="two-points", first_loading_table=self.data,
        )  # fmt: skip
        self.residuals = alpha_first(p, law) - alpha

    def summary(self):
        return {"form": "two-points", "p": list(self.data.p), "alpha": list(self.data.alpha)}


@pytest.fixture
def calibrated_dummy(dummy):
    from halfspace_calib.pipeline.law import forms as CF
    from halfspace_calib.pipeline.law import heldout as HO

    def predict(fit, p, ctx):
        return alpha_first(p, law(fit.data).replace(H=ctx.H, sigma_y=ctx.H / 2.8))

    def heldout(p, alpha, fit, ctx):
        def refit_predict(keep, p_out):
            return predict(TwoPointsFit(p[keep], alpha[keep], ctx.H), p_out, ctx)

        return HO.level_errors(p, alpha, fit.residuals, refit_predict, "two-points")

    rec = CF.FormCalibration(
        "two-points",
        F.FIRST_LOADING,
        fit=lambda p, alpha, ctx: TwoPointsFit(p, alpha, ctx.H),
        predict=predict,
        heldout=heldout,
        runtime=lambda fit: fit.data,
        candidate=False,
    )
    CF.register(rec)
    yield rec
    CF.unregister(F.FIRST_LOADING, "two-points")


def test_a_registered_form_is_calibrated_written_and_run(calibrated_dummy, tmp_path):
    from halfspace_calib.pipeline.calibration import Scene, calibrate

    scene = Scene(
        grid=16,
        pressures=(20e6, 100e6, 300e6, 600e6),
        reload_fractions=(0.25, 0.5, 0.8),
        first_loading_form="two-points",
        heldout_tol=0.5,  # a power law through two points: what is tested is the plumbing
    )
    cal = calibrate(scene, progress=False)
    P = cal.params
    assert cal.first_loading_form == P.first_loading_form == "two-points"
    p, a = cal.sweeps.loading
    data = P.first_loading_table
    assert data.p == (20e6, 600e6) and data.alpha == (a[0], a[-1])
    # the reload forms were fitted on the dummy form's alpha1(p_hist)
    assert cal.reload.first == ("two-points", data)
    assert "first_loading_eq24" in cal.errors and cal.errors["first_loading"].form == "two-points"
    Q = FrictionParams.from_json(P.to_json(tmp_path / "params.json"))
    assert Q == P and Q.first_loading_table == data
    s = data.exponent()
    np.testing.assert_allclose(
        alpha_first(np.array([50e6, 300e6]), Q),
        a[0] * (np.array([50e6, 300e6]) / 20e6) ** s,
        rtol=1e-12,
    )
    assert Q.mu_eff == pytest.approx(Q.tau_max * a[0] / 20e6, rel=1e-12)
    # every report names it, with the errors the calibration measured, Eq. 24 beside it
    first = describe_law(Q).branch("first_loading")
    assert first.running.form == "two-points" and first.others[0].form == "eq24"
    held = {
        k: cal.errors[k].summary()["heldout_max"] for k in ("first_loading", "first_loading_eq24")
    }
    assert first.running.errors.heldout_max == held["first_loading"]
    assert first.others[0].errors.heldout_max == held["first_loading_eq24"]
    assert cal.summary()["law"]["forms"].startswith("a two-point power law + ")


def test_a_scene_takes_only_registered_forms(calibrated_dummy):
    from halfspace_calib.pipeline.calibration import Scene

    assert Scene(grid=16, first_loading_form="two-points").first_loading_form == "two-points"
    with pytest.raises(ValueError, match="first_loading_form must be one of auto, eq24, tabulated"):
        Scene(grid=16, first_loading_form="spline")
