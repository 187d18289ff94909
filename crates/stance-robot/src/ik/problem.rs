//! The IK step's QP assembled in a reusable workspace, and its solve (see the parent module for
//! the math).

use nalgebra::{DMatrix, DVector, Matrix6xX, Vector3};

use super::clarabel_qp::solve_ik_qp;
use super::dense_qp::{DenseQpOptions, DenseQpStatus, DenseQpWorkspace};
use super::{
    check_options, IkAnswerFrom, IkOptions, IkQp, IkSolver, IkStatus, IkStep, JointBounds,
    LinkTarget, PointReference,
};
use crate::centroidal::centroidal_map_dot_v;
use crate::data::Data;
use crate::error::RobotError;
use crate::kinematics::{
    frame_classical_acceleration, frame_jacobian, frame_placement, ReferenceFrame,
};
use crate::model::{JointKind, Model};
use crate::spatial::Pose;

/// A contact frame held by the IK: its velocity kept at zero and, with a target placement and
/// [`IkOptions::contact_k_p`] `> 0`, its placement pulled back onto the target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactHold {
    /// Frame index (see [`Model::frame_id`]).
    pub frame: usize,
    /// `world_from_frame*`, the placement the contact must keep (optional).
    pub target: Option<Pose>,
}

impl ContactHold {
    /// Holds `frame` by its velocity only.
    ///
    /// ```
    /// assert!(stance_robot::ContactHold::velocity(3).target.is_none());
    /// ```
    pub fn velocity(frame: usize) -> Self {
        Self {
            frame,
            target: None,
        }
    }
}

/// A clearance the IK keeps (module doc of [`crate::ik`]): the point `point` (world) of the body
/// of joint `joint` is at signed distance `distance` from an obstacle along the unit `normal`
/// (world, from the body towards the obstacle); the step keeps `distance >= min_distance`
/// through the clearance damper.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DistanceBound {
    /// The joint whose body carries the point (model index).
    pub joint: usize,
    /// The witness point on the body (m, world).
    pub point: Vector3<f64>,
    /// Unit normal from the body towards the obstacle (world).
    pub normal: Vector3<f64>,
    /// Signed distance (m; negative: penetration).
    pub distance: f64,
    /// The distance to keep (m).
    pub min_distance: f64,
}

/// What an IK step tracks and holds.
#[derive(Debug, Clone, Copy)]
pub struct IkTasks<'a> {
    /// Contact frames held fixed (equality constraints).
    pub contacts: &'a [ContactHold],
    /// The CoM reference.
    pub com: PointReference,
    /// Free link tasks (weighted).
    pub links: &'a [LinkTarget],
    /// Free link tasks held as equality constraints (the desired task acceleration exactly; for
    /// example a link about to land, whose arrival at rest must not be traded for the CoM).
    pub hard_links: &'a [LinkTarget],
    /// A reference configuration for the posture task (`nq` entries; only the revolute and
    /// prismatic joints are tracked, with weight [`IkOptions::w_posture`]).
    pub posture: Option<&'a [f64]>,
    /// Clearances to keep (inequality rows).
    pub distances: &'a [DistanceBound],
}

/// Reusable buffers of the IK step: the QP's matrices, the frame Jacobian and the dense solver's
/// working set (the warm start of the next step). Sized for one model.
#[derive(Debug, Clone)]
pub struct IkWorkspace {
    nv: usize,
    jac: Matrix6xX<f64>,
    p: DMatrix<f64>,
    c: DVector<f64>,
    a_eq: DMatrix<f64>,
    b_eq: DVector<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    /// Clearance rows `G x <= h`.
    g_rows: DMatrix<f64>,
    h_rows: DVector<f64>,
    dense: DenseQpWorkspace,
}

impl IkWorkspace {
    /// Buffers for `model`.
    ///
    /// ```
    /// use stance_robot::{IkWorkspace, Model};
    /// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
    /// let ws = IkWorkspace::new(&m);
    /// # let _ = ws;
    /// ```
    pub fn new(model: &Model) -> Self {
        let nv = model.nv;
        Self {
            nv,
            jac: Matrix6xX::zeros(nv),
            p: DMatrix::zeros(nv, nv),
            c: DVector::zeros(nv),
            a_eq: DMatrix::zeros(0, nv),
            b_eq: DVector::zeros(0),
            lo: vec![f64::NEG_INFINITY; nv],
            hi: vec![f64::INFINITY; nv],
            g_rows: DMatrix::zeros(0, nv),
            h_rows: DVector::zeros(0),
            dense: DenseQpWorkspace::new(),
        }
    }

