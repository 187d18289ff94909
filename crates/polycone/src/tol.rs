//! Every numerical threshold of `polycone`, with its unit, default and reason.
//!
//! All thresholds are **dimensionless**: the engine first maps the input to well-scaled
//! coordinates (see [`crate::precondition`]), where every generator and every constraint row is a
//! unit vector, so that a slack `u . x` of two unit vectors is the cosine of their angle, and a
//! threshold on it is a relative quantity independent of the units of the input.

/// The thresholds of one conversion. [`Tolerances::default`] gives the values documented on each
/// field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerances {
    /// The wrench preconditioning ([`crate::DdOptions::wrench`]) treats a row whose force part
    /// has norm at most `zero_generator` times the row's norm as a pure moment. Unit: relative
    /// norm within one row. Default `1e-14`: a few units in the last place of `f64`.
    ///
    /// No generator is negligible next to another: a cone does not change when one of its
    /// generators is multiplied by a positive number, so every row is scaled by a power of two
    /// (its largest entry into `[0.5, 1)`) before any decision, and only a row of zeros is a
    /// zero generator.
    pub zero_generator: f64,
    /// Rank decisions (the dimension of `span(V)`, hence the equations; the lineality space) treat
    /// a singular value at most `rank` times the largest one as zero. Unit: relative singular
    /// value. Default `1e-10`: far above the `~1e-15` rounding noise of an SVD, far below the
    /// smallest relative feature of a physical stance (a 10 um contact patch 1 km from the
    /// origin is `1e-8`).
    ///
    /// A singular value between the rounding level [`RANK_NOISE`] and `rank` (relative) leaves
    /// the dimension of `span(V)` undecided: dropping it is within the tolerance, but it is no
    /// rounding error either (a contact wrench cone written about a point 1e5 m away has two
    /// singular values near `1e-11`: it is 6-D, and dropping them lost two dimensions). The
    /// floating-point conversion then refuses to decide: [`crate::ConeError::RankUndecided`]
    /// (the wrench preconditioning, or exact arithmetic, decides it).
    pub rank: f64,
    /// Two preconditioned unit generators closer than `duplicate` (Euclidean distance) are the
    /// same ray; the later one is dropped. Unit: relative distance (radians, for small angles).
    /// Default `1e-12`: identical up to rounding.
    pub duplicate: f64,
    /// Incidence: a preconditioned unit generator `v` and a unit facet normal `u` with
    /// `|u . v| <= incidence` are incident (the generator lies on the facet). This is the epsilon
    /// of the tolerance contract: structure degenerate within it is merged. Unit: cosine
    /// (dimensionless). Default `1e-9`.
    pub incidence: f64,
    /// Largest violation `u . v` (unit vectors, preconditioned coordinates) a certified answer
    /// may show; also the largest residual allowed for equations and lineality. Unit: cosine.
    /// Default `1e-8`: ten times `incidence`, the room rounding needs on top of merged
    /// degeneracy.
    pub certificate: f64,
    /// Rank counts of incidence sets (the generators tight on a facet, projected on its
    /// hyperplane) treat a Gram-Schmidt residual at most `support_rank` as zero. Unit: relative
    /// norm (the vectors are unit). Default `1e-7`: well above `incidence` (vectors merged onto
    /// the hyperplane leave residuals below it), well below the separation of distinct
    /// generators of a physical stance after preconditioning.
    pub support_rank: f64,
    /// Largest condition number allowed for the coordinates a [`crate::Continuation`] works in.
    /// A continuation keeps the whitened coordinates of its last conversion from scratch (its
    /// frame) for the generators added since; the linear map from those coordinates to a fresh
    /// whitening of all its generators has a condition number `kappa <= sqrt(1 + sum |y|^2)`
    /// over the added generators `y` (frame coordinates, not normalized; the bound is
    /// tracked). Above `continuation_condition` the continuation moves its state to fresh
    /// coordinates before continuing (one SVD). Unit: ratio. Default `10`: a cosine `c` in the
    /// frame is between `c / kappa` and `kappa c` in fresh coordinates, so structure merged
    /// within `incidence` (`1e-9`) in the frame stays within `certificate` (`1e-8`) in the
    /// coordinates a conversion from scratch would use, and rounding in the double
    /// description is amplified at most tenfold. (Adding the second contact of the paper's
    /// stances gives bounds 4.4, 6.3 and 12.9.)
    pub continuation_condition: f64,
    /// A polar ray of a [`crate::Continuation`] (a facet normal) whose largest slack on the
    /// generators it is tight on exceeds `polish` is recomputed by projecting it on the
    /// orthogonal complement of those generators. Unit: cosine (unit vectors). Default
    /// `1e-12`: rays from scratch measure about `1e-15`; continued rays come from longer
    /// chains of combinations, and on near-degenerate stances (5 mm patches) reached `3e-11`,
    /// which turned facet normals by `1.3e-8` rad against the conversion from scratch.
    pub polish: f64,
    /// The wrench preconditioning ([`crate::DdOptions::wrench`]) solves `A o = b` for the centre
    /// of the generators (`A = sum_i |f_i|^2 I - f_i f_i^T`, see [`crate::wrench`]) on the
    /// eigenvectors of `A` whose eigenvalue is above `wrench_center` times the largest; along the
    /// others (forces all parallel, or nearly) the centre takes the minimum-norm solution. Unit:
    /// relative eigenvalue (the square of a relative spread of force directions). Default
    /// `1e-12`: force directions spread by less than `1e-6` rad do not locate the centre along
    /// them better than rounding would let a 1 km offset show.
    pub wrench_center: f64,
    /// The length scale `L` of the wrench preconditioning (see [`crate::wrench`]) is at least
    /// `wrench_length` times `|o|`, the distance from the reference point to the centre of the
    /// generators. Unit: ratio of lengths. Default `1e-5`: re-centring rounds the torques of
    /// forces through `o` by about `1.1e-16 |o| |f|`, so that noise divided by `L` stays at most
    /// `1.1e-11` relative to the forces, a tenth of [`Tolerances::rank`], and a point contact
    /// (re-centred torques zero up to rounding) keeps its three equations.
    pub wrench_length: f64,
    /// The wrench preconditioning fits its centre twice (see [`crate::wrench`]): rows whose
    /// lever arm about the first centre exceeds `wrench_outlier` times the median lever arm are
    /// left out of the second fit. Unit: ratio of lengths. Default `10`: the generators of a
    /// stance have lever arms within a few times each other (the size of the contact set);
    /// facet normals with almost no torque part (lever arms at "infinity", e.g. `1e4` times
    /// the median about a point 30 km away) must not pull the centre.
    pub wrench_outlier: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Self {
            zero_generator: 1e-14,
            rank: 1e-10,
            duplicate: 1e-12,
            incidence: 1e-9,
            certificate: 1e-8,
            support_rank: 1e-7,
            continuation_condition: 10.0,
            polish: 1e-12,
            wrench_center: 1e-12,
            wrench_length: 1e-5,
            wrench_outlier: 10.0,
        }
    }
}

