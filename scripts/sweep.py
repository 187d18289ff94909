#!/usr/bin/env python3
"""Hostile-input sweep of the `stance` command line: hundreds of generated inputs, each run and
classified.

    python3 scripts/sweep.py [--stance BIN] [--report FILE.json] [--check]

Every case is generated here (a fixed seed; not hand-picked to pass) and says what a user should
get: an answer (checked by an oracle: the exact conversion, an invariant the answer must keep
under a change of scale, units or origin, a known closed form) or an error (exit code 2, one
line, naming what to fix). Each run is classified as

- ok:      the expected outcome, and the oracle agrees;
- unclear: an error was expected and given, but its message is not one line, does not name
           what to fix (the case's keywords), or shows Rust's Debug formatting (`Some(`, `{ `,
           `::`);
- wrong:   an answer that fails its oracle, NaN or infinity written to its JSON, an error where
           an answer was expected, or an answer (exit 0) where the input should have been
           refused (silently accepted);
- panic:   exit code 101 or a Rust panic message;
- crash:   killed by a signal, or a timeout.

With --check the script exits 1 when any case is wrong, panics or crashes (CI runs it that way);
unclear messages are counted and listed, not failed. Python standard library only.
"""

import argparse
import json
import math
import os
import random
import shutil
import subprocess
import sys
import tempfile
import time

# The binary finds JVRC-1 and MuJoCo in the source tree's virtualenv unless told otherwise.
os.environ.setdefault("STANCE_VENV", os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), ".venv"))

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RNG = random.Random(20261126)


class Case:
    def __init__(self, group, name, args, files=None, expect="ok", keywords=(), oracle=None,
                 stdout_closed=False):
        self.group, self.name, self.args = group, name, args
        self.files = files or {}
        self.expect = expect  # "ok", "error", or "ok_or_error" (an answer, or an error naming a keyword)
        self.keywords = keywords  # an error message must contain one of these (case-insensitive)
        self.oracle = oracle  # fn(result_json, runner) -> None or a string saying what is wrong
        self.stdout_closed = stdout_closed


# ---------------------------------------------------------------------------------------------
# Helpers


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v] if n > 0 else v


def same_rows(a, b, tol=1e-6):
    """Same set of unit rows up to `tol` (each row of a has a row of b within tol and back)."""
    if len(a) != len(b):
        return False
    ua, ub = [unit(r) for r in a], [unit(r) for r in b]
    def covered(x, ys):
        return any(max(abs(p - q) for p, q in zip(x, y)) <= tol for y in ys)
    return all(covered(x, ub) for x in ua) and all(covered(y, ua) for y in ub)


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def rect_scene(feet, mass=60.0, gravity=None, friction=0.7):
    """feet: list of (name, position, half_length, half_width)."""
    s = {"mass": mass, "contacts": [
        {"name": n, "position": p, "shape": {"rectangle": {"half_length": hl, "half_width": hw}},
         "friction": friction} for n, p, hl, hw in feet]}
    if gravity is not None:
        s["gravity"] = gravity
    return s


def cwc_generators(center, hl=0.1, hw=0.05, mu=0.7):
    rows = []
    for sx in (-1, 1):
        for sy in (-1, 1):
            r = [center[0] + sx * hl, center[1] + sy * hw, center[2]]
            for f in ([mu, 0, 1], [-mu, 0, 1], [0, mu, 1], [0, -mu, 1]):
                rows.append(f + cross(r, f))
    return rows


# ---------------------------------------------------------------------------------------------
# Case generators


