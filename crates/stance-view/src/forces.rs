//! The contact forces the page draws: at every playback frame, forces at the vertices of the
//! segment's planned contacts that hold the frame's motion, from the independent check's
//! problem.
//!
//! At the frame's trajectory sample `(q, v, a)` the gravito-inertial wrench `w_GI` comes from
//! the model's centroidal dynamics ([`stance_motion::checks::w_gi_of`]), and
//! [`stance_contact::supporting_forces`] finds vertex forces inside the planned friction
//! pyramids with `sum f = -w_GI` of least squared norm (the force check's problem, solved by
//! its slow path, Clarabel, at each frame on its own). Each vertex force `f`, in its contact
//! frame `(f_t, f_n)`, has the friction usage `|f_t| / (mu f_n)` against Coulomb's circle
//! (`mu` the contact's own coefficient): below 1 it sticks; a pyramid's corners reach
//! `sqrt 2` for an outer pyramid.

use serde::Serialize;
use stance_contact::{supporting_forces, Contact, ForcesOutcome, FrictionModel, Stance};
use stance_motion::result::TrajectoryInfo;
use stance_motion::StanceError;
use stance_robot::{Data, Model};

/// Length of the arrow of a force equal to the robot's weight (m).
pub const WEIGHT_ARROW: f64 = 1.0;

/// The contact forces of the playback (`forces` in the page data).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ForcesView {
    /// Arrow length per newton (m/N): [`WEIGHT_ARROW`] over the weight.
    pub scale: f64,
    /// Per frame: whether forces hold the motion there (`false`: the check finds none, and the
    /// frame has no forces).
    pub feasible: Vec<bool>,
    /// Per frame, per contact of the frame's stance (in the stance's order), per vertex: the
    /// force on the robot (N, world axes), rounded to 0.1 N.
    pub forces: Vec<Vec<Vec<[f64; 3]>>>,
    /// Per frame, per contact, per vertex: the friction usage `|f_t| / (mu f_n)` (module doc),
    /// rounded to 1e-3 (0 for a vertex without load).
    pub usage: Vec<Vec<Vec<f64>>>,
}

/// The forces at the trajectory samples `samples` (indices into `tr`), each in the stance of
/// its segment (`stances[k]`, the contacts of segment `k`).
///
/// # Errors
///
/// A sample that does not fit the model.
pub fn forces_view(
    model: &Model,
    tr: &TrajectoryInfo,
    samples: &[usize],
    stances: &[Vec<Contact>],
    friction: FrictionModel,
    gravity: [f64; 3],
) -> Result<ForcesView, StanceError> {
    let mut data = Data::new(model);
    let weight = model.total_mass() * gravity.iter().map(|g| g * g).sum::<f64>().sqrt();
    let tol = Default::default();
    let stances: Vec<Option<Stance>> = stances
        .iter()
        .map(|c| Stance::new(c.clone(), friction).ok())
        .collect();
    let mut view = ForcesView {
        scale: WEIGHT_ARROW / weight.max(f64::MIN_POSITIVE),
        feasible: Vec::with_capacity(samples.len()),
        forces: Vec::with_capacity(samples.len()),
        usage: Vec::with_capacity(samples.len()),
    };
    for &i in samples {
        let segment = tr.segment[i].saturating_sub(1);
        let w = stance_motion::checks::w_gi_of(
            model, &mut data, &tr.q[i], &tr.v[i], &tr.a[i], gravity,
        )?;
        let found = match stances.get(segment).and_then(Option::as_ref) {
            Some(stance) => supporting_forces(stance, &w, &tol)
                .ok()
                .filter(|f| f.outcome == ForcesOutcome::Feasible)
                .map(|f| (stance, f)),
            None => None,
        };
        let Some((stance, found)) = found else {
            view.feasible.push(false);
            view.forces.push(Vec::new());
            view.usage.push(Vec::new());
            continue;
        };
        let round = |x: f64| (x * 10.0).round() / 10.0;
        let mut forces = Vec::new();
        let mut usage = Vec::new();
        for (c, contact) in found.contacts.iter().zip(stance.contacts()) {
            forces.push(c.forces_world.iter().map(|f| f.map(round)).collect());
            usage.push(
                c.forces_local
                    .iter()
                    .map(|f| {
                        let tangential = f[0].hypot(f[1]);
                        let normal = f[2] * contact.friction();
                        if normal > 1e-9 * weight {
                            (tangential / normal * 1e3).round() / 1e3
                        } else {
                            0.0
                        }
                    })
                    .collect(),
            );
        }
        view.feasible.push(true);
        view.forces.push(forces);
        view.usage.push(usage);
    }
    Ok(view)
}
