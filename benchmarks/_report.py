"""Shared by the benchmark scripts: rewrite one marked section of benchmarks/README.md."""

from __future__ import annotations

from pathlib import Path

README = Path(__file__).resolve().with_name("README.md")


def write_section(marker: str, table: str, path: Path = README) -> None:
    """Replace the text between ``<!-- marker:start -->`` and ``<!-- marker:end -->`` (append if absent)."""
    start, end = f"<!-- {marker}:start -->", f"<!-- {marker}:end -->"
    text = path.read_text() if path.exists() else ""
    block = f"{start}\n{table}\n{end}"
    if start in text and end in text:
        text = text[: text.index(start)] + block + text[text.index(end) + len(end):]
    else:
        text += f"\n{block}\n"
    path.write_text(text)


def shared_aero() -> Path:
    """``shared/openfast/aero`` next to the repository (or above a worktree); exits if absent."""
    for parent in README.parents:
        if (parent / "shared" / "openfast" / "aero").is_dir():
            return parent / "shared" / "openfast" / "aero"
    raise SystemExit("shared/openfast/aero not found")
