//! Stage 2, whole-body path: per segment, the contacts are read off the configuration at its
//! start and checked against their environment surfaces, the task references are built from the
//! moves ([`super::references`]), and the acceleration-level IK ([`stance_robot::ik`]) is
//! integrated along the segment's grid into `q(s), q_s, q_ss` with the path terms
//! `p, p_s, p_ss, l1, l2` of eq. 14 at every IK sample (docs/math.md section 6).
//!
//! The IK holds the stance's contact frames at their placements at the segment's start
//! (velocity damping and pose correction with the contact gain), tracks the CoM and the free
//! links with the segment's gain and weights, the nominal posture with a small weight, and keeps
//! the joints within the paper's damper bounds (`K_s = K_ss = 10`, ranges shrunk to
//! `ik.joint_range`). A segment starts from the state `(q, q_s)` where the previous one ended, so
//! that `q_s` (the joint velocity per unit path speed) is continuous across segments.

use std::time::{Duration, Instant};

use nalgebra::{Matrix6xX, Vector3};
use stance_robot::{
    center_of_mass, forward_kinematics, frame_jacobian, frame_placement, integrate,
    path_terms_from_data, ContactHold, Data, DistanceBound, IkAnswerFrom, IkOptions, IkStatus,
    IkTasks, IkWorkspace, JointBounds, PathTerms, Pose, ReferenceFrame,
};

use super::environment::{polygon_of, OnSurface};
use super::plan::{LinkGoal, MotionPlan};
use super::references::{ComReference, CornerKernel, LinkLeg, LinkPlan, SegmentReferences};
use super::spec::ComTarget;
use crate::StanceError;

/// One IK sample of a segment.
#[derive(Debug, Clone, PartialEq)]
pub struct IkSample {
    /// Segment-local path parameter.
    pub s: f64,
    /// Configuration.
    pub q: Vec<f64>,
    /// `dq/ds` (velocity space).
    pub q_s: Vec<f64>,
    /// `d^2q/ds^2` (velocity space; constant until the next sample).
    pub q_ss: Vec<f64>,
    /// Path terms of eq. 14 at this sample, on the step that starts here (with this sample's
    /// `q_ss`: the right limit).
    pub terms: PathTerms,
    /// The same on the step that ends here (with the previous sample's `q_ss`: the left limit;
    /// equal to `terms` at a segment's first sample). The joint path's `q_ss` is constant on
    /// each step, so `p_ss` and `l2` jump at the samples, and the retiming enforces both
    /// limits.
    pub terms_left: PathTerms,
}

/// A contact of a segment as read off the robot at its start.
#[derive(Debug, Clone, PartialEq)]
pub struct PlacedContact {
    /// Robot surface index.
    pub surface: usize,
    /// Environment surface index.
    pub environment: usize,
    /// `world_from_surface`, the contact frame of the GIWC: the robot surface's placement at
    /// the segment's start snapped onto the environment surface
    /// ([`super::environment::EnvSurface::snap`]), or the target of the move that landed it
    /// when the robot is within the contact tolerances of it; the IK holds the contact there.
    pub pose: Pose,
    /// How well it lies on its environment surface.
    pub on_surface: OnSurface,
}

/// The whole-body path of one segment.
#[derive(Debug, Clone, PartialEq)]
pub struct SegmentPath {
    /// The contacts.
    pub contacts: Vec<PlacedContact>,
    /// The references tracked.
    pub references: SegmentReferences,
    /// IK samples (all of them when the IK succeeded; up to the failing step otherwise).
    pub samples: Vec<IkSample>,
    /// `None` when every step solved, else the failing step and its status.
    pub failure: Option<(usize, IkStatus)>,
    /// Largest distance of the CoM from its reference at the samples (m).
    pub max_com_error: f64,
    /// Largest displacement of a contact frame from its placement (m).
    pub max_contact_drift: f64,
    /// Largest rotation of a contact frame from its placement (rad).
    pub max_contact_rotation: f64,
    /// Largest joint-limit violation at the samples (rad or m; 0 within the limits).
    pub max_joint_violation: f64,
    /// Steps answered by the Clarabel fallback rather than the dense solver.
    pub fallbacks: usize,
    /// Steps whose clearance rows made the QP infeasible, solved without them (a hard task, a
    /// landing link's path, drives a body into a solid: the collision check reports it).
    pub clearance_dropped: usize,
    /// Wall time of the IK (the paper's `T_IK`).
    pub elapsed: Duration,
}

