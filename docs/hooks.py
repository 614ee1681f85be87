"""MkDocs hooks (``hooks:`` in mkdocs.yml): pages generated at build time.

* ``reference/<kind>.md``: the deck reference of each deck kind, generated from the
  pydantic models (:func:`shockfriction.deck.schema.markdown_reference`), and
  ``reference/<kind>.schema.json``, the JSON schema that ``shockfriction schema KIND`` prints;
* ``verification.md``: every verification table of the theory pages (docs/theory.md and
  docs/theory/*.md, in the order the index docs/theory.md lists them), collected under the
  heading it belongs to;
* the ``theory/*.md`` entry of the nav is replaced by every docs/theory/*.md file the nav does
  not list by name, and pages that the nav does not list are added under 'More' (a strict build
  never fails on them);
* ``<!-- theory-pages -->`` in the theory index is replaced by a list of the docs/theory/*.md
  pages that it does not link to yet (pages other branches add);
* ``<!-- gallery -->`` in a page is replaced by every figure under docs/figures/, and
  ``<!-- examples -->`` by a table of the files in examples/ (their leading comment).
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

from mkdocs.structure.files import File, Files

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
sys.path.insert(0, str(ROOT / "src"))

THEORY_GLOB = "theory/*.md"


_INDEX_LINK = re.compile(r"\]\((theory/[^)#\s]+\.md)(?:#[^)]*)?\)")


def _indexed_pages() -> list[str]:
    """The docs/theory/*.md pages the index docs/theory.md links to, in its order."""
    index = DOCS / "theory.md"
    found = _INDEX_LINK.findall(index.read_text(encoding="utf-8")) if index.exists() else []
    return [p for p in dict.fromkeys(found) if (DOCS / p).exists()]


def _theory_pages() -> list[str]:
    """Every docs/theory/*.md page: those the index lists (chapters first), then the others."""
    listed = _indexed_pages()
    rest = sorted(p.relative_to(DOCS).as_posix() for p in (DOCS / "theory").glob("*.md"))
    return listed + [p for p in rest if p not in listed]


def _title(path: str) -> str:
    for line in (DOCS / path).read_text(encoding="utf-8").splitlines():
        if line.startswith("# "):
            return line[2:].strip()
    return Path(path).stem.replace("-", " ").replace("_", " ")


def _expand_nav(items: list, named: set[str]) -> list:
    out = []
    for item in items:
        if item == THEORY_GLOB:
            out += [{_title(p): p} for p in _theory_pages() if p not in named]
        elif isinstance(item, dict):
            out.append({k: _expand_nav(v, named) if isinstance(v, list) else v for k, v in item.items()})
        else:
            out.append(item)
    return out


def on_config(config, **kwargs):
    if config.get("nav"):
        config["nav"] = _expand_nav(config["nav"], set(_nav_paths(config["nav"])))
    return config


def on_files(files: Files, config, **kwargs) -> Files:
    from shockfriction.deck.schema import DECKS, json_text, markdown_reference

    for kind in DECKS:
        files.append(File.generated(config, f"reference/{kind}.md", content=markdown_reference(kind)))
        files.append(File.generated(config, f"reference/{kind}.schema.json", content=json_text(kind) + "\n"))
    files.append(File.generated(config, "verification.md", content=verification_page()))
    if config.get("nav"):  # a page another branch adds outside the nav still gets listed
        listed = set(_nav_paths(config["nav"]))
        extra = sorted(f.src_uri for f in files.documentation_pages() if f.src_uri not in listed)
        if extra:
            config["nav"].append({"More": [{_title(p) if (DOCS / p).exists() else p: p} for p in extra]})
    return files


def _nav_paths(items) -> list[str]:
    out = []
    for item in items if isinstance(items, list) else [items]:
        if isinstance(item, str):
            out.append(item)
        elif isinstance(item, dict):
            for v in item.values():
                out += _nav_paths(v)
    return out


# --- verification tables ---------------------------------------------------------------------------

_HEADING = re.compile(r"^(#{1,6})\s+(.*)$")


def _slug(text: str) -> str:
    """The anchor the markdown toc extension gives a heading (default slugify)."""
    text = re.sub(r"[^\w\s-]", "", text).strip().lower()
    return re.sub(r"[-\s]+", "-", text)


def _tables(path: str):
    """(heading trail, anchor, table lines) of each table under a verification heading or with a
    tolerance column."""
    lines = (DOCS / path).read_text(encoding="utf-8").splitlines()
    trail: list[tuple[int, str]] = []
    fence = False
    k = 0
    while k < len(lines):
        line = lines[k]
        if line.lstrip().startswith("```"):
            fence = not fence
        m = _HEADING.match(line) if not fence else None
        if m:
            level = len(m.group(1))
            trail = [t for t in trail if t[0] < level] + [(level, m.group(2).strip())]
        if not fence and line.startswith("|") and k + 1 < len(lines) and re.match(r"^\|[\s:|-]+\|$", lines[k + 1]):
            table = []
            while k < len(lines) and lines[k].startswith("|"):
                table.append(lines[k])
                k += 1
            header = table[0].lower()
            in_verification = any("verification" in t[1].lower() for t in trail)
            if "tolerance" in header or (in_verification and ("result" in header or "measured" in header)):
                yield trail, table
            continue
        k += 1


def verification_page() -> str:
    out = ["# Verification", "",
           "Every model is tested against an exact or independent solution with a tolerance near the",
           "measured error. The tables below are collected at build time from the theory pages (each",
           "under the heading it belongs to, with a link to it); the numbers are those the tests measured.",
           "Run them with `python -m pytest tests/verification tests/subgrid -s` (add `-m slow` for the",
           "refinement studies).", ""]
    for path in ["theory.md"] + _theory_pages():
        for trail, table in _tables(path):
            parts = [t[1] for t in trail if t[0] > 1]
            if path != "theory.md" or not parts:
                parts = [_title(path)] + parts
            title = " / ".join(parts)
            anchor = _slug(trail[-1][1]) if trail else ""
            out += [f"## {title}", "", f"From [{_title(path)}]({path}#{anchor}).", ""] + table + [""]
    return "\n".join(out)


# --- figure gallery ----------------------------------------------------------------------------------

def on_page_markdown(markdown: str, page, config, files, **kwargs) -> str:
    if "<!-- theory-pages -->" in markdown:
        markdown = markdown.replace("<!-- theory-pages -->", unindexed_theory_list())
    if "<!-- examples -->" in markdown:
        markdown = markdown.replace("<!-- examples -->", example_table())
    if "<!-- gallery -->" not in markdown:
        return markdown
    depth = page.file.src_uri.count("/")
    prefix = "../" * depth
    blocks = []
    for folder in sorted({p.parent for p in (DOCS / "figures").rglob("*.png")}):
        rel = folder.relative_to(DOCS).as_posix()
        blocks += [f"### {folder.relative_to(DOCS / 'figures').as_posix()}", ""]
        for png in sorted(folder.glob("*.png")):
            caption = png.stem.replace("_", " ")
            blocks += [f"![{caption}]({prefix}{rel}/{png.name})", f"*{png.name}*", ""]
    return markdown.replace("<!-- gallery -->", "\n".join(blocks))


def unindexed_theory_list() -> str:
    """A list of the docs/theory/*.md pages the index does not link to (empty when none)."""
    indexed = set(_indexed_pages())
    extra = [p for p in _theory_pages() if p not in indexed]
    if not extra:
        return ""
    return "\n".join(["Pages added since this index was written:", ""] + [f"- [{_title(p)}]({p})" for p in extra])


# --- example table -----------------------------------------------------------------------------------

_COMMAND = re.compile(r"((?:shockfriction|python) \S.*?)(?:\s{2,}|$)")


def _header(path: Path) -> tuple[str, str | None]:
    """First sentence(s) of the leading comment (or docstring) of an example, and its command line."""
    text = path.read_text(encoding="utf-8")
    if path.suffix == ".py":
        m = re.search(r'"""(.*?)"""', text, re.S)
        lines = m.group(1).splitlines() if m else []
    else:
        lines = []
        for line in text.splitlines():
            if not line.startswith("#"):
                break
            lines.append(line.lstrip("#").strip())
    words, command = [], None
    for line in lines:
        hit = _COMMAND.search(line)
        if hit and ("shockfriction " in hit.group(1) or "examples/" in hit.group(1)):
            command = command or hit.group(1).strip()
            continue
        if not line.strip():
            if words:
                break
            continue
        words.append(line.strip())
    about = " ".join(words)
    if len(about) > 260:
        about = about[:260].rsplit(" ", 1)[0] + " ..."
    return about, command


def _default_command(rel: str) -> str:
    stem = Path(rel).stem
    if rel.startswith("examples/subgrid/"):
        return f"shockfriction subgrid {rel} --out out/{stem}"
    if rel.startswith("examples/calibration/"):
        kind = "fit" if "fit" in stem else "sweep"
        return f"shockfriction {kind} {rel} --out out/{stem}"
    if rel.startswith("examples/verification/"):
        return f"shockfriction run {rel} --out out/{stem}"
    return f"shockfriction run {rel} --out out/{stem}"


def example_table() -> str:
    rows = ["| example | what it is | command |", "|---|---|---|"]
    files = sorted(p for p in (ROOT / "examples").rglob("*") if p.suffix in (".toml", ".py")
                   and not p.name.startswith("_"))
    for path in files:
        rel = path.relative_to(ROOT).as_posix()
        about, command = _header(path)
        if path.suffix == ".py" and command is None:
            command = f"python {rel}"
        command = command or _default_command(rel)
        cells = [f"`{rel}`", about.replace("|", "\\|"), f"`{command}`".replace("|", "\\|")]
        rows.append("| " + " | ".join(cells) + " |")
    return "\n".join(rows)
