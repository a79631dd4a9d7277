import json
import math

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
        (lambda d: d.update(version=2), "unsupported version 2"),
        (lambda d: d.update(format="other"), "'format' must be"),
        (lambda d: d["parameters"].pop("C2"), "missing parameters"),
        (lambda d: d["units"].update(H="MPa"), "H must be given in 'Pa'"),
        (lambda d: d["parameters"].update(bogus=1.0), "unknown parameters"),
        (lambda d: d["parameters"].update(n1=-1.0), "n1 must be in"),
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