def cone_cases():
    cases = []
    # Random cones at random row scales: the answer must be the exact conversion's.
    for k in range(60):
        d = RNG.randint(2, 5)
        n = RNG.randint(d, d + 6)
        rows = [[RNG.uniform(-1, 1) for _ in range(d)] for _ in range(n)]
        lo = RNG.choice([0, 10, 100, 250])
        # A positive factor per row (a generator, or a facet below): the same cone.
        scaled = [[x * f for x in r] for r in rows for f in [10 ** RNG.uniform(-lo, lo)]]
        cases.append(Case("cone", f"random_scaled_{k}", ["cone", "span-to-face", "{f}"],
                          {"f": {"generators": scaled}}, oracle=agrees_with_exact("span-to-face")))
        if k % 3 == 0:
            face = {"facets": [[-x for x in r] for r in scaled]}
            cases.append(Case("cone", f"random_face_scaled_{k}", ["cone", "face-to-span", "{f}"],
                              {"f": face}, oracle=agrees_with_exact("face-to-span")))
    # Units: a factor per coordinate from 1e-3 to 1e3 (millimetres, kilonewtons, ...).
    for k in range(15):
        d = RNG.randint(2, 5)
        rows = [[RNG.uniform(-1, 1) for _ in range(d)] for _ in range(RNG.randint(d, d + 5))]
        cols = [10 ** RNG.uniform(-3, 3) for _ in range(d)]
        cases.append(Case("cone", f"random_units_{k}", ["cone", "span-to-face", "{f}"],
                          {"f": {"generators": [[x * c for x, c in zip(r, cols)] for r in rows]}},
                          oracle=agrees_with_exact("span-to-face")))
    # The sweep's silently wrong cases: one row at a relative scale.
    for e in [1e-6, 1e-10, 1e-11, 1e-20, 1e-100, 1e-300]:
        cases.append(Case("cone", f"tiny_generator_{e:g}", ["cone", "span-to-face", "{f}"],
                          {"f": {"generators": [[e, 0, 0], [0, 1, 0], [0, 0, 1]]}},
                          oracle=facet_count(3, 0)))
        cases.append(Case("cone", f"tiny_facet_{e:g}", ["cone", "face-to-span", "{f}"],
                          {"f": {"facets": [[e, 0, 0], [0, -1, 0]]}},
                          oracle=generator_count(2, 1)))
        cases.append(Case("cone", f"exact_tiny_entries_{e:g}", ["cone", "span-to-face", "--exact", "{f}"],
                          {"f": {"generators": [[e, 2e-100, 0], [0, e, 1], [3, 0, e], [e, e, -e]]}},
                          oracle=unit_facets))
    # Contact wrench cones far from the origin, with and without --wrench: 6-D, 32 facets, or
    # (without --wrench, where the dimension is undecided in floating point) an error naming it.
    for x in [0, 1e2, 1e4, 1e5, 1e6]:
        for flag in ([], ["--wrench"]):
            cases.append(Case("cone", f"cwc_at_{x:g}{'_wrench' if flag else ''}",
                              ["cone", "span-to-face", *flag, "{f}"],
                              {"f": {"generators": cwc_generators([x, 0.3 * x, 0])}},
                              expect="ok" if flag else "ok_or_error", keywords=["--wrench"],
                              oracle=facet_count(32, 0)))
    # Bad input: an error naming what to fix.
    bad = [
        ("nan", '{"generators": [[NaN, 0]]}', ["json", "nan", "number", "value"]),
        ("inf_string", '{"generators": [[1e999, 0]]}', ["finite", "inf", "number"]),
        ("ragged", '{"generators": [[1, 0], [1, 0, 0]]}', ["row", "entries", "dim"]),
        ("empty_no_dim", '{"generators": []}', ["empty", "dim"]),
        ("dim_zero", '{"generators": [], "dim": 0}', ["dimension", "dim"]),
        ("dim_huge", '{"generators": [], "dim": 4294967296}', ["limit", "dimension"]),
        ("dim_100000", '{"generators": [], "dim": 100000}', ["limit", "dimension"]),
        ("dim_negative", '{"generators": [], "dim": -3}', ["dim", "invalid"]),
        ("string_entry", '{"generators": [["1", 0]]}', ["generators", "number", "invalid type"]),
        ("bare_array", '[[1, 0], [0, 1]]', ["object"]),
        ("unknown_key", '{"generators": [[1, 0]], "generator": [[0, 1]]}', ["unknown field", "generator"]),
        ("not_json", 'generators = 1 2 3', ["invalid json"]),
        ("empty_file", '', ["empty"]),
        ("null", 'null', ["object", "null"]),
        ("nested_deep", '{"generators": ' + '[' * 5000 + ']' * 5000 + '}', ["recursion", "depth", "nest", "json"]),
    ]
    for name, text, kw in bad:
        cases.append(Case("cone", f"bad_{name}", ["cone", "span-to-face", "{f}"], {"f": text},
                          expect="error", keywords=kw))
    # A UTF-8 byte-order mark (some editors write one) is read past, not an error.
    cases.append(Case("cone", "utf8_bom", ["cone", "span-to-face", "{f}"],
                      {"f": '\ufeff{"generators": [[1, 0], [0, 1]]}'}, oracle=facet_count(2, 0)))
    bad_face = [
        ("nothing", '{"facets": []}', ["empty", "dim"]),
        ("ragged", '{"facets": [[1, 0], [1]]}', ["row", "entries", "dim"]),
        ("eq_mismatch", '{"facets": [[1, 0]], "equations": [[1, 0, 0]]}', ["equations", "entries", "dim", "columns"]),
        ("dim_huge", '{"facets": [], "dim": 100000}', ["limit", "dimension"]),
    ]
    for name, text, kw in bad_face:
        cases.append(Case("cone", f"bad_face_{name}", ["cone", "face-to-span", "{f}"], {"f": text},
                          expect="error", keywords=kw))
    return cases