/// Reusable buffers of the IK stage.
#[derive(Debug, Clone)]
pub struct IkStageWorkspace {
    ik: IkWorkspace,
    data: Data,
    jac: Matrix6xX<f64>,
}

impl IkStageWorkspace {
    /// Buffers for the plan's robot.
    pub fn new(plan: &MotionPlan) -> Self {
        let m = &plan.robot.model;
        Self {
            ik: IkWorkspace::new(m),
            data: Data::new(m),
            jac: Matrix6xX::zeros(m.nv),
        }
    }
}

/// The linear and angular path velocity `J q_s` of a frame (world axes, at its origin).
pub fn frame_path_velocity(
    plan: &MotionPlan,
    ws: &mut IkStageWorkspace,
    q: &[f64],
    q_s: &[f64],
    frame: usize,
) -> Result<(Vector3<f64>, Vector3<f64>), StanceError> {
    let m = &plan.robot.model;
    forward_kinematics(m, &mut ws.data, q).map_err(StanceError::Robot)?;
    frame_jacobian(
        m,
        &ws.data,
        frame,
        ReferenceFrame::LocalWorldAligned,
        &mut ws.jac,
    )
    .map_err(StanceError::Robot)?;
    let mut out = [0.0; 6];
    for (r, o) in out.iter_mut().enumerate() {
        *o = (0..m.nv).map(|k| ws.jac[(r, k)] * q_s[k]).sum();
    }
    Ok((
        Vector3::new(out[0], out[1], out[2]),
        Vector3::new(out[3], out[4], out[5]),
    ))
}

/// The placement of a contact of segment `k` from the robot surface's placement `actual`: the
/// placement it had in the previous segment when it was a contact there already (a contact does
/// not move while it is held); else the target of the previous segment's `onto` move of that
/// surface onto that environment surface when the robot is within the contact tolerances of it
/// (the intended geometry: two feet landed parallel stay parallel); else `actual` snapped onto
/// the surface.
fn contact_pose(
    plan: &MotionPlan,
    k: usize,
    previous: &[PlacedContact],
    surface: usize,
    env: usize,
    actual: &Pose,
) -> Pose {
    if let Some(c) = previous
        .iter()
        .find(|c| c.surface == surface && c.environment == env)
    {
        return c.pose;
    }
    let landed = k.checked_sub(1).and_then(|prev| {
        plan.segments[prev]
            .moves
            .iter()
            .flat_map(|m| &m.links)
            .rfind(|l| l.surface == surface)
            .and_then(|l| match l.goal {
                LinkGoal::Onto { surface: e, pose } if e == env => Some(pose),
                _ => None,
            })
    });
    if let Some(target) = landed {
        let dp = (target.translation - actual.translation).norm();
        let dr =
            stance_robot::spatial::rotation_log(&(target.rotation * actual.rotation.transpose()))
                .norm();
        if dp <= crate::tol::CONTACT_DISTANCE && dr <= crate::tol::CONTACT_ANGLE {
            return target;
        }
    }
    plan.environment[env].snap(actual)
}

