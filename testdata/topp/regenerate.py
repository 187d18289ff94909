#!/usr/bin/env python3
"""Check (default) or regenerate the retiming goldens of testdata/topp/ with toppra and an LP.

Each instance file holds a CoM path sampled on the grid ``s_0 = 0 < ... < s_N = 1`` (N = 100),
the GIWC face matrix ``U`` (rows with ``U w_GI <= 0``), the mass ``m``, gravity ``g``, the rows
``a, b, c`` ((N + 1) x rows of U) of ``a u + b x + c <= 0`` (``u = s''``, ``x = s'^2``), the end
speeds, and toppra's answers under ``reference``. This script checks, for each file:

(a) Rows (the paper's eq. 13-14, docs/math.md section 5). For a point mass (angular momentum
    ``L = 0``, so ``l1 = l2 = 0``), ``p'' = p_s u + p_ss x`` put into
    ``w_GI = (m (g - p''), p x m (g - p''))`` gives ``w_GI = w_c + w_a u + w_b x`` with

        w_a = -(m p_s , m p x p_s ),   w_b = -(m p_ss, m p x p_ss),   w_c = (m g, m p x g),

    and ``U w_GI <= 0`` row by row is ``a u + b x + c <= 0`` with
    ``a = U w_a, b = U w_b, c = U w_c``. They are recomputed at every grid point from the stored
    samples ``com_path.p, ps, pss`` and compared with the stored ``a, b, c``: max absolute
    difference at most ``ROWS_TOL`` times the largest stored entry (the same arithmetic gives
    identical bits; the tolerance only allows another BLAS summation order). Checked, not
    rewritten.

(b) The path. ``p(s) = p0 + s (p1 - p0) + sin(pi s) bow`` with ``p0 = p(0)``, ``p1 = p(1)`` (the
    first and last samples) and ``bow = (p_s(0) - (p1 - p0)) / pi`` (from ``p_s(s) = p1 - p0 +
    pi cos(pi s) bow``); ``p_ss(s) = -pi^2 sin(pi s) bow``. It must reproduce all the samples
    ``p, ps, pss`` within ``PATH_TOL`` (metres) before it is used for the N = 1000 rows; the grid
    ``s`` must be ``numpy.linspace(0, 1, N + 1)``.

(c) toppra 0.6.10 (reachability analysis, seidel solver wrapper; used only through its public
    API) on the stored rows, fed as a ``LinearConstraint`` with ``F = I, g = 0`` (toppra's
    canonical form ``a u + b x + c = v, F v <= g``), rest to rest (``sd_start``, ``sd_end``):
    ``duration_collocation``, ``duration_interpolation`` (toppra's own conversion
    ``canlinear_colloc_to_interpolate``) and the speed profile ``sd_collocation``; then the same on
    ``numpy.linspace(0, 1, 1001)`` with rows recomputed by (a) from U and the path of (b):
    ``duration_collocation_N1000``, ``duration_interpolation_N1000``. A duration is
    ``sum_i 2 Delta_i / (sd_i + sd_{i+1})`` (constant ``u`` on each interval).

(d) ``duration_one_shot_lp_collocation``: the discretized problem as one LP (SciPy's ``linprog``,
    HiGHS), variables ``x_0 .. x_N >= 0`` and free ``u_0 .. u_N``:

        maximize  sum_i x_i
        subject to  x_{i+1} = x_i + 2 Delta_i u_i          (i < N)
                    a_i u_i + b_i x_i + c_i <= 0            (i <= N, collocation; u_N is free)
                    x_0 = sd_start^2,  x_N = sd_end^2,

    and its duration from ``sd_i = sqrt(x_i)``. Maximizing ``sum x_i`` is what the stored value
    is: it reproduces it to the last bit, whereas it is not the minimum time: on ds_flat the
    feasible set has no pointwise-largest profile (``x_57`` and ``x_58`` cannot both take their
    largest values), the LP trades ``x_57`` for ``x_58`` and its duration is 1.2e-6 (relative)
    longer than toppra's greedy profile; on mc_minvel it is 7.7e-7 shorter than toppra (whose
    forward pass keeps a small margin).

How agreement is judged (``--check``): every duration within a relative ``DURATION_RTOL`` = 1e-6
of the stored one, ``sd_collocation`` within ``DURATION_RTOL`` times its largest value. toppra
and HiGHS are deterministic here: the N = 100 values and the LP come out bit-identical, the
N = 1000 ones differ by at most 5.1e-16 (relative) because the path is recovered from its rounded
samples. 1e-6 is therefore far from what determinism needs; it is kept because it is a
meaningful bound for a duration (a change of a grid, solver or version that moves a duration by
more than that is worth a look) and the LP value is compared with its own recomputation, never
with toppra's (they are 1.2e-6 apart on ds_flat).

``--write`` rewrites ``reference`` (``toppra_version`` becomes the running toppra's) and nothing
else, with ``json.dumps`` defaults, the layout the files had when copied, so unchanged values stay
byte-identical (a file that was not in that layout is reported when written).

The versions it ran with are printed, with a warning when one differs from ``RECORDED`` (toppra:
the one the references were produced with; Python, NumPy, SciPy: those this script last passed
with) or from the file's ``reference.toppra_version``.

Usage, from the repository root, after ``bash scripts/setup-venv.sh --peers``:

    .venv/bin/python testdata/topp/regenerate.py [--check | --write] [FILE.json ...]
"""

