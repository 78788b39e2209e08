#!/usr/bin/env python3
"""The folders of include/jamsim and src include one another one way only.

usage: layering.py SOURCE_DIR

Reads the order of the folders from the Layout block of src/README.md (one folder per line,
ground floor first, `campaign/` on top; src/app above everything) and checks every
`#include "jamsim/<folder>/..."` in include/jamsim/<folder>/ and src/<folder>/: a folder may
include itself and the folders listed before it. The exceptions below, each with its reason,
are the only ones allowed; an exception that is no longer needed fails too, so the list
shrinks as the code is fixed. Prints every violation, exits 1 if there is one.
"""
import pathlib
import re
import sys

# (folder, the folder above it that it includes, why)
ALLOWED = {
    ("params", "linalg"): "the parameter table checks CD0's solver and PETSc option names",
    ("params", "minimize"): "the parameter table checks the minimiser's name against its registry",
}


def layer_order(readme):
    text = readme.read_text()
    block = text[text.index("include/jamsim/"):]
    block = block[:block.index("```")]
    order = re.findall(r"^  ([a-z_]+)/ ", block, flags=re.M)
    if len(order) < 5:
        sys.exit(f"FAIL: no layer list found in {readme}")
    return order + ["app"]


def main(root):
    root = pathlib.Path(root)
    order = layer_order(root / "src" / "README.md")
    rank = {name: k for k, name in enumerate(order)}
    bad, used = [], set()
    for base in (root / "include" / "jamsim", root / "src"):
        for path in sorted(base.rglob("*")):
            if path.suffix not in (".hpp", ".cpp", ".h") or not path.is_file():
                continue
            folder = path.relative_to(base).parts[0]
            if folder not in rank:
                bad.append(f"{path.relative_to(root)}: folder '{folder}' is not in src/README.md's layout")
                continue
            for line_no, line in enumerate(path.read_text().splitlines(), 1):
                m = re.match(r'\s*#\s*include\s+"jamsim/([a-z_]+)/', line)
                if not m or rank.get(m.group(1), -1) <= rank[folder]:
                    continue
                if (folder, m.group(1)) in ALLOWED:
                    used.add((folder, m.group(1)))
                    continue
                bad.append(f"{path.relative_to(root)}:{line_no}: {folder}/ includes {m.group(1)}/, "
                           f"which lies above it in src/README.md's layout")
    for pair in sorted(set(ALLOWED) - used):
        bad.append(f"the exception {pair[0]}/ -> {pair[1]}/ ({ALLOWED[pair]}) is no longer needed: remove it")
    for b in bad:
        print("FAIL:", b)
    if bad:
        return 1
    print(f"ok: {len(order)} layers, every include goes down ({len(ALLOWED)} exceptions, each with its reason)")
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: layering.py SOURCE_DIR")
    sys.exit(main(sys.argv[1]))
