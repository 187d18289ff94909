//! Constraints known only through an oracle: the rows of a grid point are completed, where the
//! solver needs it, by valid rows ("cuts") that a separation oracle returns.
//!
//! # Math
//!
//! Some constraints of a grid point are not rows in `(u, x)` but the projection of a polytope
//! with extra variables (torque limits with the contact forces as unknowns: the redundantly
//! actuated form of Pham and Pham, T-RO 2018, section VII). Every LP of the reachability passes
//! is solved over the point's rows and the cuts found so far; its optimum is then given to the
//! oracle, which either accepts it (it satisfies the extra constraints) or returns a row valid
//! for every admissible state of that point and violated by the optimum; the row joins the
//! point's cuts and the LP is solved again. When the oracle accepts the optimum of an LP over a
//! relaxation (rows and cuts contain the exact set), the optimum is the exact one: the
//! controllable sets, the forward pass's accelerations, and so the profile, are those of the
//! exact sets, without ever projecting them.
//!
//! The cuts found are returned with the solution (a tag per cut lets the caller name what it
//! stands for), to be reused: a later solve may start from them.

use crate::constraints::Row;
use crate::error::ToppError;

/// A row valid for every admissible state of a grid point, and a tag for the caller.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cut {
    /// `a u + b x + c <= 0`.
    pub row: Row,
    /// What it stands for (the caller's code).
    pub tag: u32,
}

/// The oracle of a grid point's extra constraints (module doc).
pub trait Separation {
    /// `None` when `(u, x)` satisfies grid point `point`'s extra constraints, else a cut that
    /// `(u, x)` violates.
    ///
    /// # Errors
    ///
    /// Whatever stops the oracle (it ends the solve).
    fn separate(&mut self, point: usize, u: f64, x: f64) -> Result<Option<Cut>, ToppError>;

    /// The same for the constraints of grid point `point` that also hold at the end of the
    /// interval before it (the interpolation discretization asks this with that interval's
    /// state; [`crate::CanonicalConstraints::with_next_rows`]). By default all of them:
    /// [`Self::separate`].
    ///
    /// # Errors
    ///
    /// Whatever stops the oracle (it ends the solve).
    fn separate_next(&mut self, point: usize, u: f64, x: f64) -> Result<Option<Cut>, ToppError> {
        self.separate(point, u, x)
    }
}

/// The cuts found per grid point.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Cuts {
    /// Rows per grid point.
    pub rows: Vec<Vec<Row>>,
    /// Their tags.
    pub tags: Vec<Vec<u32>>,
    /// The rows among them that the oracle gave for the end of the interval before the point
    /// ([`Separation::separate_next`]): also imposed there.
    pub next_rows: Vec<Vec<Row>>,
}

impl Cuts {
    /// No cuts at `n` grid points.
    pub fn new(n: usize) -> Self {
        Self {
            rows: vec![Vec::new(); n],
            tags: vec![Vec::new(); n],
            next_rows: vec![Vec::new(); n],
        }
    }

    /// The cuts of grid point `i` (none past the end).
    pub fn at(&self, i: usize) -> &[Row] {
        self.rows.get(i).map_or(&[], Vec::as_slice)
    }

    /// The cuts of grid point `i` that also hold at the end of the interval before it (none
    /// past the end).
    pub fn next_at(&self, i: usize) -> &[Row] {
        self.next_rows.get(i).map_or(&[], Vec::as_slice)
    }

    /// Adds a cut at grid point `i` (`next`: [`Separation::separate_next`] gave it, and it
    /// also holds at the end of the interval before the point).
    pub fn push(&mut self, i: usize, cut: Cut, next: bool) {
        self.rows[i].push(cut.row);
        self.tags[i].push(cut.tag);
        if next {
            self.next_rows[i].push(cut.row);
        }
    }

    /// Number of cuts.
    pub fn len(&self) -> usize {
        self.rows.iter().map(Vec::len).sum()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The oracle seen from the unit grid (`s~ = (s - s_0) / L`): states in the caller's units
/// (`u = L u~`, `x = L^2 x~`), cuts back in the unit grid's (`(a L, b L^2, c)`, scaled by a
/// power of two into the solver's window).
pub(crate) struct OnUnitGrid<'a> {
    pub inner: &'a mut dyn Separation,
    pub l: f64,
}

impl OnUnitGrid<'_> {
    /// A cut in the caller's units, in the unit grid's.
    fn to_unit(&self, mut c: Cut) -> Cut {
        let l = self.l;
        c.row = Row {
            a: c.row.a * l,
            b: c.row.b * l * l,
            c: c.row.c,
        };
        crate::constraints::into_window(&mut c.row);
        c
    }
}

impl Separation for OnUnitGrid<'_> {
    fn separate(&mut self, point: usize, u: f64, x: f64) -> Result<Option<Cut>, ToppError> {
        let l = self.l;
        Ok(self
            .inner
            .separate(point, u * l, x * l * l)?
            .map(|c| self.to_unit(c)))
    }

    fn separate_next(&mut self, point: usize, u: f64, x: f64) -> Result<Option<Cut>, ToppError> {
        let l = self.l;
        Ok(self
            .inner
            .separate_next(point, u * l, x * l * l)?
            .map(|c| self.to_unit(c)))
    }
}
