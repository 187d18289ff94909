//! Task references: the CoM and free-link via-points joined by straight lines, as functions of
//! the path parameter.
//!
//! # Math
//!
//! Moves of lengths `T_k` (path units) follow one another along the global path parameter,
//! with boundaries `sigma_0 = 0 < sigma_1 < ...` across all segments.
//!
//! **CoM.** Its via-points `c_0` (the CoM of the initial posture), `c_1, ...` (one per move) are
//! to be reached at the move boundaries `sigma_k`, at rest before `sigma_0` and after the last.
//! The CoM must keep moving through via-points and segment boundaries (a segment that is not
//! quasi-statically stable is crossed with momentum), so the reference is a control polyline
//! `L(s)` (rates `r_k` on each move, at rest outside) whose corners are rounded by a biweight
//! kernel of half-width `h`, `K(tau) = 15 / (16 h) (1 - u^2)^2` on a support of width `2h`.
//! Writing `L` as a sum of ramps, `L(s) = c_0 + sum_k dv_k max(s - sigma_k, 0)` with `dv_k` the
//! change of rate at `sigma_k`, each corner is smoothed by its own placement of the kernel:
//!
//! ```text
//! p*(s) = c_0 + sum_k dv_k G(s - sigma_k + l_k)
//! p*_s  = sum_k dv_k F(s - sigma_k + l_k),       p*_ss = sum_k dv_k K(s - sigma_k + l_k)
//! ```
//!
//! with `G` the ramp smoothed by the kernel on `[0, 2h]` (`F = 1/2 + 15/16 (u - 2u^3/3 + u^5/5)`,
//! `G = h (u/2 + 15/16 (u^2/2 - u^4/6 + u^6/30) + 5/32)`, `u = x / h - 1`, on `[0, 2h]`;
//! `G = x - h` beyond) and the lead `l_k`:
//!
//! - `0` where the CoM leaves a rest (the first via-point, the end of a move that keeps the CoM
//!   where it is): the corner is rounded after `sigma_k`, the CoM starts at rest on `c_k`;
//! - `2h` where it arrives at a rest (the last via-point, before a move that keeps it): rounded
//!   before `sigma_k`, the CoM arrives at rest;
//! - where it passes through moving at a stance switch, in the stance with more contacts (`0`
//!   where the next has at least as many, else `2h`): turning the CoM takes contact forces,
//!   which a single support has least of (centred on a switch, half of the turn of the stair
//!   climbing's last step fell in the single support before the landing: the retiming slowed
//!   the landing foot's last 2 mm to 140 ms, and MuJoCo put it down early);
//! - `h` where it passes through moving within a segment: rounded symmetrically about
//!   `sigma_k`.
//!
//! The rates are not the via-points' differences: they solve the interpolation conditions
//! `p*(sigma_i) = c_i` (one 3-vector per moving move, a small dense linear system; a move that
//! keeps the CoM has rate 0), so that the reference passes **through** every via-point at its
//! time, instead of lagging it (a causal kernel alone delays the line by `h`: 12.5 % of a move
//! at the defaults). With every move at least `4h` long the system is a perturbation of the
//! identity in the control vertices (a move between two rests runs at `dc / (T - 2h)`, at most
//! twice the polyline's rate). The reference is the straight control line except within the
//! kernels' supports, twice continuously differentiable, starts at rest on `c_0` (`p*_s =
//! p*_ss = 0` at `s = 0`) and arrives at rest on the last via-point.
//!
//! **Free links** run along the straight line between their via-points
//! `(R_a, x_a) -> (R_b, x_b)` with the minimum-jerk progress
//! `phi(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5`, `tau = (s - sigma_k-1) / T_k`:
//!
//! ```text
//! x*(s) = x_a + (x_b - x_a) phi,            x*_s = (x_b - x_a) phi' / T,   x*_ss = (x_b - x_a) phi'' / T^2
//! R*(s) = R_a Exp(phi omega), omega = Log(R_a^T R_b),   w*_s = R_a omega phi' / T,   w*_ss = R_a omega phi'' / T^2
//! ```
//!
//! so every link arrives at each via-point with zero velocity and acceleration: a landing foot
//! touches down at rest (no impact), whatever the CoM does meanwhile (the IK holds a landing
//! leg's task as an equality, so its tracking is not traded for the CoM's). A link still moving
//! when its segment starts (a free move of the segment before, not yet at rest) leaves on its
//! first leg at that path rate `(v_0, w_0)`: `x* += v_0 T psi(tau)` and the rotation vector
//! `omega phi + T psi(tau) R_a^T w_0`, `psi = tau - 6 tau^3 + 8 tau^4 - 3 tau^5` (slope 1 at 0;
//! value, slope and curvature 0 at 1), so that a landing held as an equality starts without a
//! velocity error to correct (without it a step down's landing ended 0.68 mm inside the
//! floor). Before its first move in a
//! segment a link holds its placement at the segment's start, after its last move its last
//! via-point.

