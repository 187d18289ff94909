#!/usr/bin/env python3
"""Hostile-input sweep of the `stance` command line: hundreds of generated inputs, each run and
classified.

    python3 scripts/sweep.py [--stance BIN] [--report FILE.json] [--check] [--only GROUP,...]
                             [--time-bound S]

Every case is generated here (a fixed seed; not hand-picked to pass) and says what a user should
get: an answer (checked by an oracle: the exact conversion, an invariant the answer must keep
under a change of scale, units, origin or parameterization, a known closed form, an answer of
another command or route) or an error (exit code 2, one line, naming what to fix). Every
command is covered: cone, topp, giwc, equilibrium, retime, retime-joints, motion (mutations of
the built-in small-sway, a handful on JVRC-1), simulate (argument and file errors; one real
MuJoCo run), view (the page's data block read back), robot centroidal, setup --check, and the
command line itself; the groups `range` (numbers from 1e-300 to 1e300 where the answer has a
closed form) and `bounded` (inputs at and just beyond each documented limit) cut across them.
Each run is classified as

- ok:      the expected outcome, and the oracle agrees;
- unclear: an error was expected and given, but its message is not one line, does not name
           what to fix (the case's keywords), or shows Rust's Debug formatting (`Some(`, `{ `,
           `::`);
- wrong:   an answer that fails its oracle, NaN or infinity written to its JSON, a null where
           the oracle reads a number, an error where an answer was expected, or an answer
           (exit 0) where the input should have been refused (silently accepted);
- panic:   exit code 101 or a Rust panic message;
- crash:   killed by a signal;
- known:   a case of the open findings (`KNOWN`, each with what it shows) that still fails;
- fixed:   a case of the open findings that passes now (take it off `KNOWN`);
- slow:    over the work bound: still running after the time bound (20 s wall, `--time-bound`;
           the case is killed then), or an allocation over the memory bound (3 GB of data).
           Measured on the project's 2-core machine: the slowest passing case (one MuJoCo run
           of small-sway) takes 1.6 s with the release binary and 2.1 s with the dev profile's
           (which `cargo test` builds; opt-level 1, dependencies at 2), the largest uses 0.7 GB,
           and the whole sweep takes 100 s and 130 s.

With --check the script exits 1 when any case is wrong, panics, crashes, is slow or is fixed
(CI runs it that way); unclear messages are counted and listed, not failed (the cargo test fails on them).
Python standard library only (3.8+).
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
# Work a case may take (see the module doc): wall time (s) and memory (bytes of data; an
# allocation beyond it fails). 20 s and 3 GB leave about ten and four times the slowest and
# largest passing cases' for a loaded machine, and catch the inputs whose work runs away (a
# 64-sided friction pyramid in small-sway: 40 s and 7 GB with the release binary).
TIME_BOUND = 20.0
MEMORY_BOUND = 3 << 30


class Case:
    def __init__(self, group, name, args, files=None, expect="ok", keywords=(), oracle=None,
                 stdout_closed=False, ext=None, stdout="json", outputs=None, env=None):
        self.group, self.name, self.args = group, name, args
        # Input files: key -> content (text; a dict or list, written as JSON, or as TOML when
        # the case's extension is .toml; or a function of the runner giving either), each
        # written to a file whose path replaces "{key}" in the arguments and keywords.
        self.files = files or {}
        self.expect = expect  # "ok", "error", or "ok_or_error" (an answer, or an error naming a keyword)
        # An error message must contain one of these (case-insensitive; a tuple: all of its
        # strings). A keyword with "{key}" names that file's path; the others are matched
        # against the message with the case's paths taken out (a path could contain anything).
        self.keywords = keywords
        self.oracle = oracle  # fn(result, runner) -> None or a string saying what is wrong
        self.stdout_closed = stdout_closed
        self.ext = ext or (".urdf" if group == "robot" else ".json")
        self.stdout = stdout  # "json": the answer is JSON on stdout; "text": the oracle gets the text
        self.outputs = outputs or {}  # key -> extension: a path for a file the command writes
        self.env = env or {}  # environment variables for this case (None: unset)

# ---------------------------------------------------------------------------------------------
# Helpers


def toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{toml_key(k)} = {toml_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(f"no TOML for {v!r}")


def toml_key(k):
    return k if k and all(c.isalnum() or c in "_-" for c in k) and k.isascii() else json.dumps(k)


def toml_doc(d):
    """A TOML document of `d`: one key per line, tables and arrays of tables under their own
    headers (so that a message quoting the offending line shows its key)."""
    lines = []

    def table_array(v):
        return isinstance(v, list) and v and all(isinstance(x, dict) for x in v)

    def table(t, path):
        for k, v in t.items():
            if not isinstance(v, dict) and not table_array(v):
                lines.append(f"{toml_key(k)} = {toml_value(v)}")
        for k, v in t.items():
            p = path + [toml_key(k)]
            if isinstance(v, dict):
                lines.extend(["", "[" + ".".join(p) + "]"])
                table(v, p)
            elif table_array(v):
                for item in v:
                    lines.extend(["", "[[" + ".".join(p) + "]]"])
                    table(item, p)
    table(d, [])
    return "\n".join(lines) + "\n"


def number(x):
    """`x` if it is a finite number (a null or NaN where a number is expected is an error)."""
    if isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(x):
        raise ValueError(f"{x!r} where a number is expected")
    return x


def numbers(v):
    """Every entry of a nested list, checked by `number`."""
    if isinstance(v, list):
        return [numbers(x) for x in v]
    return number(v)


def rel_close(a, b, rel=1e-6, abs_tol=0.0):
    return abs(number(a) - number(b)) <= rel * max(abs(a), abs(b)) + abs_tol


def all_of(*checks):
    """An oracle that runs each of `checks` in turn."""
    def check(out, run):
        for c in checks:
            why = c(out, run)
            if why:
                return why
        return None
    return check


def deep(d, *keys):
    for k in keys:
        d = d[k]
    return d


def mutate(base, path, value):
    """A deep copy of `base` with the entry at `path` (keys and indices) set to `value`
    (DELETE: removed)."""
    d = json.loads(json.dumps(base))
    node = d
    for k in path[:-1]:
        node = node[k]
    if value is DELETE:
        del node[path[-1]]
    else:
        node[path[-1]] = value
    return d


DELETE = object()


def regular_polygon(n, r, phase=0.0):
    return [[r * math.cos(phase + 2 * math.pi * k / n), r * math.sin(phase + 2 * math.pi * k / n)]
            for k in range(n)]


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
# Whole-body motions (`stance motion`): mutations of the built-in small-sway on the project's
# small humanoid (about 0.3 s each in release), a handful on JVRC-1


def small_sway():
    """crates/stance-motion/motions/small-sway.toml as a dict (case `motion/file_as_name`
    checks that it is the built-in motion)."""
    return {
        "name": "small-sway",
        "robot": "small-humanoid",
        "environment": [{"name": "floor", "position": [0.0, 0.0, 0.0],
                         "shape": {"rectangle": {"half_length": 2.0, "half_width": 2.0}},
                         "friction": 0.9}],
        "initial": {"standing": {"com_height": 0.9, "contacts": {
            "LF": {"surface": "floor", "at": [0.0, 0.1]},
            "RF": {"surface": "floor", "at": [0.0, -0.1]}}}},
        "planning": {"friction": 0.7, "area_scale": 0.7},
        "limits": {"velocity": 1.0, "torque": 1.0},
        "segments": [
            {"name": "shift onto the left foot", "stance": {"LF": "floor", "RF": "floor"},
             "moves": [{"com": {"by": [0.0, 0.09, 0.0]}}]},
            {"name": "step forward with the right foot", "stance": {"LF": "floor"},
             "moves": [{"links": [{"surface": "RF", "by": [0.05, 0.0, 0.05]}]},
                       {"links": [{"surface": "RF", "onto": "floor", "at": [0.1, -0.1]}]}]},
            {"name": "back to both feet", "stance": {"LF": "floor", "RF": "floor"},
             "moves": [{"com": {"by": [0.05, -0.09, 0.0]}}]},
        ],
    }


SWAY = small_sway()
SWAY_REF = ("sway", ["motion", "small-sway"])  # the reference answer, with its checks
SWAY_FREE = ("sway_free", ["motion", "small-sway", "--no-limits", "--no-checks"])
SEG = ["segments"]


def motion_ok(out, run, checks=True):
    """Status optimal, a finite duration, and (when checked) every check sample has
    supporting contact forces as retimed."""
    if out.get("status") != "optimal":
        return f"status {out.get('status')}: {(out.get('failure') or {}).get('reason')}"
    number(out["duration"])
    c = out.get("checks")
    if checks and c is not None and number(c["samples_without_forces"]) != 0:
        return f"{c['samples_without_forces']} check samples without supporting forces as retimed"
    return None


def motion_vs(ref, relation="eq", rel=1e-6, factor=1.0, checks=True):
    """The answer is optimal (motion_ok) and its duration is `relation` ("eq", "ge": at least,
    "le": at most) `factor` times the reference's (`ref`: (cache key, arguments)). A motion
    tighter than the reference ("ge") may also have no timing (not retimable, with its
    failure)."""
    def check(out, run):
        if relation == "ge" and out.get("status") == "not_retimable" and out.get("failure"):
            return None  # tighter than a motion that is just feasible: no timing holds
        why = motion_ok(out, run, checks)
        if why:
            return why
        r = run.cached(*ref)
        if r is None or r.get("duration") is None:
            return f"the reference `stance {' '.join(ref[1])}` failed"
        d, want = number(out["duration"]), number(r["duration"]) * factor
        if relation == "eq" and not rel_close(d, want, rel):
            return f"duration {d!r}, expected {want!r} (relative {abs(d - want) / want:.1e} > {rel:g})"
        if relation == "ge" and d < want * (1 - rel):
            return f"duration {d!r} shorter than {want!r}, whose limits are looser"
        if relation == "le" and d > want * (1 + rel):
            return f"duration {d!r} longer than {want!r}, whose limits are tighter"
        return None
    return check


def trajectory_every(dt):
    """The trajectory starts at 0, ends at the duration, and no two samples are more than dt
    apart."""
    def check(out, run):
        t = numbers(out["trajectory"]["t"])
        d = number(out["duration"])
        if t[0] != 0 or abs(t[-1] - d) > 1e-9 * d:
            return f"trajectory from {t[0]} to {t[-1]}, duration {d}"
        gap = max(b - a for a, b in zip(t, t[1:]))
        if gap > dt * (1 + 1e-9) or min(b - a for a, b in zip(t, t[1:])) <= 0:
            return f"samples {gap} apart (dt {dt}) or not increasing"
        return None
    return check


def rotate_z(v, yaw):
    c, s = math.cos(yaw), math.sin(yaw)
    return [c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]]


def sway_moved(dx, dy, yaw=0.0):
    """small-sway with the floor (and so the robot, placed on it) moved by (dx, dy) and turned
    by yaw about z, its world-axis offsets turned alike: the same motion."""
    m = small_sway()
    m["environment"][0]["position"] = [dx, dy, 0.0]
    if yaw:
        m["environment"][0]["rpy"] = [0.0, 0.0, yaw]
        for seg in m["segments"]:
            for mv in seg["moves"]:
                if "com" in mv:
                    mv["com"]["by"] = rotate_z(mv["com"]["by"], yaw)
                for link in mv.get("links", []):
                    if "by" in link:
                        link["by"] = rotate_z(link["by"], yaw)
    return m


def sway_as_urdf_map():
    """The small humanoid as a robot map: models/small_humanoid.urdf with the built-in's
    surfaces and posture (crates/stance-motion/src/robot.rs)."""
    posture = {f"{side}_{j}": x for side in "lr"
               for j, x in [("hip_p", -0.4), ("knee", 0.8), ("ankle_p", -0.4), ("elbow", -0.3)]}
    rect = lambda a, b: {"rectangle": {"half_length": a, "half_width": b}}
    m = small_sway()
    m["robot"] = {"urdf": os.path.join(ROOT, "models/small_humanoid.urdf"), "posture": posture,
                  "surfaces": [
                      {"name": "LF", "link": "l_sole", "position": [0, 0, 0], "shape": rect(0.11, 0.05)},
                      {"name": "RF", "link": "r_sole", "position": [0, 0, 0], "shape": rect(0.11, 0.05)},
                      {"name": "LH", "link": "l_hand", "position": [0, 0, -0.1], "shape": rect(0.04, 0.02)},
                      {"name": "RH", "link": "r_hand", "position": [0, 0, -0.1], "shape": rect(0.04, 0.02)}]}
    return m


def motion_case(name, spec, args=(), expect="ok", keywords=(), oracle=None, ext=".toml", group="motion"):
    return Case(group, name, ["motion", "{f}", *args], {"f": spec}, expect=expect,
                keywords=keywords, oracle=oracle, ext=ext)


def motion_cases():
    cases = []
    ok = lambda out, run: motion_ok(out, run)
    # The built-in motion, by name, as a TOML file and as a JSON file: one answer.
    cases.append(Case("motion", "by_name", ["motion", "small-sway"], oracle=motion_vs(SWAY_REF)))
    cases.append(motion_case("file_as_name", SWAY, oracle=motion_vs(SWAY_REF, rel=1e-12)))
    cases.append(motion_case("json_as_name", SWAY, ext=".json", oracle=motion_vs(SWAY_REF, rel=1e-12)))
    cases.append(motion_case("urdf_map_as_name", sway_as_urdf_map(), ["--no-checks"],
                             oracle=motion_vs(SWAY_REF, rel=1e-12)))
    # Invariances: the whole scene and motion moved in x/y (the same duration to 1e-6), turned
    # about the vertical (to 1e-4: the IK's and the grid refinement's tolerances).
    for dx, dy in [(0.3, -0.2), (-5.0, 12.0), (1e3, -3e2), (1e5, 0.0), (0.0, -1e6)]:
        cases.append(motion_case(f"moved_{dx:g}_{dy:g}", sway_moved(dx, dy), ["--no-checks"],
                                 oracle=motion_vs(SWAY_REF)))
    # Farther than 1000 km the digits below the millimetre go (the squat at 1e12 m moved its
    # duration by 8e-4): refused, naming the surface and the range.
    for dx in [1.5e6, 1e12, -1e300]:
        cases.append(motion_case(f"moved_{dx:g}", sway_moved(dx, 0.0), ["--no-checks"],
                                 expect="error",
                                 keywords=["floor", "from the world origin", "within 1e6 m"]))
    for yaw in [0.5, math.pi / 2, math.pi, -2.0]:
        cases.append(motion_case(f"turned_{yaw:.3g}", sway_moved(0.0, 0.0, yaw), ["--no-checks"],
                                 oracle=motion_vs(SWAY_REF, rel=1e-4), ext=".json"))
    # The output step does not change the retiming: the same duration, samples at most dt apart.
    for dt in [1e-4, 0.003, 0.05, 1.0, 1e300]:
        extra = [] if dt >= 0.003 else ["--no-checks"]
        cases.append(Case("motion", f"dt_{dt:g}", ["motion", "small-sway", "--dt", repr(dt), *extra],
                          oracle=all_of(motion_vs(SWAY_REF), trajectory_every(dt))))
    for dt in [0.0005, 0.01]:
        cases.append(Case("motion", f"check_dt_{dt:g}", ["motion", "small-sway", "--check-dt", repr(dt)],
                          oracle=motion_vs(SWAY_REF)))
    # Played k times faster: the duration divided by k.
    for k in [1e-9, 0.5, 2.0, 1e6]:
        cases.append(Case("motion", f"time_scale_{k:g}",
                          ["motion", "small-sway", "--time-scale", repr(k), "--no-checks"],
                          oracle=motion_vs(SWAY_REF, factor=1 / k, rel=1e-9)))
    # Looser or tighter: rest to rest is never faster than chained, no limits never slower.
    cases.append(Case("motion", "rest_to_rest", ["motion", "small-sway", "--rest-to-rest"],
                      oracle=motion_vs(SWAY_REF, "ge")))
    cases.append(motion_case("rest_to_rest_key", mutate(SWAY, ["retiming"], {"rest_to_rest": True}),
                             oracle=motion_vs(SWAY_REF, "ge")))
    cases.append(Case("motion", "no_limits", ["motion", "small-sway", "--no-limits"],
                      oracle=motion_vs(SWAY_REF, "le")))
    for key, value, rel in [("velocity", 0.5, "ge"), ("velocity", False, "le"), ("torque", 0.8, "ge"),
                            ("torque", False, "le"), ("acceleration", 200.0, "ge")]:
        spec = mutate(SWAY, ["limits", key], value)
        cases.append(motion_case(f"limits_{key}_{value}", spec, ["--no-checks"],
                                 oracle=motion_vs(SWAY_REF, rel)))
    # Limits so large they never bind: the answer without them.
    cases.append(motion_case("limits_huge", mutate(SWAY, ["limits"], {"velocity": 1e300, "torque": 1e300,
                                                                     "acceleration": 1e300}),
                             ["--no-checks"], oracle=motion_vs(SWAY_FREE)))
    cases.append(motion_case("acceleration_per_joint", mutate(SWAY, ["limits", "acceleration"],
                                                              {"default": 1e300, "r_knee": 1e299}),
                             ["--no-checks"], oracle=motion_vs(SWAY_REF)))
    # Gravity, without actuator limits: rows c ~ |g|, so the duration goes as 1 / sqrt(|g|),
    # within the supported range of whole-body motions (0.01 to 1000 m/s^2), refused outside.
    for g in [1e-3, 0.0, 1e4]:
        cases.append(motion_case(f"gravity_out_of_range_{g:g}", mutate(SWAY, ["gravity"], [0.0, 0.0, -g]),
                                 ["--no-limits"], expect="error", keywords=[("gravity", "0.01 to 1000")]))
    for g in [1e-2, 1.0, 9.81 * 4, 1e3]:
        spec = mutate(SWAY, ["gravity"], [0.0, 0.0, -g])
        cases.append(motion_case(f"gravity_{g:g}", spec, ["--no-limits", "--no-checks"],
                                 oracle=motion_vs(SWAY_FREE, factor=math.sqrt(9.81 / g), rel=1e-6)))
    # The force check with more friction than planned and the whole contact area holds.
    for mu in [0.9, 1e6]:
        cases.append(Case("motion", f"check_friction_{mu:g}",
                          ["motion", "small-sway", "--check-friction", repr(mu)], oracle=motion_vs(SWAY_REF)))
    # Grid intervals per segment: an optimal answer that passes the force check at every sample.
    # (Two intervals are too few for the IK's steps: it may fail, and says where.) A coarse grid
    # holds s'' constant over long intervals: slower than the default 100 (measured 2.83 s at 10,
    # 2.33 s at 20, 2.07 s at 100 and 2.02 s at 300), within 10 % from 100 intervals on.
    for n, relation, rel in [(2, "ge", 1e-6), (10, "ge", 1e-6), (300, "eq", 0.1)]:
        cases.append(Case("motion", f"grid_{n}", ["motion", "small-sway", "--grid", str(n)],
                          oracle=lambda out, run, n=n, relation=relation, rel=rel: None
                          if out.get("status") == "ik_failed" and n == 2
                          else motion_vs(SWAY_REF, relation=relation, rel=rel)(out, run)))
    # Options that write or repeat: the same answer.
    cases.append(Case("motion", "repeat_3", ["motion", "small-sway", "--repeat", "3", "--no-checks"],
                      oracle=motion_vs(SWAY_REF)))
    cases.append(Case("motion", "table", ["motion", "small-sway", "--table", "--no-checks"],
                      oracle=motion_vs(SWAY_REF)))
    cases.append(Case("motion", "output_file", ["motion", "small-sway", "--no-checks", "-o", "{o}"],
                      outputs={"o": ".json"}, stdout="text", oracle=output_file_like(SWAY_REF)))
    cases.append(Case("motion", "plots", ["motion", "small-sway", "--no-checks", "--plot", "{d}"],
                      outputs={"d": ""}, oracle=plots_written(["motion.svg", "segment-1.svg",
                                                               "segment-2.svg", "segment-3.svg"])))
    cases.append(Case("motion", "plots_png", ["motion", "small-sway", "--no-checks", "--plot", "{d}",
                                              "--plot-format", "png"],
                      outputs={"d": ""}, oracle=plots_written(["motion.png", "segment-3.png"])))
    # The polygon limit of a contact shape: a 64-gon floor is a floor, a 65-gon an error.
    for n in [64, 65]:
        spec = mutate(SWAY, ["environment", 0, "shape"], {"polygon": regular_polygon(n, 2.0)})
        cases.append(motion_case(f"floor_polygon_{n}", spec, ["--no-checks"],
                                 expect="ok" if n == 64 else "error", keywords=[("64", "floor")],
                                 oracle=motion_vs(SWAY_REF, rel=1e-6)))
    # The largest grid (10,000 intervals per segment) on one segment with one IK step per
    # interval (all three segments at the default substeps take 15 s and 6 GB in release).
    one = mutate(SWAY, SEG, SWAY["segments"][:1])
    one["ik"] = {"substeps": 1}
    cases.append(motion_case("grid_max_one_segment", one, ["--grid", "10000", "--no-checks"], oracle=ok))
    cases.extend(motion_error_cases())
    # JVRC-1, the paper's robot (its description from PyPI): a handful.
    cases.append(Case("motion", "stair_climbing", ["motion", "stair-climbing", "--no-checks"],
                      oracle=lambda out, run: motion_ok(out, run) or (
                          None if abs(number(out["duration"]) - 5.564) < 1e-3
                          else f"duration {out['duration']}, the README's table says 5.564 s")))
    cases.append(Case("motion", "box_climbing_grid_bad", ["motion", "box-climbing", "--grid", "1"],
                      expect="error", keywords=[("--grid", "2..=10000")]))
    return cases


def output_file_like(ref):
    def check(out, run):
        if out.strip():
            return "-o FILE, yet the result went to standard output too"
        with open(run.paths["o"]) as f:
            data = json.load(f, parse_constant=lambda c: (_ for _ in ()).throw(ValueError(c)))
        return motion_vs(ref, checks=False)(data, run)
    return check


def svg_written(out, run):
    with open(run.paths["p"], encoding="utf-8") as f:
        head = f.read(200).lstrip()
    return None if head.startswith(("<svg", "<?xml")) else "the plot is not an SVG"


def plots_written(names):
    def check(out, run):
        for n in names:
            path = os.path.join(run.paths["d"], n)
            with open(path, "rb") as f:
                head = f.read(64)
            if n.endswith(".svg") and b"<svg" not in head and b"<?xml" not in head:
                return f"{n} is not an SVG"
            if n.endswith(".png") and not head.startswith(b"\x89PNG"):
                return f"{n} is not a PNG"
        return None
    return check


def motion_error_cases():
    """Mutations of small-sway (TOML: a message quotes the offending line, so names its key),
    each with the error it must give: the key or option, segments numbered from 1 with their
    names, and the fix."""
    cases = []
    nan, inf = float("nan"), float("inf")
    seg2_link = SEG + [1, "moves", 0, "links", 0]
    rect = lambda a, b: {"rectangle": {"half_length": a, "half_width": b}}
    bad = [
        # top level
        ("name_number", ["name"], 123, [("name", "string")]),
        ("robot_unknown", ["robot"], "tiny-humanoid", [("tiny-humanoid", "small-humanoid")]),
        ("robot_number", ["robot"], 5, [("robot", "name")]),
        ("robot_missing_urdf", ["robot"], {"urdf": "/nonexistent/robot.urdf", "surfaces": []},
         ["/nonexistent/robot.urdf"]),
        ("robot_bad_link", ["robot"], {"urdf": os.path.join(ROOT, "models/small_humanoid.urdf"),
                                       "surfaces": [{"name": "LF", "link": "l_sol", "position": [0, 0, 0],
                                                     "shape": rect(0.1, 0.05)}]}, [("l_sol", "link")]),
        ("robot_unknown_key", ["robot"], {"urdf": "x.urdf", "surfaces": [], "lock": {}}, [("lock", "unknown field")]),
        ("gravity_two", ["gravity"], [0.0, -9.81], [("gravity", "3")]),
        ("gravity_nan", ["gravity"], [0.0, 0.0, nan], ["gravity"]),
        ("gravity_string", ["gravity"], "down", [("gravity", "invalid type")]),
        ("unknown_key", ["gravty"], [0.0, 0.0, -9.81], [("gravty", "unknown field")]),
        ("no_segments_key", ["segments"], DELETE, [("segments", "missing")]),
        ("no_robot_key", ["robot"], DELETE, [("robot", "missing")]),
        # environment
        ("environment_empty", ["environment"], [], ["\"floor\""]),
        ("environment_duplicate", ["environment"], [SWAY["environment"][0]] * 2, [("floor", "unique")]),
        ("env_name_number", ["environment", 0, "name"], 7, [("name", "string")]),
        ("env_position_two", ["environment", 0, "position"], [0.0, 0.0], [("position", "3")]),
        ("env_position_nan", ["environment", 0, "position"], [nan, 0.0, 0.0], [("floor", "position"), ("floor", "finite")]),
        ("env_position_inf", ["environment", 0, "position"], [0.0, -inf, 0.0], [("floor", "position"), ("floor", "finite")]),
        ("env_friction_negative", ["environment", 0, "friction"], -1.0, [("floor", "friction")]),
        ("env_friction_nan", ["environment", 0, "friction"], nan, [("floor", "friction")]),
        ("env_friction_inf", ["environment", 0, "friction"], inf, [("floor", "friction")]),
        ("env_friction_huge", ["environment", 0, "friction"], 1e300, [("floor", "friction", "1e6")]),
        ("env_friction_zero", ["environment", 0, "friction"], 0.0, [("planning.friction", "floor")]),
        ("env_friction_string", ["environment", 0, "friction"], "high", [("friction", "invalid type")]),
        ("env_half_length_negative", ["environment", 0, "shape"], rect(-2.0, 2.0), [("floor", "half")]),
        ("env_half_length_zero", ["environment", 0, "shape"], rect(2.0, 0.0), [("floor", "half")]),
        ("env_half_length_nan", ["environment", 0, "shape"], rect(nan, 2.0), [("floor", "half"), ("floor", "finite")]),
        ("env_shape_circle", ["environment", 0, "shape"], {"circle": {"radius": 2.0}}, [("circle", "variant")]),
        ("env_shape_point", ["environment", 0, "shape"], "point", [("floor", "point", "rectangle")]),
        ("env_polygon_two", ["environment", 0, "shape"], {"polygon": [[0, 0], [1, 0]]}, [("floor", "polygon")]),
        ("env_polygon_nonconvex", ["environment", 0, "shape"],
         {"polygon": [[2, 2], [-2, 2], [0, 0], [-2, -2], [2, -2]]}, [("floor", "convex")]),
        ("env_polygon_vertex_three", ["environment", 0, "shape"], {"polygon": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]},
         [("polygon", "2"), ("vertex", "2")]),
        ("env_rpy_two", ["environment", 0, "rpy"], [0.0, 0.0], [("rpy", "3")]),
        ("env_rpy_nan", ["environment", 0, "rpy"], [0.0, nan, 0.0], [("floor", "rpy"), ("floor", "finite")]),
        ("env_rotation_scaled", ["environment", 0, "rotation"], [[2, 0, 0], [0, 1, 0], [0, 0, 1]],
         [("floor", "rotation")]),
        ("env_thickness_negative", ["environment", 0, "thickness"], -1.0, [("floor", "thickness")]),
        ("env_thickness_zero", ["environment", 0, "thickness"], 0.0, [("floor", "thickness")]),
        ("env_thickness_nan", ["environment", 0, "thickness"], nan, [("floor", "thickness")]),
        ("env_thickness_huge", ["environment", 0, "thickness"], 1e300, [("floor", "thickness")]),
        ("env_unknown_key", ["environment", 0, "frction"], 0.9, [("frction", "unknown field")]),
        # initial posture
        ("initial_empty", ["initial"], {}, ["initial", "standing", "configuration"]),
        ("initial_configuration_short", ["initial"], {"configuration": [0.0] * 5}, [("initial.configuration", "29")]),
        ("initial_configuration_nan", ["initial"], {"configuration": [nan] + [0.0] * 28}, ["initial.configuration"]),
        ("com_height_string", ["initial", "standing", "com_height"], "high", [("com_height", "invalid type")]),
        ("com_height_nan", ["initial", "standing", "com_height"], nan, ["com_height"]),
        ("com_height_inf", ["initial", "standing", "com_height"], inf, ["com_height"]),
        ("com_height_huge", ["initial", "standing", "com_height"], 1e300, ["com_height"]),
        ("com_height_low", ["initial", "standing", "com_height"], 0.3, ["com_height"]),
        ("com_height_negative", ["initial", "standing", "com_height"], -1.0, ["com_height"]),
        ("com_xy_far", ["initial", "standing", "com_xy"], [0.0, 5.0], ["com_xy"]),
        ("com_xy_one", ["initial", "standing", "com_xy"], [0.0], [("com_xy", "2")]),
        ("com_xy_nan", ["initial", "standing", "com_xy"], [nan, 0.0], ["com_xy"]),
        ("standing_surface_misspelled", ["initial", "standing", "contacts", "LF", "surface"], "flor",
         [("flor", "floor")]),
        ("standing_unknown_robot_surface", ["initial", "standing", "contacts"],
         {"XF": {"surface": "floor", "at": [0.0, 0.1]}, "RF": {"surface": "floor", "at": [0.0, -0.1]}},
         [("XF", "LF")]),
        ("standing_at_three", ["initial", "standing", "contacts", "LF", "at"], [0.0, 0.1, 0.0], [("at", "2")]),
        ("standing_at_nan", ["initial", "standing", "contacts", "LF", "at"], [nan, 0.1], [("LF", "finite")]),
        ("standing_yaw_string", ["initial", "standing", "contacts", "LF", "yaw"], "left", [("yaw", "invalid type")]),
        ("standing_yaw_inf", ["initial", "standing", "contacts", "LF", "yaw"], inf, [("LF", "finite")]),
        ("standing_no_contacts", ["initial", "standing", "contacts"], {}, [("initial.standing", "contact")]),
        ("standing_one_foot", ["initial", "standing", "contacts"], {"LF": {"surface": "floor", "at": [0.0, 0.1]}},
         [("segment 1", "shift onto the left foot", "RF")]),
        # planning
        ("planning_friction_zero", ["planning", "friction"], 0.0, ["planning.friction"]),
        ("planning_friction_negative", ["planning", "friction"], -0.5, ["planning.friction"]),
        ("planning_friction_nan", ["planning", "friction"], nan, ["planning.friction"]),
        ("planning_friction_above_surface", ["planning", "friction"], 1.0, [("planning.friction", "floor")]),
        ("planning_friction_string", ["planning", "friction"], "0.7", [("friction", "invalid type")]),
        ("area_scale_zero", ["planning", "area_scale"], 0.0, ["planning.area_scale"]),
        ("area_scale_above_one", ["planning", "area_scale"], 1.5, ["planning.area_scale"]),
        ("area_scale_nan", ["planning", "area_scale"], nan, ["planning.area_scale"]),
        ("area_scale_tiny", ["planning", "area_scale"], 2e-16, ["planning.area_scale", "[1e-6, 1]"]),
        ("margin_negative", ["planning", "margin"], -0.1, ["planning.margin"]),
        ("margin_above_half", ["planning", "margin"], 0.6, ["planning.margin"]),
        ("margin_nan", ["planning", "margin"], nan, ["planning.margin"]),
        ("friction_cone_sides_2", ["planning", "friction_cone"], {"sides": 2}, [("friction_cone", "sides")]),
        ("friction_cone_sides_65", ["planning", "friction_cone"], {"sides": 65}, [("friction_cone", "sides", "64")]),
        ("friction_cone_sides_negative", ["planning", "friction_cone"], {"sides": -4}, [("sides", "invalid value")]),
        ("friction_cone_approximation", ["planning", "friction_cone"], {"sides": 8, "approximation": "middle"},
         [("middle", "inner")]),
        ("planning_unknown_key", ["planning", "frction"], 0.7, [("frction", "unknown field")]),
    ]
    for key, bad_value, hint in [("w_com", -1.0, "weight"), ("w_link", nan, "weight"), ("w_posture", inf, "weight"),
                                 ("gain", 0.0, "gain"), ("contact_gain", -1.0, "gain"),
                                 ("joint_range", 0.0, "fraction"), ("joint_range", 1.5, "fraction"),
                                 ("substeps", 0, "1 to 100"), ("substeps", 101, "1 to 100"),
                                 ("com_blend", 0.0, "quarter"), ("com_blend", 1e9, "quarter"),
                                 ("clearance", -0.01, "clearance"), ("clearance", 0.6, "clearance"),
                                 ("clearance", nan, "clearance")]:
        bad.append((f"ik_{key}_{bad_value}", ["ik"], {key: bad_value}, [(f"ik.{key}", hint)]))
    bad += [
        ("ik_substeps_string", ["ik"], {"substeps": "4"}, [("substeps", "invalid type")]),
        ("ik_substeps_negative", ["ik"], {"substeps": -1}, [("substeps", "invalid value")]),
        ("ik_unknown_key", ["ik"], {"gian": 10.0}, [("gian", "unknown field")]),
        ("retiming_grid_1", ["retiming"], {"grid": 1}, [("retiming.grid", "2 to 10000")]),
        ("retiming_grid_10001", ["retiming"], {"grid": 10001}, [("retiming.grid", "2 to 10000")]),
        ("retiming_grid_negative", ["retiming"], {"grid": -3}, [("grid", "invalid value")]),
        ("retiming_discretization", ["retiming"], {"discretization": "midpoint"}, [("midpoint", "interpolation")]),
        ("retiming_dt_zero", ["retiming"], {"dt": 0.0}, [("retiming.dt", "0.0001")]),
        ("retiming_dt_nan", ["retiming"], {"dt": nan}, [("retiming.dt", "0.0001")]),
        ("retiming_check_dt_negative", ["retiming"], {"check_dt": -1.0}, [("retiming.check_dt", "0.0001")]),
        ("retiming_rest_to_rest_string", ["retiming"], {"rest_to_rest": "yes"}, [("rest_to_rest", "invalid type")]),
        ("retiming_unknown_key", ["retiming"], {"gird": 100}, [("gird", "unknown field")]),
        ("limits_velocity_zero", ["limits", "velocity"], 0.0, [("limits.velocity", "> 0")]),
        ("limits_velocity_negative", ["limits", "velocity"], -1.0, [("limits.velocity", "> 0")]),
        ("limits_velocity_nan", ["limits", "velocity"], nan, [("limits.velocity", "> 0")]),
        ("limits_velocity_true", ["limits", "velocity"], True, [("true", "false")]),
        ("limits_torque_string", ["limits", "torque"], "1.0", [("torque", "invalid type")]),
        ("limits_torque_inf", ["limits", "torque"], inf, [("limits.torque", "finite")]),
        ("limits_acceleration_zero", ["limits", "acceleration"], 0.0, [("limits.acceleration", "> 0")]),
        ("limits_acceleration_negative_default", ["limits", "acceleration"], {"default": -1.0},
         [("limits.acceleration.default", "> 0")]),
        ("limits_acceleration_nan_joint", ["limits", "acceleration"], {"r_knee": nan},
         [("limits.acceleration.r_knee", "> 0")]),
        ("limits_acceleration_misspelled", ["limits", "acceleration"], {"r_kneee": 40.0}, [("r_kneee", "r_knee")]),
        ("limits_acceleration_base", ["limits", "acceleration"], {"root_joint": 10.0}, [("root_joint", "remove")]),
        ("limits_unknown_key", ["limits", "acceleraton"], 10.0, [("acceleraton", "unknown field")]),
        # segments: numbered from 1, with their names
        ("segments_empty", SEG, [], [("no segments", "at least one")]),
        ("segment_stance_empty", SEG + [0, "stance"], {}, [("segment 1", "shift onto the left foot", "stance")]),
        ("segment_surface_misspelled", SEG + [1, "stance"], {"LF": "flor"},
         [("segment 2", "step forward with the right foot", "flor")]),
        ("segment_robot_surface_unknown", SEG + [2, "stance"], {"LF": "floor", "XF": "floor"},
         [("segment 3", "back to both feet", "XF")]),
        ("segment_stance_number", SEG + [0, "stance"], {"LF": 1}, [("LF", "invalid type")]),
        # a segment without moves is a planned CoM shift (the footholds planner): the right
        # foot leaves the floor there without landing, which the next segment names
        ("segment_no_moves", SEG + [1, "moves"], [], [("segment 3", "back to both feet", "land it there")]),
        ("segment_w_link_negative", SEG + [0, "w_link"], -1.0, [("segment 1", "shift onto the left foot", "w_link")]),
        ("segment_gain_zero", SEG + [2, "gain"], 0.0, [("segment 3", "back to both feet", "gain")]),
        ("segment_name_number", SEG + [0, "name"], 42, [("name", "string")]),
        ("segment_unknown_key", SEG + [0, "moevs"], [], [("moevs", "unknown field")]),
    ]
    for value in [0.0, -1.0, nan, inf, 1e5, 1e-4]:
        bad.append((f"move_duration_{value:g}", SEG + [0, "moves", 0, "duration"], value,
                    [("segment 1", "shift onto the left foot", "move 1", "duration")]))
    bad += [
        ("move_duration_huge", SEG + [2, "moves", 0, "duration"], 1e300,
         [("segment 3", "back to both feet", "move 1", "duration")]),
        ("move_duration_string", SEG + [0, "moves", 0, "duration"], "2", [("duration", "invalid type")]),
        ("com_by_nan", SEG + [0, "moves", 0, "com"], {"by": [nan, 0.09, 0.0]},
         [("segment 1", "shift onto the left foot", "move 1", "CoM")]),
        ("com_by_two", SEG + [0, "moves", 0, "com"], {"by": [0.0, 0.09]}, [("com", "3 numbers")]),
        ("com_by_and_to", SEG + [0, "moves", 0, "com"], {"by": [0.0, 0.09, 0.0], "to": [0.0, 0.0, 0.9]},
         [("com", "by", "to")]),
        ("com_empty", SEG + [0, "moves", 0, "com"], {}, [("com", "by", "to")]),
        ("move_unknown_key", SEG + [0, "moves", 0, "comm"], {"by": [0.0, 0.0, 0.0]}, [("comm", "unknown field")]),
        ("link_surface_unknown", seg2_link + ["surface"], "XF",
         [("segment 2", "step forward with the right foot", "XF")]),
        ("link_is_contact", seg2_link + ["surface"], "LF",
         [("segment 2", "step forward with the right foot", "move 1", "LF")]),
        ("link_by_and_to", seg2_link + ["to"], [0.0, -0.1, 0.05],
         [("segment 2", "step forward with the right foot", "move 1", "exactly one")]),
        ("link_by_and_rpy", seg2_link + ["rpy"], [0.0, 0.0, 0.1],
         [("segment 2", "step forward with the right foot", "move 1", "exactly one")]),
        ("link_by_nan", seg2_link + ["by"], [0.05, nan, 0.05],
         [("segment 2", "step forward with the right foot", "move 1", "non-finite")]),
        ("link_rotate_by_inf", seg2_link + ["rotate_by"], [0.0, inf, 0.0],
         [("segment 2", "step forward with the right foot", "move 1", "non-finite")]),
        ("link_onto_misspelled", SEG + [1, "moves", 1, "links", 0, "onto"], "flor",
         [("segment 2", "step forward with the right foot", "move 2", "flor")]),
        ("link_onto_without_at", SEG + [1, "moves", 1, "links", 0, "at"], DELETE,
         [("segment 2", "step forward with the right foot", "move 2", "at")]),
        ("link_at_one", SEG + [1, "moves", 1, "links", 0, "at"], [0.1], [("at", "2")]),
        ("link_twice", SEG + [1, "moves", 0, "links"], [{"surface": "RF", "by": [0.05, 0.0, 0.05]}] * 2,
         [("segment 2", "step forward with the right foot", "move 1", "twice")]),
        ("link_unknown_key", seg2_link + ["bye"], [0.0, 0.0, 0.0], [("bye", "unknown field")]),
    ]
    for name, path, value, kw in bad:
        spec = mutate(SWAY, path, value)
        cases.append(motion_case(f"bad_{name}", spec, expect="error", keywords=kw))
    # Out of reach: a landing 5 m away on a floor that extends there is an answer saying the
    # IK failed in segment 2, not an error and not an optimal plan; off the 2 m floor, the same
    # landing is refused before any work, naming the move and the distance (issue 30).
    far = mutate(SWAY, SEG + [1, "moves", 1, "links", 0, "at"], [5.0, -0.1])
    wide = mutate(far, ["environment", 0, "shape", "rectangle", "half_length"], 6.0)
    cases.append(motion_case("landing_out_of_reach", wide, ["--no-checks"], oracle=status_is("ik_failed", 2)))
    cases.append(motion_case("landing_off_the_floor", far, expect="error",
                             keywords=[("segment 2", "move 2", '"RF" placed at [5, -0.1]', "3.11",
                                        "outside that surface")]))
    # Gravity pulling the robot off the floor: no timing holds (an answer, not retimable).
    up = mutate(SWAY, ["gravity"], [0.0, 0.0, 9.81])
    cases.append(motion_case("gravity_up", up, ["--no-checks"], oracle=status_is("not_retimable", 1)))
    # A safety margin tightens every row: never faster (or not retimable).
    cases.append(motion_case("margin_tightens", mutate(SWAY, ["planning", "margin"], 0.01), ["--no-checks"],
                             oracle=motion_vs(SWAY_REF, "ge", checks=False)))
    # Larger friction pyramids than the default inscribed octagon: never slower.
    for cone in [{"sides": 16}, {"sides": 4, "approximation": "outer"}]:
        cases.append(motion_case(f"friction_cone_{cone['sides']}_{cone.get('approximation', 'inner')}",
                                 mutate(SWAY, ["planning", "friction_cone"], cone), ["--no-checks"],
                                 oracle=motion_vs(SWAY_REF, "le", checks=False)))
    # Segment names are optional ("segment k"): the same answer.
    unnamed = json.loads(json.dumps(SWAY))
    for s in unnamed["segments"]:
        del s["name"]
    cases.append(motion_case("segments_unnamed", unnamed, ["--no-checks"], oracle=motion_vs(SWAY_REF)))
    # Text-level mistakes.
    text = toml_doc(SWAY)
    cases.append(motion_case("bad_toml_duplicate_key", text.replace("friction = 0.9", "friction = 0.9\nfriction = 0.8"),
                             expect="error", keywords=[("duplicate", "friction")]))
    cases.append(motion_case("bad_toml_truncated", text[: len(text) // 2] + "[[segm", expect="error",
                             keywords=["invalid toml"]))
    cases.append(motion_case("bad_toml_as_json", text, ext=".json", expect="error", keywords=["invalid json"]))
    cases.append(motion_case("bad_json_as_toml", json.dumps(SWAY), expect="error", keywords=["invalid toml"]))
    cases.append(motion_case("bad_empty", "", expect="error", keywords=["empty"]))
    cases.append(motion_case("utf8_bom", "\ufeff" + text, ["--no-checks"], oracle=motion_vs(SWAY_REF)))
    # JSON written by a program on one line: a wrong type must still name its key.
    for name, path, value, kw in [("com_height", ["initial", "standing", "com_height"], "high", "com_height"),
                                  ("duration", SEG + [0, "moves", 0, "duration"], "2", "duration"),
                                  ("friction", ["planning", "friction"], "0.7", "friction")]:
        cases.append(motion_case(f"bad_json_type_{name}", mutate(SWAY, path, value), ext=".json",
                                 expect="error", keywords=[kw]))
    # Options on the command line.
    for name, args, kw in [
        ("grid_0", ["--grid", "0"], [("--grid", "2..=10000")]),
        ("grid_10001", ["--grid", "10001"], [("--grid", "2..=10000")]),
        ("grid_negative", ["--grid", "-1"], ["--grid"]),
        ("grid_float", ["--grid", "1e3"], [("--grid", "1e3")]),
        ("dt_zero", ["--dt", "0"], [("dt", "0.0001")]),
        ("dt_negative", ["--dt", "-0.01"], [("dt", "0.0001")]),
        ("dt_nan", ["--dt", "nan"], [("dt", "0.0001")]),
        ("dt_inf", ["--dt", "inf"], [("dt", "finite")]),
        ("dt_below_min", ["--dt", "5e-5"], [("dt", "0.0001")]),
        ("dt_text", ["--dt", "fast"], [("--dt", "fast")]),
        ("check_dt_zero", ["--check-dt", "0"], [("check_dt", "0.0001")]),
        ("check_dt_negative", ["--check-dt", "-1"], [("check_dt", "0.0001")]),
        ("time_scale_zero", ["--time-scale", "0"], [("time scale", "> 0")]),
        ("time_scale_negative", ["--time-scale", "-2"], [("time scale", "> 0")]),
        ("time_scale_nan", ["--time-scale", "nan"], [("time scale", "> 0")]),
        ("time_scale_inf", ["--time-scale", "inf"], [("time scale", "finite")]),
        ("check_friction_zero", ["--check-friction", "0"], [("--check-friction", "> 0")]),
        ("check_friction_negative", ["--check-friction", "-0.5"], [("--check-friction", "> 0")]),
        ("check_friction_nan", ["--check-friction", "nan"], [("--check-friction", "> 0")]),
        ("check_friction_inf", ["--check-friction", "inf"], [("--check-friction", "> 0")]),
        ("plot_format_pdf", ["--plot", "d", "--plot-format", "pdf"], [("--plot-format", "svg")]),
        ("plot_unwritable", ["--plot", "/proc/nonexistent/plots"], ["/proc/nonexistent/plots"]),
        ("output_unwritable", ["-o", "/proc/nonexistent/r.json"], ["/proc/nonexistent/r.json"]),
        ("repeat_zero", ["--repeat", "0"], [("--repeat", "1..=")]),
        ("segments_option", ["--segments", "1..2"], [("--segments", "unexpected")]),
    ]:
        cases.append(Case("motion", f"bad_option_{name}", ["motion", "small-sway", *args], expect="error",
                          keywords=kw))
    for name, source, kw in [("unknown_name", "moonwalk", [("moonwalk", "small-sway")]),
                             ("name_case", "Small-Sway", [("Small-Sway", "small-sway")]),
                             ("directory", "/", [("/", "small-sway")]),
                             ("missing_file", "/nonexistent/motion.toml", ["/nonexistent/motion.toml"])]:
        cases.append(Case("motion", f"bad_source_{name}", ["motion", source], expect="error", keywords=kw))
    return cases


def status_is(status, segment):
    """An answer with this status, its failure in segment `segment` (numbered from 1)."""
    def check(out, run):
        f = out.get("failure") or {}
        if out.get("status") != status or f.get("segment") != segment:
            return f"status {out.get('status')}, failure in segment {f.get('segment')}; expected {status} in {segment}"
        if not f.get("segment_name") or not f.get("reason"):
            return "the failure has no segment name or reason"
        return None
    return check


# ---------------------------------------------------------------------------------------------
# `stance simulate`: argument and file errors (found before MuJoCo runs), and one real run


def simulate_cases():
    cases = []
    for name, args, kw in [
        ("segments_zero", ["--segments", "0..1"], [("--segments", "1-based")]),
        ("segments_reversed", ["--segments", "3..1"], [("--segments", "FIRST..LAST")]),
        ("segments_out_of_range", ["--segments", "1..9"], [("segments 1..9", "3 segments")]),
        ("segments_beyond", ["--segments", "4..4"], [("segments 4..4", "3 segments")]),
        ("segments_text", ["--segments", "a..b"], [("--segments", "FIRST..LAST")]),
        ("segments_dash", ["--segments", "1-2"], [("--segments", "FIRST..LAST")]),
        ("segments_open", ["--segments", "2.."], [("--segments", "FIRST..LAST")]),
        ("segments_empty", ["--segments", ""], [("--segments", "FIRST..LAST")]),
        ("segments_negative", ["--segments", "-1..2"], [("--segments", "FIRST..LAST")]),
        ("segments_huge", ["--segments", "1..99999999999999999999999"], [("--segments", "FIRST..LAST")]),
        ("friction_zero", ["--friction", "0"], [("--friction", "(0, 10]")]),
        ("friction_negative", ["--friction", "-0.5"], [("--friction", "(0, 10]")]),
        ("friction_nan", ["--friction", "nan"], [("--friction", "(0, 10]")]),
        ("friction_inf", ["--friction", "inf"], [("--friction", "(0, 10]")]),
        ("friction_above_10", ["--friction", "11"], [("--friction", "(0, 10]")]),
        ("friction_text", ["--friction", "high"], [("--friction", "high")]),
        ("time_scale_zero", ["--time-scale", "0"], [("time scale", "> 0")]),
        ("time_scale_negative", ["--time-scale", "-1"], [("time scale", "> 0")]),
        ("time_scale_nan", ["--time-scale", "nan"], [("time scale", "> 0")]),
        ("time_scale_inf", ["--time-scale", "inf"], [("time scale", "finite")]),
        # Bounded work: played a billion times slower, the motion would last 65 years: refused
        # with the least time scale that fits the simulator's 120 s.
        ("time_scale_1e-9", ["--time-scale", "1e-9"], [("time scale", "at least 0.018")]),
        ("time_scale_1e-300", ["--time-scale", "1e-300"], [("time scale", "at least 0.018")]),
        ("time_scale_text", ["--time-scale", "slow"], [("--time-scale", "slow")]),
        ("keep_unwritable", ["--keep", "/proc/nonexistent/keep"], ["/proc/nonexistent/keep"]),
        ("unknown_option", ["--grid", "10"], [("--grid", "unexpected")]),
        ("repeat_zero", ["--repeat", "0"], [("--repeat", "1..=")]),
        ("no_meshes_without_view", ["--no-meshes"], [("--view", "required")]),
    ]:
        cases.append(Case("simulate", f"bad_{name}", ["simulate", "small-sway", *args], expect="error",
                          keywords=kw))
    for name, source, kw in [("unknown_name", "moonwalk", [("moonwalk", "small-sway")]),
                             ("missing_file", "/nonexistent/m.toml", ["/nonexistent/m.toml"])]:
        cases.append(Case("simulate", f"bad_source_{name}", ["simulate", source], expect="error", keywords=kw))
    nan = float("nan")
    for name, path, value, kw in [
        ("com_height_nan", ["initial", "standing", "com_height"], nan, ["com_height"]),
        ("segment_surface_misspelled", SEG + [1, "stance"], {"LF": "flor"},
         [("segment 2", "step forward with the right foot", "flor")]),
        ("move_duration_zero", SEG + [2, "moves", 0, "duration"], 0.0,
         [("segment 3", "back to both feet", "move 1", "duration")]),
        ("limits_velocity_zero", ["limits", "velocity"], 0.0, [("limits.velocity", "> 0")]),
    ]:
        cases.append(Case("simulate", f"bad_file_{name}", ["simulate", "{f}"], {"f": mutate(SWAY, path, value)},
                          ext=".toml", expect="error", keywords=kw))
    # A motion that cannot be retimed has nothing to simulate: one line saying why.
    cases.append(Case("simulate", "bad_not_retimable", ["simulate", "{f}"],
                      {"f": mutate(SWAY, ["gravity"], [0.0, 0.0, 9.81])}, ext=".toml", expect="error",
                      keywords=[("could not be retimed", "segment 1")]))
    # One real run (about 4 s in release): the built-in motion holds in MuJoCo.
    cases.append(Case("simulate", "small_sway_holds", ["simulate", "small-sway"], oracle=sim_holds))
    return cases


def sim_holds(out, run):
    if out.get("held") is not True or out.get("fell") is not False:
        return f"held {out.get('held')}, fell {out.get('fell')}: {out.get('reason')}"
    if number(out["max_slip_m"]) > 5e-3 or number(out["contact_losses"]) != 0:
        return f"slip {out['max_slip_m']} m, {out['contact_losses']} contact losses"
    for key in ("max_base_error_m", "max_com_error_m", "max_friction_usage", "sim_time_s", "wall_s"):
        number(out[key])
    return None


# ---------------------------------------------------------------------------------------------
# `stance view`: one page per scene, motion or result


def page_data(run, key="page"):
    """The page's data block (the `stance-data` JSON) as the page's script reads it."""
    with open(run.paths[key], encoding="utf-8") as f:
        html = f.read()
    start = '<script id="stance-data" type="application/json">'
    i = html.index(start) + len(start)
    text = html[i:html.index("</script>", i)].replace("<\\/", "</")
    data = json.loads(text, parse_constant=lambda c: (_ for _ in ()).throw(ValueError(f"{c} in the page")))
    bad = nulls_in_lists(data)
    if bad:
        raise ValueError(f"null (a NaN) in the page's data at {bad}")
    return data


def nulls_in_lists(v, where="data"):
    """Where a list holds a null: NaN written by serde_json (a number expected)."""
    if isinstance(v, list):
        for i, x in enumerate(v):
            if x is None:
                return f"{where}[{i}]"
            w = nulls_in_lists(x, f"{where}[{i}]")
            if w:
                return w
    elif isinstance(v, dict):
        for k, x in v.items():
            w = nulls_in_lists(x, f"{where}.{k}")
            if w:
                return w
    return None


def scene_page(contacts, polygon_of=None):
    """A scene's page: one stance with `contacts` contacts, a robust region; with `polygon_of`
    (the arguments of `stance equilibrium polygon`), its static polygon is that one (the page
    rounds to 0.1 mm)."""
    def check(out, run):
        d = page_data(run)
        if d["kind"] != "scene" or len(d["stances"]) != 1 or len(d["stances"][0]["contacts"]) != contacts:
            return f"kind {d['kind']}, {len(d['stances'])} stances, expected one of {contacts} contacts"
        if d["region"] is None:
            return "no robust region on a scene's page"
        if polygon_of:
            want = run([*polygon_of])
            got = d["stances"][0]["polygon"]
            if want is None or got is None:
                return "no polygon"
            box = lambda vs: [min(v[0] for v in vs), max(v[0] for v in vs), min(v[1] for v in vs), max(v[1] for v in vs)]
            if max(abs(a - b) for a, b in zip(box(got["vertices"]), box(want["vertices"]))) > 2e-4:
                return f"page polygon {box(got['vertices'])}, `stance equilibrium polygon` {box(want['vertices'])}"
        return None
    return check


def motion_page(ref, segments):
    """A motion's page: a stance per segment, the robot played to the motion's duration."""
    def check(out, run):
        d = page_data(run)
        r = run.cached(*ref)
        if d["kind"] != "motion" or len(d["stances"]) != segments or d["robot"] is None:
            return f"kind {d['kind']}, {len(d['stances'])} stances, robot {d['robot'] is not None}"
        t = numbers(d["robot"]["t"])
        if r is None or abs(t[-1] - number(r["duration"])) > 1e-6 * r["duration"] + 0.02:
            return f"played to {t[-1]} s, the motion lasts {r and r['duration']} s"
        numbers(d["robot"]["positions"])
        return None
    return check


def view_cases():
    cases = []
    page = {"page": ".html"}
    for name, n in [("single-support", 1), ("double-support", 2), ("stairs", 2), ("robust-equilibrium", None)]:
        cases.append(Case("view", f"scene_{name}", ["view", name, "-o", "{page}"], outputs=page, stdout="text",
                          oracle=scene_page(n, ["equilibrium", "polygon", name]) if n else
                          (lambda out, run: None if page_data(run)["kind"] == "scene" else "not a scene")))
    feet = rect_scene([("l", [0, 0.1, 0], 0.11, 0.065), ("r", [0.1, -0.1, 0], 0.11, 0.065)])
    cases.append(Case("view", "scene_file", ["view", "{f}", "-o", "{page}"], {"f": feet}, outputs=page,
                      stdout="text", oracle=scene_page(2, ["equilibrium", "polygon", "{f}"])))
    for name, extra in [("com_height", ["--com-height", "1.5"]), ("com_height_negative", ["--com-height=-2"]),
                        ("gravities", ["--gravity=0.5,0,-9.81", "--gravity=-0.5,0,-9.81"]),
                        ("as_scene", ["--scene"])]:
        cases.append(Case("view", f"scene_file_{name}", ["view", "{f}", "-o", "{page}", *extra], {"f": feet},
                          outputs=page, stdout="text", oracle=scene_page(2)))
    # A scene far from the origin and a large one: a page, its numbers finite.
    far = rect_scene([("l", [1e6, 0.1, 0], 0.11, 0.065), ("r", [1e6, -0.1, 0], 0.11, 0.065)])
    cases.append(Case("view", "scene_far", ["view", "{f}", "-o", "{page}"], {"f": far}, outputs=page,
                      stdout="text", oracle=scene_page(2)))
    cases.append(Case("view", "scene_box_climbing", ["view", "box-climbing", "--scene", "-o", "{page}"],
                      outputs=page, stdout="text", oracle=scene_page(2)))
    cases.append(Case("view", "motion_small_sway", ["view", "small-sway", "-o", "{page}"], outputs=page,
                      stdout="text", oracle=motion_page(SWAY_REF, 3)))
    cases.append(Case("view", "motion_file", ["view", "{f}", "-o", "{page}"], {"f": SWAY}, ext=".toml",
                      outputs=page, stdout="text", oracle=motion_page(SWAY_REF, 3)))
    cases.append(Case("view", "motion_file_as_motion", ["view", "{f}", "--motion", "-o", "{page}"], {"f": SWAY},
                      outputs=page, stdout="text", oracle=motion_page(SWAY_REF, 3)))
    # The JSON a `stance motion` run wrote.
    result = lambda run: run.cached(*SWAY_REF)

    def result_without(key):
        def content(run):
            r = dict(run.cached(*SWAY_REF))
            del r[key]
            return r
        return content
    cases.append(Case("view", "motion_result", ["view", "{f}", "-o", "{page}"], {"f": result}, outputs=page,
                      stdout="text", oracle=motion_page(SWAY_REF, 3)))
    cases.append(Case("view", "motion_result_as_motion", ["view", "{f}", "--motion", "-o", "{page}"],
                      {"f": result}, outputs=page, stdout="text", oracle=motion_page(SWAY_REF, 3)))
    # A result without a trajectory (as a motion that could not be retimed writes it): a page
    # of its stances.
    cases.append(Case("view", "motion_result_without_trajectory", ["view", "{f}", "-o", "{page}"],
                      {"f": result_without("trajectory")}, outputs=page, stdout="text",
                      oracle=lambda out, run: None if page_data(run)["kind"] == "motion" else "not a motion page"))
    # The robot as it looks: the small humanoid's primitives with or without --no-meshes (no
    # mesh file either way), JVRC-1's 35 Collada meshes, one per visual of its URDF.
    def looks(meshes, files):
        def check(out, run):
            r = page_data(run)["robot"]
            if len(r["meshes"]) != meshes or len(r["mesh_data"]) != files:
                return f"{len(r['meshes'])} drawn geometries of {len(r['mesh_data'])} files, expected {meshes} of {files}"
            if len(r["orientations"]) != len(r["t"]):
                return "no orientation per frame"
            return None
        return check
    cases.append(Case("view", "motion_primitives", ["view", "small-sway", "-o", "{page}"], outputs=page,
                      stdout="text", oracle=looks(26, 0)))
    cases.append(Case("view", "motion_no_meshes", ["view", "small-sway", "--no-meshes", "-o", "{page}"],
                      outputs=page, stdout="text", oracle=looks(26, 0)))
    cases.append(Case("view", "motion_jvrc1_meshes", ["view", "stair-climbing", "-o", "{page}"], outputs=page,
                      stdout="text", oracle=looks(35, 35)))
    # A simulation report (written here: no MuJoCo needed), drawn beside its plan; one whose
    # motion changed since, or without its trajectory, is refused.
    def sim_report(duration=None, trajectory=True):
        def content(run):
            r = run.cached(*SWAY_REF)
            q0 = r["trajectory"]["q"][0]
            rep = {"held": True, "reason": "held: largest slip 0.10 mm", "time_scale": 1.0,
                   "events": [{"kind": "slip", "t": 0.5, "position": [0, 0.1, 0], "text": "LF slipped"}],
                   "motion": {"motion": "small-sway", "time_scale": 1.0, "segments": None, "no_limits": False,
                              "duration": r["duration"] if duration is None else duration}}
            if trajectory:
                rep["trajectory"] = {"t": [0.0, 0.02], "q": [q0, q0], "plan_t0": 0.0}
            return rep
        return content

    def sim_page(out, run):
        d = page_data(run)
        sim = d.get("simulation")
        if sim is None or len(sim["events"]) != 1 or not d["title"].endswith("held in MuJoCo"):
            return f"title {d['title']!r}, simulation {sim is not None}"
        return None
    cases.append(Case("view", "simulation_report", ["view", "{f}", "-o", "{page}"], {"f": sim_report()},
                      outputs=page, stdout="text", oracle=sim_page))
    # Bad sources: one line naming the file (or the names there are) and what to fix.
    def result_edit(edit):
        def content(run):
            r = json.loads(json.dumps(run.cached(*SWAY_REF)))
            edit(r)
            return r
        return content

    def result_text(run):
        return json.dumps(run.cached(*SWAY_REF))
    for name, args, files, kw in [
        ("missing_file", ["/nonexistent/scene.json"], {}, ["/nonexistent/scene.json"]),
        ("unknown_name", ["moon"], {}, [("moon", "small-sway", "stairs")]),
        ("directory", ["/"], {}, [("\"/\"", "file")]),
        ("result_truncated", ["{f}"], {"f": lambda run: result_text(run)[:5000]}, [("{f}", "json")]),
        ("result_q_short", ["{f}"], {"f": result_edit(lambda r: r["trajectory"].update(
            q=[q[:28] for q in r["trajectory"]["q"]]))}, [("{f}", "29")]),
        ("result_robot_unknown", ["{f}"], {"f": result_edit(lambda r: r["robot"].update(name="tiny-humanoid"))},
         [("tiny-humanoid", "robot")]),
        ("result_t_string", ["{f}"], {"f": result_edit(lambda r: r["trajectory"].update(t="x"))}, [("{f}", "invalid type")]),
        ("result_without_robot", ["{f}"], {"f": result_without("robot")}, [("{f}", "robot")]),
        ("result_as_scene", ["{f}", "--scene"], {"f": result}, [("{f}", "unknown field"), ("{f}", "mass")]),
        ("scene_as_motion", ["{f}", "--motion"], {"f": feet}, [("{f}", "robot"), ("{f}", "unknown field")]),
        ("scene_bad_friction", ["{f}"], {"f": rect_scene([("l", [0, 0, 0], 0.1, 0.05)], friction=-1)},
         [("`l`", "friction")]),
        ("motion_bad_surface", ["{f}"], {"f": mutate(SWAY, SEG + [1, "stance"], {"LF": "flor"})},
         [("segment 2", "flor")]),
        ("empty_file", ["{f}"], {"f": ""}, [("{f}", "empty")]),
        ("bare_array", ["{f}"], {"f": "[1, 2]"}, [("{f}", "object")]),
        ("not_json", ["{f}"], {"f": "view me"}, [("{f}", "json")]),
        ("sim_report_changed", ["{f}"], {"f": sim_report(duration=99.0)}, [("{f}", "changed", "simulate")]),
        ("sim_report_without_trajectory", ["{f}"], {"f": sim_report(trajectory=False)},
         [("{f}", "trajectory", "simulate again")]),
    ]:
        cases.append(Case("view", f"bad_{name}", ["view", *args, "-o", "{page}"], files, outputs=page,
                          expect="error", keywords=kw, ext=".toml" if name == "motion_bad_surface" else None))
    for name, args, kw in [
        ("com_height_nan", ["--com-height", "nan"], [("--com-height", "finite")]),
        ("com_height_inf", ["--com-height", "inf"], [("--com-height", "finite")]),
        ("gravity_two", ["--gravity", "0,-9.81"], [("--gravity", "three")]),
        ("gravity_nan", ["--gravity", "0,0,nan"], [("--gravity", "finite")]),
        ("scene_and_motion", ["--scene", "--motion"], [("--scene", "--motion")]),
        ("output_unwritable", ["-o", "/proc/nonexistent/v.html"], ["/proc/nonexistent/v.html"]),
        ("motion_as_scene", ["--scene"], [("small-sway", "scene")]),
    ]:
        cases.append(Case("view", f"bad_option_{name}", ["view", "small-sway", *args], expect="error", keywords=kw))
    return cases


# ---------------------------------------------------------------------------------------------
# `stance setup --check`: where the virtualenv is, and whether it is ready (installs nothing)


def setup_cases():
    venv = os.environ.get("STANCE_VENV", "")
    ready = os.path.isfile(os.path.join(venv, "bin", "python"))

    def says(folder, exists):
        def check(out, run):
            want = f"{folder() if callable(folder) else folder} ({'ready' if exists else 'missing: run `stance setup`'})"
            if out.strip() != want or out.count("\n") != 1:
                return f"printed {out!r}, expected {want!r}"
            return None
        return check
    cases = [
        Case("setup", "check_venv", ["setup", "--check"], stdout="text", oracle=says(venv, ready)),
        Case("setup", "check_missing", ["setup", "--check"], stdout="text", env={"STANCE_VENV": "/nonexistent/venv"},
             oracle=says("/nonexistent/venv", False)),
        Case("setup", "check_spaces", ["setup", "--check"], stdout="text", env={"STANCE_VENV": "/nonexistent/my venv"},
             oracle=says("/nonexistent/my venv", False)),
        # An empty folder is not a virtualenv.
        Case("setup", "check_empty_folder", ["setup", "--check"], stdout="text", env={"STANCE_VENV": "/"},
             oracle=says("/", False)),
        # Without STANCE_VENV: the per-user data folder.
        Case("setup", "check_default", ["setup", "--check"], stdout="text",
             env={"STANCE_VENV": None, "XDG_DATA_HOME": "/nonexistent/data"},
             oracle=says("/nonexistent/data/stance/.venv", False)),
        Case("setup", "check_python_ignored", ["setup", "--check", "--python", "/nonexistent/python3"],
             stdout="text", oracle=says(venv, ready)),
        # Set but empty (`STANCE_VENV= stance ...`): a folder, or an error naming the variable.
        Case("setup", "check_empty_variable", ["setup", "--check"], stdout="text", env={"STANCE_VENV": ""},
             expect="ok_or_error", keywords=["STANCE_VENV"],
             oracle=lambda out, run: None if out.split(" (")[0].strip() else f"printed {out!r}: no folder"),
        Case("setup", "bad_option", ["setup", "--chek"], expect="error", keywords=[("--chek", "--check")]),
        Case("setup", "bad_argument", ["setup", "--check", "now"], expect="error", keywords=[("now", "unexpected")]),
    ]
    return cases


# ---------------------------------------------------------------------------------------------
# `stance retime-joints`: mutations of gallery/arm-swing.toml (the three-link arm)


def arm_swing():
    """gallery/arm-swing.toml as a dict, its URDF by absolute path (case `joints/file_as_gallery`
    checks that it is the gallery's file)."""
    return {
        "urdf": os.path.join(ROOT, "models/three_link_arm.urdf"),
        "joints": ["yaw", "shoulder", "elbow", "wrist"],
        "waypoints": [[0.0, 0.3, 0.5, 0.0], [1.0, -0.5, 1.2, 2.0], [2.0, 0.4, 0.3, 4.0]],
        "interpolation": "spline",
        "spline": "not-a-knot",
        "grid_points": 101,
        "dt": 0.01,
        "limits": {"velocity": 1.0, "torque": 1.0, "acceleration": 10.0},
    }


ARM = arm_swing()
ARM_REF = ("arm", ["retime-joints", os.path.join(ROOT, "gallery/arm-swing.toml")])


def joints_vs(ref, relation="eq", rel=1e-6, ratio=None):
    """Optimal, its duration `relation` the reference's (see motion_vs); with `ratio`, the
    checks' velocity, acceleration and torque ratios at most 1 + ratio."""
    def check(out, run):
        if relation == "ge" and out.get("status") != "optimal" and out.get("failure"):
            return None
        if out.get("status") != "optimal":
            return f"status {out.get('status')}: {out.get('failure')}"
        r = run.cached(*ref)
        if r is None:
            return f"the reference `stance {' '.join(ref[1])}` failed"
        d, want = number(out["duration"]), number(r["duration"])
        if relation == "eq" and not rel_close(d, want, rel):
            return f"duration {d!r}, expected {want!r}"
        if relation == "ge" and d < want * (1 - rel):
            return f"duration {d!r} shorter than {want!r}, whose limits are looser"
        if relation == "le" and d > want * (1 + rel):
            return f"duration {d!r} longer than {want!r}, whose limits are tighter"
        if ratio is not None:
            c = out["checks"]
            worst = max(number(c[k]) for k in ("max_velocity_ratio", "max_acceleration_ratio", "max_torque_ratio"))
            if worst > 1 + ratio:
                return f"a limit exceeded by a ratio {worst!r} > 1 + {ratio:g}"
        return None
    return check


def same_refinement(ref):
    def check(out, run):
        a, b = out.get("refinement"), run.cached(*ref).get("refinement")
        pa, pb = (a or {}).get("points_added", 0), (b or {}).get("points_added", 0)
        if pa != pb:
            return f"the refinement added {pa} grid points ({a}), the reference's {pb}"
        return None
    return check


def joints_case(name, spec, args=(), expect="ok", keywords=(), oracle=None, ext=".toml"):
    return Case("joints", name, ["retime-joints", "{f}", *args], {"f": spec}, expect=expect,
                keywords=keywords, oracle=oracle, ext=ext)


def joints_cases():
    cases = []
    nan, inf = float("nan"), float("inf")
    arm_free_acc = ("arm_no_acceleration", ["retime-joints", "{f}"], ".json", mutate(ARM, ["limits", "acceleration"], DELETE))
    cases.append(Case("joints", "gallery", ARM_REF[1], oracle=joints_vs(ARM_REF, ratio=1e-3)))
    cases.append(joints_case("file_as_gallery", ARM, oracle=joints_vs(ARM_REF, rel=1e-12)))
    cases.append(joints_case("json_as_gallery", ARM, ext=".json", oracle=joints_vs(ARM_REF, rel=1e-12)))
    # Tighter limits never shorten the motion, looser never lengthen it.
    for name, path, value, relation in [
        ("acceleration_5", ["limits", "acceleration"], 5.0, "ge"),
        ("acceleration_20", ["limits", "acceleration"], 20.0, "le"),
        ("acceleration_elbow_5", ["limits", "acceleration"], {"default": 10.0, "elbow": 5.0}, "ge"),
        ("acceleration_wrist_1", ["limits", "acceleration"], {"default": 10.0, "wrist": 1.0}, "ge"),
        ("acceleration_none", ["limits", "acceleration"], DELETE, "le"),
        ("velocity_half", ["limits", "velocity"], 0.5, "ge"),
        ("velocity_double", ["limits", "velocity"], 2.0, "le"),
        ("velocity_off", ["limits", "velocity"], False, "le"),
        ("torque_tenth", ["limits", "torque"], 0.1, "ge"),
        ("torque_off", ["limits", "torque"], False, "le"),
        ("acceleration_tiny", ["limits", "acceleration"], 1e-3, "ge"),
    ]:
        cases.append(joints_case(f"limit_{name}", mutate(ARM, path, value), oracle=joints_vs(ARM_REF, relation)))
    # A limit so large it never binds: the answer without it.
    for value in [1e12, 1e300]:
        cases.append(joints_case(f"acceleration_{value:g}", mutate(ARM, ["limits", "acceleration"], value),
                                 oracle=joints_vs(arm_free_acc)))
    # The path parameter's unit and origin: knots scaled and shifted, the same path in time, the
    # same grid (its refinement included: the gallery's needs no point added), and without the
    # refinement the same grid as given.
    arm_unrefined = ("arm_unrefined", ["retime-joints", "{f}"], ".json", dict(ARM, max_violation_fraction=False))
    for scale, shift in [(1e-6, 0.0), (1e-3, 7.0), (3.0, -2.0), (1e3, 1e3), (1e6, 0.0)]:
        spec = dict(ARM, knots=[shift, shift + 0.5 * scale, shift + scale])
        cases.append(joints_case(f"knots_{scale:g}_{shift:g}", spec,
                                 oracle=all_of(joints_vs(ARM_REF, rel=1e-9), same_refinement(ARM_REF))))
        cases.append(joints_case(f"knots_{scale:g}_{shift:g}_unrefined", dict(spec, max_violation_fraction=False),
                                 oracle=joints_vs(arm_unrefined, rel=1e-9)))
    # The output step: the same retiming.
    for dt in [0.001, 0.1, 10.0]:
        cases.append(joints_case(f"dt_{dt:g}", ARM, ["--dt", repr(dt)], oracle=joints_vs(ARM_REF)))
    # Refined to 1e-6: the checks' ratios within it (the README: 1 + 9e-7).
    cases.append(joints_case("violation_1e-6", dict(ARM, max_violation_fraction=1e-6),
                             oracle=joints_vs(ARM_REF, rel=1e-3, ratio=1.5e-6)))
    for name, key, value in [("polyline", "interpolation", "polyline"), ("natural", "spline", "natural"),
                             ("clamped", "spline", "clamped"), ("collocation", "discretization", "collocation"),
                             ("unrefined", "max_violation_fraction", False), ("grid_3", "grid_points", 3)]:
        cases.append(joints_case(f"variant_{name}", dict(ARM, **{key: value}),
                                 oracle=joints_vs(ARM_REF, rel=0.5)))
    cases.append(Case("joints", "plot", ["retime-joints", "{f}", "--plot", "{p}"], {"f": ARM}, ext=".toml",
                      outputs={"p": ".svg"}, oracle=all_of(joints_vs(ARM_REF), svg_written)))
    bad = [
        ("acceleration_misspelled", ["limits", "acceleration"], {"elbw": 5.0}, [("elbw", "elbow")]),
        ("acceleration_link_name", ["limits", "acceleration"], {"forearm": 5.0}, [("forearm", "joint")]),
        ("acceleration_negative", ["limits", "acceleration"], -1.0, [("limits.acceleration", "> 0")]),
        ("acceleration_zero", ["limits", "acceleration"], 0.0, [("limits.acceleration", "> 0")]),
        ("acceleration_nan", ["limits", "acceleration"], nan, [("limits.acceleration", "> 0")]),
        ("acceleration_inf", ["limits", "acceleration"], inf, [("limits.acceleration", "finite")]),
        ("acceleration_default_nan", ["limits", "acceleration"], {"default": nan}, [("limits.acceleration.default", "> 0")]),
        ("acceleration_joint_negative", ["limits", "acceleration"], {"wrist": -2.0}, [("limits.acceleration.wrist", "> 0")]),
        ("acceleration_string", ["limits", "acceleration"], "fast", [("acceleration", "invalid type")]),
        ("velocity_negative", ["limits", "velocity"], -1.0, [("limits.velocity", "> 0")]),
        ("velocity_nan", ["limits", "velocity"], nan, [("limits.velocity", "> 0")]),
        ("velocity_true", ["limits", "velocity"], True, [("true", "false")]),
        ("torque_zero", ["limits", "torque"], 0.0, [("limits.torque", "> 0")]),
        ("limits_unknown_key", ["limits", "jerk"], 5.0, [("jerk", "unknown field")]),
        ("waypoint_short", ["waypoints", 2], [2.0, 0.4, 0.3], [("waypoint 2", "4 joint")]),
        ("waypoint_long", ["waypoints", 0], [0.0, 0.3, 0.5, 0.0, 1.0], [("waypoint 0", "4 joint")]),
        ("waypoint_nan", ["waypoints", 1], [1.0, nan, 1.2, 2.0], [("waypoint", "finite")]),
        ("waypoint_inf", ["waypoints", 1], [1.0, 0.0, inf, 2.0], [("waypoint", "finite")]),
        ("waypoint_string", ["waypoints", 1], [1.0, "x", 1.2, 2.0], [("waypoints", "invalid type")]),
        ("waypoints_one", ["waypoints"], [[0.0, 0.3, 0.5, 0.0]], [("waypoints", "at least 2")]),
        ("waypoints_none", ["waypoints"], [], [("waypoints", "at least 2")]),
        ("interpolation_cubic", ["interpolation"], "cubic", [("cubic", "polyline")]),
        ("spline_periodic", ["spline"], "periodic", [("periodic", "not-a-knot")]),
        ("joints_misspelled", ["joints"], ["yaw", "shoulder", "elbw", "wrist"], [("elbw", "elbow")]),
        ("joints_twice", ["joints"], ["yaw", "shoulder", "elbow", "elbow"], [("elbow", "twice")]),
        ("joints_missing", ["joints"], ["yaw", "shoulder", "elbow"], [("wrist", "locked")]),
        ("joints_empty", ["joints"], [], [("yaw", "locked")]),
        ("locked_and_listed", ["locked"], {"wrist": 0.0}, [("wrist", "locked")]),
        ("locked_unknown", ["locked"], {"wristt": 0.0}, ["wristt"]),
        ("knots_decreasing", ["knots"], [1.0, 0.5, 0.0], [("knots", "increasing")]),
        ("knots_length", ["knots"], [0.0, 1.0], [("knot", "waypoints")]),
        ("knots_nan", ["knots"], [0.0, nan, 1.0], [("knots", "finite")]),
        ("knots_repeated", ["knots"], [0.0, 0.0, 1.0], [("knots", "increasing")]),
        ("grid_points_1", ["grid_points"], 1, [("grid_points", "2 to 20000")]),
        ("grid_points_20001", ["grid_points"], 20001, [("grid_points", "2 to 20000")]),
        ("grid_points_negative", ["grid_points"], -1, [("grid_points", "invalid value")]),
        ("grid_points_float", ["grid_points"], 101.5, [("grid_points", "invalid type")]),
        ("sd_start_negative", ["sd_start"], -1.0, [("sd_start", ">= 0")]),
        ("sd_end_nan", ["sd_end"], nan, [("sd_end", ">= 0")]),
        ("dt_zero", ["dt"], 0.0, [("dt", "> 0")]),
        ("dt_inf", ["dt"], inf, [("dt", "finite")]),
        ("samples_per_interval_0", ["samples_per_interval"], 0, [("samples_per_interval", "1 to 100")]),
        ("samples_per_interval_101", ["samples_per_interval"], 101, [("samples_per_interval", "1 to 100")]),
        ("max_violation_zero", ["max_violation_fraction"], 0.0, [("max_violation_fraction", "> 0")]),
        ("max_violation_true", ["max_violation_fraction"], True, [("true", "false")]),
        ("gravity_two", ["gravity"], [0.0, -9.81], [("gravity", "3")]),
        ("gravity_nan", ["gravity"], [0.0, 0.0, nan], [("gravity", "finite")]),
        ("discretization", ["discretization"], "midpoint", [("midpoint", "collocation")]),
        ("urdf_missing", ["urdf"], "/nonexistent/arm.urdf", ["/nonexistent/arm.urdf"]),
        ("urdf_not_urdf", ["urdf"], os.path.join(ROOT, "gallery/arm-swing.toml"), [("arm-swing.toml", "urdf")]),
        ("unknown_key", ["waypoint"], [[0.0] * 4], [("waypoint", "unknown field")]),
        ("no_urdf_key", ["urdf"], DELETE, [("urdf", "missing")]),
    ]
    for name, path, value, kw in bad:
        cases.append(joints_case(f"bad_{name}", mutate(ARM, path, value), expect="error", keywords=kw))
    # The small humanoid's URDF, its root fixed: its 22 movable joints, not the arm's 4.
    humanoid = dict(ARM, urdf=os.path.join(ROOT, "models/small_humanoid.urdf"))
    del humanoid["joints"]
    cases.append(joints_case("bad_wrong_robot", humanoid, expect="error", keywords=[("waypoint 0", "joint")]))
    # Everything locked: nothing to retime.
    locked = dict(ARM, locked={"yaw": 0.0, "shoulder": 0.0, "elbow": 0.0, "wrist": 0.0}, joints=[],
                  waypoints=[[], []])
    cases.append(joints_case("bad_all_locked", locked, expect="error", keywords=[("no movable joint", "locked")]))
    for name, args, kw in [("dt_zero", ["--dt", "0"], [("dt", "> 0")]), ("dt_negative", ["--dt", "-1"], [("dt", "> 0")]),
                           ("dt_nan", ["--dt", "nan"], [("dt", "> 0")]),
                           ("plot_pdf", ["--plot", "x.pdf"], [("x.pdf", ".svg")]),
                           ("plot_unwritable", ["--plot", "/proc/nonexistent/p.svg"], ["/proc/nonexistent/p.svg"]),
                           ("repeat_huge", ["--repeat", "1000001"], [("--repeat", "1..=")])]:
        cases.append(joints_case(f"bad_option_{name}", ARM, args, expect="error", keywords=kw))
    cases.append(Case("joints", "bad_missing_file", ["retime-joints", "/nonexistent/arm.toml"], expect="error",
                      keywords=["/nonexistent/arm.toml"]))
    return cases


# ---------------------------------------------------------------------------------------------
# Number range: every command across the range of doubles where the answer has a closed form


FEET = [("l", [0, 0.1, 0], 0.1, 0.05), ("r", [0, -0.1, 0], 0.1, 0.05)]
COM_PATH = {"waypoints": [[0, 0, 0.8], [0.05, 0.02, 0.8], [0.08, -0.01, 0.78]]}
RETIME_REF = ("retime_ref", ["retime", "{f}"], ".json", {"scene": rect_scene(FEET), "path": COM_PATH})
HUMANOID_Q = "--q=" + ",".join("1" if i in (6, 24) else "0" for i in range(29))


def duration_like(ref, factor=1.0, rel=1e-6):
    """Optimal, with `factor` times the reference's duration (`ref` as Runner.cached takes it)."""
    def check(out, run):
        r = run.cached(*ref)
        if r is None or r.get("duration") is None:
            return "the reference failed"
        d, want = out.get("duration"), number(r["duration"]) * factor
        if out.get("status") != "optimal" or d is None or not rel_close(d, want, rel):
            return f"status {out.get('status')}, duration {d}, expected {want!r}"
        return None
    return check


def topp_on_length(fixture, length, shift=0.0):
    """A fixture's instance on the path s' = shift + length s, rows in the new path's units
    (a / length, b / length^2): the same retiming in time."""
    d = json.load(open(os.path.join(ROOT, "testdata/topp", fixture + ".json")))
    return {"s": [shift + length * s for s in d["s"]],
            "a": [[x / length for x in r] for r in d["a"]],
            "b": [[x / length / length for x in r] for r in d["b"]],
            "c": d["c"], "sd_start": d["sd_start"], "sd_end": d["sd_end"]}


def centroidal_scaled(lam, base):
    """`robot centroidal` at velocity lam v: the same mass, CoM, J_com and A_g, and
    dA_g/dt v scaled by lam^2 (to 1e-9 of the scale, or underflowing to zero)."""
    def check(out, run):
        ref = run.cached("centroidal_v1", ["robot", "centroidal", "--urdf", os.path.join(ROOT, "models/small_humanoid.urdf"),
                                           HUMANOID_Q, "--v=" + ",".join(repr(x) for x in base)])
        if ref is None:
            return "the reference failed"
        for key in ("mass", "com", "com_jacobian", "centroidal_map"):
            if numbers(out[key]) != numbers(ref[key]):
                return f"{key} changed with the velocity"
        got, want = numbers(out["centroidal_map_dot_v"]), ref["centroidal_map_dot_v"]
        scale = max(abs(x) for x in want)
        for g, w in zip(got, want):
            if abs(g - lam * lam * w) > 1e-9 * lam * lam * scale + 1e-300:
                return f"dA_g/dt v {got[:3]}..., expected lam^2 times {want[:3]}..."
        return None
    return check


def same_polygon(ref, rel=1e-6):
    """The same static polygon as the reference (vertex for vertex, within rel of its size)."""
    def check(out, run):
        r = run.cached(*ref)
        if r is None:
            return "the reference failed"
        if out.get("status") != r.get("status"):
            return f"status {out.get('status')} against {r.get('status')}"
        a, b = numbers(out["vertices"]), numbers(r["vertices"])
        size = max((max(abs(x) for x in v) for v in b), default=1.0)
        if len(a) != len(b) or any(min(math.dist(p, q) for q in b) > rel * size for p in a):
            return f"{len(a)} vertices {a[:4]}..., expected {len(b)}: {b[:4]}..."
        return None
    return check


def range_cases():
    cases = []
    # retime: gravity's magnitude from 1e-300 to 1e300; rows c ~ |g|, so duration sqrt(|g|) is fixed.
    for g in [1e-300, 1e-200, 1e-100, 1e-30, 1e-6, 1.0, 98.1, 1e6, 1e30, 1e100, 1e200, 1e300]:
        spec = {"scene": rect_scene(FEET, gravity=[0, 0, -g]), "path": COM_PATH}
        cases.append(Case("range", f"retime_gravity_{g:g}", ["retime", "{f}"], {"f": spec},
                          oracle=duration_like(RETIME_REF, math.sqrt(9.81 / g))))
    # retime: the robot's mass from 1e-300 to 1e300: the same duration.
    for m in [1e-300, 1e-200, 1e-100, 1e-30, 1e30, 1e100, 1e200, 1e300]:
        spec = {"scene": rect_scene(FEET, mass=m), "path": COM_PATH}
        cases.append(Case("range", f"retime_mass_{m:g}", ["retime", "{f}"], {"f": spec},
                          oracle=duration_like(RETIME_REF)))
    # retime: mass and gravity together (the weight from 1e-600 to 1e600 newtons).
    for m, g in [(1e-300, 1e-300), (1e300, 1e300), (1e-300, 1e300)]:
        spec = {"scene": rect_scene(FEET, mass=m, gravity=[0, 0, -g]), "path": COM_PATH}
        cases.append(Case("range", f"retime_mass_{m:g}_gravity_{g:g}", ["retime", "{f}"], {"f": spec},
                          oracle=duration_like(RETIME_REF, math.sqrt(9.81 / g))))
    # topp: the reference instance on paths of length 1e-12 to 1e12, rows in the path's units.
    ref = ("topp_ds_flat", ["topp", os.path.join(ROOT, "testdata/topp/ds_flat_N100.json")])
    for length, shift in [(1e-12, 0.0), (1e-9, 0.0), (1e-6, 1.0), (1e-3, 0.0), (1e3, 0.0), (1e6, -5e6),
                          (1e9, 0.0), (1e12, 0.0), (1.0, 1e6), (1e-6, 1e3)]:
        cases.append(Case("range", f"topp_length_{length:g}_{shift:g}", ["topp", "{f}"],
                          {"f": topp_on_length("ds_flat_N100", length, shift)}, oracle=duration_like(ref)))
    # robot centroidal: joint velocities up to 1e300: an answer (never null), or one error naming
    # --v and the range it supports.
    rng = random.Random(7)
    base = [round(rng.uniform(-1, 1), 3) for _ in range(27)]
    urdf = os.path.join(ROOT, "models/small_humanoid.urdf")
    for lam in [1e-300, 1e-150, 1e-10, 1e10, 1e100, 1e150, 1e154, 1e155, 1e200, 1e300]:
        v = "--v=" + ",".join(repr(lam * x) for x in base)
        cases.append(Case("range", f"centroidal_v_{lam:g}", ["robot", "centroidal", "--urdf", urdf, HUMANOID_Q, v],
                          expect="ok_or_error", keywords=[("--v", "range"), ("--v", "at most")],
                          oracle=centroidal_scaled(lam, base)))
    # equilibrium polygon: a tilted gravity's magnitude from 1e-300 to 1e300, as --gravity: the
    # same polygon at the same height.
    tilt = [0.3, 0.1, -9.81]
    norm = math.sqrt(sum(x * x for x in tilt))
    ref = ("polygon_tilt", ["equilibrium", "polygon", "stairs", "--height", "0.8", "--gravity=" + ",".join(map(repr, tilt))])
    for g in [1e-300, 1e-150, 1e-30, 1e-3, 1e3, 1e30, 1e150, 1e300]:
        gv = ",".join(repr(x / norm * g) for x in tilt)
        cases.append(Case("range", f"polygon_gravity_{g:g}", ["equilibrium", "polygon", "stairs", "--height", "0.8",
                                                              f"--gravity={gv}"], oracle=same_polygon(ref)))
        cases.append(Case("range", f"polygon_gravity_{g:g}_u", ["equilibrium", "polygon", "stairs", "--height", "0.8",
                                                                "--via-u-stance", f"--gravity={gv}"],
                          oracle=same_polygon(ref, 1e-5)))
    # equilibrium region and test: gravity's magnitude does not change static equilibrium.
    for g in [1e-300, 1e300]:
        cases.append(Case("range", f"test_gravity_{g:g}", ["equilibrium", "test", "double-support", "--points", "{p}",
                                                           f"--gravity=0,0,{-g!r}"],
                          {"p": {"points": [[0, 0, 0.8], [0.05, 0.1, 0.3], [0.2, 0, 0.8], [0, 0.3, 1.0]]}},
                          oracle=lambda out, run: None if out["stable"] == [True, True, False, False]
                          else f"stable {out['stable']}, expected [true, true, false, false]"))
    return cases


# ---------------------------------------------------------------------------------------------
# Bounded work: inputs at and just beyond each documented limit answer or refuse within the
# time bound


def polygon_contact(n, r=0.1, center=(0.0, 0.0, 0.0)):
    return {"mass": 60, "contacts": [{"name": "p", "position": list(center), "friction": 0.7,
                                      "shape": {"polygon": regular_polygon(n, r)}}]}


def bounded_cases():
    cases = []
    # A polygon contact of 64 vertices (the limit) is a foot; 65 is refused naming the limit.
    for n in [64, 65]:
        kw = [("64", "vertices")]
        cases.append(Case("bounded", f"polygon_{n}_vertices", ["equilibrium", "polygon", "{f}"],
                          {"f": polygon_contact(n)}, expect="ok" if n == 64 else "error", keywords=kw,
                          oracle=polygon_box(-0.1, 0.1, -0.1, 0.1, 1e-9)))
        cases.append(Case("bounded", f"giwc_polygon_{n}_vertices", ["giwc", "{f}"], {"f": polygon_contact(n)},
                          expect="ok" if n == 64 else "error", keywords=kw, oracle=giwc_sound))
    # Friction pyramids of 64 sides (the limit) and 65.
    for n in [64, 65]:
        scene = rect_scene([("l", [0, 0, 0], 0.11, 0.065)])
        scene["friction_model"] = {"sides": n, "approximation": "inner"}
        cases.append(Case("bounded", f"giwc_friction_sides_{n}", ["giwc", "{f}"], {"f": scene},
                          expect="ok" if n == 64 else "error", keywords=[("sides", "64")], oracle=giwc_sound))
    # retime: grid_points at its limit (20,000) and beyond.
    for n, expect in [(20000, "ok"), (20001, "error")]:
        spec = {"scene": rect_scene(FEET), "path": COM_PATH, "grid_points": n}
        cases.append(Case("bounded", f"retime_grid_points_{n}", ["retime", "{f}"], {"f": spec}, expect=expect,
                          keywords=[("grid_points", "20000")], oracle=finer_grid))
    # retime: a long path, 2,000 waypoints around a small circle.
    circle = [[0.03 * math.cos(2 * math.pi * k / 400), 0.03 * math.sin(2 * math.pi * k / 400), 0.8] for k in range(2000)]
    cases.append(Case("bounded", "retime_2000_waypoints", ["retime", "{f}"],
                      {"f": {"scene": rect_scene(FEET), "path": {"waypoints": circle}, "grid_points": 2001}},
                      oracle=lambda out, run: None if out.get("status") == "optimal" and number(out["duration"]) > 0
                      else f"status {out.get('status')}"))
    # retime-joints: the arm through 2,000 waypoints on a 2,001-point grid.
    wps = [[0.5 * math.sin(k / 50), 0.3 * math.cos(k / 70), 0.6 + 0.2 * math.sin(k / 30), k / 200]
           for k in range(2000)]
    cases.append(Case("bounded", "joints_2000_waypoints", ["retime-joints", "{f}"],
                      {"f": dict(ARM, waypoints=wps, grid_points=2001)}, ext=".json",
                      oracle=lambda out, run: None if out.get("status") == "optimal" and number(out["duration"]) > 0
                      else f"status {out.get('status')}"))
    # view: a scene of two 64-vertex polygon contacts (a 1,000-vertex one wrote nothing in 300 s
    # before the vertex limit) and the longest built-in motion, thirteen stances.
    cases.append(Case("bounded", "view_polygon_64_vertices", ["view", "{f}", "-o", "{page}"],
                      {"f": polygon_contact(64)}, outputs={"page": ".html"}, stdout="text",
                      oracle=lambda out, run: None if page_data(run)["kind"] == "scene" else "not a scene"))
    cases.append(Case("bounded", "view_staircase_walk", ["view", "staircase-walk", "-o", "{page}"],
                      outputs={"page": ".html"}, stdout="text",
                      oracle=lambda out, run: None if len(page_data(run)["stances"]) == 13 else "not 13 stances"))
    # motion: the same, planned and retimed with its checks.
    cases.append(Case("bounded", "motion_staircase_walk", ["motion", "staircase-walk"],
                      oracle=lambda out, run: motion_ok(out, run)))
    # topp: 100,001 grid points, the closed form (accelerate, cruise at sd = 1, brake: 2 s).
    n = 100001
    cases.append(Case("bounded", "topp_100001_points", ["topp", "{f}"],
                      {"f": {"s": [i / (n - 1) for i in range(n)], "a": [[1, -1, 0]] * n, "b": [[0, 0, 1]] * n,
                             "c": [[-1, -1, -1]] * n}}, oracle=duration_is(2.0, 1e-6)))
    # cone: 2,000 generators around a circle: 2,000 facets; its face form back: 2,000 generators.
    circ = [[math.cos(2 * math.pi * k / 2000), math.sin(2 * math.pi * k / 2000), 1.0] for k in range(2000)]
    cases.append(Case("bounded", "cone_circle_2000", ["cone", "span-to-face", "{f}"], {"f": {"generators": circ}},
                      oracle=facet_count(2000, 0)))
    cases.append(Case("bounded", "cone_circle_2000_face", ["cone", "face-to-span", "{f}"],
                      {"f": {"facets": [[x, y, -1.0] for x, y, _ in circ]}}, oracle=generator_count(2000, 0)))
    # ... and 20,000 (a fine circular friction cone): took 4 minutes in release; refused with the
    # command's limit, and 5,000, at it, converted.
    circ = [[math.cos(2 * math.pi * k / 20000), math.sin(2 * math.pi * k / 20000), 1.0] for k in range(20000)]
    cases.append(Case("bounded", "cone_circle_20000", ["cone", "span-to-face", "{f}"], {"f": {"generators": circ}},
                      expect="error", keywords=[("generators", "20000 rows", "5000")]))
    circ = [[math.cos(2 * math.pi * k / 5000), math.sin(2 * math.pi * k / 5000), 1.0] for k in range(5000)]
    cases.append(Case("bounded", "cone_circle_5000", ["cone", "span-to-face", "{f}"], {"f": {"generators": circ}},
                      oracle=facet_count(5000, 0)))
    # A 4-D cone over 500 points of a sphere: every point is extreme.
    rng = random.Random(11)
    sphere = []
    for _ in range(500):
        v = [rng.gauss(0, 1) for _ in range(3)]
        norm = math.sqrt(sum(x * x for x in v))
        sphere.append([x / norm for x in v] + [3.0])
    cases.append(Case("bounded", "cone_sphere_500", ["cone", "span-to-face", "{f}"], {"f": {"generators": sphere}},
                      oracle=lambda out, run: None if len(out["extreme_generators"]) == 500
                      else f"{len(out['extreme_generators'])} extreme generators of 500"))
    # The largest dimension (1024) and beyond.
    cases.append(Case("bounded", "cone_dim_1024", ["cone", "span-to-face", "{f}"], {"f": {"generators": [], "dim": 1024}},
                      oracle=facet_count(0, 1024)))
    cases.append(Case("bounded", "cone_dim_1025", ["cone", "span-to-face", "{f}"], {"f": {"generators": [], "dim": 1025}},
                      expect="error", keywords=[("dim", "1024")]))
    # --repeat at its limit on a small input, and beyond.
    for n, expect in [(1000000, "ok"), (1000001, "error")]:
        cases.append(Case("bounded", f"repeat_{n}", ["cone", "span-to-face", "--repeat", str(n), "{f}"],
                          {"f": {"generators": [[1, 0], [0, 1]]}}, expect=expect, keywords=[("--repeat", "1000000")],
                          oracle=facet_count(2, 0)))
    cases.append(Case("bounded", "repeat_centroidal_100000", ["robot", "centroidal", "--urdf",
                                                               os.path.join(ROOT, "models/small_humanoid.urdf"),
                                                               HUMANOID_Q, "--repeat", "100000"],
                      oracle=lambda out, run: None if rel_close(out["mass"], 43.2, 1e-12) else f"mass {out['mass']}"))
    # equilibrium test: 200,000 CoMs (a stable square and an unstable ring).
    pts = [[0.05 * ((i % 7) / 3 - 1), 0.1 * ((i % 5) / 2 - 1), 0.8] if i % 2 else [0.5 + i * 1e-6, 0.0, 0.8]
           for i in range(200000)]
    cases.append(Case("bounded", "test_200000_points", ["equilibrium", "test", "double-support", "--points", "{f}"],
                      {"f": {"points": pts}},
                      oracle=lambda out, run: None if out["stable"] == [bool(i % 2) for i in range(200000)]
                      else "a point's verdict is wrong"))
    # motion: --dt at its least (1e-4 s) and --check-dt at its least.
    cases.append(Case("bounded", "motion_check_dt_min", ["motion", "small-sway", "--check-dt", "1e-4"],
                      oracle=motion_vs(SWAY_REF)))
    cases.append(Case("bounded", "motion_dt_min", ["motion", "small-sway", "--dt", "1e-4", "--no-checks"],
                      oracle=all_of(motion_vs(SWAY_REF), trajectory_every(1e-4))))
    # motion: moves at their longest (1e4 path units) and shortest (1e-3).
    for d in [1e4, 1e-3]:
        spec = mutate(SWAY, SEG + [0, "moves", 0, "duration"], d)
        cases.append(motion_case(f"motion_move_duration_{d:g}", spec, ["--no-checks"], group="bounded",
                                 expect="ok_or_error", keywords=[("segment 1", "move 1")],
                                 oracle=lambda out, run: None if out.get("status") in ("optimal", "ik_failed", "not_retimable")
                                 else f"status {out.get('status')}"))
    # motion: the friction pyramid at its limit (64 sides), the default inscribed one.
    # ... refused with the sides that fit (two feet of 64 sides took 40 s and 7 GB), and at the
    # largest that fits, an answer no slower than the default's.
    cases.append(motion_case("motion_friction_cone_64", mutate(SWAY, ["planning", "friction_cone"], {"sides": 64}),
                             ["--no-checks"], group="bounded", expect="error",
                             keywords=[("friction_cone", "at most 32 sides")]))
    cases.append(motion_case("motion_friction_cone_32", mutate(SWAY, ["planning", "friction_cone"], {"sides": 32}),
                             ["--no-checks"], group="bounded", oracle=motion_vs(SWAY_REF, "le", checks=False)))
    return cases


def finer_grid(out, run):
    """On a finer grid the interpolation discretization, conservative, is no slower, and
    converges (0.7926 s on 101 points, 0.7597 s on 20,000)."""
    r = run.cached(*RETIME_REF)
    d = number(out["duration"])
    if out["status"] != "optimal" or not 0.9 * r["duration"] <= d <= r["duration"] * (1 + 1e-9):
        return f"status {out['status']}, duration {d} against {r['duration']} on 101 points"
    return None


def giwc_sound(out, run):
    """Every generator of the span form satisfies every facet (U g <= 1e-9 |g|); the facets
    are unit rows; no null."""
    f, span = numbers(out["giwc"]["facets"]), numbers(out["span"])
    for r in f:
        if abs(math.sqrt(sum(x * x for x in r)) - 1) > 1e-9:
            return "a facet is not a unit row"
    for g in span:
        ng = math.sqrt(sum(x * x for x in g))
        worst = max((sum(a * b for a, b in zip(u, g)) for u in f), default=0.0)
        if worst > 1e-9 * ng:
            return f"a generator violates a facet by {worst:.2e}"
    return None


# ---------------------------------------------------------------------------------------------
# `stance giwc`: invariances of the cone (the contact wrench cone does not depend on the mass or
# gravity), its two forms agreeing, and errors


def same_cone_as(other):
    """The same cone as `other(out, run)`'s answer (a GIWC report): the span generators of
    each satisfy the facets of the other (to 1e-9 of their size). The exact arithmetic on the
    rounded generators may split facets of the intended geometry (`giwc --help`): not the same
    rows, the same cone."""
    def check(out, run):
        o = other(out, run)
        if o is None:
            return "the other route failed"
        for a, b, what in [(out, o, "this answer's"), (o, out, "the other's")]:
            f = numbers(b["giwc"]["facets"])
            for g in numbers(a["span"]):
                ng = math.sqrt(sum(x * x for x in g))
                if max((sum(p * q for p, q in zip(u, g)) for u in f), default=0.0) > 1e-9 * ng:
                    return f"a generator of {what} cone is outside the other"
        return None
    return check


def same_giwc(ref, sign=1.0, tol=1e-6):
    """The same facets as the reference's (`sign` -1: the net contact wrench cone, -U)."""
    def check(out, run):
        why = giwc_sound(out, run) if sign > 0 else None
        if why:
            return why
        r = run.cached(*ref)
        if r is None:
            return "the reference failed"
        a = [[sign * x for x in row] for row in numbers(out["giwc"]["facets"])]
        if not same_rows(a, r["giwc"]["facets"], tol):
            return f"{len(a)} facets, not the reference's {len(r['giwc']['facets'])}"
        return None
    return check


def giwc_cases():
    cases = []
    for name in ["single-support", "double-support", "stairs", "box-climbing", "robust-equilibrium"]:
        cases.append(Case("giwc", f"builtin_{name}", ["giwc", name], oracle=giwc_sound))
        ref = (f"giwc_{name}", ["giwc", name])
        cases.append(Case("giwc", f"builtin_{name}_net", ["giwc", name, "--net-contact-wrench"],
                          oracle=same_giwc(ref, -1.0)))
    for name in ["double-support", "stairs"]:
        cases.append(Case("giwc", f"builtin_{name}_exact", ["giwc", name, "--exact"],
                          oracle=all_of(giwc_sound, same_cone_as(lambda out, run, name=name: run.cached(
                              f"giwc_{name}", ["giwc", name])))))
    # The cone of the contacts: the same for any mass and gravity.
    feet = rect_scene([("l", [0.02, 0.1, 0.0], 0.11, 0.065), ("r", [-0.05, -0.12, 0.03], 0.11, 0.065)])
    ref = ("giwc_feet", ["giwc", "{f}"], ".json", feet)
    for m in [1e-300, 1e-6, 1e6, 1e300]:
        cases.append(Case("giwc", f"mass_{m:g}", ["giwc", "{f}"], {"f": dict(feet, mass=m)}, oracle=same_giwc(ref)))
    for g in [[0, 0, -1e-300], [0, 0, -1e300], [3.0, -2.0, -9.0], [0, 0, 9.81]]:
        cases.append(Case("giwc", f"gravity_{g[0]:g}_{g[1]:g}_{g[2]:g}", ["giwc", "{f}"], {"f": dict(feet, gravity=g)},
                          oracle=same_giwc(ref)))
    cases.append(Case("giwc", "repeat_5", ["giwc", "{f}", "--repeat", "5"], {"f": feet}, oracle=same_giwc(ref)))
    cases.append(Case("giwc", "toml_scene", ["giwc", "{f}"], {"f": feet}, ext=".toml", oracle=same_giwc(ref)))
    # Random stances of 1 to 3 contacts (rectangles and polygons, tilted): sound, and the exact
    # arithmetic agrees.
    for k in range(10):
        contacts = []
        for i in range(RNG.randint(1, 3)):
            roll, pitch, yaw = (RNG.uniform(-0.3, 0.3) for _ in range(3))
            shape = ({"rectangle": {"half_length": RNG.uniform(0.02, 0.2), "half_width": RNG.uniform(0.02, 0.2)}}
                     if RNG.random() < 0.6 else {"polygon": regular_polygon(RNG.randint(3, 8), RNG.uniform(0.02, 0.2))})
            contacts.append({"name": f"c{i}", "position": [RNG.uniform(-0.5, 0.5) for _ in range(3)],
                             "rotation": rpy_matrix(roll, pitch, yaw), "shape": shape,
                             "friction": RNG.uniform(0.2, 1.2)})
        scene = {"mass": 50, "contacts": contacts}
        cases.append(Case("giwc", f"random_{k}", ["giwc", "{f}"], {"f": scene},
                          oracle=all_of(giwc_sound, same_cone_as(lambda out, run: run(["giwc", "--exact", "{f}"])))))
    for name, scene, kw in [
        ("unknown_example", "moon", [("moon", "stairs")]),
        ("mass_zero", dict(feet, mass=0), ["mass"]),
        ("friction_sides_2", dict(feet, friction_model={"sides": 2}), [("sides", "3 to 64")]),
        ("friction_approximation", dict(feet, friction_model={"sides": 4, "approximation": "middle"}),
         [("middle", "inner")]),
        ("friction_huge", rect_scene([("l", [0, 0, 0], 0.1, 0.05)], friction=1e7), [("friction", "1e6")]),
        ("no_contacts", {"mass": 60, "contacts": []}, ["contact"]),
        ("rotation_not_orthonormal", {"mass": 60, "contacts": [dict(feet["contacts"][0], rotation=[[1, 0, 0], [0, 1, 0], [0, 0, 2]])]},
         [("`l`", "rotation")]),
        ("polygon_nonconvex", polygon_scene([[0.1, 0.1], [-0.1, 0.1], [0, 0], [-0.1, -0.1], [0.1, -0.1]]), [("`p`", "convex")]),
        ("polygon_collinear", polygon_scene([[0, 0], [0.1, 0], [0.2, 0]]), [("`p`", "area")]),
        ("unknown_key", dict(feet, gravty=[0, 0, -9.81]), [("gravty", "unknown field")]),
    ]:
        cases.append(Case("giwc", f"bad_{name}", ["giwc", scene if isinstance(scene, str) else "{f}"],
                          {} if isinstance(scene, str) else {"f": scene}, expect="error", keywords=kw))
    return cases


def polygon_scene(vertices):
    return {"mass": 60, "contacts": [{"name": "p", "position": [0, 0, 0], "friction": 0.7,
                                      "shape": {"polygon": vertices}}]}


def rpy_matrix(r, p, y):
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return [[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr]]


# ---------------------------------------------------------------------------------------------
# More of equilibrium, retime, topp, robot, cone


def inside_polygon(p, poly, eps):
    """+1 inside (by more than eps), -1 outside (by more than eps), 0 near the boundary, for a
    counter-clockwise convex polygon."""
    worst = math.inf
    for (x0, y0), (x1, y1) in zip(poly, poly[1:] + poly[:1]):
        n = math.hypot(x1 - x0, y1 - y0)
        worst = min(worst, ((x1 - x0) * (p[1] - y0) - (y1 - y0) * (p[0] - x0)) / n)
    return 1 if worst > eps else -1 if worst < -eps else 0


def equilibrium_more_cases():
    cases = []
    # Random stances: the polygon straight from the contact forces and through U_stance agree, and
    # `equilibrium test` says stable exactly inside it (away from its boundary).
    for k in range(8):
        contacts = []
        for i in range(RNG.randint(2, 3)):
            contacts.append({"name": f"c{i}", "position": [RNG.uniform(-0.4, 0.4), RNG.uniform(-0.4, 0.4), RNG.uniform(0, 0.3)],
                             "rotation": rpy_matrix(RNG.uniform(-0.4, 0.4), RNG.uniform(-0.4, 0.4), RNG.uniform(-1, 1)),
                             "shape": {"rectangle": {"half_length": 0.1, "half_width": 0.05}},
                             "friction": RNG.uniform(0.4, 1.0)})
        scene = {"mass": 50, "contacts": contacts}
        ref = (f"polygon_random_{k}", ["equilibrium", "polygon", "{f}"], ".json", scene)
        cases.append(Case("equilibrium", f"random_{k}_via_u", ["equilibrium", "polygon", "--via-u-stance", "{f}"],
                          {"f": scene}, oracle=same_polygon(ref, 1e-6)))
        pts = [[RNG.uniform(-0.6, 0.6), RNG.uniform(-0.6, 0.6), RNG.uniform(0.5, 1.5)] for _ in range(200)]
        cases.append(Case("equilibrium", f"random_{k}_test", ["equilibrium", "test", "{f}", "--points", "{p}", "--margin"],
                          {"f": scene, "p": {"points": pts}}, oracle=test_agrees(ref, pts)))
    # Region M for one vertical gravity: the polygon's prism (its half-spaces have no z).
    for name in ["double-support", "stairs"]:
        cases.append(Case("equilibrium", f"region_{name}", ["equilibrium", "region", name],
                          oracle=lambda out, run: None if all(abs(h[2]) < 1e-9 for h in numbers(out["halfspaces"]))
                          else "a half-space of the static region depends on z"))
    # More gravities can only shrink the robust region: every vertex of M(g1, g2) is in M(g1).
    gs = ["--gravity=0,0,-9.81", "--gravity=1.5,0,-9.81", "--gravity=0,-1.5,-9.81"]
    cases.append(Case("equilibrium", "region_robust", ["equilibrium", "region", "stairs", *gs],
                      oracle=inside_static_polygon(("polygon_stairs", ["equilibrium", "polygon", "stairs"]))))
    cases.append(Case("equilibrium", "polygon_upward_gravity", ["equilibrium", "polygon", "double-support",
                                                               "--gravity=0,0,9.81"],
                      oracle=lambda out, run: None if out["status"] == "empty" else f"status {out['status']}"))
    cases.append(Case("equilibrium", "polygon_plot_svg", ["equilibrium", "polygon", "stairs", "--plot", "{p}"],
                      outputs={"p": ".svg"}, oracle=svg_written))
    for name, args, files, kw in [
        ("height_nan", ["polygon", "stairs", "--height", "nan"], {}, [("--height", "finite")]),
        ("height_inf", ["polygon", "stairs", "--height", "inf"], {}, [("--height", "finite")]),
        ("gravity_zero", ["polygon", "stairs", "--gravity=0,0,0"], {}, [("gravity", "non-zero")]),
        ("gravity_four", ["polygon", "stairs", "--gravity=0,0,0,-9.81"], {}, [("--gravity", "three")]),
        ("gravity_inf", ["polygon", "stairs", "--gravity=0,0,-inf"], {}, [("--gravity", "finite")]),
        ("region_gravity_nan", ["region", "stairs", "--gravity=0,nan,-9.81"], {}, [("--gravity", "finite")]),
        ("region_plot_pdf", ["region", "stairs", "--plot", "r.pdf"], {}, [("pdf", "svg")]),
        ("test_points_missing", ["test", "stairs", "--points", "/nonexistent/p.json"], {}, ["/nonexistent/p.json"]),
        ("test_no_points_option", ["test", "stairs"], {}, [("--points", "required")]),
        ("test_point_two", ["test", "stairs", "--points", "{p}"], {"p": {"points": [[0, 0]]}}, [("point", "3 numbers")]),
        ("test_point_four", ["test", "stairs", "--points", "{p}"], {"p": {"points": [[0, 0, 1, 2]]}}, [("point", "3 numbers")]),
        ("test_point_huge", ["test", "stairs", "--points", "{p}"], {"p": '{"points": [[0, 0, 1e999]]}'}, [("{p}", "number")]),
        ("test_points_key", ["test", "stairs", "--points", "{p}"], {"p": {"point": [[0, 0, 1]]}}, [("point", "unknown field")]),
        ("test_points_not_list", ["test", "stairs", "--points", "{p}"], {"p": {"points": 3}}, [("{p}", "invalid type")]),
    ]:
        cases.append(Case("equilibrium", f"bad_{name}", ["equilibrium", *args], files, expect="error", keywords=kw))
    cases.append(Case("equilibrium", "test_point_nan_toml", ["equilibrium", "test", "stairs", "--points", "{p}"],
                      {"p": {"points": [[0.0, 0.0, 1.0], [0.0, float("nan"), 1.0]]}}, ext=".toml", expect="error",
                      keywords=[("point 1", "finite")]))
    return cases


def inside_static_polygon(ref):
    """Every vertex of a robust region (more gravities than the scene's) is statically stable:
    in the prism of the static polygon (within 1e-6 m)."""
    def check(out, run):
        poly = numbers(run.cached(*ref)["vertices"])
        vs = numbers(out["vertices"])
        if out["status"] != "bounded" or not vs:
            return f"status {out['status']}, {len(vs)} vertices"
        for v in vs:
            if inside_polygon(v, poly, 1e-6) < 0:
                return f"vertex {v} of the robust region is outside the static polygon"
        return None
    return check


def test_agrees(ref, pts):
    def check(out, run):
        poly = run.cached(*ref)
        if poly is None or poly["status"] != "bounded":
            return "the reference polygon failed"
        vs = numbers(poly["vertices"])
        margins = numbers(out["margin"])
        for p, s, mg in zip(pts, out["stable"], margins):
            side = inside_polygon(p, vs, 1e-6)
            if side and (side > 0) != s:
                return f"CoM {p}: stable {s}, but {'inside' if side > 0 else 'outside'} the static polygon"
            if (mg > 1e-9 and not s) or (mg < -1e-9 and s):
                return f"CoM {p}: stable {s} with margin {mg}"
        return None
    return check


def retime_more_cases():
    cases = []
    # The scene and path moved together in x/y: the same duration.
    for dx, dy in [(10.0, -3.0), (1e3, 1e3)]:
        feet = [(n, [p[0] + dx, p[1] + dy, p[2]], hl, hw) for n, p, hl, hw in FEET]
        path = {"waypoints": [[x + dx, y + dy, z] for x, y, z in COM_PATH["waypoints"]]}
        cases.append(Case("retime", f"moved_{dx:g}_{dy:g}", ["retime", "{f}"],
                          {"f": {"scene": rect_scene(feet), "path": path}}, oracle=duration_like(RETIME_REF)))
    cases.append(Case("retime", "toml", ["retime", "{f}"], {"f": {"scene": rect_scene(FEET), "path": COM_PATH}},
                      ext=".toml", oracle=duration_like(RETIME_REF, rel=1e-12)))
    cases.append(Case("retime", "plot", ["retime", "{f}", "--plot", "{p}"],
                      {"f": {"scene": rect_scene(FEET), "path": COM_PATH}}, outputs={"p": ".png"},
                      oracle=lambda out, run: None if open(run.paths["p"], "rb").read(8).startswith(b"\x89PNG")
                      else "not a PNG"))
    cases.append(Case("retime", "builtin_scene", ["retime", "{f}"],
                      {"f": {"scene": "double-support", "path": {"waypoints": [[0, 0.05, 0.8], [0, -0.05, 0.8]]}}},
                      oracle=lambda out, run: None if out["status"] == "optimal" and number(out["duration"]) > 0
                      else f"status {out['status']}"))
    # A path out of the support: not retimable at rest, an answer (exit 0) with the grid index.
    cases.append(Case("retime", "unstable_path", ["retime", "{f}"],
                      {"f": {"scene": rect_scene(FEET), "path": {"waypoints": [[0.5, 0, 0.8], [0.6, 0, 0.8]]}}},
                      oracle=lambda out, run: None if out["status"] != "optimal" and out.get("duration") is None
                      else f"status {out['status']}, duration {out.get('duration')}"))
    # A path that does not move: any timing holds, so the solver's box decides, and says so (or
    # an error naming the waypoints).
    cases.append(Case("retime", "path_standing_still", ["retime", "{f}"],
                      {"f": {"scene": rect_scene(FEET), "path": {"waypoints": [[0, 0, 0.8], [0, 0, 0.8]]}}},
                      expect="ok_or_error", keywords=["waypoint"],
                      oracle=lambda out, run: None if out["status"] == "optimal" and out["speed_at_box"] is True
                      else f"status {out['status']}, speed_at_box {out['speed_at_box']}"))
    base = {"scene": rect_scene(FEET), "path": COM_PATH}
    for name, spec, kw in [
        ("grid_points_1", dict(base, grid_points=1), [("grid_points", "2")]),
        ("sd_start_negative", dict(base, sd_start=-1), [("sd_start", ">= 0")]),
        ("sd_end_string", dict(base, sd_end="0"), [("{f}", "invalid type")]),
        ("dt_zero", dict(base, dt=0), [("dt", "> 0")]),
        ("samples_per_interval_0", dict(base, samples_per_interval=0), [("samples_per_interval", "1 to 100")]),
        ("samples_per_interval_101", dict(base, samples_per_interval=101), [("samples_per_interval", "1 to 100")]),
        ("max_violation_zero", dict(base, max_violation_fraction=0), [("max_violation_fraction", "> 0")]),
        ("discretization", dict(base, discretization="midpoint"), [("midpoint", "collocation")]),
        ("interpolation", dict(base, path=dict(COM_PATH, interpolation="cubic")), [("cubic", "spline")]),
        ("knots_length", dict(base, path=dict(COM_PATH, knots=[0, 1])), [("knot", "waypoints")]),
        ("waypoint_two", dict(base, path={"waypoints": [[0, 0], [0, 0.1]]}), [("{f}", "3")]),
        ("angular_momentum_lengths", dict(base, angular_momentum={"l1": [[0, 0, 0]], "l2": [[0, 0, 0]] * 3}),
         [("angular", "l1")]),
        ("point_contacts_only", {"scene": {"mass": 60, "contacts": [
            {"name": "p", "position": [0, 0, 0], "shape": "point", "friction": 0.5}]}, "path": COM_PATH},
         [("lower-dimensional", "surface contacts")]),
        ("unknown_key", dict(base, grid=100), [("grid", "unknown field")]),
        ("no_path", {"scene": rect_scene(FEET)}, [("path", "missing")]),
    ]:
        cases.append(Case("retime", f"bad_{name}", ["retime", "{f}"], {"f": spec}, expect="error", keywords=kw))
    return cases


def topp_more_cases():
    cases = []
    # Closed forms: |sdd| <= A, sd <= V on [0, L], the switch points on the grid: accelerate over
    # k tenths of the path, cruise, brake: T = L / V + V / A (k < 5), 2 sqrt(L / A) (k = 5).
    rng = random.Random(5)
    for i in range(10):
        length = 10 ** rng.uniform(-4, 4)
        k = rng.randint(1, 5)
        v = 10 ** rng.uniform(-2, 2)
        acc = v * v / (2 * length * k / 10)
        t = 2 * math.sqrt(length / acc) if k == 5 else length / v + v / acc
        n = 11
        inst = {"s": [length * j / (n - 1) for j in range(n)], "a": [[1, -1, 0]] * n, "b": [[0, 0, 1]] * n,
                "c": [[-acc, -acc, -v * v]] * n}
        if i % 2:
            inst["discretization"] = "interpolation"
        cases.append(Case("topp", f"closed_form_{i}", ["topp", "{f}"], {"f": inst}, oracle=duration_is(t, 1e-9)))
    # Infeasible: rows no acceleration meets at one point (sdd <= -1 and sdd >= 1): a status,
    # exit 0, with the grid point.
    n = 11
    inst = {"s": [j / 10 for j in range(n)], "a": [[1, -1]] * n, "b": [[0, 0]] * n,
            "c": [[-1, -1]] * 5 + [[1, 1]] + [[-1, -1]] * 5}
    cases.append(Case("topp", "infeasible", ["topp", "{f}"], {"f": inst},
                      oracle=lambda out, run: None if out["status"] != "optimal" and out.get("index") == 5
                      else f"status {out['status']}, index {out.get('index')}"))
    # TOML input, and a starting speed.
    inst = {"s": [j / 10 for j in range(n)], "a": [[1, -1, 0]] * n, "b": [[0, 0, 1]] * n, "c": [[-1, -1, -1]] * n}
    cases.append(Case("topp", "toml", ["topp", "{f}"], {"f": inst}, ext=".toml", oracle=duration_is(2.0)))
    cases.append(Case("topp", "sd_start_1", ["topp", "{f}"], {"f": dict(inst, sd_start=1.0, sd_end=1.0)},
                      oracle=duration_is(1.0)))
    cases.append(Case("topp", "repeat_10", ["topp", "{f}", "--repeat", "10"], {"f": inst}, oracle=duration_is(2.0)))
    for name, text, kw in [
        ("nan_toml", None, [("{f}", "finite"), ("{f}", "nan")]),
        ("sd_end_above_box", dict(inst, sd_end=2.0), None),
        ("c_ragged_rows", dict(inst, c=[[-1, -1, -1]] * 10 + [[-1, -1]]), [("c", "rows")]),
        ("a_fewer_points", dict(inst, a=[[1, -1, 0]] * 10), [("a", "points"), ("a", "grid")]),
        ("s_repeated", dict(inst, s=[0.0] * n), [("increasing", "s")]),
        ("s_range_huge", dict(inst, s=[j * 1e200 for j in range(n)]), [("range", "1e150")]),
        ("s_inf", '{"s": [0, 1e999], "a": [[1]], "b": [[0]], "c": [[-1]]}', [("{f}", "number")]),
        ("discretization_number", dict(inst, discretization=1), [("discretization", "invalid type")]),
        ("sd_start_string", dict(inst, sd_start="0"), [("sd_start", "invalid type"), ("{f}", "invalid type")]),
    ]:
        if name == "nan_toml":
            cases.append(Case("topp", "bad_nan_toml", ["topp", "{f}"],
                              {"f": dict(inst, c=[[-1, -1, float("nan")]] + [[-1, -1, -1]] * 10)}, ext=".toml",
                              expect="error", keywords=[("c", "finite"), ("c", "nan")]))
            continue
        if kw is None:
            # An end speed the rows forbid (sd <= 1): a status, not an error.
            cases.append(Case("topp", f"{name}", ["topp", "{f}"], {"f": text},
                              oracle=lambda out, run: None if out["status"] != "optimal"
                              else "optimal with an end speed the rows forbid"))
            continue
        cases.append(Case("topp", f"bad_{name}", ["topp", "{f}"], {"f": text}, expect="error", keywords=kw))
    return cases


def robot_more_cases():
    cases = []
    urdf = os.path.join(ROOT, "models/small_humanoid.urdf")
    q0 = [1.0 if i in (6, 24) else 0.0 for i in range(29)]
    rng = random.Random(3)
    qr = list(q0)
    for i in list(range(7, 24)) + list(range(26, 29)):
        qr[i] = round(rng.uniform(-0.5, 0.5), 3)
    qs = lambda q: "--q=" + ",".join(repr(x) for x in q)
    ref = ("centroidal_q", ["robot", "centroidal", "--urdf", urdf, qs(qr)])
    # The world origin: the base moved by up to 1e12 m: A_g and J_com unchanged, the CoM moved alike.
    for x in [1.0, 1e3, 1e6, 1e12]:
        q = list(qr)
        q[0], q[1] = q[0] + x, q[1] - x / 2
        cases.append(Case("robot", f"base_moved_{x:g}", ["robot", "centroidal", "--urdf", urdf, qs(q)],
                          oracle=centroidal_moved(ref, [x, -x / 2, 0.0])))
    # Locking a joint keeps the mass; the configuration loses its coordinate.
    cases.append(Case("robot", "lock_knee", ["robot", "centroidal", "--urdf", urdf, "--lock", "r_knee=0.3",
                                             "--q=" + ",".join("1" if i in (6, 23) else "0" for i in range(28))],
                      oracle=lambda out, run: None if rel_close(out["mass"], 43.2, 1e-12) and out["nq"] == 28 and out["nv"] == 26
                      else f"mass {out['mass']}, nq {out['nq']}, nv {out['nv']}"))
    # A quaternion not of unit norm: normalized (the same answer) or an error naming it.
    q = list(qr)
    q[3:7] = [0.0, 0.0, 0.0, 2.0]
    cases.append(Case("robot", "quaternion_not_unit", ["robot", "centroidal", "--urdf", urdf, qs(q)],
                      expect="ok_or_error", keywords=["quaternion", "unit"],
                      oracle=lambda out, run: None if same_rows(out["centroidal_map"], run.cached(*ref)["centroidal_map"], 1e-9)
                      else "not the answer of the unit quaternion"))
    for name, args, kw in [
        ("q_short", [qs(q0[:28])], [("29", "q")]),
        ("q_text", ["--q=" + ",".join(["a"] * 29)], [("--q", "entry 0")]),
        ("q_nan", ["--q=" + ",".join(["nan"] + ["0"] * 28)], [("--q", "entry 0", "finite")]),
        ("q_inf", ["--q=" + ",".join(["0"] * 5 + ["inf"] + ["0"] * 23)], [("--q", "entry 5", "finite")]),
        ("q_empty", ["--q="], [("--q", "entry 0")]),
        ("v_short", [qs(q0), "--v=" + ",".join(["0"] * 26)], [("27", "v")]),
        ("v_inf", [qs(q0), "--v=" + ",".join(["inf"] + ["0"] * 26)], [("--v", "entry 0", "finite")]),
        ("lock_unknown", [qs(q0), "--lock", "r_kne"], [("r_kne", "joint")]),
        ("lock_empty_name", [qs(q0), "--lock", "=0.3"], [("--lock", "name")]),
        ("lock_bad_value", [qs(q0), "--lock", "r_knee=abc"], [("--lock", "abc")]),
        ("lock_twice", [qs(q0[:28]), "--lock", "r_knee", "--lock", "r_knee"], [("r_knee", "twice"), ("r_knee", "duplicate")]),
        ("no_q", [], [("--q", "required")]),
    ]:
        cases.append(Case("robot", f"bad_{name}", ["robot", "centroidal", "--urdf", urdf, *args], expect="error", keywords=kw))
    for name, path, kw in [("urdf_missing", "/nonexistent/robot.urdf", ["/nonexistent/robot.urdf"]),
                           ("urdf_directory", "/", [("/", "directory"), ("/", "read")])]:
        cases.append(Case("robot", f"bad_{name}", ["robot", "centroidal", "--urdf", path, qs(q0)], expect="error", keywords=kw))
    return cases


def centroidal_moved(ref, offset):
    def check(out, run):
        r = run.cached(*ref)
        if r is None:
            return "the reference failed"
        scale = max(1.0, max(abs(x) for x in offset))
        for key in ("centroidal_map", "com_jacobian"):
            a, b = numbers(out[key]), r[key]
            if max(abs(x - y) for ra, rb in zip(a, b) for x, y in zip(ra, rb)) > 1e-9 * scale:
                return f"{key} changed with the world origin"
        c = numbers(out["com"])
        if max(abs(x - y - o) for x, y, o in zip(c, r["com"], offset)) > 1e-12 * scale + 1e-12:
            return f"CoM {c}, expected {r['com']} + {offset}"
        return None
    return check


def cone_more_cases():
    cases = []
    # Round trip: span -> face -> span gives the extreme rays back (random pointed 3-D to 5-D cones).
    for k in range(10):
        d = RNG.randint(3, 5)
        rows = [[RNG.uniform(-1, 1) for _ in range(d - 1)] + [1.0] for _ in range(RNG.randint(d, d + 8))]
        cases.append(Case("cone", f"round_trip_{k}", ["cone", "span-to-face", "--repeat", "2", "{f}"],
                          {"f": {"generators": rows}}, oracle=round_trip(rows)))
    # A contact wrench cone's face form (from span-to-face --wrench) back to its span form with
    # --wrench, at distances from 1 m to 1e5 m: the 16 generators it was made of.
    for x in [1.0, 1e3, 1e5]:
        gens = cwc_generators([x, 0.3 * x, 0])
        key = f"cwc_face_{x:g}"
        face = lambda run, key=key, gens=gens: {"facets": run.cached(
            key, ["cone", "span-to-face", "--wrench", "{f}"], ".json", {"generators": gens})["facets"]}
        cases.append(Case("cone", f"cwc_face_wrench_{x:g}", ["cone", "face-to-span", "--wrench", "{f}"], {"f": face},
                          oracle=lambda out, run, gens=gens: None if same_rows(out["generators"], gens, 1e-6)
                          and not out["lineality"] else f"{len(out['generators'])} generators, not the 16 given"))
    for name, text, kw in [
        ("toml_nan", None, None),
        ("lineality_key", '{"generators": [[1, 0]], "lineality": [[0, 1]]}', [("lineality", "unknown field")]),
        ("dim_string", '{"generators": [], "dim": "3"}', [("dim", "invalid type")]),
    ]:
        if text is None:
            cases.append(Case("cone", "bad_toml_nan", ["cone", "span-to-face", "{f}"],
                              {"f": {"generators": [[1.0, float("nan")]]}}, ext=".toml", expect="error",
                              keywords=[("generators", "finite"), ("generators", "nan")]))
            continue
        cases.append(Case("cone", f"bad_{name}", ["cone", "span-to-face", "{f}"], {"f": text}, expect="error", keywords=kw))
    return cases


def round_trip(rows):
    def check(out, run):
        back = run(["cone", "face-to-span", run.write("round_trip", {"facets": out["facets"],
                                                                     "equations": out["equations"]})])
        if back is None:
            return "face-to-span of the answer failed"
        extreme = [rows[i] for i in out["extreme_generators"]]
        if not same_rows(back["generators"], extreme, 1e-6):
            return f"{len(back['generators'])} generators back, {len(extreme)} extreme ones given"
        return None
    return check


COMMANDS = ["cone", "topp", "giwc", "equilibrium", "retime", "retime-joints", "motion", "simulate", "demo",
            "view", "robot", "setup"]


def cli_more_cases():
    cases = []

    def text_has(*words):
        def check(out, run):
            missing = [w for w in words if w not in out]
            return f"the text lacks {missing}" if missing else None
        return check
    cases.append(Case("cli", "help", ["--help"], stdout="text", oracle=text_has(*COMMANDS)))
    cases.append(Case("cli", "version", ["--version"], stdout="text", oracle=text_has("stance ")))
    for c in COMMANDS:
        cases.append(Case("cli", f"help_{c}", [c, "--help"], stdout="text", oracle=text_has(f"stance {c}")))
    for group, subs in [("equilibrium", ["polygon", "region", "test"]), ("robot", ["centroidal"])]:
        cases.append(Case("cli", f"{group}_alone", [group], expect="error", keywords=[tuple(subs)]))
    for name, args, kw in [
        ("unknown_option", ["--verbose"], [("--verbose", "unexpected")]),
        ("motion_no_source", ["motion"], [("MOTION", "required")]),
        ("view_no_source", ["view"], [("SOURCE", "required")]),
        ("topp_two_files", ["topp", "a.json", "b.json"], [("b.json", "unexpected")]),
        ("retime_joints_no_file", ["retime-joints"], [("PATH", "required")]),
        ("demo_unknown_option", ["demo", "--fast"], [("--fast", "unexpected")]),
    ]:
        cases.append(Case("cli", name, args, expect="error", keywords=kw))
    return cases


# ---------------------------------------------------------------------------------------------
# Running and classifying


class Runner:
    def __init__(self, binary, tmp):
        self.binary, self.tmp, self.last_file = binary, tmp, None
        self.paths = {}  # the current case's files and outputs, by key
        self.cache = {}  # answers computed once for several cases (see cached)
        self.count = 0

    def __call__(self, args, env=None):
        """Runs an oracle's extra command ("{key}": the current case's file): its JSON, or None
        when it failed."""
        for key, path in self.paths.items():
            args = [a.replace("{" + key + "}", path) for a in args]
        p = subprocess.run([self.binary, *args], capture_output=True, text=True, timeout=600,
                           env=case_env(env), preexec_fn=limit_memory)
        if p.returncode != 0:
            return None
        return json.loads(p.stdout)

    def write(self, name, content, ext=".json"):
        """Writes an oracle's extra input file; its path."""
        path = os.path.join(self.tmp, f"oracle_{name}{ext}")
        with open(path, "w", encoding="utf-8") as f:
            f.write(content if isinstance(content, str) else
                    toml_doc(content) if ext == ".toml" else json.dumps(content))
        return path

    def cached(self, key, args, ext=".json", content=None):
        """The JSON answer of `stance args` ("{f}" in args: `content` written to a file first),
        computed once (None when the command failed)."""
        if key not in self.cache:
            if content is not None:
                path = self.write("cached_" + key, content, ext)
                args = [a.replace("{f}", path) for a in args]
            self.cache[key] = self(args)
        return self.cache[key]


def case_env(extra):
    env = dict(os.environ)
    for k, v in (extra or {}).items():
        if v is None:
            env.pop(k, None)
        else:
            env[k] = v
    return env


def file_text(content, ext, runner):
    if callable(content):
        content = content(runner)
    if isinstance(content, str):
        return content
    return toml_doc(content) if ext == ".toml" else json.dumps(content)


def message_matches(err, keywords, paths):
    """Whether the error names one of `keywords` (see Case.keywords)."""
    bare = err
    for path in sorted(paths.values(), key=len, reverse=True):
        bare = bare.replace(path, "FILE")
    bare = bare.lower()

    def one(k):
        if any("{" + key + "}" in k for key in paths):
            for key, path in paths.items():
                k = k.replace("{" + key + "}", path)
            return k.lower() in err.lower()
        return k.lower() in bare
    return any(all(one(x) for x in k) if isinstance(k, tuple) else one(k) for k in keywords)


def limit_memory():
    """In the child, before the binary starts: at most MEMORY_BOUND bytes of data."""
    try:
        import resource
        resource.setrlimit(resource.RLIMIT_DATA, (MEMORY_BOUND, MEMORY_BOUND))
    except (ImportError, ValueError, OSError):
        pass


def run_case(case, runner, tmp, bound):
    args = []
    paths = {}
    runner.count += 1
    for key, content in case.files.items():
        # Neutral names: a message is matched against keywords with the paths taken out.
        path = os.path.join(tmp, f"c{runner.count}_{key}{case.ext}")
        paths[key] = path
        with open(path, "w", encoding="utf-8") as f:
            f.write(file_text(content, case.ext, runner))
    for key, ext in case.outputs.items():
        paths[key] = os.path.join(tmp, f"c{runner.count}_{key}{ext}")
    for a in case.args:
        for key, path in paths.items():
            a = a.replace("{" + key + "}", path)
        args.append(a)
    runner.last_file = paths.get("f")
    runner.paths = paths
    env = case_env(case.env)
    t0 = time.time()
    try:
        if case.stdout_closed:
            p = subprocess.run(f'"{runner.binary}" ' + " ".join(f"'{a}'" for a in args) + " >&-",
                               shell=True, capture_output=False, stderr=subprocess.PIPE, text=True,
                               timeout=bound, env=env, preexec_fn=limit_memory)
            stdout = ""
        else:
            p = subprocess.run([runner.binary, *args], capture_output=True, text=True,
                               timeout=bound, env=env, preexec_fn=limit_memory)
            stdout = p.stdout
    except subprocess.TimeoutExpired:
        return "slow", f"still running after {bound:g} s: killed", time.time() - t0
    dt = time.time() - t0
    err = p.stderr or ""
    # Rust's Debug formatting reaching a user: Some(..), a struct's braces, a path
    debug = next((d for d in ("Some(", "{ ", "::") if d in err), None)
    if "memory allocation of" in err:
        return "slow", f"over the memory bound of {MEMORY_BOUND / 2 ** 30:g} GB after {dt:.1f} s: " + err.strip().splitlines()[0][:200], dt
    if p.returncode == 101 or "panicked" in err:
        return "panic", err.strip().splitlines()[0] if err.strip() else "exit 101", dt
    if p.returncode < 0:
        return "crash", f"signal {-p.returncode}", dt
    if dt > bound:
        return "slow", f"{dt:.1f} s, over the bound of {bound:g} s", dt
    if p.returncode != 0 and debug:
        return "unclear", f"Debug formatting ({debug!r}) in: " + err.strip()[:300].replace("\n", " | "), dt
    if case.expect == "ok_or_error" and p.returncode != 0:
        lines = err.strip().splitlines()
        if len(lines) == 1 and message_matches(err, case.keywords, paths):
            return "ok", "", dt
        return "unclear", err.strip()[:300].replace("\n", " | "), dt
    if case.expect == "error":
        if p.returncode == 0:
            return "wrong", "accepted (exit 0) where an error was expected", dt
        lines = err.strip().splitlines()
        if len(lines) != 1 or len(err) > 600 or not message_matches(err, case.keywords, paths):
            return "unclear", err.strip()[:300].replace("\n", " | "), dt
        return "ok", "", dt
    if p.returncode != 0:
        return "wrong", "error where an answer was expected: " + err.strip()[:300], dt
    def no_constant(name):
        raise ValueError(f"{name} written to JSON")

    if case.stdout == "json":
        try:
            out = json.loads(stdout, parse_constant=no_constant)
        except json.JSONDecodeError:
            return "wrong", "exit 0 without JSON", dt
        except ValueError as e:
            return "wrong", str(e), dt
    else:
        out = stdout
    if case.oracle is not None:
        try:
            why = case.oracle(out, runner)
        except (KeyError, TypeError, IndexError, ValueError, OSError) as e:
            # The output lacks what the oracle reads (a field, a shape): not the answer asked for.
            why = f"the output lacks what the check needs: {type(e).__name__} {e}"
        if why:
            return "wrong", why, dt
    return "ok", "", dt


OUTCOMES = ("ok", "unclear", "wrong", "panic", "crash", "slow", "known", "fixed")

# Open findings: cases that fail today, each with the finding it shows (issue 30's list of what
# is left). They are reported as `known` and do not fail --check; one that passes is reported
# as `fixed`, which fails --check until it is taken off this list (so the list stays true).
KNOWN = {
}


def footholds_steps(n=2, stride=0.12):
    """The small humanoid's `n` steps forward written as footholds only (both feet down between
    them): every segment is planned by the footholds planner."""
    m = small_sway()
    m["name"] = "footholds-steps"
    del m["limits"]
    feet = {"LF": "floor", "RF": "floor"}
    segs = [{"stance": dict(feet)}]
    for i in range(n):
        foot, other, y = ("RF", "LF", -0.1) if i % 2 == 0 else ("LF", "RF", 0.1)
        segs.append({"name": f"{foot} step {i + 1}", "stance": {other: "floor"},
                     "moves": [{"links": [{"surface": foot, "onto": "floor",
                                           "at": [stride * (i + 1), y]}]}]})
        segs.append({"stance": dict(feet)})
    m["segments"] = segs
    return m


STEPS = footholds_steps()


def footholds_vs(factor=1.0, rel=1e-6, free=False):
    """Optimal, every segment planned, and the duration `factor` times the reference's (the
    footholds steps as written, without checks; `free`: without actuator limits)."""
    args = ["motion", "{f}", "--no-checks"] + (["--no-limits"] if free else [])

    def check(out, run):
        why = motion_ok(out, run, checks=False)
        if why:
            return why
        planned = (out.get("planning") or {}).get("segments") or []
        if len(planned) != len(STEPS["segments"]):
            return f"{len(planned)} planned segments, expected {len(STEPS['segments'])}"
        ref = run.cached("steps_free" if free else "steps", args, ".json", STEPS)
        if ref is None or ref.get("duration") is None:
            return "the reference footholds steps failed"
        d, want = number(out["duration"]), number(ref["duration"]) * factor
        if not rel_close(d, want, rel):
            return f"duration {d!r}, expected {want!r} (relative {abs(d - want) / want:.1e} > {rel:g})"
        return None
    return check


def footholds_moved(dx, dy, yaw=0.0):
    m = footholds_steps()
    m["environment"][0]["position"] = [dx, dy, 0.0]
    if yaw:
        m["environment"][0]["rpy"] = [0.0, 0.0, yaw]
    return m


def footholds_cases():
    """The footholds planner (issue 29): its answers, their invariances, its refusals."""
    cases = []
    g = "footholds"
    steps_ok = lambda out, run: motion_ok(out, run) or (
        None if len((out.get("planning") or {}).get("segments") or []) == 5 else "not planned")
    cases.append(motion_case("steps", STEPS, oracle=steps_ok, group=g))
    cases.append(motion_case("steps_json", STEPS, ["--no-checks"], ext=".json",
                             oracle=footholds_vs(rel=1e-12), group=g))
    # Invariances: the world moved (the regions, the swings and the search move with it) or
    # turned about the vertical (the IK's tolerances: 1e-4).
    for dx, dy in [(0.3, -0.2), (-5.0, 12.0), (1e3, -3e2)]:
        cases.append(motion_case(f"moved_{dx:g}_{dy:g}", footholds_moved(dx, dy), ["--no-checks"],
                                 oracle=footholds_vs(), group=g))
    for yaw in [math.pi / 2, -2.0]:
        cases.append(motion_case(f"turned_{yaw:.3g}", footholds_moved(0.0, 0.0, yaw), ["--no-checks"],
                                 oracle=footholds_vs(rel=1e-4), group=g))
    # Gravity: every candidate's duration scales alike, so the search picks the same plan and
    # the duration goes as 1 / sqrt(|g|) (without actuator limits).
    for grav in [1.0, 9.81 * 4]:
        spec = mutate(STEPS, ["gravity"], [0.0, 0.0, -grav])
        cases.append(motion_case(f"gravity_{grav:g}", spec, ["--no-limits", "--no-checks"],
                                 oracle=footholds_vs(math.sqrt(9.81 / grav), free=True), group=g))
    # The fraction fixed by the file: planned without a search.
    for a in [0.25, 1.0]:
        spec = mutate(STEPS, ["planning", "switch_margin"], a)
        cases.append(motion_case(f"switch_margin_{a:g}", spec, oracle=lambda out, run, a=a: motion_ok(out, run)
                                 or (None if out["planning"]["switch_margin"] == a
                                     and not out["planning"]["evaluations"] else "searched anyway"),
                                 group=g))
    # Refusals, naming the key or the segment.
    for a in [0.0, 1.5, -1.0]:
        cases.append(motion_case(f"bad_switch_margin_{a:g}", mutate(STEPS, ["planning", "switch_margin"], a),
                                 expect="error", keywords=[("planning.switch_margin", "(0, 1]")], group=g))
    for c in [0.0, 1.0, -0.1]:
        cases.append(motion_case(f"bad_swing_clearance_{c:g}",
                                 mutate(STEPS, ["planning", "swing"], {"clearance": c}),
                                 expect="error", keywords=[("planning.swing.clearance",)], group=g))
    cases.append(motion_case("bad_swing_key", mutate(STEPS, ["planning", "swing"], {"height": 0.1}),
                             expect="error", keywords=[("height", "clearance")], group=g))
    long_step = footholds_steps(1, stride=1.5)
    long_step["segments"] = long_step["segments"][:2] + [{"stance": {"RF": "floor"}}]
    cases.append(motion_case("bad_long_step", long_step, expect="error",
                             keywords=[("segment 2", "RF step 1", "m apart", "add a stance")], group=g))
    two = mutate(STEPS, SEG + [1, "moves", 0, "links"],
                 [{"surface": "RF", "onto": "floor", "at": [0.1, -0.1]},
                  {"surface": "LH", "onto": "floor", "at": [0.3, 0.3]}])
    cases.append(motion_case("bad_two_landings", two, expect="error",
                             keywords=[("segment 2", "lands 2")], group=g))
    cases.append(motion_case("bad_onto_unknown", mutate(STEPS, SEG + [1, "moves", 0, "links", 0, "onto"], "flor"),
                             expect="error", keywords=[("segment 2", "flor", "does not exist")], group=g))
    nowhere = mutate(STEPS, SEG + [1, "moves", 0, "links", 0], {"surface": "RF", "onto": "floor"})
    cases.append(motion_case("bad_onto_without_at", nowhere, expect="error",
                             keywords=[("segment 2", "at = [x, y]")], group=g))
    # A landing off its surface (a fuzz finding, issue 30: 500 km off a 4 m floor took 9 s of
    # search before its error): refused at once, naming the segment, the surfaces, the distance.
    for x, far in [(500302.0, "500300."), (2.0, "0.")]:
        off = mutate(STEPS, SEG + [1, "moves", 0, "links", 0, "at"], [x, -0.1])
        cases.append(motion_case(f"bad_landing_off_floor_{x:g}", off, expect="error",
                                 keywords=[("segment 2", '"RF" placed at', far, "outside that surface")],
                                 group=g))
    # A floor too large for the collision queries (a fuzz finding: 1e161 m made them panic,
    # 1e20 m see a collision that was not there): refused with the supported size.
    for hw in [1e20, 6.7e160]:
        huge = mutate(STEPS, ["environment", 0, "shape", "rectangle", "half_width"], hw)
        cases.append(motion_case(f"bad_floor_size_{hw:g}", huge, expect="error",
                                 keywords=[('environment surface "floor"', "supported size is up to 1e5 m")],
                                 group=g))
    # A hand in the first stance that was never placed (a fuzz finding: the planner computed
    # its regions for seconds before the IK found it): refused before any planning.
    hand = mutate(STEPS, SEG + [0, "stance"], {"LF": "floor", "RF": "floor", "LH": "floor"})
    cases.append(motion_case("bad_unplaced_hand", hand, expect="error",
                             keywords=[("segment 1", '"LH" is not on "floor"', "initial.standing.contacts")],
                             group=g))
    off_start = mutate(STEPS, ["initial", "standing", "contacts", "LF", "at"], [0.0, 7.0])
    cases.append(motion_case("bad_initial_off_floor", off_start, expect="error",
                             keywords=[("initial.standing", '"LF" placed at [0, 7]', "outside that surface")],
                             group=g))
    # Bounded work: 30 planned steps (91 segments) complete within the bound.
    cases.append(motion_case("many_steps_30", footholds_steps(30, stride=0.05), ["--no-checks"],
                             oracle=lambda out, run: motion_ok(out, run, checks=False), group=g))
    # The planned motion in the other commands: the page and the simulator take it as is.
    steps_ref = ("steps", ["motion", "{f}", "--no-checks"], ".json", STEPS)
    cases.append(Case(g, "view", ["view", "{f}", "-o", "{page}"], {"f": STEPS}, outputs={"page": ".html"},
                      stdout="text", oracle=motion_page(steps_ref, 5)))
    return cases


def all_cases():
    return (cone_cases() + cone_more_cases() + near_degenerate_cases() + topp_cases() + topp_more_cases()
            + retime_cases() + retime_more_cases() + equilibrium_cases() + equilibrium_more_cases()
            + giwc_cases() + robot_cases() + robot_more_cases() + range_cases() + bounded_cases()
            + motion_cases() + footholds_cases() + simulate_cases() + view_cases() + joints_cases() + setup_cases()
            + cli_cases() + cli_more_cases())


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--stance", default=os.path.join(ROOT, "target/release/stance"))
    ap.add_argument("--report", help="write every case's outcome as JSON")
    ap.add_argument("--check", action="store_true", help="exit 1 on wrong, panic, crash or slow")
    ap.add_argument("--time-bound", type=float, metavar="S", default=TIME_BOUND,
                    help=f"wall time a case may take (default {TIME_BOUND:g} s)")
    ap.add_argument("--only", metavar="GROUP", help="run only the cases of these groups (comma separated)")
    args = ap.parse_args()
    bound = args.time_bound
    cases = all_cases()
    if args.only:
        groups = args.only.split(",")
        cases = [c for c in cases if c.group in groups]
    tmp = tempfile.mkdtemp(prefix="stance-sweep-")
    runner = Runner(args.stance, tmp)
    counts = {k: 0 for k in OUTCOMES}
    by_group = {}
    report = []
    t_start = time.time()
    for c in cases:
        outcome, detail, dt = run_case(c, runner, tmp, bound)
        key = f"{c.group}/{c.name}"
        if key in KNOWN:
            if outcome == "ok":
                outcome, detail = "fixed", f"passes now: take it off KNOWN ({KNOWN[key]})"
            else:
                outcome, detail = "known", f"{detail} [open finding: {KNOWN[key]}]"
        counts[outcome] += 1
        by_group.setdefault(c.group, {k: 0 for k in counts})[outcome] += 1
        report.append({"group": c.group, "case": c.name, "outcome": outcome, "detail": detail,
                       "seconds": round(dt, 3)})
        if outcome != "ok":
            print(f"{outcome:8} {c.group}/{c.name}: {detail}", flush=True)
    shutil.rmtree(tmp, ignore_errors=True)
    wall = time.time() - t_start
    slowest = max(report, key=lambda r: r["seconds"], default=None)
    print(f"\n{len(cases)} cases: " + ", ".join(f"{k} {v}" for k, v in counts.items()))
    for g, cs in by_group.items():
        print(f"  {g:12} " + ", ".join(f"{k} {v}" for k, v in cs.items() if v))
    if slowest:
        print(f"wall time {wall:.1f} s; slowest case {slowest['group']}/{slowest['case']} "
              f"{slowest['seconds']:.2f} s (bound {bound:g} s)")
    if args.report:
        with open(args.report, "w") as f:
            json.dump({"counts": counts, "by_group": by_group, "cases": report}, f, indent=1)
    if args.check and (counts["wrong"] or counts["panic"] or counts["crash"] or counts["slow"]
                       or counts["fixed"]):
        sys.exit(1)


if __name__ == "__main__":
    main()
