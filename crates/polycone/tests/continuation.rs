//! A continued conversion (`Continuation::add_generators`) against the conversion from scratch
//! of the same stacked generators, and against the cdd exact references.

mod common;

use common::*;
use polycone::nalgebra::DMatrix;
use polycone::{span_to_face, Arithmetic, Continuation, DdOptions, Restart, SpanToFace, Step};
use proptest::prelude::*;

/// Largest angle between a facet of the continued result and the matching one from scratch.
const MAX_ANGLE: f64 = 1e-9;

/// Rows `from..to` of `v`.
fn rows(v: &DMatrix<f64>, from: usize, to: usize) -> DMatrix<f64> {
    v.rows(from, to - from).into_owned()
}

/// The continued result equals the conversion from scratch: same facets (as sets, up to
/// `MAX_ANGLE`; the lexicographic order of both is the same rule on values that differ by
/// rounding, so rows whose leading coordinates tie up to rounding may swap), same equations
/// and lineality spaces, same extreme generators, both certified.
fn assert_same(cont: &SpanToFace, scratch: &SpanToFace, what: &str) {
    assert_same_cone(cont, scratch, None, what);
}

/// [`assert_same`] on random stances (generators `v`), which may be degenerate at the scale of
/// the tolerances: there the two answers may merge that structure differently, or one of them
/// may come from the exact fallback (module docs of `polycone::continuation`). Where their
/// facets differ, both must still be the cone for the membership oracle at the points where
/// they differ most (`probe_unmatched_facets` of `tests/common`): an answer missing a genuine facet (what
/// cddlib's float mode loses) contains points beyond it by the margin of its other facets; one
/// that merged it into a facet through the same generators does not.
fn assert_same_up_to_merging(
    cont: &SpanToFace,
    scratch: &SpanToFace,
    v: &DMatrix<f64>,
    what: &str,
) {
    assert_same_cone(cont, scratch, Some(v), what);
}

fn assert_same_cone(cont: &SpanToFace, scratch: &SpanToFace, v: Option<&DMatrix<f64>>, what: &str) {
    assert!(cont.certificate.certified, "{what}: {:?}", cont.certificate);
    assert!(scratch.certificate.certified, "{what}: scratch");
    let same = cont.certificate.arithmetic == scratch.certificate.arithmetic
        && same_rows_up_to_scaling(&cont.face.facets, &scratch.face.facets, MAX_ANGLE).is_some();
    match (same, v) {
        (true, _) => assert_eq!(
            cont.extreme_generators, scratch.extreme_generators,
            "{what}: extreme generators"
        ),
        (false, None) => panic!(
            "{what}: {} facets continued ({:?}), {} from scratch ({:?})",
            cont.face.facets.nrows(),
            cont.certificate.arithmetic,
            scratch.face.facets.nrows(),
            scratch.certificate.arithmetic
        ),
        (false, Some(v)) => {
            // Merged differently (extreme generators near-degenerate too): probe the
            // differences with the oracle.
            let (fc, fs) = (&cont.face.facets, &scratch.face.facets);
            let a = probe_unmatched_facets(fc, fs, v, MAX_ANGLE);
            let b = probe_unmatched_facets(fs, fc, v, MAX_ANGLE);
            let summary = format!(
                "{what}: {} facets continued ({:?}), {} from scratch ({:?}), unmatched probed: \
                 {a:?} {b:?}",
                fc.nrows(),
                cont.certificate.arithmetic,
                fs.nrows(),
                scratch.certificate.arithmetic
            );
            assert!(a.is_ok() && b.is_ok(), "{summary}");
            eprintln!("merged differently: {summary}");
        }
    }
    assert_eq!(
        cont.face.equations.nrows(),
        scratch.face.equations.nrows(),
        "{what}: equations"
    );
    assert!(
        same_span(&cont.face.equations, &scratch.face.equations, 1e-9),
        "{what}: equation span"
    );
    assert_eq!(
        cont.lineality.nrows(),
        scratch.lineality.nrows(),
        "{what}: lineality dimension"
    );
    assert!(
        same_span(&cont.lineality, &scratch.lineality, 1e-9),
        "{what}: lineality span"
    );
}

