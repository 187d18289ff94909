//! The backward pass in pieces, so that it can start before the whole grid's rows exist.
//!
//! # Math
//!
//! Cut the grid `s_0 < ... < s_N` into consecutive pieces that share their end points (piece
//! `p` ends where piece `p + 1` starts). The backward pass (module doc of [`super`]) computes
//! `K_i` from `K_{i+1}` and the rows of stage `i` alone (grid points `i` and `i + 1`), so the
//! pass over piece `p` needs only its own rows and `K` at its last point, which the pass over
//! piece `p + 1` found. Run last piece first, each resuming with the set and the warm start
//! (the lines active at the two optima) the pass after it stopped with, the pieces' passes are
//! the whole grid's pass step for step: the same LPs on the same rows, the same oracle
//! questions in the same order, hence the same sets and cuts. The forward pass then runs over
//! the whole grid with the pieces' sets and cuts (each grid point's cuts in the order the whole
//! pass would have found them: the pieces' cuts last piece first).
//!
//! A caller that computes the rows of the pieces last to first can so run a piece's pass while
//! the rows before it are being computed.
//!
//! Each piece is solved on the path parameter the whole grid is solved on (its unit `L` and
//! origin: [`CanonicalConstraints::on_unit_grid`]), so that its numbers are the whole solve's;
//! with a separation oracle, as here, the solver does not change the time unit.

use super::options::{Solution, SolveOptions, SolveStats};
use super::reachability::{
    backward_pass, forward_pass, from_unit_grid, Actives, Backward, PassEnd,
};
use super::separation::{Cuts, OnUnitGrid, Separation};
use crate::constraints::CanonicalConstraints;
use crate::error::ToppError;

/// The backward pass over one piece of a grid (module doc): its controllable sets and cuts,
/// and where it stopped.
#[derive(Debug, Clone)]
pub struct BackwardPiece {
    pass: Backward,
    /// The piece's grid ends.
    ends: [f64; 2],
    /// The whole grid's ends, which set the path parameter it is solved on.
    whole: [f64; 2],
    /// `Ok(actives at the first stage)`, or `Err(i)`: `K_i` empty.
    outcome: Result<Actives, usize>,
}

impl BackwardPiece {
    /// The grid point of the piece (from 0) where the pass found an empty controllable set
    /// (the pieces before it cannot be solved: solve the whole grid for the diagnosis).
    pub fn failed_at(&self) -> Option<usize> {
        self.outcome.err()
    }
}

impl super::Workspace {
    /// The backward pass over `k`, one piece of the grid from `whole[0]` to `whole[1]`
    /// (module doc): from the end speeds of `opts` when `after` is `None` (the last piece),
    /// else from the controllable set the pass over the next piece (`after`) found at its
    /// first point, which must be `k`'s last. The oracle is asked about the piece's points
    /// (from 0).
    ///
    /// # Errors
    ///
    /// [`ToppError::InvalidValue`] when `after` failed, does not start where `k` ends or is a
    /// piece of another grid; the oracle's errors.
    ///
    /// ```
    /// use stance_topp::{CanonicalConstraints, Cut, Row, Separation, SolveOptions, ToppError,
    ///     Workspace};
    /// struct Accept;
    /// impl Separation for Accept {
    ///     fn separate(&mut self, _: usize, _: f64, _: f64) -> Result<Option<Cut>, ToppError> {
    ///         Ok(None)
    ///     }
    /// }
    /// // |u| <= 1 on [0, 1], in two pieces [0, 0.5] and [0.5, 1] that share s = 0.5
    /// let rows = vec![Row { a: 1.0, b: 0.0, c: -1.0 }, Row { a: -1.0, b: 0.0, c: -1.0 }];
    /// let piece = |i0: usize, i1: usize| {
    ///     let s: Vec<f64> = (i0..=i1).map(|i| i as f64 / 10.0).collect();
    ///     let offsets: Vec<usize> = (0..=s.len()).map(|i| 2 * i).collect();
    ///     CanonicalConstraints::new(s, offsets, rows.repeat(i1 - i0 + 1)).unwrap()
    /// };
    /// let (whole, first, second) = (piece(0, 10), piece(0, 5), piece(5, 10));
    /// let (opts, mut ws) = (SolveOptions::default(), Workspace::new());
    /// let p2 = ws.backward_piece(&second, &opts, [0.0, 1.0], None, &mut Accept).unwrap();
    /// let p1 = ws.backward_piece(&first, &opts, [0.0, 1.0], Some(&p2), &mut Accept).unwrap();
    /// let sol = ws.forward_over_pieces(&whole, &opts, &[p1, p2], &mut Accept).unwrap();
    /// let alone = ws.solve_separated(&whole, &opts, &mut Accept).unwrap();
    /// assert_eq!(sol, alone);
    /// assert!((sol.duration().unwrap() - 2.0).abs() < 1e-9);
    /// ```
    pub fn backward_piece(
        &mut self,
        k: &CanonicalConstraints,
        opts: &SolveOptions,
        whole: [f64; 2],
        after: Option<&BackwardPiece>,
        sep: &mut dyn Separation,
    ) -> Result<BackwardPiece, ToppError> {
        opts.validate()?;
        let s = k.grid();
        let n = s.len();
        let ends = [s[0], s[n - 1]];
        if !(whole[0] <= ends[0] && ends[1] <= whole[1]) {
            return Err(piece_error(format!(
                "a piece from {:e} to {:e} outside its grid, from {:e} to {:e}",
                ends[0], ends[1], whole[0], whole[1]
            )));
        }
        // on the whole grid's path parameter (module doc)
        let unit = k.on_unit_grid_of(whole)?;
        let (k, l) = match &unit {
            Some((k_unit, l)) => (k_unit, *l),
            None => (k, 1.0),
        };
        let end = match after {
            None => PassEnd::Speeds([(opts.sd_end[0] / l).powi(2), (opts.sd_end[1] / l).powi(2)]),
            Some(next) if next.whole != whole => {
                return Err(piece_error(format!(
                    "the next piece is one of the grid from {:e} to {:e}, not of this one's",
                    next.whole[0], next.whole[1]
                )));
            }
            Some(next) => {
                let Ok(active) = next.outcome else {
                    return Err(piece_error(
                        "the pass over the next piece failed: solve the whole grid for the \
                         diagnosis"
                            .into(),
                    ));
                };
                if next.ends[0] != ends[1] {
                    return Err(piece_error(format!(
                        "the next piece starts at s = {:e}, not at this piece's end {:e}",
                        next.ends[0], ends[1]
                    )));
                }
                let set = next.pass.controllable[0].expect("the next piece's pass succeeded");
                PassEnd::Given(set, active)
            }
        };
        let mut pass = Backward {
            controllable: vec![None; n],
            cuts: Cuts::new(n),
            stats: SolveStats::default(),
            hit_box: false,
        };
        let outcome = if unit.is_some() {
            let mut on_unit = OnUnitGrid { inner: sep, l };
            backward_pass(k, opts, end, &mut pass, &mut Some(&mut on_unit))?
        } else {
            backward_pass(k, opts, end, &mut pass, &mut Some(sep))?
        };
        Ok(BackwardPiece {
            pass,
            ends,
            whole,
            outcome,
        })
    }

