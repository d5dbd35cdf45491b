//! The exact derivatives of a cell Lagrangian in the fibre's chart, by
//! dual-number passes over [`DiscreteLagrangian::cell_lagrangian`]: vertex
//! gradients (one pass of M directions), the gradients at the later
//! vertices of a cell, the mixed blocks ∂²L_β/∂y_a∂y_b (hyper-duals), and
//! the check of a model's closed forms against them.
use nalgebra::{Const, SMatrix, SVector, U1};
use num_dual::{Dual64, DualSVec, DualSVec64, HyperDual64, HyperDualSVec64};

use super::{DiscreteLagrangian, MAX_CELL_VERTICES, SMALL_CELL, with_values};
use crate::ad::Scalar;
use crate::complex::TopCell;
use crate::field::fibre::Fibre;

/// The seeds e_i (i = 0..M) of M-direction dual numbers over `D`.
pub fn seeds<D: Scalar, const M: usize>() -> SVector<DualSVec<D, M>, M> {
    SVector::from_fn(|i, _| DualSVec::<D, M>::from_re(D::zero()).derivative(i))
}

fn gradient_of<const M: usize>(x: DualSVec64<M>) -> (f64, SVector<f64, M>) {
    (x.re, x.eps.unwrap_generic(Const::<M>, U1))
}

/// L_β and ∂L_β/∂y_l (the derivative of L_β(…, y_l·τ(ξ), …) at ξ = 0).
pub fn vertex_gradient<F, L, const M: usize>(
    lag: &L,
    cell: &TopCell,
    y: &[F::Point<f64>],
    l: usize,
) -> (f64, SVector<f64, M>)
where
    F: Fibre<M>,
    L: DiscreteLagrangian<F, M> + ?Sized,
{
    debug_assert!(y.len() <= MAX_CELL_VERTICES && l < y.len());
    if M == 1 {
        // One direction: the plain dual number, whose derivative part is a
        // number rather than an optional vector (the same operations).
        let x = seeded_pass::<F, L, Dual64, M>(
            lag,
            cell,
            y,
            l,
            &SVector::from_element(Dual64::from_re(0.0).derivative()),
        );
        return (x.re, SVector::from_element(x.eps));
    }
    gradient_of(seeded_pass::<F, L, _, M>(lag, cell, y, l, &seeds::<f64, M>()))
}

/// L_β over the scalar D with vertex l's chart carrying `seeds`
/// (y_l·τ(ξ) at ξ = `seeds`) and the other vertices as constants.
#[inline]
fn seeded_pass<F, L, D, const M: usize>(
    lag: &L,
    cell: &TopCell,
    y: &[F::Point<f64>],
    l: usize,
    seeds: &SVector<D, M>,
) -> D
where
    F: Fibre<M>,
    L: DiscreteLagrangian<F, M> + ?Sized,
    D: Scalar,
{
    let seeded = F::retract_seeded(&y[l], seeds);
    with_values(
        y.len(),
        |i| if i == l { seeded } else { F::lift(&y[i]) },
        |v| lag.cell_lagrangian(cell, v),
    )
}

/// Directions of the one dual pass of [`later_gradients`].
pub const LATER_DIRECTIONS: usize = 4;

/// ∂L_β/∂y_l for every later vertex l = 1 … k − 1 (k = `y.len()`) into
/// `out[l]`, by one dual pass in which vertex l's chart carries the
/// directions (l − 1)M … lM − 1: one evaluation of L_β (and of its
/// transcendental functions) instead of k − 1. Only when those fit in
/// [`LATER_DIRECTIONS`] (a scalar field on lattices up to dimension 4);
/// returns `false` otherwise, and the caller takes them one by one
/// ([`vertex_gradient`], the same numbers to round-off).
pub fn later_gradients<F, L, const M: usize>(
    lag: &L,
    cell: &TopCell,
    y: &[F::Point<f64>],
    out: &mut [SVector<f64, M>],
) -> bool
where
    F: Fibre<M>,
    L: DiscreteLagrangian<F, M> + ?Sized,
{
    let k = y.len();
    if k < 2 || (k - 1) * M > LATER_DIRECTIONS || out.len() < k {
        return false;
    }
    // A dual number of exactly (k − 1)M directions: each direction's part
    // is computed alone, so a wider one gives the same bits for more work.
    match (k - 1) * M {
        1 => later_pass::<F, L, M, 1>(lag, cell, y, out),
        2 => later_pass::<F, L, M, 2>(lag, cell, y, out),
        3 => later_pass::<F, L, M, 3>(lag, cell, y, out),
        _ => later_pass::<F, L, M, LATER_DIRECTIONS>(lag, cell, y, out),
    }
    true
}