/// The CoM reference of the whole motion: via-points from the CoM of the initial posture and
/// the moves' targets, at the moves' boundaries ([`super::references`]).
pub fn com_reference(plan: &MotionPlan) -> Result<ComReference, StanceError> {
    let m = &plan.robot.model;
    let c0 = center_of_mass(m, &mut Data::new(m), &plan.q0).map_err(StanceError::Robot)?;
    let mut knots = vec![0.0];
    let mut points = vec![c0];
    // at a stance switch, the CoM turns in the stance with more contacts (module doc of
    // `references`)
    let mut turns = vec![None];
    for (k, seg) in plan.segments.iter().enumerate() {
        for (j, mv) in seg.moves.iter().enumerate() {
            let last = points[points.len() - 1];
            points.push(match &mv.com {
                None => last,
                Some(ComTarget::By(v)) => last + Vector3::from(*v),
                Some(ComTarget::To(v)) => Vector3::from(*v),
            });
            knots.push(knots[knots.len() - 1] + mv.duration);
            let switch = j + 1 == seg.moves.len();
            turns.push(plan.segments.get(k + 1).filter(|_| switch).map(|next| {
                if next.stance.len() >= seg.stance.len() {
                    CornerKernel::After
                } else {
                    CornerKernel::Before
                }
            }));
        }
    }
    ComReference::new(knots, points, plan.com_blend, &turns)
}

/// The IK of segment `k` (starting at the global path parameter `s_offset`) from `(q, q_s)`, on
/// `n` steps. `previous` are the contacts of the segment before (a surface that stays in
/// contact keeps its placement; one that leaves is held where it is until moved).
///
/// # Errors
///
/// [`StanceError::BadMotion`] when a contact of the stance is not on its environment surface at
/// the segment's start (what to fix: the previous segment's moves).
#[allow(clippy::too_many_arguments)]
pub fn run_segment(
    plan: &MotionPlan,
    k: usize,
    com: &ComReference,
    s_offset: f64,
    q: &[f64],
    q_s: &[f64],
    previous: &[PlacedContact],
    n: usize,
    ws: &mut IkStageWorkspace,
) -> Result<SegmentPath, StanceError> {
    let t0 = Instant::now();
    let m = &plan.robot.model;
    forward_kinematics(m, &mut ws.data, q).map_err(StanceError::Robot)?;
    let contacts = placed_contacts(plan, k, previous, &ws.data)?;
    let references = segment_references(plan, k, com, s_offset, previous, &ws.data, q_s)?;
    let options = ik_options(plan, k);
    let holds: Vec<ContactHold> = contacts
        .iter()
        .map(|c| ContactHold {
            frame: plan.robot.surfaces[c.surface].frame,
            target: Some(c.pose),
        })
        .collect();
    let length = references.length();
    let mut out = SegmentPath {
        contacts,
        references,
        samples: Vec::with_capacity(n + 1),
        failure: None,
        max_com_error: 0.0,
        max_contact_drift: 0.0,
        max_contact_rotation: 0.0,
        max_joint_violation: 0.0,
        fallbacks: 0,
        clearance_dropped: 0,
        elapsed: Duration::ZERO,
    };
    let mut watch = ClearanceWatch::new(plan, &out);
    let mut distances = Vec::new();
    let (mut q, mut q_s) = (q.to_vec(), q_s.to_vec());
    let ds = length / n as f64;
    let (mut soft, mut hard) = (Vec::new(), Vec::new());
    let (mut soft_mid, mut hard_mid) = (Vec::new(), Vec::new());
    for i in 0..=n {
        let s = if i == n { length } else { i as f64 * ds };
        // The step's q_ss is held constant over [s, s + ds]: its feedforward is the references'
        // second derivative at the middle of the step (second-order accurate, where the value at
        // its start lags by ds / 2: measured, it halves the landing residuals of first order).
        let mid = (s + 0.5 * ds).min(length);
        out.references.links_at(s, &mut soft, &mut hard);
        out.references.links_at(mid, &mut soft_mid, &mut hard_mid);
        for (t, m) in soft
            .iter_mut()
            .zip(&soft_mid)
            .chain(hard.iter_mut().zip(&hard_mid))
        {
            t.reference.p_ss = m.reference.p_ss;
            if let (Some(o), Some(om)) = (&mut t.orientation, &m.orientation) {
                o.w_ss = om.w_ss;
            }
        }
        let mut com = out.references.com_at(s);
        com.p_ss = out.references.com_at(mid).p_ss;
        watch.rows(plan, &mut ws.data, &q, &mut distances)?;
        let tasks = IkTasks {
            contacts: &holds,
            com,
            links: &soft,
            hard_links: &hard,
            posture: Some(&plan.robot.posture),
            distances: &distances,
        };
        let step = ws
            .ik
            .step(m, &mut ws.data, &q, &q_s, &tasks, ds, &options)
            .map_err(StanceError::Robot)?;
        // certificates at this sample (data holds the kinematics of q)
        out.max_com_error = out.max_com_error.max((ws.data.com - tasks.com.p).norm());
        for (h, c) in holds.iter().zip(&out.contacts) {
            let x = frame_placement(m, &ws.data, h.frame).map_err(StanceError::Robot)?;
            out.max_contact_drift = out
                .max_contact_drift
                .max((x.translation - c.pose.translation).norm());
            let r = c.pose.rotation.transpose() * x.rotation;
            let angle = ((r.trace() - 1.0) / 2.0).clamp(-1.0, 1.0).acos();
            out.max_contact_rotation = out.max_contact_rotation.max(angle);
        }
        for j in &m.joints[2..] {
            if j.dims() == (1, 1) {
                let v = (j.lower - q[j.idx_q]).max(q[j.idx_q] - j.upper);
                out.max_joint_violation = out.max_joint_violation.max(v);
            }
        }
        if step.status != IkStatus::Solved {
            out.failure = Some((i, step.status));
            break;
        }
        if step.answer_from == IkAnswerFrom::Clarabel {
            out.fallbacks += 1;
        }
        if step.clearance_dropped {
            out.clearance_dropped += 1;
        }
        let terms = path_terms_from_data(&ws.data, &q_s, &step.q_ss);
        let terms_left = match out.samples.last() {
            Some(prev) => path_terms_from_data(&ws.data, &q_s, &prev.q_ss),
            None => terms,
        };
        out.samples.push(IkSample {
            s,
            q: q.clone(),
            q_s: q_s.clone(),
            q_ss: step.q_ss.clone(),
            terms,
            terms_left,
        });
        if i < n {
            let delta: Vec<f64> = q_s
                .iter()
                .zip(&step.q_ss)
                .map(|(v, a)| v * ds + 0.5 * a * ds * ds)
                .collect();
            q = integrate(m, &q, &delta).map_err(StanceError::Robot)?;
            for (v, a) in q_s.iter_mut().zip(&step.q_ss) {
                *v += a * ds;
            }
        }
    }
    out.elapsed = t0.elapsed();
    Ok(out)
}

