#!/usr/bin/env python3
"""The include graph of src/ against the layer table of docs/architecture.md.

Each folder of src/ is one row of the table, lowest layer first. A folder may include
only itself and the folders its "uses" cell names ("all above": every row above it;
"everything": every other row), and those must lie above it. Every folder of src/ has a
row, every row a folder, and the "uses" cell names no folder the code does not include:
so the layering cannot drift and the document tells the truth.

Usage: include_graph_test.py SOURCE_DIR   (exit 0: consistent; 1: each violation printed)
"""
import pathlib
import re
import sys


def read_table(doc):
    """[(folder, uses cell)] in table order."""
    rows = []
    for line in doc.read_text(encoding="utf-8").splitlines():
        m = re.match(r"\|\s*`([a-z_]+)/`\s*\|[^|]*\|\s*([^|]*?)\s*\|", line)
        if m:
            rows.append((m.group(1), m.group(2)))
    return rows


def includes_of(folder):
    """{included src folder: first file:line including it}."""
    found = {}
    for path in sorted(folder.rglob("*")):
        if path.suffix not in (".hpp", ".cpp", ".h", ".in"):
            continue
        for number, line in enumerate(path.read_text(encoding="utf-8", errors="replace").splitlines(), 1):
            m = re.match(r'\s*#\s*include\s+"([a-z_]+)/', line)
            if m:
                found.setdefault(m.group(1), f"{path}:{number}")
    return found


def main():
    root = pathlib.Path(sys.argv[1])
    doc = root / "docs" / "architecture.md"
    rows = read_table(doc)
    order = [folder for folder, _ in rows]
    errors = []
    folders = sorted(p.name for p in (root / "src").iterdir() if p.is_dir())
    for name in folders:
        if name not in order:
            errors.append(f"src/{name}/ has no row in {doc}")
    for name in order:
        if name not in folders:
            errors.append(f"{doc} has a row for {name}/, which src/ does not have")
    for rank, (name, uses_cell) in enumerate(rows):
        above = order[:rank]
        if uses_cell in ("—", "-", ""):
            uses = []
        elif uses_cell == "all above":
            uses = above
        elif uses_cell == "everything":
            uses = [f for f in order if f != name]
        else:
            uses = [u.strip() for u in uses_cell.split(",")]
        for u in uses:
            if u not in above:
                errors.append(f"{doc}: {name}/ is said to use {u}/, which is not a layer above it")
        if name not in folders:
            continue
        included = includes_of(root / "src" / name)
        for target, where in sorted(included.items()):
            if target == name or target not in order:
                continue  # itself, or a generated or third-party path
            if target not in uses:
                errors.append(f"{where}: {name}/ includes {target}/, which its row of {doc} does not allow")
        if uses_cell not in ("all above", "everything"):
            for u in uses:
                if u in folders and u not in included:
                    errors.append(f"{doc}: {name}/ is said to use {u}/, but includes nothing from it")
    for e in errors:
        print(e)
    print(f"{len(rows)} layers, {len(errors)} violations")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
