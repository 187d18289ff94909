//! Stage 3b, actuator-limit rows: joint velocity, acceleration and torque limits of a
//! floating-base robot in contact, as rows in `(u, x) = (s'', s'^2)` beside the contact rows
//! of eq. 14.
//!
//! # Math
//!
//! Along the whole-body path, joint `j` moves at `q_s,j s'` and accelerates at
//! `q_s,j u + q_ss,j x`: its velocity and acceleration limits are rows of
//! [`stance_topp::limits`]. Its torque needs the contact forces. The equations of motion are
//!
//! ```text
//!     tau_a u + tau_b x + tau_c = S^T tau_act + sum_k J_k^T w_k
//! ```
//!
//! with the inverse-dynamics coefficients along the path ([`stance_robot::torque_path_terms`]),
//! the contact wrench `w_k` of contact `k` in its own frame (force, then moment about its
//! origin) and its frame Jacobian `J_k` in that frame (`LOCAL`): the six base rows have no
//! actuator and balance the contact wrenches; each actuated joint's torque is what remains,
//! `tau_j = r_j(u, x) - sum_k J_k[:, j] . w_k`, with `|tau_j| <= T_j`. Each `w_k` lies in its
//! contact wrench cone `H_k w_k <= 0` (the face form of the planned contact's span form
//! `V_surf`: the same pyramids, friction and polygons as the GIWC).
//!
//! - A joint that is not on the chain from the base to any contact (`J_k[:, j] = 0` for all
//!   `k`) has `tau_j = r_j(u, x)`: two rows.
//! - With **one contact**, the base rows determine its wrench,
//!   `w_1 = J_1,b^-T r_b(u, x)` (the `6 x 6` base block of `J_1` is invertible: it is the
//!   adjoint of the contact frame from the base), so every torque is linear in `(u, x)`: two
//!   rows per joint.
//! - With **K >= 2 contacts**, the wrenches `w_2 .. w_K` are free (`y = (w_2, .., w_K) / (m |g|)`)
//!   and `w_1 = J_1,b^-T (r_b - sum_k J_k,b^T w_k)`: every contact-wrench-cone row and every
//!   chain joint's torque row is affine in `(u, x, y)`. The admissible `(u, x)` are the
//!   projection of that polytope (the redundantly actuated form of Pham and Pham's
//!   reachability analysis). The retiming never computes it: its separation oracle
//!   ([`super::separation`]) tests the states the solver's LPs reach and cuts off those that
//!   admit no contact forces ([`stance_topp::lifted::Membership::separate`]), so the extra
//!   variables are eliminated only where the profile needs it.
//!
//! A cut carries the lifted rows that define it: one whose definition involves a torque limit
//! is reported as that joint's torque ([`RowOrigin::TorqueWithContacts`], the torque row of
//! largest weight), one that involves only contact wrench cones as contact stability.

use std::sync::Arc;

use nalgebra::{Matrix6, Matrix6xX, Vector6};
use stance_contact::Stance;
use stance_robot::{frame_jacobian, torque_path_terms_two, Data, ReferenceFrame};
use stance_topp::facets::{redundant_rows, FacetWorkspace};
use stance_topp::lifted::LiftedRows;
use stance_topp::limits::{JointLimits, LimitKind, LimitTag};
use stance_topp::lp2::Box2;
use stance_topp::{Row, Tolerances};

use super::ik_stage::IkSample;
use super::plan::MotionPlan;
use crate::binding::RowOrigin;
use crate::limits::{JointLimitInfo, LimitsSpec};
use crate::StanceError;

/// The actuated joints of a motion's robot and their limits.
#[derive(Debug, Clone)]
pub struct LimitsPlan {
    /// Velocity index of each actuated coordinate (the movable joints but the base).
    pub velocity_index: Vec<usize>,
    /// Their names.
    pub names: Vec<String>,
    /// Velocity and acceleration limits per coordinate (torque limits infinite here).
    pub kinematic: JointLimits,
    /// The layout of their rows ([`JointLimits::layout`]).
    pub kinematic_tags: Vec<LimitTag>,
    /// Torque limits per coordinate (`f64::INFINITY`: none).
    pub torque: Vec<f64>,
    /// The limits as used, per joint.
    pub info: Vec<JointLimitInfo>,
}