/// [`later_gradients`]' dual pass with W ≥ (k − 1)M directions.
#[inline]
fn later_pass<F, L, const M: usize, const W: usize>(
    lag: &L,
    cell: &TopCell,
    y: &[F::Point<f64>],
    out: &mut [SVector<f64, M>],
) where
    F: Fibre<M>,
    L: DiscreteLagrangian<F, M> + ?Sized,
{
    let k = y.len();
    let value = with_values(
        k,
        |i| {
            if i == 0 {
                F::lift::<DualSVec64<W>>(&y[0])
            } else {
                let seeds = SVector::<DualSVec64<W>, M>::from_fn(|m, _| {
                    DualSVec64::<W>::from_re(0.0).derivative((i - 1) * M + m)
                });
                F::retract_seeded(&y[i], &seeds)
            }
        },
        |v| lag.cell_lagrangian(cell, v),
    );
    let eps = value.eps.unwrap_generic(Const::<W>, U1);
    for (l, g) in out.iter_mut().enumerate().take(k).skip(1) {
        *g = SVector::from_fn(|m, _| eps[(l - 1) * M + m]);
    }
}

/// ∂L_β/∂y_l: the Lagrangian's closed form
/// ([`DiscreteLagrangian::analytic_gradient`], else
/// [`DiscreteLagrangian::analytic_gradients`]) where it offers one, the
/// dual pass ([`vertex_gradient`]) otherwise.
pub fn exact_gradient<F, L, const M: usize>(lag: &L, cell: &TopCell, y: &[F::Point<f64>], l: usize) -> SVector<f64, M>
where
    F: Fibre<M>,
    L: DiscreteLagrangian<F, M> + ?Sized,
{
    if let Some(g) = lag.analytic_gradient(cell, y, l) {
        return g;
    }
    let k = y.len();
    if k <= SMALL_CELL {
        let mut out = [SVector::zeros(); SMALL_CELL];
        if lag.analytic_gradients(cell, y, &mut out[..k]) {
            return out[l];
        }
    } else if k <= MAX_CELL_VERTICES {
        let mut out = [SVector::zeros(); MAX_CELL_VERTICES];
        if lag.analytic_gradients(cell, y, &mut out[..k]) {
            return out[l];
        }
    }
    vertex_gradient::<F, L, M>(lag, cell, y, l).1
}

/// Checks the Lagrangian's closed-form gradients
/// ([`DiscreteLagrangian::analytic_gradients`]) against the derivative of
/// its own cell Lagrangian ([`vertex_gradient`]) on one cell: a closed form
/// resting on a declaration of the model (such as
/// [`SmoothDensity::diagonal_jet_metric`](crate::field::discretize::SmoothDensity::diagonal_jet_metric))
/// that does not hold gives another gradient. The comparison is made at the
/// vertex values `y` moved by fixed chart steps of size 1e-2 in every
/// direction, so that every term of the Lagrangian varies (a direction along
/// which the data do not vary would hide a wrong declaration for it) and no
/// gradient is at round-off level (data at rest, say). `Ok` where the
/// Lagrangian has no closed form or is not finite there (suitability is
/// checked elsewhere).
///
/// # Errors
/// [`Error::InvalidParameter`](crate::Error::InvalidParameter) for
/// `cell Lagrangian`, the cell named by `name()`, where the two differ by
/// more than 1e-9 of the cell's largest gradient entry at some vertex (they
/// agree to round-off where the declaration holds).
pub fn check_closed_form<F, L, const M: usize>(
    lag: &L,
    cell: &TopCell,
    y: &[F::Point<f64>],
    name: impl FnOnce() -> String,
) -> crate::Result<()>
where
    F: Fibre<M>,
    L: DiscreteLagrangian<F, M> + ?Sized,
{
    let k = y.len();
    if k == 0 || k > MAX_CELL_VERTICES {
        return Ok(());
    }
    let mut moved = [y[0]; MAX_CELL_VERTICES];
    for (l, z) in moved.iter_mut().enumerate().take(k) {
        let step = SVector::<f64, M>::from_fn(|c, _| 1e-2 * (1.0 + 3.7 * l as f64 + 1.3 * c as f64).sin());
        *z = F::retract(&y[l], &step);
    }
    let moved = &moved[..k];
    let mut closed = [SVector::<f64, M>::zeros(); MAX_CELL_VERTICES];
    if !lag.analytic_gradients(cell, moved, &mut closed[..k]) {
        return Ok(());
    }
    let mut dual = [SVector::<f64, M>::zeros(); MAX_CELL_VERTICES];
    for (l, g) in dual.iter_mut().enumerate().take(k) {
        *g = vertex_gradient::<F, L, M>(lag, cell, moved, l).1;
    }
    if !dual[..k]
        .iter()
        .chain(&closed[..k])
        .all(|g| g.iter().all(|x| x.is_finite()))
    {
        return Ok(());
    }
    let scale = dual[..k].iter().map(|g| g.amax()).fold(0.0, f64::max);
    for l in 0..k {
        let difference = (closed[l] - dual[l]).amax();
        if difference > 1e-9 * scale.max(f64::MIN_POSITIVE) {
            return Err(crate::Error::InvalidParameter {
                name: "cell Lagrangian".into(),
                value: name(),
                reason: format!(
                    "its closed-form gradient at vertex {l} differs from the derivative of its cell Lagrangian by \
                 {difference:.2e} ({:.1e} of the largest entry {scale:.2e}): a declaration the closed form rests on \
                 (such as SmoothDensity::diagonal_jet_metric) does not hold",
                    difference / scale.max(f64::MIN_POSITIVE)
                ),
            });
        }
    }
    Ok(())
}

