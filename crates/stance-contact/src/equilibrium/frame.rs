//! The length frame of a stance: its static-equilibrium polygon computed near the origin and at
//! unit size, then mapped back, so that the answer does not depend on where the world origin
//! is or on the unit of length.
//!
//! # Math
//!
//! With `o` the mean of the contact positions and `L` a power of two at least the stance's
//! extent (the largest `|p_i - o| + r_i`, `r_i` the radius of contact `i`'s shape), the
//! stance `S' = {(p_i - o) / L, R_i, shape_i / L, mu_i}` has the same contact forces as `S`
//! (friction cones depend on `R_i` and `mu_i` only), and a CoM `c` is in static equilibrium
//! for `S` if and only if `c' = (c - o) / L` is for `S'` (moments scale by `L`, about a
//! shifted point). So the polygon of `S` at height `z` is `o + L P'` with `P'` the polygon of
//! `S'` at height `(z - o_z) / L`; a half-plane `a . c' <= b'` is `a . c <= L b' + a . o`.
//! Dividing by `L` is exact (a power of two); the subtraction `p_i - o` rounds at
//! `u |p_i|`, the rounding the caller's coordinates already carry.

use super::statics::StaticPolygon;
use crate::Stance;

/// `o` and `L` of a stance (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct LengthFrame {
    pub origin: [f64; 3],
    pub length: f64,
}

impl LengthFrame {
    /// The frame of `stance`, or `None` when it is already at the origin and unit size (within
    /// a factor of two): nothing to map.
    pub fn of(stance: &Stance) -> Option<Self> {
        let cs = stance.contacts();
        let n = cs.len() as f64;
        let mut o = [0.0; 3];
        for c in cs {
            for (oi, pi) in o.iter_mut().zip(c.position()) {
                *oi += pi / n;
            }
        }
        let extent = cs
            .iter()
            .map(|c| {
                let p = c.position();
                let d =
                    ((p[0] - o[0]).powi(2) + (p[1] - o[1]).powi(2) + (p[2] - o[2]).powi(2)).sqrt();
                d + c.shape().radius()
            })
            .fold(0.0, f64::max);
        if !(extent > 0.0 && extent.is_finite()) {
            return None;
        }
        let length = 2f64.powi(extent.log2().ceil() as i32);
        // (A length or inverse that is not a normal number: stay in the caller's coordinates.)
        if !(length.is_normal() && (1.0 / length).is_normal()) {
            return None;
        }
        let near = o.iter().all(|x| x.abs() <= 2.0 * length) && (0.25..=4.0).contains(&length);
        (!near).then_some(Self { origin: o, length })
    }

    /// The stance in this frame (module docs).
    pub fn local(&self, stance: &Stance) -> Stance {
        let inv = 1.0 / self.length;
        let contacts = stance
            .contacts()
            .iter()
            .map(|c| {
                let p = c.position();
                let shape = c.shape().scaled(inv);
                c.rescaled(
                    [
                        (p[0] - self.origin[0]) * inv,
                        (p[1] - self.origin[1]) * inv,
                        (p[2] - self.origin[2]) * inv,
                    ],
                    shape,
                    inv,
                )
            })
            .collect();
        stance.with_contacts(contacts)
    }

    /// A height in this frame.
    pub fn height(&self, z: f64) -> f64 {
        (z - self.origin[2]) / self.length
    }

    /// A polygon of the local stance, mapped back to the world (module docs).
    pub fn polygon_to_world(&self, mut p: StaticPolygon, height: f64) -> StaticPolygon {
        let (o, l) = (self.origin, self.length);
        for v in &mut p.vertices {
            *v = [o[0] + l * v[0], o[1] + l * v[1]];
        }
        for (a, b) in &mut p.halfplanes {
            *b = l * *b + a[0] * o[0] + a[1] * o[1];
        }
        p.height = height;
        p
    }
}