use nalgebra::{Matrix3, Vector3};
use stance_robot::{LinkTarget, OrientationReference, PointReference, Pose};

use crate::StanceError;

/// One straight move of a free link.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkLeg {
    /// Path parameters (segment-local) of its start and end.
    pub s: [f64; 2],
    /// Start placement.
    pub from: Pose,
    /// End placement.
    pub to: Pose,
    /// It lands the link on an environment surface (`onto`): the IK holds the link's task as
    /// an equality over the segment, so that its arrival at rest is not traded for the CoM.
    pub landing: bool,
}

/// A free link's references over a segment.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkPlan {
    /// Index of the robot surface.
    pub surface: usize,
    /// Its frame in the model.
    pub frame: usize,
    /// Its placement at the segment's start.
    pub start: Pose,
    /// Its path velocity at the segment's start, linear and angular (world axes): a first leg
    /// that starts with the segment starts at this rate (module doc).
    pub start_rate: [Vector3<f64>; 2],
    /// Its moves, in order.
    pub legs: Vec<LinkLeg>,
}

/// Where the kernel that rounds a corner of the CoM's control polyline sits (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CornerKernel {
    /// On `[sigma, sigma + 2h]`: the CoM leaves a rest there, or turns in the next stance.
    After,
    /// On `[sigma - h, sigma + h]`: the CoM passes through the via-point while turning.
    Centred,
    /// On `[sigma - 2h, sigma]`: the CoM arrives at rest there, or turns in the stance before.
    Before,
}

impl CornerKernel {
    /// How far the kernel's support starts before the corner (`0`, `h` or `2h`).
    fn lead(self, h: f64) -> f64 {
        match self {
            Self::After => 0.0,
            Self::Centred => h,
            Self::Before => 2.0 * h,
        }
    }
}

/// The CoM reference of the whole motion (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct ComReference {
    /// Via-point times `sigma_k` (global path parameter).
    pub knots: Vec<f64>,
    /// Via-points `c_k`.
    pub points: Vec<Vector3<f64>>,
    /// Half-width `h` of the smoothing kernel (path units).
    pub blend: f64,
    /// Each corner's kernel.
    pub corners: Vec<CornerKernel>,
    /// The control polyline's rate on each move (`rates[k]` from `sigma_k` to `sigma_k+1`).
    pub rates: Vec<Vector3<f64>>,
}

/// The biweight-smoothed unit ramp `G` and its first two derivatives at `x` (module doc):
/// kernel support `[0, 2h]`.
fn smoothed_ramp(x: f64, h: f64) -> [f64; 3] {
    if x <= 0.0 {
        [0.0; 3]
    } else if x >= 2.0 * h {
        [x - h, 1.0, 0.0]
    } else {
        let u = x / h - 1.0;
        let (u2, u3) = (u * u, u * u * u);
        let w = 1.0 - u2;
        [
            h * (0.5 * u + 15.0 / 16.0 * (0.5 * u2 - u2 * u2 / 6.0 + u3 * u3 / 30.0) + 5.0 / 32.0),
            0.5 + 15.0 / 16.0 * (u - 2.0 * u3 / 3.0 + u3 * u2 / 5.0),
            15.0 / (16.0 * h) * w * w,
        ]
    }
}

