"""The layering of ``halfspace_calib`` (docs/architecture.md), read from the source with ``ast``.

Every import of the package's own modules (module level and inside functions) is an edge; the test
fails on an import circle and on a lower layer importing a higher one.
"""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1] / "halfspace_calib"
PKG = "halfspace_calib"

#: what each part of the package may import of the package (besides itself)
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


def _modules():
    """``{dotted name: path}`` of every module of the package."""
    out = {}
    for path in ROOT.rglob("*.py"):
        parts = list(path.relative_to(ROOT.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def _is_package(name, modules):
    return modules[name].name == "__init__.py"


def _imports(name, modules):
    """The package's modules that module ``name`` imports, explicitly."""
    tree = ast.parse(modules[name].read_text(encoding="utf-8"))
    here = name if _is_package(name, modules) else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names if a.name.split(".")[0] == PKG)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = here.split(".")
                base = base[: len(base) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target.split(".")[0] != PKG:
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


def test_the_graph_sees_the_package(graph):
    """The parser finds the modules and their edges (a broken parser would pass everything)."""
    assert len(graph) > 30
    assert "halfspace_calib.contact.normal" in graph["halfspace_calib.pipeline.sweeps"]
    assert "halfspace_calib.topography.surface" in graph["halfspace_calib.topography.synthesis"]
    assert {_part(m) for m in graph} == set(ALLOWED)


def test_lower_layers_do_not_import_higher_ones(graph):
    bad = [
        f"{m} imports {t}"
        for m, targets in graph.items()
        for t in sorted(targets)
        if _part(t) != _part(m) and _part(t) not in ALLOWED[_part(m)]
    ]
    assert bad == []


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


#: the 600-line rule: every module of these packages, and frictionlaw.export's templates
#: (the Fortran, README and deck files that replaced Fortran inside Python strings)
LINE_RULE = {
    "halfspace_calib": ("*.py",),
    "frictionlaw": ("*.py", "*.f", "*.f90", "*.md", "*.inp", "*.k"),
}


@pytest.mark.parametrize("package", sorted(LINE_RULE))
def test_no_module_over_600_lines(package):
    base = ROOT.parent / package
    files = [p for pattern in LINE_RULE[package] for p in base.rglob(pattern)]
    assert len(files) > 20  # the globs see the package
    long = {
        str(p.relative_to(base)): n
        for p in files
        if (n := len(p.read_text(encoding="utf-8").splitlines())) > 600
    }
    assert long == {}


def _third_party_roots(package):
    """Top-level names imported anywhere in ``package`` (a folder next to ``halfspace_calib``)."""
    roots = set()
    for path in (ROOT.parent / package).rglob("*.py"):
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
