//! The CoM retiming in units where the mass and the gravity are of order one, mapped back.
//!
//! # Math
//!
//! The rows (13)-(14) are `U w <= 0` with the gravito-inertial wrench
//! `w = m (p'' - g, p x (p'' - g)) + (0, L')`, `L' = l1 s'' + l2 s'^2`. Two changes of units leave
//! the answer as physics says it changes:
//!
//! - **mass**: `U (w / m') <= 0` iff `U w <= 0` for any `m' > 0` (a cone), so the problem with
//!   mass `m / m'` and angular terms `l1 / m'`, `l2 / m'` has the same profile `s'(s)`;
//! - **gravity**: with `t = tau t_n`, `s' = s'_n / tau`, `s'' = s''_n / tau^2`, the wrench of the
//!   motion under gravity `g` is `1 / tau^2` times that of the motion `s_n(t_n)` under gravity
//!   `tau^2 g` (the same `l1`, `l2`): durations scale with `tau = sqrt(|g_n| / |g|)`.
//!
//! Both factors are powers of two (`m' = 2^i` nearest `m`, `tau = 2^j` with `tau^2 |g|` nearest
//! 9.81 m/s^2), so the change of units is exact in floating point: problems whose masses or
//! gravities differ by such powers are solved bit for bit alike, and every other answer is the
//! one at a mass and gravity of order one, where the solver's absolute tolerances (the speed
//! box, the zero of a row) are meant to work. Without the change, a gravity of 1e-10 m/s^2 gave
//! a duration 20 % off and a mass of 1e-300 kg one 2,700 times too short, with nothing flagged.
//! A zero gravity keeps its units of time (there is no time scale to take from it).

use stance_topp::ldexp as times_pow2;

use super::{ComMotionSpec, Retiming, SceneRef};
use crate::StanceError;

/// The gravity the problems are solved at, in magnitude (m/s^2).
const REFERENCE_GRAVITY: f64 = 9.81;

/// The change of units of one retiming: mass divided by `2^mass_exp`, time multiplied by
/// `2^time_exp` (`tau`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Units {
    mass_exp: i32,
    time_exp: i32,
}

impl Units {
    /// The powers of two nearest the scene's mass and `sqrt(|g| / 9.81)`.
    pub(super) fn of(mass: f64, gravity: [f64; 3]) -> Units {
        // |g| without overflow or underflow of its squares (relative to its largest component)
        let top = gravity.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let g = if top > 0.0 && top.is_finite() {
            top * gravity
                .iter()
                .map(|x| (x / top).powi(2))
                .sum::<f64>()
                .sqrt()
        } else {
            0.0
        };
        let mass_exp = if mass > 0.0 && mass.is_finite() {
            mass.log2().round() as i32
        } else {
            0
        };
        let time_exp = if g > 0.0 {
            ((REFERENCE_GRAVITY.log2() - g.log2()) / 2.0).round() as i32
        } else {
            0
        };
        Units { mass_exp, time_exp }
    }

    /// `tau`: seconds of the caller per unit of time of the new units.
    pub(super) fn time_unit(self) -> f64 {
        times_pow2(1.0, self.time_exp)
    }

    /// Whether the change of units is the identity.
    pub(super) fn is_identity(&self) -> bool {
        self.mass_exp == 0 && self.time_exp == 0
    }

    /// The problem in the new units: mass `m / 2^i`, gravity `g tau^2`, angular terms
    /// `l / 2^i`, boundary speeds `s' tau` (`dt` stays in the caller's seconds: the resampling
    /// divides it by [`Self::time_unit`], so that its errors speak the caller's units).
    ///
    /// # Errors
    ///
    /// A boundary speed or time step that does not fit the new units (beyond the range of
    /// doubles), named with the range that fits.
    pub(super) fn normalize(
        self,
        spec: &ComMotionSpec,
        scene: &stance_contact::Scene,
    ) -> Result<ComMotionSpec, StanceError> {
        let (i, j) = (self.mass_exp, self.time_exp);
        let mut scene = scene.clone();
        scene.mass = times_pow2(scene.mass, -i);
        for g in &mut scene.gravity {
            *g = times_pow2(*g, 2 * j);
        }
        let mut out = spec.clone();
        out.scene = SceneRef::Inline(Box::new(scene));
        for (what, v, n) in [
            ("sd_start", spec.sd_start, &mut out.sd_start),
            ("sd_end", spec.sd_end, &mut out.sd_end),
        ] {
            *n = times_pow2(v, j);
            if !(*n * *n).is_finite() {
                return Err(StanceError::BadMotion(format!(
                    "{what} = {v:e} is beyond what this gravity allows (its square in units of \
                     the scene's time scale overflows); give {what} below {:e}",
                    times_pow2(1e150, -j)
                )));
            }
        }
        if let Some(l) = &mut out.angular_momentum {
            for v in l.l1.iter_mut().chain(l.l2.iter_mut()) {
                for x in v.iter_mut() {
                    *x = times_pow2(*x, -i);
                }
            }
        }
        Ok(out)
    }

    /// The answer in the scene's units: times and durations times `tau`, speeds over `tau`,
    /// accelerations and `x = s'^2` over `tau^2`, violations in newtons times `2^i / tau^2`.
    pub(super) fn restore(self, mut r: Retiming) -> Retiming {
        let (i, j) = (self.mass_exp, self.time_exp);
        let time = |x: f64| times_pow2(x, j);
        let speed = |x: f64| times_pow2(x, -j);
        let accel = |x: f64| times_pow2(x, -2 * j);
        r.duration = r.duration.map(time);
        r.t.iter_mut().for_each(|x| *x = time(*x));
        r.sd.iter_mut().for_each(|x| *x = speed(*x));
        r.sdd.iter_mut().for_each(|x| *x = accel(*x));
        for set in r
            .controllable_sets
            .iter_mut()
            .chain(r.feasible_sets.iter_mut())
            .flatten()
        {
            set[0] = accel(set[0]);
            set[1] = accel(set[1]);
        }
        if let Some(b) = &mut r.between {
            b.max_violation_newtons = times_pow2(b.max_violation_newtons, i - 2 * j);
        }
        for smp in &mut r.samples {
            *smp = [time(smp[0]), smp[1], speed(smp[2]), accel(smp[3])];
        }
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn powers_of_two_near_the_mass_and_the_time_scale() {
        let u = Units::of(39.0, [0.0, 0.0, -9.81]);
        assert_eq!((u.mass_exp, u.time_exp), (5, 0));
        // a gravity 4^k times smaller: time 2^k times longer
        let u = Units::of(1.0, [0.0, 0.0, -9.81 / 1024.0]);
        assert_eq!((u.mass_exp, u.time_exp), (0, 5));
        // the ends of the range: no overflow in the norm or the factors
        let u = Units::of(1e-300, [1e300, 1e300, 1e300]);
        assert!(u.time_exp < -490 && u.mass_exp < -990, "{u:?}");
        let u = Units::of(f64::MAX, [0.0, 0.0, -5e-324]);
        assert!(u.time_exp > 530 && u.mass_exp == 1024, "{u:?}");
        assert!(Units::of(1.0, [0.0; 3]).is_identity());
        assert_eq!(times_pow2(3.0, 1100), 3.0 * 2f64.powi(550) * 2f64.powi(550));
        // exponents beyond what one power of two holds, as restore's i - 2j can be
        assert_eq!(times_pow2(times_pow2(1e300, -2000), 2000), 1e300);
    }
}
