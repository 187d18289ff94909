#!/usr/bin/env python3
"""Golden cubic splines for stance_topp::path::WaypointPath, computed by SciPy's CubicSpline (the
interpolator behind toppra's SplineInterpolator).

For random waypoints (fixed seed) in 1 to 4 dimensions on 2 to 9 random knots, and each of the
boundary conditions "not-a-knot", "natural" and "clamped" (zero end tangents), it writes q, q_s
and q_ss at 7 random parameters inside the domain and at both ends.

Regenerate (from the project root, with the virtualenv of scripts/setup-venv.sh --peers):

    "${STANCE_VENV:-.venv}/bin/python" testdata/topp/make_splines.py
"""

import json
import os

import numpy as np
import scipy
from scipy.interpolate import CubicSpline

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    rng = np.random.default_rng(27)
    cases = []
    for n in range(2, 10):
        for bc in ["not-a-knot", "natural", "clamped"]:
            dim = int(rng.integers(1, 5))
            knots = np.cumsum(np.concatenate([[rng.uniform(-1, 1)], rng.uniform(0.05, 1.0, n - 1)]))
            points = rng.uniform(-2, 2, (n, dim))
            sp = CubicSpline(knots, points, bc_type=bc)
            s = np.concatenate([[knots[0]], rng.uniform(knots[0], knots[-1], 7), [knots[-1]]])
            cases.append({
                "bc_type": bc,
                "knots": knots.tolist(),
                "points": points.tolist(),
                "s": s.tolist(),
                "q": sp(s).tolist(),
                "q_s": sp(s, 1).tolist(),
                "q_ss": sp(s, 2).tolist(),
            })
    out = {"generator": "testdata/topp/make_splines.py", "scipy_version": scipy.__version__,
           "cases": cases}
    path = os.path.join(HERE, "splines.json")
    with open(path, "w") as f:
        json.dump(out, f, separators=(",", ":"))
        f.write("\n")
    print(f"{path}: {len(cases)} cases")


if __name__ == "__main__":
    main()
