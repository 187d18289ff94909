#!/usr/bin/env python3
"""3-D convex hull benchmark: polycone's hull3 (Rust) against Qhull (SciPy's ConvexHull), same
inputs, one run.

Inputs: the vertices of the robust static-equilibrium regions of the four example stances
(testdata/polytope/robust_region_vertices.json) and synthetic clouds (sphere with interior
points, a cube with points on its faces, a 1 km x 1 m x 1 mm box tilted and moved, a cloud
with clusters of nearly coincident points). The answers are compared before anything is timed
(the script stops on a disagreement):

- every hull3 plane supports Qhull's vertices (none more than 1e-9 m above it) and passes
  within 1e-9 m of at least three of them;
- both volumes agree within 1e-9 m x the surface area;
- on the inputs without clusters, the facet counts agree (Qhull's coplanar simplices grouped
  by equal equations) and every hull3 plane is a Qhull facet plane (normals within 1e-7).

Timings are medians of 7 batches (each at least 20 ms), wall clock, one process per side.
Run from the repository root with the project's virtualenv:
    $STANCE_VENV/bin/python bench/peers/hull3.py      (or .venv/bin/python)
See bench/peers/hull3.md.
"""

import json
import os
import subprocess
import sys
import time

import numpy as np
from scipy.spatial import ConvexHull

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TOL = 1e-9


def rotation(a, b, c):
    ca, sa, cb, sb, cc, sc = np.cos(a), np.sin(a), np.cos(b), np.sin(b), np.cos(c), np.sin(c)
    rx = np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]])
    ry = np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
    rz = np.array([[cc, -sc, 0], [sc, cc, 0], [0, 0, 1]])
    return rz @ ry @ rx


def clouds():
    out = []
    with open(os.path.join(ROOT, "testdata", "polytope", "robust_region_vertices.json")) as f:
        for r in json.load(f)["regions"]:
            out.append(("region " + r["scene"], np.array(r["vertices"]), False))
    rng = np.random.default_rng(2026)
    s = rng.normal(size=(300, 3))
    s /= np.linalg.norm(s, axis=1)[:, None]
    out.append(("sphere 300 + 200 inside", np.vstack([s, 0.9 * rng.uniform(-0.5, 0.5, (200, 3))]), False))
    g = np.array([[x, y, z] for x in (0, 0.5, 1) for y in (0, 0.5, 1) for z in (0, 0.5, 1)], float)
    out.append(("cube grid 3x3x3", g, False))
    h = np.array([500.0, 0.5, 5e-4])
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * h
    inside = rng.uniform(-1, 1, (60, 3)) * h
    box = (np.vstack([corners, inside]) @ rotation(0.3, -0.7, 1.1).T) + np.array([1e3, -2e3, 5e2])
    out.append(("box 1 km x 1 m x 1 mm, tilted", box, False))
    base = rng.uniform(-1, 1, (60, 3))
    near = base[rng.integers(0, 60, 40)] + 1e-7 * rng.uniform(-1, 1, (40, 3))
    out.append(("60 points + 40 within 1e-7", np.vstack([base, near]), True))
    return out


def timed(f):
    t = time.perf_counter()
    f()
    once = max(time.perf_counter() - t, 1e-7)
    reps = max(1, int(np.ceil(0.02 / once)))
    batches = []
    for _ in range(7):
        t = time.perf_counter()
        for _ in range(reps):
            f()
        batches.append((time.perf_counter() - t) / reps)
    return sorted(batches)[3] * 1e6


def qhull_facets(hull):
    """Qhull's facets: its (triangulated) simplices grouped by equal equations."""
    eqs = []
    for e in hull.equations:
        if not any(np.abs(e - q).max() < 1e-12 for q in eqs):
            eqs.append(e)
    return np.array(eqs)


def volume(vertices, faces, planes):
    o = vertices[0]
    vol = 0.0
    for face, pl in zip(faces, planes):
        n, d = np.array(pl[:3]), pl[3] - np.dot(pl[:3], o)
        p = vertices[face]
        area = 0.0
        for i in range(1, len(face) - 1):
            area += 0.5 * np.dot(np.cross(p[i] - p[0], p[i + 1] - p[0]), n)
        vol += d * area / 3.0
    return vol


def main():
    data = clouds()
    job = {"clouds": [{"name": n, "points": p.tolist()} for n, p, _ in data]}
    cmd = ["cargo", "run", "--quiet", "--release", "-p", "polycone", "--example", "hull3_bench"]
    res = subprocess.run(cmd, cwd=ROOT, input=json.dumps(job), capture_output=True, text=True, check=True)
    ours = json.loads(res.stdout)
    rows = []
    for (name, pts, clustered), o in zip(data, ours):
        hull = ConvexHull(pts)
        qv = pts[hull.vertices]
        facets = qhull_facets(hull)
        planes = np.array(o["planes"])
        verts = np.array(o["vertices"])
        for pl in planes:
            h = qv @ pl[:3] - pl[3]
            if h.max() > TOL or np.sum(np.abs(h) <= TOL) < 3:
                sys.exit(f"{name}: hull3 plane {pl} does not support Qhull's vertices (max {h.max():.2e})")
        vol = volume(verts, o["faces"], planes)
        if abs(vol - hull.volume) > TOL * hull.area:
            sys.exit(f"{name}: volumes differ: hull3 {vol!r}, Qhull {hull.volume!r}")
        if not clustered:
            if len(facets) != len(planes):
                sys.exit(f"{name}: {len(planes)} hull3 faces, {len(facets)} Qhull facets")
            for pl in planes:
                # Qhull's equation: n . x + off <= 0, unit n.
                if not any(np.abs(pl[:3] - f[:3]).max() < 1e-7 for f in facets):
                    sys.exit(f"{name}: hull3 plane {pl} is not a Qhull facet")
        t_q = timed(lambda: ConvexHull(pts))
        rows.append((name, len(pts), len(verts), len(planes), len(facets), o["us_hull3"], t_q))
    print(f"{'input':32} {'points':>6} {'verts':>5} {'faces':>5} {'qhull':>5} {'hull3 us':>9} {'Qhull us':>9} {'Qhull/hull3':>11}")
    for name, n, v, f, qf, t_o, t_q in rows:
        print(f"{name:32} {n:6d} {v:5d} {f:5d} {qf:5d} {t_o:9.1f} {t_q:9.1f} {t_q / t_o:11.2f}")
    print("(answers agree; faces: hull3's merged faces, qhull: Qhull's facets after grouping equal equations)")


if __name__ == "__main__":
    main()