    /// Assembles the QP of one step at `(q, q_s)` for a path step `ds > 0`; afterwards `data`
    /// holds the kinematics, CoM and centroidal map of `q` (velocities `q_s`).
    ///
    /// ```
    /// use stance_robot::{ContactHold, Data, IkOptions, IkTasks, IkWorkspace, Model, PointReference};
    /// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
    /// let (mut ws, mut d) = (IkWorkspace::new(&m), Data::new(&m));
    /// let feet = [ContactHold::velocity(m.frame_id("r_sole").unwrap()),
    ///             ContactHold::velocity(m.frame_id("l_sole").unwrap())];
    /// let tasks = IkTasks { contacts: &feet, com: PointReference::hold(nalgebra::Vector3::zeros()),
    ///                       links: &[], hard_links: &[], posture: None, distances: &[] };
    /// ws.build(&m, &mut d, &m.neutral(), &vec![0.0; m.nv], &tasks, 0.01, &IkOptions::default()).unwrap();
    /// assert_eq!(ws.qp().a_eq.nrows(), 12);
    /// ```
    #[allow(clippy::too_many_arguments)]
    pub fn build(
        &mut self,
        model: &Model,
        data: &mut Data,
        q: &[f64],
        q_s: &[f64],
        tasks: &IkTasks,
        ds: f64,
        options: &IkOptions,
    ) -> Result<(), RobotError> {
        self.check_inputs(model, tasks, ds, options)?;
        let dh = centroidal_map_dot_v(model, data, q, q_s)?;
        // objective: 2 eps I, then the weighted tasks
        self.p.fill(0.0);
        self.p.fill_diagonal(2.0 * options.regularization);
        self.c.fill(0.0);
        self.add_com_task(data, q_s, &tasks.com, &dh, options);
        for l in tasks.links {
            self.add_link_task(model, data, q_s, l, options)?;
        }
        if let (Some(post), true) = (tasks.posture, options.w_posture > 0.0) {
            self.add_posture_task(model, q, q_s, post, options);
        }
        // equations: contacts, then hard link tasks
        self.equation_rows(model, data, q_s, tasks, options)?;
        self.clearance_rows(
            model,
            data,
            q_s,
            tasks.distances,
            ds,
            options.clearance_gain,
        )?;
        self.joint_bounds(model, q, q_s, ds, options);
        Ok(())
    }

    /// The checks of [`Self::build`]'s inputs before anything is assembled: the options, this
    /// workspace's model, a finite positive `ds`, finite task references, known frames and a
    /// valid posture configuration.
    fn check_inputs(
        &self,
        model: &Model,
        tasks: &IkTasks,
        ds: f64,
        options: &IkOptions,
    ) -> Result<(), RobotError> {
        check_options(options)?;
        if self.nv != model.nv {
            return Err(RobotError::Dimension {
                what: "IK workspace (made for another model: use IkWorkspace::new(&model))",
                expected: model.nv,
                got: self.nv,
            });
        }
        if !(ds.is_finite() && ds > 0.0) {
            return Err(RobotError::InvalidOption {
                name: "ds",
                reason: format!("the path step {ds} must be finite and > 0"),
            });
        }
        let refs_finite = std::iter::once(&tasks.com)
            .chain(tasks.links.iter().map(|l| &l.reference))
            .chain(tasks.hard_links.iter().map(|l| &l.reference))
            .all(|r| {
                r.p.iter()
                    .chain(r.p_s.iter())
                    .chain(r.p_ss.iter())
                    .all(|x| x.is_finite())
            });
        if !refs_finite {
            return Err(RobotError::InvalidOption {
                name: "reference",
                reason: "a task reference is not finite".into(),
            });
        }
        for f in tasks
            .contacts
            .iter()
            .map(|c| c.frame)
            .chain(tasks.links.iter().map(|l| l.frame))
            .chain(tasks.hard_links.iter().map(|l| l.frame))
        {
            if f >= model.frames.len() {
                return Err(RobotError::UnknownFrame(format!("#{f}")));
            }
        }
        if let Some(post) = tasks.posture {
            crate::kinematics::check_configuration(model, post)?;
        }
        Ok(())
    }

