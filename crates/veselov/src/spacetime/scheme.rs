//! The scalar nonlinear-wave schemes of seed 002 §5.2 and their discrete
//! energies. Notation: `y_ij ≈ φ(i·k, j·h)`, `h = dt`, `k = dx`,
//! `∂_k² y_ij = y_{i+1,j} − 2y_ij + y_{i−1,j}`, `∂_h² y_ij = y_{i,j+1} − 2y_ij + y_{i,j−1}`.

/// A three-level scheme for `φ_tt − φ_xx − N′(φ) = 0`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Scheme {
    /// Multisymplectic triangle scheme (5.8):
    /// `∂_k²y/k² − ∂_h²y/h² + ⅓[N′(ȳ_{Δ(i,j)}) + N′(ȳ_{Δ(i,j−1)}) + N′(ȳ_{Δ(i−1,j−1)})] = 0`,
    /// `ȳ_Δ` the centroid. Energy: footnote 5 with `k` (not `2k`):
    /// `E_j = Σ_i ½((y_{i,j+1}−y_ij)/h)² + ½((y_{i+1,j}−y_ij)/k)² − N(ȳ_{Δ(i,j)})`.
    Triangle,
    /// Footnote-3 variant of (5.8): the potential at vertex 1,
    /// `y_{i,j+1} = 2y_ij − y_{i,j−1} + (h/k)²∂_k²y_ij + h²N′(y_ij)` (explicit).
    /// Energy: the triangle energy with `N(y_ij)`.
    TriangleExplicit,
    /// Multisymplectic rectangle scheme (5.9)/(5.10):
    /// `(1/k²)[¼∂_k²y_{i,j+1} + ½∂_k²y_ij + ¼∂_k²y_{i,j−1}] − ∂_h²y_ij/h² + N̄′ = 0`,
    /// `N̄′` the mean of `N′` at the averages of the four rectangles touching
    /// the node. Energy: footnote 4.
    Rectangle,
    /// Symmetric (box) rectangle scheme (5.12): as (5.10) with the time
    /// difference averaged, `(1/h²)[¼∂_h²y_{i+1,j} + ½∂_h²y_ij + ¼∂_h²y_{i−1,j}]`.
    /// Energy: footnote 4. Even `N` admits the parasitic mode `(A + Bj)(−1)^{i+j}`.
    SymmetricRectangle,
    /// Vu-Quoc & Li (5.14): the linear part of (5.10) with
    /// `½[(N(y_{i,j+1}) − N(y_ij))/(y_{i,j+1} − y_ij) + (N(y_ij) − N(y_{i,j−1}))/(y_ij − y_{i,j−1})]`.
    /// Energy: footnote 4 (not conserved by this scheme).
    VuQuocLi,
    /// Guo, Pascual, Rodriguez & Vázquez (5.15):
    /// `∂_k²y/k² − ∂_h²y/h² + (N(y_{i,j+1}) − N(y_{i,j−1}))/(y_{i,j+1} − y_{i,j−1}) = 0`.
    /// Energy: the exactly conserved
    /// `E^{j+½} = Σ_i ½((y_{i,j+1}−y_ij)/h)² + ½(y_{i+1,j+1}−y_{i,j+1})(y_{i+1,j}−y_ij)/k² − ½(N(y_{i,j+1}) + N(y_ij))`.
    Guo,
}

impl Scheme {
    /// All schemes.
    pub const ALL: [Scheme; 6] = [
        Scheme::Triangle,
        Scheme::TriangleExplicit,
        Scheme::Rectangle,
        Scheme::SymmetricRectangle,
        Scheme::VuQuocLi,
        Scheme::Guo,
    ];
    /// A short name (`triangle`, `triangle-explicit`, `rectangle`,
    /// `symmetric-rectangle`, `vu-quoc-li`, `guo`).
    pub fn name(&self) -> &'static str {
        match self {
            Scheme::Triangle => "triangle",
            Scheme::TriangleExplicit => "triangle-explicit",
            Scheme::Rectangle => "rectangle",
            Scheme::SymmetricRectangle => "symmetric-rectangle",
            Scheme::VuQuocLi => "vu-quoc-li",
            Scheme::Guo => "guo",
        }
    }
    /// Parse a [`Scheme::name`].
    pub fn from_name(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|x| x.name() == s)
    }
    /// Is the scheme the DELf of a discrete Lagrangian (multisymplectic)?
    pub fn is_multisymplectic(&self) -> bool {
        matches!(
            self,
            Scheme::Triangle | Scheme::TriangleExplicit | Scheme::Rectangle | Scheme::SymmetricRectangle
        )
    }
}
