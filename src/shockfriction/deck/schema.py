"""JSON schemas of the deck kinds and their markdown reference (``shockfriction schema``, docs).

Unit-bearing fields are strings with a dimension (:class:`shockfriction.units.QuantityValidator`);
numeric defaults of such fields, held in SI by the models, are shown with their SI unit.
"""

from __future__ import annotations

import importlib
import json
from typing import Any

from shockfriction.units import quantity_schema

#: deck kind -> (model "module:class", one line on what it is)
DECKS: dict[str, tuple[str, str]] = {
    "run": ("shockfriction.deck.run:RunDeck", "hydrocode run deck (`shockfriction run DECK.toml`)"),
    "subgrid": ("shockfriction.deck.subgrid:SubgridDeck",
                "sub-grid interface columns under imposed loading (`shockfriction subgrid DECK.toml`)"),
    "sweep": ("shockfriction.sweep.spec:SweepSpec", "parameter sweep (`shockfriction sweep SWEEP.toml`)"),
    "fit": ("shockfriction.sweep.fitspec:FitSpec", "least-squares fit (`shockfriction fit FIT.toml`)"),
}


def deck_model(kind: str):
    """The pydantic model of a deck kind (a key of :data:`DECKS`)."""
    module, name = DECKS[kind][0].split(":")
    return getattr(importlib.import_module(module), name)


def _with_unit(value: Any, unit: str) -> Any:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not unit:
        return value
    return f"{value:g} {unit}"


def _fix_defaults(node: Any) -> None:
    """Numeric SI defaults of unit fields -> strings with the SI unit (what a deck would say)."""
    if isinstance(node, list):
        for v in node:
            _fix_defaults(v)
        return
    if not isinstance(node, dict):
        return
    if "default" in node:
        unit = _unit_of(node)
        if unit is not None:
            d = node["default"]
            node["default"] = [_with_unit(v, unit) for v in d] if isinstance(d, list) else _with_unit(d, unit)
    for v in node.values():
        _fix_defaults(v)


def _unit_of(node: dict) -> str | None:
    if "x-si-unit" in node:
        return node["x-si-unit"]
    for key in ("anyOf", "prefixItems"):
        for sub in node.get(key, []):
            if isinstance(sub, dict) and "x-si-unit" in sub:
                return sub["x-si-unit"]
    items = node.get("items")
    if isinstance(items, dict) and "x-si-unit" in items:
        return items["x-si-unit"]
    return None


def json_schema(kind: str) -> dict:
    """JSON schema (draft 2020-12, validation mode) of a deck kind."""
    schema = deck_model(kind).model_json_schema()
    _fix_defaults(schema)
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    schema.setdefault("description", DECKS[kind][1])
    return schema


def json_text(kind: str) -> str:
    return json.dumps(json_schema(kind), indent=2)


# --- markdown reference --------------------------------------------------------------------------

def _anchor(name: str) -> str:
    return name.lower()


def _type(node: dict, defs: dict) -> str:
    if "$ref" in node:
        name = node["$ref"].rsplit("/", 1)[-1]
        return f"[{name}](#{_anchor(name)})"
    if "x-quantity" in node:
        kind = node["x-quantity"]
        if kind == "dimensionless":
            return "number"
        return f"{kind.replace('_', ' ')} `{node['x-dimension']}`, e.g. `\"{node['examples'][0]}\"`"
    if "const" in node:
        return f'`"{node["const"]}"`' if isinstance(node["const"], str) else f"`{node['const']}`"
    if "enum" in node:
        return " \\| ".join(f'`"{v}"`' if isinstance(v, str) else f"`{v}`" for v in node["enum"])
    for key in ("anyOf", "oneOf"):
        if key in node:
            parts = [_type(s, defs) for s in node[key] if s.get("type") != "null"]
            opt = " (or omitted)" if any(s.get("type") == "null" for s in node[key]) else ""
            return " or ".join(parts) + opt
    t = node.get("type")
    if t == "array":
        if "prefixItems" in node:
            return "[" + ", ".join(_type(s, defs) for s in node["prefixItems"]) + "]"
        items = node.get("items")
        return f"list of {_type(items, defs)}" if items else "list"
    if t == "object":
        extra = node.get("additionalProperties")
        return f"table of {_type(extra, defs)}" if isinstance(extra, dict) else "table"
    if isinstance(t, list):
        return " or ".join(t)
    return t or "any"


def _notes(node: dict) -> str:
    notes = []
    for sub in [node] + [s for s in node.get("anyOf", []) if isinstance(s, dict)]:
        if "x-bound" in sub:
            notes.append(sub["x-bound"])
        for key, op in (("exclusiveMinimum", ">"), ("minimum", ">="), ("exclusiveMaximum", "<"), ("maximum", "<=")):
            if key in sub:
                notes.append(f"{op} {sub[key]}")
        for key, what in (("minItems", "at least {} items"), ("maxItems", "at most {} items"),
                          ("minLength", "at least {} characters"), ("pattern", "matches `{}`")):
            if key in sub and not (key.endswith("Items") and "prefixItems" in sub):
                notes.append(what.format(sub[key]))
        auto = quantity_schema(sub["x-quantity"])["description"] if "x-quantity" in sub else None
        if sub.get("description") and sub["description"] != auto and sub is node:
            notes.append(sub["description"].replace("\n", " "))
    return "; ".join(dict.fromkeys(notes))


def _default(node: dict, required: bool) -> str:
    if required:
        return "**required**"
    if "default" not in node:
        return ""
    d = node["default"]
    return "" if d is None else f"`{json.dumps(d)}`"


def _table(model: dict, defs: dict) -> list[str]:
    props = model.get("properties", {})
    if not props:
        return ["(no keys)", ""]
    req = set(model.get("required", []))
    lines = ["| key | type | default | constraints, notes |", "|---|---|---|---|"]
    for key, node in props.items():
        cells = (f"`{key}`", _type(node, defs), _default(node, key in req), _notes(node))
        lines.append("| " + " | ".join(c.replace("|", "\\|") if c is cells[3] else c for c in cells) + " |")
    return lines + [""]


def markdown_reference(kind: str) -> str:
    """The deck reference of ``kind`` as markdown: one table per section, generated from the model."""
    schema = json_schema(kind)
    defs = schema.get("$defs", {})
    title = deck_model(kind).__name__
    out = [f"# `{kind}` deck reference", "",
           f"Generated from the pydantic model `{DECKS[kind][0]}` ({DECKS[kind][1]}); the same schema in",
           f"JSON: `shockfriction schema {kind}`.  Quantities with a dimension are strings with a unit",
           "(`\"250 m/s\"`, `\"10 GPa\"`); defaults of such fields are shown in SI.", "",
           f"## {title}", "", (schema.get("description") or "").strip(), ""]
    out += _table(schema, defs)
    for name in sorted(defs):
        model = defs[name]
        out += [f"## {name}", "", (model.get("description") or "").strip(), ""]
        out += _table(model, defs) if model.get("type") == "object" else [f"{_type(model, defs)}", ""]
    return "\n".join(out)