IDENTITY = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]


def rational_stance(contacts, unit_m):
    """Contact wrench generators (e, p x e) of a stance with rational geometry. `contacts`: list
    of (centre, half-sizes, frame, denominator), centre and half-sizes integer multiples of
    `unit_m` metres, the contact frame `frame / denominator` with integer entries (a rotation,
    or a rotation times sqrt(1 + s^2) for I + s J, which turns the friction pyramid alike),
    friction pyramid of apothem 0.7. Returns (rows in metres computed in floating point as a
    user's program does, so rounded; the same rows with integer entries below 2^53): the row of
    a contact with denominator D is (D f, p' x f), f = frame (+-7, +-7, 10), p' = D c + frame h,
    that is 10 D^2 (e, p x e / unit_m), a positive row scaling and a change of the torque unit,
    which keep the number of facets. So `--exact` on the second gives the cone of the intended,
    unrounded geometry."""
    def exact(x):
        assert abs(x) < 2 ** 53, f"{x} is not exact in a double"
        return float(x)
    rows, ints = [], []
    for c, h, frame, den in contacts:
        fr = [[x / den for x in row] for row in frame]
        apply = (lambda m: lambda v: [sum(a * b for a, b in zip(row, v)) for row in m])
        for sx, sy in [(1, 1), (-1, 1), (-1, -1), (1, -1)]:
            corner = [sx * h[0], sy * h[1], 0]
            off = apply(fr)([x * unit_m for x in corner])
            p = [ci * unit_m + o for ci, o in zip(c, off)]
            p_int = [den * ci + o for ci, o in zip(c, apply(frame)(corner))]
            for a, b in [(1, 1), (-1, 1), (-1, -1), (1, -1)]:
                e = apply(fr)([0.7 * a, 0.7 * b, 1.0])
                rows.append(e + cross(p, e))
                f_int = apply(frame)([7 * a, 7 * b, 10])
                ints.append([exact(den * x) for x in f_int] + [exact(x) for x in cross(p_int, f_int)])
    return rows, ints


def two_feet(dz):
    """Two flat feet (0.22 x 0.13 m, 0.2 m apart), the right one raised by dz (a multiple of
    1 nm), in nanometres."""
    h = [110_000_000, 65_000_000]
    return rational_stance([([0, 100_000_000, 0], h, IDENTITY, 1),
                            ([0, -100_000_000, round(dz * 1e9)], h, IDENTITY, 1)], 1e-9)


STAIRS_TURN = [[6351, -1120, 0], [1120, 6351, 0], [0, 0, 6449]]  # 10.0004 degrees about z, / 6449


def stairs_with_patches(half):
    """The stairs stance (left foot at (0, 0.1, 0), right foot at (0.28, -0.1, 0.24) turned by
    10.0004 degrees about z) with square patches of half-size `half` (a multiple of 0.1 um)."""
    h = [round(half * 1e7)] * 2
    return rational_stance([([0, 1_000_000, 0], h, IDENTITY, 1),
                            ([2_800_000, -1_000_000, 2_400_000], h, STAIRS_TURN, 6449)], 1e-7)


def three_contacts_rolled():
    """Three flat feet (0.22 x 0.13 m), the third rolled about x by atan(1 / 5730) = 0.0099995
    degrees (frame I + J / 5730), in millimetres."""
    h = [110, 65]
    return rational_stance([([0, 100, 0], h, IDENTITY, 1), ([50, -100, 0], h, IDENTITY, 1),
                            ([300, 0, 0], h, [[5730, 0, 0], [0, 5730, -1], [0, 1, 5730]], 5730)], 1e-3)


