#!/usr/bin/env python3
"""Before/after timing of two polycone `cone_bench` runner builds on the inputs of cones.py.

    "${STANCE_VENV:-.venv}/bin/python" bench/peers/cones_ab.py BEFORE_BIN AFTER_BIN \
        [--repeats N] [--rounds R]

Both binaries are `cargo build --release -p polycone --example cone_bench` builds of two
revisions (copy the first one aside before building the second). The runs alternate
(before, after, before, after, ...) so that both see the same machine load; the minimum over
rounds of each runner's median is reported. Before any timing is printed, the two answers are
compared: same facet counts, both certified, and the largest entry-wise difference of the
facet matrices (0 means bit-identical output). Cases that need the exact fallback (slow) are
skipped.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cones  # noqa: E402  (the same inputs as the peer benchmark)

SKIP = {"rolled_0.01deg"}  # exact fallback: seconds per run, not what this compares


def run(binary, path, repeats):
    out = subprocess.run([binary, path, str(repeats)], check=True, capture_output=True, text=True)
    return {r["name"]: r for r in json.loads(out.stdout)["results"]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--repeats", type=int, default=300)
    ap.add_argument("--rounds", type=int, default=2)
    args = ap.parse_args()
    cases = [(g, n, v) for g, n, v in cones.cases() if n not in SKIP]
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "cases.json")
        with open(path, "w") as f:
            json.dump({"cases": [{"name": n, "generators_hex": [[float(x).hex() for x in r] for r in v]}
                                 for _, n, v in cases]}, f)
        before, after = [], []
        for _ in range(args.rounds):
            before.append(run(args.before, path, args.repeats))
            after.append(run(args.after, path, args.repeats))
    ratios = {}
    print(f'{"case":30s} {"facets":>6s} {"before us":>10s} {"after us":>9s} {"x":>6s} {"max |diff|":>10s}')
    for group, name, v in cases:
        b, a = before[0][name], after[0][name]
        if "error" in b or "error" in a:
            sys.exit(f"{name}: runner error: {b.get('error')} / {a.get('error')}")
        if b["facets_count"] != a["facets_count"] or not (a["certified"] and b["certified"]):
            sys.exit(f"{name}: answers differ ({b['facets_count']} vs {a['facets_count']} facets)")
        diff = max((max(abs(x - y) for x, y in zip(r, s)) for r, s in zip(b["facets"], a["facets"])),
                   default=0.0)
        tb = min(r[name]["median_ms"] for r in before) * 1e3
        ta = min(r[name]["median_ms"] for r in after) * 1e3
        ratios.setdefault(len(v) == 16, []).append(tb / ta)
        print(f"{name:30s} {a['facets_count']:6d} {tb:10.1f} {ta:9.1f} {tb / ta:6.2f} {diff:10.1e}")
    print(f"median after/before speed-up: 16 generators x{statistics.median(ratios[True]):.2f}, "
          f"32+ generators x{statistics.median(ratios[False]):.2f}")


if __name__ == "__main__":
    main()
