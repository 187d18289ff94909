//! Reports: the library's results as plain data to write out, one type per command's output
//! (serde; the command line writes them as JSON or TOML with one call, and their field names
//! are the file format). Matrices become lists of rows (generators and facets are rows, the
//! project's convention), statuses their machine names.
//!
//! Each report is built from the result it reports and nothing else the caller could get wrong:
//! [`SpanToFaceReport::new`] from a [`polycone::SpanToFace`], [`GiwcReport::new`] from the
//! stance and its [`Giwc`], and so on. The command line adds only what it was asked (the CoM
//! height of a polygon, the gravities of a region).

use nalgebra::{Dim, Matrix, RawStorage};
use polycone::{Certificate, FaceToSpan, SpanToFace};
use serde::Serialize;
use stance_contact::equilibrium::{PolygonRoute, RobustRegion, StaticPolygon};
use stance_contact::{Giwc, Stance};
use stance_robot::{Data, Model};

/// The rows of a matrix.
fn rows<R: Dim, C: Dim, S: RawStorage<f64, R, C>>(m: &Matrix<f64, R, C, S>) -> Vec<Vec<f64>> {
    m.row_iter().map(|r| r.iter().copied().collect()).collect()
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

/// How a cone conversion was computed (the part of its [`Certificate`] a reader needs).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConversionRoute {
    /// Whether the answer is certified.
    pub certified: bool,
    /// `"tolerance"`, `"exact"` (asked for) or `"exact_fallback"` ([`Certificate::route`]).
    pub arithmetic: &'static str,
    /// Why the floating-point answer was replaced by the exact one (exact fallback only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fallback_reason: Option<String>,
    /// Exact-fallback rows dropped as slivers ([`Certificate::merged_rows`]): any unit vector
    /// the output admits violates a dropped row by at most `merge_distance` (unit rows, the
    /// input's coordinates).
    #[serde(skip_serializing_if = "is_zero")]
    pub merged_rows: usize,
    /// The proven bound of the merge (when rows were merged).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub merge_distance: Option<f64>,
    /// The frame of the wrench route (`--wrench`), where its tolerances apply: facet rows
    /// `(u_f, u_t)` are compared as `(u_f - center x u_t, length u_t)`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wrench_frame: Option<WrenchFrameReport>,
}

/// [`polycone::wrench::WrenchFrame`]: its centre and length scale, in the input's units.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WrenchFrameReport {
    /// The centre `o`.
    pub center: [f64; 3],
    /// The length scale `L`.
    pub length: f64,
}

impl ConversionRoute {
    fn of(c: &Certificate) -> Self {
        ConversionRoute {
            certified: c.certified,
            arithmetic: c.route(),
            fallback_reason: c.fallback.clone(),
            merged_rows: c.merged_rows,
            merge_distance: (c.merged_rows > 0).then_some(c.merge_distance),
            wrench_frame: c.wrench_frame.map(|f| WrenchFrameReport {
                center: f.center,
                length: f.length,
            }),
        }
    }
}

/// `stance cone span-to-face`: the face form of a cone given by generators.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SpanToFaceReport {
    /// Dimension of the space.
    pub dim: usize,
    /// Facet rows `u` (`u . x <= 0`).
    pub facets: Vec<Vec<f64>>,
    /// Equation rows `e` (`e . x = 0`).
    pub equations: Vec<Vec<f64>>,
    /// A basis of the lineality space, one vector per row.
    pub lineality: Vec<Vec<f64>>,
    /// Indices of the input generators that are extreme.
    pub extreme_generators: Vec<usize>,
    /// Certificate and arithmetic.
    #[serde(flatten)]
    pub route: ConversionRoute,
}

impl SpanToFaceReport {
    /// The report of a conversion.
    ///
    /// ```
    /// use stance::polycone::{nalgebra::DMatrix, span_to_face, DdOptions};
    /// let r = span_to_face(&DMatrix::identity(3, 3), &DdOptions::default()).unwrap();
    /// let report = stance::report::SpanToFaceReport::new(&r);
    /// assert_eq!((report.facets.len(), report.route.arithmetic), (3, "tolerance"));
    /// ```
    pub fn new(r: &SpanToFace) -> Self {
        SpanToFaceReport {
            dim: r.face.dim,
            facets: rows(&r.face.facets),
            equations: rows(&r.face.equations),
            lineality: rows(&r.lineality),
            extreme_generators: r.extreme_generators.clone(),
            route: ConversionRoute::of(&r.certificate),
        }
    }
}