def near_degenerate_cases():
    """Near-degenerate stances (a perception system never gives exactly coplanar feet): two
    feet almost coplanar, the stairs with contact patches of 10 to 100 um, three contacts with
    one rolled by 0.01 degree; as cones (with and without --wrench) and as a scene's GIWC. The
    default answer has at most the facets of the intended geometry, no two rows within the
    tolerance, contains every generator, its rays violate the exact cone of the input by at
    most the tolerance (checked with --exact on the output), and it says which arithmetic gave
    it."""
    cases = []
    from_cone = (lambda out: (out["facets"], out))
    from_giwc = (lambda out: (out["giwc"]["facets"], out["route"]))
    for dz in [0.0, 1e-9, 1e-8, 1e-7, 1e-6, 1e-5]:
        stance = two_feet(dz)
        cases.append(Case("degenerate", f"feet_out_of_plane_{dz:g}", ["cone", "span-to-face", "{f}"],
                          {"f": {"generators": stance[0]}}, oracle=sliver_free(stance, from_cone)))
        scene = rect_scene([("l", [0, 0.1, 0], 0.11, 0.065), ("r", [0, -0.1, dz], 0.11, 0.065)])
        cases.append(Case("degenerate", f"giwc_feet_out_of_plane_{dz:g}", ["giwc", "{f}"],
                          {"f": scene},
                          oracle=sliver_free(stance, from_giwc, lambda out: out["span"])))
    for half in [5e-6, 1e-5, 5e-5]:
        stance = stairs_with_patches(half)
        for flags in [[], ["--wrench"]]:
            cases.append(Case("degenerate", f"stairs_patches_{half:g}{''.join(flags)}",
                              ["cone", "span-to-face", *flags, "{f}"],
                              {"f": {"generators": stance[0]}}, oracle=sliver_free(stance, from_cone)))
        turn = [[x / 6449 for x in row] for row in STAIRS_TURN]
        scene = rect_scene([("l", [0, 0.1, 0], half, half), ("r", [0.28, -0.1, 0.24], half, half)])
        scene["contacts"][1]["rotation"] = turn
        cases.append(Case("degenerate", f"giwc_stairs_patches_{half:g}", ["giwc", "{f}"], {"f": scene},
                          oracle=sliver_free(stance, from_giwc, lambda out: out["span"])))
    stance = three_contacts_rolled()
    for flags in [[], ["--wrench"]]:
        cases.append(Case("degenerate", f"three_contacts_rolled{''.join(flags)}",
                          ["cone", "span-to-face", *flags, "{f}"],
                          {"f": {"generators": stance[0]}}, oracle=sliver_free(stance, from_cone)))
    return cases


def sliver_free(stance, answer, generators=None, tol=1e-8):
    """`stance`: (input generators, integer generators of the intended geometry), from
    rational_stance; `answer(out)`: (facet rows, the route's report); `generators(out)`: the
    generators of the answer's cone (default: the input's)."""
    def check(out, run):
        f, route = answer(out)
        gens = generators(out) if generators else stance[0]
        intended = run(["cone", "span-to-face", "--exact", run.write("intended", {"generators": stance[1]})])
        exact = run(["cone", "span-to-face", "--exact", run.write("input", {"generators": gens})])
        if intended is None or exact is None:
            return "the exact conversion failed"
        if route.get("arithmetic") not in ("tolerance", "exact_fallback"):
            return f"arithmetic {route.get('arithmetic')!r}"
        if route.get("merged_rows", 0) and not route.get("merge_distance", 1.0) <= tol:
            return f"merge distance {route.get('merge_distance')} above the tolerance"
        if len(f) > len(intended["facets"]):
            return f"{len(f)} facets, the intended geometry has {len(intended['facets'])}"
        uf = [unit(r) for r in f]
        # The wrench route compares rows in its frame too, (u_f - o x u_t, L u_t): a row is
        # dropped only when both distances are within the tolerance.
        frame = route.get("wrench_frame")
        if frame:
            o, length = frame["center"], frame["length"]
            ug = [unit([a - b for a, b in zip(r[:3], cross(o, r[3:]))] + [length * x for x in r[3:]])
                  for r in f]
        for i in range(len(uf)):
            for k in range(i):
                if math.dist(uf[i], uf[k]) <= tol and (not frame or math.dist(ug[i], ug[k]) <= tol):
                    return f"rows {i} and {k} within {tol:g}"
        for g in gens:
            ng = math.sqrt(sum(x * x for x in g))
            if any(sum(a * b for a, b in zip(u, g)) > 1e-12 * ng for u in uf):
                return "a generator is outside the answer"
        rays = run(["cone", "face-to-span", "--exact", run.write("answer", {"facets": f})])
        if rays is None:
            return "the exact face-to-span of the answer failed"
        worst = max((sum(a * b for a, b in zip(unit(u), unit(r)))
                     for u in exact["facets"] for r in rays["generators"]), default=0.0)
        if worst > tol:
            return f"a ray of the answer violates the exact cone by {worst:.2e} > {tol:g}"
        return None
    return check


def agrees_with_exact(direction):
    def check(out, run):
        exact = run(["cone", direction, "--exact", run.last_file])
        if exact is None:
            return None  # the exact conversion refused: nothing to compare
        key = "facets" if direction == "span-to-face" else "generators"
        if not same_rows(out[key], exact[key], 1e-6):
            return f"{len(out[key])} {key} against {len(exact[key])} exact"
        other = "equations" if direction == "span-to-face" else "lineality"
        if len(out[other]) != len(exact[other]):
            return f"{len(out[other])} {other} against {len(exact[other])} exact"
        return None
    return check


def facet_count(nf, ne):
    def check(out, run):
        if len(out["facets"]) != nf or len(out["equations"]) != ne:
            return f"{len(out['facets'])} facets and {len(out['equations'])} equations, expected {nf} and {ne}"
        return None
    return check