/// ∂L_β/∂y_a and its derivative with respect to y_b:
/// `J[(i, j)] = ∂/∂ζ_j (∂L_β/∂y_a)_i` at y_b·τ(ζ), ζ = 0. For b = a it is
/// the second derivative of L_β(…, y_a·τ(ζ)·τ(ξ), …) at ξ = ζ = 0: the
/// derivative of the gradient at the moved point y_a·τ(ζ), in that point's
/// chart — the Jacobian of a vertex residual under Newton's update
/// y_a ← y_a·τ(δ) (the Hessian, symmetric, on ℝ^M).
///
/// The Lagrangian's own evaluation ([`DiscreteLagrangian::analytic_block`])
/// where it has one, the hyper-dual pass ([`mixed_block_dual`]) otherwise.
/// The gradient it returns beside the block may differ from
/// [`exact_gradient`]'s in its last bits: the vertex solvers take their
/// residuals from the latter.
pub fn mixed_block<F, L, const M: usize>(
    lag: &L,
    cell: &TopCell,
    y: &[F::Point<f64>],
    a: usize,
    b: usize,
) -> (SVector<f64, M>, SMatrix<f64, M, M>)
where
    F: Fibre<M>,
    L: DiscreteLagrangian<F, M> + ?Sized,
{
    lag.analytic_block(cell, y, a, b)
        .unwrap_or_else(|| mixed_block_dual::<F, L, M>(lag, cell, y, a, b))
}

/// [`mixed_block`] by one pass of hyper-dual numbers over L_β (the
/// reference): ε₁ seeds y_a's M directions, ε₂ y_b's, and the ε₁ε₂ part is
/// the block; for M = 1 the plain hyper-dual number. The same derivatives
/// as first-order duals nested in first-order duals, in one flat number
/// (1 + 2M + M² parts) that its operations do not copy level by level.
/// With a Jacobian at every vertex, a vertex solve of the `field_core`
/// frame field on ℝ³ × SO(3) took 1.70 M instructions instead of 2.54 M
/// with the nested pass, one of its scalar P1 field 12.6 k instead of
/// 14.8 k.
pub fn mixed_block_dual<F, L, const M: usize>(
    lag: &L,
    cell: &TopCell,
    y: &[F::Point<f64>],
    a: usize,
    b: usize,
) -> (SVector<f64, M>, SMatrix<f64, M, M>)
where
    F: Fibre<M>,
    L: DiscreteLagrangian<F, M> + ?Sized,
{
    if M == 1 {
        // One direction each: the plain hyper-dual number, whose parts are
        // numbers rather than optional vectors (the same operations).
        let value = hyper_pass::<F, L, HyperDual64, M>(
            lag,
            cell,
            y,
            (a, b),
            &SVector::from_element(HyperDual64::from_re(0.0).derivative1()),
            &SVector::from_element(HyperDual64::from_re(0.0).derivative2()),
        );
        return (SVector::from_element(value.eps1), SMatrix::from_element(value.eps1eps2));
    }
    type Hyper<const M: usize> = HyperDualSVec64<M, M>;
    let inner = SVector::from_fn(|i, _| Hyper::<M>::from_re(0.0).derivative1(i));
    let outer = SVector::from_fn(|i, _| Hyper::<M>::from_re(0.0).derivative2(i));
    let value = hyper_pass::<F, L, Hyper<M>, M>(lag, cell, y, (a, b), &inner, &outer);
    let grad = value.eps1.unwrap_generic(Const::<M>, U1);
    let block = value.eps1eps2.unwrap_generic(Const::<M>, Const::<M>);
    (grad, block)
}

