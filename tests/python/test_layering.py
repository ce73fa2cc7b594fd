"""The Python package's imports run one way (docs/contributing.md).

Builds the graph of the package's module-level imports of its own modules with
``ast`` (no import is executed) and checks that it has no cycle, and that no
import statement follows a def or a class at module level (an import at the
bottom of a file is how a cycle hides).  Imports inside functions are lazy on
purpose (optional dependencies, the figures) and are not edges here.  Also
checks the layers: the base never imports above itself, and the many-state
machinery (``pendula._many``) never imports the public modules built on it.
"""

import ast
from pathlib import Path

import pytest

import pendula

PKG = Path(pendula.__file__).parent
EXTENSIONS = {"_fortran"}  # compiled: imports nothing of the package
BASE = {"_codes", "_config", "_errors", "_arrays", "_defaults", "_longcall", "_memory", "_tables", "_angle_warning"}


def _modules():
    out = {}
    for path in sorted(PKG.rglob("*.py")):
        rel = path.relative_to(PKG).with_suffix("")
        parts = [p for p in rel.parts if p != "__init__"]
        out[".".join(parts)] = path
    return out


def _resolve(name, level, here, is_pkg):
    """The package-relative module an import refers to ('' = the package), or None for another package."""
    if level == 0:
        if name == "pendula" or name.startswith("pendula."):
            return name[len("pendula.") :] if name != "pendula" else ""
        return None
    base = here.split(".") if here else []
    if not is_pkg:
        base = base[:-1]
    base = base[: len(base) - (level - 1)] if level > 1 else base
    return ".".join(base + ([name] if name else []))


def _edges(mods):
    graph, late = {}, []
    for mod, path in mods.items():
        tree = ast.parse(path.read_text(), filename=str(path))
        is_pkg = path.name == "__init__.py"
        deps, seen_def = set(), False
        for node in tree.body:
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                seen_def = True
            if not isinstance(node, (ast.Import, ast.ImportFrom)):
                continue
            if seen_def:
                late.append(f"{path.relative_to(PKG)}:{node.lineno}")
            if isinstance(node, ast.Import):
                targets = [_resolve(a.name, 0, mod, is_pkg) for a in node.names]
            else:
                target = _resolve(node.module or "", node.level, mod, is_pkg)
                targets = []
                if target is not None:
                    for a in node.names:
                        sub = f"{target}.{a.name}".lstrip(".")
                        if sub in mods:  # "from . import x": the submodule x
                            targets.append(sub)
                        elif sub not in EXTENSIONS:  # a name defined in the module itself
                            targets.append(target)
            # a module's parent packages are loaded before it anyway: not an edge
            parents = {".".join(mod.split(".")[:i]) for i in range(len(mod.split(".")))}
            deps.update(t for t in targets if t is not None and t in mods and t != mod and t not in parents)
        graph[mod] = deps
    return graph, late


MODS = _modules()
GRAPH, LATE = _edges(MODS)


def _cycle(graph):
    state, stack = {}, []

    def visit(m):
        state[m] = 1
        stack.append(m)
        for d in sorted(graph[m]):
            if state.get(d) == 1:
                return stack[stack.index(d) :] + [d]
            if d not in state:
                found = visit(d)
                if found:
                    return found
        stack.pop()
        state[m] = 2
        return None

    for m in sorted(graph):
        if m not in state:
            found = visit(m)
            if found:
                return found
    return None


def test_the_graph_sees_the_package():
    assert {"", "integrate", "scene", "sweep", "_many.kernels", "_many.ensemble", "_plotting.base"} <= set(MODS)
    assert "_many.kernels" in GRAPH["_many.ensemble"] and "_many.ensemble" in GRAPH["integrate"]


def test_no_import_cycle():
    cycle = _cycle(GRAPH)
    assert cycle is None, "import cycle: " + " -> ".join(m or "pendula" for m in cycle)


def test_no_import_after_a_definition():
    assert not LATE, f"imports below a def or class (move them to the top): {LATE}"


@pytest.mark.parametrize(
    "layer, forbidden",
    [
        (BASE, lambda d: d not in BASE),
        ({m for m in MODS if m.startswith("_many")}, lambda d: not (d in BASE or d.startswith("_many"))),
    ],
)
def test_layers_import_only_below(layer, forbidden):
    bad = {m: sorted(d for d in GRAPH[m] if forbidden(d)) for m in layer if m in GRAPH}
    assert not any(bad.values()), f"imports above the layer: { {k: v for k, v in bad.items() if v} }"


def test_the_cycle_finder_finds_cycles():
    assert _cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]
    assert _cycle({"a": {"b"}, "b": set()}) is None