import argparse
import glob
import importlib.metadata
import json
import os
import platform
import sys
import time

import numpy as np
import scipy
import scipy.sparse as sp
from scipy.optimize import linprog
import toppra
import toppra.algorithm as algo
import toppra.constraint as tc

HERE = os.path.dirname(os.path.abspath(__file__))

RECORDED = {"Python": "3.11.7", "toppra": "0.6.10", "numpy": "2.4.6", "scipy": "1.17.1"}

ROWS_TOL = 1e-12       # relative to the largest stored entry of each of a, b, c
PATH_TOL = 1e-12       # metres (and metres per unit of s) on the path samples
DURATION_RTOL = 1e-6   # durations, and sd_collocation relative to its largest value
N_FINE = 1000
DISC = {"collocation": tc.DiscretizationType.Collocation,
        "interpolation": tc.DiscretizationType.Interpolation}


def report_versions():
    running = {"Python": platform.python_version(),
               "toppra": importlib.metadata.version("toppra"),
               "numpy": np.__version__, "scipy": scipy.__version__}
    print("versions: " + ", ".join(f"{k} {v}" for k, v in running.items()))
    for k, v in running.items():
        if v != RECORDED[k]:
            print(f"WARNING: running {k} {v}, the references were recorded with {k} {RECORDED[k]}",
                  file=sys.stderr)
    return running


# ----------------------------------------------------------------------------- eq. 14, path

def rows_eq14(U, mass, gravity, p, ps, pss):
    """a, b, c of eq. 14 (L = 0) at the points p with tangents ps and curvatures pss."""
    g = np.tile(np.asarray(gravity, dtype=float), (len(p), 1))
    w_a = -np.hstack([mass * ps, mass * np.cross(p, ps)])
    w_b = -np.hstack([mass * pss, mass * np.cross(p, pss)])
    w_c = np.hstack([mass * g, mass * np.cross(p, g)])
    return w_a @ U.T, w_b @ U.T, w_c @ U.T


def path_from_samples(com):
    """p0, p1, bow of p(s) = p0 + s (p1 - p0) + sin(pi s) bow, from the samples at s = 0, 1."""
    p, ps = np.array(com["p"]), np.array(com["ps"])
    p0, p1 = p[0], p[-1]
    return p0, p1, (ps[0] - (p1 - p0)) / np.pi


def path_at(s, p0, p1, bow):
    sn, cs = np.sin(np.pi * s)[:, None], np.cos(np.pi * s)[:, None]
    return (p0 + s[:, None] * (p1 - p0) + sn * bow, (p1 - p0) + np.pi * cs * bow,
            -np.pi ** 2 * sn * bow)


# ----------------------------------------------------------------------------- solvers

# The rows as a toppra constraint: the same wrapper the peer benchmark uses (one definition).
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(HERE)), "bench", "peers"))
from topp import CanonicalRows as Rows  # noqa: E402


def duration(s, sd):
    return float(np.sum(2.0 * np.diff(s) / (sd[:-1] + sd[1:])))


