//! The torque limits with the contact forces as unknowns, given to the retiming as a separation
//! oracle ([`stance_topp::Separation`]).
//!
//! # Math
//!
//! A side of an IK sample with two contacts or more has lifted rows in `(u, x, y)`
//! ([`crate::limit_rows`]): its admissible states are their projection onto `(u, x)`. The solver
//! asks the oracle about each state its LPs reach at a grid point; the oracle tests it against
//! every lifted side of that point (the grid point's own sides; at a stance switch the stance
//! after it only, the stance before it at the point before, at the state `x + 2 Delta u` the
//! interval reaches at the switch, a cut found there written back in `(u, x)`: module doc of
//! `chain`): a contact-force witness, or the margin program
//! ([`stance_topp::lifted::Membership::separate`]), accepts it, or the program's dual gives a
//! row valid for every admissible state of that side that the state violates. The solver adds
//! the row to the point and solves that LP again; when every optimum is accepted, the profile
//! is the one of the exact sets. The rows found are kept in the sides (so that a later solve,
//! after the refinement adds grid points, starts from them) and named by the torque of largest
//! weight in their definition.

use std::time::{Duration, Instant};

use stance_topp::lifted::Membership;
use stance_topp::{Cut, Row, Separation, ToppError};

use super::rows::SegmentRows;
use crate::binding::RowOrigin;

/// A side of an IK sample: segment, sample, left side.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SideRef {
    /// Segment index.
    pub segment: usize,
    /// IK sample within the segment.
    pub sample: usize,
    /// The left side (the step arriving at the sample).
    pub left: bool,
}

/// A cut the oracle returned.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FoundCut {
    /// Whose lifted rows it separates.
    pub side: SideRef,
    /// The row in `(u, x)`.
    pub row: Row,
    /// What it stands for.
    pub origin: RowOrigin,
}

/// The oracle of the lifted sides of a layout's grid points (module doc).
pub struct LiftedOracle<'a> {
    rows: &'a mut [SegmentRows],
    /// Per global grid point, its lifted sides: each with the `2 Delta` that maps the point's
    /// state to the side's (`x_side = x + 2 Delta u`: the stance before a switch, at the
    /// point before it; zero otherwise), and whether it also holds at the end of the interval
    /// before the point (not at a switch: module doc of `chain`).
    points: Vec<Vec<(SideRef, f64, bool)>>,
    /// Added to the solver's grid index (a segment solved alone).
    pub offset: usize,
    member: Membership,
    /// Cuts returned, in order (a cut's tag is its index here).
    pub found: Vec<FoundCut>,
    /// Time spent in the oracle.
    pub elapsed: Duration,
    /// States tested.
    pub tests: usize,
}

impl<'a> LiftedOracle<'a> {
    /// The oracle of the grid points of `rows` laid out end to end (segment `k`'s grid point `i`
    /// is global point `seg_start[k] + i`; a segment's last point is the next one's first).
    /// `None` when no grid point has lifted rows.
    pub fn new(rows: &'a mut [SegmentRows], seg_start: &[usize]) -> Option<Self> {
        Self::between(rows, seg_start, [false, false])
    }

    /// The oracle of one segment's grid points alone (its grid point `i` is point `i` here),
    /// `[before, after]`: whether a segment comes before it and after it in the motion (its
    /// ends are then stance switches).
    pub fn of_segment(rows: &'a mut SegmentRows, neighbours: [bool; 2]) -> Option<Self> {
        let seg_start = [0, rows.grid.len() - 1];
        Self::between(std::slice::from_mut(rows), &seg_start, neighbours)
    }

