#!/usr/bin/env python3
"""Check (default) or regenerate the golden wrench cones of testdata/cones/ with pycddlib.

Each golden file holds the generators ``v_1 .. v_n`` of a 6-D cone
``C = {sum_i z_i v_i : z >= 0}`` (one generator per row) in two forms:

- ``generators.exact``: the intended geometry, exact rationals ``"p/q"``;
- ``generators.float64_hex``: the same numbers rounded to float64 (bit-exact, ``float.hex``).

and the face form ``C = {x : U x <= 0, E x = 0}`` computed from them by cddlib (through pycddlib):

(a) ``reference_cdd_gmp_exact_input``: cddlib in GMP exact mode on the exact generators:
    ``facets`` (rows of U, exact), ``facets_float64`` (each of them rounded to float64),
    ``equations`` (rows of E, exact) and ``lineality_dim``;
(b) ``cdd_float``: cddlib in floating-point mode on the float64 generators: ``facets``,
    ``equations``.

How the face form is obtained. pycddlib is given the V-representation ``[0 v_i]`` (a leading 0
marks a ray) and returns an H-representation ``[b_j A_j]`` meaning ``b_j + A_j x >= 0`` (``= 0``
for the rows in ``lin_set``). For a cone every ``b_j`` is 0; a row with ``A_j = 0`` (the trivial
``1 >= 0``) carries no information and is dropped. A row outside ``lin_set`` gives the facet
``U_j = -A_j`` (so that ``U_j x <= 0``); a row inside gives the equation ``E_j = A_j``. The stored
references are exactly these rows, in cddlib's order.

The lineality space of ``{x : U x <= 0, E x = 0}`` is the null space of ``[U; E]``, so
``lineality_dim = 6 - rank [U; E]`` (exact rank over the rationals).

``summary`` is checked too: the counts, and ``extreme_generators_exact``, the number of extreme
rays of the exact cone when it is pointed (``None`` when it is not: a cone with a lineality space
has no extreme ray). A nonzero generator ``v`` of a pointed cone spans an extreme ray iff the
facets tight at ``v`` (``U_j v = 0``) together with E have rank ``6 - 1``; rays are counted once
up to positive scaling. ``summary.time_ms`` is left alone.

``README.md`` also quotes the facet counts of cddlib's GMP mode on the float64 inputs read as
exact rationals (``Fraction(x)`` of each float, used by crates/polycone/tests/exact.rs); they are
recomputed and checked against ``ROUNDED_INPUT_FACETS`` below (they are not stored in the files).

How agreement is judged (``--check``):

- inputs: ``generators.float64`` and ``float64_hex`` are the same floats, and each is the correctly
  rounded value of ``generators.exact`` (Python's ``float(Fraction)`` rounds correctly);
- exact facets: the same set of rays up to positive scaling, exactly: each row is divided by its
  largest absolute entry (a positive factor) and the two multisets of scaled rows must be equal;
- exact equations: the same number, spanning the same space: ``rank E_ref = rank E_new =
  rank [E_ref; E_new]`` (exact);
- ``lineality_dim``: equal; ``facets_float64``: bit-equal to ``float(Fraction(facet))``;
- float part: each row scaled to unit Euclidean norm; the facets must match one to one (as sets,
  order ignored) within 1e-9 in every component; the equations must have the same count and span
  the same space within 1e-9 (orthonormal bases, projection residual).

``--write`` stores the recomputed values in those fields (and the counts of ``summary``), keeping
the key order and every other field; the files are written as ``json.dumps(..., indent=1)``, the
layout they had when copied, so unchanged values stay byte-identical (a file that was not in that
layout is reported when written, and rewritten in that layout anyway).

The versions it ran with are printed, with a warning when one differs from ``RECORDED`` (the
versions the references were produced and last checked with).

Usage, from the repository root, after ``bash scripts/setup-venv.sh --peers``:

    .venv/bin/python testdata/cones/regenerate.py [--check | --write] [FILE.json ...]
"""

import argparse
import glob
import importlib.metadata
import json
import math
import os
import platform
import re
import sys
import time
from collections import Counter
from fractions import Fraction

import cdd
import cdd.gmp
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))

# The references were produced with pycddlib 3.0.2 on cddlib 0.94m; Python and NumPy are the
# versions this script last passed `--check` with.
RECORDED = {"Python": "3.11.7", "pycddlib": "3.0.2", "cddlib": "0.94m", "numpy": "2.4.6"}

