"""Imports point one way (ARCHITECTURE.md): a static check of every ``import`` in the package.

Reference: the layer rules of ARCHITECTURE.md, read off the source with ``ast`` (imports inside
functions count too). Rules:

1. No general layer imports :mod:`mbsym.wind` (only ``mbsym/wind`` itself and the CLI may).
2. The rooms of :mod:`mbsym.wind` import downward only, in the order of ``WIND_ROOMS``.
3. The modules of :mod:`mbsym.linear` import downward only, in the order of ``LINEAR_MODULES``.
4. The general packages form no import cycle, except the documented facade methods of
   ``EquationsOfMotion`` (``eom.linearize``, ``eom.export_c``, …: imported on use).
"""

from __future__ import annotations

import ast
from collections import defaultdict
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "mbsym"

#: Rooms of mbsym.wind, lowest first (a room may import the rooms before it).
WIND_ROOMS = ("inflow", "deck", "structure", "aero", "control", "offshore", "operation", "mpc", "analysis")
#: Modules of mbsym.linear, lowest first (ARCHITECTURE.md; groups on one line may not import each other).
LINEAR_MODULES = (("_cache", "model", "point"), ("functions", "target", "fd"), ("outputs",), ("linearize",),
                  ("batch", "sensitivity", "operating"), ("azimuth",))
#: Imports allowed against the package order: EquationsOfMotion's facade methods.
FACADES = {("equations", "linear"), ("equations", "export")}


def _imports() -> dict[str, set[str]]:
    """Module name -> the mbsym modules it imports (absolute names)."""
    out: dict[str, set[str]] = defaultdict(set)
    for path in PACKAGE.rglob("*.py"):
        parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        module = ".".join(parts)
        package = parts if path.name == "__init__.py" else parts[:-1]
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom):
                base = package[: len(package) - node.level + 1] if node.level else []
                target = ".".join(base + ([node.module] if node.module else [])) if node.level else node.module
                names = [f"{target}.{a.name}" for a in node.names]
                out[module].update([target] + names)
            elif isinstance(node, ast.Import):
                out[module].update(a.name for a in node.names)
    return {m: {t for t in ts if t and t.split(".")[0] == "mbsym"} for m, ts in out.items()}


IMPORTS = _imports()


def _room(module: str, prefix: str) -> str | None:
    parts = module.split(".")
    n = len(prefix.split("."))
    return parts[n] if module.startswith(prefix + ".") and len(parts) > n else None


def test_general_layers_never_import_wind():
    bad = sorted(f"{m} -> {t}" for m, ts in IMPORTS.items() for t in ts
                 if t.startswith("mbsym.wind") and not m.startswith(("mbsym.wind", "mbsym.cli")))
    assert not bad, bad


def test_wind_rooms_import_downward():
    rank = {r: i for i, r in enumerate(WIND_ROOMS)}
    bad = []
    for m, ts in IMPORTS.items():
        a = _room(m, "mbsym.wind")
        for t in ts:
            b = _room(t, "mbsym.wind")
            if a in rank and b in rank and rank[b] > rank[a]:
                bad.append(f"{m} -> {t}")
    assert not bad, sorted(set(bad))


def test_linear_modules_import_downward():
    rank = {name: i for i, group in enumerate(LINEAR_MODULES) for name in group}
    bad = []
    for m, ts in IMPORTS.items():
        a = _room(m, "mbsym.linear")
        for t in ts:
            b = _room(t, "mbsym.linear")
            if a in rank and b in rank and a != b and rank[b] >= rank[a]:
                bad.append(f"{m} -> {t}")
    assert not bad, sorted(set(bad))


def test_general_packages_form_no_cycle():
    edges: dict[str, set[str]] = defaultdict(set)
    for m, ts in IMPORTS.items():
        a = _room(m, "mbsym")
        for t in ts:
            b = _room(t, "mbsym")
            if a and b and a != b and "wind" not in (a, b) and "cli" not in (a, b) and (a, b) not in FACADES:
                edges[a].add(b)
    seen, stack, cycles = set(), [], []

    def visit(node):
        if node in stack:
            cycles.append(stack[stack.index(node):] + [node])
            return
        if node in seen:
            return
        seen.add(node)
        stack.append(node)
        for nxt in sorted(edges[node]):
            visit(nxt)
        stack.pop()

    for node in sorted(edges):
        visit(node)
    assert not cycles, cycles


def _face_imports(path: Path) -> list[str]:
    """Imports in ``path`` of the package face ``mbsym`` itself (``import mbsym``, ``from mbsym import Name``,
    ``from .. import Name`` resolving to ``mbsym``) where ``Name`` is not a sub-module: the face re-exports
    names, the defining modules hold them."""
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    package = parts[:-1] if parts[-1] != "__init__" else parts[:-1]
    found = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found += [a.name for a in node.names if a.name == "mbsym"]
        elif isinstance(node, ast.ImportFrom):
            base = package[: len(package) - node.level + 1] if node.level else []
            target = ".".join(base + ([node.module] if node.module else [])) if node.level else node.module
            if target == "mbsym":
                found += [f"from mbsym import {a.name}" for a in node.names
                          if not (PACKAGE / a.name).is_dir() and not (PACKAGE / f"{a.name}.py").is_file()]
    return found


def test_library_modules_import_the_defining_modules_not_the_face():
    """ARCHITECTURE.md: only the package's own ``__init__``, the CLI and the demo (top layers, written as a user
    writes) import the face ``mbsym``; a library module importing it depends on everything the face loads and
    hides its real dependency (e.g. control/models.py once did ``import mbsym as mb`` for ``System``)."""
    bad = {}
    for path in PACKAGE.rglob("*.py"):
        rel = path.relative_to(PACKAGE).as_posix()
        if rel == "__init__.py" or rel.startswith("cli/") or rel in ("demo.py", "__main__.py"):
            continue
        found = _face_imports(path)
        if found:
            bad[rel] = found
    assert not bad, bad
