"""The files a scientific Python package ships beside its code: licence, citation, changelog."""

import re
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))


def test_license_text_matches_the_declared_licence():
    declared = PYPROJECT["project"]["license"]["text"]
    assert declared == "BSD-3-Clause"
    text = (ROOT / "LICENSE").read_text(encoding="utf-8")
    assert text.startswith("BSD 3-Clause License")
    # the three conditions and the disclaimer of the BSD-3-Clause text
    for phrase in (
        "Redistributions of source code must retain the above copyright notice",
        "Redistributions in binary form must reproduce the above copyright notice",
        "Neither the name of the copyright holder nor the names of its",
        'THIS SOFTWARE IS PROVIDED BY THE COPYRIGHT HOLDERS AND CONTRIBUTORS "AS IS"',
    ):
        assert phrase in text


def test_citation_file_is_valid_cff_and_cites_the_paper():
    cffconvert = pytest.importorskip("cffconvert")
    text = (ROOT / "CITATION.cff").read_text(encoding="utf-8")
    citation = cffconvert.Citation(text)
    citation.validate()  # raises on a schema violation (CFF 1.2.0)
    cff = citation.cffobj
    assert cff["version"] == PYPROJECT["project"]["version"]
    assert cff["license"] == PYPROJECT["project"]["license"]["text"]
    paper = cff["preferred-citation"]
    assert paper["journal"] == "Tribology in Industry"
    assert (paper["volume"], paper["issue"], paper["year"]) == (37, 4, 2015)
    assert (paper["start"], paper["end"]) == (400, 412)
    assert paper["title"].startswith("Development of a Constitutive Friction Law")


def test_changelog_follows_keep_a_changelog_and_knows_the_version():
    text = (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")
    assert "keepachangelog.com" in text
    assert "## [Unreleased]" in text
    assert "## Version policy" in text
    versions = re.findall(r"^## \[(\d+\.\d+\.\d+)\]", text, flags=re.M)
    assert PYPROJECT["project"]["version"] in versions