impl LimitsPlan {
    /// The limits of `spec` for the plan's robot; `None` when none is finite.
    ///
    /// # Errors
    ///
    /// As [`LimitsSpec::resolve`].
    pub fn new(
        plan_model: &stance_robot::Model,
        spec: &LimitsSpec,
    ) -> Result<Option<Self>, StanceError> {
        let joints: Vec<usize> = (1..plan_model.joints.len())
            .filter(|&k| {
                let j = &plan_model.joints[k];
                j.dims().1 == 1 && j.kind != stance_robot::JointKind::FreeFlyer
            })
            .collect();
        let resolved = spec.resolve(plan_model, &joints)?;
        if !resolved.any() {
            return Ok(None);
        }
        let mut kinematic = resolved.limits.clone();
        let torque = std::mem::replace(&mut kinematic.torque, vec![f64::INFINITY; joints.len()]);
        Ok(Some(Self {
            kinematic_tags: kinematic.layout(),
            velocity_index: joints.iter().map(|&k| plan_model.joints[k].idx_v).collect(),
            names: joints
                .iter()
                .map(|&k| plan_model.joints[k].name.clone())
                .collect(),
            kinematic,
            torque,
            info: resolved.joints,
        }))
    }

    /// Whether any torque limit is finite.
    pub fn any_torque(&self) -> bool {
        self.torque.iter().any(|t| t.is_finite())
    }
}

/// A segment's contacts as the torque rows need them.
#[derive(Debug, Clone)]
pub struct SegmentContacts {
    /// Model frame of each contact's robot surface.
    pub frames: Vec<usize>,
    /// Each contact's planned frame (`world_from_contact`): the frame of its wrench cone.
    pub poses: Vec<stance_robot::Pose>,
    /// Each contact's wrench cone in its own frame, face form (`h . w <= 0`, unit rows;
    /// equations as two rows).
    pub cwc: Vec<Vec<[f64; 6]>>,
}

impl SegmentContacts {
    /// From the planned stance of a segment (its contacts in the order of the path's).
    ///
    /// # Errors
    ///
    /// [`StanceError::BadMotion`] when a contact's wrench cone cannot be converted.
    pub fn new(
        plan: &MotionPlan,
        surfaces: &[usize],
        poses: &[stance_robot::Pose],
        stance: &Stance,
    ) -> Result<Self, StanceError> {
        let mut ws = polycone::Workspace::new();
        let mut cwc = Vec::with_capacity(stance.contacts().len());
        for c in stance.contacts() {
            let v = c.v_surf(stance.friction_model());
            let f = ws
                .span_to_face(&v, &polycone::DdOptions::default())
                .map_err(|e| {
                    StanceError::BadMotion(format!(
                        "the wrench cone of contact {} cannot be converted: {e}",
                        c.name()
                    ))
                })?;
            let mut rows = Vec::new();
            let push = |rows: &mut Vec<[f64; 6]>, r: nalgebra::RowDVector<f64>| {
                let mut a = [0.0; 6];
                for k in 0..6 {
                    a[k] = r[k];
                }
                rows.push(a);
            };
            for r in f.face.facets.row_iter() {
                push(&mut rows, r.into_owned());
            }
            for r in f.face.equations.row_iter() {
                push(&mut rows, r.into_owned());
                push(&mut rows, -r.into_owned());
            }
            cwc.push(rows);
        }
        Ok(Self {
            frames: surfaces
                .iter()
                .map(|&s| plan.robot.surfaces[s].frame)
                .collect(),
            poses: poses.to_vec(),
            cwc,
        })
    }
}

