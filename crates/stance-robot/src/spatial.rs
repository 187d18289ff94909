//! Spatial algebra: rigid placements, 6-D motion and force vectors, rigid-body inertias.
//!
//! # Conventions (Pinocchio's)
//!
//! - A placement `a_from_b = (R, t)` maps coordinates in frame `b` to frame `a`:
//!   `x_a = R x_b + t`. Composition: `a_from_c = a_from_b * b_from_c`.
//! - A motion (twist) is `(v, w)`, **linear first**; expressed "at a point `o`" its linear part is
//!   the velocity of the material point that coincides with `o`. The spatial velocity of a body in
//!   the world frame (Pinocchio's `WORLD`) is taken at the world origin: `v_O = v_P + w x (O - P)`.
//! - A force (momentum, wrench) is `(f, n)`, linear first, with the moment about a stated point.
//! - Cross products: `V1 x V2 = (w1 x v2 + v1 x w2, w1 x w2)` on motions and
//!   `V x* F = (w x f + 0, w x n + v x f)` on forces.
//! - A rigid body's inertia about the world origin, in world axes, is stored compactly as
//!   `(m, h = m c, I_O)` with `c` the CoM and `I_O = sum m_j [r_j]^T [r_j]` the rotational inertia
//!   about the origin; applied to a motion `(v, w)` it gives the momentum
//!   `(m v + w x h,  h x v + I_O w)` (linear, angular about the origin).

use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

/// A rigid placement `a_from_b`: `x_a = rotation * x_b + translation`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Rotation matrix (columns: axes of `b` in `a`).
    pub rotation: Matrix3<f64>,
    /// Origin of `b` in `a`.
    pub translation: Vector3<f64>,
}

impl Default for Pose {
    fn default() -> Self {
        Self::identity()
    }
}

impl Pose {
    /// The identity placement.
    ///
    /// ```
    /// let p = stance_robot::Pose::identity();
    /// assert_eq!(p.translation.norm(), 0.0);
    /// ```
    pub fn identity() -> Self {
        Self {
            rotation: Matrix3::identity(),
            translation: Vector3::zeros(),
        }
    }

    /// From URDF `xyz` and `rpy` (fixed-axis roll about x, then pitch about y, then yaw about z:
    /// `R = Rz(yaw) Ry(pitch) Rx(roll)`).
    ///
    /// ```
    /// use stance_robot::Pose;
    /// let p = Pose::from_xyz_rpy([1.0, 2.0, 3.0], [0.0, 0.0, std::f64::consts::FRAC_PI_2]);
    /// let x = p.transform_point(&nalgebra::Vector3::new(1.0, 0.0, 0.0));
    /// assert!((x - nalgebra::Vector3::new(1.0, 3.0, 3.0)).norm() < 1e-15);
    /// ```
    pub fn from_xyz_rpy(xyz: [f64; 3], rpy: [f64; 3]) -> Self {
        Self {
            rotation: rpy_to_matrix(rpy),
            translation: Vector3::from(xyz),
        }
    }

    /// `self * other`.
    ///
    /// ```
    /// use stance_robot::Pose;
    /// let a = Pose::from_xyz_rpy([1.0, 0.0, 0.0], [0.0, 0.0, 0.3]);
    /// let b = Pose::from_xyz_rpy([0.0, 2.0, 0.0], [0.1, 0.0, 0.0]);
    /// let ab = a.compose(&b);
    /// let x = nalgebra::Vector3::new(0.3, -0.2, 0.5);
    /// assert!((ab.transform_point(&x) - a.transform_point(&b.transform_point(&x))).norm() < 1e-15);
    /// ```
    #[inline]
    pub fn compose(&self, other: &Pose) -> Pose {
        Pose {
            rotation: self.rotation * other.rotation,
            translation: self.rotation * other.translation + self.translation,
        }
    }

