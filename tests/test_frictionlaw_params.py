import json
import math
import re

import numpy as np
import pytest

from frictionlaw import FrictionParams

BASE = dict(m=0.5, sigma_y=300e6, H=800e6, C1=1.2, n1=2.0, C2=3.0, n2=1.5)


def test_k_defaults_to_half_sigma_y_and_derived_values():
    p = FrictionParams(**BASE)
    assert p.k == 150e6
    assert p.tau_max == 0.5 * 150e6
    assert p.mu_eff == pytest.approx(0.5 * 150e6 * 1.2 / 800e6, rel=1e-15)
    assert FrictionParams(**BASE, k=300e6 / math.sqrt(3)).k == pytest.approx(173.2050807568877e6)


@pytest.mark.parametrize(
    "field, value, fragment",
    [
        ("m", -0.1, "m must be in [0, 1]"),
        ("m", 1.5, "m must be in [0, 1]"),
        ("sigma_y", 0.0, "sigma_y must be in [1000, 1e+13]"),
        ("H", -1.0, "H must be in [1000, 1e+13]"),
        ("H", math.inf, "H must be in [1000, 1e+13]"),
        ("C1", 0.0, "C1 must be in [1e-06, 1e+06]"),
        ("C2", math.nan, "C2 must be in [1e-06, 1e+06]"),
        ("n1", 0.0, "n1 must be in [0.001, 1e+06]"),
        ("n2", 2e6, "n2 must be in [0.001, 1e+06]"),
        ("k", -5.0, "k must be in [100, 1e+13]"),
        ("m", "abc", "m must be a real number"),
    ],
)
def test_bad_values_name_the_field_and_range(field, value, fragment):
    kw = dict(BASE)
    kw[field] = value
    with pytest.raises(ValueError) as exc:
        FrictionParams(**kw)
    assert fragment in str(exc.value)


def test_frozen_and_replace_revalidates():
    p = FrictionParams(**BASE)
    with pytest.raises(AttributeError):
        p.m = 0.3
    assert p.replace(m=0.2).m == 0.2
    with pytest.raises(ValueError, match="m must be in"):
        p.replace(m=2.0)


def test_json_round_trip_with_provenance(tmp_path):
    p = FrictionParams(**BASE, continuous_reload=True, provenance={"grid": [128, 128], "R2": 0.998})
    path = p.to_json(tmp_path / "sub" / "params.json")
    q = FrictionParams.from_json(path)
    assert q == p
    assert q.continuous_reload is True
    assert q.provenance == {"grid": [128, 128], "R2": 0.998}
    doc = json.loads(path.read_text())
    assert doc["format"] == "sbmf-friction-params" and doc["version"] == 1
    assert doc["units"]["H"] == "Pa" and doc["units"]["m"] == "1"
    # atomic write leaves no temporary files behind
    assert sorted(x.name for x in path.parent.iterdir()) == ["params.json"]


def test_malformed_files_raise_clear_errors(tmp_path):
    p = FrictionParams(**BASE)
    good = p.to_dict()
    f = tmp_path / "x.json"
    f.write_text("{not json")
    with pytest.raises(ValueError, match="not valid JSON"):
        FrictionParams.from_json(f)
    for mutate, msg in [
        (lambda d: d.update(version=4), "unsupported version 4"),
        (lambda d: d.update(version=3.0), "unsupported version 3.0"),
        (lambda d: d.update(format="other"), "'format' must be"),
        (lambda d: d["parameters"].pop("C2"), "missing parameters"),
        (lambda d: d["units"].update(H="MPa"), "H must be given in 'Pa'"),
        (lambda d: d["parameters"].update(bogus=1.0), "unknown parameters"),
        (lambda d: d["parameters"].update(n1=-1.0), "n1 must be in"),
        # JSON numbers only: a quoted number or a boolean is refused, not converted
        (lambda d: d["parameters"].update(H="8e8"), "H must be a real number in .*got '8e8'"),
        (lambda d: d["parameters"].update(m=True), "m must be a real number in .*got True"),
        (
            lambda d: d.update(calibrated_range={"p_min": "1e8", "p_max": 6e8}),
            "calibrated_range: p_range must be",
        ),
    ]:
        d = json.loads(json.dumps(good))
        mutate(d)
        f.write_text(json.dumps(d))
        with pytest.raises(ValueError, match=msg):
            FrictionParams.from_json(f)


def test_eq26_geometric_share_scales_the_law_and_round_trips(tmp_path):
    import numpy as np

    from frictionlaw import shear_limit

    p0 = FrictionParams(**BASE)
    p1 = FrictionParams(**BASE, geo_ratio=0.08)
    assert p1.tau_max == pytest.approx(1.08 * p0.tau_max, rel=1e-15)
    assert p1.mu_eff == pytest.approx(1.08 * p0.mu_eff, rel=1e-15)
    p = np.linspace(0, 2e9, 41)
    for p_hist in (0.0, 5e8):
        np.testing.assert_allclose(
            shear_limit(p, p_hist, p1), 1.08 * shear_limit(p, p_hist, p0), rtol=1e-14
        )
    assert FrictionParams.from_json(p1.to_json(tmp_path / "g.json")).geo_ratio == 0.08
    d = p0.to_dict()
    d["parameters"].pop("geo_ratio")  # files without the term read as Eqs. 24-25 alone
    assert FrictionParams.from_dict(d).geo_ratio == 0.0
    with pytest.raises(ValueError, match=r"geo_ratio must be in \[0, 10\]"):
        FrictionParams(**BASE, geo_ratio=-0.1)


