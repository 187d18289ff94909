"""Contacts and stances: the GIWC against cddlib's exact answers, every face-form answer
against the independent supporting-forces QP, and the invariances (world origin, heading,
units, mass)."""

from __future__ import annotations

import json
from typing import List

import numpy as np
import pytest

import stance

from conftest import TESTDATA, load, same_rows_up_to_scaling, same_span

GIWC_CASES = sorted(
    p.stem for p in (TESTDATA / "contact").glob("*.json") if p.stem != "surface_cwc_foot"
)


def fixture_stance(case: str, mass: float = 50.0) -> stance.Stance:
    d = load(f"contact/{case}.json")
    contacts = [
        stance.Contact.rectangle(c["pos"], c["R"], c["half_size"][0], c["half_size"][1], c["mu"], name=c["name"])
        for c in d["contacts"]
    ]
    return stance.Stance(contacts, mass=mass)


@pytest.mark.parametrize("case", GIWC_CASES)
def test_giwc_equals_cdd_exact(case: str) -> None:
    d = load(f"contact/{case}.json")
    giwc = fixture_stance(case).giwc()
    assert giwc.certified
    assert same_rows_up_to_scaling(giwc.facets, np.array(d["reference_facets"]).reshape(-1, 6), angle=1e-8)
    assert same_span(giwc.equations, np.array(d["reference_equations"], dtype=float).reshape(-1, 6))
    assert giwc.lineality.shape[0] == d["reference_lineality_dim"]


@pytest.mark.parametrize("dz", [0.0, 1e-9, 1e-5])
def test_giwc_says_which_arithmetic_gave_it(dz: float) -> None:
    # Two flat feet, the right one raised by dz: coplanar, the floating-point answer (16 rows);
    # 1e-9 m and 1e-5 m, an exact fallback whose slivers are merged (16 and 42 rows, the
    # intended geometries' counts, as the Rust tests check).
    feet = [
        stance.Contact.rectangle([0.0, y, z], np.eye(3), 0.11, 0.065, 0.7, name=n)
        for n, y, z in [("l", 0.1, 0.0), ("r", -0.1, dz)]
    ]
    giwc = stance.Stance(feet, mass=60.0).giwc()
    assert giwc.certified
    if dz == 0.0:
        assert (giwc.arithmetic, giwc.merged_rows, giwc.facets.shape[0]) == ("tolerance", 0, 16)
    else:
        assert giwc.arithmetic == "exact_fallback"
        assert giwc.merged_rows > 0
        assert giwc.facets.shape[0] <= 42
    assert stance.Giwc(giwc.facets).arithmetic is None


def double_support() -> stance.Stance:
    foot = dict(rotation=np.eye(3), half_length=0.11, half_width=0.065, friction=0.7)
    return stance.Stance(
        [
            stance.Contact.rectangle([0.0, 0.1, 0.0], name="LF", **foot),
            stance.Contact.rectangle([0.1, -0.1, 0.05], name="RF", **foot),
        ],
        mass=40.0,
    )


def random_coms(rng: np.random.Generator, n: int, center: np.ndarray, spread: float = 0.3) -> np.ndarray:
    return center + rng.uniform(-spread, spread, size=(n, 3)) * np.array([1, 1, 0.3])


@pytest.mark.parametrize("scene", ["stairs", "box-climbing", "double-support"])
def test_static_equilibrium_equals_supporting_forces(scene: str, rng: np.random.Generator) -> None:
    st = stance.Stance.from_scene(scene)
    centre = np.mean([c.position for c in st.contacts], axis=0) + [0, 0, 0.8]
    coms = random_coms(rng, 200, centre)
    fast = st.is_static_equilibrium(coms)
    poly = st.static_equilibrium_polygon()
    checked = 0
    for p, ok in zip(coms, fast):
        # Skip CoMs within 0.1 mm of the boundary (the tolerance decides there).
        margin = np.min(poly.b - poly.A @ p[:2]) if poly.status == "bounded" else np.inf
        if abs(margin) < 1e-4:
            continue
        f = st.supporting_forces(p)
        assert f.outcome in ("feasible", "infeasible")
        assert f.feasible == bool(ok), (p, ok, f)
        checked += 1
    assert checked > 150
    assert 0 < fast.sum() < len(fast)