/// The clearances of one segment's IK ([`super::collision`]): which robot bodies keep their
/// distance from which solids, and how much.
struct ClearanceWatch {
    /// Watched bodies (indices in the collision model): every capsule, and the boxes of the
    /// surfaces neither held nor landing in the segment (a landing link's path is a hard task).
    bodies: Vec<usize>,
    clearance: f64,
}

impl ClearanceWatch {
    fn new(plan: &MotionPlan, path: &SegmentPath) -> Self {
        use super::collision::BodyKind;
        let landing: Vec<usize> = path
            .references
            .links
            .iter()
            .filter(|l| l.legs.iter().any(|leg| leg.landing))
            .map(|l| l.surface)
            .collect();
        let held: Vec<usize> = path.contacts.iter().map(|c| c.surface).collect();
        let bodies = plan
            .collision
            .bodies
            .iter()
            .enumerate()
            .filter(|(_, b)| match b.kind {
                BodyKind::Bone { .. } => true,
                BodyKind::Surface { surface } => {
                    !held.contains(&surface) && !landing.contains(&surface)
                }
            })
            .map(|(i, _)| i)
            .collect();
        Self {
            bodies,
            clearance: plan.spec.ik.clearance,
        }
    }

    /// The distance rows at `q` into `out` (kinematics of `q` left in `data`).
    fn rows(
        &mut self,
        plan: &MotionPlan,
        data: &mut Data,
        q: &[f64],
        out: &mut Vec<DistanceBound>,
    ) -> Result<(), StanceError> {
        out.clear();
        if self.bodies.is_empty() {
            return Ok(());
        }
        let c = &plan.collision;
        forward_kinematics(&plan.robot.model, data, q).map_err(StanceError::Robot)?;
        let range = self.clearance + crate::tol::CLEARANCE_WATCH;
        for &b in &self.bodies {
            c.distances(data, b, range, |_, d| {
                out.push(DistanceBound {
                    joint: c.bodies[b].joint,
                    point: d.point,
                    normal: d.normal,
                    distance: d.distance,
                    min_distance: self.clearance,
                })
            });
        }
        Ok(())
    }
}