    /// The forward pass over the whole grid `k` from the backward passes of its pieces, in the
    /// grid's order (module doc): the solution [`super::Workspace::solve_separated`] finds.
    ///
    /// # Errors
    ///
    /// [`ToppError::InvalidValue`] when a piece failed or the pieces do not make up `k`'s grid;
    /// the oracle's errors.
    pub fn forward_over_pieces(
        &mut self,
        k: &CanonicalConstraints,
        opts: &SolveOptions,
        pieces: &[BackwardPiece],
        sep: &mut dyn Separation,
    ) -> Result<Solution, ToppError> {
        opts.validate()?;
        let n = k.num_points();
        let whole_ends = [k.grid()[0], k.grid()[n - 1]];
        let mut starts = Vec::with_capacity(pieces.len());
        let mut at = 0;
        for (p, piece) in pieces.iter().enumerate() {
            if piece.whole != whole_ends {
                return Err(piece_error(format!(
                    "piece {p} is one of the grid from {:e} to {:e}, not this one's",
                    piece.whole[0], piece.whole[1]
                )));
            }
            if piece.outcome.is_err() {
                return Err(piece_error(format!(
                    "the backward pass over piece {p} failed: solve the whole grid"
                )));
            }
            let len = piece.pass.controllable.len();
            if at + len > n
                || k.grid()[at] != piece.ends[0]
                || k.grid()[at + len - 1] != piece.ends[1]
            {
                return Err(piece_error(format!(
                    "piece {p} (s from {:e} to {:e}, {len} points) is not the grid's points \
                     from {at} on",
                    piece.ends[0], piece.ends[1]
                )));
            }
            starts.push(at);
            at += len - 1;
        }
        if at + 1 != n || pieces.is_empty() {
            return Err(piece_error(format!(
                "the pieces cover {} of the grid's {n} points",
                at + 1
            )));
        }
        let mut whole = Backward {
            controllable: vec![None; n],
            cuts: Cuts::new(n),
            stats: SolveStats::default(),
            hit_box: false,
        };
        // the cuts in the order the whole grid's pass finds them: last piece first
        for (piece, &a) in pieces.iter().zip(&starts).rev() {
            let p = &piece.pass;
            for (i, set) in p.controllable.iter().enumerate() {
                whole.controllable[a + i] = *set;
                whole.cuts.rows[a + i].extend_from_slice(&p.cuts.rows[i]);
                whole.cuts.tags[a + i].extend_from_slice(&p.cuts.tags[i]);
                whole.cuts.next_rows[a + i].extend_from_slice(&p.cuts.next_rows[i]);
            }
            whole.stats.lps += p.stats.lps;
            whole.stats.moves += p.stats.moves;
            whole.stats.inner_steps += p.stats.inner_steps;
            whole.stats.cuts += p.stats.cuts;
            whole.hit_box |= p.hit_box;
        }
        // as `Workspace::solve_separated` does: on the unit grid, the answer mapped back
        let Some((k_unit, l)) = k.on_unit_grid()? else {
            return forward_pass(k, opts, whole, Some(sep));
        };
        let unit_opts = SolveOptions {
            sd_start: opts.sd_start / l,
            sd_end: [opts.sd_end[0] / l, opts.sd_end[1] / l],
            ..*opts
        };
        let mut on_unit = OnUnitGrid { inner: sep, l };
        let sol = forward_pass(&k_unit, &unit_opts, whole, Some(&mut on_unit))?;
        Ok(from_unit_grid(sol, k.grid(), l))
    }
}

fn piece_error(detail: String) -> ToppError {
    ToppError::InvalidValue {
        what: "backward pass in pieces",
        detail,
    }
}
