//! A complete motion file from the planner's geometry and a margin fraction `alpha`: each
//! switch's CoM is the point nearest the feet with at least `alpha` times the largest margin
//! the two stances share (the point of largest margin when they share none).

use nalgebra::Vector3;

use super::geometry::{Geometry, Switch};
use super::regions;
use super::PlannedSegment;
use crate::spec::{ComTarget, MotionSpec, MoveSpec};

/// The switch's CoM for `alpha` and its margin (m).
fn switch_point(s: &Switch, alpha: f64) -> ([f64; 2], f64) {
    let (centre, best) = s.centre;
    let xy = if best > 0.0 {
        regions::closest_with_margin(&s.halfplanes, s.nominal, alpha * best).unwrap_or(centre)
    } else {
        centre
    };
    (xy, regions::margin(&s.halfplanes, xy))
}

/// The motion file for margin fraction `alpha`, and what was planned.
pub fn assemble(g: &Geometry, alpha: f64) -> (MotionSpec, Vec<PlannedSegment>) {
    let mut out = g.spec.clone();
    let mut info = Vec::new();
    let mut com = g.c0;
    for (k, sw) in g.switches.iter().enumerate() {
        let Some(sw) = sw else {
            for mv in &g.spec.segments[k].moves {
                com = match &mv.com {
                    None => com,
                    Some(ComTarget::By(v)) => com + Vector3::from(*v),
                    Some(ComTarget::To(v)) => Vector3::from(*v),
                };
            }
            continue;
        };
        let start_margin = regions::margin(&sw.own, [com.x, com.y]);
        let (xy, margin) = switch_point(sw, alpha);
        let target = Vector3::new(xy[0], xy[1], sw.z);
        let moves: Vec<MoveSpec> = if sw.swing.is_empty() {
            vec![MoveSpec {
                duration: sw.duration,
                com: Some(ComTarget::To(target.into())),
                links: Vec::new(),
            }]
        } else {
            let n = sw.swing.len() as f64;
            sw.swing
                .iter()
                .enumerate()
                .map(|(i, l)| MoveSpec {
                    duration: sw.duration,
                    com: Some(ComTarget::To(
                        (com + (target - com) * ((i + 1) as f64 / n)).into(),
                    )),
                    links: vec![l.clone()],
                })
                .collect()
        };
        info.push(PlannedSegment {
            segment: k + 1,
            name: g.spec.segments[k]
                .name
                .clone()
                .unwrap_or_else(|| format!("segment {}", k + 1)),
            landing: sw.landing.clone(),
            com: target.into(),
            start_margin,
            margin,
            moves: moves.len(),
        });
        out.segments[k].moves = moves;
        com = target;
    }
    (out, info)
}
