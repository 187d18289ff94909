#!/usr/bin/env python3
"""Side-by-side benchmark of stance-topp against toppra (Python package, seidel solver wrapper).

Same rows a, b, c, same grid, same discretization, rest to rest. Durations are compared first
(the run stops if they disagree), then solve times are measured and printed with their ratios.

Instances: the two shared N = 100 instances of testdata/topp/ and N = 1000 versions made here by
evaluating the same U and CoM path (p0 + s (p1 - p0) + sin(pi s) bow, recovered from the
samples) on a finer grid with the paper's eq. 14; the N = 1000 toppra durations are checked
against the reference values stored in the instance files.

Usage (from the repository root):
    STANCE_VENV=/path/to/venv bash scripts/setup-venv.sh --peers   # once
    $STANCE_VENV/bin/python bench/peers/topp.py [--quick]
    $STANCE_VENV/bin/python bench/peers/topp.py --write-instances INSTANCES.json  # runners' input
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
import toppra
import toppra.algorithm as algo
import toppra.constraint as tc

# The binaries run here find JVRC-1 and MuJoCo in this virtualenv (the one running this script).
os.environ.setdefault("STANCE_VENV", sys.prefix)

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
NAMES = ["ds_flat", "mc_minvel"]
DISC = {"collocation": tc.DiscretizationType.Collocation,
        "interpolation": tc.DiscretizationType.Interpolation}


class CanonicalRows(tc.LinearConstraint):
    """Precomputed rows a u + b x + c <= 0 (F = I, g = 0), converted by toppra itself to
    first-order interpolation when asked."""

    def __init__(self, a, b, c, disc):
        super().__init__()
        self.a, self.b, self.c = a, b, c
        m = a.shape[1]
        self.F, self.g = np.eye(m), np.zeros(m)
        self.identical = True
        self.set_discretization_type(disc)

    def compute_constraint_params(self, path, gridpoints, *args, **kwargs):
        if self.discretization_type == tc.DiscretizationType.Interpolation:
            return tc.canlinear_colloc_to_interpolate(
                self.a, self.b, self.c, self.F, self.g, None, None, gridpoints, identical=True)
        return self.a, self.b, self.c, self.F, self.g, None, None


def bow_of(inst):
    p = np.array(inst["com_path"]["p"])
    ps = np.array(inst["com_path"]["ps"])
    p0, p1 = p[0], p[-1]
    return p0, p1, (ps[0] - (p1 - p0)) / np.pi


def eq14(U, mass, g, s, p0, p1, bow):
    """Rows of the paper's eq. 14 (point mass, L = 0) on grid s."""
    sn, cs = np.sin(np.pi * s)[:, None], np.cos(np.pi * s)[:, None]
    p = p0 + s[:, None] * (p1 - p0) + sn * bow
    ps = (p1 - p0) + np.pi * cs * bow
    pss = -np.pi ** 2 * sn * bow
    g = np.asarray(g)
    wa = -np.hstack([mass * ps, mass * np.cross(p, ps)])
    wb = -np.hstack([mass * pss, mass * np.cross(p, pss)])
    wc = np.hstack([np.tile(mass * g, (len(s), 1)), mass * np.cross(p, np.tile(g, (len(s), 1)))])
    return wa @ U.T, wb @ U.T, wc @ U.T


