#!/usr/bin/env python3
"""Side-by-side benchmark of the whole-body motion pipeline (the paper's stair and box climbing
on JVRC-1) against pycddlib (U_stance) and toppra (TOPP), on the pipeline's own inputs.

Run from the project root, with the virtualenv of `scripts/setup-venv.sh --peers`:

    "${STANCE_VENV:-.venv}/bin/python" bench/peers/motion.py [--quick]

Steps, per motion:
1. the Rust runner (`crates/stance-motion/examples/bench_motion.rs`, release build) runs the motion
   `--repeat` times and writes its stage timings (medians), each segment's GIWC generators (span
   form) and U_stance rows, and the whole motion's retiming rows exactly as its solver solved
   them;
2. answers first: per segment, pycddlib (float and GMP) converts the same generators to a face
   form, which is compared with our rows (unit rows within 1e-6, both ways); the whole motion's
   retiming problem is solved by toppra (same rows, grid, first-order interpolation, rest to
   rest) and its duration compared with ours. The script stops before any timing if an answer
   disagrees;
3. timings, in rounds (the Rust runner, then pycddlib's conversions, then toppra's solves, so
   that both sides see the same load on this small shared machine): medians beside the Rust
   medians, with ratios; then the totals against the targets. See bench/peers/motion.md.
"""

import argparse
import datetime
import importlib.metadata
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from fractions import Fraction

import numpy as np
import cdd
import cdd.gmp
import toppra
import toppra.algorithm as algo
import toppra.constraint as tc

# The binaries run here find JVRC-1 and MuJoCo in this virtualenv (the one running this script).
os.environ.setdefault("STANCE_VENV", sys.prefix)

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MOTIONS = ["stair-climbing", "box-climbing"]
ROW_TOL = 1e-6       # unit rows: same within this Euclidean distance
GAP_TOL = 1e-6       # our cone against cddlib's exact cone (relative, see cone_gap)
TOPP_TOL = 1e-4      # relative difference of the durations
TARGETS = {"u_abc_topp_ms": 5.0, "ik_step_us": 50.0, "pipeline_ms": 100.0}


# ---------------------------------------------------------------------------------------------
# Rust side