    /// The CoM task `w_com |J_com x + Jd_com q_s - pdd_com*|^2` (module doc) added to the
    /// objective: the CoM drift `Jd_com q_s` is the linear part of the centroidal momentum
    /// rate `dh` (`A_g`-dot `q_s`, from [`centroidal_map_dot_v`]) divided by the mass.
    fn add_com_task(
        &mut self,
        data: &Data,
        q_s: &[f64],
        com: &PointReference,
        dh: &nalgebra::Vector6<f64>,
        options: &IkOptions,
    ) {
        let j_com = &data.com_jacobian;
        let com_s = row_dot(j_com, q_s);
        let drift_com = Vector3::new(dh[0], dh[1], dh[2]) / data.mass;
        let desired = com.p_ss + (com.p_s - com_s) * options.k_d + (com.p - data.com) * options.k_p;
        add_task(
            &mut self.p,
            &mut self.c,
            j_com,
            &(desired - drift_com),
            options.w_com,
        );
    }

    /// A link task `w_link |J_l x + Jd_l q_s - pdd_l*|^2` (and its orientation part, with the
    /// same weight) added to the objective.
    fn add_link_task(
        &mut self,
        model: &Model,
        data: &Data,
        q_s: &[f64],
        l: &LinkTarget,
        options: &IkOptions,
    ) -> Result<(), RobotError> {
        let (lin, ang) = self.link_rows(model, data, q_s, l, options)?;
        let j_lin = self.jac.fixed_rows::<3>(0);
        add_task(&mut self.p, &mut self.c, &j_lin, &lin, options.w_link);
        if let Some(ang) = ang {
            let j_ang = self.jac.fixed_rows::<3>(3);
            add_task(&mut self.p, &mut self.c, &j_ang, &ang, options.w_link);
        }
        Ok(())
    }

    /// The posture task `w_posture |x_j - xdd_j*|^2` on the revolute and prismatic joints,
    /// `xdd_j* = -K_d q_s,j + K_p (q*_j - q_j)`: `2 w_posture` on the diagonal of `P` and
    /// `-2 w_posture xdd_j*` in `c`.
    fn add_posture_task(
        &mut self,
        model: &Model,
        q: &[f64],
        q_s: &[f64],
        post: &[f64],
        options: &IkOptions,
    ) {
        let w2 = 2.0 * options.w_posture;
        for j in &model.joints[1..] {
            if matches!(
                j.kind,
                JointKind::Revolute { .. } | JointKind::Prismatic { .. }
            ) {
                let desired =
                    -options.k_d * q_s[j.idx_v] + options.k_p * (post[j.idx_q] - q[j.idx_q]);
                self.p[(j.idx_v, j.idx_v)] += w2;
                self.c[j.idx_v] -= w2 * desired;
            }
        }
    }

