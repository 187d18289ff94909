//! `GiwcBuilder::add_contact` (continued double description) against `Stance::u_stance` from
//! scratch on the stance with the contact added: golden scenes built one contact at a time,
//! random stances, two point contacts (5-D GIWC), opposing walls (non-pointed).

mod common;

use common::*;
use nalgebra::Vector3;
use polycone::{Restart, Step};
use proptest::prelude::*;
use stance_contact::{
    examples, Approximation, Contact, FrictionModel, Giwc, GiwcBuilder, Shape, Stance,
};

/// Largest difference (max-norm of unit rows) between a continued facet and its match from
/// scratch.
const ROW_TOL: f64 = 1e-9;

/// Same cone: same facet set, same equation and lineality spaces, both certified.
fn assert_same(cont: &Giwc, scratch: &Giwc, what: &str) {
    assert!(cont.certified && scratch.certified, "{what}: certified");
    same_rows(&cont.facets, &scratch.facets, ROW_TOL).unwrap_or_else(|e| panic!("{what}: {e}"));
    assert_eq!(cont.equations.nrows(), scratch.equations.nrows(), "{what}");
    assert_eq!(cont.lineality.nrows(), scratch.lineality.nrows(), "{what}");
    let d = (projector(&cont.equations, 6) - projector(&scratch.equations, 6)).amax();
    assert!(d < 1e-9, "{what}: equation spaces differ by {d:e}");
    let d = (projector(&cont.lineality, 6) - projector(&scratch.lineality, 6)).amax();
    assert!(d < 1e-9, "{what}: lineality spaces differ by {d:e}");
}

/// Builds `stance` one contact at a time, checking every step against the conversion from
/// scratch; returns the steps taken.
fn build_one_at_a_time(stance: &Stance, what: &str) -> Vec<Step> {
    let fm = *stance.friction_model();
    let cs = stance.contacts();
    let first = Stance::new(vec![cs[0].clone()], fm).unwrap();
    let mut b = GiwcBuilder::new(&first, &Default::default()).unwrap();
    assert_same(
        b.giwc(),
        &first.u_stance(&Default::default()).unwrap(),
        what,
    );
    let mut steps = Vec::new();
    for (i, c) in cs.iter().enumerate().skip(1) {
        let giwc = b.add_contact(c.clone()).unwrap().clone();
        let prefix = Stance::new(cs[..=i].to_vec(), fm).unwrap();
        assert_eq!(b.stance(), &prefix);
        let scratch = prefix.u_stance(&Default::default()).unwrap();
        assert_same(&giwc, &scratch, &format!("{what}, contact {i}"));
        steps.push(b.last_step().clone());
    }
    steps
}

/// The paper's scenes (single -> double support, stairs, box climbing: foot then hand) and
/// the shared fixtures (flat double support, two feet and two hands on opposing walls with
/// and without friction): every added rectangle continues (the first is already 6-D) and
/// equals the conversion from scratch.
#[test]
fn golden_scenes_one_contact_at_a_time() {
    let mut stances: Vec<(String, Stance)> = ["double-support", "stairs", "box-climbing"]
        .iter()
        .map(|n| {
            (
                n.to_string(),
                examples::by_name(n).unwrap().stance().unwrap(),
            )
        })
        .collect();
    for f in [
        "double_support_flat",
        "opposing_walls_frictionless",
        "opposing_walls_friction",
    ] {
        stances.push((f.to_string(), fixture_stance(&fixture(f))));
    }
    for (name, stance) in &stances {
        for step in build_one_at_a_time(stance, name) {
            assert!(
                matches!(step, Step::Continued { .. } | Step::Reframed { .. }),
                "{name}: {step:?}"
            );
        }
    }
    // The walls: pointed until the second hand, then a 3-D lineality (frictionless) or the
    // whole space (with friction).
    let walls = fixture_stance(&fixture("opposing_walls_frictionless"));
    let mut b = GiwcBuilder::new(
        &Stance::new(walls.contacts()[..3].to_vec(), FrictionModel::default()).unwrap(),
        &Default::default(),
    )
    .unwrap();
    assert_eq!(b.giwc().lineality.nrows(), 0);
    assert_eq!(
        b.add_contact(walls.contacts()[3].clone())
            .unwrap()
            .lineality
            .nrows(),
        3
    );
}

