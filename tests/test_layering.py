"""Layering (issue 28): the deck layer and the material library do not import each other back, both read
TOML through the low module shockfriction.tomlio, and problem set-up (the cone shot) is not in the library.

The import graph is read from the source with ``ast`` (every ``import`` and ``from ... import``, at any depth
of a module, functions included), so a lazy import inside a function counts too."""

import ast
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src" / "shockfriction"


def _module(path: Path) -> str:
    parts = path.relative_to(SRC.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path) -> set[str]:
    """The shockfriction modules a file imports (``from a.b import c`` counts a.b and a.b.c)."""
    out = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            out |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            out.add(node.module)
            out |= {f"{node.module}.{a.name}" for a in node.names}
    return {m for m in out if m.split(".")[0] == "shockfriction"}


def _graph() -> dict[str, set[str]]:
    files = {_module(p): p for p in SRC.rglob("*.py")}
    graph = {}
    for mod, path in files.items():
        # an import of a.b.c names the module a.b.c if it exists, else the module a.b (c is a name in it);
        # importing a submodule also runs its packages' __init__
        deps = set()
        for m in _imports(path):
            while m not in files and "." in m:
                m = m.rsplit(".", 1)[0]
            parts = m.split(".")
            deps |= {".".join(parts[:k]) for k in range(2, len(parts) + 1)}
        graph[mod] = deps - {mod}
    return graph


def _reach(graph, start: str) -> set[str]:
    seen, todo = set(), [start]
    while todo:
        for dep in graph.get(todo.pop(), ()):
            if dep not in seen:
                seen.add(dep)
                todo.append(dep)
    return seen


def _in(mod: str, package: str) -> bool:
    return mod == package or mod.startswith(package + ".")


def test_materials_never_reach_the_deck_layer():
    graph = _graph()
    for mod in graph:
        if _in(mod, "shockfriction.materials"):
            bad = sorted(m for m in _reach(graph, mod) if _in(m, "shockfriction.deck"))
            assert not bad, f"{mod} imports the deck layer: {bad}"


def test_no_import_loop_between_deck_and_materials():
    """Neither package imports the other back (the deck layer may use the library, one way)."""
    graph = _graph()
    deck_to_mat = any(_in(d, "shockfriction.materials") for m in graph if _in(m, "shockfriction.deck")
                      for d in _reach(graph, m))
    mat_to_deck = any(_in(d, "shockfriction.deck") for m in graph if _in(m, "shockfriction.materials")
                      for d in _reach(graph, m))
    assert not (deck_to_mat and mat_to_deck)
    assert not mat_to_deck


def test_tomlio_is_low():
    """shockfriction.tomlio imports neither the deck layer nor the materials (both read TOML through it)."""
    graph = _graph()
    reach = _reach(graph, "shockfriction.tomlio")
    assert not any(_in(m, "shockfriction.deck") or _in(m, "shockfriction.materials") for m in reach), reach
    assert "shockfriction.tomlio" in graph["shockfriction.materials.library"]
    assert "shockfriction.tomlio" in graph["shockfriction.deck.base"]


def test_the_graph_sees_lazy_imports(tmp_path):
    """The check can fail: a function-level import of the deck layer inside a module is found."""
    f = tmp_path / "m.py"
    f.write_text("def f():\n    from shockfriction.deck.base import read_toml\n    return read_toml\n")
    assert "shockfriction.deck.base" in _imports(f)


def test_problem_set_up_is_not_in_the_library():
    assert not (SRC / "coupled" / "cone_shot.py").exists()
    root = SRC.parents[1]
    assert (root / "examples" / "cone_shot.py").exists() and (root / "examples" / "cone_in_cylinder.geo").exists()
