"""The layering of the distribution (docs/architecture.md), read from the source with ``ast``.

Every import of the project's own modules (module level and inside functions) is an edge. The
tests fail on an import circle, on a package importing one it may not, on a lower layer of
``halfspace_calib`` or ``fe_demo`` importing a higher one, and on a module over 600 lines.
"""

import ast
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
#: the distribution's packages, and the coupling scripts beside them
PACKAGES = ("sbmf_cli", "frictionlaw", "halfspace_calib", "fe_demo", "couplings")
ROOT = REPO / "halfspace_calib"
PKG = "halfspace_calib"

#: what each package may import of the others: sbmf_cli is the bottom floor (standard library
#: only), the runtime law imports nothing of the project (its commands: the command layer)
PACKAGE_ALLOWED = {
    "sbmf_cli": set(),
    "frictionlaw": {"sbmf_cli"},
    "halfspace_calib": {"sbmf_cli", "frictionlaw"},
    "fe_demo": {"sbmf_cli", "frictionlaw"},
    "couplings": {"sbmf_cli", "frictionlaw", "fe_demo"},
}
#: the modules of frictionlaw that may import the command layer: its two commands (the export's
#: library function ``export`` writes through ``sbmf_cli.OutputFolder`` too)
FRICTIONLAW_COMMANDS = ("frictionlaw.__main__", "frictionlaw.export")

#: what each part of halfspace_calib may import of the package (besides itself)
ALLOWED = {
    "common": set(),
    "contact": {"common"},
    "topography": {"common"},
    "studies": {"common", "contact", "topography"},
    "output": {"common", "contact", "topography", "studies"},
    "pipeline": {"common", "contact", "topography", "studies", "output"},
    "cli": {"common", "contact", "topography", "studies", "pipeline", "output"},
    "__main__": {"cli"},
    "__init__": {"common", "contact", "topography", "studies", "pipeline", "output"},
}


#: what each part of halfspace_calib.pipeline may import of it (besides itself), bottom to top
#: (issue 39): the law's forms and their acceptance, the scene with its levels and sweeps, the
#: calibration, several samples and their band
PIPELINE = "halfspace_calib.pipeline"
PIPELINE_ALLOWED = {
    "law": set(),
    "sweep": {"law"},
    "calibration": {"law", "sweep"},
    "band": {"law", "sweep", "calibration"},
    "__init__": {"law", "sweep", "calibration"},
}


#: what each part of fe_demo may import of the package (besides itself), bottom to top
FE_ALLOWED = {
    "solver": set(),
    "asperity": {"solver"},
    "output": {"solver"},
    "scenes": {"solver", "output"},
    "analysis": {"solver", "output", "scenes"},
    "cli": {"solver", "output", "scenes", "analysis"},
    "__main__": {"cli"},
    "__init__": {"solver", "scenes"},
}
#: the layered packages and their rules
LAYERS = {PKG: ALLOWED, "fe_demo": FE_ALLOWED}

#: modules over the 600-line rule, each with the work that brings it under
#: modules allowed over 600 lines, each with the reason (none since issue 34 step 1)
LONG_EXEMPT: dict = {}


