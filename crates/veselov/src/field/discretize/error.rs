//! Suitability errors of a discretised cell (note 003 §2.5 item 5, Def. 5.9;
//! Cor. 6.3 for the rod).

use std::fmt;

use crate::error::Error;
use crate::lie::LieError;

/// Why a top cell cannot be discretised with the given data: the cell is not
/// *suitable* (Def. 5.9), or its data are malformed. Every variant names the
/// cell by its index in the complex.
#[derive(Debug, Clone, PartialEq)]
pub enum CellError {
    /// The node map does not know the cell (a shape index outside the
    /// complex's shape classes) or gave a different number of vertices than
    /// the rule needs.
    Nodes {
        /// Index of the cell.
        cell: usize,
        /// Vertex count the rule needs.
        expected: usize,
        /// Vertex count the node map (or the caller's data) provided.
        got: usize,
    },
    /// The embedded cell is degenerate: the node matrix T^X (or X_β, (5.6))
    /// is singular, so the jet φ_u = T_Y (T^X)⁻¹ of Lemma 5.15 does not exist.
    SingularNodes {
        /// Index of the cell.
        cell: usize,
        /// |det T^X| relative to the product of its column norms.
        relative_determinant: f64,
    },
    /// The fibre logarithm between two vertex values failed (a rotation pair
    /// at the cut locus, angle ≈ π).
    Logarithm {
        /// Index of the cell.
        cell: usize,
        /// Position of the base vertex u in the cell.
        from: usize,
        /// Position of the other vertex v.
        to: usize,
        /// The underlying failure.
        source: LieError,
    },
    /// The vertex values lie too far apart for the geodesic interpolation of
    /// Def. 5.4 to be well defined (Lemma 5.5; for the rod Cor. 6.3: fewer than
    /// two pairwise traces tr(R_iᵀR_j) > 1).
    Unsuitable {
        /// Index of the cell.
        cell: usize,
        /// What failed.
        reason: String,
    },
    /// A vertex value, node or the resulting Lagrangian is NaN or infinite.
    NonFinite {
        /// Index of the cell.
        cell: usize,
        /// Which quantity.
        what: &'static str,
    },
}

impl CellError {
    /// Index of the offending cell.
    pub fn cell(&self) -> usize {
        match *self {
            CellError::Nodes { cell, .. }
            | CellError::SingularNodes { cell, .. }
            | CellError::Logarithm { cell, .. }
            | CellError::Unsuitable { cell, .. }
            | CellError::NonFinite { cell, .. } => cell,
        }
    }
}

impl fmt::Display for CellError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CellError::Nodes { cell, expected, got } => {
                write!(f, "cell {cell}: the rule needs {expected} vertices, got {got}")
            }
            CellError::SingularNodes {
                cell,
                relative_determinant,
            } => write!(
                f,
                "cell {cell}: degenerate embedded cell (relative node determinant {relative_determinant:e})"
            ),
            CellError::Logarithm { cell, from, to, source } => {
                write!(
                    f,
                    "cell {cell}: no logarithm from vertex {from} to vertex {to}: {source}"
                )
            }
            CellError::Unsuitable { cell, reason } => write!(f, "cell {cell} is not suitable: {reason}"),
            CellError::NonFinite { cell, what } => write!(f, "cell {cell}: non-finite {what}"),
        }
    }
}

impl std::error::Error for CellError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            CellError::Logarithm { source, .. } => Some(source),
            _ => None,
        }
    }
}

impl From<CellError> for Error {
    fn from(e: CellError) -> Self {
        Error::InvalidParameter {
            name: format!("cell {}", e.cell()),
            value: "its vertex values".to_string(),
            reason: e.to_string(),
        }
    }
}
