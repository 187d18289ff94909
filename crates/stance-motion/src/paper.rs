//! The paper's whole-body experiments beside ours: the per-segment figures of its Tables I
//! (stair climbing) and II (box climbing) on HRP-4, and the side-by-side report `stance demo`
//! prints for our runs of the same motions on JVRC-1.
//!
//! The paper's figures: rows of `U_stance` (cdd's output, unpruned), `T_U`, `T_abc` and
//! `T_TOPP` (ms, on a 2015 CPU) and the segment durations (s), every segment retimed rest to
//! rest. Ours: irredundant rows, this machine, the segments chained (and rest to rest beside).

use std::fmt::Write as _;

use crate::result::MotionResult;

/// One of the paper's tables of a whole-body experiment.
#[derive(Debug, Clone, Copy)]
pub struct PaperTable {
    /// The built-in motion it compares with ([`crate::experiments::NAMES`]).
    pub motion: &'static str,
    /// The table's title.
    pub title: &'static str,
    /// Rows of `U_stance` per segment.
    pub rows: &'static [usize],
    /// `T_U` per segment (ms).
    pub t_u: &'static [f64],
    /// `T_abc` per segment (ms).
    pub t_abc: &'static [f64],
    /// `T_TOPP` per segment (ms).
    pub t_topp: &'static [f64],
    /// Duration per segment (s).
    pub duration: &'static [f64],
}

/// Tables I and II.
pub const TABLES: [PaperTable; 2] = [
    PaperTable {
        motion: "stair-climbing",
        title: "Table I, stair climbing (24 cm step)",
        rows: &[114, 16, 162, 16, 162],
        t_u: &[4.2, 1.3, 4.5, 1.3, 4.3],
        t_abc: &[2.0, 2.0, 2.0, 2.0, 2.0],
        t_topp: &[130.0, 350.0, 560.0, 360.0, 150.0],
        duration: &[0.4, 0.6, 0.2, 0.8, 0.8],
    },
    PaperTable {
        motion: "box-climbing",
        title: "Table II, box climbing (10 cm box, slope, 90 cm ledge)",
        rows: &[113, 84, 55, 118],
        t_u: &[4.4, 3.7, 3.0, 4.0],
        t_abc: &[2.5, 2.5, 2.5, 2.5],
        t_topp: &[420.0, 310.0, 60.0, 320.0],
        duration: &[6.7, 8.3, 0.3, 6.1],
    },
];

/// The heading of the comparison.
pub const HEADER: &str = "Whole-body motions across stances on JVRC-1 (IK -> U_stance -> \
eq. 14 -> chained TOPP, force check at every 10 ms sample;\n   paper: HRP-4, unpruned cdd rows, \
2015 CPU, every segment rest to rest; ours: irredundant rows, this machine, chained)\n";

impl PaperTable {
    /// The table beside our run `r` of the same motion (chained) and `r2r` (rest to rest):
    /// per segment rows, times and durations, then the totals and the force check.
    pub fn compare(&self, r: &MotionResult, r2r: &MotionResult) -> String {
        let mut o = String::new();
        // (Writing to a String cannot fail.)
        let _ = self.write_comparison(&mut o, r, r2r);
        o
    }

    fn write_comparison(
        &self,
        o: &mut String,
        r: &MotionResult,
        r2r: &MotionResult,
    ) -> std::fmt::Result {
        let two = |x: Option<f64>| x.map_or_else(|| "-".to_string(), |v| format!("{v:.2}"));
        writeln!(
            o,
            "\n   {}: {:?}, {} segments",
            self.title,
            r.status,
            r.segments.len()
        )?;
        writeln!(
            o,
            "   {:<3} {:>11} {:>13} {:>13} {:>15} {:>7} {:>6} {:>27}",
            "seg",
            "rows",
            "T_U ms",
            "T_abc ms",
            "T_TOPP ms",
            "T_IK",
            "grid",
            "duration s (chained, r2r)"
        )?;
        writeln!(
            o,
            "   {:<3} {:>11} {:>13} {:>13} {:>15} {:>7} {:>6} {:>27}",
            "", "ours paper", "ours paper", "ours paper", "ours paper", "ms", "", "ours ours paper"
        )?;
        for (k, s) in r.segments.iter().enumerate() {
            let paper = |v: &[f64]| v.get(k).copied().unwrap_or(f64::NAN);
            writeln!(
                o,
                "   {:<3} {:>5} {:>5} {:>6.2} {:>6.1} {:>6.2} {:>6.1} {:>7.2} {:>7.0} {:>7.1} {:>6} {:>9} {:>8} {:>8.1}",
                k + 1,
                s.u_stance_rows,
                self.rows.get(k).map_or("-".into(), |n| n.to_string()),
                s.t_u_ms,
                paper(self.t_u),
                s.t_abc_ms,
                paper(self.t_abc),
                s.t_topp_ms.unwrap_or(f64::NAN),
                paper(self.t_topp),
                s.t_ik_ms,
                s.grid_points,
                two(s.duration),
                two(r2r.segments.get(k).and_then(|s| s.duration)),
                paper(self.duration),
            )?;
        }
        let t = &r.timings;
        let total = |v: &[f64]| v.iter().sum::<f64>();
        writeln!(
            o,
            "   all: U_stance + rows + TOPP {:.2} ms (paper {:.0} ms), refinement between grid \
             points {:.2} ms, IK {:.1} ms, whole pipeline {:.1} ms",
            t.t_u_abc_topp_ms,
            total(self.t_u) + total(self.t_abc) + total(self.t_topp),
            t.t_refine_ms,
            t.t_ik_ms,
            t.t_pipeline_ms
        )?;
        writeln!(
            o,
            "   duration: chained {} s, rest to rest {} s ({}), paper {:.1} s",
            two(r.duration),
            two(r2r.duration),
            r2r.failure.as_ref().map_or_else(
                || "feasible".to_string(),
                |f| format!("segment {} cannot end at rest", f.segment)
            ),
            total(self.duration)
        )?;
        if let Some(c) = &r.checks {
            writeln!(
                o,
                "   check: {} samples, {} without supporting forces; friction usage <= {:.2}, \
                 contact drift <= {:.2} mm, joints within limits: {}",
                c.samples,
                c.samples_without_forces,
                c.max_friction_usage,
                c.max_contact_drift * 1e3,
                c.max_joint_violation == 0.0
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tables_have_one_figure_per_segment_of_their_motion() {
        for t in &TABLES {
            let spec = crate::experiments::by_name(t.motion).unwrap();
            let n = spec.segments.len();
            assert_eq!(t.rows.len(), n, "{}", t.motion);
            for v in [t.t_u, t.t_abc, t.t_topp, t.duration] {
                assert_eq!(v.len(), n, "{}", t.motion);
            }
        }
    }
}