/// Golden stances built one contact (16 generators) at a time: every step continues (the
/// first contact is a 6-D rectangle wrench cone, so the span never grows), equals the
/// conversion from scratch of the generators so far, and the last one equals cdd's exact
/// reference. Covers a non-pointed end (opposing frictionless walls: 3-D lineality appears at
/// the last contact) and the whole space (walls with friction: no facet).
#[test]
fn golden_stances_one_contact_at_a_time() {
    let opts = DdOptions::default();
    for case in [
        "double_support_flat",
        "double_support_stairs",
        "tilted_foot_hand_ledge",
        "opposing_walls_frictionless",
        "opposing_walls_friction",
    ] {
        let j = load(case);
        let v = matrix_hex(&j["generators"]["float64_hex"], 6);
        let n = v.nrows();
        assert_eq!(n % 16, 0);
        let mut c = Continuation::new(&rows(&v, 0, 16), &opts).unwrap();
        assert_eq!(c.last_step(), &Step::FromScratch(Restart::Initial));
        for end in (32..=n).step_by(16) {
            let r = c.add_generators(&rows(&v, end - 16, end)).unwrap().clone();
            assert!(
                matches!(
                    c.last_step(),
                    Step::Continued { .. } | Step::Reframed { .. }
                ),
                "{case} at {end}: {:?}",
                c.last_step()
            );
            assert_eq!(c.generators(), &rows(&v, 0, end));
            let scratch = span_to_face(&rows(&v, 0, end), &opts).unwrap();
            assert_same(&r, &scratch, &format!("{case} at {end}"));
        }
        let reference = &j["reference_cdd_gmp_exact_input"];
        let ref_facets = normalized(&matrix_f64(&reference["facets_float64"], 6));
        let r = c.result();
        assert!(
            same_rows_up_to_scaling(&r.face.facets, &ref_facets, MAX_ANGLE).is_some(),
            "{case}: {} facets, cdd {}",
            r.face.facets.nrows(),
            ref_facets.nrows()
        );
        assert_eq!(
            r.lineality.nrows(),
            reference["lineality_dim"].as_u64().unwrap() as usize,
            "{case}"
        );
        assert_eq!(r.face.equations.nrows(), 0, "{case}");
    }
}

/// The same golden stances split in two at every contact boundary and at odd places inside
/// a contact (a partial rectangle is still 6-D after 8 generators of a tilted foot, not
/// after 4 of a flat one): continued or restarted for a stated reason, always equal to the
/// conversion from scratch.
#[test]
fn golden_stances_split_anywhere() {
    let opts = DdOptions::default();
    let mut continued = 0;
    let mut restarted = 0;
    for case in [
        "double_support_flat",
        "double_support_stairs",
        "tilted_foot_hand_ledge",
        "opposing_walls_frictionless",
    ] {
        let v = matrix_hex(&load(case)["generators"]["float64_hex"], 6);
        let n = v.nrows();
        for split in [1, 3, 5, 8, 11, 16, 19, 24, 29, 31] {
            let mut c = Continuation::new(&rows(&v, 0, split), &opts).unwrap();
            let r = c.add_generators(&rows(&v, split, n)).unwrap().clone();
            match c.last_step() {
                Step::Continued { rows_added } | Step::Reframed { rows_added, .. } => {
                    assert!(*rows_added <= n - split);
                    continued += 1;
                }
                Step::FromScratch(Restart::RankChanged { from, to }) => {
                    assert!(from < to, "{case} split {split}");
                    restarted += 1;
                }
                other => panic!("{case} split {split}: {other:?}"),
            }
            let scratch = span_to_face(&v, &opts).unwrap();
            assert_same(&r, &scratch, &format!("{case} split {split}"));
        }
    }
    assert!(continued > 10 && restarted > 5, "{continued} {restarted}");
}

