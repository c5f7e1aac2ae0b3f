#!/usr/bin/env python3
"""The build's layers, checked: every `#include "varsfm/<x>/..."` in src/varsfm/<m>/ must name
<m> itself or a module <m> declares in its CMakeLists.txt (`varsfm_module(m DEPS varsfm_x ...)`),
directly or through the modules it declares; and no module may include or declare one that comes
after it in the data-flow order of DEVELOPERS.md's layout table (a module uses only modules above
it). Without this, every module sees all of src/ and its declared dependencies drift from what it
includes.

    scripts/check_module_layers.py [--order m1,m2,...] [ROOT]

ROOT is the source tree (default: this script's parent folder). --order replaces the table's
order (the self-test gives a reversed one, which must fail). Prints one line per violation and
exits 1 when there is any.
"""
import argparse
import pathlib
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s+"varsfm/([a-z_0-9]+)/', re.M)
MODULE_CALL = re.compile(r'varsfm_module\(\s*([a-z_0-9]+)(.*?)\)', re.S)
TABLE_ROW = re.compile(r'^\|\s*`src/varsfm/([a-z_0-9]+)`\s*\|', re.M)


def read_order(root):
    """Modules in the order of DEVELOPERS.md's layout table."""
    return TABLE_ROW.findall((root / "DEVELOPERS.md").read_text())


def read_declared(modules_dir):
    """module -> the varsfm modules its varsfm_module(...) call lists."""
    declared = {}
    for cmake in sorted(modules_dir.glob("*/CMakeLists.txt")):
        text = re.sub(r"#.*", "", cmake.read_text())
        for name, args in MODULE_CALL.findall(text):
            declared[name] = set(re.findall(r"\bvarsfm_([a-z_0-9]+)\b", args))
    return declared


def closure(module, declared):
    seen, stack = set(), [module]
    while stack:
        for dep in declared.get(stack.pop(), ()):
            if dep not in seen:
                seen.add(dep)
                stack.append(dep)
    return seen


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--order", help="comma-separated modules, replacing DEVELOPERS.md's")
    parser.add_argument("root", nargs="?", default=pathlib.Path(__file__).resolve().parent.parent)
    args = parser.parse_args()
    root = pathlib.Path(args.root)
    modules_dir = root / "src" / "varsfm"
    order = args.order.split(",") if args.order else read_order(root)
    rank = {m: i for i, m in enumerate(order)}
    declared = read_declared(modules_dir)
    problems = []

    folders = sorted(p.name for p in modules_dir.iterdir() if (p / "CMakeLists.txt").exists())
    for m in folders:
        if m not in rank:
            problems.append(f"src/varsfm/{m}: not in the layout table of DEVELOPERS.md")
        if m not in declared:
            problems.append(f"src/varsfm/{m}/CMakeLists.txt: no varsfm_module({m} ...) call")
    for m, deps in sorted(declared.items()):
        for dep in sorted(deps):
            if dep in rank and m in rank and rank[dep] > rank[m]:
                problems.append(f"src/varsfm/{m}/CMakeLists.txt: declares {dep}, which comes after "
                                f"{m} in DEVELOPERS.md's data-flow order")

    for m in folders:
        if m not in declared:
            continue
        allowed = closure(m, declared) | {m}
        for source in sorted((modules_dir / m).rglob("*")):
            if source.suffix not in (".h", ".cc") or not source.is_file():
                continue
            text = source.read_text(errors="replace")
            for match in INCLUDE.finditer(text):
                x = match.group(1)
                line = text.count("\n", 0, match.start()) + 1
                where = f"{source.relative_to(root)}:{line}"
                if x != m and x in rank and m in rank and rank[x] > rank[m]:
                    problems.append(f"{where}: includes varsfm/{x}/, which comes after {m} in "
                                    f"DEVELOPERS.md's data-flow order")
                elif x not in allowed:
                    problems.append(f"{where}: includes varsfm/{x}/, but src/varsfm/{m}/"
                                    f"CMakeLists.txt does not declare {x} (directly or through "
                                    f"the modules it declares)")

    for p in problems:
        print(p)
    if problems:
        print(f"{len(problems)} layering problem(s)", file=sys.stderr)
        return 1
    print(f"{len(folders)} modules: every include declared and in data-flow order")
    return 0


if __name__ == "__main__":
    sys.exit(main())