impl Tolerances {
    /// Checks that every threshold is finite and non-negative.
    pub(crate) fn validate(&self) -> Result<(), crate::ConeError> {
        let all = [
            ("zero_generator", self.zero_generator),
            ("rank", self.rank),
            ("duplicate", self.duplicate),
            ("incidence", self.incidence),
            ("certificate", self.certificate),
            ("support_rank", self.support_rank),
            ("continuation_condition", self.continuation_condition),
            ("polish", self.polish),
            ("wrench_center", self.wrench_center),
            ("wrench_length", self.wrench_length),
            ("wrench_outlier", self.wrench_outlier),
        ];
        for (name, v) in all {
            if !(v.is_finite() && v >= 0.0) {
                return Err(crate::ConeError::BadTolerance { name, value: v });
            }
        }
        Ok(())
    }
}

/// The one-sided Jacobi SVD of the whitening ([`crate::precondition`]) stops when every pair of
/// columns `b_p, b_q` has `|b_p . b_q| <= JACOBI_ORTHOGONALITY |b_p| |b_q|`. Unit: cosine.
/// Value `eps = 2.2e-16`: the stopping cosine `c` leaves the right singular vectors of two
/// singular values `s_p > s_q` turned by about `c s_p s_q / (s_p^2 - s_q^2)`, so it must be
/// at rounding level: with `16 eps` a pair of singular values `3e-7` apart (relative; the
/// re-centred facets of a stance 30 km away) came out turned by `6e-9`, with `eps` by `1e-10`,
/// the accuracy of the general SVD. A computed cosine of `D`-vectors carries up to `D eps` of
/// rounding, so sweeps continue only while some cosine exceeds `D JACOBI_ORTHOGONALITY`
/// (the last sweep still rotates every pair above `JACOBI_ORTHOGONALITY`).
pub(crate) const JACOBI_ORTHOGONALITY: f64 = f64::EPSILON;