def toppra_solve(s, a, b, c, disc, sd_start, sd_end):
    """toppra's profile sd and its duration (the path object is a placeholder: the constraint
    supplies the rows directly)."""
    path = toppra.SplineInterpolator([0.0, 1.0], [[0.0], [1.0]])
    solver = algo.TOPPRA([Rows(a, b, c, DISC[disc])], path, gridpoints=s,
                         solver_wrapper="seidel")
    _, sd, _, _ = solver.compute_parameterization(sd_start, sd_end, return_data=True)
    sd = np.asarray(sd, dtype=float)
    if sd.size == 0 or not np.all(np.isfinite(sd)):
        raise RuntimeError(f"toppra found no parameterization ({disc}, N = {len(s) - 1})")
    return sd, duration(s, sd)


def one_shot_lp(s, a, b, c, sd_start, sd_end):
    """Duration of the collocation LP maximizing sum x_i (see the module docstring)."""
    n1, m = a.shape                     # N + 1 grid points, m rows each
    nv = 2 * n1                         # x_0 .. x_N, u_0 .. u_N
    ix = np.arange(n1)
    # a_i u_i + b_i x_i <= -c_i
    r = np.arange(n1 * m)
    A_ub = sp.csr_matrix((np.concatenate([b.ravel(), a.ravel()]),
                          (np.concatenate([r, r]), np.concatenate([np.repeat(ix, m),
                                                                   n1 + np.repeat(ix, m)]))),
                         shape=(n1 * m, nv))
    b_ub = -c.ravel()
    # x_{i+1} - x_i - 2 Delta_i u_i = 0; x_0, x_N fixed
    N = n1 - 1
    k = np.arange(N)
    A_eq = sp.csr_matrix((np.concatenate([np.ones(N), -np.ones(N), -2.0 * np.diff(s), [1.0, 1.0]]),
                          (np.concatenate([k, k, k, [N, N + 1]]),
                           np.concatenate([k + 1, k, n1 + k, [0, N]]))), shape=(N + 2, nv))
    b_eq = np.concatenate([np.zeros(N), [sd_start ** 2, sd_end ** 2]])
    cost = np.concatenate([-np.ones(n1), np.zeros(n1)])
    bounds = [(0, None)] * n1 + [(None, None)] * n1
    res = linprog(cost, A_ub=A_ub, b_ub=b_ub, A_eq=A_eq, b_eq=b_eq, bounds=bounds,
                  method="highs")
    if res.status != 0:
        raise RuntimeError(f"one-shot LP: {res.message}")
    return duration(s, np.sqrt(np.maximum(res.x[:n1], 0.0)))


# ----------------------------------------------------------------------------- one file