impl ComReference {
    /// The reference through `points` at `knots` (module doc): picks each corner's kernel and
    /// solves for the control polyline's rates. `turns[k]` places the kernel of a corner the
    /// CoM passes through moving (at a stance switch: in the stance that turns it, module doc);
    /// `None` or missing centres it.
    ///
    /// # Errors
    ///
    /// [`StanceError::BadMotion`] naming `ik.com_blend` when the knots are not increasing by
    /// more than `4 blend` or the interpolation conditions are singular (not expected then).
    pub fn new(
        knots: Vec<f64>,
        points: Vec<Vector3<f64>>,
        blend: f64,
        turns: &[Option<CornerKernel>],
    ) -> Result<Self, StanceError> {
        let n = points.len();
        let h = blend;
        let bad = |why: String| StanceError::BadMotion(format!("ik.com_blend is {h}: {why}"));
        if knots.len() != n || n == 0 {
            return Err(StanceError::BadMotion(format!(
                "the CoM reference has {} knots for {n} via-points",
                knots.len()
            )));
        }
        if !(h.is_finite() && h > 0.0) {
            return Err(bad("give a half-width > 0".into()));
        }
        if let Some(w) = knots
            .windows(2)
            .find(|w| (w[1] - w[0]).is_nan() || w[1] - w[0] < 4.0 * h)
        {
            return Err(bad(format!(
                "a move of {} path units is shorter than 4 com_blend; give at most a quarter of \
                 the shortest move",
                w[1] - w[0]
            )));
        }
        // moves: k from knot k to k + 1; a hold keeps its point
        let moves = n - 1;
        let hold: Vec<bool> = (0..moves).map(|k| points[k + 1] == points[k]).collect();
        let still = |k: isize| k < 0 || k as usize >= moves || hold[k as usize];
        let corners: Vec<CornerKernel> = (0..n as isize)
            .map(|k| {
                if still(k - 1) {
                    CornerKernel::After
                } else if still(k) {
                    CornerKernel::Before
                } else {
                    turns
                        .get(k as usize)
                        .copied()
                        .flatten()
                        .unwrap_or(CornerKernel::Centred)
                }
            })
            .collect();
        // The rate r_m of move m enters corner m with +1 and corner m + 1 with -1:
        // p*(sigma_i) = c_0 + sum_m r_m [G_m(sigma_i - sigma_m) - G_m+1(sigma_i - sigma_m+1)].
        let ramp = |k: usize, x: f64| smoothed_ramp(x + corners[k].lead(h), h)[0];
        let unknown: Vec<usize> = (0..moves).filter(|&m| !hold[m]).collect();
        let u = unknown.len();
        let mut a = nalgebra::DMatrix::<f64>::zeros(u, u);
        let mut b = nalgebra::DMatrix::<f64>::zeros(u, 3);
        for (row, &i) in unknown.iter().enumerate() {
            let si = knots[i + 1];
            for (col, &m) in unknown.iter().enumerate() {
                a[(row, col)] = ramp(m, si - knots[m]) - ramp(m + 1, si - knots[m + 1]);
            }
            let rhs = points[i + 1] - points[0];
            for d in 0..3 {
                b[(row, d)] = rhs[d];
            }
        }
        let x = if u == 0 {
            b // every move holds: no rate to solve for
        } else {
            a.lu()
                .solve(&b)
                .filter(|x| x.iter().all(|v| v.is_finite()))
                .ok_or_else(|| {
                    bad("the CoM via-points cannot be interpolated; give a smaller one".into())
                })?
        };
        let mut rates = vec![Vector3::zeros(); moves];
        for (row, &m) in unknown.iter().enumerate() {
            rates[m] = Vector3::new(x[(row, 0)], x[(row, 1)], x[(row, 2)]);
        }
        Ok(Self {
            knots,
            points,
            blend,
            corners,
            rates,
        })
    }

