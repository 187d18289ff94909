//! What the planner computes once per motion: where every link and contact is at the start of
//! each segment (following the hand-written moves and the landings), the static-equilibrium
//! polygons of the stances, the switch regions, and the swing paths.

use nalgebra::Vector3;
use stance_robot::{center_of_mass, forward_kinematics, frame_placement, Data, Pose};

use super::regions::{self, Halfplanes};
use super::swing::{self, SwingProblem};
use super::{planned_segments, segment_name, stance_names};
use crate::plan::{LinkGoal, MotionPlan};
use crate::spec::{LinkMoveSpec, MotionSpec, MoveSpec};
use crate::StanceError;

/// Where every robot surface is at the start of each segment, and which contacts hold.
struct Walk {
    /// Per segment: the pose of every robot surface at its start.
    starts: Vec<Vec<Pose>>,
    /// Per segment: the environment surface each robot surface rests on at its start.
    resting: Vec<Vec<Option<usize>>>,
    /// Per segment: its stance as `(robot surface, environment surface, pose)`.
    stances: Vec<Vec<(usize, usize, Pose)>>,
}

/// Follows the link goals of every segment (as the IK's references do) from the initial
/// posture.
fn walk(plan: &MotionPlan, data: &Data) -> Result<Walk, StanceError> {
    let m = &plan.robot.model;
    let mut pose: Vec<Pose> = plan
        .robot
        .surfaces
        .iter()
        .map(|s| frame_placement(m, data, s.frame).map_err(StanceError::Robot))
        .collect::<Result<_, _>>()?;
    let mut resting: Vec<Option<usize>> = pose
        .iter()
        .enumerate()
        .map(|(r, p)| {
            let surf = &plan.robot.surfaces[r];
            let poly = crate::environment::polygon_of(&surf.shape, &surf.name, true).ok()?;
            plan.environment
                .iter()
                .position(|e| e.check(p, &poly).holds())
        })
        .collect();
    let mut out = Walk {
        starts: Vec::new(),
        resting: Vec::new(),
        stances: Vec::new(),
    };
    for (k, seg) in plan.segments.iter().enumerate() {
        let mut stance = Vec::new();
        for &(r, e) in &seg.stance {
            if resting[r] != Some(e) {
                // checked where the walk put it (as the IK stage checks the pose it reached),
                // then snapped onto the surface
                let surf = &plan.robot.surfaces[r];
                let poly = crate::environment::polygon_of(&surf.shape, &surf.name, true)?;
                let on = plan.environment[e].check(&pose[r], &poly);
                if !on.holds() {
                    let env = &plan.environment[e].name;
                    let fix = crate::environment::landing_fix(k, env);
                    return Err(StanceError::BadMotion(format!(
                        "{}: {:?} is not on {env:?} where the segment starts ({}); {fix}",
                        crate::plan::segment_label(k, &seg.name),
                        surf.name,
                        crate::environment::describe(&on),
                    )));
                }
                pose[r] = plan.environment[e].snap(&pose[r]);
                resting[r] = Some(e);
            }
            stance.push((r, e, pose[r]));
        }
        out.starts.push(pose.clone());
        out.resting.push(resting.clone());
        out.stances.push(stance);
        for mv in &seg.moves {
            for l in &mv.links {
                pose[l.surface] = l.goal.after(&pose[l.surface]);
                resting[l.surface] = match &l.goal {
                    LinkGoal::Onto { surface, .. } => Some(*surface),
                    _ => None,
                };
            }
        }
    }
    Ok(out)
}

/// A planned segment's end, before the margin fraction is chosen.
#[derive(Debug, Clone)]
pub struct Switch {
    /// The half-planes of the segment's own stance's static-equilibrium polygon.
    pub own: Halfplanes,
    /// The half-planes of the region where the CoM ends (two stances' polygons, or one).
    pub halfplanes: Halfplanes,
    /// The point of largest margin there, and that margin (m; negative: a gap).
    pub centre: ([f64; 2], f64),
    /// Where the CoM would be nearest the feet (m).
    pub nominal: [f64; 2],
    /// CoM height at the end (m).
    pub z: f64,
    /// The swing's via-points (empty: no landing).
    pub swing: Vec<LinkMoveSpec>,
    /// The landing link.
    pub landing: Option<String>,
    /// Length of each move (path units).
    pub duration: f64,
}

/// Everything the assembly of a plan needs (module doc).
#[derive(Debug, Clone)]
pub struct Geometry {
    /// The file as written.
    pub spec: MotionSpec,
    /// The CoM of the initial posture (m).
    pub c0: Vector3<f64>,
    /// Per segment: its switch when planned.
    pub switches: Vec<Option<Switch>>,
}

