//! Finite windows of the lattices ℤⁿ, each axis open or periodic, with the
//! vertex and base-vertex numbering shared by the cubic and CFK lattices; and
//! the indexing of the symmetric group Sym(n).

use crate::complex::MAX_LATTICE_DIMENSION;
use crate::error::{Result, invalid};

/// A lattice point, zero beyond the dimension.
pub type Point = [i64; MAX_LATTICE_DIMENSION];

/// One axis of a window.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Axis {
    /// Number of unit cells along the axis.
    pub cells: usize,
    /// Periodic wrap (coordinates mod `cells`); open otherwise.
    pub periodic: bool,
}

impl Axis {
    /// An open axis of `cells` unit cells (`cells + 1` vertices, `cells ≥ 1`).
    pub fn open(cells: usize) -> Self {
        Self { cells, periodic: false }
    }
    /// A periodic axis of `cells` unit cells and as many vertices (`cells ≥ 3`).
    pub fn periodic(cells: usize) -> Self {
        Self { cells, periodic: true }
    }
    fn vertices(&self) -> usize {
        if self.periodic { self.cells } else { self.cells + 1 }
    }
}

/// Keeps the incident cells that lie in a window, replaced by their wrapped
/// representatives (`wrap` returns `None` outside the window).
pub(crate) fn keep_wrapped<C>(cells: &mut Vec<(C, i8)>, wrap: impl Fn(&C) -> Option<C>) {
    cells.retain_mut(|(c, _)| match wrap(c) {
        Some(w) => {
            *c = w;
            true
        }
        None => false,
    });
}

/// Checks a lattice dimension: 1 ≤ n ≤ [`MAX_LATTICE_DIMENSION`].
///
/// # Errors
/// [`Error::InvalidParameter`](crate::Error::InvalidParameter) naming `dimension`.
pub fn check_dimension(n: usize) -> Result<()> {
    if n == 0 || n > MAX_LATTICE_DIMENSION {
        return Err(invalid(
            "dimension",
            n,
            &format!("a lattice dimension must be in 1..={MAX_LATTICE_DIMENSION}"),
        ));
    }
    Ok(())
}

/// The box of vertices and base vertices of a window.
///
/// Vertex `p` (0 ≤ p_i < vertices along axis i) has index Σ_i p_i·stride_i
/// with axis 0 varying fastest; base vertices (0 ≤ p_i < cells_i) are numbered
/// the same way with their own strides.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Extent {
    n: usize,
    axes: Vec<Axis>,
    vertex_count: usize,
    base_count: usize,
}

impl Extent {
    /// A window with the given axes (`axes.len()` is the dimension).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) for a dimension outside
    /// 1..=[`MAX_LATTICE_DIMENSION`], an open axis of no cells, a periodic axis
    /// of fewer than 3 cells (the quotient would identify star-adjacent
    /// vertices), or a window whose size overflows.
    pub fn new(axes: &[Axis]) -> Result<Self> {
        check_dimension(axes.len())?;
        let mut vertex_count = 1usize;
        let mut base_count = 1usize;
        for (i, a) in axes.iter().enumerate() {
            if a.periodic && a.cells < 3 {
                return Err(invalid(
                    &format!("axes[{i}].cells"),
                    a.cells,
                    "a periodic axis needs at least 3 cells (window too small)",
                ));
            }
            if !a.periodic && a.cells == 0 {
                return Err(invalid(
                    &format!("axes[{i}].cells"),
                    a.cells,
                    "an open axis needs at least 1 cell (window too small)",
                ));
            }
            let overflow = || invalid(&format!("axes[{i}].cells"), a.cells, "the window is too large");
            // doubled coordinates up to 2·cells + 1 must fit an i64
            if a.cells > (i64::MAX / 4) as usize {
                return Err(overflow());
            }
            vertex_count = vertex_count.checked_mul(a.vertices()).ok_or_else(overflow)?;
            base_count = base_count.checked_mul(a.cells).ok_or_else(overflow)?;
        }
        Ok(Self {
            n: axes.len(),
            axes: axes.to_vec(),
            vertex_count,
            base_count,
        })
    }
    /// Dimension.
    pub fn dimension(&self) -> usize {
        self.n
    }
    /// The axes.
    pub fn axes(&self) -> &[Axis] {
        &self.axes
    }
    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.vertex_count
    }
    /// Number of base vertices (unit cubes).
    pub fn base_count(&self) -> usize {
        self.base_count
    }
    /// The canonical representative of `p` along axis `i` in a `scale`-fold
    /// refined lattice (`scale` = 2 for doubled coordinates), or `None` when
    /// it leaves an open axis (allowed range 0..=scale·cells).
    pub(crate) fn wrap_coordinate(&self, i: usize, x: i64, scale: i64) -> Option<i64> {
        let a = self.axes[i];
        let period = scale * a.cells as i64;
        if a.periodic {
            Some(x.rem_euclid(period))
        } else if (0..=period).contains(&x) {
            Some(x)
        } else {
            None
        }
    }
    /// The canonical representative of vertex `p`, `None` outside the window.
    pub fn wrap(&self, p: &Point) -> Option<Point> {
        let mut q = [0; MAX_LATTICE_DIMENSION];
        for i in 0..self.n {
            q[i] = self.wrap_coordinate(i, p[i], 1)?;
        }
        Some(q)
    }
    /// Index of vertex `p` (wrapped), `None` outside the window.
    pub fn vertex_index(&self, p: &Point) -> Option<usize> {
        let q = self.wrap(p)?;
        let mut index = 0usize;
        for i in (0..self.n).rev() {
            index = index * self.axes[i].vertices() + q[i] as usize;
        }
        Some(index)
    }
    /// Coordinates of vertex `index`.
    pub fn vertex(&self, mut index: usize) -> Point {
        let mut p = [0; MAX_LATTICE_DIMENSION];
        for i in 0..self.n {
            let m = self.axes[i].vertices();
            p[i] = (index % m) as i64;
            index /= m;
        }
        p
    }
    /// Index of base vertex `p` (wrapped), `None` when the unit cube at `p`
    /// leaves the window.
    pub fn base_index(&self, p: &Point) -> Option<usize> {
        let q = self.wrap(p)?;
        let mut index = 0usize;
        for i in (0..self.n).rev() {
            let m = self.axes[i].cells;
            if q[i] as usize >= m {
                return None;
            }
            index = index * m + q[i] as usize;
        }
        Some(index)
    }
    /// Coordinates of base vertex `index`.
    pub fn base(&self, mut index: usize) -> Point {
        let mut p = [0; MAX_LATTICE_DIMENSION];
        for i in 0..self.n {
            let m = self.axes[i].cells;
            p[i] = (index % m) as i64;
            index /= m;
        }
        p
    }
}

