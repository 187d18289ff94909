//! Swing paths: how a free link goes from where it is to its landing, clear of the environment.
//!
//! # Method
//!
//! A swing is a polyline of via-points, each a move of the IK (straight lines with
//! minimum-jerk timing; the orientation along the geodesic):
//!
//! 1. lift-off along the start surface's normal `n_A` by the clearance `c` (when the link starts
//!    in contact; a link in the air starts where it is): `w_1 = A + c n_A`;
//! 2. the approach point above the landing, along the target surface's normal `n_B`:
//!    `w_2 = B + c n_B`;
//! 3. a level traverse above them, at the height of the higher one plus `h >= 0`: up from
//!    `w_1`, across, down to `w_2`, with the smallest `h` (found by raising it) for which the
//!    link's contact box ([`crate::collision`]) keeps at least `c` from every environment solid
//!    at every centimetre of the traverse;
//! 4. onto `B` along `n_B`, where the landing arrives at rest (the landing speed bound of the
//!    retiming).
//!
//! Collinear legs are merged (a lift-off from a floor straight to the traverse height). The
//! clearance is the contact box's: the rest of the leg keeps the IK's own clearance
//! (`ik.clearance`) through its damper.

use nalgebra::{Matrix3, Rotation3, Vector3};
use stance_robot::Pose;

use crate::collision::CollisionModel;
use crate::spec::LinkMoveSpec;
use crate::StanceError;

/// The world `z` axis.
fn up() -> Vector3<f64> {
    Vector3::z()
}

/// A swing to plan.
#[derive(Debug, Clone)]
pub struct SwingProblem<'a> {
    /// Name of the robot surface (for the moves and errors).
    pub surface_name: &'a str,
    /// Index of the robot surface.
    pub surface: usize,
    /// Where it starts (world), and whether it lifts off a surface there.
    pub start: Pose,
    /// Lifts off a surface (its normal is the start frame's `z`).
    pub from_contact: bool,
    /// Its landing (world).
    pub target: Pose,
    /// The landing as the file wrote it (kept as the last move).
    pub landing: LinkMoveSpec,
    /// Clearance `c` (m).
    pub clearance: f64,
}

/// The via-points of a swing (module doc), one link move per IK move.
///
/// # Errors
///
/// [`StanceError::BadMotion`] when no traverse up to [`crate::tol::MAX_SWING_HEIGHT`] above
/// the straight one clears the environment.
pub fn plan_swing(
    p: &SwingProblem,
    collision: &CollisionModel,
    what: &str,
) -> Result<Vec<LinkMoveSpec>, StanceError> {
    let c = p.clearance;
    let n_a = p.start.rotation.column(2).into_owned();
    let n_b = p.target.rotation.column(2).into_owned();
    let lift = if p.from_contact {
        n_a * c
    } else {
        Vector3::zeros()
    };
    let w1 = p.start.translation + lift;
    let w2 = p.target.translation + n_b * c;
    let mut h = 0.0;
    let (u1, u2) = loop {
        // the traverse is level, at the higher end's height plus h
        let level = w1.z.max(w2.z) + h;
        let u1 = Vector3::new(w1.x, w1.y, level);
        let u2 = Vector3::new(w2.x, w2.y, level);
        let worst = traverse_clearance(p, collision, &u1, &u2);
        if worst >= c - crate::tol::SWING_CLEARANCE_SLACK {
            break (u1, u2);
        }
        h += (c - worst).max(crate::tol::SWING_RAISE_STEP);
        if h > crate::tol::MAX_SWING_HEIGHT {
            return Err(StanceError::BadMotion(format!(
                "{what}: no swing of {:?} clears the environment by {c} m (planning.swing.\
                 clearance) with a traverse up to {} m above its start and landing; write its \
                 moves by hand or move the landing",
                p.surface_name,
                crate::tol::MAX_SWING_HEIGHT
            )));
        }
    };
    let mut out = Vec::new();
    let vertical = |n: &Vector3<f64>| (n - up()).norm() <= crate::tol::SWING_VERTICAL;
    let by = |v: Vector3<f64>| LinkMoveSpec {
        surface: p.surface_name.to_string(),
        by: Some(v.into()),
        ..empty_move()
    };
    let to = |v: Vector3<f64>, r: Option<&Matrix3<f64>>| LinkMoveSpec {
        surface: p.surface_name.to_string(),
        to: Some(v.into()),
        rpy: r.map(rpy_of),
        ..empty_move()
    };
    let rise = u1.z - w1.z;
    let drop = u2.z - w2.z;
    if p.from_contact && vertical(&n_a) {
        out.push(by(up() * (c + rise)));
    } else {
        if p.from_contact {
            out.push(by(lift));
        }
        if rise > 0.0 {
            out.push(by(up() * rise));
        }
    }
    if drop > 0.0 {
        out.push(to(u2, Some(&p.target.rotation)));
        if !vertical(&n_b) {
            out.push(to(w2, None));
        }
    } else {
        out.push(to(w2, Some(&p.target.rotation)));
    }
    out.push(p.landing.clone());
    Ok(out)
}

fn empty_move() -> LinkMoveSpec {
    LinkMoveSpec {
        surface: String::new(),
        by: None,
        rotate_by: None,
        to: None,
        rpy: None,
        onto: None,
        at: None,
        yaw: None,
    }
}

/// The smallest distance (m) of the link's contact box to the environment's solids along the
/// traverse `u1 -> u2`, its orientation turning from the start's to the landing's.
fn traverse_clearance(
    p: &SwingProblem,
    collision: &CollisionModel,
    u1: &Vector3<f64>,
    u2: &Vector3<f64>,
) -> f64 {
    let length = (u2 - u1).norm();
    let n = ((length / crate::tol::SWING_SAMPLE).ceil() as usize).clamp(1, 10_000);
    let turn =
        stance_robot::spatial::rotation_log(&(p.start.rotation.transpose() * p.target.rotation));
    let range = p.clearance + crate::tol::SWING_CLEARANCE_SLACK;
    let mut worst = f64::INFINITY;
    for i in 0..=n {
        let t = i as f64 / n as f64;
        let pose = Pose {
            rotation: p.start.rotation * Rotation3::from_scaled_axis(turn * t).into_inner(),
            translation: u1 + (u2 - u1) * t,
        };
        for solid in 0..collision.solids.len() {
            if let Some(d) = collision.surface_distance(p.surface, &pose, solid, range) {
                worst = worst.min(d.distance);
            }
        }
    }
    worst
}

/// Roll, pitch, yaw (URDF convention, `R = Rz(yaw) Ry(pitch) Rx(roll)`) of a rotation.
pub fn rpy_of(r: &Matrix3<f64>) -> [f64; 3] {
    let pitch = (-r[(2, 0)]).clamp(-1.0, 1.0).asin();
    [
        r[(2, 1)].atan2(r[(2, 2)]),
        pitch,
        r[(1, 0)].atan2(r[(0, 0)]),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rpy_round_trips() {
        for rpy in [
            [0.3, -0.2, 1.1],
            [0.0, 0.0, -3.0],
            [0.39, 0.0, 0.0],
            [-1.0, 1.2, 2.0],
        ] {
            let r = Pose::from_xyz_rpy([0.0; 3], rpy).rotation;
            let back = Pose::from_xyz_rpy([0.0; 3], rpy_of(&r)).rotation;
            assert!((r - back).norm() < 1e-14, "{rpy:?}");
        }
    }
}