/// A random rectangle contact (positions within 1 m, tilts up to 40 degrees, patches 1 to
/// 20 cm, friction 0.3 to 1).
#[allow(clippy::needless_range_loop)] // matrix products read like the math
fn random_contact(p: [f64; 3], ang: [f64; 3], half: [f64; 2], mu: f64) -> Contact {
    let mut c = Contact::flat([p[0], p[1], 0.3 * p[2]], half, mu);
    let r1 = rotation([1.0, 0.0, 0.0], ang[0]);
    let r2 = rotation([0.0, 1.0, 0.0], ang[1]);
    let r3 = rotation([0.0, 0.0, 1.0], ang[2]);
    let mut r12 = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            for k in 0..3 {
                r12[i][j] += r1[i][k] * r2[k][j];
            }
        }
    }
    c.rot = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            for k in 0..3 {
                c.rot[i][j] += r12[i][k] * r3[k][j];
            }
        }
    }
    c
}

fn contact_strategy() -> impl Strategy<Value = Contact> {
    (
        prop::array::uniform3(-1.0f64..1.0),
        prop::array::uniform3(-0.7f64..0.7),
        prop::array::uniform2(0.005f64..0.1),
        0.3f64..1.0,
    )
        .prop_map(|(p, ang, half, mu)| random_contact(p, ang, half, mu))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, .. ProptestConfig::default() })]

    /// Random stances of 1 to 4 rectangles, one contact added at a time after the first:
    /// every step continues (or restarts on the condition bound) and equals the conversion
    /// from scratch (itself checked against
    /// a membership oracle in `properties.rs`).
    #[test]
    fn random_stances_one_contact_at_a_time(
        contacts in prop::collection::vec(contact_strategy(), 1..=4),
    ) {
        let opts = DdOptions::default();
        let v = giwc_generators(&contacts);
        let mut c = Continuation::new(&rows(&v, 0, 16), &opts).unwrap();
        let scratch = span_to_face(&rows(&v, 0, 16), &opts).unwrap();
        assert_same_up_to_merging(c.result(), &scratch, &rows(&v, 0, 16), "first contact");
        for end in (32..=v.nrows()).step_by(16) {
            let previous_exact = c.result().certificate.arithmetic == Arithmetic::Exact;
            let r = c.add_generators(&rows(&v, end - 16, end)).unwrap().clone();
            let scratch = span_to_face(&rows(&v, 0, end), &opts).unwrap();
            // Small patches far apart leave the frame of the first contacts badly conditioned
            // for the new ones: then the state moves to fresh coordinates (`Reframed`). On
            // stances degenerate at the scale of the tolerances the continued double
            // description may fail the certificate: then a stated restart (the answer is the
            // one from scratch); and a result from the exact fallback leaves no state to
            // continue from (the next step starts over, and says why).
            prop_assert!(
                matches!(
                    c.last_step(),
                    Step::Continued { .. }
                        | Step::Reframed { .. }
                        | Step::FromScratch(Restart::Uncertified(_))
                ) || (previous_exact
                    && c.last_step() == &Step::FromScratch(Restart::NotResumable)),
                "{:?} (previous result exact: {previous_exact})",
                c.last_step()
            );
            assert_same_up_to_merging(&r, &scratch, &rows(&v, 0, end), &format!("at {end}"));
        }
    }
}