/// n! (n ≤ 20).
pub fn factorial(n: usize) -> usize {
    (1..=n).product()
}

/// The index of a permutation σ = (σ₀, …, σ_{n−1}) of 0..n in Sym(n): its
/// rank in lexicographic order (Lehmer code, σ₀ most significant), so the
/// identity is 0 and the reversal (n−1, …, 0) is n! − 1.
pub fn permutation_index(sigma: &[usize]) -> usize {
    let n = sigma.len();
    let mut index = 0;
    for a in 0..n {
        let smaller_later = sigma[a + 1..].iter().filter(|&&s| s < sigma[a]).count();
        index = index * (n - a) + smaller_later;
    }
    index
}

/// The permutation with the given index (inverse of [`permutation_index`]),
/// written into `sigma[..n]` (`index < n!`, `sigma.len() ≥ n`). This is the
/// lexicographic indexing of Sym(n) used for [`TopCell::shape`](crate::complex::TopCell::shape)
/// throughout the complex module.
pub fn permutation_into(n: usize, mut index: usize, sigma: &mut [usize]) {
    let mut digits = [0usize; MAX_LATTICE_DIMENSION];
    for a in (0..n).rev() {
        let radix = n - a;
        digits[a] = index % radix;
        index /= radix;
    }
    let mut used = 0u32;
    for a in 0..n {
        // the digits[a]-th unused value
        let mut skip = digits[a];
        let mut s = 0;
        loop {
            if used & (1 << s) == 0 {
                if skip == 0 {
                    break;
                }
                skip -= 1;
            }
            s += 1;
        }
        used |= 1 << s;
        sigma[a] = s;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn permutation_indexing_is_a_bijection() {
        for n in 1..=6 {
            let mut seen = vec![false; factorial(n)];
            let mut sigma = [0usize; MAX_LATTICE_DIMENSION];
            for index in 0..factorial(n) {
                permutation_into(n, index, &mut sigma);
                assert_eq!(permutation_index(&sigma[..n]), index);
                let mut sorted = sigma[..n].to_vec();
                sorted.sort_unstable();
                assert_eq!(sorted, (0..n).collect::<Vec<_>>());
                seen[index] = true;
            }
            assert!(seen.iter().all(|&s| s));
            let reversal: Vec<usize> = (0..n).rev().collect();
            assert_eq!(permutation_index(&reversal), factorial(n) - 1);
            assert_eq!(permutation_index(&(0..n).collect::<Vec<_>>()), 0);
        }
    }

    #[test]
    fn extent_numbers_vertices_and_wraps() {
        let e = Extent::new(&[Axis::periodic(3), Axis::open(2)]).expect("extent");
        assert_eq!((e.vertex_count(), e.base_count()), (9, 6));
        for v in 0..e.vertex_count() {
            assert_eq!(e.vertex_index(&e.vertex(v)), Some(v));
        }
        for b in 0..e.base_count() {
            assert_eq!(e.base_index(&e.base(b)), Some(b));
        }
        let mut p = [0; MAX_LATTICE_DIMENSION];
        p[0] = -1;
        p[1] = 2;
        assert_eq!(e.wrap(&p).map(|q| (q[0], q[1])), Some((2, 2)));
        assert_eq!(e.base_index(&p), None, "the cube at the open end leaves the window");
        p[1] = 3;
        assert_eq!(e.vertex_index(&p), None);
    }
}