/// `stance cone face-to-span`: generators of a cone given by facets and equations.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FaceToSpanReport {
    /// Dimension of the space.
    pub dim: usize,
    /// Generator rows (extreme rays, lineality not included).
    pub generators: Vec<Vec<f64>>,
    /// A basis of the lineality space, one vector per row.
    pub lineality: Vec<Vec<f64>>,
    /// Indices of the input facets that are irredundant.
    pub irredundant_facets: Vec<usize>,
    /// Certificate and arithmetic (merged rows are generators here).
    #[serde(flatten)]
    pub route: ConversionRoute,
}

impl FaceToSpanReport {
    /// The report of a conversion.
    pub fn new(r: &FaceToSpan) -> Self {
        FaceToSpanReport {
            dim: r.span.dim,
            generators: rows(&r.span.generators),
            lineality: rows(&r.span.lineality),
            irredundant_facets: r.irredundant_facets.clone(),
            route: ConversionRoute::of(&r.certificate),
        }
    }
}

/// A face form as rows.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FaceRows {
    /// Facet rows.
    pub facets: Vec<Vec<f64>>,
    /// Equation rows.
    pub equations: Vec<Vec<f64>>,
    /// Lineality basis rows.
    pub lineality: Vec<Vec<f64>>,
}

/// `stance giwc`: the gravito-inertial wrench cone of a stance, both forms.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GiwcReport {
    /// The face form (`U_stance`, or its net-contact-wrench sign flip).
    pub giwc: FaceRows,
    /// The span form, one generator per row.
    pub span: Vec<Vec<f64>>,
    /// What the rows mean (sign, wrench point, order of force and torque).
    pub convention: &'static str,
    /// Whether the face form is certified.
    pub certified: bool,
    /// How the face form was computed: arithmetic and route, fallback reason, merged rows.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub route: Option<ConversionRoute>,
    /// The contacts' names, in order.
    pub contacts: Vec<String>,
}

impl GiwcReport {
    /// The report of `giwc`, the cone of `stance`; with `net_contact_wrench`, for the net
    /// contact wrench `w_c = -w_GI` instead of the paper's `w_GI` (rows and span negated).
    pub fn new(stance: &Stance, giwc: &Giwc, net_contact_wrench: bool) -> Self {
        let (facets, span, convention) = if net_contact_wrench {
            (
                giwc.net_contact_wrench_face().0,
                -stance.giwc_span(),
                "net contact wrench: rows u with u . w_c <= 0, w_c = -w_GI, wrench at the world origin (force, torque)",
            )
        } else {
            (
                giwc.facets.clone(),
                stance.giwc_span(),
                "GIWC (paper): rows u with u . w_GI <= 0, wrench at the world origin (force, torque)",
            )
        };
        GiwcReport {
            giwc: FaceRows {
                facets: rows(&facets),
                equations: rows(&giwc.equations),
                lineality: rows(&giwc.lineality),
            },
            span: rows(&span),
            convention,
            certified: giwc.certified,
            route: giwc.certificate.as_ref().map(ConversionRoute::of),
            contacts: stance
                .contacts()
                .iter()
                .map(|c| c.name().to_string())
                .collect(),
        }
    }
}

/// `stance equilibrium polygon`: the static-equilibrium polygon at a CoM height.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PolygonReport {
    /// `"empty"`, `"bounded"` or `"unbounded"`.
    pub status: &'static str,
    /// `"direct"`, or `"u_stance"` with the reason when the direct route gave way (or
    /// `"u_stance (requested)"`).
    pub route: String,
    /// 2 for a proper polygon, 1 for a segment, 0 for a point (or empty).
    pub dim: usize,
    /// Vertices `(x, y)`, counter-clockwise.
    pub vertices: Vec<[f64; 2]>,
    /// Half-planes `[n_x, n_y, b]` with `n . (x, y) <= b`.
    pub halfplanes: Vec<[f64; 3]>,
    /// The CoM height (m).
    pub height: f64,
    /// The gravity (m/s^2).
    pub gravity: [f64; 3],
}