/// Five contacts: 64 generators (one-word zero sets) before the fifth, 80 after (two words):
/// the continuation re-packs the zero sets and still equals the conversion from scratch; so
/// does a continuation that starts below 64 and crosses with several contacts at once.
#[test]
fn crossing_the_one_word_boundary() {
    let opts = DdOptions::default();
    let contacts = [
        random_contact([0.0, 0.3, 0.0], [0.1, 0.0, 0.2], [0.11, 0.065], 0.7),
        random_contact([0.1, -0.3, 0.5], [0.0, 0.2, -0.3], [0.11, 0.065], 0.6),
        random_contact([0.5, 0.6, 2.0], [1.2, 0.1, 0.0], [0.05, 0.04], 0.8),
        random_contact([0.4, -0.6, 1.8], [-1.1, 0.0, 0.4], [0.05, 0.04], 0.5),
        random_contact([-0.3, 0.0, 0.2], [0.3, -0.3, 0.5], [0.08, 0.03], 0.9),
    ];
    let v = giwc_generators(&contacts);
    assert_eq!(v.nrows(), 80);
    for (first, steps) in [
        (64, vec![80]),
        (48, vec![80]),
        (16, vec![40, 63, 64, 65, 80]),
    ] {
        let mut c = Continuation::new(&rows(&v, 0, first), &opts).unwrap();
        let mut from = first;
        for to in steps {
            let r = c.add_generators(&rows(&v, from, to)).unwrap().clone();
            assert!(
                matches!(
                    c.last_step(),
                    Step::Continued { .. } | Step::Reframed { .. }
                ),
                "{first} -> {to}: {:?}",
                c.last_step()
            );
            let scratch = span_to_face(&rows(&v, 0, to), &opts).unwrap();
            assert_same(&r, &scratch, &format!("{first} -> {to}"));
            from = to;
        }
    }
}

/// Two point contacts: a 3-D cone, then a 5-D one (the span grows: from scratch), then a
/// third point off their line makes it 6-D (from scratch again); a fourth point continues.
#[test]
fn point_contacts_grow_the_span() {
    let opts = DdOptions::default();
    let point = |x: f64, y: f64, z: f64| {
        // A rectangle of size zero: its first corner is the point, with 4 pyramid edges.
        let c = Contact::flat([x, y, z], [0.0, 0.0], 0.7);
        giwc_generators(&[c]).rows(0, 4).into_owned()
    };
    let p1 = point(0.0, 0.0, 0.0);
    let mut c = Continuation::new(&p1, &opts).unwrap();
    assert_eq!(c.result().face.equations.nrows(), 3);
    let steps = [
        (point(0.3, 0.0, 0.0), Some((3, 5))),
        (point(0.0, 0.4, 0.1), Some((5, 6))),
        (point(0.2, 0.3, 0.05), None),
    ];
    for (new, restart) in steps {
        let r = c.add_generators(&new).unwrap().clone();
        match restart {
            Some((from, to)) => assert_eq!(
                c.last_step(),
                &Step::FromScratch(Restart::RankChanged { from, to })
            ),
            None => assert!(matches!(
                c.last_step(),
                Step::Continued { rows_added: 4 } | Step::Reframed { rows_added: 4, .. }
            )),
        }
        let scratch = span_to_face(c.generators(), &opts).unwrap();
        assert_same(&r, &scratch, "points");
    }
    // The 5-D cone of the first two points had one equation; the four points have none.
    assert_eq!(c.result().face.equations.nrows(), 0);
}

