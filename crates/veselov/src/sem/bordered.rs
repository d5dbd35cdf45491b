//! The SEM step Jacobian in bordered form `[B c; rᵀ d]`, solved by block
//! elimination through the momentum block `B = h ∂²S/∂q₀∂q₁ = −M + O(h²)`.
//!
//! `B` is as well conditioned as the mass matrix, so eliminating through it
//! is stable; the Schur complement `σ = d − rᵀB⁻¹c` is the derivative of the
//! energy residual along the momentum equation (the ill-conditioned
//! direction, note 001 §3.4), and a vanishing `σ` is reported as a singular
//! Jacobian. Everything lives on the stack: `B⁻¹` from nalgebra's
//! fixed-size inverse, then `2N² + 3N` flops per solve.

use nalgebra::{SMatrix, SVector};

/// Factors of `[B c; rᵀ d]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct BorderedLu<const N: usize> {
    /// `B⁻¹`.
    inverse: SMatrix<f64, N, N>,
    /// `B⁻¹c`.
    column: SVector<f64, N>,
    /// `rᵀB⁻¹` (as a column).
    row: SVector<f64, N>,
    /// `σ = d − rᵀB⁻¹c`.
    schur: f64,
}

impl<const N: usize> BorderedLu<N> {
    /// Factor `[block column; rowᵀ corner]`; `None` if `B` or `σ` is singular
    /// or anything is not finite.
    pub(super) fn factor(
        block: &SMatrix<f64, N, N>,
        column: &SVector<f64, N>,
        row: &SVector<f64, N>,
        corner: f64,
    ) -> Option<Self> {
        let inverse = block.try_inverse()?;
        let b_column = inverse * column;
        let b_row = inverse.transpose() * row;
        let schur = corner - row.dot(&b_column);
        let finite = inverse
            .iter()
            .chain(b_column.iter())
            .chain(b_row.iter())
            .all(|x| x.is_finite());
        (finite && schur != 0.0 && schur.is_finite()).then_some(Self {
            inverse,
            column: b_column,
            row: b_row,
            schur,
        })
    }

    /// Solve `[B c; rᵀ d] (x, y) = (top, bottom)`.
    pub(super) fn solve(&self, top: &SVector<f64, N>, bottom: f64) -> (SVector<f64, N>, f64) {
        let y = (bottom - self.row.dot(top)) / self.schur;
        (self.inverse * top - self.column * y, y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix3, Vector3, Vector4};

    /// Against a dense solve of the assembled 4×4 system.
    #[test]
    fn matches_the_assembled_system() {
        let block = Matrix3::new(-2.0, 0.3, 0.1, 0.2, -1.5, 0.4, 0.0, 0.7, -3.0);
        let (column, row, corner) = (Vector3::new(0.5, -1.0, 2.0), Vector3::new(1.5, 0.25, -0.75), 0.125);
        let mut full = nalgebra::Matrix4::zeros();
        full.fixed_view_mut::<3, 3>(0, 0).copy_from(&block);
        full.fixed_view_mut::<3, 1>(0, 3).copy_from(&column);
        full.fixed_view_mut::<1, 3>(3, 0).copy_from(&row.transpose());
        full[(3, 3)] = corner;
        let rhs = Vector4::new(1.0, -2.0, 0.5, 3.0);
        let expected = full.lu().solve(&rhs).expect("regular");
        let lu = BorderedLu::factor(&block, &column, &row, corner).expect("regular");
        let (x, y) = lu.solve(&rhs.fixed_rows::<3>(0).into_owned(), rhs[3]);
        // Both are backward stable; the solution has entries up to 30.
        let scale = 1e-14 * expected.amax();
        assert!((x - expected.fixed_rows::<3>(0)).amax() < scale, "{x} {expected}");
        assert!((y - expected[3]).abs() < scale);
    }

    /// A vanishing Schur complement (the energy row a combination of the
    /// momentum rows) is singular, not a division by zero.
    #[test]
    fn singular_schur_complement_is_refused() {
        let block = Matrix3::identity() * -1.0;
        let column = Vector3::new(1.0, 2.0, 3.0);
        let row = Vector3::new(1.0, 0.0, 0.0);
        assert!(BorderedLu::factor(&block, &column, &row, -1.0).is_none());
        assert!(BorderedLu::factor(&Matrix3::zeros(), &column, &row, 1.0).is_none());
    }
}
