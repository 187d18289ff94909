//! Thresholds of the facade's glue (each with its unit, default and reason).

/// Largest grid (number of points) the refinement between grid points may build before it
/// stops unconverged. Unit: grid points. Default 20 000: a hundred times the paper's grids,
/// still solved in milliseconds; beyond it the violation is not a grid effect.
pub const MAX_REFINED_GRID_POINTS: usize = 20_000;

/// Largest number of samples per grid interval in the check between grid points. Unit:
/// samples. Default 100: the violation of smooth rows converges long before (10 is the
/// default); with [`MAX_REFINED_GRID_POINTS`] points and about 170 rows per point it bounds the
/// check to a few hundred million row evaluations (about a second), where a larger count from a
/// file would hang the command.
pub const MAX_SAMPLES_PER_INTERVAL: usize = 100;