    /// The reference at global `s`.
    pub fn at(&self, s: f64) -> PointReference {
        let h = self.blend;
        let mut out = PointReference::hold(self.points[0]);
        let rate = |k: usize| {
            k.checked_sub(1)
                .and_then(|m| self.rates.get(m))
                .copied()
                .unwrap_or_else(Vector3::zeros)
        };
        for (k, corner) in self.corners.iter().enumerate() {
            let dv = rate(k + 1) - rate(k);
            let x = s - self.knots[k] + corner.lead(h);
            if x <= 0.0 || dv == Vector3::zeros() {
                continue;
            }
            let [g, f, kk] = smoothed_ramp(x, h);
            out.p += dv * g;
            out.p_s += dv * f;
            out.p_ss += dv * kk;
        }
        out
    }
}

/// The references of one segment.
#[derive(Debug, Clone, PartialEq)]
pub struct SegmentReferences {
    /// Move boundaries (segment-local path parameter), one more than the moves.
    pub knots: Vec<f64>,
    /// Global path parameter of the segment's start.
    pub s_offset: f64,
    /// The motion's CoM reference.
    pub com: ComReference,
    /// Free links with tasks.
    pub links: Vec<LinkPlan>,
}

/// The quintic `psi(tau) = tau - 6 tau^3 + 8 tau^4 - 3 tau^5` and its first two derivatives:
/// unit slope at 0, and value, slope and curvature zero at 1 (and curvature zero at 0).
fn launch(tau: f64) -> [f64; 3] {
    let t = tau.clamp(0.0, 1.0);
    let (t2, t3) = (t * t, t * t * t);
    [
        t - 6.0 * t3 + 8.0 * t2 * t2 - 3.0 * t2 * t3,
        1.0 - 18.0 * t2 + 32.0 * t3 - 15.0 * t2 * t2,
        -36.0 * t + 96.0 * t2 - 60.0 * t3,
    ]
}

/// Minimum-jerk progress and its first two derivatives in `tau`.
fn min_jerk(tau: f64) -> [f64; 3] {
    let t = tau.clamp(0.0, 1.0);
    let t2 = t * t;
    [
        t2 * t * (10.0 - 15.0 * t + 6.0 * t2),
        30.0 * t2 * (1.0 - t) * (1.0 - t),
        60.0 * t * (1.0 - t) * (1.0 - 2.0 * t),
    ]
}

fn log(r: &Matrix3<f64>) -> Vector3<f64> {
    stance_robot::spatial::rotation_log(r)
}

fn exp(w: &Vector3<f64>) -> Matrix3<f64> {
    *nalgebra::Rotation3::new(*w).matrix()
}

impl LinkPlan {
    /// The link's target at segment-local `s`.
    pub fn target_at(&self, s: f64) -> LinkTarget {
        let hold = |x: &Pose| LinkTarget {
            frame: self.frame,
            reference: PointReference::hold(x.translation),
            orientation: Some(OrientationReference::hold(x.rotation)),
        };
        let Some(first) = self.legs.first() else {
            return hold(&self.start);
        };
        if s < first.s[0] {
            return hold(&self.start);
        }
        for (k, leg) in self.legs.iter().enumerate() {
            let next_start = self.legs.get(k + 1).map_or(f64::INFINITY, |l| l.s[0]);
            if s <= leg.s[1] {
                let t = leg.s[1] - leg.s[0];
                let tau = (s - leg.s[0]) / t;
                let [phi, d1, d2] = min_jerk(tau);
                // the first leg leaves at the link's rate at the segment's start
                let [v0, w0] = if k == 0 && leg.s[0] <= 0.0 {
                    self.start_rate
                } else {
                    [Vector3::zeros(); 2]
                };
                let [psi, e1, e2] = launch(tau);
                let dx = leg.to.translation - leg.from.translation;
                let omega = log(&(leg.from.rotation.transpose() * leg.to.rotation));
                // the rotation vector in the start's frame: omega phi + nu T psi
                let nu = leg.from.rotation.transpose() * w0;
                let theta = omega * phi + nu * (t * psi);
                let r = leg.from.rotation;
                return LinkTarget {
                    frame: self.frame,
                    reference: PointReference {
                        p: leg.from.translation + dx * phi + v0 * (t * psi),
                        p_s: dx * (d1 / t) + v0 * e1,
                        p_ss: dx * (d2 / (t * t)) + v0 * (e2 / t),
                    },
                    orientation: Some(OrientationReference {
                        rotation: r * exp(&theta),
                        w_s: r * (omega * (d1 / t) + nu * e1),
                        w_ss: r * (omega * (d2 / (t * t)) + nu * (e2 / t)),
                    }),
                };
            }
            if s < next_start {
                return hold(&leg.to);
            }
        }
        hold(&self.legs[self.legs.len() - 1].to)
    }
}