def test_polygon_vertices_are_supported_and_just_outside_is_not() -> None:
    st = double_support()
    poly = st.static_equilibrium_polygon(height=0.8)
    assert poly.status == "bounded" and poly.dim == 2
    c = poly.vertices.mean(axis=0)
    for v in poly.vertices:
        inside = v + 1e-4 * (c - v) / np.linalg.norm(c - v)
        outside = v - 1e-3 * (c - v) / np.linalg.norm(c - v)
        assert st.supporting_forces([*inside, 0.8]).feasible
        assert not st.supporting_forces([*outside, 0.8]).feasible
    # The half-planes are those of the vertices.
    assert (poly.A @ poly.vertices.T - poly.b[:, None]).max() <= 1e-9


def test_robust_region_is_the_intersection_of_static_sets(rng: np.random.Generator) -> None:
    st = stance.Stance.from_scene("robust-equilibrium")
    gravities = np.array([[2.0, 0, -9.81], [-2.0, 0, -9.81], [0, 2.0, -9.81], [0, -2.0, -9.81], [0, 0, -9.81]])
    region = st.robust_static_region(gravities)
    assert region.status == "bounded" and region.dim == 3
    centre = region.vertices.mean(axis=0)
    coms = centre + rng.uniform(-0.4, 0.4, size=(300, 3))
    robust = st.is_robust_static_equilibrium(coms, gravities)
    assert np.array_equal(robust, region.contains(coms))
    each = np.all([st.is_static_equilibrium(coms, gravity=g) for g in gravities], axis=0)
    margins = np.array([region.margin(p) for p in coms])
    far = np.abs(margins) > 1e-6
    assert np.array_equal(robust[far], each[far])
    assert 0 < robust.sum() < len(robust)


def moved(st: stance.Stance, R: np.ndarray, t: np.ndarray, k: float = 1.0) -> stance.Stance:
    """The stance seen from another world frame (rotation R, translation t) and length unit
    (lengths times k; gravity in the same unit)."""
    contacts = []
    for c in st.contacts:
        d = c.to_dict()
        shape = d["shape"]
        if isinstance(shape, dict) and "rectangle" in shape:
            r = shape["rectangle"]
            contacts.append(
                stance.Contact.rectangle(
                    k * (R @ c.position + t), R @ c.rotation, k * r["half_length"], k * r["half_width"], c.friction, name=c.name
                )
            )
        else:
            raise NotImplementedError(shape)
    return stance.Stance(contacts, st.mass, gravity=k * (R @ st.gravity))


def test_answers_do_not_depend_on_the_world_frame_or_units(rng: np.random.Generator) -> None:
    st = stance.Stance.from_scene("stairs")
    centre = np.mean([c.position for c in st.contacts], axis=0) + [0, 0, 0.8]
    coms = random_coms(rng, 300, centre)
    base = st.is_static_equilibrium(coms)
    poly = st.static_equilibrium_polygon()
    margin = np.array([np.min(poly.b - poly.A @ p[:2]) for p in coms])
    clear = np.abs(margin) > 1e-5
    a = 0.7
    Rz = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
    for R, t, k in [
        (np.eye(3), np.array([1000.0, -2000.0, 30.0]), 1.0),  # origin 2 km away
        (Rz, np.array([3.0, 4.0, 0.0]), 1.0),  # another heading
        (np.eye(3), np.zeros(3), 1000.0),  # millimetres
        (Rz, np.array([5.0, 0.0, 0.0]), 0.01),  # hectometres
    ]:
        other = moved(st, R, t, k)
        mapped = k * (coms @ R.T + t)
        got = other.is_static_equilibrium(mapped)
        assert np.array_equal(got[clear], base[clear]), (R, t, k)
        other_poly = other.static_equilibrium_polygon(height=float(mapped[0, 2]))
        assert other_poly.vertices.shape == poly.vertices.shape


