//! Via-points reached: where the IK's whole-body path is at the end of each move, against the
//! CoM and link via-points the motion file asked for.
//!
//! # Math
//!
//! A move ends at the segment-local path parameter `sigma` (the sum of its segment's move
//! durations so far). The IK samples the path at `s_i` with `q_ss` constant on each step, and
//! records the CoM's path terms `(p, p_s, p_ss)` of the step that starts at each sample; the CoM
//! at `sigma` in `[s_i, s_i+1)` is `p + p_s d + p_ss d^2 / 2`, `d = sigma - s_i` (exact for the
//! CoM's second-order expansion along the step). A link's placement is read at the sample
//! nearest `sigma` by forward kinematics: links arrive at their via-points at rest (minimum-jerk
//! legs, module [`super::references`]), so half a step off the end moves them by a third-order
//! amount (below 1e-6 of the leg's length at the default grid). The errors are the distances
//! to the via-points and, for links, the angle of `R_target^T R_reached`.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use stance_robot::{forward_kinematics, frame_placement, Data};

use super::ik_stage::SegmentPath;
use super::plan::MotionPlan;
use crate::StanceError;

/// One move's end: its via-points and where the IK's path was.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MoveInfo {
    /// Segment-local path parameter of the move's end.
    pub s_end: f64,
    /// The CoM via-point (m, world): the file's `com` target, or where the CoM stays.
    pub com_target: [f64; 3],
    /// The CoM of the IK's path there (`null` where the IK stopped before).
    pub com_reached: Option<[f64; 3]>,
    /// Distance between the two (m).
    pub com_error: Option<f64>,
    /// Links whose move ends here.
    pub links: Vec<LinkReached>,
}

/// A link's via-point at the end of its move.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LinkReached {
    /// The robot surface.
    pub surface: String,
    /// Target position (m, world).
    pub target: [f64; 3],
    /// Distance of the reached position from the target (m).
    pub position_error: f64,
    /// Angle between the reached and target orientations (degrees).
    pub rotation_error_deg: f64,
}

/// The moves of every segment, in order (`paths` as the IK made them).
///
/// # Errors
///
/// A model error of the forward kinematics (not expected for the plan's own configurations).
pub fn moves_reached(
    plan: &MotionPlan,
    paths: &[SegmentPath],
) -> Result<Vec<Vec<MoveInfo>>, StanceError> {
    let m = &plan.robot.model;
    let mut data = Data::new(m);
    let mut via = 1; // the CoM's via-point at the end of the next move (0: the start)
    let mut out = Vec::with_capacity(paths.len());
    for path in paths {
        let refs = &path.references;
        let com = &refs.com;
        let mut moves = Vec::with_capacity(refs.knots.len().saturating_sub(1));
        for &sigma in &refs.knots[1..] {
            let target = com.points[via.min(com.points.len() - 1)];
            via += 1;
            let reached = com_at(path, sigma);
            let mut links = Vec::new();
            for l in &refs.links {
                let Some(leg) = l.legs.iter().find(|leg| same_s(leg.s[1], sigma)) else {
                    continue;
                };
                let Some(i) = nearest_sample(path, sigma) else {
                    continue;
                };
                forward_kinematics(m, &mut data, &path.samples[i].q).map_err(StanceError::Robot)?;
                let x = frame_placement(m, &data, l.frame).map_err(StanceError::Robot)?;
                let angle = stance_robot::spatial::rotation_log(
                    &(leg.to.rotation.transpose() * x.rotation),
                )
                .norm();
                links.push(LinkReached {
                    surface: plan.robot.surfaces[l.surface].name.clone(),
                    target: leg.to.translation.into(),
                    position_error: (x.translation - leg.to.translation).norm(),
                    rotation_error_deg: angle.to_degrees(),
                });
            }
            moves.push(MoveInfo {
                s_end: sigma,
                com_target: target.into(),
                com_reached: reached.map(Into::into),
                com_error: reached.map(|p| (p - target).norm()),
                links,
            });
        }
        out.push(moves);
    }
    Ok(out)
}

