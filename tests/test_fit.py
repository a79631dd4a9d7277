import json

import numpy as np
import pytest

from frictionlaw import FrictionParams, alpha_first, alpha_reload, shear_limit
from halfspace_calib import topography as S
from halfspace_calib.pipeline.law import fit as F
from halfspace_calib.pipeline.law.params import make_params

H = 800e6
TRUE = FrictionParams(m=0.5, sigma_y=H / 2.8, H=H, C1=1.6, n1=2.5, C2=2.4, n2=1.8)
P = np.array([10, 25, 50, 100, 200, 300, 400, 500, 600]) * 1e6
P_HIST = np.arange(100, 601, 100) * 1e6
FRACS = np.array([0.1, 0.25, 0.5, 0.75, 0.9])


def g(x, n):
    """Independent NumPy oracle of the smooth minimum tanh(x**n)**(1/n)."""
    return np.tanh(x**n) ** (1 / n)


def reload_curves(law, noise=0.0, rng=None):
    out = []
    for ph in P_HIST:
        p = ph * FRACS
        a = alpha_reload(p, ph, law)
        if noise:
            a = a * (1 + noise * rng.standard_normal(a.size))
        out.append((ph, p, a))
    return out


def test_model_matches_oracle():
    # the fit evaluates the law through frictionlaw; check that against the plain formula
    x1 = P * TRUE.C1 / H
    np.testing.assert_allclose(alpha_first(P, TRUE), g(x1, TRUE.n1), rtol=1e-12)


def test_exact_first_loading_recovers_parameters():
    r = F.fit_first_loading(P, alpha_first(P, TRUE), H)
    assert r.success and r.converged
    assert r.C1 == pytest.approx(TRUE.C1, rel=1e-6)
    assert r.n1 == pytest.approx(TRUE.n1, rel=1e-6)
    assert r.r_squared == pytest.approx(1.0, abs=1e-12)
    assert r.rmse < 1e-10 and r.at_bound == ()


@pytest.mark.parametrize("continuous", [False, True])
def test_exact_reload_recovers_parameters(continuous):
    law = TRUE.replace(continuous_reload=continuous)
    r = F.fit_reload(reload_curves(law), H, TRUE.C1, TRUE.n1, continuous=continuous)
    assert r.success
    assert r.C2 == pytest.approx(TRUE.C2, rel=1e-6)
    assert r.n2 == pytest.approx(TRUE.n2, rel=1e-6)
    assert r.r_squared == pytest.approx(1.0, abs=1e-12)
    assert r.continuous is continuous


def _noisy_first_fits(noise, relative, n=20, seed=42):
    a = alpha_first(P, TRUE)
    rng = np.random.default_rng(seed)
    est, err = [], []
    for _ in range(n):
        e = noise * rng.standard_normal(a.size)
        data = a * (1 + e) if relative else np.clip(a + e, 0, 1)
        r = F.fit_first_loading(P, data, H, relative=relative)
        assert r.success
        est.append([r.C1, r.n1])
        err.append([r.stderr["C1"], r.stderr["n1"]])
    return np.array(est), np.array(err)


@pytest.mark.parametrize("relative", [True, False])
def test_noisy_first_loading_is_unbiased_with_honest_errors(relative):
    # 1 % noise on alpha (relative: alpha (1 + 0.01 N), fitted with relative=True;
    # absolute: alpha + 0.01 N, the default fit), 20 seeded realisations. Asymptotic
    # theory: unbiased to O(noise^2), scatter equal to the reported standard error
    # (averaged: a single stderr rests on 7 degrees of freedom), every error within 5 of
    # them (a normal 5-sigma event has probability 6e-7).
    est, err = _noisy_first_fits(0.01, relative)
    truth = np.array([TRUE.C1, TRUE.n1])
    scatter = est.std(axis=0, ddof=1)
    assert np.all(np.abs(est.mean(axis=0) - truth) < 3 * scatter / np.sqrt(len(est)))
    assert np.all((scatter > 0.5 * err.mean(axis=0)) & (scatter < 2 * err.mean(axis=0)))
    assert np.all(np.abs(est - truth) < 5 * err.mean(axis=0))


def test_noisy_first_loading_plain_tolerance():
    # 1 % relative noise: the measured scatter (200 seeds) is 0.46 % on C1, the Coulomb
    # slope fixed by the low-pressure points, and 6.7 % on n1, the corner sharpness fixed
    # by the few points near p C1 / H ~ 1. Tolerances are about 5 times that.
    est, _ = _noisy_first_fits(0.01, True)
    assert np.all(np.abs(est[:, 0] / TRUE.C1 - 1) < 0.03)
    assert np.all(np.abs(est[:, 1] / TRUE.n1 - 1) < 0.35)


