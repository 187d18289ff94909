#!/usr/bin/env python3
"""Lists the Rust functions longer than N lines (default 150) in `crates/*/src/**/*.rs`.

A function's length counts the lines from the line of its `fn` keyword to the line of the
closing brace of its body, both included (attributes and doc comments above it are not
counted). Bodies are found by brace matching that skips comments (`//`, nested `/* */`),
string literals (including raw strings `r#"..."#` and byte strings) and char literals (told
apart from lifetimes). Functions without a body (trait declarations) are skipped; functions
nested in others, and those written inside macro calls (`proptest! { fn ... }`), count on
their own.

Exits 1 if any function is longer than N lines, 0 otherwise.

    python3 scripts/fn-lengths.py                    # every crate, N = 150
    python3 scripts/fn-lengths.py --max-lines 100    # another N
    python3 scripts/fn-lengths.py --summary          # also the longest function per crate
    python3 scripts/fn-lengths.py crates/polycone    # some crates only
"""

import argparse
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent


def is_ident(c):
    return c.isalnum() or c == "_"


def code_mask(text):
    """`text` with every character of a comment, string or char literal replaced by a space
    (newlines kept), so that keywords and braces can be found by plain scanning."""
    out = list(text)
    n = len(text)
    i = 0

    def blank(a, b):
        for k in range(a, min(b, n)):
            if out[k] != "\n":
                out[k] = " "

    while i < n:
        c = text[i]
        if c == "/" and text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            blank(i, j)
            i = j
        elif c == "/" and text.startswith("/*", i):
            depth, j = 1, i + 2
            while j < n and depth:
                if text.startswith("/*", j):
                    depth, j = depth + 1, j + 2
                elif text.startswith("*/", j):
                    depth, j = depth - 1, j + 2
                else:
                    j += 1
            blank(i, j)
            i = j
        elif c in "rb" and (i == 0 or not is_ident(text[i - 1])):
            # raw string r"..", r#".."#, br#".."#; byte string b".."; else an identifier
            j = i + 1
            if c == "b" and j < n and text[j] == "r":
                j += 1
            raw = text[i] == "r" or (j > i + 1)
            hashes = 0
            while raw and j < n and text[j] == "#":
                hashes, j = hashes + 1, j + 1
            if j < n and text[j] == '"' and raw:
                close = '"' + "#" * hashes
                k = text.find(close, j + 1)
                k = n if k < 0 else k + len(close)
                blank(i, k)
                i = k
            elif c == "b" and j == i + 1 and j < n and text[j] in "\"'":
                i = j  # the literal is handled from its quote
            else:
                while i < n and is_ident(text[i]):
                    i += 1
        elif is_ident(c):
            while i < n and is_ident(text[i]):
                i += 1
        elif c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            blank(i, j + 1)
            i = j + 1
        elif c == "'":
            # a char literal ('x', '\n', '\u{..}', '{') or a lifetime / label ('a)
            if i + 1 < n and text[i + 1] == "\\":
                j = i + 3  # past the escaped character ('\'' included)
                while j < n and text[j] != "'":
                    j += 1
                blank(i, j + 1)
                i = j + 1
            elif i + 2 < n and text[i + 2] == "'":
                blank(i, i + 3)
                i += 3
            else:
                i += 1
        else:
            i += 1
    return "".join(out)


def functions(text):
    """(name, first line, last line) of every function with a body in `text`."""
    code = code_mask(text)
    n = len(code)
    line_starts = [0]
    for k, ch in enumerate(code):
        if ch == "\n":
            line_starts.append(k + 1)

    def line_of(pos):
        lo, hi = 0, len(line_starts) - 1
        while lo < hi:
            mid = (lo + hi + 1) // 2
            if line_starts[mid] <= pos:
                lo = mid
            else:
                hi = mid - 1
        return lo + 1

    out = []
    i = code.find("fn")
    while i >= 0:
        before_ok = i == 0 or not is_ident(code[i - 1])
        j = i + 2
        if before_ok and j < n and code[j].isspace():
            while j < n and code[j].isspace():
                j += 1
            k = j
            while k < n and is_ident(code[k]):
                k += 1
            name = code[j:k]
            if name:
                # the body's `{`, or `;` for a declaration, outside (), [] and <>-free nesting
                depth, m = 0, k
                while m < n:
                    ch = code[m]
                    if ch in "([":
                        depth += 1
                    elif ch in ")]":
                        depth -= 1
                    elif depth == 0 and ch in "{;":
                        break
                    m += 1
                if m < n and code[m] == "{":
                    braces, e = 0, m
                    while e < n:
                        if code[e] == "{":
                            braces += 1
                        elif code[e] == "}":
                            braces -= 1
                            if braces == 0:
                                break
                        e += 1
                    out.append((name, line_of(i), line_of(min(e, n - 1))))
        i = code.find("fn", i + 2)
    return out


def crate_of(path):
    rel = path.relative_to(ROOT).parts
    return rel[1] if len(rel) > 1 and rel[0] == "crates" else str(path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("crates", nargs="*", help="crate directories (default: crates/*)")
    ap.add_argument("-n", "--max-lines", type=int, default=150, help="N (default 150)")
    ap.add_argument("--summary", action="store_true", help="the longest function per crate")
    args = ap.parse_args()

    dirs = [pathlib.Path(c).resolve() for c in args.crates] or sorted(
        p for p in (ROOT / "crates").iterdir() if (p / "src").is_dir()
    )
    offenders = []
    longest = {}
    for d in dirs:
        for path in sorted((d / "src").rglob("*.rs")):
            text = path.read_text(encoding="utf-8")
            for name, first, last in functions(text):
                length = last - first + 1
                crate = crate_of(path)
                rel = path.relative_to(ROOT)
                if crate not in longest or length > longest[crate][0]:
                    longest[crate] = (length, f"{rel}:{first}", name)
                if length > args.max_lines:
                    offenders.append((length, f"{rel}:{first}", name))
            longest.setdefault(crate_of(path), (0, "", ""))
    for length, where, name in sorted(offenders, key=lambda o: (o[1].split(":")[0], -o[0])):
        print(f"{where}: fn {name}: {length} lines")
    if args.summary:
        print(f"{'crate':20} {'longest':>7}  function")
        for crate, (length, where, name) in sorted(longest.items()):
            print(f"{crate:20} {length:7}  {name} ({where})")
    if offenders:
        print(
            f"{len(offenders)} function(s) longer than {args.max_lines} lines",
            file=sys.stderr,
        )
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