def run_rust(name, repeat):
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    exe = os.path.join(target, "release", "examples", "bench_motion")
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "motion.json")
        r = subprocess.run([exe, name, str(repeat), out], cwd=ROOT, capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(f"bench_motion {name} failed:\n{r.stderr}")
        with open(out) as f:
            return json.load(f)


# ---------------------------------------------------------------------------------------------
# U_stance against pycddlib

def unit_outward(h):
    """Unit outward normals u (u . w <= 0 on the cone) of a cdd H-representation b + A w >= 0,
    and the number of equations (lin_set). Exact rows are scaled exactly before rounding."""
    lin = set(h.lin_set)
    out = []
    for i, r in enumerate(h.array):
        if i in lin:
            continue
        big = max(abs(x) for x in r[1:])
        out.append([-float(x / big) for x in r[1:]] if isinstance(big, Fraction)
                   else [-float(x) / float(big) for x in r[1:]])
    u = np.array(out, dtype=float).reshape(len(out), len(h.array[0]) - 1 if len(h.array) else 6)
    return u / np.linalg.norm(u, axis=1, keepdims=True), len(lin)


def nearest(a, b):
    """For each row of a: Euclidean distance to the nearest row of b."""
    if len(a) == 0:
        return np.zeros(0)
    if len(b) == 0:
        return np.full(len(a), np.inf)
    return np.linalg.norm(a[:, None, :] - b[None, :, :], axis=2).min(axis=1)


def same_rows(a, b, tol=ROW_TOL):
    return len(a) == len(b) and bool(np.all(nearest(a, b) < tol) and np.all(nearest(b, a) < tol))


def cdd_float(v):
    m = cdd.matrix_from_array([[0.0] + list(r) for r in v], rep_type=cdd.RepType.GENERATOR)
    return cdd.copy_inequalities(cdd.polyhedron_from_matrix(m))


def cdd_gmp(vq):
    m = cdd.gmp.matrix_from_array(vq, rep_type=cdd.RepType.GENERATOR)
    return cdd.gmp.copy_inequalities(cdd.gmp.polyhedron_from_matrix(m))


def exact_rank(rows):
    rows = [list(r) for r in rows]
    rank, ncol = 0, len(rows[0]) if rows else 0
    for col in range(ncol):
        piv = next((i for i in range(rank, len(rows)) if rows[i][col] != 0), None)
        if piv is None:
            continue
        rows[rank], rows[piv] = rows[piv], rows[rank]
        p = rows[rank]
        for i in range(rank + 1, len(rows)):
            if rows[i][col] != 0:
                f = rows[i][col] / p[col]
                rows[i] = [x - f * y for x, y in zip(rows[i], p)]
        rank += 1
    return rank


def exact_facets(h, vq):
    """Irredundant count of an exact cdd H-representation of the cone of the generators vq
    (rows [0, v]): a row is a facet iff it is valid on every generator and the generators on it
    span dim - 1 (exact rational arithmetic); rows with the same generator set are one facet."""
    gens = [r[1:] for r in vq]
    dim = exact_rank(gens)
    lin = set(h.lin_set)
    seen = set()
    for i, r in enumerate(h.array):
        if i in lin:
            continue
        vals = [sum(a * x for a, x in zip(r[1:], g)) for g in gens]
        if any(x < 0 for x in vals):
            raise SystemExit("cdd GMP returned an invalid row (a generator violates it)")
        tight = frozenset(j for j, x in enumerate(vals) if x == 0)
        if exact_rank([gens[j] for j in tight]) == dim - 1:
            seen.add(tight)
    return len(seen)


def cone_gap(v, u, exact_u):
    """How far our cone {u . w <= 0} is from the exact cone of the generators v, both ways,
    relative: max over generators of u . v / |v| (a generator outside our rows), and max over
    the extreme rays r of our cone (cdd float, from our rows) of f . r / |r| for the exact unit
    facets f (our cone reaching outside the exact cone)."""
    vn = v / np.linalg.norm(v, axis=1, keepdims=True)
    gen_out = float((u @ vn.T).max())
    try:
        m = cdd.matrix_from_array([[0.0] + list(-r) for r in u], rep_type=cdd.RepType.INEQUALITY)
        g = cdd.copy_generators(cdd.polyhedron_from_matrix(m))
        rays = np.array([[float(x) for x in r[1:]] for r in g.array])
        rays /= np.linalg.norm(rays, axis=1, keepdims=True)
        ray_out = float((exact_u @ rays.T).max())
    except RuntimeError:
        ray_out = float("nan")
    return gen_out, ray_out


def check_segment(seg, gmp_canonicalize_max):
    """Answers only (no timing): counts and comparisons."""
    v = np.array(seg["generators"])
    u = np.array(seg["u"])
    vq = [[Fraction(0)] + [Fraction(float(x)) for x in r] for r in v]
    r = {"name": seg["name"], "generators": len(v), "ours": len(u)}
    try:
        h = cdd_float(v)
        raw, r["float_eq"] = unit_outward(h)
        cdd.matrix_canonicalize(h)
        irr, _ = unit_outward(h)
        r["float_raw"], r["float_irr"] = len(raw), len(irr)
        r["eq_float_raw"], r["eq_float_irr"] = same_rows(u, raw), same_rows(u, irr)
        # rows cdd's float redundancy removal dropped that are ours
        r["float_dropped_ours"] = int(np.sum(nearest(u, irr) >= ROW_TOL))
    except RuntimeError as e:  # cddlib float: "numerical inconsistency"
        r.update(float_raw=-1, float_irr=-1, eq_float_raw=False, eq_float_irr=False,
                 float_error=str(e)[:60], float_dropped_ours=0)
    hg = cdd_gmp(vq)
    gu, r["gmp_eq"] = unit_outward(hg)
    r["gmp_raw"] = len(gu)
    r["gmp_irr"] = exact_facets(hg, vq)
    r["gmp_canon"] = None
    if len(gu) <= gmp_canonicalize_max:  # cddlib's exact redundancy removal (slow: LPs in GMP)
        t0 = time.perf_counter()
        cdd.gmp.matrix_canonicalize(hg)
        r["gmp_canon"] = len(hg.array) - len(hg.lin_set)
        r["gmp_canon_s"] = time.perf_counter() - t0
    r["eq_gmp"] = same_rows(u, gu)
    d = nearest(u, gu)
    r["ours_in_gmp"] = int(np.sum(d < ROW_TOL))
    r["gen_out"], r["ray_out"] = cone_gap(v, u, gu)
    # The verdict: ours is the answer of cdd float or cdd GMP, or every one of our rows is an
    # exact facet and our cone is within GAP_TOL of the exact one (GMP's extra rows: slivers).
    gap_ok = r["gen_out"] < GAP_TOL and r["ray_out"] < GAP_TOL  # NaN: not ok
    r["ok"] = (r["eq_float_irr"] or r["eq_gmp"]
               or (r["ours_in_gmp"] == len(u) and gap_ok))
    parts = []
    if r["eq_float_irr"]:
        parts.append("= cdd float")
    elif r["eq_float_raw"]:
        parts.append(f"= cdd float as returned; its redundancy removal drops {r['float_dropped_ours']}"
                     f" exact facets" if r["ours_in_gmp"] == len(u) else
                     "= cdd float as returned, not after its redundancy removal")
    else:
        parts.append("!= cdd float")
    if r["eq_gmp"]:
        parts.append("= cdd GMP")
    elif r["ours_in_gmp"] == len(u):
        parts.append(f"all ours are GMP facets, GMP has {r['gmp_raw'] - len(u)} more (slivers)")
    else:
        parts.append(f"{len(u) - r['ours_in_gmp']} of ours are not GMP facets")
    r["answer"] = "; ".join(parts)
    return r


def time_segment(seg, reps, gmp_reps):
    """Samples (s) of cddlib float's conversion (matrix, conversion, copy of the inequalities),
    of its redundancy removal of that output, and of the GMP conversion."""
    v = np.array(seg["generators"])
    vq = [[Fraction(0)] + [Fraction(float(x)) for x in r] for r in v]
    out = {"float": [], "canon": [], "gmp": []}
    try:
        for _ in range(reps):
            t0 = time.perf_counter()
            h = cdd_float(v)
            t1 = time.perf_counter()
            cdd.matrix_canonicalize(h)
            t2 = time.perf_counter()
            out["float"].append(t1 - t0)
            out["canon"].append(t2 - t1)
    except RuntimeError:
        out["float"], out["canon"] = [float("nan")], [float("nan")]
    for _ in range(gmp_reps):
        t0 = time.perf_counter()
        cdd_gmp(vq)
        out["gmp"].append(time.perf_counter() - t0)
    return out


# ---------------------------------------------------------------------------------------------
# TOPP against toppra

class CanonicalRows(tc.LinearConstraint):
    """Precomputed rows a u + b x + c <= 0 at the grid points (F = I, g = 0), converted by toppra
    itself to first-order interpolation (as in bench/peers/topp.py)."""

    def __init__(self, a, b, c):
        super().__init__()
        self.a, self.b, self.c = a, b, c
        m = a.shape[1]
        self.F, self.g = np.eye(m), np.zeros(m)
        self.identical = True
        self.set_discretization_type(tc.DiscretizationType.Interpolation)

    def compute_constraint_params(self, path, gridpoints, *args, **kwargs):
        return tc.canlinear_colloc_to_interpolate(
            self.a, self.b, self.c, self.F, self.g, None, None, gridpoints, identical=True)


def toppra_rows(k, widen=1):
    """Our rows padded to the largest count (times `widen`) with inactive rows (0, 0, -1); upper
    bounds on x as rows (0, 1, -hi). Returns s, a, b, c and the number of real rows."""
    s = np.array(k["s"])
    if k["discretization"] != "interpolation":
        sys.exit(f"unexpected discretization {k['discretization']}")
    n = len(s)
    width = widen * max(len(k["a"][i]) + (k["x_bounds"][i][1] != -1) for i in range(n))
    a, b, c = np.zeros((n, width)), np.zeros((n, width)), -np.ones((n, width))
    real = 0
    for i in range(n):
        m = len(k["a"][i])
        a[i, :m], b[i, :m], c[i, :m] = k["a"][i], k["b"][i], k["c"][i]
        lo, hi = k["x_bounds"][i]
        if lo != 0.0:
            sys.exit(f"grid point {i}: lower bound {lo} on x (toppra keeps x >= 0 only)")
        if hi != -1:
            b[i, m], c[i, m] = 1.0, -hi
            m += 1
        real += m
    return s, a, b, c, real


def toppra_solve(s, a, b, c):
    path = toppra.SplineInterpolator([s[0], s[-1]], [[0.0], [1.0]])
    return algo.TOPPRA([CanonicalRows(a, b, c)], path, gridpoints=s, solver_wrapper="seidel")


def profile_violation(k):
    """Largest row value a u + b x + c of our profile on the interpolation rows (rows of grid
    points i and i + 1 with u = (x_{i+1} - x_i) / (2 (s_{i+1} - s_i))) and the bounds on x."""
    s, x = np.array(k["s"]), np.array(k["sd"]) ** 2
    worst = -np.inf
    for i in range(len(s) - 1):
        u = (x[i + 1] - x[i]) / (2 * (s[i + 1] - s[i]))
        for j in (i, i + 1):
            v = np.array(k["a"][j]) * u + np.array(k["b"][j]) * x[j] + np.array(k["c"][j])
            worst = max(worst, float(v.max()))
    for j, (lo, hi) in enumerate(k["x_bounds"]):
        worst = max(worst, lo - x[j], x[j] - hi if hi != -1 else -np.inf)
    return worst


def check_topp(k):
    s, a, b, c, real = toppra_rows(k)
    solver = toppra_solve(s, a, b, c)
    _, sd, _, K = solver.compute_parameterization(0.0, 0.0, return_data=True)
    r = {"points": len(s), "width": a.shape[1], "real_rows": real, "ours_max_row": profile_violation(k)}
    if sd is None:
        bad = np.where(np.isnan(K).any(axis=1))[0]
        where = (f"its controllable set at grid point {bad.max()} of {len(s)} is NaN (toppra: "
                 f"\"a numerical error occurs\")" if len(bad) else "")
        r.update(ok=False, why=f"toppra finds no profile; {where}; ours: duration "
                 f"{k['duration']:.6f} s, largest row value of our profile {r['ours_max_row']:.1e} N")
        return r
    sd = np.asarray(sd)
    ours = np.array(k["sd"])
    r["duration"] = float(np.sum(2 * np.diff(s) / (sd[:-1] + sd[1:])))
    r["rel"] = (k["duration"] - r["duration"]) / r["duration"]
    pos = ours > 1e-9
    ratio = sd[pos] ** 2 / ours[pos] ** 2
    r["x_ratio"] = (float(ratio.min()), float(ratio.max()))
    r["ends"] = (float(sd[0]), float(sd[-1]))
    r["ok"] = abs(r["rel"]) <= TOPP_TOL and abs(sd[0]) < 1e-12 and abs(sd[-1]) < 1e-12
    r["why"] = "" if r["ok"] else f"durations differ by {r['rel']:+.1e} relative"
    return r


def time_topp(k, reps):
    """Samples (s) of toppra's setup and solve, and of the solve with twice the padding (for an
    estimate of what the padding rows cost it), in alternation."""
    s, a, b, c, _ = toppra_rows(k)
    s2, a2, b2, c2, _ = toppra_rows(k, widen=2)
    out = {"setup": [], "solve": [], "solve_2x": []}
    for _ in range(reps):
        t0 = time.perf_counter()
        solver = toppra_solve(s, a, b, c)
        t1 = time.perf_counter()
        solver.compute_parameterization(0.0, 0.0)
        t2 = time.perf_counter()
        out["setup"].append(t1 - t0)
        out["solve"].append(t2 - t1)
        solver = toppra_solve(s2, a2, b2, c2)
        t0 = time.perf_counter()
        solver.compute_parameterization(0.0, 0.0)
        out["solve_2x"].append(time.perf_counter() - t0)
    return out


def merge_rust(runs):
    """The Rust runs of the rounds as one: each timing is the median of the runs' medians (the
    solve's minimum: the minimum); the answers are the first run's (the others must be equal)."""
    first = runs[0]
    for r in runs[1:]:
        if r["duration"] != first["duration"] or [len(x["u"]) for x in r["segments"]] != \
                [len(x["u"]) for x in first["segments"]]:
            sys.exit("the Rust runs of the rounds give different answers (durations or rows)")
    med = statistics.median
    out = dict(first)
    out["timings"] = {key: (med([r["timings"][key] for r in runs])
                            if isinstance(first["timings"][key], float) else first["timings"][key])
                      for key in first["timings"]}
    # the force check runs in the first repeat of each run: median over the rounds too
    out["segments"] = [dict(seg, **{key: med([r["segments"][i][key] for r in runs])
                                    for key in ("t_ik_ms", "t_u_ms", "t_abc_ms", "t_topp_ms")})
                       for i, seg in enumerate(first["segments"])]
    k = dict(first["constraints"])
    k["solve_us_median"] = med([r["constraints"]["solve_us_median"] for r in runs])
    k["solve_us_min"] = min(r["constraints"]["solve_us_min"] for r in runs)
    k["solve_us_rounds"] = [r["constraints"]["solve_us_median"] for r in runs]
    out["constraints"] = k
    return out


# ---------------------------------------------------------------------------------------------

def loadavg():
    return "{:.2f}, {:.2f}, {:.2f}".format(*os.getloadavg())


def fmt(x, nd=2):
    return "-" if x is None or x != x else f"{x:.{nd}f}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="fewer repetitions, no exact redundancy "
                    "removal by cddlib")
    ap.add_argument("--motions", nargs="+", default=MOTIONS, help="built-in motion names")
    ap.add_argument("--rounds", type=int, help="rounds of timing, Rust and peers in alternation "
                    "(default 3, quick 1)")
    ap.add_argument("--repeat", type=int, help="Rust runs of each motion per round (default 20, "
                    "quick 5)")
    ap.add_argument("--cdd-repeats", type=int, help="pycddlib float runs per round (default 10, "
                    "quick 5)")
    ap.add_argument("--gmp-repeats", type=int, help="pycddlib GMP runs, first round only "
                    "(default 3, quick 1)")
    ap.add_argument("--toppra-repeats", type=int, help="toppra solves per round (default 10, "
                    "quick 5)")
    ap.add_argument("--gmp-canonicalize-max", type=int,
                    help="run cddlib's exact redundancy removal when GMP returns at most this many "
                         "rows (default 60, quick 0; 52 rows take several seconds)")
    args = ap.parse_args()
    q = args.quick
    rounds = args.rounds or (1 if q else 3)
    repeat = args.repeat or (5 if q else 20)
    cdd_reps = args.cdd_repeats or (5 if q else 10)
    gmp_reps = args.gmp_repeats or (1 if q else 3)
    topp_reps = args.toppra_repeats or (5 if q else 10)
    gmp_canon_max = args.gmp_canonicalize_max if args.gmp_canonicalize_max is not None else (0 if q else 60)

    started = datetime.datetime.now(datetime.timezone.utc)
    load_start = loadavg()
    subprocess.run(["cargo", "build", "--release", "-q", "-p", "stance-motion", "--example", "bench_motion"],
                   cwd=ROOT, check=True)
    print("# Whole-body motions: the pipeline against pycddlib and toppra\n")
    print(f"date (UTC): {started:%Y-%m-%d %H:%M}; machine: {platform.machine()}, {os.cpu_count()} "
          f"CPUs, shared with other jobs")
    print(f"Python {platform.python_version()}, pycddlib {importlib.metadata.version('pycddlib')}, "
          f"toppra {importlib.metadata.version('toppra')}, NumPy {np.__version__}")
    print('command (from the project root): "${STANCE_VENV:-.venv}/bin/python" bench/peers/motion.py'
          + "".join(" " + a for a in sys.argv[1:]))
    print(f"{rounds} round(s) of: Rust runner ({repeat} runs of the motion), cdd float ({cdd_reps} "
          f"conversions per segment), toppra ({topp_reps} solves); cdd GMP {gmp_reps} conversions "
          f"per segment in the first round; cddlib's exact redundancy removal when GMP returns <= "
          f"{gmp_canon_max} rows")
    print(f"load average (1, 5, 15 min) at start: {load_start}")

    failed = []
    for name in args.motions:
        # 1. the Rust runner
        rust = run_rust(name, repeat)
        load_rust = loadavg()
        if rust["status"] != "optimal":
            sys.exit(f"{name}: the pipeline returned {rust['status']}")
        k = rust["constraints"]

        # 2. answers first
        checks = [check_segment(seg, gmp_canon_max) for seg in rust["segments"]]
        tcheck = check_topp(k)
        print(f"\n## {name}: {len(rust['segments'])} segments, duration {rust['duration']:.6f} s "
              f"(chained, whole motion rest to rest)\n")
        print("### U_stance against pycddlib on the same generators (answers, checked first)\n")
        print("Row counts: ours; cdd float as returned / after cddlib's redundancy removal; cdd GMP "
              "as returned / irredundant (exact facet test; in brackets cddlib's exact redundancy "
              "removal where it ran). Cone gap: generators outside our rows, and our cone's "
              "extreme rays outside the exact cone (relative).\n")
        print("| segment | generators | ours | cdd float | cdd float irredundant | cdd GMP | "
              "GMP irredundant | answer | gap: generators | gap: our rays |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        for i, r in enumerate(checks):
            canon = ("" if r["gmp_canon"] is None
                     else f" [{r['gmp_canon']}, in {r['gmp_canon_s']:.1f} s]")
            print(f"| {i + 1}. {r['name']} | {r['generators']} | {r['ours']} | {r['float_raw']} | "
                  f"{r['float_irr']} | {r['gmp_raw']} | {r['gmp_irr']}{canon} | "
                  f"{r['answer']}{'' if r['ok'] else ' DISAGREE'} | {r['gen_out']:.1e} | "
                  f"{r['ray_out']:.1e} |")
        print("\n### TOPP against toppra, whole motion (answers, checked first)\n")
        if "duration" in tcheck:
            print(f"{tcheck['points']} grid points, rows per point padded to {tcheck['width']} "
                  f"({tcheck['real_rows']} real rows of {tcheck['points'] * tcheck['width']}); "
                  f"duration ours {k['duration']:.9f} s, toppra {tcheck['duration']:.9f} s, "
                  f"relative difference {tcheck['rel']:+.1e}; x = sd^2 toppra / ours in "
                  f"[{tcheck['x_ratio'][0]:.9f}, {tcheck['x_ratio'][1]:.9f}]; "
                  f"toppra's end speeds {tcheck['ends'][0]:g}, {tcheck['ends'][1]:g}; largest row "
                  f"value of our profile on the interpolation rows {tcheck['ours_max_row']:.1e} N")
        bad = [f"segment {i + 1} ({r['name']}): ours {r['ours']} rows, {r['answer']}, gap "
               f"{r['gen_out']:.1e} / {r['ray_out']:.1e}" for i, r in enumerate(checks) if not r["ok"]]
        if not tcheck["ok"]:
            bad.append(f"TOPP: {tcheck['why']}")
        if not bad:
            print(f"\nanswers agree: U_stance on all {len(checks)} segments (unit rows within "
                  f"{ROW_TOL:g}; cone gap to cddlib's exact cone below {GAP_TOL:g}), TOPP duration "
                  f"within {TOPP_TOL:g} relative")
        if bad:
            failed.append(name)
            print(f"\n{name}: ANSWERS DISAGREE, nothing timed:\n  " + "\n  ".join(bad),
                  file=sys.stderr)
            continue

        # 3. timings: rounds of Rust runner, cddlib, toppra (the first Rust run is round 1's)
        runs, seg_samples, topp_samples = [rust], [], []
        for rnd in range(rounds):
            if rnd > 0:
                runs.append(run_rust(name, repeat))
            seg_samples.append([time_segment(seg, cdd_reps, gmp_reps if rnd == 0 else 0)
                                for seg in rust["segments"]])
            topp_samples.append(time_topp(k, topp_reps))
        load_end = loadavg()
        rust = merge_rust(runs)
        k = rust["constraints"]
        med = statistics.median
        times = []
        for i in range(len(rust["segments"])):
            pool = {key: [x for rnd in seg_samples for x in rnd[i][key]]
                    for key in ("float", "canon", "gmp")}
            times.append({f"{key}_ms": 1e3 * med(v) for key, v in pool.items()})
        pool = {key: [x for rnd in topp_samples for x in rnd[key]]
                for key in ("setup", "solve", "solve_2x")}
        ttopp = {"setup_us": 1e6 * med(pool["setup"]), "solve_us": 1e6 * med(pool["solve"]),
                 "solve_min_us": 1e6 * min(pool["solve"]), "solve_2x_us": 1e6 * med(pool["solve_2x"])}
        # padding estimate: the 2x solve has one more padded block of the same size (linear model)
        total = tcheck["points"] * tcheck["width"]
        per_row = (ttopp["solve_2x_us"] - ttopp["solve_us"]) / total
        ttopp["solve_unpadded_us"] = ttopp["solve_us"] - per_row * (total - tcheck["real_rows"])
        round_x = [med(t["solve"]) * 1e6 / o for t, o in zip(topp_samples, k["solve_us_rounds"])]

        print("\n### Per segment (ms; ours: the call in the pipeline, median over the Rust runs "
              "(median of the rounds' medians); cdd: median of all its calls; x = cdd / ours)\n")
        print("| segment | rows ours / cdd float / cdd irredundant | T_U ours | cdd float | x | "
              "cdd float + redundancy removal | x | cdd GMP | x | T_abc | T_TOPP (pipeline) | "
              "T_IK | IK steps | grid points | duration (s) |")
        print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
        for seg, r, t in zip(rust["segments"], checks, times):
            tu = seg["t_u_ms"]
            both = t["float_ms"] + t["canon_ms"]
            print(f"| {seg['name']} | {r['ours']} / {r['float_raw']} / {r['float_irr']} | {tu:.3f} | "
                  f"{t['float_ms']:.3f} | {t['float_ms'] / tu:.1f} | {both:.3f} | {both / tu:.1f} | "
                  f"{t['gmp_ms']:.1f} | {t['gmp_ms'] / tu:.0f} | {seg['t_abc_ms']:.3f} | "
                  f"{seg['t_topp_ms']:.3f} | {seg['t_ik_ms']:.2f} | {seg['ik_steps']} | "
                  f"{seg['grid_points']} | {fmt(seg['duration'], 3)} |")
        su = sum(s["t_u_ms"] for s in rust["segments"])
        sf = sum(t["float_ms"] for t in times)
        sc = sum(t["float_ms"] + t["canon_ms"] for t in times)
        sg = sum(t["gmp_ms"] for t in times)
        print(f"| all segments | | {su:.3f} | {sf:.3f} | {sf / su:.1f} | {sc:.3f} | {sc / su:.1f} | "
              f"{sg:.1f} | {sg / su:.0f} | | | | | | |")

        tm = rust["timings"]
        print("\n### Whole motion: TOPP ours against toppra (same rows, grid, interpolation, rest to "
              "rest)\n")
        print("Ours: the solve alone, 200 times per Rust run (median of the rounds' medians, "
              "minimum); toppra: `compute_parameterization(0, 0)`, median and minimum of all its "
              "solves; x per round: toppra's median over ours in each round.\n")
        print("| duration ours (s) | duration toppra (s) | rel diff | ours solve median / min (us) | "
              "toppra solve median / min (us) | toppra setup (us) | x (median) | x (min) | "
              "x per round | toppra, twice the padding (us) | toppra without padding, estimate (us) "
              "| x |")
        print("|---|---|---|---|---|---|---|---|---|---|---|---|")
        print(f"| {k['duration']:.9f} | {tcheck['duration']:.9f} | {tcheck['rel']:+.1e} | "
              f"{k['solve_us_median']:.0f} / {k['solve_us_min']:.0f} | {ttopp['solve_us']:.0f} / "
              f"{ttopp['solve_min_us']:.0f} | {ttopp['setup_us']:.0f} | "
              f"{ttopp['solve_us'] / k['solve_us_median']:.0f} | "
              f"{ttopp['solve_min_us'] / k['solve_us_min']:.0f} | "
              f"{', '.join(f'{x:.0f}' for x in round_x)} | {ttopp['solve_2x_us']:.0f} | "
              f"{ttopp['solve_unpadded_us']:.0f} | "
              f"{ttopp['solve_unpadded_us'] / k['solve_us_median']:.0f} |")

        def met(x, target):
            return "yes" if x <= target else "**no**"

        print("\n### Totals against the targets (medians over the Rust runs: median of the "
              "rounds' medians)\n")
        print("| quantity | measured | target | met |")
        print("|---|---|---|---|")
        print(f"| U_stance + rows + TOPP (t_u_abc_topp_ms) | {tm['t_u_abc_topp_ms']:.2f} ms "
              f"(U {tm['t_u_ms']:.2f}, rows {tm['t_abc_ms']:.2f}, TOPP {tm['t_topp_ms']:.2f}) | "
              f"<= {TARGETS['u_abc_topp_ms']:g} ms | {met(tm['t_u_abc_topp_ms'], TARGETS['u_abc_topp_ms'])} |")
        print(f"| refinement between grid points (t_refine_ms), apart | {tm['t_refine_ms']:.2f} ms | - | - |")
        both = tm['t_u_abc_topp_ms'] + tm['t_refine_ms']
        print(f"| U_stance + rows + TOPP + refinement, for reference | {both:.2f} ms | - | - |")
        print(f"| one IK step (t_ik_step_us) | {tm['t_ik_step_us']:.1f} us ({tm['ik_steps']} steps, "
              f"{tm['t_ik_ms']:.1f} ms) | <= {TARGETS['ik_step_us']:g} us | "
              f"{met(tm['t_ik_step_us'], TARGETS['ik_step_us'])} |")
        print(f"| whole pipeline, IK included (t_pipeline_ms) | {tm['t_pipeline_ms']:.1f} ms "
              f"(plan {tm['t_plan_ms']:.1f}, IK {tm['t_ik_ms']:.1f}) | <= {TARGETS['pipeline_ms']:g} ms "
              f"| {met(tm['t_pipeline_ms'], TARGETS['pipeline_ms'])} |")
        print(f"| wall time of a run, trajectory included, checks not (t_wall_ms) | "
              f"{tm['t_wall_ms']:.1f} ms | <= {TARGETS['pipeline_ms']:g} ms | "
              f"{met(tm['t_wall_ms'], TARGETS['pipeline_ms'])} |")
        print(f"| force check, on its own (t_checks_ms: first run of each round) | "
              f"{tm['t_checks_ms']:.1f} ms: "
              f"{tm['t_check_per_sample_us']:.0f} us per sample, {tm['check_samples']} samples, "
              f"{tm['samples_without_forces']} without forces | - | - |")
        print(f"\nload average (1, 5, 15 min): after the first Rust run {load_rust}, after the "
              f"timings {load_end}")

    if failed:
        sys.exit(f"answers disagree on {', '.join(failed)}: timings not comparable")


if __name__ == "__main__":
    main()