    /// [`Self::new`] for segments between others (`[before, after]`: [`Self::of_segment`]).
    fn between(
        rows: &'a mut [SegmentRows],
        seg_start: &[usize],
        [before, after]: [bool; 2],
    ) -> Option<Self> {
        let n = seg_start.last().map_or(0, |&e| e + 1);
        let mut points = vec![Vec::new(); n];
        let mut any = false;
        let nseg = rows.len();
        for (k, r) in rows.iter().enumerate() {
            let last = r.grid.len() - 1;
            for (i, &j) in r.grid.iter().enumerate() {
                let Some(sides) = r.sides[j].as_ref() else {
                    continue;
                };
                let g = seg_start[k] + i;
                for (left, on) in [(false, i < last), (true, i > 0)] {
                    if !(on && sides[usize::from(left)].lifted.is_some()) {
                        continue;
                    }
                    let side = SideRef {
                        segment: k,
                        sample: j,
                        left,
                    };
                    let entry = if left && i == last && (after || k + 1 < nseg) {
                        // the stance before a switch: at the point before, in its state
                        let two_delta = 2.0 * (r.s_of(j) - r.s_of(r.grid[i - 1]));
                        (g - 1, (side, two_delta, false))
                    } else {
                        // the stance after a switch holds with its own interval only
                        (g, (side, 0.0, !((before || k > 0) && i == 0)))
                    };
                    points[entry.0].push(entry.1);
                    any = true;
                }
            }
        }
        any.then(|| Self {
            rows,
            points,
            offset: 0,
            member: Membership::new(),
            found: Vec::new(),
            elapsed: Duration::ZERO,
            tests: 0,
        })
    }

    /// The oracle's membership workspace (its recent witnesses: states tested later start from
    /// them), to hand on to the oracle that continues this one's work.
    pub fn member_mut(&mut self) -> &mut Membership {
        &mut self.member
    }

    /// Keeps the cuts found in their sides' rows (the grids' rows change at the next
    /// [`SegmentRows::refresh`]); returns how many.
    pub fn keep_cuts(self) -> usize {
        keep_found(self.rows, &self.found);
        self.found.len()
    }
}

/// Keeps cuts an oracle over `rows` found ([`LiftedOracle::keep_cuts`]).
pub fn keep_found(rows: &mut [SegmentRows], found: &[FoundCut]) {
    for c in found {
        rows[c.side.segment].add_cut(c.side.sample, c.side.left, c.row, c.origin);
    }
}

impl LiftedOracle<'_> {
    /// The first lifted side of `point` (all of them, or those that also hold at the end of the
    /// interval before: `next`) that `(u, x)` violates, as a cut in the point's state.
    fn separate_sides(
        &mut self,
        point: usize,
        u: f64,
        x: f64,
        next: bool,
    ) -> Result<Option<Cut>, ToppError> {
        let t0 = Instant::now();
        let mut out = None;
        let sides = self
            .points
            .get(point + self.offset)
            .map_or(&[][..], Vec::as_slice);
        for &(side, two_delta, both) in sides {
            if next && !both {
                continue;
            }
            self.tests += 1;
            let lifted = self.rows[side.segment].sides[side.sample]
                .as_mut()
                .and_then(|s| s[usize::from(side.left)].lifted.as_mut())
                .expect("the oracle's sides have lifted rows");
            let Some(cut) =
                self.member
                    .separate(&lifted.rows, u, x + two_delta * u, &mut lifted.witnesses)?
            else {
                continue;
            };
            let origin = cut
                .support
                .iter()
                .map(|&(j, _)| lifted.origins[j])
                .find(|o| matches!(o, RowOrigin::TorqueWithContacts(_)))
                .unwrap_or(RowOrigin::Contact);
            let tag = self.found.len() as u32;
            // kept in the side's own state (the layout shifts it), given in the point's
            self.found.push(FoundCut {
                side,
                row: cut.row,
                origin,
            });
            let row = Row {
                a: cut.row.a + two_delta * cut.row.b,
                b: cut.row.b,
                c: cut.row.c,
            };
            out = Some(Cut { row, tag });
            break;
        }
        self.elapsed += t0.elapsed();
        Ok(out)
    }
}

impl Separation for LiftedOracle<'_> {
    fn separate(&mut self, point: usize, u: f64, x: f64) -> Result<Option<Cut>, ToppError> {
        self.separate_sides(point, u, x, false)
    }

    fn separate_next(&mut self, point: usize, u: f64, x: f64) -> Result<Option<Cut>, ToppError> {
        self.separate_sides(point, u, x, true)
    }
}
