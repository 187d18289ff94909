//! The footholds planner: a motion written as where the robot touches, one stance after
//! another, becomes a complete motion file with CoM via-points and swing paths.
//!
//! # What is planned
//!
//! A segment is *planned* when it gives no `moves`, or a single move of landings only (links
//! with `onto`, no `com`): `{ stance = { RF = "floor" }, moves = [{ links = [{ surface = "LF",
//! onto = "step", at = [0, 0.1] }] }] }`, unless the file positioned the landing link itself
//! since it last touched a surface (then the landing is the straight one it wrote; give a
//! `com`, e.g. `com = { by = [0, 0, 0] }`, to keep any segment as written). Every other segment
//! is hand-written and kept as it is; the two mix freely (the planner follows the hand-written
//! CoM via-points and link moves to know where everything is when a planned segment starts).
//!
//! # Method
//!
//! The CoM is planned at the stance switches, where the retiming is tightest. Segment `k` holds
//! stance `S_k`; its CoM path goes in a straight line (through its moves, proportionally) from
//! where the previous segment left it to the switch point `p_k`:
//!
//! - horizontally, in the intersection of the static-equilibrium polygons of `S_k` and
//!   `S_{k+1}` (of `S_k` alone for the last segment), computed with the planning friction, area
//!   scale and friction cone, where the CoM can stop on either side of the switch (Bretl and
//!   Lall 2008 for the polygons): the point nearest the feet with at least a fraction `alpha` of
//!   the largest margin the intersection has (its Chebyshev centre's, [`regions`]). Since the
//!   polygons are convex and `p_{k-1}` and `p_k` both lie in `S_k`'s, the whole straight path of
//!   segment `k` holds at rest. A small `alpha` shortens the CoM's path, a large one leaves the
//!   swings room to accelerate the swinging leg; `alpha` is chosen by the retimed duration
//!   itself (`search`: the pipeline on a few candidates), or given (`planning.switch_margin`);
//! - where the two polygons do not intersect, the same LP gives the middle of the gap between
//!   them (negative margin), which only momentum can cross: the chained retiming then has to
//!   (each stance holds with its own path acceleration at the switch: module doc of the chained
//!   retiming). Gaps wider than [`crate::tol::MAX_CROSSING_GAP`] are refused with the segment
//!   and the width. (The paper's box climbing crossed its third switch with momentum; with the
//!   hand on the ledge in both stances their polygons do meet, and the planned box climbing
//!   stops there.)
//! - vertically, the initial CoM height above the feet (the surfaces of the first segment's
//!   stance) is kept above the lowest foot in contact in `S_k` or `S_{k+1}`: a CoM rises onto a
//!   step while the back foot swings, not while it is still down.
//!
//! A landing link gets a swing path ([`swing`]): lift-off along its surface's normal, a
//! traverse at least `planning.swing.clearance` clear of every environment solid, landing along
//! the target's normal.
//!
//! # Limitations
//!
//! - One margin fraction for the whole motion; the switch points are otherwise those of the
//!   static regions, not optimised one by one, and CoM velocities are not planned: a crossing
//!   with momentum is left to the retiming along the straight CoM path, which does not always
//!   find one (a walk without double support is not retimable).
//! - A motion that the pipeline cannot make (an IK failure, a switch it cannot cross) is
//!   reported as for a hand-written file.
//! - One landing per planned segment; the swing's clearance is the landing link's contact
//!   box's (the rest of the leg keeps the IK's `ik.clearance`).

mod assemble;
mod geometry;
pub mod regions;
mod search;
pub mod swing;

use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::plan::MotionPlan;
use crate::spec::MotionSpec;
use crate::{RunOptions, StanceError};

pub use regions::{closest_with_margin, largest_margin};
pub use search::Evaluation;
pub use swing::rpy_of;

/// A motion whose planned segments have been planned.
#[derive(Debug, Clone)]
pub struct PlannedMotion {
    /// The complete motion file (`stance motion FILE --write-plan OUT.toml` writes it).
    pub spec: MotionSpec,
    /// What was planned.
    pub info: PlanningInfo,
}

/// What the planner did (the result's `planning` key).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlanningInfo {
    /// One entry per planned segment.
    pub segments: Vec<PlannedSegment>,
    /// The margin fraction of the switches (the file's `planning.switch_margin`, or the
    /// search's choice).
    pub switch_margin: f64,
    /// The search's evaluations (none when the file fixes the fraction).
    pub evaluations: Vec<Evaluation>,
    /// Wall time of the planning (ms).
    pub millis: f64,
}