def test_tangential_stiffness_table_interpolates_log_log_and_round_trips(tmp_path):
    from frictionlaw import TangentialStiffness

    k = TangentialStiffness(p=[1e8, 4e8], k_t=[1e14, 1.6e15])  # k_t ~ p^2 between the points
    np.testing.assert_allclose(k([2e8, 1e8, 4e8]), [4e14, 1e14, 1.6e15], rtol=1e-12)
    # held constant beyond the calibrated points, p <= 0 included (no power-law extrapolation)
    np.testing.assert_array_equal(k([-1.0, 0.0, 1e3, 1e12]), [1e14, 1e14, 1e14, 1.6e15])
    P = FrictionParams(**BASE, p_range=(1e8, 6e8), k_t=k)
    f = tmp_path / "p.json"
    P.to_json(f)
    doc = json.loads(f.read_text())
    assert doc["calibrated_range"] == {"p_min": 1e8, "p_max": 6e8, "unit": "Pa"}
    assert doc["tangential_stiffness"]["units"] == {"p": "Pa", "k_t": "Pa/m"}
    Q = FrictionParams.from_json(f)
    assert Q == P and Q.k_t == k and Q.p_range == (1e8, 6e8)
    # files without the optional entries still read (version 1 unchanged)
    plain = FrictionParams(**BASE)
    assert (
        plain.to_dict().keys() >= {"parameters"} and "tangential_stiffness" not in plain.to_dict()
    )


@pytest.mark.parametrize(
    "kw, fragment",
    [
        (dict(p=[2e8, 1e8], k_t=[1.0, 2.0]), "strictly increasing"),
        (dict(p=[1e8], k_t=[1.0, 2.0]), "need equal"),
        (dict(p=[1e8], k_t=[0.0]), "k_t table k_t must hold finite values in (0, inf)"),
        (dict(p=[], k_t=[]), "non-empty"),
    ],
)
def test_tangential_stiffness_refuses_bad_tables(kw, fragment):
    from frictionlaw import TangentialStiffness

    with pytest.raises(ValueError, match=re.escape(fragment)):
        TangentialStiffness(**kw)


def test_p_range_and_k_t_validation():
    with pytest.raises(ValueError, match=r"p_range must satisfy 0 < p_min <= p_max"):
        FrictionParams(**BASE, p_range=(6e8, 1e8))
    with pytest.raises(ValueError, match="k_t must be a TangentialStiffness"):
        FrictionParams(**BASE, k_t=[1.0])
    doc = FrictionParams(**BASE, p_range=(1e8, 6e8)).to_dict()
    doc["calibrated_range"] = {"p_min": 1e8}
    with pytest.raises(ValueError, match="calibrated_range is missing 'p_max'"):
        FrictionParams.from_dict(doc)


@pytest.mark.parametrize("ratio", [0.5, 1 / math.sqrt(3), 2 / 3])
def test_k_between_tresca_and_twin_shear_is_accepted(ratio):
    # Tresca, von Mises and twin shear (the band's ends are exact, up to file rounding)
    assert FrictionParams(**BASE, k=ratio * 300e6).k == ratio * 300e6
    assert FrictionParams(**BASE, k=0.5 * 300e6 * (1 - 1e-12)).k < 150e6


@pytest.mark.parametrize("k", [1e3, 0.49 * 300e6, 0.67 * 300e6, 1e12])
def test_k_disagreeing_with_sigma_y_is_refused_naming_both(k):
    with pytest.raises(ValueError) as exc:
        FrictionParams(**BASE, k=k)
    msg = str(exc.value)
    assert f"k = {k:g} Pa disagrees with sigma_y = 3e+08 Pa" in msg
    assert "allowed [0.5, 0.6667]" in msg and "leave k out for sigma_y/2" in msg


def test_k_of_one_pascal_is_refused_by_the_validated_range():
    with pytest.raises(ValueError, match=r"k must be in \[100, 1e\+13\], got 1.0"):
        FrictionParams(**BASE, k=1.0)


def test_editing_sigma_y_in_a_file_without_k_is_not_silent(tmp_path):
    """k is written to the file; a sigma_y changed by hand no longer passes unnoticed."""
    f = tmp_path / "p.json"
    FrictionParams(**BASE).to_json(f)
    doc = json.loads(f.read_text())
    assert doc["parameters"]["k"] == 150e6
    doc["parameters"]["sigma_y"] = 400e6  # k / sigma_y = 0.375
    with pytest.raises(ValueError, match=r"k = 1.5e\+08 Pa disagrees with sigma_y = 4e\+08 Pa"):
        FrictionParams.from_dict(doc)
    # leaving k out makes it follow sigma_y
    del doc["parameters"]["k"]
    assert FrictionParams.from_dict(doc).k == 200e6
