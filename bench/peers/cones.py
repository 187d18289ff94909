#!/usr/bin/env python3
"""Side-by-side benchmark of span -> face conversions: polycone vs pycddlib (float and GMP).

Run from the repository root with the peers' virtualenv (see bench/peers/cones.md):

    "${STANCE_VENV:-.venv}/bin/python" bench/peers/cones.py [--repeats N] [--gmp-repeats M]

Both sides get the same inputs (bit-exact float64 generators): the project's golden cones
(testdata/cones), a stress corpus of near-degenerate stances, and generic stances of 16, 32, 48
and 64 generators. Answers are compared before any timing is reported. Times are medians per
conversion: polycone in a warm workspace (Rust, release build, `--example cone_bench`), cddlib
through pycddlib: `float` = matrix construction + conversion + copy of the inequalities,
`float core` = the conversion call alone.
"""

import argparse
import glob
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from fractions import Fraction

import numpy as np
import cdd
import cdd.gmp

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def rotation(axis, angle):
    x, y, z = np.asarray(axis, float) / np.linalg.norm(axis)
    s, c = np.sin(angle), np.cos(angle)
    t = 1 - c
    return np.array([
        [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
        [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
        [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
    ])


def giwc_generators(contacts):
    """-(f, p x f) for the pyramid edges (+-mu, +-mu, 1) at the 4 corners of each rectangle."""
    rows = []
    for pos, rot, half, mu in contacts:
        for sx, sy in [(1, 1), (1, -1), (-1, -1), (-1, 1)]:
            p = np.asarray(pos, float) + rot @ np.array([sx * half[0], sy * half[1], 0.0])
            for ex, ey in [(1, 1), (1, -1), (-1, -1), (-1, 1)]:
                f = rot @ np.array([ex * mu, ey * mu, 1.0])
                rows.append(np.concatenate([-f, -np.cross(p, f)]))
    return np.array(rows)


FOOT = (0.11, 0.065)


def double_support(offset=(0, 0, 0), dz=0.0, roll_deg=0.0, half=FOOT):
    o = np.asarray(offset, float)
    return [
        (o + [0, 0.1, 0], np.eye(3), half, 0.7),
        (o + [0.05, -0.1, dz], rotation([1, 0, 0], np.radians(roll_deg)), half, 0.7),
    ]


def generic_stance(k, seed):
    rng = np.random.default_rng(seed)
    contacts = []
    for _ in range(k):
        pos = rng.uniform(-0.5, 0.5, 3) * [1, 1, 0.4]
        rot = rotation(rng.normal(size=3), rng.uniform(0.05, 0.6))
        half = tuple(rng.uniform(0.03, 0.12, 2))
        contacts.append((pos, rot, half, rng.uniform(0.4, 1.0)))
    return contacts


def cases():
    out = []
    for f in sorted(glob.glob(os.path.join(ROOT, "testdata", "cones", "*.json"))):
        d = json.load(open(f))
        v = np.array([[float.fromhex(x) for x in r] for r in d["generators"]["float64_hex"]])
        out.append(("golden", os.path.basename(f)[:-5], v))
    stress = [
        ("origin_50m", double_support(offset=(50, 0, 0))),
        ("origin_1km", double_support(offset=(1000, -700, 30))),
        ("patch_1mm", double_support(half=(5e-4, 5e-4))),
        ("patch_10um", double_support(half=(5e-6, 5e-6))),
    ]
    stress += [(f"out_of_plane_{dz:g}", double_support(dz=dz)) for dz in (1e-5, 1e-7, 1e-9)]
    stress += [(f"rolled_{r:g}deg", double_support(roll_deg=r)) for r in (1, 0.1, 0.01)]
    for name, c in stress:
        out.append(("stress", name, giwc_generators(c)))
    for k in (1, 2, 3, 4):
        for seed in range(3):
            out.append((f"generic_{16 * k}", f"generic_{16 * k}_s{seed}", giwc_generators(generic_stance(k, 100 * k + seed))))
    return out


def cdd_float(v, repeats):
    rows = [[0.0] + list(r) for r in v]
    def run():
        m = cdd.matrix_from_array(rows, rep_type=cdd.RepType.GENERATOR)
        t0 = time.perf_counter()
        p = cdd.polyhedron_from_matrix(m)
        t1 = time.perf_counter()
        h = cdd.copy_inequalities(p)
        return h, t1 - t0
    times, core = [], []
    for _ in range(repeats):
        t0 = time.perf_counter()
        h, tc = run()
        times.append(time.perf_counter() - t0)
        core.append(tc)
    return h, 1e3 * statistics.median(times), 1e3 * statistics.median(core)


def cdd_gmp(v, repeats):
    rows = [[0] + [Fraction(float(x)) for x in r] for r in v]
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        m = cdd.gmp.matrix_from_array(rows, rep_type=cdd.RepType.GENERATOR)
        p = cdd.gmp.polyhedron_from_matrix(m)
        h = cdd.gmp.copy_inequalities(p)
        times.append(time.perf_counter() - t0)
    return h, 1e3 * statistics.median(times)


def facets_of(h):
    """Unit facet normals u (u . x <= 0) and equations from a cdd H-representation b + A x >= 0."""
    a = np.array([[float(x) for x in r] for r in h.array]) if len(h.array) else np.zeros((0, 1))
    lin = set(h.lin_set)
    fac = [-a[i, 1:] for i in range(len(a)) if i not in lin]
    eqs = [a[i, 1:] for i in range(len(a)) if i in lin]
    fac = np.array([f / np.linalg.norm(f) for f in fac]) if fac else np.zeros((0, a.shape[1] - 1))
    return fac, len(eqs)


def same_facets(a, b, max_angle=1e-6):
    a, b = np.asarray(a), np.asarray(b)
    if a.shape[0] != b.shape[0]:
        return False
    if a.shape[0] == 0:
        return True
    c = np.clip(a @ b.T, -1, 1)
    return bool(np.all(np.arccos(c.max(axis=1)) < max_angle) and np.all(np.arccos(c.max(axis=0)) < max_angle))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=50)
    ap.add_argument("--gmp-repeats", type=int, default=3)
    ap.add_argument("--json", help="also write the raw results to this file")
    ap.add_argument("--no-completeness", action="store_true",
                    help="also time polycone without the completeness check of its certificate "
                         "(soundness and support only), to show what the completeness proof costs")
    args = ap.parse_args()

    all_cases = cases()
    with tempfile.TemporaryDirectory() as tmp:
        inp = os.path.join(tmp, "cones.json")
        json.dump({"cases": [{"name": n, "generators_hex": [[float(x).hex() for x in r] for r in v]}
                             for _, n, v in all_cases]}, open(inp, "w"))
        subprocess.run(["cargo", "build", "--release", "-q", "-p", "polycone", "--example", "cone_bench"],
                       cwd=ROOT, check=True)
        exe = os.path.join(ROOT, "target", "release", "examples", "cone_bench")
        ours = json.loads(subprocess.run([exe, inp, str(args.repeats)], capture_output=True, check=True,
                                         text=True).stdout)["results"]
        # Without the completeness check: the same double description, a cheaper certificate.
        nc = [None] * len(all_cases)
        if args.no_completeness:
            nc = json.loads(subprocess.run([exe, inp, str(args.repeats), "--no-completeness"],
                                           capture_output=True, check=True, text=True).stdout)["results"]
        # Exact mode, against cddlib GMP (both exact for the input as given).
        exact = json.loads(subprocess.run([exe, inp, str(args.gmp_repeats), "--exact"], capture_output=True,
                                          check=True, text=True).stdout)["results"]

    rows = []
    print("Facet counts (ours, cdd float, cdd GMP on the same float input; cdd-f -1: cddlib float failed)")
    print(f"{'group':<12} {'case':<30} {'n':>3} {'ours':>5} {'cdd-f':>5} {'gmp':>5}  {'answer':<22} "
          f"{'ours ms':>9} {'cdd-f ms':>9} {'core ms':>9} {'gmp ms':>9} {'x float':>8} {'x core':>7} {'x gmp':>7}"
          f"  {'exact ms':>9} {'ex/gmp':>7}")
    for (group, name, v), r, rx, rn in zip(all_cases, ours, exact, nc):
        try:
            hf, tf, tcore = cdd_float(v, args.repeats)
            ff, ef = facets_of(hf)
        except RuntimeError:  # cddlib float gives up ("numerical inconsistency")
            tf = tcore = float("nan")
            ff, ef = np.zeros((0, v.shape[1])), -1
        hg, tg = cdd_gmp(v, args.gmp_repeats)
        fg, eg = facets_of(hg)
        if "error" in r:
            status, ours_n, t_ours = "ERROR: " + r["error"][:40], -1, float("nan")
        else:
            uf = np.array(r["facets"]) if r["facets"] else np.zeros((0, v.shape[1]))
            ours_n, t_ours = len(uf), r["median_ms"]
            # Compare first: exact answer for the input (cdd GMP), cdd float, or our certified
            # tolerance answer (merged degeneracy).
            if same_facets(uf, fg) and r["equations"] == eg:
                status = "= cdd GMP"
            elif same_facets(uf, ff) and r["equations"] == ef:
                status = "= cdd float (not GMP)"
            else:
                status = "tolerance (certified)" if r["certified"] else "DIFFERS, uncertified"
        nff = len(ff) if ef >= 0 else -1
        # Our exact mode must give cddlib GMP's answer; otherwise its time is not reported.
        t_exact = float("nan")
        if "error" not in rx:
            ux = np.array(rx["facets"]) if rx["facets"] else np.zeros((0, v.shape[1]))
            if rx["certified"] and same_facets(ux, fg) and rx["equations"] == eg:
                t_exact = rx["median_ms"]
            else:
                status += " / EXACT DIFFERS"
        # Without completeness: timed only when it returns the same facets as the certified run.
        t_nc = float("nan")
        if rn is not None and "error" not in rn and "error" not in r:
            un = np.array(rn["facets"]) if rn["facets"] else np.zeros((0, v.shape[1]))
            if same_facets(un, uf) and rn["equations"] == r["equations"]:
                t_nc = rn["median_ms"]
        rows.append(dict(group=group, name=name, n=len(v), ours=ours_n, cdd_float=nff, cdd_gmp=len(fg),
                         status=status, ours_ms=t_ours, float_ms=tf, core_ms=tcore, gmp_ms=tg,
                         exact_ms=t_exact, no_completeness_ms=t_nc))
        print(f"{group:<12} {name:<30} {len(v):>3} {ours_n:>5} {nff:>5} {len(fg):>5}  {status:<22} "
              f"{t_ours:>9.4f} {tf:>9.4f} {tcore:>9.4f} {tg:>9.3f} {tf / t_ours:>8.1f} {tcore / t_ours:>7.1f} "
              f"{tg / t_ours:>7.0f}  {t_exact:>9.3f} {tg / t_exact:>7.1f}")

    print()
    print("Median speed-ups of polycone (certified, tolerance mode) over pycddlib:")
    for label, sel in [("16 generators", lambda x: x["n"] == 16), ("32+ generators", lambda x: x["n"] >= 32)]:
        g = [x for x in rows if sel(x) and x["ours_ms"] == x["ours_ms"] and x["float_ms"] == x["float_ms"]]
        if g:
            print(f"  {label:<15} ({len(g):>2} cones): float x{statistics.median(x['float_ms'] / x['ours_ms'] for x in g):.1f}, "
                  f"float core x{statistics.median(x['core_ms'] / x['ours_ms'] for x in g):.1f}, "
                  f"GMP x{statistics.median(x['gmp_ms'] / x['ours_ms'] for x in g):.0f}")
    print("Median speed-up of polycone's exact mode over pycddlib GMP (same exact answer, checked):")
    for label, sel in [("16 generators", lambda x: x["n"] == 16), ("32+ generators", lambda x: x["n"] >= 32)]:
        g = [x for x in rows if sel(x) and x["exact_ms"] == x["exact_ms"]]
        if g:
            print(f"  {label:<15} ({len(g):>2} cones): x{statistics.median(x['gmp_ms'] / x['exact_ms'] for x in g):.2f}")
    if args.no_completeness:
        print()
        print("The certificate's completeness proof (same run; 'no-compl': soundness and support only, "
              "the checks cddlib's wrong float outputs also pass; '-': a different answer, not timed):")
        print(f"{'case':<30} {'n':>3} {'ours ms':>9} {'no-compl ms':>12} {'share':>6} {'x float':>8} "
              f"{'x float no-compl':>17}")
        for x in rows:
            if x["no_completeness_ms"] == x["no_completeness_ms"]:
                share = 1.0 - x["no_completeness_ms"] / x["ours_ms"]
                print(f"{x['name']:<30} {x['n']:>3} {x['ours_ms']:>9.4f} {x['no_completeness_ms']:>12.4f} "
                      f"{share:>6.0%} {x['float_ms'] / x['ours_ms']:>8.1f} "
                      f"{x['float_ms'] / x['no_completeness_ms']:>17.1f}")
            else:
                print(f"{x['name']:<30} {x['n']:>3} {x['ours_ms']:>9.4f} {'-':>12}")
        print("Median speed-ups over pycddlib float without the completeness check:")
        for label, sel in [("16 generators", lambda x: x["n"] == 16), ("32+ generators", lambda x: x["n"] >= 32)]:
            g = [x for x in rows if sel(x) and x["no_completeness_ms"] == x["no_completeness_ms"]
                 and x["float_ms"] == x["float_ms"]]
            if g:
                print(f"  {label:<15} ({len(g):>2} cones): x{statistics.median(x['float_ms'] / x['no_completeness_ms'] for x in g):.1f}"
                      f" (certified on the same cones: x{statistics.median(x['float_ms'] / x['ours_ms'] for x in g):.1f})")
    if args.json:
        json.dump(rows, open(args.json, "w"), indent=1)


if __name__ == "__main__":
    sys.exit(main())