/// Zero and duplicate new generators are dropped as from scratch: adding only those leaves
/// the cone unchanged with no polar row processed; mixed with a new one, only it counts.
#[test]
fn zero_and_duplicate_generators() {
    let opts = DdOptions::default();
    let j = load("double_support_stairs");
    let v = matrix_hex(&j["generators"]["float64_hex"], 6);
    let first = rows(&v, 0, 16);
    let mut c = Continuation::new(&first, &opts).unwrap();
    let before = c.result().clone();
    // Zero rows and positively scaled copies of earlier generators.
    let mut junk = DMatrix::zeros(4, 6);
    junk.row_mut(1).copy_from(&(first.row(3) * 2.5));
    junk.row_mut(2).copy_from(&first.row(7));
    let r = c.add_generators(&junk).unwrap().clone();
    assert_eq!(c.last_step(), &Step::Continued { rows_added: 0 });
    assert_same(&r, &before, "junk vs before");
    assert_eq!(r.extreme_generators, before.extreme_generators);
    assert_same(&r, &span_to_face(c.generators(), &opts).unwrap(), "junk");
    // The second foot with a duplicate of itself inside, and a zero row.
    let mut more = DMatrix::zeros(18, 6);
    more.rows_mut(0, 16).copy_from(&rows(&v, 16, 32));
    more.row_mut(16).copy_from(&v.row(20));
    let r = c.add_generators(&more).unwrap().clone();
    assert_eq!(c.last_step(), &Step::Continued { rows_added: 16 });
    assert_same(&r, &span_to_face(c.generators(), &opts).unwrap(), "foot");
    // Adding nothing.
    let r = c.add_generators(&DMatrix::zeros(0, 6)).unwrap().clone();
    assert_eq!(c.last_step(), &Step::Continued { rows_added: 0 });
    assert_eq!(r.face.facets.nrows(), 176);
}

/// Generators 1e15 times smaller than the ones added later stay generators: a cone does not
/// change when a generator is scaled, so the continuation keeps them (no restart) and gives
/// the cone of the same rows at unit scale.
#[test]
fn tiny_old_generators_stay_generators() {
    let opts = DdOptions::default();
    let unit = [1.0, 0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0];
    let tiny: Vec<f64> = unit.iter().map(|x| x * 1e-20).collect();
    let mut c = Continuation::new(&DMatrix::from_row_slice(4, 3, &tiny), &opts).unwrap();
    assert_eq!(c.result().extreme_generators.len(), 4);
    let big = DMatrix::from_row_slice(3, 3, &[1e-5, 0.0, 1e-5, 0.0, 1e-5, 1e-5, 0.0, 0.0, 1e-5]);
    let r = c.add_generators(&big).unwrap().clone();
    assert!(
        matches!(c.last_step(), Step::Continued { .. }),
        "{:?}",
        c.last_step()
    );
    assert_same(&r, &span_to_face(c.generators(), &opts).unwrap(), "tiny");
    let mut all_unit = DMatrix::from_row_slice(4, 3, &unit);
    all_unit = all_unit.resize_vertically(7, 0.0);
    all_unit.rows_mut(4, 3).copy_from(&DMatrix::from_row_slice(
        3,
        3,
        &[1.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0],
    ));
    assert_same(&r, &span_to_face(&all_unit, &opts).unwrap(), "unit");
}

/// Exact arithmetic: every step is an exact conversion from scratch, equal to
/// `span_to_face` in exact mode.
#[test]
fn exact_mode_restarts() {
    let opts = DdOptions {
        arithmetic: Arithmetic::Exact,
        ..DdOptions::default()
    };
    let v = matrix_hex(&load("single_support_flat")["generators"]["float64_hex"], 6);
    let mut c = Continuation::new(&rows(&v, 0, 12), &opts).unwrap();
    let r = c.add_generators(&rows(&v, 12, 16)).unwrap().clone();
    assert_eq!(c.last_step(), &Step::FromScratch(Restart::ExactArithmetic));
    assert_eq!(r.certificate.arithmetic, Arithmetic::Exact);
    let scratch = span_to_face(&v, &opts).unwrap();
    assert_eq!(r, scratch);
}