/// L_β over the hyper-dual scalar D with y_a's chart carrying the ε₁
/// directions `inner` and y_b's the ε₂ directions `outer`
/// ([`mixed_block_dual`]).
fn hyper_pass<F, L, D, const M: usize>(
    lag: &L,
    cell: &TopCell,
    y: &[F::Point<f64>],
    (a, b): (usize, usize),
    inner: &SVector<D, M>,
    outer: &SVector<D, M>,
) -> D
where
    F: Fibre<M>,
    L: DiscreteLagrangian<F, M> + ?Sized,
    D: Scalar,
{
    let k = y.len();
    debug_assert!(k <= MAX_CELL_VERTICES && a < k && b < k);
    // For b = a the outer step comes first, y_a·τ(ζ)·τ(ξ): the gradient at
    // the moved point in its own chart, which is what Newton's update
    // y_a ← y_a·τ(δ) changes (on a group, y_a·τ(ξ)·τ(ζ) would differ by a
    // bracket term of the size of the gradient itself).
    let ya = if a == b {
        F::retract(&F::retract_seeded(&y[a], outer), inner)
    } else {
        F::retract_seeded(&y[a], inner)
    };
    let yb = F::retract_seeded(&y[b], outer);
    with_values(
        k,
        |i| {
            if i == a {
                ya
            } else if i == b && b != a {
                yb
            } else {
                F::lift(&y[i])
            }
        },
        |v| lag.cell_lagrangian(cell, v),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::fibre::Euclidean;

    /// A scalar cell Lagrangian with products, a quotient and transcendental
    /// functions of every vertex value.
    struct Scalar1;

    impl DiscreteLagrangian<Euclidean<1>, 1> for Scalar1 {
        fn cell_lagrangian<D: Scalar>(&self, _cell: &TopCell, y: &[SVector<D, 1>]) -> D {
            let mean = y.iter().fold(D::zero(), |acc, v| acc + v[0]) / y.len() as f64;
            let d = y[y.len() - 1][0] - y[0][0];
            d * d * 0.5 - (D::one() - mean.cos()) + (y[0][0] * 0.3).sin() / (mean * mean + 2.0)
        }
    }

    /// The cell the tests evaluate [`Scalar1`] on (which ignores it).
    const CELL: TopCell = TopCell {
        index: 0,
        shape: 0,
        origin: [0; crate::complex::MAX_LATTICE_DIMENSION],
    };

    /// 50 random scalar cells of each size from 2 to `largest` vertices.
    fn random_cells(seed: u64, largest: usize) -> Vec<Vec<SVector<f64, 1>>> {
        let mut uniform = crate::test_support::uniform(seed);
        let mut cells = Vec::new();
        for k in 2..=largest {
            for _ in 0..50 {
                cells.push((0..k).map(|_| SVector::from([3.0 * uniform()])).collect());
            }
        }
        cells
    }

    /// [`later_gradients`]' pass of exactly (k − 1)M directions gives the
    /// bits of the widest pass, for cells of 2 to 4 vertices.
    #[test]
    fn later_gradients_narrow_pass_has_the_bits_of_the_wide_one() {
        for y in random_cells(0x2d35_8dcc_aa6c_78a5, 4) {
            let k = y.len();
            let mut narrow = [SVector::zeros(); 4];
            assert!(later_gradients::<Euclidean<1>, _, 1>(&Scalar1, &CELL, &y, &mut narrow));
            let mut wide = [SVector::zeros(); 4];
            later_pass::<Euclidean<1>, _, 1, LATER_DIRECTIONS>(&Scalar1, &CELL, &y, &mut wide);
            for l in 1..k {
                assert_eq!(narrow[l][0].to_bits(), wide[l][0].to_bits(), "k = {k}, l = {l}");
                assert!(narrow[l][0] != 0.0, "k = {k}, l = {l}: a zero gradient tests nothing");
            }
        }
    }

    /// The one-direction path of [`vertex_gradient`] gives the bits of the
    /// M-direction dual pass it stands in for, at every vertex of random
    /// cells of 2 to 5 vertices.
    #[test]
    fn one_direction_gradient_has_the_bits_of_the_vector_dual_pass() {
        for y in random_cells(0x5851_f42d_4c95_7f2d, 5) {
            let k = y.len();
            for l in 0..k {
                let (value, gradient) = vertex_gradient::<Euclidean<1>, _, 1>(&Scalar1, &CELL, &y, l);
                let (vector_value, vector_gradient) = gradient_of(seeded_pass::<Euclidean<1>, _, _, 1>(
                    &Scalar1,
                    &CELL,
                    &y,
                    l,
                    &seeds::<f64, 1>(),
                ));
                assert_eq!(value.to_bits(), vector_value.to_bits(), "value, k = {k}, l = {l}");
                assert_eq!(
                    gradient[0].to_bits(),
                    vector_gradient[0].to_bits(),
                    "gradient, k = {k}, l = {l}: {gradient} against {vector_gradient}"
                );
            }
        }
    }
}