    /// The inverse placement `b_from_a`.
    ///
    /// ```
    /// use stance_robot::Pose;
    /// let a = Pose::from_xyz_rpy([1.0, 0.5, 0.0], [0.2, -0.1, 0.3]);
    /// let i = a.compose(&a.inverse());
    /// assert!((i.rotation - nalgebra::Matrix3::identity()).norm() < 1e-15);
    /// assert!(i.translation.norm() < 1e-15);
    /// ```
    pub fn inverse(&self) -> Pose {
        let rt = self.rotation.transpose();
        Pose {
            rotation: rt,
            translation: -(rt * self.translation),
        }
    }

    /// `rotation * x + translation`.
    ///
    /// ```
    /// let p = stance_robot::Pose::from_xyz_rpy([0.0, 0.0, 1.0], [0.0; 3]);
    /// assert_eq!(p.transform_point(&nalgebra::Vector3::zeros()).z, 1.0);
    /// ```
    #[inline]
    pub fn transform_point(&self, x: &Vector3<f64>) -> Vector3<f64> {
        self.rotation * x + self.translation
    }
}

/// `Rz(y) Ry(p) Rx(r)` for URDF's `rpy = (r, p, y)`.
pub(crate) fn rpy_to_matrix(rpy: [f64; 3]) -> Matrix3<f64> {
    *Rotation3::from_euler_angles(rpy[0], rpy[1], rpy[2]).matrix()
}

/// The rotation vector `theta * axis` of a rotation matrix (the logarithm of SO(3)), robust to
/// round-off: the angle is `atan2(|vee(R - R^T)| / 2, (tr R - 1) / 2)`, which stays defined for a
/// matrix a few ulps from orthonormal (where `acos((tr R - 1) / 2)` of a trace above 3 is NaN),
/// and near `pi` the axis comes from the symmetric part `(R + I) / 2 = a a^T`.
///
/// ```
/// use nalgebra::{Matrix3, Rotation3, Vector3};
/// use stance_robot::spatial::rotation_log;
/// let w = Vector3::new(0.1, -0.2, 0.3);
/// assert!((rotation_log(Rotation3::new(w).matrix()) - w).norm() < 1e-15);
/// let nearly_identity = Matrix3::identity() * (1.0 + 1e-15);
/// assert!(rotation_log(&nearly_identity).norm() < 1e-14);
/// let half_turn = Vector3::new(0.0, std::f64::consts::PI, 0.0);
/// assert!((rotation_log(Rotation3::new(half_turn).matrix()).abs() - half_turn).norm() < 1e-7);
/// ```
pub fn rotation_log(r: &Matrix3<f64>) -> Vector3<f64> {
    let v = Vector3::new(
        r[(2, 1)] - r[(1, 2)],
        r[(0, 2)] - r[(2, 0)],
        r[(1, 0)] - r[(0, 1)],
    ) * 0.5;
    let s = v.norm();
    let c = 0.5 * (r.trace() - 1.0);
    let theta = s.atan2(c);
    if theta < 1e-8 {
        // first order: R = I + [w]x
        return v;
    }
    if theta < std::f64::consts::PI - 1e-6 {
        return v * (theta / s);
    }
    // near pi: (R + I) / 2 = a a^T (+ O(pi - theta)); the largest diagonal entry's column
    let b = (r + Matrix3::identity()) * 0.5;
    let k = (0..3)
        .max_by(|&i, &j| b[(i, i)].total_cmp(&b[(j, j)]))
        .unwrap_or(0);
    let mut a = b.column(k).into_owned() / b[(k, k)].max(f64::MIN_POSITIVE).sqrt();
    a /= a.norm().max(f64::MIN_POSITIVE);
    // the sign of the axis from the (small) skew part
    if a.dot(&v) < 0.0 {
        a = -a;
    }
    a * theta
}

/// Rotation of angle `angle` about the unit axis `axis` (Rodrigues).
#[inline]
pub(crate) fn axis_angle(axis: &Vector3<f64>, angle: f64) -> Matrix3<f64> {
    let (s, c) = angle.sin_cos();
    axis_cos_sin(axis, c, s)
}