    /// The equations `A_eq x = b_eq`: per contact frame the 6 rows
    /// `J_c x = -Jd_c q_s - gamma J_c q_s + k_c e_c` (`e_c` the placement error when the hold
    /// has a target and `k_c > 0`, else 0), then per hard link task its 3 (or 6, with an
    /// orientation) rows `J_h x = pdd_h* - Jd_h q_s`.
    fn equation_rows(
        &mut self,
        model: &Model,
        data: &Data,
        q_s: &[f64],
        tasks: &IkTasks,
        options: &IkOptions,
    ) -> Result<(), RobotError> {
        let nv = model.nv;
        let rows = 6 * tasks.contacts.len()
            + tasks
                .hard_links
                .iter()
                .map(|l| if l.orientation.is_some() { 6 } else { 3 })
                .sum::<usize>();
        if self.a_eq.nrows() != rows {
            self.a_eq = DMatrix::zeros(rows, nv);
            self.b_eq = DVector::zeros(rows);
        }
        for (i, hold) in tasks.contacts.iter().enumerate() {
            frame_jacobian(
                model,
                data,
                hold.frame,
                ReferenceFrame::LocalWorldAligned,
                &mut self.jac,
            )?;
            let (lin, ang) = frame_classical_acceleration(
                model,
                data,
                hold.frame,
                ReferenceFrame::LocalWorldAligned,
            )?;
            let mut error = [0.0; 6];
            if let (Some(target), true) = (hold.target, options.contact_k_p > 0.0) {
                let x = frame_placement(model, data, hold.frame)?;
                let dp = target.translation - x.translation;
                let dr = rotation_error(&target.rotation, &x.rotation);
                error = [dp.x, dp.y, dp.z, dr.x, dr.y, dr.z];
            }
            for r in 0..6 {
                let mut vel = 0.0;
                for (k, v) in q_s.iter().enumerate() {
                    let jk = self.jac[(r, k)];
                    self.a_eq[(6 * i + r, k)] = jk;
                    vel += jk * v;
                }
                let drift = if r < 3 { lin[r] } else { ang[r - 3] };
                self.b_eq[6 * i + r] =
                    -drift - options.gamma * vel + options.contact_k_p * error[r];
            }
        }
        let mut row = 6 * tasks.contacts.len();
        for l in tasks.hard_links {
            let (lin, ang) = self.link_rows(model, data, q_s, l, options)?;
            let targets = [Some(lin), ang];
            for (block, target) in targets.iter().enumerate() {
                let Some(t) = target else { continue };
                for r in 0..3 {
                    for k in 0..nv {
                        self.a_eq[(row, k)] = self.jac[(3 * block + r, k)];
                    }
                    self.b_eq[row] = t[r];
                    row += 1;
                }
            }
        }
        Ok(())
    }

    /// The clearance rows `G x <= h` (module doc):
    /// `n^T J_p x <= min(K^2 (d - d_min) + 2 K d_s, 2 (d + d_s ds) / ds^2) - n^T a_p`, with
    /// `n^T J_p` summed along the joint's chain to the root (`n . (s_lin + s_ang x p)` per
    /// velocity coordinate), `d_s = -n^T J_p q_s` and `a_p` the point's classical acceleration
    /// at `x = 0`. A bound on an unknown joint or with a value that is not finite is an error.
    fn clearance_rows(
        &mut self,
        model: &Model,
        data: &Data,
        q_s: &[f64],
        distances: &[DistanceBound],
        ds: f64,
        gain: f64,
    ) -> Result<(), RobotError> {
        let nv = model.nv;
        if self.g_rows.nrows() != distances.len() {
            self.g_rows = DMatrix::zeros(distances.len(), nv);
            self.h_rows = DVector::zeros(distances.len());
        }
        for (r, b) in distances.iter().enumerate() {
            if b.joint >= model.joints.len()
                || ![b.distance, b.min_distance]
                    .iter()
                    .chain(b.point.iter())
                    .chain(b.normal.iter())
                    .all(|x| x.is_finite())
            {
                return Err(RobotError::InvalidOption {
                    name: "distances",
                    reason: format!(
                        "clearance row {r}: joint {} of {}, or a value that is not finite",
                        b.joint,
                        model.joints.len()
                    ),
                });
            }
            let mut row = self.g_rows.row_mut(r);
            row.fill(0.0);
            let mut i = b.joint;
            while i != 0 {
                let j = &model.joints[i];
                for k in j.idx_v..j.idx_v + j.dims().1 {
                    let (sl, sa) = data.s_world[k];
                    row[k] = b.normal.dot(&(sl + sa.cross(&b.point)));
                }
                i = j.parent;
            }
            let d_s = -(0..nv).map(|k| row[k] * q_s[k]).sum::<f64>();
            let (v_o, w) = data.velocity[b.joint];
            let (a_o, alpha) = data.drift[b.joint];
            let p_dot = v_o + w.cross(&b.point);
            let a_p = a_o + alpha.cross(&b.point) + w.cross(&p_dot);
            let n_a = b.normal.dot(&a_p);
            let damper = gain * gain * (b.distance - b.min_distance) + 2.0 * gain * d_s - n_a;
            let next_step = 2.0 * (b.distance + d_s * ds) / (ds * ds) - n_a;
            self.h_rows[r] = damper.min(next_step);
        }
        Ok(())
    }

