#!/usr/bin/env python3
"""Contact-stability benchmark: stance (Rust) against the Python peers, same inputs, one run.

Peers (black boxes, from PyPI, see requirements-peers.txt):
- U_stance: pycddlib float (the paper's pipeline: span -> face of A_stance V_all);
- static-equilibrium polygon: pymanoid's "hull" method rebuilt with pypoman + pycddlib + SciPy
  (CWC face matrix by pypoman.compute_cone_face_matrix, then pypoman.compute_polygon_hull on
  B = [-a_y, a_x], c = -a_z), and pypoman's Bretl projection (project_polytope method="bretl"
  over vertex forces and the CoM);
- robust static-equilibrium test of one CoM: NumPy eq. (12) (U (g_k, p x g_k) <= 0 for all k),
  per CoM and vectorized over many CoMs.

Answers are compared before anything is timed (the script stops on a disagreement). Timings are
medians over 7 batches of repeated calls (CPU wall time, one process). Run from the repository
root with the project's virtualenv:  $STANCE_VENV/bin/python bench/peers/contact.py
(or .venv/bin/python). See bench/peers/contact.md.
"""

import json
import os
import subprocess
import sys
import time

import numpy as np
import cdd
import pypoman

# The binaries run here find JVRC-1 and MuJoCo in this virtualenv (the one running this script).
os.environ.setdefault("STANCE_VENV", sys.prefix)

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENES = ["single-support", "double-support", "stairs", "box-climbing"]
GRAVITIES = [[0.15, 0.0, -9.81], [-0.15, 0.0, -9.81], [0.0, 0.15, -9.81], [0.0, -0.15, -9.81]]
N_SAMPLE = 2000
N_BATCH = 1_000_000
ROW_TOL = 1e-6  # unit-row agreement of the face matrices
VERTEX_TOL = 1e-6  # metres, polygon vertices ours vs "hull"


def timeit(f):
    """Median seconds per call over 7 batches of at least 20 ms."""
    reps = 1
    while True:
        t = time.perf_counter()
        for _ in range(reps):
            f()
        if time.perf_counter() - t >= 0.02:
            break
        reps *= 2
    v = []
    for _ in range(7):
        t = time.perf_counter()
        for _ in range(reps):
            f()
        v.append((time.perf_counter() - t) / reps)
    return sorted(v)[3]


def rotation(c):
    return np.array(c.get("rotation", np.eye(3)), dtype=float)


def vertices_local(c):
    s = c["shape"]
    if s == "point":
        return [np.zeros(2)]
    if "rectangle" in s:
        x, y = s["rectangle"]["half_length"], s["rectangle"]["half_width"]
        return [np.array(v) for v in ([x, y], [-x, y], [-x, -y], [x, -y])]
    return [np.array(v) for v in s["polygon"]]


def cwc_span(scene):
    """Net contact wrench cone generators (f, q x f) at the world origin, one per column
    (outer 4-sided pyramids at the shape vertices, the paper's model)."""
    cols = []
    for c in scene["contacts"]:
        R, p, mu = rotation(c), np.array(c["position"], float), c["friction"]
        for v in vertices_local(c):
            q = p + R @ np.array([v[0], v[1], 0.0])
            for sx in (1, -1):
                for sy in (1, -1):
                    f = R @ np.array([sx * mu, sy * mu, 1.0])
                    cols.append(np.concatenate([f, np.cross(q, f)]))
    return np.array(cols).T


def face_cdd(V):
    """pycddlib float span -> face: rows U (unit) with U x <= 0 and equations."""
    mat = cdd.matrix_from_array(np.hstack([np.zeros((V.shape[0], 1)), V]), rep_type=cdd.RepType.GENERATOR)
    P = cdd.polyhedron_from_matrix(mat)
    H = cdd.copy_inequalities(P)
    A = np.array(H.array)
    lin = sorted(H.lin_set)
    ineq = [i for i in range(A.shape[0]) if i not in lin]
    U = -A[ineq, 1:]
    return U, A[lin, 1:]


def unit_rows(M):
    n = np.linalg.norm(M, axis=1)
    return M[n > 0] / n[n > 0, None]


def same_rows(A, B, tol):
    A, B = unit_rows(np.asarray(A)), unit_rows(np.asarray(B))
    if A.shape != B.shape:
        return False
    d = np.abs(A[:, None, :] - B[None, :, :]).max(axis=2)
    return bool((d.min(axis=1) < tol).all() and (d.min(axis=0) < tol).all())