/// Reusable buffers of [`sample_limit_rows`].
#[derive(Debug, Clone)]
pub struct LimitWorkspace {
    data: Data,
    jac: Vec<Matrix6xX<f64>>,
    qs: Vec<f64>,
    qs_end: Vec<f64>,
    qss: Vec<f64>,
    buf: Vec<Row>,
    /// Both sides' rows of a sample before pruning.
    pub(crate) scratch: [(Vec<Row>, Vec<RowOrigin>); 2],
    /// Buffers of [`drop_redundant`].
    facets: (FacetWorkspace, Vec<bool>, Vec<(Row, RowOrigin)>),
}

impl LimitWorkspace {
    /// Buffers for the plan's robot.
    pub fn new(plan: &MotionPlan) -> Self {
        let m = &plan.robot.model;
        Self {
            data: Data::new(m),
            jac: Vec::new(),
            qs: Vec::new(),
            qs_end: Vec::new(),
            qss: Vec::new(),
            buf: Vec::new(),
            scratch: Default::default(),
            facets: Default::default(),
        }
    }
}

/// Largest contact wrench of the lifted rows' extra variables, in weights `m |g|`: a bound the
/// physical solutions never reach (a cut may rest on it: it is valid, and looser than needed,
/// only where no force below a thousand weights would hold the motion).
const Y_BOUND: f64 = 1e3;

/// The explicit rows and origins of one side of a sample.
pub type SideLimits<'a> = (&'a mut Vec<Row>, &'a mut Vec<RowOrigin>);

/// A side's torque rows with the contact forces as unknowns, and what each stands for (the
/// same for both sides of a sample: shared).
pub type Lifted = (LiftedRows, Arc<[RowOrigin]>);