def test_polygon_does_not_depend_on_the_mass() -> None:
    a = double_support().static_equilibrium_polygon()
    scene = double_support().to_dict()
    scene["mass"] = 4000.0
    b = stance.Stance.from_scene(scene).static_equilibrium_polygon()
    assert np.allclose(a.vertices, b.vertices, atol=1e-12)


def test_supporting_forces_balance_the_wrench() -> None:
    st = double_support()
    f = st.supporting_forces([0.05, 0.0, 0.8], com_acceleration=[0.3, 0.0, 0.0])
    assert f.feasible
    total = f.forces.sum(axis=0)
    assert np.allclose(total, -st.mass * (st.gravity - [0.3, 0.0, 0.0]), atol=1e-6)
    torque = np.cross(f.points, f.forces).sum(axis=0)
    assert np.allclose(np.concatenate([total, torque]), -f.w_gi, atol=1e-6)
    assert f.contact_names == ["LF", "RF"]
    assert len(f.contact_index) == 8
    # Too much acceleration: a certified negative outcome, a value.
    no = st.supporting_forces([0.05, 0.0, 0.8], com_acceleration=[30.0, 0.0, 0.0])
    assert no.outcome == "infeasible" and not no


def test_from_scene_accepts_a_path_a_dict_and_a_name(tmp_path) -> None:  # type: ignore[no-untyped-def]
    by_name = stance.Stance.from_scene("box-climbing")
    d = by_name.to_dict()
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(d))
    for other in (stance.Stance.from_scene(d), stance.Stance.from_scene(path), stance.Stance.from_scene(str(path))):
        assert other.to_dict() == d
        assert np.array_equal(other.giwc().facets, by_name.giwc().facets)
    with pytest.raises(stance.InputError, match="stairs"):
        stance.Stance.from_scene("moon")
    with pytest.raises(stance.InputError):
        stance.Stance.from_scene({"mass": 10})


def test_contacts_of_every_shape() -> None:
    R = np.eye(3)
    tri = stance.Contact.polygon([0, 0, 0], R, [[0.1, 0], [-0.05, 0.08], [-0.05, -0.08]], 0.6, name="tri")
    pt = stance.Contact.point([0.3, 0, 0], friction=0.5)
    assert tri.vertices.shape == (3, 3)
    assert pt.vertices.shape == (1, 3)
    st = stance.Stance([tri, pt], mass=10.0)
    assert st.is_static_equilibrium([0.1, 0.0, 0.5])
    contacts: List[stance.Contact] = st.contacts
    assert [c.name for c in contacts] == ["tri", "contact1"]  # numbered by its place


def test_contacts_without_names_are_numbered_and_explicit_duplicates_are_an_error() -> None:
    # the pypoman way: contacts made without names; a stance numbers them by their place
    feet = [stance.Contact.rectangle([0.0, y, 0.0], np.eye(3), 0.11, 0.065, 0.7) for y in (0.1, -0.1)]
    s = stance.Stance(feet, mass=60.0)
    assert [c.name for c in s.contacts] == ["contact0", "contact1"]
    assert s.giwc().facets.shape[0] == 16
    # a given name keeps its own, and the numbering steps around it
    mixed = [
        stance.Contact.rectangle([0.0, 0.1, 0.0], np.eye(3), 0.11, 0.065, 0.7, name="contact1"),
        stance.Contact.rectangle([0.0, -0.1, 0.0], np.eye(3), 0.11, 0.065, 0.7),
    ]
    assert [c.name for c in stance.Stance(mixed, mass=60.0).contacts] == ["contact1", "contact1_1"]
    twice = [
        stance.Contact.rectangle([0.0, y, 0.0], np.eye(3), 0.11, 0.065, 0.7, name="foot") for y in (0.1, -0.1)
    ]
    with pytest.raises(stance.InputError, match="duplicate contact name"):
        stance.Stance(twice, mass=60.0)