/// Bad input is an error and leaves the continuation as it was.
#[test]
fn bad_input() {
    let opts = DdOptions::default();
    let v = DMatrix::<f64>::identity(3, 3);
    assert!(Continuation::new(&DMatrix::zeros(2, 0), &opts).is_err());
    assert!(Continuation::new(&DMatrix::from_row_slice(1, 2, &[f64::NAN, 0.0]), &opts).is_err());
    let mut c = Continuation::new(&v, &opts).unwrap();
    let e = c.add_generators(&DMatrix::zeros(1, 4)).unwrap_err();
    assert!(e.to_string().contains("new generators"), "{e}");
    let e = c
        .add_generators(&DMatrix::from_row_slice(1, 3, &[0.0, f64::INFINITY, 1.0]))
        .unwrap_err();
    assert!(e.to_string().contains("finite"), "{e}");
    assert_eq!(c.generators(), &v);
    // Still usable, and it still continues.
    c.add_generators(&DMatrix::from_row_slice(1, 3, &[-1.0, 1.0, 1.0]))
        .unwrap();
    assert_eq!(c.last_step(), &Step::Continued { rows_added: 1 });
}

/// The condition bound of the frame is enforced: with `continuation_condition = 1` every
/// addition moves the state to fresh coordinates (a new generator always has `|y| > 0`), which
/// resets the bound, and still equals the conversion from scratch; with the default, the same
/// step continues in the frame.
#[test]
fn condition_bound_is_enforced() {
    let v = matrix_hex(
        &load("double_support_stairs")["generators"]["float64_hex"],
        6,
    );
    let mut strict = DdOptions::default();
    strict.tol.continuation_condition = 1.0;
    let mut c = Continuation::new(&rows(&v, 0, 16), &strict).unwrap();
    assert_eq!(c.condition_bound(), 1.0);
    let r = c.add_generators(&rows(&v, 16, 24)).unwrap().clone();
    match c.last_step() {
        Step::Reframed { rows_added, kappa } => assert!(*rows_added == 8 && *kappa > 1.0),
        other => panic!("{other:?}"),
    }
    assert_eq!(c.condition_bound(), 1.0);
    assert_same(
        &r,
        &span_to_face(&rows(&v, 0, 24), &strict).unwrap(),
        "strict 24",
    );
    let r = c.add_generators(&rows(&v, 24, 32)).unwrap().clone();
    assert!(matches!(
        c.last_step(),
        Step::Reframed { rows_added: 8, .. }
    ));
    assert_same(&r, &span_to_face(&v, &strict).unwrap(), "strict 32");
    let mut c = Continuation::new(&rows(&v, 0, 16), &DdOptions::default()).unwrap();
    c.add_generators(&rows(&v, 16, 32)).unwrap();
    assert!(matches!(c.last_step(), Step::Continued { rows_added: 16 }));
    assert!(c.condition_bound() > 1.0 && c.condition_bound() < 10.0);
    // A negative or NaN bound is bad input.
    let mut bad = DdOptions::default();
    bad.tol.continuation_condition = f64::NAN;
    assert!(Continuation::new(&rows(&v, 0, 16), &bad).is_err());
}

/// A continuation can move to and be shared between threads.
#[test]
fn continuation_is_send_and_sync() {
    fn check<T: Send + Sync>() {}
    check::<Continuation>();
    check::<Step>();
}