    /// The joint bounds `lo <= x <= hi` (boxes on single coordinates, module doc): for
    /// revolute and prismatic joints the bounds of [`joint_box`], for all of them, continuous
    /// joints included, the rate bound `-r_max <= q_s + x ds <= r_max` when
    /// [`IkOptions::max_path_rate`] is finite; an infinite (or NaN) bound is no bound.
    fn joint_bounds(
        &mut self,
        model: &Model,
        q: &[f64],
        q_s: &[f64],
        ds: f64,
        options: &IkOptions,
    ) {
        self.lo.fill(f64::NEG_INFINITY);
        self.hi.fill(f64::INFINITY);
        for j in &model.joints[1..] {
            if matches!(j.kind, JointKind::Continuous { .. }) && options.max_path_rate.is_finite() {
                // no position limits; the rate bound as for the others
                let (k, vj) = (j.idx_v, q_s[j.idx_v]);
                self.lo[k] = -(options.max_path_rate + vj) / ds;
                self.hi[k] = (options.max_path_rate - vj) / ds;
            }
            if !matches!(
                j.kind,
                JointKind::Revolute { .. } | JointKind::Prismatic { .. }
            ) {
                continue;
            }
            let (k, vj) = (j.idx_v, q_s[j.idx_v]);
            let (lo, hi) = joint_box(j.lower, j.upper, q[j.idx_q], vj, ds, options.joint_bounds);
            // an infinite limit gives an infinite (or NaN, for inf - inf) bound: no bound
            self.lo[k] = if lo.is_finite() {
                lo
            } else {
                f64::NEG_INFINITY
            };
            self.hi[k] = if hi.is_finite() { hi } else { f64::INFINITY };
            if options.max_path_rate.is_finite() {
                self.lo[k] = self.lo[k].max(-(options.max_path_rate + vj) / ds);
                self.hi[k] = self.hi[k].min((options.max_path_rate - vj) / ds);
            }
        }
    }

    /// A link task's Jacobian (left in `self.jac`) and its desired accelerations minus drifts:
    /// `J_lin x = lin` (and `J_ang x = ang` with an orientation task).
    fn link_rows(
        &mut self,
        model: &Model,
        data: &Data,
        q_s: &[f64],
        l: &LinkTarget,
        options: &IkOptions,
    ) -> Result<(Vector3<f64>, Option<Vector3<f64>>), RobotError> {
        frame_jacobian(
            model,
            data,
            l.frame,
            ReferenceFrame::LocalWorldAligned,
            &mut self.jac,
        )?;
        let (lin_drift, ang_drift) =
            frame_classical_acceleration(model, data, l.frame, ReferenceFrame::LocalWorldAligned)?;
        let placement = frame_placement(model, data, l.frame)?;
        let vel = row_dot(&self.jac.fixed_rows::<3>(0), q_s);
        let r = &l.reference;
        let lin =
            r.p_ss + (r.p_s - vel) * options.k_d + (r.p - placement.translation) * options.k_p
                - lin_drift;
        let ang = l.orientation.as_ref().map(|o| {
            let w = row_dot(&self.jac.fixed_rows::<3>(3), q_s);
            let error = rotation_error(&o.rotation, &placement.rotation);
            o.w_ss + (o.w_s - w) * options.k_d + error * options.k_p - ang_drift
        });
        Ok((lin, ang))
    }

    /// Solves the assembled QP (dense solver with Clarabel as fallback, or as asked by
    /// [`IkOptions::solver`]).
    ///
    /// ```
    /// use stance_robot::{ContactHold, Data, IkAnswerFrom, IkOptions, IkStatus, IkTasks,
    ///     IkWorkspace, Model, PointReference};
    /// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
    /// let (mut ws, mut d) = (IkWorkspace::new(&m), Data::new(&m));
    /// let feet = [ContactHold::velocity(m.frame_id("r_sole").unwrap()),
    ///             ContactHold::velocity(m.frame_id("l_sole").unwrap())];
    /// let q = m.neutral();
    /// let c0 = stance_robot::center_of_mass(&m, &mut d, &q).unwrap();
    /// let tasks = IkTasks { contacts: &feet, links: &[], hard_links: &[], posture: None,
    ///     distances: &[], com: PointReference::hold(c0 + nalgebra::Vector3::new(0.0, 0.0, -0.01)) };
    /// let o = IkOptions::default();
    /// ws.build(&m, &mut d, &q, &vec![0.0; m.nv], &tasks, 0.01, &o).unwrap();
    /// let step = ws.solve(&o).unwrap();
    /// assert_eq!((step.status, step.answer_from), (IkStatus::Solved, IkAnswerFrom::Dense));
    /// assert!(step.contact_residual < 1e-9);
    /// ```
    pub fn solve(&mut self, options: &IkOptions) -> Result<IkStep, RobotError> {
        let step = self.solve_rows(options)?;
        if step.status == IkStatus::Solved || self.g_rows.nrows() == 0 {
            return Ok(step);
        }
        // the clearances cannot all be kept: solve without them (module doc)
        self.g_rows = DMatrix::zeros(0, self.nv);
        self.h_rows = DVector::zeros(0);
        let mut step = self.solve_rows(options)?;
        step.clearance_dropped = true;
        Ok(step)
    }