def process(path, write, toppra_version):
    with open(path) as f:
        raw = f.read()
    doc = json.loads(raw)
    name = os.path.basename(path)
    ref = doc["reference"]
    lines, ok = [name], True

    def line(good, text):
        nonlocal ok
        ok &= good
        lines.append(f"  {'ok  ' if good else 'FAIL'}  {text}")

    if ref.get("toppra_version") != toppra_version:
        print(f"WARNING: {name}: reference.toppra_version {ref.get('toppra_version')}, "
              f"running toppra {toppra_version}", file=sys.stderr)

    s = np.array(doc["s"], dtype=float)
    U = np.array(doc["U"], dtype=float)
    mass, gravity = float(doc["mass"]), doc["gravity"]
    sd0, sd1 = float(doc["sd_start"]), float(doc["sd_end"])
    a, b, c = (np.array(doc[k], dtype=float) for k in "abc")
    com = doc["com_path"]
    p, ps, pss = (np.array(com[k], dtype=float) for k in ("p", "ps", "pss"))
    N = len(s) - 1

    # (a) rows from eq. 14 with the stored samples.
    new = rows_eq14(U, mass, gravity, p, ps, pss)
    diffs = {k: float(np.abs(v - w).max()) for k, v, w in zip("abc", new, (a, b, c))}
    good = all(diffs[k] <= ROWS_TOL * np.abs(w).max() for k, w in zip("abc", (a, b, c)))
    line(good, f"rows a, b, c from U, mass, gravity and the samples (eq. 14, L = 0): max |diff| "
               + ", ".join(f"{k} {v:.1e}" for k, v in diffs.items())
               + f" (largest entries {np.abs(a).max():.1f}, {np.abs(b).max():.1f}, "
                 f"{np.abs(c).max():.1f})")

    # (b) the grid and the path.
    grid_ok = bool(np.array_equal(s, np.linspace(0.0, 1.0, N + 1)))
    p0, p1, bow = path_from_samples(com)
    pp, pps, ppss = path_at(s, p0, p1, bow)
    dev = max(float(np.abs(x - y).max()) for x, y in ((pp, p), (pps, ps), (ppss, pss)))
    line(grid_ok and dev <= PATH_TOL,
         f"grid is linspace(0, 1, {N + 1}): {grid_ok}; path p0 + s (p1 - p0) + sin(pi s) bow, "
         f"bow = {np.array2string(bow, precision=6)}, vs the samples: max |diff| {dev:.1e}")

    # (c), (d) the references.
    got = {}
    t0 = time.perf_counter()
    sd_coll, got["duration_collocation"] = toppra_solve(s, a, b, c, "collocation", sd0, sd1)
    _, got["duration_interpolation"] = toppra_solve(s, a, b, c, "interpolation", sd0, sd1)
    got["duration_one_shot_lp_collocation"] = one_shot_lp(s, a, b, c, sd0, sd1)
    s_fine = np.linspace(0.0, 1.0, N_FINE + 1)
    af, bf, cf = rows_eq14(U, mass, gravity, *path_at(s_fine, p0, p1, bow))
    _, got[f"duration_collocation_N{N_FINE}"] = toppra_solve(s_fine, af, bf, cf, "collocation",
                                                             sd0, sd1)
    _, got[f"duration_interpolation_N{N_FINE}"] = toppra_solve(s_fine, af, bf, cf,
                                                               "interpolation", sd0, sd1)
    got["sd_collocation"] = sd_coll.tolist()
    elapsed = time.perf_counter() - t0

    for key, val in got.items():
        if key == "sd_collocation":
            st = np.array(ref[key], dtype=float)
            if st.shape != sd_coll.shape:
                line(False, f"{key}: {len(sd_coll)} values, {len(st)} stored")
                continue
            rel = float(np.abs(sd_coll - st).max() / np.abs(st).max())
            line(rel <= DURATION_RTOL, f"{key:<34} max |diff| / max sd {rel:.1e}")
            continue
        r = float(ref[key])
        rel = (val - r) / r
        line(abs(rel) <= DURATION_RTOL, f"{key:<34} {val:.16f}  stored {r:.16f}  rel {rel:+.1e}")
    lines.append(f"  (toppra and the LP: {elapsed:.2f} s)")

    if write:
        new_ref = dict(ref)
        new_ref["toppra_version"] = toppra_version
        new_ref.update(got)
        doc["reference"] = new_ref
        text = json.dumps(doc)
        if text == raw:
            lines.append("  reference unchanged")
        else:
            with open(path, "w") as f:
                f.write(text)
            layout = "" if json.dumps(json.loads(raw)) == raw else \
                " (the file's layout was not json.dumps' default: reformatted)"
            lines.append("  reference rewritten" + layout)
    return ok or write, "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    mode = ap.add_mutually_exclusive_group()
    mode.add_argument("--check", action="store_true",
                      help="compare with the stored references (default)")
    mode.add_argument("--write", action="store_true",
                      help="rewrite `reference` with the recomputed values")
    ap.add_argument("files", nargs="*", help="instance files (default: all of testdata/topp)")
    args = ap.parse_args()
    # the retiming instances (splines.json beside them is make_splines.py's)
    files = args.files or sorted(glob.glob(os.path.join(HERE, "*_N[0-9]*.json")))

    t0 = time.perf_counter()
    running = report_versions()
    ok = True
    for path in files:
        good, msg = process(path, args.write, running["toppra"])
        ok &= good
        print(msg, flush=True)
    elapsed = time.perf_counter() - t0
    verdict = "rewritten" if args.write else ("all agree" if ok else "DISAGREEMENT")
    print(f"{len(files)} TOPP files, {elapsed:.1f} s: {verdict}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
