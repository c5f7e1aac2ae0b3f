#!/usr/bin/env python3
"""The project's size limits on its sources: no file above MAX_FILE lines, no function above
MAX_FUNCTION lines (DEVELOPERS.md, Standards). Run by ctest (`source_size_limits`) so they stay
true.

usage: check_source_size.py [--max-file N] [--max-function N] [--list]
                            [--allow PATH_SUFFIX:FUNCTION]... FOLDER_OR_FILE...

--allow names a function known to be too long whose owner is to split it: reported, not failed.

A function is a brace block opened at namespace or class scope whose head (the text since the
previous `;`, `{` or `}`) is not a namespace, class, struct, union, enum, `extern "C"` or an
initialiser (`=`). Its length runs from the head's first line to its closing brace. Comments,
string and character literals are blanked first so their braces do not count; lambdas and local
classes count towards the function that holds them. Exit 1 with one line per violation.
"""
import argparse
import pathlib
import re
import sys

SOURCE_SUFFIXES = {".cc", ".h", ".cpp", ".hpp"}
NOT_A_FUNCTION = re.compile(r"^(template\s*<.*>\s*)?(namespace|class|struct|union|enum)\b|^extern\b",
                            re.S)
NEXT_CHARACTER = re.compile(r"\s*(\S)")


def blank_comments_and_literals(text):
    """`text` with comments and string/char literals replaced by spaces (newlines kept)."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == "R" and text.startswith('R"', i) and (i == 0 or not text[i - 1].isalnum()):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            if not m:
                out.append(c)
                i += 1
                continue
            end = text.find(")" + m.group(1) + '"', i)
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c in "\"'":
            # A digit separator (1'000'000) is not a character literal.
            if c == "'" and i > 0 and text[i - 1].isalnum() and i + 1 < n and text[i + 1].isalnum():
                out.append(c)
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            out.append(c + re.sub(r"[^\n]", " ", text[i + 1:j - 1]) + c if j - i >= 2 else c)
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


def functions(text):
    """(name, first line, last line) of every function body at namespace or class scope."""
    code = blank_comments_and_literals(text)
    # Preprocessor lines carry no braces of the program's structure.
    code = re.sub(r"(?m)^[ \t]*#.*(\\\n.*)*$", lambda m: re.sub(r"[^\n]", " ", m.group(0)), code)
    found = []
    stack = []  # for each open brace: (kind, head start offset)
    head_start = 0
    for i, c in enumerate(code):
        if c == "{":
            in_function = any(kind in ("function", "initializer") for kind, _ in stack)
            head = code[head_start:i].strip()
            before_parameters = head.split("(")[0]
            if in_function:
                kind = "inner"
            elif "=" in before_parameters and "operator" not in before_parameters:
                kind = "initializer"  # a variable's braced or lambda initialiser
            elif NOT_A_FUNCTION.match(head) or not head:
                kind = "scope"
            else:
                kind = "function"
            # The head starts at its first non-blank character.
            start = head_start + (len(code[head_start:i]) - len(code[head_start:i].lstrip()))
            stack.append((kind, start))
            head_start = i + 1
        elif c == "}":
            if stack:
                kind, start = stack.pop()
                following = NEXT_CHARACTER.match(code, i + 1)
                if kind == "function" and following and following.group(1) in ("{", ","):
                    # A member's braced initialiser in a constructor's initialiser list: the
                    # constructor's head goes on.
                    head_start = start
                    continue
                if kind == "function":
                    first = code.count("\n", 0, start) + 1
                    last = code.count("\n", 0, i) + 1
                    name = re.sub(r"\s+", " ", code[start:code.find("(", start, i) if "(" in code[start:i] else i])
                    found.append((name.strip().split(" ")[-1] or "?", first, last))
            head_start = i + 1
        elif c == ";":
            head_start = i + 1
    return found


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--max-file", type=int, default=800)
    parser.add_argument("--max-function", type=int, default=150)
    parser.add_argument("--list", action="store_true", help="print every function's length")
    parser.add_argument("--allow", action="append", default=[],
                        help="PATH_SUFFIX:FUNCTION reported but not failed")
    parser.add_argument("folders", nargs="+")
    args = parser.parse_args()
    problems = []
    for folder in args.folders:
        root = pathlib.Path(folder)
        for path in [root] if root.is_file() else sorted(root.rglob("*")):
            if path.suffix not in SOURCE_SUFFIXES or not path.is_file():
                continue
            text = path.read_text(encoding="utf-8", errors="replace")
            lines = text.count("\n") + (0 if text.endswith("\n") else 1)
            if lines > args.max_file:
                problems.append(f"{path}: {lines} lines (at most {args.max_file})")
            for name, first, last in functions(text):
                length = last - first + 1
                if args.list:
                    print(f"{length:5d} {path}:{first} {name}")
                allowed = any(str(path).endswith(a.rsplit(":", 1)[0]) and name == a.rsplit(":", 1)[1]
                              for a in args.allow)
                if length > args.max_function and allowed:
                    print(f"{path}:{first}: function {name} has {length} lines (allowed for now)")
                elif length > args.max_function:
                    problems.append(f"{path}:{first}: function {name} has {length} lines "
                                    f"(at most {args.max_function})")
    for p in problems:
        print(p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