/// Appends the explicit limit rows of both sides of an IK sample (`q_ss_sides`: `q_ss` of the
/// step leaving it and of the step arriving at it; `q_s_ends`: `q_s` at the other end of each
/// step, for the velocity rows of [`JointLimits::fill_rows_on_step`]) to each side's rows,
/// with their origins, and
/// returns each side's torque rows with the contact forces as unknowns when the stance has two
/// contacts or more (module doc); `contacts` is needed when torque limits apply. The two sides
/// share the sample's kinematics, `tau_a`, `tau_c` and contact Jacobians.
#[allow(clippy::too_many_arguments)]
pub fn sample_limit_rows(
    plan: &MotionPlan,
    lp: &LimitsPlan,
    contacts: Option<&SegmentContacts>,
    sample: &IkSample,
    q_ss_sides: [&[f64]; 2],
    q_s_ends: [&[f64]; 2],
    ws: &mut LimitWorkspace,
    sides: [SideLimits<'_>; 2],
) -> Result<[Option<Lifted>; 2], StanceError> {
    let [(rows_r, origins_r), (rows_l, origins_l)] = sides;
    let mut out: [(&mut Vec<Row>, &mut Vec<RowOrigin>); 2] =
        [(rows_r, origins_r), (rows_l, origins_l)];
    kinematic_rows(lp, sample, q_ss_sides, q_s_ends, ws, &mut out);
    let Some(contacts) = contacts.filter(|_| lp.any_torque()) else {
        return Ok([None, None]);
    };
    inverse_dynamics_and_jacobians(plan, contacts, sample, q_ss_sides, ws)?;
    let tp = &ws.data.torque_path;
    let terms = TorqueTerms {
        tau_a: &tp.tau_a,
        tau_b: [&tp.tau_b, &ws.data.tau_b_other],
        tau_c: &tp.tau_c,
        jac: &ws.jac,
    };
    let chain = terms.chain_joints(lp);
    off_chain_torque_rows(lp, &chain, &terms, &mut out);
    if chain.is_empty() {
        return Ok([None, None]);
    }
    let w1 = ContactOneWrench::new(&terms)?;
    if contacts.frames.len() == 1 {
        one_contact_torque_rows(lp, &chain, &terms, &w1, &mut out);
        return Ok([None, None]);
    }
    Ok(lifted_torque_rows(plan, lp, contacts, &chain, &terms, &w1))
}

/// The velocity and acceleration rows of both sides ([`JointLimits::fill_rows_on_step`] on the
/// actuated coordinates' `q_s`, each side's `q_ss` and `q_s` at its step's other end), with
/// their origins; a side's velocity rows are tagged with the coordinate that is tightest.
#[inline]
fn kinematic_rows(
    lp: &LimitsPlan,
    sample: &IkSample,
    q_ss_sides: [&[f64]; 2],
    q_s_ends: [&[f64]; 2],
    ws: &mut LimitWorkspace,
    out: &mut [SideLimits<'_>; 2],
) {
    let tags = &lp.kinematic_tags;
    ws.qs.clear();
    ws.qs
        .extend(lp.velocity_index.iter().map(|&i| sample.q_s[i]));
    for (side, (rows, origins)) in out.iter_mut().enumerate() {
        ws.qss.clear();
        ws.qss
            .extend(lp.velocity_index.iter().map(|&i| q_ss_sides[side][i]));
        ws.qs_end.clear();
        ws.qs_end
            .extend(lp.velocity_index.iter().map(|&i| q_s_ends[side][i]));
        ws.buf.clear();
        ws.buf.resize(tags.len(), Row::default());
        let tight =
            lp.kinematic
                .fill_rows_on_step(&ws.qs, Some(&ws.qs_end), &ws.qss, None, &mut ws.buf);
        rows.extend_from_slice(&ws.buf);
        for t in tags {
            let mut t = *t;
            if t.kind == LimitKind::Velocity {
                t.coordinate = tight.unwrap_or(0);
            }
            origins.push(RowOrigin::Limit(t));
        }
    }
}

/// The inverse dynamics along the path at the sample, both sides
/// ([`torque_path_terms_two`], into `ws.data`), and each contact's frame Jacobian
/// ([`contact_jacobian`], into `ws.jac`).
#[inline]
fn inverse_dynamics_and_jacobians(
    plan: &MotionPlan,
    contacts: &SegmentContacts,
    sample: &IkSample,
    q_ss_sides: [&[f64]; 2],
    ws: &mut LimitWorkspace,
) -> Result<(), StanceError> {
    let m = &plan.robot.model;
    torque_path_terms_two(
        m,
        &mut ws.data,
        &sample.q,
        &sample.q_s,
        q_ss_sides[0],
        q_ss_sides[1],
        plan.gravity,
    )
    .map_err(StanceError::Robot)?;
    let k = contacts.frames.len();
    // (a new Jacobian only when there are more contacts than before: the fill value of
    // `resize` would be built, and dropped, at every sample)
    if ws.jac.len() != k {
        ws.jac.resize_with(k, || Matrix6xX::zeros(m.nv));
    }
    for (c, &f) in contacts.frames.iter().enumerate() {
        contact_jacobian(m, &ws.data, f, &contacts.poses[c], &mut ws.jac[c])?;
    }
    Ok(())
}

/// A sample's torque terms as its torque rows read them: `r(u, x) = tau_a u + tau_b x + tau_c`
/// (`tau_b` per side) and the contacts' Jacobians `J_k`.
struct TorqueTerms<'a> {
    tau_a: &'a [f64],
    tau_b: [&'a [f64]; 2],
    tau_c: &'a [f64],
    jac: &'a [Matrix6xX<f64>],
}

impl TorqueTerms<'_> {
    /// The coordinates with a torque limit on the chain from the base to some contact (a
    /// nonzero column in some `J_k`).
    fn chain_joints(&self, lp: &LimitsPlan) -> Vec<usize> {
        let on_chain = |iv: usize| {
            self.jac
                .iter()
                .any(|j| j.column(iv).iter().any(|&x| x != 0.0))
        };
        (0..lp.velocity_index.len())
            .filter(|&c| lp.torque[c].is_finite() && on_chain(lp.velocity_index[c]))
            .collect()
    }
}

/// Column `iv` of a contact Jacobian.
#[inline]
fn column6(j: &Matrix6xX<f64>, iv: usize) -> Vector6<f64> {
    Vector6::from_iterator(j.column(iv).iter().copied())
}

/// Appends the two rows of `|tau| <= t` for coordinate `c`, with
/// `tau = abc[0] u + abc[1] x + abc[2]`: `(tau / t) - 1 <= 0` and `(-tau / t) - 1 <= 0`, the
/// upper limit first.
#[inline]
fn push_torque_limit(
    rows: &mut Vec<Row>,
    origins: &mut Vec<RowOrigin>,
    c: usize,
    abc: [f64; 3],
    t: f64,
) {
    let (a, b, cc) = (abc[0] / t, abc[1] / t, abc[2] / t);
    rows.push(Row { a, b, c: cc - 1.0 });
    rows.push(Row {
        a: -a,
        b: -b,
        c: -cc - 1.0,
    });
    for upper in [true, false] {
        origins.push(RowOrigin::Limit(LimitTag {
            kind: LimitKind::Torque,
            coordinate: c,
            upper,
        }));
    }
}

/// The torque rows of the limited joints off every contact chain, both sides:
/// `tau_j = r_j(u, x)`.
#[inline]
fn off_chain_torque_rows(
    lp: &LimitsPlan,
    chain: &[usize],
    terms: &TorqueTerms<'_>,
    out: &mut [SideLimits<'_>; 2],
) {
    for (side, (rows, origins)) in out.iter_mut().enumerate() {
        for c in 0..lp.velocity_index.len() {
            let t = lp.torque[c];
            let iv = lp.velocity_index[c];
            if t.is_finite() && !chain.contains(&c) {
                push_torque_limit(
                    rows,
                    origins,
                    c,
                    [terms.tau_a[iv], terms.tau_b[side][iv], terms.tau_c[iv]],
                    t,
                );
            }
        }
    }
}

/// Contact 1's wrench from the six base rows (module doc):
/// `w_1 = M1 (r_b - sum_k J_k,b^T w_k)` with `M1 = J_1,b^-T`; its terms in `u`
/// (`wa = M1 tau_a,b`), in `x` per side (`wb`) and constant (`wc`).
struct ContactOneWrench {
    m1: Matrix6<f64>,
    wa: Vector6<f64>,
    wb: [Vector6<f64>; 2],
    wc: Vector6<f64>,
}

impl ContactOneWrench {
    /// From the sample's terms.
    ///
    /// # Errors
    ///
    /// [`StanceError::BadMotion`] when `J_1,b` is singular (no floating base).
    #[inline]
    fn new(terms: &TorqueTerms<'_>) -> Result<Self, StanceError> {
        let j1b = terms.jac[0].fixed_view::<6, 6>(0, 0).into_owned();
        let Some(m1) = j1b.transpose().try_inverse() else {
            return Err(StanceError::BadMotion(
                "a contact frame's Jacobian has a singular base block (the robot has no \
                 free-flyer base?): torque limits with contacts need a floating base"
                    .into(),
            ));
        };
        let base = |v: &[f64]| Vector6::from_iterator(v[..6].iter().copied());
        let (wa, wc) = (m1 * base(terms.tau_a), m1 * base(terms.tau_c));
        let wb = [m1 * base(terms.tau_b[0]), m1 * base(terms.tau_b[1])];
        Ok(Self { m1, wa, wb, wc })
    }
}

/// With one contact, the chain joints' torque rows, both sides: its wrench is `w_1` of the base
/// rows, so `tau_j = r_j - J_1j . w_1` is linear in `(u, x)`.
#[inline]
fn one_contact_torque_rows(
    lp: &LimitsPlan,
    chain: &[usize],
    terms: &TorqueTerms<'_>,
    w1: &ContactOneWrench,
    out: &mut [SideLimits<'_>; 2],
) {
    for (side, (rows, origins)) in out.iter_mut().enumerate() {
        for &c in chain {
            let iv = lp.velocity_index[c];
            let j = column6(&terms.jac[0], iv);
            push_torque_limit(
                rows,
                origins,
                c,
                [
                    terms.tau_a[iv] - j.dot(&w1.wa),
                    terms.tau_b[side][iv] - j.dot(&w1.wb[side]),
                    terms.tau_c[iv] - j.dot(&w1.wc),
                ],
                lp.torque[c],
            );
        }
    }
}

/// With `K >= 2` contacts, each side's lifted rows in `(u, x, y)`, `y_k = w_{k+1} / W` with
/// the weight `W = m |g|` (1 without gravity) (module doc): contact 1's cone `h . w_1 <= 0`
/// with `w_1 = wa u + wb x + wc - sum_q N_q y_q`, `N_q = M1 J_{q+1},b^T W`; the other cones
/// `W h . y_k <= 0`; and each chain joint's `|r_j - J_1j . w_1 - sum_k J_{k+1}j . W y_k| <= T_j`,
/// scaled by `1 / T_j`.
fn lifted_torque_rows(
    plan: &MotionPlan,
    lp: &LimitsPlan,
    contacts: &SegmentContacts,
    chain: &[usize],
    terms: &TorqueTerms<'_>,
    w1: &ContactOneWrench,
) -> [Option<Lifted>; 2] {
    let m = &plan.robot.model;
    let k = contacts.frames.len();
    let jac = terms.jac;
    let (m1, wa, wb, wc) = (w1.m1, w1.wa, w1.wb, w1.wc);
    let weight = m.total_mass() * plan.gravity.iter().map(|g| g * g).sum::<f64>().sqrt();
    let weight = if weight > 0.0 { weight } else { 1.0 };
    let ky = 6 * (k - 1);
    let nk: Vec<Matrix6<f64>> = (1..k)
        .map(|q| m1 * jac[q].fixed_view::<6, 6>(0, 0).transpose() * weight)
        .collect();
    let rows_count = contacts.cwc.iter().map(Vec::len).sum::<usize>() + 2 * chain.len();
    // the two sides differ only in their `x` terms: each row's `d` is computed once
    let mut lifted = [0, 1].map(|_| LiftedRows::with_capacity(ky, Y_BOUND, rows_count));
    let mut origins = Vec::with_capacity(rows_count);
    let mut d = vec![0.0; ky];
    // contact 1's cone: h . w_1 <= 0
    for h in &contacts.cwc[0] {
        let hv = Vector6::from_row_slice(h);
        for (q, nq) in nk.iter().enumerate() {
            let g = nq.transpose() * hv;
            for i in 0..6 {
                d[6 * q + i] = -g[i];
            }
        }
        for (side, l) in lifted.iter_mut().enumerate() {
            l.push(hv.dot(&wa), hv.dot(&wb[side]), hv.dot(&wc), &d);
        }
        origins.push(RowOrigin::Contact);
    }
    // the other cones: W h . y_k <= 0
    for q in 1..k {
        for h in &contacts.cwc[q] {
            d.fill(0.0);
            for (i, x) in h.iter().enumerate() {
                d[6 * (q - 1) + i] = weight * x;
            }
            for l in lifted.iter_mut() {
                l.push(0.0, 0.0, 0.0, &d);
            }
            origins.push(RowOrigin::Contact);
        }
    }
    // chain torques: tau_j = r_j - J_1j . w_1 - sum_k J_kj . W y_k
    for &c in chain {
        let iv = lp.velocity_index[c];
        let t = lp.torque[c];
        let j1 = column6(&jac[0], iv);
        let a = terms.tau_a[iv] - j1.dot(&wa);
        let b = [0, 1].map(|side| terms.tau_b[side][iv] - j1.dot(&wb[side]));
        let cc = terms.tau_c[iv] - j1.dot(&wc);
        for (q, nq) in nk.iter().enumerate() {
            // + J_1j . N_q y_q - W J_qj . y_q
            let g = nq.transpose() * j1 - column6(&jac[q + 1], iv) * weight;
            for i in 0..6 {
                d[6 * q + i] = g[i] / t;
            }
        }
        for (side, l) in lifted.iter_mut().enumerate() {
            l.push(a / t, b[side] / t, cc / t - 1.0, &d);
        }
        for x in d.iter_mut() {
            *x = -*x;
        }
        for (side, l) in lifted.iter_mut().enumerate() {
            l.push(-a / t, -b[side] / t, -cc / t - 1.0, &d);
        }
        for upper in [true, false] {
            origins.push(RowOrigin::TorqueWithContacts(LimitTag {
                kind: LimitKind::Torque,
                coordinate: c,
                upper,
            }));
        }
    }
    let [right, left] = lifted;
    let origins: Arc<[RowOrigin]> = origins.into();
    [Some((right, Arc::clone(&origins))), Some((left, origins))]
}

/// The Jacobian (6 x nv, linear rows first) of the frame rigidly attached to the robot surface
/// `frame`'s body that coincides now with the contact's planned frame `world_from_contact`, in
/// that frame's axes at its origin: the map from `v` to the twist of the body at the contact,
/// whose transpose turns a contact wrench in the cone's frame into generalized forces. With
/// `surface_from_contact = (R, p)`, `J_c = [R^T, -R^T [p]x; 0, R^T] J_surface` (`LOCAL`).
///
/// # Errors
///
/// [`StanceError::Robot`] for a frame the model does not have.
pub fn contact_jacobian(
    model: &stance_robot::Model,
    data: &Data,
    frame: usize,
    world_from_contact: &stance_robot::Pose,
    out: &mut Matrix6xX<f64>,
) -> Result<(), StanceError> {
    frame_jacobian(model, data, frame, ReferenceFrame::Local, out).map_err(StanceError::Robot)?;
    let world_from_surface =
        stance_robot::frame_placement(model, data, frame).map_err(StanceError::Robot)?;
    let off = world_from_surface.inverse().compose(world_from_contact);
    let rt = off.rotation.transpose();
    let px = nalgebra::Matrix3::new(
        0.0,
        -off.translation.z,
        off.translation.y,
        off.translation.z,
        0.0,
        -off.translation.x,
        -off.translation.y,
        off.translation.x,
        0.0,
    );
    let rpx = -rt * px;
    // in place, column by column: (lin, ang) -> (R^T lin - R^T [p]x ang, R^T ang)
    for mut col in out.column_iter_mut() {
        let lin = nalgebra::Vector3::new(col[0], col[1], col[2]);
        let ang = nalgebra::Vector3::new(col[3], col[4], col[5]);
        if lin.iter().chain(ang.iter()).all(|&v| v == 0.0) {
            continue; // not on the contact's chain: stays exactly zero
        }
        let l = rt * lin + rpx * ang;
        let a = rt * ang;
        for i in 0..3 {
            col[i] = l[i];
            col[3 + i] = a[i];
        }
    }
    Ok(())
}

/// The retiming's bounding box of `(u, x)` ([`Tolerances::max_u`], [`Tolerances::max_x`]).
fn solver_box(tol: &Tolerances) -> Box2 {
    Box2 {
        u_lo: -tol.max_u,
        u_hi: tol.max_u,
        x_lo: 0.0,
        x_hi: tol.max_x,
    }
}

/// Whether a row is a joint velocity limit (a bound on `x`).
fn is_velocity(o: &RowOrigin) -> bool {
    matches!(o, RowOrigin::Limit(t) if t.kind == LimitKind::Velocity)
}

/// A side's explicit rows pruned and sorted: drops the acceleration and torque rows
/// (`rows[first..]`, with their origins) that no state within the bounding box of the other
/// rows (`rows[..first]` and the velocity rows) can reach, `max over the box of a u + b x + c
/// < 0` with a margin (exact, since the box is implied by rows that are kept; it spares the
/// retiming most joints' rows, those of joints far from their limits), then moves the rows
/// redundant at the side's polygon behind the others ([`drop_redundant`]) and returns how many
/// come first.
///
/// One polygon serves both: the box is that of the polygon clipped by the other rows, which
/// is then clipped by the acceleration and torque rows kept. When that polygon is empty (or a
/// row is not finite) nothing is dropped and every row comes first, for the diagnosis.
pub(crate) fn prune_and_drop_redundant(
    rows: &mut Vec<Row>,
    origins: &mut Vec<RowOrigin>,
    first: usize,
    ws: &mut LimitWorkspace,
) -> usize {
    let bbox = solver_box(&Tolerances::default());
    let facets = &mut ws.facets.0;
    let bounding = rows[..first].iter().chain(
        rows[first..]
            .iter()
            .zip(&origins[first..])
            .filter(|(_, o)| is_velocity(o))
            .map(|(r, _)| r),
    );
    let Some(b) = (facets.start(bbox) && facets.clip_all(bounding))
        .then(|| facets.bounds())
        .flatten()
    else {
        return rows.len();
    };
    // slightly enlarged, within the solver's box
    let pad = |lo: f64, hi: f64| 1e-6 * (hi - lo).abs().max(lo.abs()).max(hi.abs()) + 1e-9;
    let (pu, px) = (pad(b.u_lo, b.u_hi), pad(b.x_lo, b.x_hi));
    let b = Box2 {
        u_lo: (b.u_lo - pu).max(bbox.u_lo),
        u_hi: (b.u_hi + pu).min(bbox.u_hi),
        x_lo: (b.x_lo - px).max(bbox.x_lo),
        x_hi: (b.x_hi + px).min(bbox.x_hi),
    };
    let mut j = first;
    for i in first..rows.len() {
        let r = rows[i];
        let velocity = is_velocity(&origins[i]);
        let top = (r.a * b.u_lo).max(r.a * b.u_hi) + (r.b * b.x_lo).max(r.b * b.x_hi) + r.c;
        let scale =
            (r.a * b.u_lo).abs().max((r.a * b.u_hi).abs()) + (r.b * b.x_hi).abs() + r.c.abs();
        if velocity || top >= -1e-9 * scale {
            rows[j] = r;
            origins[j] = origins[i];
            j += 1;
        }
    }
    rows.truncate(j);
    origins.truncate(j);
    let kept_limits = rows[first..]
        .iter()
        .zip(&origins[first..])
        .filter(|(_, o)| !is_velocity(o))
        .map(|(r, _)| r);
    if !ws.facets.0.clip_all(kept_limits) {
        return rows.len();
    }
    let (facets, redundant, _) = &mut ws.facets;
    match facets.mark_redundant(rows, bbox, redundant) {
        Some(0) | None => rows.len(),
        Some(_) => move_redundant_behind(rows, origins, ws),
    }
}

/// Moves the rows of a side that are redundant at its own polygon
/// ([`stance_topp::facets`]) behind the others, with their origins, and returns how many rows
/// come first (all of them when the polygon is empty, or not bounded by the rows themselves
/// within the solver's box: then nothing is left out). The grid's LPs read the first rows
/// only; the samples' checks read them all.
pub(crate) fn drop_redundant(
    rows: &mut [Row],
    origins: &mut [RowOrigin],
    ws: &mut LimitWorkspace,
) -> usize {
    let n = rows.len();
    let b = solver_box(&Tolerances::default());
    let (facets, redundant, _) = &mut ws.facets;
    match redundant_rows(rows, b, facets, redundant) {
        Some(0) | None => n,
        Some(_) => move_redundant_behind(rows, origins, ws),
    }
}

/// Moves the rows marked redundant in the workspace behind the others, keeping the order of
/// each part, with their origins; returns how many come first.
fn move_redundant_behind(
    rows: &mut [Row],
    origins: &mut [RowOrigin],
    ws: &mut LimitWorkspace,
) -> usize {
    let n = rows.len();
    let (_, redundant, buf) = &mut ws.facets;
    buf.clear();
    buf.extend(rows.iter().copied().zip(origins.iter().copied()));
    let (mut front, mut back) = (0, n - redundant.iter().filter(|r| **r).count());
    let kept = back;
    for (&(r, o), &red) in buf.iter().zip(redundant.iter()) {
        let at = if red { &mut back } else { &mut front };
        rows[*at] = r;
        origins[*at] = o;
        *at += 1;
    }
    kept
}