/// The pose (world) of robot surface `r` in the configuration whose kinematics `data` holds.
fn surface_pose(plan: &MotionPlan, data: &Data, r: usize) -> Result<Pose, StanceError> {
    frame_placement(&plan.robot.model, data, plan.robot.surfaces[r].frame)
        .map_err(StanceError::Robot)
}

/// The contacts of segment `k`'s stance, read off the start configuration (kinematics in
/// `data`) and checked against their environment surfaces.
fn placed_contacts(
    plan: &MotionPlan,
    k: usize,
    previous: &[PlacedContact],
    data: &Data,
) -> Result<Vec<PlacedContact>, StanceError> {
    let seg = &plan.segments[k];
    let what = crate::plan::segment_label(k, &seg.name);
    let mut contacts = Vec::new();
    for &(r, e) in &seg.stance {
        let pose = surface_pose(plan, data, r)?;
        let surf = &plan.robot.surfaces[r];
        let poly = polygon_of(&surf.shape, &surf.name, true)?;
        let on = plan.environment[e].check(&pose, &poly);
        if !on.holds() {
            let env = &plan.environment[e].name;
            let fix = crate::environment::landing_fix(k, env);
            return Err(StanceError::BadMotion(format!(
                "{what}: {:?} is not on {env:?} at the segment's start ({}): {fix}",
                surf.name,
                crate::environment::describe(&on),
            )));
        }
        contacts.push(PlacedContact {
            surface: r,
            environment: e,
            pose: contact_pose(plan, k, previous, r, e, &pose),
            on_surface: on,
        });
    }
    Ok(contacts)
}

/// The path rate `J q_s` (linear, angular; world axes) of robot surface `r` in the
/// configuration whose kinematics `data` holds.
fn path_rate(
    plan: &MotionPlan,
    data: &Data,
    q_s: &[f64],
    r: usize,
) -> Result<[Vector3<f64>; 2], StanceError> {
    let m = &plan.robot.model;
    let mut jac = Matrix6xX::zeros(m.nv);
    frame_jacobian(
        m,
        data,
        plan.robot.surfaces[r].frame,
        ReferenceFrame::LocalWorldAligned,
        &mut jac,
    )
    .map_err(StanceError::Robot)?;
    let v = &jac * nalgebra::DVector::from_column_slice(q_s);
    Ok([
        Vector3::new(v[0], v[1], v[2]),
        Vector3::new(v[3], v[4], v[5]),
    ])
}

