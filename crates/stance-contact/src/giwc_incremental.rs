//! `U_stance` kept up to date while contacts are added, without redoing the whole conversion.
//!
//! # Math
//!
//! `A_stance V_all` is block-structured: its columns are those of `A_i V_i` for each contact
//! `i` (`A_i` the 6 x 6 block of contact `i` in `A_stance`, eq. 8-9; `V_i` its `V_surf`). So
//!
//! ```text
//! GIWC = span(A_stance V_all) = span(A_1 V_1) + ... + span(A_n V_n),
//! ```
//!
//! the **Minkowski sum of the contacts' wrench cones** (each moved to the world origin).
//! Adding contact `n + 1` appends the columns `A_{n+1} V_{n+1}`: the generators of the GIWC are
//! those of the previous stance plus those of the new contact. In the polar, where polycone's
//! double description runs, the sum becomes an intersection,
//!
//! ```text
//! GIWC° = {u : u . g <= 0 for every generator g} = (A_1 V_1)° ∩ ... ∩ (A_{n+1} V_{n+1})°,
//! ```
//!
//! so **appending generators appends polar rows**, one double description step each: the
//! facets of the new `U_stance` are obtained by continuing the previous conversion with the new
//! contact's rows ([`polycone::Continuation`]), not by converting all `N` generators again.
//! The result is certified like a conversion from scratch. The continuation starts over (a
//! stated [`polycone::Restart`] reason) when the new contact enlarges the linear span of the
//! GIWC (a lower-dimensional GIWC, e.g. point contacts: 3-D, then 5-D, then 6-D), and in the
//! other cases listed in polycone's `continuation` docs.

use crate::giwc_dd::{conversion_point, giwc_at_origin, span_at};
use crate::{Contact, ContactError, Giwc, GiwcOptions, Stance};

/// A stance and its `U_stance`, updated by continuation when a contact is added. Build it
/// with [`GiwcBuilder::new`] (or [`Stance::giwc_builder`]).
///
/// ```
/// use stance_contact::{examples, GiwcBuilder};
/// let stairs = examples::stairs().stance().unwrap();
/// let (left, right) = (stairs.contacts()[0].clone(), stairs.contacts()[1].clone());
/// let single = stance_contact::Stance::new(vec![left], *stairs.friction_model()).unwrap();
/// let mut b = GiwcBuilder::new(&single, &Default::default()).unwrap();
/// assert_eq!(b.giwc().facets.nrows(), 16);
/// let giwc = b.add_contact(right).unwrap();
/// assert_eq!(giwc.facets.nrows(), 176);
/// assert!(giwc.certified);
/// assert!(matches!(b.last_step(), polycone::Step::Continued { .. }));
/// assert_eq!(b.stance(), &stairs);
/// ```
#[derive(Debug, Clone)]
pub struct GiwcBuilder {
    stance: Stance,
    cont: polycone::Continuation,
    giwc: Giwc,
    /// Where the conversion runs (the first contact's origin, as in [`Stance::u_stance`]).
    point: [f64; 3],
}

impl GiwcBuilder {
    /// `U_stance` of `stance` (as [`Stance::u_stance`]), keeping the conversion's state.
    ///
    /// ```
    /// use stance_contact::{examples, GiwcBuilder};
    /// let s = examples::double_support_flat().stance().unwrap();
    /// let b = GiwcBuilder::new(&s, &Default::default()).unwrap();
    /// assert_eq!(b.giwc(), &s.u_stance(&Default::default()).unwrap());
    /// ```
    pub fn new(stance: &Stance, opts: &GiwcOptions) -> Result<Self, ContactError> {
        let point = conversion_point(stance);
        let cont = polycone::Continuation::new(&span_at(&stance.giwc_span(), point), &opts.dd)
            .map_err(ContactError::Cone)?;
        Ok(Self {
            stance: stance.clone(),
            giwc: giwc_at_origin(cont.result(), point),
            cont,
            point,
        })
    }