/// Rotation about the unit axis `axis` with the given cosine and sine of the angle.
#[inline]
pub(crate) fn axis_cos_sin(axis: &Vector3<f64>, c: f64, s: f64) -> Matrix3<f64> {
    let k = skew(axis);
    Matrix3::identity() + k * s + k * k * (1.0 - c)
}

/// The skew-symmetric matrix `[a]` with `[a] b = a x b`.
#[inline]
pub(crate) fn skew(a: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -a.z, a.y, a.z, 0.0, -a.x, -a.y, a.x, 0.0)
}

/// Rotation matrix of the unit quaternion `(x, y, z, w)` (already normalized).
#[inline]
pub(crate) fn quaternion_matrix(x: f64, y: f64, z: f64, w: f64) -> Matrix3<f64> {
    let q = UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(w, x, y, z));
    *q.to_rotation_matrix().matrix()
}

/// The SE(3) exponential of a body twist `(v, w)`: the placement reached after moving for unit
/// time with that constant twist (expressed in the moving frame).
pub(crate) fn exp6(v: &Vector3<f64>, w: &Vector3<f64>) -> Pose {
    let theta = w.norm();
    let k = skew(w);
    let k2 = k * k;
    // Below a small angle, the Taylor series (the closed forms divide by powers of theta and
    // `theta - sin theta` cancels); `1 - cos` is computed as `2 sin^2(theta / 2)`, exact to
    // round-off at every angle.
    let (a, b, c) = if theta < crate::tol::EXP_SERIES_ANGLE {
        let t2 = theta * theta;
        (
            1.0 - t2 / 6.0 * (1.0 - t2 / 20.0),
            0.5 - t2 / 24.0 * (1.0 - t2 / 30.0),
            1.0 / 6.0 - t2 / 120.0 * (1.0 - t2 / 42.0),
        )
    } else {
        let (s, half) = (theta.sin(), (0.5 * theta).sin());
        (
            s / theta,
            2.0 * half * half / (theta * theta),
            (theta - s) / (theta * theta * theta),
        )
    };
    let rotation = Matrix3::identity() + k * a + k2 * b;
    let left_jacobian = Matrix3::identity() + k * b + k2 * c;
    Pose {
        rotation,
        translation: left_jacobian * v,
    }
}

/// A rigid body's inertia in its own frame: mass, CoM lever and rotational inertia about the CoM.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inertia {
    /// Mass (kg).
    pub mass: f64,
    /// CoM in the body frame (m).
    pub lever: Vector3<f64>,
    /// Rotational inertia about the CoM, body axes (kg m^2).
    pub inertia_com: Matrix3<f64>,
}

impl Inertia {
    /// Zero inertia.
    ///
    /// ```
    /// assert_eq!(stance_robot::Inertia::zero().mass, 0.0);
    /// ```
    pub fn zero() -> Self {
        Self {
            mass: 0.0,
            lever: Vector3::zeros(),
            inertia_com: Matrix3::zeros(),
        }
    }

    /// The same body seen from frame `a`, given `a_from_body`.
    ///
    /// ```
    /// use stance_robot::{Inertia, Pose};
    /// let i = Inertia { mass: 2.0, lever: nalgebra::Vector3::new(0.1, 0.0, 0.0),
    ///                   inertia_com: nalgebra::Matrix3::identity() };
    /// let j = i.transformed(&Pose::from_xyz_rpy([0.0, 0.0, 1.0], [0.0; 3]));
    /// assert!((j.lever - nalgebra::Vector3::new(0.1, 0.0, 1.0)).norm() < 1e-15);
    /// ```
    pub fn transformed(&self, a_from_body: &Pose) -> Inertia {
        Inertia {
            mass: self.mass,
            lever: a_from_body.transform_point(&self.lever),
            inertia_com: a_from_body.rotation * self.inertia_com * a_from_body.rotation.transpose(),
        }
    }

