//! The view of a motion: environment, stances, robot playback, phase plane and table, from
//! the motion's result (as computed, or as read back from `stance motion`'s JSON output).

use std::path::Path;

use serde::Deserialize;
use stance_contact::equilibrium::{EquilibriumOptions, PolygonWorkspace};
use stance_contact::{Contact, FrictionModel, Shape, Stance};
use stance_robot::{center_of_mass, Data, Model, UrdfOptions};

use crate::forces::forces_view;
use crate::look::{pose7, robot_look, RobotLook};

use super::{
    round, round3, scale_of, ContactView, PhaseView, PolygonView, RobotView, StanceView,
    SurfaceView, TableView, ViewData, MAX_FRAME_RATE,
};
use stance_motion::result::{
    EnvironmentInfo, MotionResult, MotionStatus, PhaseInfo, RobotInfo, SegmentInfo, TrajectoryInfo,
};
use stance_motion::robot::{bones, MotionRobot};
use stance_motion::spec::RobotRef;
use stance_motion::StanceError;

/// Capsule radius of the drawn links (m): the simulator's default.
const LINK_RADIUS: f64 = 0.03;

/// What the view needs of a motion's result: the fields of [`MotionResult`] it draws, read
/// from `stance motion`'s JSON output (other fields are ignored).
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct MotionRecord {
    /// Name.
    pub name: String,
    /// Outcome.
    pub status: MotionStatus,
    /// Duration (s).
    pub duration: Option<f64>,
    /// The robot.
    pub robot: RobotInfo,
    /// Gravity.
    pub gravity: [f64; 3],
    /// Environment surfaces.
    pub environment: Vec<EnvironmentInfo>,
    /// Friction cone of the contacts.
    pub friction_cone: FrictionModel,
    /// Segments.
    pub segments: Vec<SegmentInfo>,
    /// Phase plane.
    pub phase: Option<PhaseInfo>,
    /// Trajectory.
    pub trajectory: Option<TrajectoryInfo>,
}

impl From<&MotionResult> for MotionRecord {
    fn from(r: &MotionResult) -> Self {
        Self {
            name: r.name.clone(),
            status: r.status.clone(),
            duration: r.duration,
            robot: r.robot.clone(),
            gravity: r.gravity,
            environment: r.environment.clone(),
            friction_cone: r.friction_cone,
            segments: r.segments.clone(),
            phase: r.phase.clone(),
            trajectory: r.trajectory.clone(),
        }
    }
}

impl MotionRecord {
    /// The robot's model, loaded again from what the result names (a built-in robot, or its
    /// URDF file with the same locked joints).
    ///
    /// # Errors
    ///
    /// The URDF is gone or changed (its joint count differs from the result's).
    pub fn load_model(&self) -> Result<Model, StanceError> {
        let r = &self.robot;
        let model = match (&r.urdf, r.name.as_str()) {
            (_, "jvrc1" | "small-humanoid") => {
                MotionRobot::load(&RobotRef::Named(r.name.clone()), None)?.model
            }
            (Some(urdf), _) => {
                let options = UrdfOptions {
                    locked: r.locked.clone(),
                    ..Default::default()
                };
                Model::from_urdf_file(Path::new(urdf), &options).map_err(StanceError::Robot)?
            }
            (None, name) => {
                return Err(StanceError::BadMotion(format!(
                    "the result's robot {name:?} is neither built in nor a URDF file"
                )))
            }
        };
        if model.nq != r.nq || model.nv != r.nv {
            return Err(StanceError::BadMotion(format!(
                "the robot {:?} now has nq = {}, nv = {}, the result was computed with nq = {}, \
                 nv = {}: run `stance motion` again",
                r.name, model.nq, model.nv, r.nq, r.nv
            )));
        }
        Ok(model)
    }
}

/// What [`motion_view`] draws besides the plan, and how a motion run for the page reports.
#[derive(Debug, Clone, Copy)]
pub struct MotionViewOptions {
    /// Read the URDF's mesh files (else primitives and capsules only: a small page).
    pub meshes: bool,
    /// Where a motion run for the page says what its long work is doing
    /// ([`stance_motion::RunOptions::progress`]); `None`: silent.
    pub progress: Option<fn(&str)>,
}

impl Default for MotionViewOptions {
    fn default() -> Self {
        Self {
            meshes: true,
            progress: None,
        }
    }
}