def _modules():
    """``{dotted name: path}`` of every module of the project's packages."""
    out = {}
    for pkg in PACKAGES:
        for path in (REPO / pkg).rglob("*.py"):
            parts = list(path.relative_to(REPO).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts = parts[:-1]
            out[".".join(parts)] = path
    return out


def _is_package(name, modules):
    return modules[name].name == "__init__.py"


def _imports(name, modules):
    """The project's modules that module ``name`` imports, explicitly."""
    tree = ast.parse(modules[name].read_text(encoding="utf-8"))
    here = name if _is_package(name, modules) else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names if a.name.split(".")[0] in PACKAGES)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = here.split(".")
                base = base[: len(base) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target.split(".")[0] not in PACKAGES:
                continue
            subs = [f"{target}.{a.name}" for a in node.names if f"{target}.{a.name}" in modules]
            found.update(subs if subs else [target])
    return {m for m in found if m in modules and m != name}


def _part(name):
    parts = name.split(".")
    return "__init__" if len(parts) == 1 else parts[1]


@pytest.fixture(scope="module")
def graph():
    modules = _modules()
    return {m: _imports(m, modules) for m in modules}


def _within(graph, pkg):
    """The edges within package ``pkg``."""
    return {
        m: {t for t in ts if t.split(".")[0] == pkg}
        for m, ts in graph.items()
        if m.split(".")[0] == pkg
    }


@pytest.fixture(scope="module")
def calib(graph):
    """The edges within halfspace_calib."""
    return _within(graph, PKG)


def test_the_graph_sees_the_packages(graph, calib):
    """The parser finds the modules and their edges (a broken parser would pass everything)."""
    assert len(calib) > 30
    assert "halfspace_calib.contact.normal" in graph["halfspace_calib.pipeline.sweep.sweeps"]
    assert "halfspace_calib.topography.surface" in graph["halfspace_calib.topography.synthesis"]
    assert {_part(m) for m in calib} == set(ALLOWED)
    assert {m.split(".")[0] for m in graph} == set(PACKAGES)
    assert any(t.startswith("sbmf_cli") for t in graph["halfspace_calib.cli"])


def test_packages_import_only_what_they_may(graph):
    bad = [
        f"{m} imports {t}"
        for m, targets in graph.items()
        for t in sorted(targets)
        if t.split(".")[0] != m.split(".")[0]
        and t.split(".")[0] not in PACKAGE_ALLOWED[m.split(".")[0]]
    ]
    assert bad == []


def test_the_runtime_law_does_not_import_the_command_layer(graph):
    """Only frictionlaw's commands import sbmf_cli: an FE code's law never carries it."""
    bad = [
        f"{m} imports {t}"
        for m, targets in graph.items()
        if m.split(".")[0] == "frictionlaw" and not m.startswith(FRICTIONLAW_COMMANDS)
        for t in sorted(targets)
        if t.startswith("sbmf_cli")
    ]
    assert bad == []


def test_the_getfem_script_does_not_import_fe_demo(graph):
    """The coupling runs under Debian's Python without fe_demo; only the comparison uses it."""
    script = [
        m for m in graph if m.startswith("couplings.getfem") and m != "couplings.getfem.compare"
    ]
    assert "couplings.getfem.ring" in script
    assert [t for m in script for t in graph[m] if t.startswith("fe_demo")] == []


@pytest.mark.parametrize("pkg", sorted(LAYERS))
def test_lower_layers_do_not_import_higher_ones(graph, pkg):
    edges = _within(graph, pkg)
    assert {_part(m) for m in edges} == set(LAYERS[pkg])  # every part has its rule
    bad = [
        f"{m} imports {t}"
        for m, targets in edges.items()
        for t in sorted(targets)
        if _part(t) != _part(m) and _part(t) not in LAYERS[pkg][_part(m)]
    ]
    assert bad == []


def _pipeline_part(name):
    parts = name.split(".")
    return "__init__" if len(parts) == 2 else parts[2]


def test_pipeline_parts_import_one_way(graph):
    """The pipeline's subpackages by role (issue 39): a lower one never imports a higher one."""
    edges = {
        m: {t for t in ts if t.startswith(PIPELINE)}
        for m, ts in graph.items()
        if m == PIPELINE or m.startswith(PIPELINE + ".")
    }
    assert {_pipeline_part(m) for m in edges} == set(PIPELINE_ALLOWED)
    assert f"{PIPELINE}.law.forms" in edges[f"{PIPELINE}.sweep.levels"]  # edges are seen
    assert f"{PIPELINE}.calibration" in edges[f"{PIPELINE}.band.samples"]
    bad = [
        f"{m} imports {t}"
        for m, targets in edges.items()
        for t in sorted(targets)
        if _pipeline_part(t) != _pipeline_part(m)
        and _pipeline_part(t) not in PIPELINE_ALLOWED[_pipeline_part(m)]
    ]
    assert bad == []


def test_fe_demo_graph_sees_its_layers(graph):
    """The rule has something to hold: the layers' known edges are seen."""
    assert "fe_demo.solver.model" in graph["fe_demo.scenes.press"]
    assert "fe_demo.scenes.press" in graph["fe_demo.scenes"]
    assert "fe_demo.scenes" in graph["fe_demo.analysis.ringfit"]


def _circles(graph):
    """Every import circle a depth-first search meets, as ``[a, b, ..., a]``."""
    state, stack, circles = {}, [], []

    def visit(m):
        state[m] = "open"
        stack.append(m)
        for t in sorted(graph[m]):
            if state.get(t) == "open":
                circles.append(stack[stack.index(t) :] + [t])
            elif t not in state:
                visit(t)
        stack.pop()
        state[m] = "done"

    for m in sorted(graph):
        if m not in state:
            visit(m)
    return circles


def test_no_import_circle(graph):
    assert _circles(graph) == []


def test_the_circle_finder_finds_a_circle():
    """The search reports a known circle, and none in a chain."""
    assert _circles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c", "a"]]
    assert _circles({"a": {"b"}, "b": {"c"}, "c": set()}) == []


#: file patterns under the 600-line rule: every module, and frictionlaw.export's templates (the
#: Fortran, README and deck files that replaced Fortran inside Python strings)
LINE_PATTERNS = {"frictionlaw": ("*.py", "*.f", "*.f90", "*.md", "*.inp", "*.k")}


def _long_modules():
    return {
        p.relative_to(REPO).as_posix(): n
        for pkg in PACKAGES
        for pattern in LINE_PATTERNS.get(pkg, ("*.py",))
        for p in (REPO / pkg).rglob(pattern)
        if (n := len(p.read_text(encoding="utf-8").splitlines())) > 600
    }


def test_no_module_over_600_lines():
    """In every package of the distribution (and the coupling scripts)."""
    assert set(_long_modules()) == set(LONG_EXEMPT)  # an exemption no longer needed fails too


def _third_party_roots(package):
    """Top-level names imported anywhere in ``package`` (a folder next to ``halfspace_calib``)."""
    roots = set()
    for path in (REPO / package).rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                roots.update(a.name.split(".")[0] for a in node.names)
            elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
                roots.add(node.module.split(".")[0])
    return roots


def test_the_three_packages_import_one_way():
    """frictionlaw imports neither other package; halfspace_calib never imports fe_demo."""
    assert {"halfspace_calib", "fe_demo"} & _third_party_roots("frictionlaw") == set()
    assert "fe_demo" not in _third_party_roots("halfspace_calib")
    assert "frictionlaw" in _third_party_roots("halfspace_calib")  # the parser sees imports


def test_the_command_layer_is_standard_library_only():
    """sbmf_cli imports no third-party package (the GetFEM script runs it under Debian's Python)."""
    import sys

    roots = _third_party_roots("sbmf_cli") - {"sbmf_cli", "__future__"}
    assert roots and roots <= set(sys.stdlib_module_names), sorted(
        roots - set(sys.stdlib_module_names)
    )