/// Regression (found by the random-stance property at 1500 cases): four contacts with 5 mm
/// patches, built one at a time. Without polishing, the continued facet normals came from
/// longer chains of ray combinations and were up to 1.3e-8 rad away from those from scratch
/// (tight residuals 3e-11 against 2e-15); with `Tolerances::polish` they agree within 1e-9.
#[test]
fn regression_tiny_patches_continued_facets_are_polished() {
    let mk =
        |pos: [f64; 3], rot: [[f64; 3]; 3], half: [f64; 2], mu: f64| Contact { pos, rot, half, mu };
    let cs = [
        mk(
            [0.2675006364597472, -0.40322450974875557, 0.1589367577262561],
            [
                [0.8366960822952185, 0.2779523963559359, 0.4718920758307196],
                [-0.4107336922891827, 0.8884184169837002, 0.20496475400095285],
                [
                    -0.36226716645361046,
                    -0.3653151813491589,
                    0.8575006229650818,
                ],
            ],
            [0.005, 0.005],
            0.3,
        ),
        mk(
            [0.0, -0.6133195044554318, 0.0],
            [
                [0.7496431786368106, 0.5617650285301887, -0.34993593334176915],
                [-0.4170875160728617, 0.811511471207551, 0.4092519224569708],
                [0.5138804419896413, -0.16083900279171212, 0.8426492191425199],
            ],
            [0.005, 0.0737747837544293],
            0.32410896296055797,
        ),
        mk(
            [0.0, 0.0, 0.0],
            [
                [0.7637142924454946, -0.6370166028878075, 0.10464381090038104],
                [0.605264970329602, 0.6502112483129258, -0.459216341454932],
                [0.22448785091042978, 0.4140473163934577, 0.8821394586917607],
            ],
            [0.005, 0.08787480541033334],
            0.3,
        ),
        mk(
            [-0.7671634352604421, 0.0, 0.0],
            [
                [
                    0.9870489253048417,
                    -0.03921486923693959,
                    -0.1555526055239409,
                ],
                [0.12106510650132776, 0.8182834609219196, 0.5619211844818339],
                [0.10525045863263113, -0.5734756940031327, 0.812433363018313],
            ],
            [0.005, 0.005],
            0.3,
        ),
    ];
    let v = giwc_generators(&cs);
    let worst_angle = |opts: &DdOptions| {
        let mut c = Continuation::new(&rows(&v, 0, 16), opts).unwrap();
        for end in [32, 48, 64] {
            c.add_generators(&rows(&v, end - 16, end)).unwrap();
        }
        let (r, s) = (c.result(), span_to_face(&v, opts).unwrap());
        assert_eq!(r.face.facets.nrows(), s.face.facets.nrows());
        let row = |m: &DMatrix<f64>, i: usize| m.row(i).iter().copied().collect::<Vec<f64>>();
        (0..r.face.facets.nrows())
            .map(|i| {
                (0..s.face.facets.nrows())
                    .map(|j| angle(&row(&r.face.facets, i), &row(&s.face.facets, j)))
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max)
    };
    let polished = worst_angle(&DdOptions::default());
    assert!(polished <= MAX_ANGLE, "{polished:e}");
    let mut raw = DdOptions::default();
    raw.tol.polish = f64::MAX;
    let unpolished = worst_angle(&raw);
    assert!(
        unpolished > 1e-9,
        "the regression input lost its teeth: {unpolished:e}"
    );
}

/// The probe of [`assert_same_up_to_merging`] has teeth: with any one facet dropped from a
/// conversion (the failure of cddlib's float mode), the dropped facet is probed and the probe
/// fails; the answer against itself passes. (With a 5 mm patch in the stance, a facet through
/// five of its nearly parallel generators can span so thin a wedge that dropping it stays
/// within the band at the probed point: like the membership oracle, the probe sees the cone,
/// not its combinatorics, which the certificate proves.)
#[test]
fn probing_finds_every_dropped_facet() {
    let contacts = [
        random_contact([0.0, 0.3, 0.0], [0.1, 0.0, 0.2], [0.11, 0.065], 0.7),
        random_contact([0.1, -0.3, 0.5], [0.0, 0.2, -0.3], [0.11, 0.065], 0.6),
        random_contact([0.5, 0.6, 2.0], [1.2, 0.1, 0.0], [0.05, 0.04], 0.8),
    ];
    let v = giwc_generators(&contacts);
    let r = span_to_face(&v, &DdOptions::default()).unwrap();
    let f = &r.face.facets;
    assert_eq!(probe_unmatched_facets(f, f, &v, MAX_ANGLE), Ok(0));
    let nf = r.face.facets.nrows();
    assert!(nf > 50, "{nf}");
    for k in 0..nf {
        let dropped = f.clone().remove_row(k);
        let probe = probe_unmatched_facets(f, &dropped, &v, MAX_ANGLE);
        assert!(
            probe
                .as_ref()
                .is_err_and(|e| e.contains("contains the point")),
            "facet {k}: {probe:?}"
        );
    }
}
