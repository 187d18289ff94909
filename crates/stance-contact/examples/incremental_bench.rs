//! Adding a contact: `U_stance` of the stance with the contact from scratch (warm workspace)
//! against continuing the conversion of the stance without it (`GiwcBuilder::add_contact`),
//! on the paper's scenes and a 4-contact stance with fixed random poses. Both answers are
//! compared before timing. Each time is the median of single calls (at least 2000 calls, at
//! least 0.3 s per scene and variant); the continuation is timed on a fresh clone of the
//! builder of the smaller stance each call (the clone is outside the timed region, and timed
//! apart). "no completeness" repeats both with `DdOptions::check_completeness = false` (the
//! ridge check of the certificate skipped): the difference is that check's cost.
//!
//! Run: `cargo run --release -p stance-contact --example incremental_bench`.

use std::time::Instant;

use nalgebra::{Rotation3, Unit, Vector3};
use stance_contact::{examples, Contact, FrictionModel, GiwcBuilder, GiwcOptions, Shape, Stance};

/// Median seconds of `f` over single calls; `setup` runs before each call, untimed.
fn median<S, T, F: FnMut(T)>(mut setup: S, mut f: F) -> f64
where
    S: FnMut() -> T,
{
    let mut v = Vec::new();
    let start = Instant::now();
    while v.len() < 2000 || start.elapsed().as_secs_f64() < 0.3 {
        let x = setup();
        let t = Instant::now();
        f(x);
        v.push(t.elapsed().as_secs_f64());
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// A rectangle contact tilted by `angle` about `axis`.
fn rect(name: &str, p: [f64; 3], axis: [f64; 3], angle: f64, half: [f64; 2], mu: f64) -> Contact {
    let r = Rotation3::from_axis_angle(&Unit::new_normalize(Vector3::from(axis)), angle);
    let m = r.matrix();
    let rot = [
        [m[(0, 0)], m[(0, 1)], m[(0, 2)]],
        [m[(1, 0)], m[(1, 1)], m[(1, 2)]],
        [m[(2, 0)], m[(2, 1)], m[(2, 2)]],
    ];
    let shape = Shape::Rectangle {
        half_length: half[0],
        half_width: half[1],
    };
    Contact::new(name, p, rot, shape, mu, &Default::default()).expect("valid contact")
}

/// Four contacts with poses drawn once from a fixed-seed generator (xorshift), kept fixed.
fn four_contacts() -> Stance {
    let mut s: u64 = 0x2545_F491_4F6C_DD1D;
    let mut u = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let contacts = (0..4)
        .map(|i| {
            let p = [0.4 * u(), 0.4 * u(), 0.4 + 0.4 * u()];
            let axis = [u(), u(), 0.2 * u()];
            let angle = 0.6 * u();
            let half = [0.06 + 0.04 * u(), 0.04 + 0.02 * u()];
            let mu = 0.7 + 0.2 * u();
            rect(&format!("C{i}"), p, axis, angle, half, mu)
        })
        .collect();
    Stance::new(contacts, FrictionModel::default()).expect("valid stance")
}

struct Row {
    name: &'static str,
    gens: (usize, usize),
    facets: usize,
    scratch_us: f64,
    cont_us: f64,
    clone_us: f64,
    scratch_nc_us: f64,
    cont_nc_us: f64,
}

fn bench(name: &'static str, stance: &Stance) -> Row {
    let n = stance.contacts().len();
    let before = Stance::new(
        stance.contacts()[..n - 1].to_vec(),
        *stance.friction_model(),
    )
    .expect("valid stance");
    let added = stance.contacts()[n - 1].clone();
    let full = GiwcOptions::default();
    let mut nc = GiwcOptions::default();
    nc.dd.check_completeness = false;
    // Answers first: the continued cone equals the one from scratch.
    let scratch = stance.u_stance(&full).expect("u_stance");
    let mut b = GiwcBuilder::new(&before, &full).expect("builder");
    let cont = b.add_contact(added.clone()).expect("add_contact").clone();
    assert!(
        matches!(
            b.last_step(),
            polycone::Step::Continued { .. } | polycone::Step::Reframed { .. }
        ),
        "{name}: {:?}",
        b.last_step()
    );
    assert!(cont.certified && scratch.certified);
    assert_eq!(cont.facets.nrows(), scratch.facets.nrows(), "{name}");
    for r in cont.facets.row_iter() {
        let best = scratch
            .facets
            .row_iter()
            .map(|s| (r - s).amax())
            .fold(f64::INFINITY, f64::min);
        assert!(best < 1e-9, "{name}: facet off by {best:e}");
    }
    let mut times = Vec::new();
    for opts in [&full, &nc] {
        let mut ws = polycone::Workspace::new();
        let scratch_t = median(
            || (),
            |_| {
                std::hint::black_box(stance.u_stance_with(&mut ws, opts).expect("u_stance"));
            },
        );
        let base = GiwcBuilder::new(&before, opts).expect("builder");
        let cont_t = median(
            || base.clone(),
            |mut b| {
                std::hint::black_box(b.add_contact(added.clone()).expect("add").facets.nrows());
            },
        );
        times.push((scratch_t, cont_t));
    }
    let base = GiwcBuilder::new(&before, &full).expect("builder");
    let clone_t = median(
        || (),
        |_| {
            std::hint::black_box(base.clone());
        },
    );
    Row {
        name,
        gens: (before.giwc_span().nrows(), stance.giwc_span().nrows()),
        facets: scratch.facets.nrows(),
        scratch_us: times[0].0 * 1e6,
        cont_us: times[0].1 * 1e6,
        clone_us: clone_t * 1e6,
        scratch_nc_us: times[1].0 * 1e6,
        cont_nc_us: times[1].1 * 1e6,
    }
}

fn main() {
    let rows = [
        (
            "single -> double support",
            examples::double_support_flat().stance(),
        ),
        ("stairs (left -> + right foot)", examples::stairs().stance()),
        (
            "box climbing (foot -> + hand)",
            examples::box_climbing().stance(),
        ),
    ]
    .into_iter()
    .map(|(n, s)| bench(n, &s.expect("example stance")))
    .chain(std::iter::once(bench(
        "4 contacts, fixed random poses (3 -> 4)",
        &four_contacts(),
    )))
    .collect::<Vec<_>>();
    println!(
        "| stance | generators | facets | from scratch (us) | continued (us) | speed-up | clone (us) | no completeness: scratch / continued (us) |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for r in rows {
        println!(
            "| {} | {} -> {} | {} | {:.1} | {:.1} | x{:.2} | {:.1} | {:.1} / {:.1} |",
            r.name,
            r.gens.0,
            r.gens.1,
            r.facets,
            r.scratch_us,
            r.cont_us,
            r.scratch_us / r.cont_us,
            r.clone_us,
            r.scratch_nc_us,
            r.cont_nc_us
        );
    }
}