def toppra_run(s, a, b, c, disc, reps):
    path = toppra.SplineInterpolator([0.0, 1.0], [[0.0], [1.0]])

    def setup():
        return algo.TOPPRA([CanonicalRows(a, b, c, DISC[disc])], path, gridpoints=s,
                           solver_wrapper="seidel")

    solver = setup()
    sdd, sd, _, _ = solver.compute_parameterization(0.0, 0.0, return_data=True)
    if sd is None:
        return None
    x_toppra = np.asarray(sd) ** 2
    duration = float(np.sum(2 * np.diff(s) / (sd[:-1] + sd[1:])))
    setup_t, solve_t = [], []
    for _ in range(reps):
        t0 = time.perf_counter()
        solver = setup()
        t1 = time.perf_counter()
        solver.compute_parameterization(0.0, 0.0)
        t2 = time.perf_counter()
        setup_t.append(t1 - t0)
        solve_t.append(t2 - t1)
    return {"duration": duration, "x": x_toppra, "setup_us": statistics.median(setup_t) * 1e6,
            "solve_us": statistics.median(solve_t) * 1e6, "solve_min_us": min(solve_t) * 1e6}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="fewer repetitions")
    ap.add_argument("--write-instances", metavar="PATH",
                    help="write the instances (the runners' input) to PATH and stop")
    args = ap.parse_args()
    reps100, reps1000 = (10, 3) if args.quick else (40, 8)

    instances, refs = [], {}
    for name in NAMES:
        with open(os.path.join(ROOT, "testdata", "topp", f"{name}_N100.json")) as f:
            inst = json.load(f)
        p0, p1, bow = bow_of(inst)
        U = np.array(inst["U"])
        for n in (100, 1000):
            s = np.linspace(0.0, 1.0, n + 1) if n != 100 else np.array(inst["s"])
            if n == 100:
                a, b, c = (np.array(inst[k]) for k in "abc")
            else:
                a, b, c = eq14(U, inst["mass"], inst["gravity"], s, p0, p1, bow)
            instances.append({"name": f"{name}_N{n}", "s": s.tolist(), "a": a.tolist(),
                              "b": b.tolist(), "c": c.tolist(), "U": inst["U"],
                              "mass": inst["mass"], "gravity": inst["gravity"],
                              "bow": {"p0": p0.tolist(), "p1": p1.tolist(), "bow": bow.tolist()}})
            r = inst["reference"]
            refs[(f"{name}_N{n}", "collocation")] = (
                r["duration_collocation"] if n == 100 else r["duration_collocation_N1000"])
            refs[(f"{name}_N{n}", "interpolation")] = (
                r["duration_interpolation"] if n == 100 else r["duration_interpolation_N1000"])

    if args.write_instances:
        with open(args.write_instances, "w") as f:
            json.dump({"instances": instances}, f)
        return

    # Rust side (release build of the example runner).
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "instances.json")
        with open(path, "w") as f:
            json.dump({"instances": instances}, f)
        cmd = ["cargo", "run", "--quiet", "--release", "-p", "stance-topp", "--example",
               "bench_topp", "--", path]
        rust = json.loads(subprocess.run(cmd, cwd=ROOT, check=True, capture_output=True,
                                         text=True).stdout)
    ours = {(r["name"], r["discretization"]): r for r in rust if "discretization" in r}
    abc = {r["name"]: r for r in rust if "abc_fill_us" in r}

    rows = []
    ok = True
    for inst in instances:
        n = len(inst["s"]) - 1
        s, a, b, c = (np.array(inst[k]) for k in ("s", "a", "b", "c"))
        for disc in ("collocation", "interpolation"):
            t = toppra_run(s, a, b, c, disc, reps100 if n == 100 else reps1000)
            o = ours[(inst["name"], disc)]
            ref = refs[(inst["name"], disc)]
            rel_toppra = (o["duration"] - t["duration"]) / t["duration"]
            rel_ref = (t["duration"] - ref) / ref
            x_ours = np.array(o["x"])
            pos = x_ours > 1e-9
            ratio = t["x"][pos] / x_ours[pos]
            t["x_ratio"] = (float(ratio.min()), float(ratio.max()))
            # Ours may be shorter than toppra's (its forward pass aims inside K), never longer.
            agree = -1e-5 <= rel_toppra <= 1e-9 and abs(rel_ref) < 1e-9
            ok &= agree
            rows.append((inst["name"], disc, o, t, rel_toppra, agree))

    print(f"\nmachine load (1-min average): {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs")
    print("\n## Durations (checked first) and solve times, rest to rest\n")
    print("| instance | disc | m | duration ours | duration toppra | rel diff | ours solve (us) "
          "| toppra solve (us) | toppra setup (us) | speed-up (median) | speed-up (min) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name, disc, o, t, rel, agree in rows:
        print(f"| {name} | {disc} | {o['rows']} | {o['duration']:.9f} | {t['duration']:.9f} | "
              f"{rel:+.1e}{'' if agree else ' MISMATCH'} | {o['solve_us']:.1f} | "
              f"{t['solve_us']:.0f} | {t['setup_us']:.0f} | "
              f"{t['solve_us'] / o['solve_us']:.1f}x | {t['solve_min_us'] / o['solve_min_us']:.1f}x |")
    print("\n## toppra's states against ours (x = sd^2, grid points where ours > 0)\n")
    print("| instance | disc | min x_toppra / x_ours | max x_toppra / x_ours |")
    print("|---|---|---|---|")
    for name, disc, o, t, _, _ in rows:
        print(f"| {name} | {disc} | {t['x_ratio'][0]:.8f} | {t['x_ratio'][1]:.8f} |")
    print("\n## Warm start (LP work counters: optimum moves / inner line evaluations)\n")
    print("| instance | disc | warm moves | warm inner | cold moves | cold inner | warm (us) "
          "| cold (us) | same duration |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, disc, o, _, _, _ in rows:
        same = abs(o["duration"] - o["duration_cold"]) <= 1e-12 * o["duration"]
        print(f"| {name} | {disc} | {o['moves']} | {o['inner_steps']} | {o['moves_cold']} | "
              f"{o['inner_steps_cold']} | {o['solve_us']:.1f} | {o['solve_cold_us']:.1f} | {same} |")
    print("\n## Rows from U (eq. 14): fill of a, b, c for all grid points\n")
    print("Kernel `fill` runs on this CPU: "
          + ", ".join(sorted({r.get("abc_fill_kernel", "?") for r in abc.values()}))
          + ". Each available kernel timed on the same warm buffer, 3 interleaved rounds of "
          "3000 calls: median of the round medians / minimum (us).\n")
    kernels = [k for k in ("avx512-gz", "avx512", "avx2-fma", "portable")
               if any(k in r.get("abc_fill_by_kernel", {}) for r in abc.values())]
    print("| instance | m | grid points | " + " | ".join(f"{k} (us)" for k in kernels)
          + " | avx2-fma / avx512 | avx512 / avx512-gz | fused kernels bit-identical | "
          "portable max rel diff | eq. 14 vectors and setup (us) | max rel diff to the file's rows |")
    print("|---|---|---|" + "---|" * len(kernels) + "---|---|---|---|---|---|")
    for name, r in abc.items():
        byk = r.get("abc_fill_by_kernel", {})
        cells = " | ".join(f"{byk[k]['median_us']:.2f} / {byk[k]['min_us']:.2f}" if k in byk else "-"
                           for k in kernels)
        ratio = (f"{byk['avx2-fma']['median_us'] / byk['avx512']['median_us']:.2f}x"
                 if "avx2-fma" in byk and "avx512" in byk else "-")
        ratio_gz = (f"{byk['avx512']['median_us'] / byk['avx512-gz']['median_us']:.3f}x"
                    if "avx512" in byk and "avx512-gz" in byk else "-")
        print(f"| {name} | {r['rows']} | {r['N'] + 1} | {cells} | {ratio} | {ratio_gz} | "
              f"{r.get('abc_fused_kernels_identical', '-')} | "
              f"{r.get('abc_portable_max_rel_diff', float('nan')):.1e} | "
              f"{r['abc_setup_us']:.2f} | {r['abc_max_rel_diff']:.1e} |")
    print("\n## Between grid points (20 samples per interval) and refinement to 1 % of m|g|\n")
    print("| instance | disc | max violation (N) | % of m g | at s | refine: rounds | "
          "points added | time (ms) | refined duration |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, disc, o, _, _, _ in rows:
        r = o["refine"] or {}
        print(f"| {name} | {disc} | {o['between_newton']:.2f} | {100 * o['between_fraction']:.2f} | "
              f"{o['between_at_s']:.3f} | {r.get('rounds', '-')} | {r.get('points_added', '-')} | "
              + (f"{r['ms']:.2f} | {r['duration']:.6f} |" if r else "- | - |"))
    if not ok:
        print("\nDURATIONS DISAGREE: timings above are not comparable", file=sys.stderr)
        sys.exit(1)
    if not all(r.get("abc_fused_kernels_identical", True) for r in abc.values()):
        print("\nFILL KERNELS DISAGREE: the fused kernels' rows differ", file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
