//! A joint path tracked along a grid: IK steps integrated with constant `q_ss` per step (see the
//! parent module for the math).

use super::problem::{ContactHold, IkTasks, IkWorkspace};
use super::{IkOptions, IkStatus, LinkTarget, PointReference};
use crate::data::Data;
use crate::error::RobotError;
use crate::kinematics::{check_configuration, check_velocity, frame_placement, integrate};
use crate::model::Model;

/// One grid point of a tracked path.
#[derive(Debug, Clone, PartialEq)]
pub struct PathSample {
    /// Path parameter.
    pub s: f64,
    /// Configuration.
    pub q: Vec<f64>,
    /// `dq/ds` (velocity space).
    pub q_s: Vec<f64>,
    /// `d^2q/ds^2` (velocity space).
    pub q_ss: Vec<f64>,
}

/// A joint path from [`track_path`], with its certificates.
#[derive(Debug, Clone, PartialEq)]
pub struct IkPath {
    /// Outcome: `Solved` if every step was; otherwise the first failing step's status, and the
    /// samples up to it.
    pub status: IkStatus,
    /// The samples.
    pub samples: Vec<PathSample>,
    /// Largest contact-equation residual over the steps.
    pub max_contact_residual: f64,
    /// Largest displacement of a contact frame's origin from its initial position (m).
    pub max_contact_drift: f64,
    /// Largest rotation of a contact frame from its initial orientation (rad).
    pub max_contact_rotation: f64,
    /// Largest distance between the CoM and its reference at the samples (m).
    pub max_com_error: f64,
    /// Largest joint-bound violation of a QP solution.
    pub max_bound_violation: f64,
}

/// Tracks the references along the increasing grid `s` from `(q0, q_s0)` with the contact frames
/// held: `references(s)` gives the CoM reference and the link targets at `s`.
///
/// ```
/// use nalgebra::Vector3;
/// use stance_robot::{center_of_mass, track_path, Data, IkOptions, IkStatus, Model, PointReference};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let q0 = m.neutral();
/// let c0 = center_of_mass(&m, &mut Data::new(&m), &q0).unwrap();
/// let c1 = c0 + Vector3::new(0.0, 0.0, -0.02); // crouch by 2 cm
/// let feet = [m.frame_id("r_sole").unwrap(), m.frame_id("l_sole").unwrap()];
/// let grid: Vec<f64> = (0..=20).map(|i| i as f64 / 20.0).collect();
/// let path = track_path(&m, &q0, &vec![0.0; m.nv], &feet, &grid,
///     &|s| (PointReference::segment(c0, c1, s), vec![]), &IkOptions::default()).unwrap();
/// assert_eq!(path.status, IkStatus::Solved);
/// assert!(path.max_contact_drift < 1e-3);
/// ```
#[allow(clippy::type_complexity)]
pub fn track_path(
    model: &Model,
    q0: &[f64],
    q_s0: &[f64],
    contacts: &[usize],
    grid: &[f64],
    references: &dyn Fn(f64) -> (PointReference, Vec<LinkTarget>),
    options: &IkOptions,
) -> Result<IkPath, RobotError> {
    check_configuration(model, q0)?;
    check_velocity(model, q_s0)?;
    if grid.len() < 2
        || grid.iter().any(|s| !s.is_finite())
        || grid.windows(2).any(|w| w[1] <= w[0])
    {
        return Err(RobotError::InvalidOption {
            name: "grid",
            reason: "give at least 2 finite, strictly increasing path parameters".into(),
        });
    }
    let mut data = Data::new(model);
    let mut ws = IkWorkspace::new(model);
    crate::kinematics::forward_kinematics(model, &mut data, q0)?;
    let mut initial = Vec::with_capacity(contacts.len());
    let mut holds = Vec::with_capacity(contacts.len());
    for &f in contacts {
        let x = frame_placement(model, &data, f)?;
        initial.push(x);
        holds.push(ContactHold {
            frame: f,
            target: Some(x),
        });
    }
    let mut out = IkPath {
        status: IkStatus::Solved,
        samples: Vec::with_capacity(grid.len()),
        max_contact_residual: 0.0,
        max_contact_drift: 0.0,
        max_contact_rotation: 0.0,
        max_com_error: 0.0,
        max_bound_violation: 0.0,
    };
    let (mut q, mut q_s) = (q0.to_vec(), q_s0.to_vec());
    for (i, &s) in grid.iter().enumerate() {
        let ds = if i + 1 < grid.len() {
            grid[i + 1] - s
        } else {
            s - grid[i - 1]
        };
        let (com_ref, links) = references(s);
        let tasks = IkTasks {
            contacts: &holds,
            com: com_ref,
            links: &links,
            hard_links: &[],
            posture: None,
            distances: &[],
        };
        let step = ws.step(model, &mut data, &q, &q_s, &tasks, ds, options)?;
        // certificates at this sample (data holds the kinematics of q)
        out.max_com_error = out.max_com_error.max((data.com - com_ref.p).norm());
        for (f, x0) in contacts.iter().zip(&initial) {
            let x = frame_placement(model, &data, *f)?;
            out.max_contact_drift = out
                .max_contact_drift
                .max((x.translation - x0.translation).norm());
            let r = x0.rotation.transpose() * x.rotation;
            let angle = ((r.trace() - 1.0) / 2.0).clamp(-1.0, 1.0).acos();
            out.max_contact_rotation = out.max_contact_rotation.max(angle);
        }
        if step.status != IkStatus::Solved {
            out.status = step.status;
            return Ok(out);
        }
        out.max_contact_residual = out.max_contact_residual.max(step.contact_residual);
        out.max_bound_violation = out.max_bound_violation.max(step.bound_violation);
        out.samples.push(PathSample {
            s,
            q: q.clone(),
            q_s: q_s.clone(),
            q_ss: step.q_ss.clone(),
        });
        if i + 1 < grid.len() {
            let delta: Vec<f64> = q_s
                .iter()
                .zip(&step.q_ss)
                .map(|(v, a)| v * ds + 0.5 * a * ds * ds)
                .collect();
            q = integrate(model, &q, &delta)?;
            for (v, a) in q_s.iter_mut().zip(&step.q_ss) {
                *v += a * ds;
            }
        }
    }
    Ok(out)
}
