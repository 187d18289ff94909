//! Thresholds of the facade's glue (each with its unit, default and reason).

/// Largest grid (number of points) the refinement between grid points may build before it
/// stops unconverged. Unit: grid points. Default 20 000: a hundred times the paper's grids,
/// still solved in milliseconds; beyond it the violation is not a grid effect.
pub const MAX_REFINED_GRID_POINTS: usize = 20_000;