    fn solve_rows(&mut self, options: &IkOptions) -> Result<IkStep, RobotError> {
        let nv = self.nv;
        if self.lo.iter().zip(&self.hi).any(|(l, h)| l > h) {
            // A joint's bounds cross (it is past a limit faster than the bounds allow).
            return Ok(IkStep {
                status: IkStatus::Infeasible,
                q_ss: vec![0.0; nv],
                contact_residual: 0.0,
                bound_violation: 0.0,
                clearance_dropped: false,
                answer_from: IkAnswerFrom::Dense,
            });
        }
        if options.solver == IkSolver::Dense {
            let rep = self.dense.solve_with_rows(
                &self.p,
                &self.c,
                &self.a_eq,
                &self.b_eq,
                &self.g_rows,
                &self.h_rows,
                &self.lo,
                &self.hi,
                &DenseQpOptions::default(),
            );
            if rep.status == DenseQpStatus::Optimal {
                return Ok(IkStep {
                    status: IkStatus::Solved,
                    q_ss: self.dense.solution().to_vec(),
                    contact_residual: rep.equality_residual,
                    bound_violation: rep.bound_violation.max(0.0),
                    clearance_dropped: false,
                    answer_from: IkAnswerFrom::Dense,
                });
            }
            self.dense.reset();
        }
        solve_ik_qp(&self.qp(), options.qp_tol)
    }

    /// [`Self::build`] then [`Self::solve`].
    ///
    /// ```
    /// use stance_robot::{ContactHold, Data, IkOptions, IkStatus, IkTasks, IkWorkspace, Model,
    ///     PointReference};
    /// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
    /// let (mut ws, mut d) = (IkWorkspace::new(&m), Data::new(&m));
    /// let tasks = IkTasks { contacts: &[], links: &[], hard_links: &[], posture: None,
    ///     distances: &[], com: PointReference::hold(nalgebra::Vector3::zeros()) };
    /// let step = ws.step(&m, &mut d, &m.neutral(), &vec![0.0; m.nv], &tasks, 0.01,
    ///     &IkOptions::default()).unwrap();
    /// assert_eq!(step.status, IkStatus::Solved);
    /// ```
    #[allow(clippy::too_many_arguments)]
    pub fn step(
        &mut self,
        model: &Model,
        data: &mut Data,
        q: &[f64],
        q_s: &[f64],
        tasks: &IkTasks,
        ds: f64,
        options: &IkOptions,
    ) -> Result<IkStep, RobotError> {
        self.build(model, data, q, q_s, tasks, ds, options)?;
        self.solve(options)
    }

    /// The assembled QP in the dense form of [`IkQp`] (allocates; for inspection and the
    /// Clarabel route).
    ///
    /// ```
    /// use stance_robot::{IkWorkspace, Model};
    /// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
    /// assert_eq!(IkWorkspace::new(&m).qp().p.nrows(), m.nv);
    /// ```
    pub fn qp(&self) -> IkQp {
        let nv = self.nv;
        let mut rows: Vec<(usize, f64, f64)> = Vec::new();
        for k in 0..nv {
            if self.hi[k].is_finite() {
                rows.push((k, 1.0, self.hi[k]));
            }
            if self.lo[k].is_finite() {
                rows.push((k, -1.0, -self.lo[k]));
            }
        }
        let nb = rows.len();
        let mut g = DMatrix::zeros(nb + self.g_rows.nrows(), nv);
        let mut h = DVector::zeros(nb + self.g_rows.nrows());
        for (r, (k, sign, bound)) in rows.into_iter().enumerate() {
            g[(r, k)] = sign;
            h[r] = bound;
        }
        for r in 0..self.g_rows.nrows() {
            g.row_mut(nb + r).copy_from(&self.g_rows.row(r));
            h[nb + r] = self.h_rows[r];
        }
        IkQp {
            p: self.p.clone(),
            c: self.c.clone(),
            a_eq: self.a_eq.clone(),
            b_eq: self.b_eq.clone(),
            g,
            h,
        }
    }
}