impl PolygonReport {
    /// The report of `poly`, computed at CoM height `height` under `gravity` by `route`
    /// (`None`: through `U_stance`, as requested).
    pub fn new(
        poly: &StaticPolygon,
        route: Option<&PolygonRoute>,
        height: f64,
        gravity: [f64; 3],
    ) -> Self {
        let route = match route {
            None => "u_stance (requested)".to_string(),
            Some(PolygonRoute::Direct) => "direct".to_string(),
            Some(PolygonRoute::ViaUStance(why)) => format!("u_stance ({why:?})"),
        };
        PolygonReport {
            status: poly.status.name(),
            route,
            dim: poly.dim,
            vertices: poly.vertices.clone(),
            halfplanes: poly
                .halfplanes
                .iter()
                .map(|(n, b)| [n[0], n[1], *b])
                .collect(),
            height,
            gravity,
        }
    }
}

/// `stance equilibrium region`: the robust static-equilibrium region as a polyhedron.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RegionReport {
    /// `"empty"`, `"bounded"` or `"unbounded"`.
    pub status: &'static str,
    /// Vertices (m).
    pub vertices: Vec<[f64; 3]>,
    /// Faces as vertex indices, counter-clockwise from outside.
    pub faces: Vec<Vec<usize>>,
    /// Irredundant half-spaces `[n_x, n_y, n_z, d]` with `n . p <= d`.
    pub halfspaces: Vec<[f64; 4]>,
    /// The gravity-like vectors (m/s^2).
    pub gravities: Vec<[f64; 3]>,
}

impl RegionReport {
    /// The report of a region.
    pub fn new(region: &RobustRegion) -> Self {
        let p = &region.polyhedron;
        RegionReport {
            status: p.status.name(),
            vertices: p.vertices.clone(),
            faces: p.faces.clone(),
            halfspaces: region
                .halfspaces
                .normals
                .iter()
                .zip(&region.halfspaces.offsets)
                .map(|(n, d)| [n[0], n[1], n[2], *d])
                .collect(),
            gravities: region.gravities.clone(),
        }
    }
}

/// `stance equilibrium test`: which CoMs are in the robust region.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StabilityReport {
    /// One answer per point.
    pub stable: Vec<bool>,
    /// Signed distance to the region's boundary (m, positive inside), when asked for.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub margin: Option<Vec<f64>>,
    /// The gravity-like vectors (m/s^2).
    pub gravities: Vec<[f64; 3]>,
}

/// `stance robot centroidal`: centroidal quantities of a configuration.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CentroidalReport {
    /// Total mass (kg).
    pub mass: f64,
    /// CoM (m, world).
    pub com: Vec<f64>,
    /// CoM Jacobian (3 x nv rows).
    pub com_jacobian: Vec<Vec<f64>>,
    /// Centroidal momentum matrix `A_g` (6 x nv rows).
    pub centroidal_map: Vec<Vec<f64>>,
    /// `A_g' v`.
    pub centroidal_map_dot_v: Vec<f64>,
    /// Movable joint names, in order.
    pub joint_names: Vec<String>,
    /// Configuration size.
    pub nq: usize,
    /// Velocity size.
    pub nv: usize,
}

impl CentroidalReport {
    /// The report of `data`, filled by `stance_robot::centroidal_map_dot_v` for `model`, whose
    /// result is `dh` (`A_g' v`).
    pub fn new(model: &Model, data: &Data, dh: &[f64]) -> Self {
        CentroidalReport {
            mass: data.mass,
            com: data.com.as_slice().to_vec(),
            com_jacobian: rows(&data.com_jacobian),
            centroidal_map: rows(&data.centroidal_map),
            centroidal_map_dot_v: dh.to_vec(),
            joint_names: model.joint_names(),
            nq: model.nq,
            nv: model.nv,
        }
    }
}
