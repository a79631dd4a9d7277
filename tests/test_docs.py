"""The documentation site's sources: every public name has its API entry, every page is in a toctree.

The site itself is built with ``python -m sphinx -W -b html docs OUT`` in ``.ci/run`` (warnings are
errors; the gallery under ``examples/`` is executed during the build).
"""

import re
from pathlib import Path

import pytest

import fe_demo
import frictionlaw
import frictionlaw.export
import frictionlaw.export.harness
import halfspace_calib
import sbmf_cli

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"


def _autosummary_entries(text):
    """``{module: set of names}`` from the ``currentmodule`` + ``autosummary`` blocks of api.rst."""
    entries, module = {}, None
    for line in text.splitlines():
        m = re.match(r"\.\. currentmodule:: (\S+)", line)
        if m:
            module = m.group(1)
            continue
        m = re.match(r"   ([A-Za-z_][A-Za-z0-9_]*)$", line)
        if m and module:
            entries.setdefault(module, set()).add(m.group(1))
    return entries


@pytest.mark.parametrize(
    "module",
    [
        frictionlaw,
        frictionlaw.export,
        frictionlaw.export.harness,
        halfspace_calib,
        fe_demo,
        sbmf_cli,
    ],
    ids=lambda m: m.__name__,
)
def test_api_reference_lists_the_public_surface(module):
    text = (DOCS / "api.rst").read_text(encoding="utf-8")
    listed = _autosummary_entries(text).get(module.__name__, set())
    # constants are named in the page's prose rather than given an autosummary entry
    missing = [
        n for n in module.__all__ if n not in listed and not re.search(rf"``{re.escape(n)}``", text)
    ]
    assert not missing, f"docs/api.rst lacks {missing} of {module.__name__}.__all__"
    stale = sorted(listed - set(module.__all__))
    assert not stale, f"docs/api.rst lists {stale}, not in {module.__name__}.__all__"


def test_every_markdown_page_is_in_a_toctree():
    index = (DOCS / "index.md").read_text(encoding="utf-8")
    pages = sorted(p.stem for p in DOCS.glob("*.md") if p.stem != "index")
    absent = [p for p in pages if not re.search(rf"^{re.escape(p)}$", index, flags=re.M)]
    assert not absent, f"docs/index.md toctrees miss {absent}"


def test_gallery_examples_are_executed_and_exist():
    conf = (DOCS / "conf.py").read_text(encoding="utf-8")
    assert '"filename_pattern": r"/plot_"' in conf and '"abort_on_example_error": True' in conf
    examples = sorted(p.name for p in (ROOT / "examples").glob("plot_*.py"))
    for needed in (
        "plot_calibrate_real_file.py",
        "plot_law_history.py",
        "plot_export_abaqus.py",
        "plot_band_from_patches.py",
        "plot_ring_fit.py",
        "plot_flattening.py",
    ):
        assert needed in examples


def _summary(doc):
    """The first sentence of a docstring as ``sphinx.ext.autosummary`` takes it for the table.

    Its rule: the first paragraph is split at every period followed by white space (so "Eq. 24"
    ends a sentence after "Eq."), unless the piece ends with e.g., i.e. or et al.
    """
    stanza = []
    for line in (doc or "").splitlines():
        if not line.strip():
            if stanza:
                break
            continue
        stanza.append(line.strip())
    pieces = re.split(r"\.(?:\s+)", " ".join(stanza))
    for i in range(len(pieces)):
        summary = ". ".join(pieces[: i + 1]).rstrip(".") + "."
        if not summary.endswith(("et al.", "e.g.", "i.e.")):
            return summary
    return ""


def test_api_summaries_are_whole_first_sentences():
    """No summary in the API tables ends at an abbreviation (18 of 59 ended at Eq./Eqs./Figs.)."""
    import importlib
    import inspect

    module, cut = None, []
    for line in (DOCS / "api.rst").read_text(encoding="utf-8").splitlines():
        m = re.match(r"\.\. currentmodule:: (\S+)", line)
        if m:
            module = importlib.import_module(m.group(1))
            continue
        m = re.match(r"   ([A-Za-z_][\w.]*)$", line)
        if m and module:
            obj = module
            for part in m.group(1).split("."):
                obj = getattr(obj, part)
            summary = _summary(inspect.getdoc(obj))
            assert summary, f"{m.group(1)} has no docstring"
            if re.search(r"\b(Eqs?|Figs?|Secs?|Tab|Ref|No|al)\.$", summary):
                cut.append(f"{module.__name__}.{m.group(1)}: {summary}")
    assert cut == []


def test_the_api_reference_has_the_readme_and_gallery_entries():
    """The README's law(p, p_hist), the export and the ring fit used in the gallery."""
    text = (DOCS / "api.rst").read_text(encoding="utf-8")
    entries = _autosummary_entries(text)
    assert "SBMFLaw.__call__" in text
    assert {"export", "render"} <= entries.get("frictionlaw.export", set())
    assert {"fit_m", "read_ring_tests"} <= entries.get("fe_demo.analysis.ringfit", set())