/// The position bounds on `x` of a joint at `q` (velocity `q_s`) with limits
/// `[lower, upper]` over a path step `ds` (module doc, [`JointBounds`]): the next-step bounds
/// `2 (limit - q - q_s ds) / ds^2` at the step's end, tightened by
/// `(limit - q - 1.5 q_s ds) / ds^2` within the step (keeping `q + q_s ds / 2` within the limits,
/// and relaxed to the end bound where the state breaks it); with the damper, its bounds
/// `K_ss (K_s (limit' - q) - q_s)` on the shrunk range, within the next-step bounds, unless
/// they cross.
fn joint_box(lower: f64, upper: f64, qj: f64, vj: f64, ds: f64, bounds: JointBounds) -> (f64, f64) {
    let scale = 2.0 / (ds * ds);
    let mut next_step = (
        scale * (lower - qj - vj * ds),
        scale * (upper - qj - vj * ds),
    );
    // within the step: a joint that turns back before its end peaks below
    // q + q_s ds / 2, so keeping q + q_s ds / 2 within the limits at every sample keeps
    // the whole step within them; at the step's end that is
    // q + 1.5 q_s ds + x ds^2 within the limits (the QP stays feasible from a state
    // that breaks it: the bound then only asks for the other end's)
    let viable = (
        (lower - qj - 1.5 * vj * ds) / (ds * ds),
        (upper - qj - 1.5 * vj * ds) / (ds * ds),
    );
    next_step = (
        next_step.0.max(viable.0.min(next_step.1)),
        next_step.1.min(viable.1.max(next_step.0)),
    );
    match bounds {
        JointBounds::NextStep => next_step,
        JointBounds::Damper { k_s, k_ss, range } => {
            let (mid, half) = (0.5 * (upper + lower), 0.5 * (upper - lower));
            let (lower, upper) = (mid - range * half, mid + range * half);
            // the damper may overshoot its shrunk range by about q_s / K_ss: the
            // next-step bound keeps the joint within its true limits meanwhile
            let damped = (
                (k_ss * (k_s * (lower - qj) - vj)).max(next_step.0),
                (k_ss * (k_s * (upper - qj) - vj)).min(next_step.1),
            );
            // where the damper's bounds cross (a joint beyond its shrunk range on one
            // side, driven hard: a soft task out of reach), the true limits alone hold
            // it, instead of making the step infeasible
            if damped.0 <= damped.1 {
                damped
            } else {
                next_step
            }
        }
    }
}

/// `J v` for a 3-row view.
fn row_dot<S>(j: &nalgebra::Matrix<f64, nalgebra::U3, nalgebra::Dyn, S>, v: &[f64]) -> Vector3<f64>
where
    S: nalgebra::storage::Storage<f64, nalgebra::U3, nalgebra::Dyn>,
{
    let mut out = Vector3::zeros();
    for (k, vk) in v.iter().enumerate() {
        out += j.column(k) * *vk;
    }
    out
}

/// The rotation vector of `target R^T` (world axes): the angular error to `target`.
fn rotation_error(target: &nalgebra::Matrix3<f64>, r: &nalgebra::Matrix3<f64>) -> Vector3<f64> {
    crate::spatial::rotation_log(&(target * r.transpose()))
}

