"""The documentation site builds strictly, and its generated pages cover what they claim to."""

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _hooks():
    import importlib.util

    spec = importlib.util.spec_from_file_location("docs_hooks", ROOT / "docs" / "hooks.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_example_table_lists_every_example_with_a_command():
    pytest.importorskip("mkdocs")
    table = _hooks().example_table()
    for path in (ROOT / "examples").rglob("*.toml"):
        assert f"`{path.relative_to(ROOT).as_posix()}`" in table
    assert "`shockfriction subgrid examples/subgrid/ball_al_200ms.toml" in table


def test_verification_page_collects_the_theory_tables():
    pytest.importorskip("mkdocs")
    page = _hooks().verification_page()
    assert page.count("| tolerance |") + page.count("| result |") >= 3
    for chapter in ("subgrid-models", "hydrocode", "exact-solutions", "slide-lines"):  # docs/theory.md split by chapter
        assert f"(theory/{chapter}.md#" in page, chapter


def test_theory_index_lists_every_theory_page_chapters_first():
    pytest.importorskip("mkdocs")
    hooks = _hooks()
    pages = sorted(p.relative_to(ROOT / "docs").as_posix() for p in (ROOT / "docs" / "theory").glob("*.md"))
    indexed = hooks._indexed_pages()
    assert indexed[:3] == ["theory/conventions.md", "theory/subgrid-models.md", "theory/hydrocode.md"]
    assert sorted(hooks._theory_pages()) == pages
    assert set(pages) - set(indexed) == {p.split("(")[1].rstrip(")") for p in hooks.unindexed_theory_list().splitlines()
                                         if p.startswith("- [")}


def test_theory_nav_glob_adds_only_pages_not_named():
    pytest.importorskip("mkdocs")
    hooks = _hooks()
    nav = [{"Theory": ["theory.md", {"Hydro": "theory/hydrocode.md"}, "theory/*.md"]}]
    expanded = hooks._nav_paths(hooks._expand_nav(nav, set(hooks._nav_paths(nav))))
    assert expanded.count("theory/hydrocode.md") == 1
    assert "theory/reliability.md" in expanded and "theory/*.md" not in expanded


def test_mkdocs_build_strict(tmp_path):
    pytest.importorskip("mkdocs")
    pytest.importorskip("material")
    pytest.importorskip("mkdocstrings")
    res = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-q", "--site-dir", str(tmp_path)],
                         cwd=ROOT, capture_output=True, text=True, timeout=300,
                         env={"PATH": "/usr/bin:/bin", "HOME": str(tmp_path), "NO_MKDOCS_2_WARNING": "1",
                              "PYTHONPATH": str(ROOT / "src")})
    assert res.returncode == 0, res.stderr[-3000:]
    for page in ("reference/run/index.html", "reference/fit.schema.json", "verification/index.html",
                 "cli/index.html", "api/index.html", "theory/index.html", "deck-run/index.html"):
        assert (tmp_path / page).is_file(), page
    assert "x-dimension" in (tmp_path / "reference/run.schema.json").read_text()