@pytest.mark.parametrize("continuous", [False, True])
def test_noisy_reload_recovers_parameters(continuous):
    # 1 % relative noise on 6 curves x 5 points, relative fit; every realisation within
    # 5 reported standard errors, and in plain numbers C2 to 3 %, n2 to 20 %
    law = TRUE.replace(continuous_reload=continuous)
    rng = np.random.default_rng(7)
    est = []
    for _ in range(10):
        curves = reload_curves(law, 0.01, rng)
        r = F.fit_reload(curves, H, TRUE.C1, TRUE.n1, continuous=continuous, relative=True)
        assert r.success and r.r_squared > 0.999
        assert abs(r.C2 - TRUE.C2) < 5 * r.stderr["C2"]
        assert abs(r.n2 - TRUE.n2) < 5 * r.stderr["n2"]
        est.append([r.C2, r.n2])
    est = np.array(est)
    assert np.all(np.abs(est[:, 0] / TRUE.C2 - 1) < 0.03)
    assert np.all(np.abs(est[:, 1] / TRUE.n2 - 1) < 0.2)


def test_relative_fit_needs_positive_alpha():
    a = alpha_first(P, TRUE)
    a[0] = 0.0
    with pytest.raises(ValueError, match="relative"):
        F.fit_first_loading(P, a, H, relative=True)


def test_residuals_and_r_squared_are_what_they_say():
    rng = np.random.default_rng(3)
    a = np.clip(alpha_first(P, TRUE) * (1 + 0.02 * rng.standard_normal(P.size)), 0, 1)
    r = F.fit_first_loading(P, a, H)
    model = g(P * r.C1 / H, r.n1)
    np.testing.assert_allclose(r.residuals, model - a, rtol=1e-10, atol=1e-14)
    r2 = 1 - np.sum((model - a) ** 2) / np.sum((a - a.mean()) ** 2)
    assert r.r_squared == pytest.approx(r2, rel=1e-10)
    assert r.rmse == pytest.approx(np.sqrt(np.mean((model - a) ** 2)), rel=1e-10)
    # a least-squares optimum: no small step in C1 or n1 lowers the residual
    ss = np.sum(r.residuals**2)
    for dc, dn in [(1e-4, 0), (-1e-4, 0), (0, 1e-4), (0, -1e-4)]:
        other = g(P * r.C1 * (1 + dc) / H, r.n1 * (1 + dn)) - a
        assert np.sum(other**2) >= ss * (1 - 1e-12)


def test_reload_jump_against_oracle():
    r = F.fit_reload(reload_curves(TRUE), H, TRUE.C1, TRUE.n1)
    a1 = g(P_HIST * TRUE.C1 / H, TRUE.n1)
    x2h = P_HIST * r.C2 / (H * a1)
    jump = a1 - a1 * g(x2h, r.n2)
    np.testing.assert_allclose(r.jump, jump, rtol=1e-9)
    np.testing.assert_allclose(r.jump_relative, 1 - g(x2h, r.n2), rtol=1e-9)
    assert np.all(r.jump > 0)
    # the shear of the runtime drops by m k * jump just below p_hist
    ph = P_HIST[2]
    law = TRUE.replace(C2=r.C2, n2=r.n2)
    drop = shear_limit(ph, ph, law) - shear_limit(ph * (1 - 1e-9), ph, law)
    assert drop == pytest.approx(TRUE.tau_max * r.jump[2], rel=1e-6)


def test_continuous_fit_has_no_jump_and_costs_residual():
    curves = reload_curves(TRUE)  # data from the paper's (jumping) form
    free = F.fit_reload(curves, H, TRUE.C1, TRUE.n1)
    cont = F.fit_reload(curves, H, TRUE.C1, TRUE.n1, continuous=True)
    assert np.all(np.abs(cont.jump) < 1e-12)
    assert cont.rmse > free.rmse  # the constraint is not free on jumping data
    assert cont.summary()["continuous"] is True


def test_parameter_on_bound_is_reported():
    sharp = TRUE.replace(n1=200.0)
    r = F.fit_first_loading(P, alpha_first(P, sharp), H)
    assert r.n1 == pytest.approx(F.N_BOUNDS[1], rel=1e-6)
    assert "n1" in r.at_bound and "bound" in r.message
    r = F.fit_first_loading(P, alpha_first(P, TRUE), H, n_bounds=(0.2, 2.0))
    assert r.n1 == pytest.approx(2.0, rel=1e-6) and r.at_bound == ("n1",)


@pytest.mark.parametrize(
    "args, word",
    [
        ((P, alpha_first(P, TRUE)[:-1], H), "alpha must have the same length as p"),
        ((np.where(P == P[3], np.nan, P), alpha_first(P, TRUE), H), "p must be finite"),
        ((P, np.where(P == P[3], np.nan, 0.5), H), "alpha must be finite"),
        ((P - 20e6, np.full(P.size, 0.5), H), r"p must be > 0"),
        ((P, np.linspace(0.1, 1.2, P.size), H), r"alpha must be in \[0, 1\]"),
        ((P, np.linspace(-0.1, 0.9, P.size), H), r"alpha must be in \[0, 1\]"),
        ((P, alpha_first(P, TRUE), 0.0), "H"),
        ((P[:2], alpha_first(P[:2], TRUE), H), "at least 3"),
        ((P.reshape(3, 3), alpha_first(P, TRUE).reshape(3, 3), H), "1-D"),
    ],
)
def test_first_loading_bad_input(args, word):
    with pytest.raises(ValueError, match=word):
        F.fit_first_loading(*args)