/// One planned segment.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlannedSegment {
    /// Its number (from 1).
    pub segment: usize,
    /// Its name.
    pub name: String,
    /// The link it lands, if any.
    pub landing: Option<String>,
    /// The CoM at its end (m, world).
    pub com: [f64; 3],
    /// The static margin (m) of the CoM where the segment starts, in the segment's stance:
    /// negative when the segment before (written by hand, or a crossing) leaves the CoM
    /// outside what the stance holds at rest, which only momentum can then carry.
    pub start_margin: f64,
    /// The static margin there (m): the distance to the nearest boundary of the two stances'
    /// static-equilibrium polygons; negative: half the gap crossed with momentum.
    pub margin: f64,
    /// Number of swing via-points (moves), landing included.
    pub moves: usize,
}

/// Which segments of `spec` are left to the planner (module doc): those without moves, and
/// those of one move of landings only, without `com`, whose links were not positioned by a
/// hand-written move since they last touched a surface (a landing whose approach the file
/// writes stays the straight landing it writes).
///
/// ```
/// use stance_motion::{experiments, footholds::planned_segments};
/// let written = experiments::by_name("stair-climbing").unwrap();
/// assert!(planned_segments(&written).iter().all(|p| !p));
/// let footholds = experiments::by_name("stair-climbing-footholds").unwrap();
/// assert!(planned_segments(&footholds).iter().all(|p| *p));
/// ```
pub fn planned_segments(spec: &MotionSpec) -> Vec<bool> {
    // robot surfaces moved by hand since their last contact
    let mut positioned: Vec<&str> = Vec::new();
    spec.segments
        .iter()
        .map(|s| {
            positioned.retain(|r| !s.stance.contains_key(*r));
            let planned = match s.moves.as_slice() {
                [] => true,
                [m] => {
                    m.com.is_none()
                        && !m.links.is_empty()
                        && m.links
                            .iter()
                            .all(|l| l.onto.is_some() && !positioned.contains(&l.surface.as_str()))
                }
                _ => false,
            };
            for l in s.moves.iter().flat_map(|m| &m.links) {
                positioned.retain(|r| *r != l.surface);
                if !planned && l.onto.is_none() {
                    positioned.push(&l.surface);
                }
            }
            planned
        })
        .collect()
}

/// Whether any segment of `spec` is left to the planner.
pub fn needs_planning(spec: &MotionSpec) -> bool {
    planned_segments(spec).contains(&true)
}

/// Plans every planned segment of `spec` (module doc) with the options of the run that will
/// follow (relative URDF paths from `options.base_dir`; `no_limits`; `progress`).
///
/// # Errors
///
/// [`StanceError::BadMotion`] for an invalid file, a stance that holds no CoM at rest, two
/// consecutive stances whose regions are farther apart than [`crate::tol::MAX_CROSSING_GAP`],
/// or a swing that no traverse clears.
///
/// ```
/// use stance_motion::{experiments, footholds, RunOptions};
/// let spec = experiments::by_name("small-sway").unwrap();
/// let planned = footholds::plan(&spec, &RunOptions::default()).unwrap();
/// assert!(planned.info.segments.is_empty()); // nothing to plan: written by hand
/// assert_eq!(planned.spec, spec);
/// ```
pub fn plan(spec: &MotionSpec, options: &RunOptions) -> Result<PlannedMotion, StanceError> {
    let t0 = Instant::now();
    if !needs_planning(spec) {
        return Ok(PlannedMotion {
            spec: spec.clone(),
            info: PlanningInfo {
                segments: Vec::new(),
                switch_margin: 0.0,
                evaluations: Vec::new(),
                millis: 0.0,
            },
        });
    }
    let g = geometry::Geometry::new(spec, options.base_dir.as_deref())?;
    let (alpha, evaluations) = match spec.planning.switch_margin {
        Some(a) => (a, Vec::new()),
        None => search::search(&g, options, t0),
    };
    let (spec, segments) = assemble::assemble(&g, alpha);
    Ok(PlannedMotion {
        spec,
        info: PlanningInfo {
            segments,
            switch_margin: alpha,
            evaluations,
            millis: t0.elapsed().as_secs_f64() * 1e3,
        },
    })
}

fn segment_name(plan: &MotionPlan, k: usize) -> String {
    crate::plan::segment_label(k, &plan.segments[k].name)
}

/// "LF on floor and RH on ledge".
fn stance_names(plan: &MotionPlan, k: usize) -> String {
    plan.segments[k]
        .stance
        .iter()
        .map(|&(r, e)| {
            format!(
                "{} on {}",
                plan.robot.surfaces[r].name, plan.environment[e].name
            )
        })
        .collect::<Vec<_>>()
        .join(" and ")
}