/// Adds `w |J x - r|^2` to `x^T P x / 2 + c^T x`, in place: `P += 2 w J^T J`,
/// `c -= 2 w J^T r` (a symmetric rank-3 update, both triangles).
fn add_task<S>(
    p: &mut DMatrix<f64>,
    c: &mut DVector<f64>,
    j: &nalgebra::Matrix<f64, nalgebra::U3, nalgebra::Dyn, S>,
    r: &Vector3<f64>,
    w: f64,
) where
    S: nalgebra::storage::Storage<f64, nalgebra::U3, nalgebra::Dyn>,
{
    if w == 0.0 {
        return;
    }
    let n = p.nrows();
    let w2 = 2.0 * w;
    let data = p.as_mut_slice();
    for b in 0..n {
        let (x, y, z) = (w2 * j[(0, b)], w2 * j[(1, b)], w2 * j[(2, b)]);
        c[b] -= x * r[0] + y * r[1] + z * r[2];
        if x == 0.0 && y == 0.0 && z == 0.0 {
            continue;
        }
        for (a, v) in data[b * n..(b + 1) * n].iter_mut().enumerate() {
            *v += x * j[(0, a)] + y * j[(1, a)] + z * j[(2, a)];
        }
    }
}

fn velocity_holds(contacts: &[usize]) -> Vec<ContactHold> {
    contacts.iter().map(|&f| ContactHold::velocity(f)).collect()
}

/// The tasks of [`ik_qp`] and [`ik_step`]: contacts held by their velocities, no posture.
fn plain_tasks<'a>(
    holds: &'a [ContactHold],
    com: &PointReference,
    links: &'a [LinkTarget],
) -> IkTasks<'a> {
    IkTasks {
        contacts: holds,
        com: *com,
        links,
        hard_links: &[],
        posture: None,
        distances: &[],
    }
}

/// Builds the IK QP at `(q, q_s)` (see the module doc) for a step `ds > 0`, with the contacts
/// held by their velocities.
///
/// ```
/// use stance_robot::{ik_qp, Data, IkOptions, Model, PointReference};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let mut d = Data::new(&m);
/// let q = m.neutral();
/// let feet = [m.frame_id("r_sole").unwrap(), m.frame_id("l_sole").unwrap()];
/// let com = PointReference { p: nalgebra::Vector3::zeros(), p_s: nalgebra::Vector3::zeros(),
///                            p_ss: nalgebra::Vector3::zeros() };
/// let qp = ik_qp(&m, &mut d, &q, &vec![0.0; m.nv], &feet, &com, &[], 0.01, &IkOptions::default()).unwrap();
/// assert_eq!(qp.a_eq.nrows(), 12);
/// assert_eq!(qp.p.nrows(), m.nv);
/// ```
#[allow(clippy::too_many_arguments)]
pub fn ik_qp(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    q_s: &[f64],
    contacts: &[usize],
    com: &PointReference,
    links: &[LinkTarget],
    ds: f64,
    options: &IkOptions,
) -> Result<IkQp, RobotError> {
    let holds = velocity_holds(contacts);
    let mut ws = IkWorkspace::new(model);
    ws.build(
        model,
        data,
        q,
        q_s,
        &plain_tasks(&holds, com, links),
        ds,
        options,
    )?;
    Ok(ws.qp())
}

/// One IK step: [`ik_qp`] then its solve ([`IkWorkspace::solve`]).
///
/// ```
/// use stance_robot::{ik_step, Data, IkOptions, IkStatus, Model, PointReference};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let mut d = Data::new(&m);
/// let q = m.neutral();
/// let feet = [m.frame_id("r_sole").unwrap(), m.frame_id("l_sole").unwrap()];
/// let c0 = stance_robot::center_of_mass(&m, &mut d, &q).unwrap();
/// let com = PointReference::segment(c0, c0 + nalgebra::Vector3::new(0.0, 0.03, 0.0), 0.0);
/// let step = ik_step(&m, &mut d, &q, &vec![0.0; m.nv], &feet, &com, &[], 0.01, &IkOptions::default()).unwrap();
/// assert_eq!(step.status, IkStatus::Solved);
/// assert!(step.contact_residual < 1e-6);
/// ```
#[allow(clippy::too_many_arguments)]
pub fn ik_step(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    q_s: &[f64],
    contacts: &[usize],
    com: &PointReference,
    links: &[LinkTarget],
    ds: f64,
    options: &IkOptions,
) -> Result<IkStep, RobotError> {
    let holds = velocity_holds(contacts);
    let tasks = plain_tasks(&holds, com, links);
    IkWorkspace::new(model).step(model, data, q, q_s, &tasks, ds, options)
}