impl SegmentReferences {
    /// Length of the segment (path units).
    pub fn length(&self) -> f64 {
        self.knots[self.knots.len() - 1]
    }

    /// The CoM reference at segment-local `s`.
    pub fn com_at(&self, s: f64) -> PointReference {
        self.com.at(self.s_offset + s)
    }

    /// The free-link targets at segment-local `s`: weighted tasks into `soft`, those of links
    /// that land in the segment into `hard` (over the whole segment: the tracking error of an
    /// earlier weighted leg would still decay when the link arrives).
    pub fn links_at(&self, s: f64, soft: &mut Vec<LinkTarget>, hard: &mut Vec<LinkTarget>) {
        soft.clear();
        hard.clear();
        for l in &self.links {
            let landing = l.legs.iter().any(|leg| leg.landing);
            if landing {
                hard.push(l.target_at(s));
            } else {
                soft.push(l.target_at(s));
            }
        }
    }
}

#[cfg(test)]
mod doc_examples {
    //! The examples that were in the docs of this private module.

    #[test]
    fn new_example() {
        use crate::references::ComReference;
        use nalgebra::Vector3;
        let points = vec![
            Vector3::zeros(),
            Vector3::new(0.2, 0.0, 0.0),
            Vector3::new(0.2, 0.2, 0.0),
        ];
        let c = ComReference::new(vec![0.0, 2.0, 4.0], points.clone(), 0.25, &[]).unwrap();
        let start = c.at(0.0);
        assert_eq!(
            (start.p.norm(), start.p_s.norm(), start.p_ss.norm()),
            (0.0, 0.0, 0.0)
        );
        // through the corner's via-point, moving; at rest on the last one
        assert!((c.at(2.0).p - points[1]).norm() < 1e-14 && c.at(2.0).p_s.norm() > 0.05);
        let end = c.at(4.0);
        assert!((end.p - points[2]).norm() < 1e-14 && end.p_s.norm() < 1e-15);
    }

    #[test]
    fn target_at_example() {
        use crate::references::{LinkLeg, LinkPlan};
        use stance_robot::Pose;
        let a = Pose::identity();
        let b = Pose::from_xyz_rpy([0.2, 0.0, 0.1], [0.0, 0.3, 0.0]);
        let rest = [nalgebra::Vector3::zeros(); 2];
        let plan = LinkPlan {
            surface: 0,
            frame: 7,
            start: a,
            start_rate: rest,
            legs: vec![LinkLeg {
                s: [1.0, 3.0],
                from: a,
                to: b,
                landing: false,
            }],
        };
        assert_eq!(plan.target_at(0.5).reference.p, a.translation); // holds before
        let mid = plan.target_at(2.0);
        assert!((mid.reference.p - b.translation * 0.5).norm() < 1e-15);
        let end = plan.target_at(3.0);
        assert!(
            (end.reference.p - b.translation).norm() < 1e-15 && end.reference.p_s.norm() < 1e-15
        );
        // a first leg from the segment's start leaves at the link's rate there
        let v0 = nalgebra::Vector3::new(0.0, 0.05, -0.02);
        let moving = LinkPlan {
            surface: 0,
            frame: 7,
            start: a,
            start_rate: [v0, v0],
            legs: vec![LinkLeg {
                s: [0.0, 2.0],
                from: a,
                to: b,
                landing: true,
            }],
        };
        let t0 = moving.target_at(0.0);
        assert!((t0.reference.p_s - v0).norm() < 1e-15 && t0.reference.p_ss.norm() < 1e-15);
        assert!((t0.orientation.unwrap().w_s - v0).norm() < 1e-15);
        let arrival = moving.target_at(2.0);
        assert!((arrival.reference.p - b.translation).norm() < 1e-15);
        assert!(arrival.reference.p_s.norm() < 1e-15 && arrival.reference.p_ss.norm() < 1e-12);
    }
}