    /// The sum of two bodies expressed in the same frame (combined mass, CoM, and rotational
    /// inertia about the combined CoM, by the parallel axis theorem).
    ///
    /// ```
    /// use stance_robot::Inertia;
    /// use nalgebra::{Matrix3, Vector3};
    /// let a = Inertia { mass: 1.0, lever: Vector3::new(1.0, 0.0, 0.0), inertia_com: Matrix3::zeros() };
    /// let b = Inertia { mass: 1.0, lever: Vector3::new(-1.0, 0.0, 0.0), inertia_com: Matrix3::zeros() };
    /// let s = a.plus(&b);
    /// assert_eq!(s.mass, 2.0);
    /// assert!((s.inertia_com[(1, 1)] - 2.0).abs() < 1e-15);
    /// ```
    pub fn plus(&self, other: &Inertia) -> Inertia {
        let mass = self.mass + other.mass;
        if mass <= 0.0 {
            return Inertia {
                mass,
                lever: Vector3::zeros(),
                inertia_com: self.inertia_com + other.inertia_com,
            };
        }
        let lever = (self.lever * self.mass + other.lever * other.mass) / mass;
        let d1 = self.lever - lever;
        let d2 = other.lever - lever;
        let shift = |m: f64, d: &Vector3<f64>| {
            (Matrix3::identity() * d.norm_squared() - d * d.transpose()) * m
        };
        Inertia {
            mass,
            lever,
            inertia_com: self.inertia_com
                + other.inertia_com
                + shift(self.mass, &d1)
                + shift(other.mass, &d2),
        }
    }
}

/// A rigid body's (or a set of bodies') inertia about the world origin in world axes, compact
/// form `(m, h = m c, I_O)` (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct WorldInertia {
    pub mass: f64,
    pub first_moment: Vector3<f64>,
    pub rot_origin: Matrix3<f64>,
}

impl WorldInertia {
    pub fn zero() -> Self {
        Self {
            mass: 0.0,
            first_moment: Vector3::zeros(),
            rot_origin: Matrix3::zeros(),
        }
    }

    /// Body inertia `local` (in the body frame) seen in the world, given `world_from_body`.
    #[inline]
    pub fn from_local(local: &Inertia, world_from_body: &Pose) -> Self {
        let c = world_from_body.transform_point(&local.lever);
        let r = &world_from_body.rotation;
        let m = local.mass;
        let rot_origin = r * local.inertia_com * r.transpose()
            + (Matrix3::identity() * c.norm_squared() - c * c.transpose()) * m;
        Self {
            mass: m,
            first_moment: c * m,
            rot_origin,
        }
    }

    #[inline]
    pub fn add(&mut self, other: &WorldInertia) {
        self.mass += other.mass;
        self.first_moment += other.first_moment;
        self.rot_origin += other.rot_origin;
    }

    /// Momentum `(linear, angular about the origin)` of the motion `(v, w)` (at the origin).
    #[inline]
    pub fn momentum(&self, v: &Vector3<f64>, w: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
        (
            v * self.mass + w.cross(&self.first_moment),
            self.first_moment.cross(v) + self.rot_origin * w,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The SE(3) exponential agrees with nalgebra's rotation exponential and with a fine
    /// integration of the constant twist, on both sides of the series switch.
    #[test]
    fn exp6_is_continuous_across_the_series_switch() {
        let axis = Vector3::new(0.3, -0.5, 0.8).normalize();
        let v = Vector3::new(0.2, 0.1, -0.4);
        for angle in [1e-7, 1e-4, 0.9e-2, 1.1e-2, 0.3, 1.0, 3.0] {
            let w = axis * angle;
            let e = exp6(&v, &w);
            let r = Rotation3::from_scaled_axis(w);
            assert!((e.rotation - r.matrix()).norm() < 1e-15);
            // translation: integral of R(t) v over [0, 1], by Simpson's rule with 2000 intervals
            let n = 2000;
            let mut t = Vector3::zeros();
            for k in 0..=n {
                let weight = if k == 0 || k == n {
                    1.0
                } else if k % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                let rk = Rotation3::from_scaled_axis(w * (k as f64 / n as f64));
                t += rk * v * weight;
            }
            t /= 3.0 * n as f64;
            assert!((e.translation - t).norm() < 1e-13, "angle {angle}");
        }
    }
}