def hull_polygon(scene):
    """pymanoid's "hull" static-equilibrium polygon, rebuilt (vertical gravity)."""
    A_O = pypoman.compute_cone_face_matrix(cwc_span(scene))
    a_z, a_x, a_y = A_O[:, 2], A_O[:, 3], A_O[:, 4]
    B = np.vstack([-a_y, a_x]).T
    c = -a_z
    return pypoman.compute_polygon_hull(B, c), (B, c)


def bretl_polygon(scene):
    """Static-equilibrium polygon by pypoman's Bretl projection over the vertex forces."""
    g = np.array(scene["gravity"], float)
    m = scene["mass"]
    blocks, qs = [], []
    for c in scene["contacts"]:
        R, p, mu = rotation(c), np.array(c["position"], float), c["friction"]
        F = np.array([[1, 0, -mu], [-1, 0, -mu], [0, 1, -mu], [0, -1, -mu]], float) @ R.T
        for v in vertices_local(c):
            qs.append(p + R @ np.array([v[0], v[1], 0.0]))
            blocks.append(F)
    n = 3 * len(qs)
    A = np.zeros((4 * len(qs), n + 2))
    for j, F in enumerate(blocks):
        A[4 * j:4 * j + 4, 3 * j:3 * j + 3] = F
    b = np.zeros(A.shape[0])
    C = np.zeros((6, n + 2))
    d = np.zeros(6)
    for j, q in enumerate(qs):
        C[0:3, 3 * j:3 * j + 3] = np.eye(3)
        qx = np.array([[0, -q[2], q[1]], [q[2], 0, -q[0]], [-q[1], q[0], 0]])
        C[3:6, 3 * j:3 * j + 3] = qx
    d[0:3] = -m * g  # sum of forces = -m g
    # sum q x f + m p x g = 0, p = (px, py, 0): p x g = (py gz - 0, 0 - px gz, px gy - py gx)
    C[3:6, n] = m * np.array([0.0, -g[2], g[1]])
    C[3:6, n + 1] = m * np.array([g[2], 0.0, -g[0]])
    E = np.zeros((2, n + 2))
    E[0, n] = E[1, n + 1] = 1.0
    return pypoman.project_polytope((E, np.zeros(2)), (A, b), (C, d), method="bretl")


def polygon_area(vs):
    vs = np.asarray(vs)
    x, y = vs[:, 0], vs[:, 1]
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def hausdorff(a, b):
    a, b = np.asarray(a), np.asarray(b)
    d = np.linalg.norm(a[:, None, :] - b[None, :, :], axis=2)
    return max(d.min(axis=1).max(), d.min(axis=0).max())


def robust_one(U, G, p):
    """NumPy eq. (12) for one CoM: U (g_k, p x g_k) <= 0 for all k."""
    W = np.vstack([G.T, np.cross(p, G).T])  # 6 x K
    return bool((U @ W <= 0).all())


def robust_batch(U, G, P):
    ok = np.ones(len(P), bool)
    for g in G:
        vals = U[:, :3] @ g + np.cross(P, g) @ U[:, 3:].T  # n x rows
        ok &= (vals <= 0).all(axis=1)
    return ok