def test_bad_bounds():
    a = alpha_first(P, TRUE)
    with pytest.raises(ValueError, match="C_bounds"):
        F.fit_first_loading(P, a, H, C_bounds=(0.0, 10.0))
    with pytest.raises(ValueError, match="n_bounds"):
        F.fit_first_loading(P, a, H, n_bounds=(5.0, 1.0))


def test_reload_bad_input():
    good = reload_curves(TRUE)
    bad = list(good)
    bad[1] = (good[1][0], good[1][1] * 3, good[1][2])
    with pytest.raises(ValueError, match=r"curves\[1\]\.p must be < p_hist"):
        F.fit_reload(bad, H, 1.6, 2.5)
    bad[1] = (good[1][0], good[1][1], good[1][2][:-1])
    with pytest.raises(ValueError, match=r"curves\[1\]\.alpha must have the same length"):
        F.fit_reload(bad, H, 1.6, 2.5)
    bad[1] = {"p_hist": -1.0, "p": good[1][1], "alpha": good[1][2]}
    with pytest.raises(ValueError, match=r"curves\[1\]\.p_hist"):
        F.fit_reload(bad, H, 1.6, 2.5)
    bad[1] = {"p": good[1][1]}
    with pytest.raises(ValueError, match=r"curves\[1\] lacks key"):
        F.fit_reload(bad, H, 1.6, 2.5)
    with pytest.raises(ValueError, match="at least one"):
        F.fit_reload([], H, 1.6, 2.5)
    with pytest.raises(ValueError, match="C1"):
        F.fit_reload(good, H, -1.6, 2.5)
    # dicts and ReloadCurve objects are accepted and give the same fit
    as_objs = [F.ReloadCurve(*c) for c in good]
    as_dicts = [{"p_hist": c[0], "p": c[1], "alpha": c[2]} for c in good]
    a = F.fit_reload(as_objs, H, 1.6, 2.5)
    b = F.fit_reload(as_dicts, H, 1.6, 2.5)
    assert a.params == b.params


def test_make_params_file_roundtrip(tmp_path):
    first = F.fit_first_loading(P, alpha_first(P, TRUE), H)
    rel = F.fit_reload(reload_curves(TRUE), H, first.C1, first.n1)
    wp = S.dc04_edt_like(32)
    params = make_params(
        first,
        rel,
        m=0.5,
        sigma_y=H / 2.8,
        surfaces={"workpiece": wp, "tool": {"source": "file", "sha256": "ab" * 32}},
        grid={"shape": [32, 32], "size": [S.PAPER_SIZE] * 2},
        tolerance=1e-8,
        pressures={"loading": P, "p_hist": P_HIST},
        material={"E": 210e9, "nu": 0.3, "H": H},
    )
    assert (params.C1, params.n1, params.C2, params.n2) == (first.C1, first.n1, rel.C2, rel.n2)
    assert params.H == H and not params.continuous_reload
    path = params.to_json(tmp_path / "params.json")
    back = FrictionParams.from_json(path)
    assert back == params
    prov = back.provenance
    assert prov["surfaces"]["workpiece"]["seed"] == 1
    assert prov["surfaces"]["workpiece"]["roughness"]["Rq"] == pytest.approx(1.267e-6, rel=1e-12)
    assert prov["pressures"]["loading"][0] == 10e6
    assert prov["fit"]["first_loading"]["r_squared"] == pytest.approx(1.0, abs=1e-12)
    assert len(prov["fit"]["reload"]["jump"]) == P_HIST.size
    # the file says which numbers are inputs: m is measured, not fitted from roughness
    assert prov["inputs"]["m"].startswith("input, not fitted")
    assert prov["inputs"]["k"].startswith("derived: sigma_y / 2")
    assert "calibrated_range" not in prov["inputs"]  # no p_range given here
    json.dumps(prov)  # plain JSON types throughout


def test_make_params_checks():
    first = F.fit_first_loading(P, alpha_first(P, TRUE), H)
    rel = F.fit_reload(reload_curves(TRUE), H, first.C1, first.n1, continuous=True)
    assert make_params(first, rel, m=0.5, sigma_y=3e8).continuous_reload
    other = F.fit_reload(reload_curves(TRUE), H, 1.0, 1.0)
    with pytest.raises(ValueError, match="refit"):
        make_params(first, other, m=0.5, sigma_y=3e8)
    with pytest.raises(ValueError, match="H"):
        make_params(first, rel, m=0.5, sigma_y=3e8, H=900e6)
    with pytest.raises(ValueError, match="m must be in"):
        make_params(first, rel, m=1.5, sigma_y=3e8)
    with pytest.raises(ValueError, match="material"):
        make_params(first, rel, m=0.5, sigma_y=3e8, material={"E": object()})