def generator_count(ng, nl):
    def check(out, run):
        if len(out["generators"]) != ng or len(out["lineality"]) != nl:
            return f"{len(out['generators'])} generators, {len(out['lineality'])} lineality; expected {ng}, {nl}"
        return None
    return check


def unit_facets(out, run):
    for r in out["facets"]:
        if abs(math.sqrt(sum(x * x for x in r)) - 1) > 1e-9:
            return f"facet row {r} is not a unit row"
    return None


def topp_cases():
    cases = []
    n = 11
    s = [i / (n - 1) for i in range(n)]
    def inst(f=1.0, grid=s, rows=((1, 0, -1), (-1, 0, -1), (0, 1, -1))):
        return {"s": grid, "a": [[r[0] * f for r in rows]] * len(grid),
                "b": [[r[1] * f for r in rows]] * len(grid), "c": [[r[2] * f for r in rows]] * len(grid)}
    for f in [1, 1e-10, 1e-20, 1e-100, 1e10, 1e90]:
        cases.append(Case("topp", f"rows_scaled_{f:g}", ["topp", "{f}"], {"f": inst(f)},
                          oracle=duration_is(2.0)))
    # The path parameter's unit and origin: s -> alpha s + beta, rows a/alpha, b/alpha^2.
    for alpha, beta in [(1e-12, 0), (1e-6, 0), (1e-3, 5), (1e3, -7), (1e6, 1e6), (1e12, 0)]:
        grid = [alpha * x + beta for x in s]
        rows = ((1 / alpha, 0, -1), (-1 / alpha, 0, -1), (0, 1 / alpha ** 2, -1))
        cases.append(Case("topp", f"grid_{alpha:g}_{beta:g}", ["topp", "{f}"],
                          {"f": inst(1.0, grid, rows)}, oracle=duration_is(2.0)))
    # The project's own reference instances run as they are, and agree with toppra's answer.
    for fixture in ["ds_flat_N100", "mc_minvel_N100"]:
        path = os.path.join(ROOT, "testdata/topp", fixture + ".json")
        ref = json.load(open(path))["reference"]["duration_collocation"]
        cases.append(Case("topp", f"fixture_{fixture}", ["topp", "{f}"], {"f": open(path).read()},
                          oracle=duration_is(ref, 1e-5)))
    for name, text, kw in [
        ("nan_row", json.dumps(inst()).replace("-1", "NaN", 1), ["json", "nan", "value"]),
        ("short_grid", json.dumps({**inst(), "s": [0]}), ["grid", "s", "points", "2"]),
        ("decreasing", json.dumps(inst(1.0, [1 - x for x in s])), ["increasing", "grid", "s"]),
        ("ragged", json.dumps({**inst(), "b": [[0, 0]] * n}), ["b", "rows", "match", "shape"]),
        ("huge_coefficient", json.dumps(inst(1e200)), ["exceeds", "rescale", "coefficient"]),
        ("bad_discretization", json.dumps({**inst(), "discretization": "midpoint"}), ["discretization", "variant", "collocation"]),
        ("negative_speed", json.dumps({**inst(), "sd_start": -1}), ["sd_start", "speed", "negative"]),
        ("misspelled_key", json.dumps({**inst(), "sdstart": 0}), ["sdstart", "unknown field"]),
    ]:
        cases.append(Case("topp", f"bad_{name}", ["topp", "{f}"], {"f": text}, expect="error", keywords=kw))
    return cases


def duration_is(expected, rel=1e-6):
    def check(out, run):
        d = out.get("duration")
        if out.get("status") != "optimal" or d is None or abs(d - expected) > rel * expected:
            return f"status {out.get('status')}, duration {d}, expected {expected}"
        return None
    return check