# Facet counts of cddlib's GMP mode on the float64 inputs taken as exact rationals, as quoted in
# README.md (and used by crates/polycone/tests/exact.rs).
ROUNDED_INPUT_FACETS = {
    "single_support_flat": 16,
    "surface_cwc_foot": 16,
    "double_support_flat": 32,
    "opposing_walls_frictionless": 4,
    "opposing_walls_friction": 0,
    "double_support_stairs": 282,
    "tilted_foot_hand_ledge": 249,
}

FLOAT_TOL = 1e-9
JSON_LAYOUT = {"indent": 1}


# ----------------------------------------------------------------------------- versions

def cddlib_version():
    """cddlib's version ("0.94m"), read from the "Version x.y" string compiled into the library
    that pycddlib loaded (found through /proc/self/maps on Linux; the extension modules themselves
    are searched too, for builds that link cddlib statically). None when not found."""
    paths = [cdd.__file__, cdd.gmp.__file__]
    try:
        with open("/proc/self/maps") as f:
            for line in f:
                path = line.split()[-1]
                if path.startswith("/") and "cdd" in os.path.basename(path):
                    paths.append(path)
    except OSError:
        pass
    found = set()
    for path in dict.fromkeys(paths):
        try:
            with open(path, "rb") as f:
                m = re.search(rb"Version (\d+\.\d+[a-z]?)\b", f.read())
        except OSError:
            continue
        if m:
            found.add(m.group(1).decode())
    return " / ".join(sorted(found)) if found else None


def report_versions():
    running = {
        "Python": platform.python_version(),
        "pycddlib": importlib.metadata.version("pycddlib"),
        "cddlib": cddlib_version() or "unknown",
        "numpy": np.__version__,
    }
    print("versions: " + ", ".join(f"{k} {v}" for k, v in running.items()))
    for k, v in running.items():
        if v != RECORDED[k]:
            print(f"WARNING: running {k} {v}, the references were recorded with {k} {RECORDED[k]}",
                  file=sys.stderr)


# ----------------------------------------------------------------------------- exact helpers