/// Computes what the page shows of a motion, with the robot's `model`.
///
/// # Errors
///
/// A trajectory whose configurations do not fit the model, or a contact of the result that is
/// not a valid contact.
pub fn motion_view(
    record: &MotionRecord,
    model: &Model,
    options: &MotionViewOptions,
) -> Result<ViewData, StanceError> {
    let mut notes = Vec::new();
    let look = robot_look(
        model,
        record.robot.urdf.as_deref().map(Path::new),
        options.meshes,
    )?;
    notes.extend(look.notes.iter().cloned());
    let environment: Vec<SurfaceView> = record
        .environment
        .iter()
        .map(|e| SurfaceView {
            name: e.name.clone(),
            vertices: e.vertices.iter().map(|&p| round3(p)).collect(),
        })
        .collect();
    let robot = match &record.trajectory {
        Some(tr) => Some(playback(tr, model, record, look)?),
        None => {
            notes.push("no trajectory: the motion has no retimed profile".to_string());
            None
        }
    };
    let mut stances = Vec::new();
    let mut ws = PolygonWorkspace::new();
    let segment_contacts: Vec<Vec<Contact>> = record
        .segments
        .iter()
        .map(|seg| {
            seg.contacts
                .iter()
                .map(|c| {
                    Contact::new(
                        &c.name,
                        c.position,
                        c.rotation,
                        Shape::Polygon(c.vertices.clone()),
                        c.friction,
                        &Default::default(),
                    )
                })
                .collect::<Result<_, _>>()
        })
        .collect::<Result<_, _>>()?;
    let forces = match (&robot, &record.trajectory) {
        (Some(r), Some(tr)) => Some(forces_view(
            model,
            tr,
            &r.samples,
            &segment_contacts,
            record.friction_cone,
            record.gravity,
        )?),
        _ => None,
    };
    for ((k, seg), contacts) in record.segments.iter().enumerate().zip(segment_contacts) {
        let views = contacts
            .iter()
            .map(|c| ContactView::of(c, &record.friction_cone))
            .collect();
        // The polygon at the segment's mean CoM height.
        let height = robot
            .as_ref()
            .and_then(|r| {
                let z: Vec<f64> = (0..r.t.len())
                    .filter(|&i| r.segment[i] == k)
                    .map(|i| r.com[i][2])
                    .collect();
                (!z.is_empty()).then(|| z.iter().sum::<f64>() / z.len() as f64)
            })
            .unwrap_or(0.8);
        let polygon = Stance::new(contacts, record.friction_cone)
            .map_err(StanceError::from)
            .and_then(|s| {
                ws.static_polygon(&s, record.gravity, height, &EquilibriumOptions::default())
                    .map_err(StanceError::from)
            });
        let polygon = match polygon {
            Ok(p) => Some(PolygonView::of(&p.polygon, height)),
            Err(e) => {
                notes.push(format!("segment {}: no static polygon: {e}", seg.name));
                None
            }
        };
        stances.push(StanceView {
            name: seg.name.clone(),
            t_start: seg.t_start,
            t_end: seg.t_end,
            contacts: views,
            polygon,
        });
    }
    let phase = record.phase.as_ref().and_then(|p| {
        (p.sd.len() == p.s.len()).then(|| PhaseView {
            s: p.s.clone(),
            x: p.sd.iter().map(|v| v * v).collect(),
            t: p.t.clone(),
            segment_starts: p.segment_starts.clone(),
        })
    });
    let scale = scale_of(&stances);
    let status = match record.status {
        MotionStatus::Optimal => "retimed",
        MotionStatus::IkFailed => "IK failed",
        MotionStatus::NotRetimable => "not retimable",
    };
    let subtitle = match record.duration {
        Some(d) => format!(
            "{} on {}: {status}, {} segments in {d:.3} s",
            record.name,
            record.robot.name,
            record.segments.len()
        ),
        None => format!(
            "{} on {}: {status}, {} segments",
            record.name,
            record.robot.name,
            record.segments.len()
        ),
    };
    Ok(ViewData {
        kind: "motion",
        title: record.name.clone(),
        subtitle,
        gravity: record.gravity,
        scale,
        environment,
        stances,
        region: None,
        robot,
        phase,
        forces,
        clearance: None,
        torque: None,
        simulation: None,
        table: segment_table(&record.segments),
        notes,
    })
}

fn ms(x: Option<f64>) -> String {
    x.map_or("-".to_string(), |x| format!("{x:.2}"))
}