/// Path parameters equal up to round-off of their sums.
fn same_s(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1.0)
}

/// The IK sample nearest `sigma`, if the IK got there (half a step of slack).
fn nearest_sample(path: &SegmentPath, sigma: f64) -> Option<usize> {
    let smp = &path.samples;
    let last = smp.last()?;
    let step = if smp.len() > 1 {
        smp[1].s - smp[0].s
    } else {
        0.0
    };
    if sigma > last.s + 0.5 * step {
        return None;
    }
    let i = smp.partition_point(|x| x.s <= sigma);
    let below = i.saturating_sub(1);
    Some(
        if i < smp.len() && smp[i].s - sigma < sigma - smp[below].s {
            i
        } else {
            below
        },
    )
}

/// The CoM of the IK's path at `sigma` (module doc), if the IK got there.
fn com_at(path: &SegmentPath, sigma: f64) -> Option<Vector3<f64>> {
    let smp = &path.samples;
    let i = smp.partition_point(|x| x.s <= sigma).checked_sub(1)?;
    let t = &smp[i].terms;
    let d = sigma - smp[i].s;
    if i + 1 == smp.len() && !same_s(sigma, smp[i].s) {
        return None; // the IK stopped before
    }
    Some(t.p + t.p_s * d + t.p_ss * (0.5 * d * d))
}

/// The largest via-point distance (CoM or link, m) and link angle (degrees) over `moves`.
pub fn largest_errors(moves: &[Vec<MoveInfo>]) -> [f64; 2] {
    let mut out = [0.0f64; 2];
    for mv in moves.iter().flatten() {
        out[0] = out[0].max(mv.com_error.unwrap_or(0.0));
        for l in &mv.links {
            out[0] = out[0].max(l.position_error);
            out[1] = out[1].max(l.rotation_error_deg);
        }
    }
    out
}

/// A via-point the IK's path missed by more than [`crate::tol::VIA_POINT_DISTANCE`] or
/// [`crate::tol::VIA_POINT_ANGLE_DEG`]: out of the robot's reach, held off an environment solid
/// by the IK's clearance (a straight move that cuts a step's edge), or traded by the IK for
/// another task (the CoM against a link: `ik.w_com`, `ik.w_link`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ViaPointMiss {
    /// Segment, numbered from 1.
    pub segment: usize,
    /// Its name.
    pub segment_name: String,
    /// Move within the segment, numbered from 1.
    pub move_number: usize,
    /// `"com"` or the robot surface.
    pub target: String,
    /// Distance from the via-point (m).
    pub distance: f64,
    /// Angle from its orientation (degrees; 0 for the CoM).
    pub angle_deg: f64,
}

/// The via-points of `moves` (per segment, as [`moves_reached`] gives them) missed beyond the
/// tolerances, in order.
pub fn missed(plan: &MotionPlan, moves: &[Vec<MoveInfo>]) -> Vec<ViaPointMiss> {
    let mut out = Vec::new();
    for (k, seg) in moves.iter().enumerate() {
        for (j, mv) in seg.iter().enumerate() {
            let mut push = |target: &str, distance: f64, angle_deg: f64| {
                if distance > crate::tol::VIA_POINT_DISTANCE
                    || angle_deg > crate::tol::VIA_POINT_ANGLE_DEG
                {
                    out.push(ViaPointMiss {
                        segment: k + 1,
                        segment_name: plan.segments[k].name.clone(),
                        move_number: j + 1,
                        target: target.to_string(),
                        distance,
                        angle_deg,
                    });
                }
            };
            if let Some(e) = mv.com_error {
                push("com", e, 0.0);
            }
            for l in &mv.links {
                push(&l.surface, l.position_error, l.rotation_error_deg);
            }
        }
    }
    out
}