/// Two point contacts: the GIWC goes from 3-D (three equations) to 5-D (one equation): the
/// span grows, so the builder converts from scratch and says why; a third point off their
/// line makes it 6-D (from scratch again); a fourth point continues.
#[test]
fn point_contacts_5d_then_6d() {
    let eye = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let point = |name: &str, p: [f64; 3]| {
        Contact::new(name, p, eye, Shape::Point, 0.7, &Default::default()).unwrap()
    };
    let a = Stance::new(vec![point("a", [0.0, 0.2, 0.0])], FrictionModel::default()).unwrap();
    let mut b = a.giwc_builder(&Default::default()).unwrap();
    assert_eq!(b.giwc().equations.nrows(), 3);
    let g = b.add_contact(point("b", [0.0, -0.2, 0.0])).unwrap().clone();
    assert_eq!(g.equations.nrows(), 1, "the 5-D GIWC of two points");
    assert_eq!(
        b.last_step(),
        &Step::FromScratch(Restart::RankChanged { from: 3, to: 5 })
    );
    assert_same(
        &g,
        &b.stance().u_stance(&Default::default()).unwrap(),
        "two points",
    );
    let g = b.add_contact(point("c", [0.3, 0.0, 0.05])).unwrap().clone();
    assert_eq!(g.equations.nrows(), 0);
    assert_eq!(
        b.last_step(),
        &Step::FromScratch(Restart::RankChanged { from: 5, to: 6 })
    );
    assert_same(
        &g,
        &b.stance().u_stance(&Default::default()).unwrap(),
        "three points",
    );
    let g = b.add_contact(point("d", [-0.2, 0.1, 0.0])).unwrap().clone();
    assert!(matches!(
        b.last_step(),
        Step::Continued { rows_added: 4 } | Step::Reframed { rows_added: 4, .. }
    ));
    assert_same(
        &g,
        &b.stance().u_stance(&Default::default()).unwrap(),
        "four points",
    );
}

fn contact_strategy() -> impl Strategy<Value = Contact> {
    (
        (-0.4f64..0.4, -0.4f64..0.4, 0.0f64..0.8),
        (-1.0f64..1.0, -1.0f64..1.0, 0.0f64..1.0),
        0usize..3,
        (0.02f64..0.15, 0.02f64..0.1),
        0.1f64..1.2,
    )
        .prop_map(|(p, (ax, ay, t), kind, (x, y), mu)| {
            let axis = Vector3::new(ax, ay, 0.0);
            test_contact([p.0, p.1, p.2], axis, 0.7 * t, kind, (x, y), mu)
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, .. ProptestConfig::default() })]

    /// Random stances of 1 to 4 contacts (points, rectangles, triangles; the paper's pyramid
    /// or a k-sided one), built one contact at a time: each step equals the conversion from
    /// scratch; a step restarts only for a stated reason about the span or the conditioning.
    #[test]
    fn random_stances_one_contact_at_a_time(
        contacts in prop::collection::vec(contact_strategy(), 1..=4),
        sides in prop_oneof![3 => Just(4usize), 1 => 3usize..7],
        outer in proptest::bool::ANY,
    ) {
        let fm = FrictionModel {
            sides,
            approximation: if outer { Approximation::Outer } else { Approximation::Inner },
        };
        let stance = Stance::new(contacts, fm).unwrap();
        for step in build_one_at_a_time(&stance, "random") {
            match step {
                Step::Continued { .. } | Step::Reframed { .. } => {}
                Step::FromScratch(Restart::RankChanged { from, to }) => prop_assert!(from < to),
                // Point contacts leave the rank decision to the conversion from scratch;
                // stances degenerate at the scale of the tolerances may fail the certificate
                // when continued.
                Step::FromScratch(Restart::RankUndecided | Restart::Uncertified(_)) => {}
                other => prop_assert!(false, "unexpected {other:?}"),
            }
        }
    }
}

/// A builder can move to and be shared between threads.
#[test]
fn builder_is_send_and_sync() {
    fn check<T: Send + Sync>() {}
    check::<GiwcBuilder>();
}