/// The whitening's Jacobi SVD skips a rotation that would move a column by at most
/// `JACOBI_NOISE` times the Frobenius norm of the triangular factor. Unit: relative norm.
/// Value `16 eps` (`3.6e-15`): Householder QR of a rank-deficient `n x d` input leaves about
/// `sqrt(n) d eps` of rounding in the columns that should be zero (`4e-15` for 20 x 8), and
/// each rotation adds a few `eps` of the longer column to the shorter one; rotating at that
/// level would go on for many sweeps and change nothing that matters. The skipped part is a
/// backward error of at most `16 eps |V|_F` per column, far below [`Tolerances::rank`].
pub(crate) const JACOBI_NOISE: f64 = 16.0 * f64::EPSILON;

/// Sweeps of the one-sided Jacobi SVD before it gives up and the whitening falls back to the
/// general SVD. Unit: count. Value `30`: Jacobi converges quadratically, 4 to 7 sweeps on the
/// cones of the tests; 30 is only reached on inputs it cannot handle (never seen).
pub(crate) const JACOBI_MAX_SWEEPS: usize = 30;

/// Largest entry (absolute) below which a column of the whitening's Householder QR is treated
/// as zero. Unit: absolute, on an input scaled by a power of two so that its largest entry is
/// in `[0.5, 2)`.
/// Value `2^-900` (`1.2e-271`): dropping it is a backward error 255 orders of magnitude below
/// `f64::EPSILON`, while every larger column can be rescaled by an exact power of two so that
/// its squares neither underflow nor overflow.
pub(crate) const QR_NEGLIGIBLE: f64 = f64::from_bits((1023 - 900) << 52);

/// Gradient entry below which the non-negative least squares of the fallback merge (module
/// `merge`) stop: no unit column improves the fit by more than this per unit weight. Unit:
/// absolute, on unit columns and a unit right-hand side. Value `1e-15`: a few `eps`, so the
/// fit goes to the rounding floor; stopping early only loosens the proven bound (the bound is
/// the residual actually reached), it never makes a merge unsound.
pub(crate) const NNLS_STATIONARY: f64 = 1e-15;

/// Cap on the least-squares solves of one non-negative least-squares fit (module `merge`), per
/// column. Unit: solves per column. Value 3: Lawson and Hanson's method ends in far fewer
/// (each column enters at most a few times on these well-scaled problems); the cap only bounds
/// the time of a cycling fit, which then returns its last feasible weights.
pub(crate) const NNLS_MAX_STEPS: usize = 3;

/// Relative margin by which a squared residual must beat the best one so far (a running
/// comparison) for the double description to pick its row for the initial basis: the row
/// picked is within this factor of the largest, and earlier rows win exact and near ties.
/// Unit: relative. Value `1e-9`: not a tolerance of the answer (any pivot within this factor of the largest is
/// as good numerically); it makes the choice independent of rounding in the last bits. The
/// whitened rows all have norm 1 to the last bit, and which one starts the basis sets the
/// size of the intermediate cones: on the 64-generator whole-space cone
/// (`opposing_walls_friction`) the last bit of the whitening moved the work by a large factor
/// (`bench/peers/cones.md`).
pub(crate) const BASIS_TIE: f64 = 1e-9;

/// The double description's initial basis takes, in input order, the first unit row whose
/// residual off the rows already taken is at least this (well clear of their span), and only
/// when none is, the row of largest residual. Input order keeps rows of one contact together,
/// and the intermediate cones start smaller than from the largest residual: fewer
/// instructions per conversion on most benchmark cones, a few more on two generic ones
/// (`bench/peers/cones.md`).
pub(crate) const BASIS_CLEAR: f64 = 0.7;

/// Largest ambient dimension the conversions accept. Unit: coordinates. Value `1024`: the
/// zero cone of that dimension already has a `1024 x 1024` equation matrix (8 MB), and the
/// double description's zero sets and pair tests grow with it; cones of the field are 3-D to
/// 6-D (forces, wrenches), a few tens for whole-body or multi-contact stacks. Beyond it a
/// clear error, instead of an allocation that overflows or exhausts memory.
pub const MAX_DIMENSION: usize = 1024;

/// Most rows (generators, or facets and equations) `stance cone` converts. Unit: rows. Value
/// `5000`: a 3-D cone of 5,000 generators on a circle converts in 1.5 s (debug build; 2,000 in
/// 0.13 s, 20,000 in 4 minutes, the work growing with rows times facets). Reason: bounded work
/// at the command line; the library's conversions take any count.
pub const MAX_COMMAND_ROWS: usize = 5000;

/// Relative singular value at or below which a direction of `span(V)` is rounding noise: the
/// rows of `V`, computed in floating point, carry relative errors of a few units in the last
/// place, and the SVD adds its own. Unit: relative to the largest singular value. Value
/// `64 f64::EPSILON` (`1.4e-14`). Between it and [`Tolerances::rank`] the rank is undecided (see
/// there).
pub const RANK_NOISE: f64 = 64.0 * f64::EPSILON;