impl Geometry {
    /// Validates `spec` (planned segments get a placeholder move) and computes its geometry.
    pub fn new(spec: &MotionSpec, base_dir: Option<&std::path::Path>) -> Result<Self, StanceError> {
        let mut skeleton = spec.clone();
        for s in skeleton.segments.iter_mut().filter(|s| s.moves.is_empty()) {
            s.moves.push(MoveSpec {
                duration: 2.0,
                com: None,
                links: Vec::new(),
            });
        }
        let base = MotionPlan::new(skeleton, base_dir)?;
        let m = &base.robot.model;
        let mut data = Data::new(m);
        forward_kinematics(m, &mut data, &base.q0).map_err(StanceError::Robot)?;
        let c0 = center_of_mass(m, &mut Data::new(m), &base.q0).map_err(StanceError::Robot)?;
        let walked = walk(&base, &data)?;
        let p = &spec.planning;
        let regions = walked
            .stances
            .iter()
            .enumerate()
            .map(|(k, st)| {
                let stance = crate::rows::stance_from(
                    &base,
                    st,
                    p.area_scale.sqrt(),
                    p.friction,
                    p.friction_cone,
                )?;
                regions::static_halfplanes(&stance, base.gravity, &segment_name(&base, k))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let feet: Vec<usize> = base.segments[0].stance.iter().map(|&(r, _)| r).collect();
        let h0 = c0.z - mean_height(&walked.stances[0]);
        let planned = planned_segments(spec);
        let switches = (0..base.segments.len())
            .map(|k| {
                planned[k]
                    .then(|| switch(&base, spec, &walked, &regions, &feet, h0, k))
                    .transpose()
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self {
            spec: spec.clone(),
            c0,
            switches,
        })
    }
}

/// The switch at the end of planned segment `k` (module doc of [`super`]).
fn switch(
    base: &MotionPlan,
    spec: &MotionSpec,
    walked: &Walk,
    regions: &[Halfplanes],
    feet: &[usize],
    h0: f64,
    k: usize,
) -> Result<Switch, StanceError> {
    let what = segment_name(base, k);
    let next = walked.stances.get(k + 1);
    let mut h = regions[k].clone();
    if let Some(r) = regions.get(k + 1) {
        h.extend(r.iter().cloned());
    }
    let centre = regions::largest_margin(&h).ok_or_else(|| {
        StanceError::BadMotion(format!(
            "{what}: the static-equilibrium regions of its stance and the next are unbounded; \
             the planner needs bounded ones (contacts whose friction cones do not contain the \
             vertical's opposite)"
        ))
    })?;
    if centre.1 < -0.5 * crate::tol::MAX_CROSSING_GAP {
        return Err(StanceError::BadMotion(format!(
            "{what}: no CoM path can make its end: the CoM must go from where {} can hold it to \
             where {} can, {:.2} m apart, with no stance holding it in between (the planner \
             crosses gaps of at most {} m with momentum); add a stance in between (e.g. both \
             feet down) or move the landing closer",
            stance_names(base, k),
            next.map_or("the next stance".into(), |_| stance_names(base, k + 1)),
            -2.0 * centre.1,
            crate::tol::MAX_CROSSING_GAP
        )));
    }
    let mut support = walked.stances[k].clone();
    if let Some(n) = next {
        support.extend(n.iter().cloned());
    }
    let low = support
        .iter()
        .filter(|(r, _, _)| feet.contains(r))
        .map(|(_, _, p)| p.translation.z)
        .fold(f64::INFINITY, f64::min);
    let z = h0
        + if low.is_finite() {
            low
        } else {
            mean_height(&support)
        };
    let written = &spec.segments[k].moves;
    let landings: Vec<&LinkMoveSpec> = written.iter().flat_map(|m| &m.links).collect();
    let swing = match landings.as_slice() {
        [] => Vec::new(),
        [l] => {
            let r = base
                .robot
                .surfaces
                .iter()
                .position(|s| s.name == l.surface)
                .unwrap_or(0);
            let LinkGoal::Onto { pose: target, .. } = base.segments[k].moves[0].links[0].goal
            else {
                unreachable!("a planned segment's moves are landings")
            };
            let problem = SwingProblem {
                surface_name: &l.surface,
                surface: r,
                start: walked.starts[k][r],
                from_contact: walked.resting[k][r].is_some(),
                target,
                landing: (*l).clone(),
                clearance: spec.planning.swing.clearance,
            };
            swing::plan_swing(&problem, &base.collision, &what)?
        }
        _ => {
            return Err(StanceError::BadMotion(format!(
                "{what}: the planner lands one link per segment and this one lands {}; give \
                 each landing its own segment, or write the moves by hand",
                landings.len()
            )))
        }
    };
    Ok(Switch {
        own: regions[k].clone(),
        halfplanes: h,
        centre,
        nominal: feet_centre(&support, feet),
        z,
        swing,
        landing: landings.first().map(|l| l.surface.clone()),
        duration: written.first().map_or(2.0, |m| m.duration),
    })
}

/// The mean `(x, y)` of the feet in `st` (of all its contacts when no foot is there).
fn feet_centre(st: &[(usize, usize, Pose)], feet: &[usize]) -> [f64; 2] {
    let on_feet: Vec<_> = st.iter().filter(|(r, _, _)| feet.contains(r)).collect();
    let pts = if on_feet.is_empty() {
        st.iter().collect()
    } else {
        on_feet
    };
    let n = pts.len().max(1) as f64;
    [
        pts.iter().map(|(_, _, p)| p.translation.x).sum::<f64>() / n,
        pts.iter().map(|(_, _, p)| p.translation.y).sum::<f64>() / n,
    ]
}

fn mean_height(st: &[(usize, usize, Pose)]) -> f64 {
    st.iter().map(|(_, _, p)| p.translation.z).sum::<f64>() / st.len().max(1) as f64
}