def integer_row(row):
    """`row` (Fractions or ints) times a positive rational making it a primitive vector of Python
    ints: the same ray, and the same rank in any set of rows."""
    den = math.lcm(*(Fraction(x).denominator for x in row))
    ints = [int(Fraction(x) * den) for x in row]
    g = math.gcd(*ints) or 1
    return [x // g for x in ints]


def rank_q(rows):
    """Exact rank of a list of rational rows (fraction-free Gaussian elimination on integers)."""
    m = [integer_row(r) for r in rows if any(r)]
    rank = 0
    for col in range(len(m[0]) if m else 0):
        piv = next((i for i in range(rank, len(m)) if m[i][col] != 0), None)
        if piv is None:
            continue
        m[rank], m[piv] = m[piv], m[rank]
        p = m[rank]
        for i in range(rank + 1, len(m)):
            if m[i][col] != 0:
                row = [p[col] * x - m[i][col] * y for x, y in zip(m[i], p)]
                g = math.gcd(*row) or 1
                m[i] = [x // g for x in row]
        rank += 1
        if rank == len(m):
            break
    return rank


def ray_key(row):
    """Representative of the ray of `row` up to positive scaling: divided by max |entry|."""
    s = max(abs(x) for x in row)
    return tuple(x / s for x in row)


def q(s):
    return Fraction(s)


def q_str(x):
    return str(Fraction(x))


# ----------------------------------------------------------------------------- cddlib

def face_form(h):
    """Facets U (U x <= 0) and equations E (E x = 0) from a cdd H-representation of a cone."""
    facets, equations = [], []
    lin = set(h.lin_set)
    for j, row in enumerate(h.array):
        b, a = row[0], list(row[1:])
        if not any(a):
            if b < 0:
                raise RuntimeError("cddlib returned an infeasible row 'b >= 0' with b < 0")
            continue  # the trivial row 1 >= 0
        if b != 0:
            raise RuntimeError(f"cddlib returned a non-homogeneous row for a cone: b = {b}")
        if j in lin:
            equations.append(a)
        else:
            facets.append([-x for x in a])
    return facets, equations


def cdd_gmp(generators):
    mat = cdd.gmp.matrix_from_array([[Fraction(0)] + list(g) for g in generators],
                                    rep_type=cdd.RepType.GENERATOR)
    return face_form(cdd.gmp.copy_inequalities(cdd.gmp.polyhedron_from_matrix(mat)))


def cdd_float(generators):
    mat = cdd.matrix_from_array([[0.0] + list(g) for g in generators],
                                rep_type=cdd.RepType.GENERATOR)
    return face_form(cdd.copy_inequalities(cdd.polyhedron_from_matrix(mat)))


def extreme_rays(generators, facets, equations, dim):
    """Number of extreme rays (distinct up to positive scaling) among the generators of a pointed
    cone with face form (facets, equations): v is extreme iff rank(tight facets + E) = dim - 1.
    (Rows are first scaled to integers, which changes no ray and no rank, to keep it fast.)"""
    facets = [integer_row(u) for u in facets]
    equations = [integer_row(e) for e in equations]
    rays = set()
    for v in generators:
        if not any(v):
            continue
        v = integer_row(v)
        tight = [u for u in facets if sum(a * b for a, b in zip(u, v)) == 0]
        if rank_q(tight + equations) == dim - 1:
            rays.add(tuple(v))
    return len(rays)


# ----------------------------------------------------------------------------- float helpers

def unit_rows(rows, d):
    a = np.array(rows, dtype=float).reshape(-1, d)
    return a / np.linalg.norm(a, axis=1, keepdims=True) if len(a) else a


def facet_set_deviation(new, ref, d):
    """Largest component difference between matched unit rows (one-to-one, order ignored), or
    None when the rows cannot be matched one to one within FLOAT_TOL."""
    a, b = unit_rows(new, d), unit_rows(ref, d)
    if a.shape != b.shape:
        return None
    if len(a) == 0:
        return 0.0
    dist = np.abs(a[:, None, :] - b[None, :, :]).max(axis=2)
    nearest = dist.argmin(axis=1)
    dev = dist[np.arange(len(a)), nearest]
    if len(set(nearest.tolist())) != len(a) or dev.max() > FLOAT_TOL:
        return None
    return float(dev.max())


def span_deviation(new, ref, d):
    """Projection residual between the spans of two sets of rows (same count required)."""
    a, b = np.array(new, dtype=float).reshape(-1, d), np.array(ref, dtype=float).reshape(-1, d)
    if a.shape != b.shape:
        return None
    if len(a) == 0:
        return 0.0
    qa = np.linalg.svd(a, full_matrices=False)[2]
    qb = np.linalg.svd(b, full_matrices=False)[2]
    return float(max(np.abs(qa - (qa @ qb.T) @ qb).max(), np.abs(qb - (qb @ qa.T) @ qa).max()))


# ----------------------------------------------------------------------------- one file

def process(path, write):
    """Recomputes one golden file; returns (ok, message)."""
    with open(path) as f:
        raw = f.read()
    doc = json.loads(raw)
    name = doc.get("case", os.path.basename(path))
    d = doc["dim"]
    gens = doc["generators"]
    problems = []

    # Inputs: the three forms of the generators agree.
    g_exact = [[q(x) for x in r] for r in gens["exact"]]
    g_float = [[float.fromhex(x) for x in r] for r in gens["float64_hex"]]
    if g_float != [[float(x) for x in r] for r in gens["float64"]]:
        problems.append("generators.float64 != float64_hex")
    if g_float != [[float(x) for x in r] for r in g_exact]:
        problems.append("float64 generators are not the rounding of the exact ones")

    # (a) GMP exact mode on the exact generators.
    facets, equations = cdd_gmp(g_exact)
    lineality = d - rank_q(facets + equations)
    ext = extreme_rays(g_exact, facets, equations, d) if lineality == 0 else None
    new_exact = {
        "facets": [[q_str(x) for x in r] for r in facets],
        "facets_float64": [[float(x) for x in r] for r in facets],
        "equations": [[q_str(x) for x in r] for r in equations],
        "lineality_dim": lineality,
    }
    # (b) float mode on the float64 generators.
    f_facets, f_equations = cdd_float(g_float)
    new_float = {"facets": [[float(x) for x in r] for r in f_facets],
                 "equations": [[float(x) for x in r] for r in f_equations]}
    new_summary = {"generators": len(g_exact), "facets_exact": len(facets),
                   "equations_exact": len(equations), "lineality_dim": lineality,
                   "extreme_generators_exact": ext}
    # GMP mode on the float64 inputs read exactly (counts quoted in README.md).
    r_facets, _ = cdd_gmp([[Fraction(x) for x in r] for r in g_float])

    ref = doc["reference_cdd_gmp_exact_input"]
    ref_f = doc["cdd_float"]
    summ = doc["summary"]
    # Exact part.
    ref_facets = [[q(x) for x in r] for r in ref["facets"]]
    if Counter(map(ray_key, ref_facets)) != Counter(map(ray_key, facets)):
        problems.append(f"exact facets differ ({len(facets)} recomputed, {len(ref_facets)} stored)")
    ref_eq = [[q(x) for x in r] for r in ref["equations"]]
    re_, rn = rank_q(ref_eq), rank_q(equations)
    if len(ref_eq) != len(equations) or not re_ == rn == rank_q(ref_eq + equations):
        problems.append("exact equations span a different space")
    if ref["lineality_dim"] != lineality:
        problems.append(f"lineality_dim {lineality} recomputed, {ref['lineality_dim']} stored")
    if ref["facets_float64"] != [[float(x) for x in r] for r in ref_facets]:
        problems.append("facets_float64 is not the float64 rounding of facets")
    # Float part.
    dev_f = facet_set_deviation(new_float["facets"], ref_f["facets"], d)
    if dev_f is None:
        problems.append(f"float facets differ ({len(f_facets)} recomputed, "
                        f"{len(ref_f['facets'])} stored, tolerance {FLOAT_TOL:g})")
    dev_e = span_deviation(new_float["equations"], ref_f["equations"], d)
    if dev_e is None or dev_e > FLOAT_TOL:
        problems.append("float equations differ")
    bit_identical = new_float == {"facets": ref_f["facets"], "equations": ref_f["equations"]}
    # Summary counts and README counts.
    for k, v in new_summary.items():
        if summ.get(k) != v:
            problems.append(f"summary.{k} {summ.get(k)} stored, {v} recomputed")
    want_rounded = ROUNDED_INPUT_FACETS.get(name)
    if want_rounded is not None and want_rounded != len(r_facets):
        problems.append(f"GMP on the float64 inputs: {len(r_facets)} facets, "
                        f"README says {want_rounded}")

    desc = (f"exact {len(facets)} facets, {len(equations)} eq., lineality {lineality}, "
            f"{'-' if ext is None else ext} extreme rays; float {len(f_facets)} facets "
            + ("(bit-identical)" if bit_identical else
               f"(max dev {dev_f:.1e})" if dev_f is not None else "(no match)")
            + f"; GMP on float64 input {len(r_facets)} facets")

    if write:
        for k, v in new_exact.items():
            ref[k] = v
        for k, v in new_float.items():
            ref_f[k] = v
        for k, v in new_summary.items():
            summ[k] = v
        text = json.dumps(doc, **JSON_LAYOUT)
        if text == raw:
            return True, f"unchanged  {name}: {desc}"
        with open(path, "w") as f:
            f.write(text)
        note = "" if json.dumps(json.loads(raw), **JSON_LAYOUT) == raw else \
            " (the file's layout was not indent=1 JSON: reformatted)"
        what = "; was: " + "; ".join(problems) if problems else ""
        return True, f"rewritten  {name}: {desc}{note}{what}"

    if problems:
        return False, f"FAIL  {name}: " + "; ".join(problems) + f" [{desc}]"
    return True, f"ok    {name}: {desc}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    mode = ap.add_mutually_exclusive_group()
    mode.add_argument("--check", action="store_true",
                      help="compare with the stored references (default)")
    mode.add_argument("--write", action="store_true",
                      help="rewrite the reference fields with the recomputed values")
    ap.add_argument("files", nargs="*", help="golden files (default: all of testdata/cones)")
    args = ap.parse_args()
    files = args.files or sorted(glob.glob(os.path.join(HERE, "*.json")))

    t0 = time.perf_counter()
    report_versions()
    ok = True
    for path in files:
        good, msg = process(path, args.write)
        ok &= good
        print(msg, flush=True)
    elapsed = time.perf_counter() - t0
    verdict = "rewritten" if args.write else ("all agree" if ok else "DISAGREEMENT")
    print(f"{len(files)} cone files, {elapsed:.1f} s: {verdict}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