def retime_cases():
    cases = []
    feet = [("l", [0, 0.1, 0], 0.1, 0.05), ("r", [0, -0.1, 0], 0.1, 0.05)]
    path = {"waypoints": [[0, 0, 0.8], [0.05, 0.02, 0.8], [0.08, -0.01, 0.78]]}
    ref = {"scene": rect_scene(feet), "path": path}
    cases.append(Case("retime", "reference", ["retime", "{f}"], {"f": ref}, oracle=record("retime_ref")))
    for m in [1e-12, 1e-9, 1e-3, 1e3, 1e9]:
        cases.append(Case("retime", f"mass_{m:g}", ["retime", "{f}"],
                          {"f": {"scene": rect_scene(feet, mass=m), "path": path}},
                          oracle=same_as("retime_ref", "duration")))
    for k0, k1 in [(0, 1e-6), (0, 1e-3), (0, 1e3), (0, 1e6), (5, 6), (1e6, 2e6)]:
        p = dict(path, knots=[k0, (k0 + k1) / 2, k1])
        cases.append(Case("retime", f"knots_{k0:g}_{k1:g}", ["retime", "{f}"],
                          {"f": {"scene": rect_scene(feet), "path": p}},
                          oracle=same_as("retime_ref", "duration")))
    for name, spec, kw in [
        ("negative_mass", {"scene": rect_scene(feet, mass=-1), "path": path}, ["mass"]),
        ("one_waypoint", {"scene": rect_scene(feet), "path": {"waypoints": [[0, 0, 0.8]]}}, ["waypoint", "two", "2"]),
        ("knots_decreasing", {"scene": rect_scene(feet), "path": dict(path, knots=[1, 0.5, 0])}, ["knots", "increasing"]),
        ("duplicate_contact_names", {"scene": rect_scene([feet[0], ("l", [0, -0.1, 0], 0.1, 0.05)]), "path": path}, ["duplicate", "name"]),
        ("unknown_example", {"scene": "moon", "path": path}, ["moon", "stairs"]),
        ("grid_points_huge", {"scene": rect_scene(feet), "path": path, "grid_points": 10 ** 12}, ["grid_points", "limit", "at most"]),
    ]:
        cases.append(Case("retime", f"bad_{name}", ["retime", "{f}"], {"f": spec}, expect="error", keywords=kw))
    return cases


_RECORDED = {}


def record(key):
    def check(out, run):
        _RECORDED[key] = out
        return None
    return check


def same_as(key, field, rel=1e-6):
    def check(out, run):
        ref = _RECORDED.get(key)
        if ref is None:
            return "reference missing"
        a, b = out.get(field), ref.get(field)
        if a is None or b is None or abs(a - b) > rel * abs(b):
            return f"{field} {a} against {b}"
        return None
    return check


def equilibrium_cases():
    cases = []
    # One foot at a distance from the origin: the polygon is the foot, by either route.
    for x in [0, 1e3, 1e5, 1e6, 3e6]:
        for route in ([], ["--via-u-stance"]):
            scene = rect_scene([("l", [x, 0, 0], 0.1, 0.05)])
            cases.append(Case("equilibrium", f"foot_at_{x:g}{'_u' if route else ''}",
                              ["equilibrium", "polygon", *route, "{f}"], {"f": scene},
                              oracle=polygon_box(x - 0.1, x + 0.1, -0.05, 0.05)))
    # Foot sizes from 1e-9 m to 1e6 m: the polygon is the foot.
    for h in [1e-9, 1e-6, 1e-3, 1e3, 1e6, 1e7]:
        scene = rect_scene([("l", [0, 0, 0], h, h / 2)])
        cases.append(Case("equilibrium", f"foot_size_{h:g}", ["equilibrium", "polygon", "{f}"],
                          {"f": scene}, oracle=polygon_box(-h, h, -h / 2, h / 2)))
    # Gravity magnitude: the static polygon does not depend on it.
    for g in [1e-300, 1e-12, 1e-3, 1e3, 1e12, 1e300]:
        scene = rect_scene([("l", [0, 0.1, 0], 0.1, 0.05), ("r", [0, -0.1, 0], 0.1, 0.05)],
                           gravity=[0, 0, -g])
        cases.append(Case("equilibrium", f"gravity_{g:g}", ["equilibrium", "polygon", "{f}"],
                          {"f": scene}, oracle=polygon_box(-0.1, 0.1, -0.15, 0.15)))
    for name, scene, kw in [
        ("no_contacts", {"mass": 60, "contacts": []}, ["contact"]),
        ("point_empty", {"mass": 60, "contacts": [{"name": "p", "position": [0, 0, 0], "shape": {"point": {}}, "friction": 0.5}]}, ["point", "shape", "unit", "variant"]),
        ("axis_nan_rotation", {"mass": 60, "contacts": [{"name": "p", "position": [0, 0, 0], "rotation": [[1, 0, 0], [0, 1, 0], [0, 0, "nan"]], "shape": "point", "friction": 0.5}]}, ["rotation", "number", "invalid"]),
        ("negative_friction", rect_scene([("l", [0, 0, 0], 0.1, 0.05)], friction=-0.5), ["friction"]),
        ("duplicate_names", rect_scene([("l", [0, 0.1, 0], 0.1, 0.05), ("l", [0, -0.1, 0], 0.1, 0.05)]), ["duplicate", "name"]),
        ("zero_size_foot", rect_scene([("l", [0, 0, 0], 0.0, 0.05)]), ["half_length", "size", "positive"]),
    ]:
        cases.append(Case("equilibrium", f"bad_{name}", ["equilibrium", "polygon", "{f}"], {"f": scene},
                          expect="error", keywords=kw))
    return cases


