"""The package's layers (ARCHITECTURE.md): no module imports upward, no package cycle.

Every ``import`` and ``from … import`` of ``leopod`` modules in src/leopod — also those inside
functions — is an edge between top-level packages. A package may import from its own layer or
below, never from above; the graph of packages has no cycle; and the two consumers of the
estimator's conventions that must stay independent of it (``validation`` checks it,
``simulate`` feeds it) do not import ``estimation``; figures (``plots``) import no model or
solution package: they draw the statistics the steps computed.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "leopod"

#: Layers from the bottom; a package imports only packages of its own layer or below.
LAYERS = (
    ("foundation", ("constants", "settings", "signals", "numerics", "time", "astro", "frames")),
    ("io", ("io",)),
    ("models", ("gnss", "dynamics")),
    ("solutions", ("estimation", "ambiguity", "codebias", "antenna", "validation", "simulate",
                   "ingest", "download")),
    ("application", ("plots", "workflow", "cli")),
)
LAYER_OF = {pkg: i for i, (_, pkgs) in enumerate(LAYERS) for pkg in pkgs}
#: Imports forbidden although downward: (importer, imported). Figures plot the statistics the
#: steps computed; they compute nothing of the models or solutions themselves.
FORBIDDEN = {("validation", "estimation"), ("simulate", "estimation"),
             *(("plots", pkg) for _, pkgs in LAYERS[2:4] for pkg in pkgs)}


def _package(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else ""


def import_edges(src: Path = SRC) -> list[tuple[str, str, str]]:
    """``(importer module, imported module, location)`` of every leopod import under ``src``."""
    edges = []
    for path in sorted(src.rglob("*.py")):
        rel = path.relative_to(src.parent).with_suffix("")
        module = ".".join(rel.parts[:-1] if rel.name == "__init__" else rel.parts)
        package_parts = rel.parts[:-1]
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            targets = []
            if isinstance(node, ast.ImportFrom):
                if node.level:
                    base = package_parts[:len(package_parts) - node.level + 1]
                    name = ".".join([*base, node.module] if node.module else base)
                else:
                    name = node.module or ""
                targets = [name] if name == "leopod" or name.startswith("leopod.") else []
                if name == "leopod":      # from leopod import signals: the submodule
                    targets = [f"leopod.{a.name}" for a in node.names]
            elif isinstance(node, ast.Import):
                targets = [a.name for a in node.names if a.name.startswith("leopod.")]
            for target in targets:
                edges.append((module, target, f"{path.relative_to(src.parent)}:{node.lineno}"))
    return edges


def violations(edges) -> list[str]:
    """Upward or forbidden imports among ``edges`` (each as a readable line)."""
    out = []
    for importer, imported, where in edges:
        a, b = _package(importer), _package(imported)
        if not a or not b or a == b or b == "__version__":
            continue
        if a not in LAYER_OF or b not in LAYER_OF:
            out.append(f"{where}: {importer} -> {imported}: package not in a layer")
        elif LAYER_OF[b] > LAYER_OF[a]:
            out.append(f"{where}: {importer} ({LAYERS[LAYER_OF[a]][0]}) imports upward "
                       f"{imported} ({LAYERS[LAYER_OF[b]][0]})")
        elif (a, b) in FORBIDDEN:
            out.append(f"{where}: {importer} imports {imported} (forbidden: {a} -> {b})")
    return out


def package_cycles(edges) -> list[list[str]]:
    """Cycles of the package graph (as lists of packages), by depth-first search."""
    graph: dict[str, set[str]] = {}
    for importer, imported, _ in edges:
        a, b = _package(importer), _package(imported)
        if a and b and a != b:
            graph.setdefault(a, set()).add(b)
    cycles, state = [], {}

    def visit(node, stack):
        state[node] = "open"
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == "open":
                cycles.append([*stack[stack.index(nxt):], nxt])
            elif nxt not in state:
                visit(nxt, stack)
        stack.pop()
        state[node] = "done"

    for node in sorted(graph):
        if node not in state:
            visit(node, [])
    return cycles


def test_every_package_has_a_layer():
    packages = {p.stem if p.is_file() else p.name for p in SRC.iterdir()
                if (p.is_dir() and (p / "__init__.py").exists())
                or (p.suffix == ".py" and p.name != "__init__.py")}
    assert packages - set(LAYER_OF) == set()


def test_no_module_imports_upward():
    assert violations(import_edges()) == []


def test_no_package_cycle():
    assert package_cycles(import_edges()) == []


@pytest.mark.parametrize(("edge", "expected"), [
    (("leopod.io.sp3", "leopod.gnss.products", "x.py:1"), "imports upward"),
    (("leopod.time.scales", "leopod.workflow.config", "x.py:1"), "imports upward"),
    (("leopod.validation.reference", "leopod.estimation.arc", "x.py:1"), "forbidden"),
    (("leopod.plots.slr", "leopod.validation.slr_statistics", "x.py:1"), "forbidden"),
    (("leopod.newpkg.a", "leopod.io.sp3", "x.py:1"), "not in a layer"),
])
def test_the_checks_catch_a_bad_import(edge, expected):
    """The checks themselves can fail: a made-up upward, forbidden or unknown import."""
    assert expected in " ".join(violations([edge]))


def test_the_cycle_check_catches_a_cycle():
    edges = [("leopod.gnss.a", "leopod.dynamics.b", ""), ("leopod.dynamics.b", "leopod.gnss.c", "")]
    assert package_cycles(edges) == [["dynamics", "gnss", "dynamics"]]