def main():
    rng = np.random.default_rng(7)
    sample = np.column_stack([rng.uniform(-0.5, 0.8, N_SAMPLE), rng.uniform(-0.6, 0.5, N_SAMPLE),
                              rng.uniform(0.3, 1.3, N_SAMPLE)])
    job = {"scenes": SCENES, "gravities": GRAVITIES, "sample_points": sample.tolist(), "n_batch": N_BATCH}
    cmd = ["cargo", "run", "--quiet", "--release", "-p", "stance-contact", "--example", "contact_bench"]
    res = subprocess.run(cmd, cwd=ROOT, input=json.dumps(job), capture_output=True, text=True, check=True)
    ours = json.loads(res.stdout)
    G = np.array(GRAVITIES)
    rows = []
    for r in ours:
        scene, name = r["scene"], r["name"]
        V_gi = -cwc_span(scene).T  # GIWC generators, one per row
        # --- answers first
        U_cdd, E_cdd = face_cdd(V_gi)
        assert same_rows(U_cdd, r["facets"], ROW_TOL), f"{name}: U_stance differs from pycddlib"
        assert E_cdd.shape[0] == r["equations"], f"{name}: equations differ"
        hull, _ = hull_polygon(scene)
        # (the hull method may repeat a vertex: compare as point sets)
        assert hausdorff(hull, r["polygon"]) < VERTEX_TOL, f"{name}: polygon differs from the hull method"
        assert hausdorff(hull, r["polygon_direct"]) < VERTEX_TOL, f"{name}: direct polygon differs from the hull method"
        bretl = bretl_polygon(scene)
        h_bretl = hausdorff(bretl, r["polygon"])
        U = np.array(r["facets"])
        ref = robust_batch(U, G, sample)
        # Points within 1e-9 relative of a boundary may go either way.
        W = [np.vstack([G.T, np.cross(p, G).T]) for p in sample]
        margin = np.array([(U @ w).max() / np.linalg.norm(w, axis=0).max() for w in W])
        clear = np.abs(margin) > 1e-9
        assert (np.array(r["sample_stable"])[clear] == ref[clear]).all(), f"{name}: robust tests differ"
        # --- timings
        t_cdd = timeit(lambda: face_cdd(V_gi))
        t_hull = timeit(lambda: hull_polygon(scene))
        _, (B, c) = hull_polygon(scene)
        t_hull_only = timeit(lambda: pypoman.compute_polygon_hull(B, c))
        t_bretl = timeit(lambda: bretl_polygon(scene))
        pts = sample[:200]
        t_np_one = timeit(lambda: [robust_one(U, G, p) for p in pts]) / len(pts)
        big = np.tile(sample, (50, 1))
        t_np_batch = timeit(lambda: robust_batch(U, G, big)) / len(big)
        rows.append((name, r, t_cdd, t_hull, t_hull_only, t_bretl, h_bretl, t_np_one, t_np_batch,
                     len(U), len(r["polygon"]), polygon_area(bretl) / polygon_area(r["polygon"])))
    print(f"answers agree: U_stance = pycddlib float (unit rows within {ROW_TOL}), polygon (through "
          f"U_stance and direct) = hull method (vertices within {VERTEX_TOL} m), robust tests = NumPy eq. (12) on {N_SAMPLE} CoMs\n")
    print("| scene | rows U | U_stance: pycddlib / ours (us) | x | polygon, total: hull / ours (us) | x "
          "| polygon from U: hull / ours (us) | x | Bretl (us) | x vs ours total | Bretl area ratio, Hausdorff (mm) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for (name, r, t_cdd, t_hull, t_hull_only, t_bretl, h_bretl, _, _, nu, nv, area) in rows:
        print(f"| {name} | {nu} | {1e6 * t_cdd:.0f} / {r['us_u_stance']:.1f} | {1e6 * t_cdd / r['us_u_stance']:.0f} "
              f"| {1e6 * t_hull:.0f} / {r['us_polygon_total']:.1f} | {1e6 * t_hull / r['us_polygon_total']:.0f} "
              f"| {1e6 * t_hull_only:.0f} / {r['us_polygon_from_u']:.1f} | {1e6 * t_hull_only / r['us_polygon_from_u']:.0f} "
              f"| {1e6 * t_bretl:.0f} | {1e6 * t_bretl / r['us_polygon_total']:.0f} | {area:.4f}, {1e3 * h_bretl:.2f} |")
    print("\nStatic-equilibrium polygon from scratch, direct route (support-function LPs over the contact "
          "forces, certified; no U_stance), against the hull method and Bretl's projection:\n")
    print("| scene | route | hull (us) | ours direct (us) | x | ours direct, fresh workspace (us) | x | Bretl / ours direct |")
    print("|---|---|---|---|---|---|---|---|")
    for (name, r, _, t_hull, _, t_bretl, _, _, _, _, _, _) in rows:
        d, f = r["us_polygon_direct"], r["us_polygon_direct_fresh"]
        print(f"| {name} | {r['polygon_route']} | {1e6 * t_hull:.0f} | {d:.2f} | {1e6 * t_hull / d:.0f} "
              f"| {f:.2f} | {1e6 * t_hull / f:.0f} | {1e6 * t_bretl / d:.0f} |")
    print("\n| scene | robust region M from U (us) | M vertices / half-spaces | robust test, NumPy per CoM (us) "
          "| NumPy vectorized (ns/CoM) | ours serial (ns/CoM) | ours static test serial (ns/CoM) "
          "| ours batch 1 core (ns/CoM) | ours 1e6 batch, all cores (ms) | x vs NumPy per CoM |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for (name, r, _, _, _, _, _, t_np_one, t_np_batch, _, _, _) in rows:
        print(f"| {name} | {r['us_region_from_u']:.0f} | {r['region_vertices']} / {r['region_halfspaces']} "
              f"| {1e6 * t_np_one:.1f} | {1e9 * t_np_batch:.0f} | {r['ns_robust_test_serial']:.1f} "
              f"| {r['ns_static_test_serial']:.1f} | {r['ns_robust_test_batch_1core']:.1f} "
              f"| {r['ms_batch_all_cores']:.1f} ({r['threads']} threads) | {1e9 * t_np_one / r['ns_robust_test_serial']:.0f} |")


if __name__ == "__main__":
    sys.exit(main())