    /// Adds a contact (with the stance's friction model) and returns the new `U_stance`:
    /// the same cone as [`Stance::u_stance`] of the stance with the contact appended, by
    /// continuing the previous conversion when possible ([`GiwcBuilder::last_step`]). On error
    /// the builder keeps the previous stance.
    ///
    /// ```
    /// use stance_contact::{examples, GiwcBuilder, Stance};
    /// let boxc = examples::box_climbing().stance().unwrap();
    /// let foot = Stance::new(vec![boxc.contacts()[0].clone()], *boxc.friction_model()).unwrap();
    /// let mut b = foot.giwc_builder(&Default::default()).unwrap();
    /// let giwc = b.add_contact(boxc.contacts()[1].clone()).unwrap().clone();
    /// let scratch = boxc.u_stance(&Default::default()).unwrap();
    /// assert_eq!(giwc.facets.nrows(), scratch.facets.nrows());
    /// assert!((giwc.facets - scratch.facets).amax() < 1e-9);
    /// ```
    pub fn add_contact(&mut self, contact: Contact) -> Result<&Giwc, ContactError> {
        let stance = self.stance.with_contact(contact);
        let n = stance.contacts().len();
        let new = Stance::new(
            stance.contacts()[n - 1..].to_vec(),
            *stance.friction_model(),
        )?
        .giwc_span();
        let out = self
            .cont
            .add_generators(&span_at(&new, self.point))
            .map_err(ContactError::Cone)?;
        self.giwc = giwc_at_origin(out, self.point);
        self.stance = stance;
        Ok(&self.giwc)
    }

    /// The current `U_stance` (paper's convention, world origin).
    ///
    /// ```
    /// use stance_contact::{examples, GiwcBuilder};
    /// let s = examples::single_support_flat().stance().unwrap();
    /// assert_eq!(GiwcBuilder::new(&s, &Default::default()).unwrap().giwc().facets.nrows(), 16);
    /// ```
    pub fn giwc(&self) -> &Giwc {
        &self.giwc
    }

    /// The current stance.
    ///
    /// ```
    /// use stance_contact::{examples, GiwcBuilder};
    /// let s = examples::single_support_flat().stance().unwrap();
    /// assert_eq!(GiwcBuilder::new(&s, &Default::default()).unwrap().stance(), &s);
    /// ```
    pub fn stance(&self) -> &Stance {
        &self.stance
    }

    /// How the current `U_stance` was obtained: continued, or from scratch and why.
    ///
    /// ```
    /// use stance_contact::{examples, GiwcBuilder};
    /// let s = examples::single_support_flat().stance().unwrap();
    /// let b = GiwcBuilder::new(&s, &Default::default()).unwrap();
    /// assert_eq!(b.last_step(), &polycone::Step::FromScratch(polycone::Restart::Initial));
    /// ```
    pub fn last_step(&self) -> &polycone::Step {
        self.cont.last_step()
    }

    /// The underlying cone conversion (generators, extreme generators, certificate). It runs
    /// on the wrenches at the first contact's origin (the module doc of `Stance::u_stance`'s
    /// source explains why): its generators are the rows of [`Stance::giwc_span`] moved there.
    ///
    /// ```
    /// use stance_contact::{examples, GiwcBuilder};
    /// let s = examples::double_support_flat().stance().unwrap();
    /// let b = GiwcBuilder::new(&s, &Default::default()).unwrap();
    /// let (g, span) = (b.continuation().generators(), s.giwc_span());
    /// assert_eq!(g.shape(), span.shape());
    /// // Forces unchanged; torques about the first contact's origin (0, 0.1, 0).
    /// assert_eq!(g.columns(0, 3), span.columns(0, 3));
    /// ```
    pub fn continuation(&self) -> &polycone::Continuation {
        &self.cont
    }
}

impl Stance {
    /// A [`GiwcBuilder`] starting from this stance: `U_stance` now, and continued as contacts
    /// are added.
    ///
    /// ```
    /// use stance_contact::examples;
    /// let s = examples::single_support_flat().stance().unwrap();
    /// assert!(s.giwc_builder(&Default::default()).unwrap().giwc().certified);
    /// ```
    pub fn giwc_builder(&self, opts: &GiwcOptions) -> Result<GiwcBuilder, ContactError> {
        GiwcBuilder::new(self, opts)
    }
}