/// The paper's table of segments.
fn segment_table(segments: &[SegmentInfo]) -> TableView {
    let opt = |x: Option<f64>| x.map_or("-".to_string(), |x| format!("{x:.3}"));
    TableView {
        columns: [
            "segment",
            "contacts",
            "t start (s)",
            "duration (s)",
            "U rows",
            "certified",
            "grid",
            "T_IK (ms)",
            "T_U (ms)",
            "T_abc (ms)",
            "T_TOPP (ms)",
        ]
        .map(String::from)
        .to_vec(),
        rows: segments
            .iter()
            .map(|s| {
                vec![
                    s.name.clone(),
                    s.contacts
                        .iter()
                        .map(|c| c.name.as_str())
                        .collect::<Vec<_>>()
                        .join(" "),
                    opt(s.t_start),
                    opt(s.duration),
                    s.u_stance_rows.to_string(),
                    if s.giwc_certified { "yes" } else { "no" }.to_string(),
                    s.grid_points.to_string(),
                    ms(Some(s.t_ik_ms)),
                    ms(Some(s.t_u_ms)),
                    ms(Some(s.t_abc_ms)),
                    ms(s.t_topp_ms),
                ]
            })
            .collect(),
    }
}

/// Frames of the playback: the trajectory's samples, thinned to at most [`MAX_FRAME_RATE`]
/// per second (the last sample always kept), with joint origins and CoM by forward kinematics.
fn playback(
    tr: &TrajectoryInfo,
    model: &Model,
    record: &MotionRecord,
    look: RobotLook,
) -> Result<RobotView, StanceError> {
    let n = tr.t.len();
    if tr.q.len() != n || tr.v.len() != n || tr.a.len() != n || tr.segment.len() != n {
        return Err(StanceError::BadMotion(format!(
            "the trajectory has {n} times but {} configurations, {} velocities, {} \
             accelerations and {} segment indices: give the complete output of `stance motion`",
            tr.q.len(),
            tr.v.len(),
            tr.a.len(),
            tr.segment.len()
        )));
    }
    let mut keep = Vec::new();
    let mut last = f64::NEG_INFINITY;
    for (i, &t) in tr.t.iter().enumerate() {
        if t - last >= 1.0 / MAX_FRAME_RATE - 1e-9 || i + 1 == n {
            keep.push(i);
            last = t;
        }
    }
    let qs: Vec<Vec<f64>> = keep.iter().map(|&i| tr.q[i].clone()).collect();
    let frames = fk_frames(model, &qs, !look.meshes.is_empty())?;
    Ok(RobotView {
        name: record.robot.name.clone(),
        radius: LINK_RADIUS,
        joints: model.joints[1..].iter().map(|j| j.name.clone()).collect(),
        bones: bones(model, LINK_RADIUS)
            .into_iter()
            .map(|b| [b.parent - 1, b.child - 1])
            .collect(),
        t: keep.iter().map(|&i| tr.t[i]).collect(),
        positions: frames.positions,
        orientations: frames.orientations,
        meshes: look.meshes,
        mesh_data: look.mesh_data,
        com: frames.com,
        // the page indexes its stances from 0; the result numbers segments from 1
        segment: keep
            .iter()
            .map(|&i| tr.segment[i].saturating_sub(1))
            .collect(),
        samples: keep,
    })
}

/// Forward kinematics of playback frames.
pub(crate) struct Frames {
    /// Per frame, the joint origins (flattened, rounded to 0.1 mm).
    pub positions: Vec<Vec<f64>>,
    /// Per frame, the joint orientations `qx, qy, qz, qw` (flattened, rounded to 1e-4; empty
    /// when `orientations` is false).
    pub orientations: Vec<Vec<f64>>,
    /// Per frame, the CoM.
    pub com: Vec<[f64; 3]>,
}

/// The joint frames and CoM of `model` at each configuration of `qs`.
pub(crate) fn fk_frames(
    model: &Model,
    qs: &[Vec<f64>],
    orientations: bool,
) -> Result<Frames, StanceError> {
    let mut data = Data::new(model);
    let joints = model.joints.len() - 1;
    let mut out = Frames {
        positions: Vec::with_capacity(qs.len()),
        orientations: Vec::with_capacity(qs.len()),
        com: Vec::with_capacity(qs.len()),
    };
    for q in qs {
        let c = center_of_mass(model, &mut data, q).map_err(StanceError::Robot)?;
        out.com.push(round3(c.into()));
        let mut p = Vec::with_capacity(3 * joints);
        let mut o = Vec::with_capacity(4 * joints);
        for j in 1..=joints {
            let pose = pose7(&data.world_from_joint[j]);
            p.extend([round(pose[0]), round(pose[1]), round(pose[2])]);
            if orientations {
                o.extend(pose[3..].iter().map(|x| (x * 1e4).round() / 1e4));
            }
        }
        out.positions.push(p);
        out.orientations.push(o);
    }
    Ok(out)
}