def polygon_box(x0, x1, y0, y1, rel=1e-6):
    def check(out, run):
        if out.get("status") != "bounded":
            return f"status {out.get('status')}"
        vs = out["vertices"]
        size = max(x1 - x0, y1 - y0)
        xs, ys = [v[0] for v in vs], [v[1] for v in vs]
        err = max(abs(min(xs) - x0), abs(max(xs) - x1), abs(min(ys) - y0), abs(max(ys) - y1))
        if err > rel * size + 1e-15 * max(abs(x0), abs(x1)):
            return f"bounding box off by {err:g} for a support of size {size:g}"
        return None
    return check


def robot_cases():
    cases = []
    urdf = open(os.path.join(ROOT, "models/small_humanoid.urdf")).read()
    q_ok = None
    for name, text, kw in [
        ("deep_nesting", urdf.replace("</robot>", "<x>" * 20000 + "</x>" * 20000 + "</robot>"), ["nested", "deep"]),
        ("truncated", urdf[: len(urdf) // 2], ["urdf", "xml", "end", "line", "unexpected", "element"]),
        ("not_xml", "hello", ["urdf", "xml"]),
        ("empty", "", ["empty", "urdf"]),
        ("misspelled_origin", urdf.replace("<origin", "<orgin", 1), ["orgin", "unknown", "origin"]),
        ("misspelled_inertial", urdf.replace("<inertial>", "<inertail>", 1).replace("</inertial>", "</inertail>", 1), ["inertail", "unknown", "inertial"]),
    ]:
        # The small humanoid: nq = 29, its continuous joint as (cos, sin) at q[24..26].
        q = "--q=" + ",".join("1" if i in (6, 24) else "0" for i in range(29))
        cases.append(Case("robot", f"bad_urdf_{name}", ["robot", "centroidal", "--urdf", "{f}", q],
                          {"f": text}, expect="error", keywords=kw))
    return cases


def cli_cases():
    cases = []
    for name, args, kw in [
        ("no_command", [], ["usage", "command", "subcommand"]),
        ("cone_alone", ["cone"], ["usage", "subcommand", "span-to-face"]),
        ("unknown_command", ["conee"], ["unrecognized", "conee", "subcommand"]),
        ("repeat_negative", ["cone", "span-to-face", "--repeat", "-1", "x.json"], ["repeat", "1..="]),
        ("repeat_zero", ["cone", "span-to-face", "--repeat", "0", "x.json"], ["repeat", "1..="]),
        ("repeat_huge", ["cone", "span-to-face", "--repeat", "99999999999", "x.json"], ["repeat", "1..="]),
        ("missing_file", ["cone", "span-to-face", "/nonexistent/x.json"], ["/nonexistent/x.json"]),
        ("directory", ["cone", "span-to-face", "/"], ["/", "directory", "read"]),
        ("output_unwritable", ["cone", "span-to-face", "-o", "/proc/nonexistent/out.json", "{f}"], ["/proc/nonexistent/out.json"]),
        ("plot_unwritable", ["equilibrium", "polygon", "--plot", "/proc/nonexistent/p.svg", "single-support"], ["/proc/nonexistent/p.svg"]),
        ("plot_bad_extension", ["equilibrium", "polygon", "--plot", "p.pdf", "single-support"], ["pdf", "svg", "png"]),
        ("gravity_garbage", ["equilibrium", "polygon", "--gravity", "a,b,c", "single-support"], ["gravity"]),
    ]:
        files = {"f": {"generators": [[1, 0]]}} if "{f}" in args else {}
        cases.append(Case("cli", name, args, files, expect="error", keywords=kw))
    cases.append(Case("cli", "stdout_closed", ["cone", "span-to-face", "{f}"],
                      {"f": {"generators": [[1, 0]]}}, expect="error",
                      keywords=["standard output", "stdout"], stdout_closed=True))
    return cases


# ---------------------------------------------------------------------------------------------
# Running and classifying


class Runner:
    def __init__(self, binary, tmp):
        self.binary, self.tmp, self.last_file = binary, tmp, None

    def __call__(self, args):
        """Runs an oracle's extra command: its JSON, or None when it failed."""
        p = subprocess.run([self.binary, *args], capture_output=True, text=True, timeout=120)
        if p.returncode != 0:
            return None
        return json.loads(p.stdout)

    def write(self, name, content):
        """Writes an oracle's extra input file; its path."""
        path = os.path.join(self.tmp, f"oracle_{name}.json")
        with open(path, "w", encoding="utf-8") as f:
            json.dump(content, f)
        return path


def run_case(case, runner, tmp):
    args = []
    paths = {}
    for key, content in case.files.items():
        ext = ".urdf" if case.group == "robot" else ".json"
        path = os.path.join(tmp, f"{case.group}_{case.name}_{key}{ext}")
        with open(path, "w", encoding="utf-8") as f:
            f.write(content if isinstance(content, str) else json.dumps(content))
        paths[key] = path
    for a in case.args:
        for key, path in paths.items():
            a = a.replace("{" + key + "}", path)
        args.append(a)
    runner.last_file = paths.get("f")
    t0 = time.time()
    try:
        if case.stdout_closed:
            p = subprocess.run(f'"{runner.binary}" ' + " ".join(f"'{a}'" for a in args) + " >&-",
                               shell=True, capture_output=False, stderr=subprocess.PIPE, text=True,
                               timeout=120)
            stdout = ""
        else:
            p = subprocess.run([runner.binary, *args], capture_output=True, text=True, timeout=120)
            stdout = p.stdout
    except subprocess.TimeoutExpired:
        return "crash", "timeout after 120 s", time.time() - t0
    dt = time.time() - t0
    err = p.stderr or ""
    # Rust's Debug formatting reaching a user: Some(..), a struct's braces, a path
    debug = next((d for d in ("Some(", "{ ", "::") if d in err), None)
    if p.returncode == 101 or "panicked" in err:
        return "panic", err.strip().splitlines()[0] if err.strip() else "exit 101", dt
    if p.returncode < 0:
        return "crash", f"signal {-p.returncode}", dt
    if p.returncode != 0 and debug:
        return "unclear", f"Debug formatting ({debug!r}) in: " + err.strip()[:300].replace("\n", " | "), dt
    if case.expect == "ok_or_error" and p.returncode != 0:
        lines = err.strip().splitlines()
        if len(lines) == 1 and any(k.lower() in err.lower() for k in case.keywords):
            return "ok", "", dt
        return "unclear", err.strip()[:300].replace("\n", " | "), dt
    if case.expect == "error":
        if p.returncode == 0:
            return "wrong", "accepted (exit 0) where an error was expected", dt
        lines = err.strip().splitlines()
        text = err.lower()
        if len(lines) != 1 or len(err) > 600 or not any(k.lower() in text for k in case.keywords):
            return "unclear", err.strip()[:300].replace("\n", " | "), dt
        return "ok", "", dt
    if p.returncode != 0:
        return "wrong", "error where an answer was expected: " + err.strip()[:300], dt
    def no_constant(name):
        raise ValueError(f"{name} written to JSON")

    try:
        out = json.loads(stdout, parse_constant=no_constant)
    except json.JSONDecodeError:
        return "wrong", "exit 0 without JSON", dt
    except ValueError as e:
        return "wrong", str(e), dt
    if case.oracle is not None:
        try:
            why = case.oracle(out, runner)
        except (KeyError, TypeError, IndexError, ValueError) as e:
            # The output lacks what the oracle reads (a field, a shape): not the answer asked for.
            why = f"the output lacks what the check needs: {type(e).__name__} {e}"
        if why:
            return "wrong", why, dt
    return "ok", "", dt


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--stance", default=os.path.join(ROOT, "target/release/stance"))
    ap.add_argument("--report", help="write every case's outcome as JSON")
    ap.add_argument("--check", action="store_true", help="exit 1 on wrong, panic or crash")
    args = ap.parse_args()
    cases = cone_cases() + near_degenerate_cases() + topp_cases() + retime_cases() + equilibrium_cases() + robot_cases() + cli_cases()
    tmp = tempfile.mkdtemp(prefix="stance-sweep-")
    runner = Runner(args.stance, tmp)
    counts = {k: 0 for k in ("ok", "unclear", "wrong", "panic", "crash")}
    by_group = {}
    report = []
    for c in cases:
        outcome, detail, dt = run_case(c, runner, tmp)
        counts[outcome] += 1
        by_group.setdefault(c.group, {k: 0 for k in counts})[outcome] += 1
        report.append({"group": c.group, "case": c.name, "outcome": outcome, "detail": detail,
                       "seconds": round(dt, 3)})
        if outcome != "ok":
            print(f"{outcome:8} {c.group}/{c.name}: {detail}")
    shutil.rmtree(tmp, ignore_errors=True)
    print(f"\n{len(cases)} cases: " + ", ".join(f"{k} {v}" for k, v in counts.items()))
    for g, cs in by_group.items():
        print(f"  {g:12} " + ", ".join(f"{k} {v}" for k, v in cs.items() if v))
    if args.report:
        with open(args.report, "w") as f:
            json.dump({"counts": counts, "by_group": by_group, "cases": report}, f, indent=1)
    if args.check and (counts["wrong"] or counts["panic"] or counts["crash"]):
        sys.exit(1)


if __name__ == "__main__":
    main()