/// The references of segment `k`: its knots (one per move), the CoM reference, and the legs of
/// every free link (links that left contact are held where they are until moved).
fn segment_references(
    plan: &MotionPlan,
    k: usize,
    com: &ComReference,
    s_offset: f64,
    previous: &[PlacedContact],
    data: &Data,
    q_s: &[f64],
) -> Result<SegmentReferences, StanceError> {
    let seg = &plan.segments[k];
    let mut knots = vec![0.0];
    let mut links: Vec<LinkPlan> = Vec::new();
    let in_stance = |r: usize| seg.stance.iter().any(|&(x, _)| x == r);
    for r in previous
        .iter()
        .map(|c| c.surface)
        .filter(|&r| !in_stance(r))
    {
        let start = surface_pose(plan, data, r)?;
        links.push(LinkPlan {
            surface: r,
            frame: plan.robot.surfaces[r].frame,
            start,
            start_rate: path_rate(plan, data, q_s, r)?,
            legs: Vec::new(),
        });
    }
    for mv in &seg.moves {
        let s0 = knots[knots.len() - 1];
        let s1 = s0 + mv.duration;
        knots.push(s1);
        for lm in &mv.links {
            let idx = match links.iter().position(|l| l.surface == lm.surface) {
                Some(i) => i,
                None => {
                    let start = surface_pose(plan, data, lm.surface)?;
                    links.push(LinkPlan {
                        surface: lm.surface,
                        frame: plan.robot.surfaces[lm.surface].frame,
                        start,
                        start_rate: path_rate(plan, data, q_s, lm.surface)?,
                        legs: Vec::new(),
                    });
                    links.len() - 1
                }
            };
            let plan_l = &mut links[idx];
            let from = plan_l.legs.last().map_or(plan_l.start, |l| l.to);
            let to = lm.goal.after(&from);
            plan_l.legs.push(LinkLeg {
                s: [s0, s1],
                from,
                to,
                landing: matches!(lm.goal, LinkGoal::Onto { .. }),
            });
        }
    }
    Ok(SegmentReferences {
        knots,
        s_offset,
        com: com.clone(),
        links,
    })
}

/// The IK's weights and gains for segment `k` (its own link weight and gain, the motion's
/// others; the paper's damper on the joint limits).
fn ik_options(plan: &MotionPlan, k: usize) -> IkOptions {
    let seg = &plan.segments[k];
    let ik = &plan.spec.ik;
    IkOptions {
        w_com: ik.w_com,
        w_link: seg.w_link,
        w_posture: ik.w_posture,
        k_p: seg.gain,
        k_d: seg.gain,
        gamma: ik.contact_gain,
        contact_k_p: ik.contact_gain,
        joint_bounds: JointBounds::Damper {
            k_s: 10.0,
            k_ss: 10.0,
            range: ik.joint_range,
        },
        ..Default::default()
    }
}

#[cfg(test)]
mod doc_examples {
    //! The examples that were in the docs of this private module.

    #[test]
    fn new_example() {
        use crate::{experiments, ik_stage::IkStageWorkspace, plan::MotionPlan};
        let plan = MotionPlan::new(experiments::by_name("small-sway").unwrap(), None).unwrap();
        let ws = IkStageWorkspace::new(&plan);
        let _ = ws;
    }

    #[test]
    fn frame_path_velocity_example() {
        use crate::{
            experiments,
            ik_stage::{frame_path_velocity, IkStageWorkspace},
            plan::MotionPlan,
        };
        let plan = MotionPlan::new(experiments::by_name("small-sway").unwrap(), None).unwrap();
        let mut ws = IkStageWorkspace::new(&plan);
        let m = &plan.robot.model;
        let (v, w) = frame_path_velocity(&plan, &mut ws, &plan.q0, &vec![0.0; m.nv], 1).unwrap();
        assert_eq!((v.norm(), w.norm()), (0.0, 0.0));
    }

    #[test]
    fn com_reference_example() {
        use crate::{experiments, ik_stage::com_reference, plan::MotionPlan};
        let plan = MotionPlan::new(experiments::by_name("small-sway").unwrap(), None).unwrap();
        let c = com_reference(&plan).unwrap();
        assert_eq!(
            c.points.len(),
            1 + plan.segments.iter().map(|s| s.moves.len()).sum::<usize>()
        );
    }
}
