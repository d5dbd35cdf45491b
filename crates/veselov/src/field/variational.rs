//! The variational layer of the field core (seed 003 §3): discrete action,
//! Euler–Lagrange residuals by scattering per-cell gradients, vertex classes
//! of a domain, and the discrete Noether theorem (Thm 3.15) — the full
//! identity, valid for every field, and the current through the frontier of
//! any finite domain — and the discrete multisymplectic form formula on any
//! domain ([`multisymplectic_form_sum`]).
//!
//! All of it works on any complex through its top-cell view [`TopCells`] and
//! on any fibre; gradients are exact (num-dual) in the fibre's chart.

use nalgebra::SVector;

use super::cell::{DiscreteLagrangian, MAX_CELL_VERTICES, mixed_block, vertex_gradient};
use super::fibre::Fibre;
use crate::complex::{StarEntry, TopCells};
use crate::{Error, Result};

/// Checks that a field has one value per vertex.
fn check_field<C: TopCells + ?Sized, T>(complex: &C, y: &[T]) -> Result<()> {
    if y.len() != complex.vertex_count() {
        return Err(Error::DimensionMismatch {
            what: "field values (one per vertex of the complex)".into(),
            expected: complex.vertex_count(),
            got: y.len(),
        });
    }
    Ok(())
}

/// Copies the values at the vertices of `cell` into `buf`; returns their number.
fn gather<C, P: Copy>(
    complex: &C,
    y: &[P],
    cell: usize,
    verts: &mut [usize; MAX_CELL_VERTICES],
    buf: &mut Vec<P>,
) -> usize
where
    C: TopCells + ?Sized,
{
    let k = complex.cell_vertices(cell, verts);
    buf.clear();
    buf.extend(verts[..k].iter().map(|&v| y[v]));
    k
}

/// The discrete action 𝕃_A(y) = Σ_{β∈A} L_β(y_β) (Def. 3.8) over the cells
/// `domain` (indices of top cells).
pub fn action<F, L, C, const M: usize>(
    complex: &C,
    lag: &L,
    y: &[F::Point<f64>],
    domain: impl IntoIterator<Item = usize>,
) -> Result<f64>
where
    F: Fibre<M>,
    L: DiscreteLagrangian<F, M>,
    C: TopCells + ?Sized,
{
    check_field(complex, y)?;
    let mut verts = [0; MAX_CELL_VERTICES];
    let mut buf = Vec::with_capacity(MAX_CELL_VERTICES);
    let mut sum = 0.0;
    for c in domain {
        gather(complex, y, c, &mut verts, &mut buf);
        sum += lag.cell_lagrangian(&complex.cell(c), &buf);
    }
    Ok(sum)
}

/// EL_v(y) = Σ_{β∈S_v} ∂L_β/∂y_v (3.1): the Euler–Lagrange residual at one
/// vertex, a covector in the fibre's chart at y_v.
pub fn euler_lagrange<F, L, C, const M: usize>(
    complex: &C,
    lag: &L,
    y: &[F::Point<f64>],
    v: usize,
) -> Result<SVector<f64, M>>
where
    F: Fibre<M>,
    L: DiscreteLagrangian<F, M>,
    C: TopCells + ?Sized,
{
    check_field(complex, y)?;
    let mut star = Vec::new();
    complex.star(v, &mut star);
    let mut verts = [0; MAX_CELL_VERTICES];
    let mut buf = Vec::with_capacity(MAX_CELL_VERTICES);
    let mut el = SVector::zeros();
    for StarEntry { cell, position } in star {
        gather(complex, y, cell, &mut verts, &mut buf);
        el += vertex_gradient::<F, L, M>(lag, &complex.cell(cell), &buf, position).1;
    }
    Ok(el)
}

/// EL_v at every vertex, by one pass over the top cells that scatters each
/// cell's vertex gradients (note 003 §2.2).
pub fn euler_lagrange_all<F, L, C, const M: usize>(
    complex: &C,
    lag: &L,
    y: &[F::Point<f64>],
) -> Result<Vec<SVector<f64, M>>>
where
    F: Fibre<M>,
    L: DiscreteLagrangian<F, M>,
    C: TopCells + ?Sized,
{
    check_field(complex, y)?;
    let mut el = vec![SVector::zeros(); complex.vertex_count()];
    let mut verts = [0; MAX_CELL_VERTICES];
    let mut buf = Vec::with_capacity(MAX_CELL_VERTICES);
    for c in 0..complex.cell_count() {
        let k = gather(complex, y, c, &mut verts, &mut buf);
        let cell = complex.cell(c);
        for l in 0..k {
            el[verts[l]] += vertex_gradient::<F, L, M>(lag, &cell, &buf, l).1;
        }
    }
    Ok(el)
}

/// Where a vertex lies relative to a domain A of top cells (Def. 2.4).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VertexClass {
    /// S_v ⊂ A (and S_v non-empty).
    Interior,
    /// S_v meets A and its complement.
    Frontier,
    /// S_v ∩ A = ∅ (also a vertex with an empty star, note 003 §5 item 7).
    Exterior,
}

/// The class of every vertex for the domain `in_domain` (one flag per top cell).
pub fn classify<C: TopCells + ?Sized>(complex: &C, in_domain: &[bool]) -> Result<Vec<VertexClass>> {
    if in_domain.len() != complex.cell_count() {
        return Err(Error::DimensionMismatch {
            what: "domain flags (one per top cell)".into(),
            expected: complex.cell_count(),
            got: in_domain.len(),
        });
    }
    let mut star = Vec::new();
    Ok((0..complex.vertex_count())
        .map(|v| {
            complex.star(v, &mut star);
            let inside = star.iter().filter(|e| in_domain[e.cell]).count();
            match inside {
                0 => VertexClass::Exterior,
                k if k == star.len() => VertexClass::Interior,
                _ => VertexClass::Frontier,
            }
        })
        .collect())
}

/// The two sides of the discrete Noether identity (Thm 3.15) on a domain A
/// for a vertical field D.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NoetherBalance {
    /// Σ_{v ∈ int A} ⟨EL_v(y), D(y_v)⟩.
    pub interior: f64,
    /// The current J_D(A) = Σ_{v ∈ fr A} Σ_{β ∈ A, v ≺ β} ⟨∂L_β/∂y_v, D(y_v)⟩ (3.2).
    pub current: f64,
    /// Σ over the cells of A of Σ_v |⟨∂L_β/∂y_v, D(y_v)⟩|: the size the two
    /// sides are to be compared with.
    pub scale: f64,
}

impl NoetherBalance {
    /// |interior + current| / scale: zero to round-off for every field when
    /// D is a symmetry.
    pub fn relative_defect(&self) -> f64 {
        (self.interior + self.current).abs() / self.scale.max(f64::MIN_POSITIVE)
    }
}

/// Both sides of the Noether identity 0 = Σ_{int A}⟨EL_v, D⟩ + J_D(A) for
/// the domain `in_domain` and the vertical field `generator` (D(y) in the
/// fibre's chart at y). When D is a symmetry the identity holds for every
/// field y; on solutions (EL = 0 on int A) it says J_D(A) = 0.
pub fn noether_balance<F, L, C, const M: usize>(
    complex: &C,
    lag: &L,
    y: &[F::Point<f64>],
    in_domain: &[bool],
    generator: impl Fn(&F::Point<f64>) -> SVector<f64, M>,
) -> Result<NoetherBalance>
where
    F: Fibre<M>,
    L: DiscreteLagrangian<F, M>,
    C: TopCells + ?Sized,
{
    check_field(complex, y)?;
    let class = classify(complex, in_domain)?;
    let mut verts = [0; MAX_CELL_VERTICES];
    let mut buf = Vec::with_capacity(MAX_CELL_VERTICES);
    let mut balance = NoetherBalance {
        interior: 0.0,
        current: 0.0,
        scale: 0.0,
    };
    // The interior sum through the stars (the Euler–Lagrange path), the
    // current through the cells of A: two independent evaluations.
    for (v, _) in class.iter().enumerate().filter(|(_, c)| **c == VertexClass::Interior) {
        balance.interior += euler_lagrange::<F, L, C, M>(complex, lag, y, v)?.dot(&generator(&y[v]));
    }
    for c in (0..complex.cell_count()).filter(|&c| in_domain[c]) {
        let k = gather(complex, y, c, &mut verts, &mut buf);
        let cell = complex.cell(c);
        for l in 0..k {
            let pairing = vertex_gradient::<F, L, M>(lag, &cell, &buf, l)
                .1
                .dot(&generator(&buf[l]));
            balance.scale += pairing.abs();
            if class[verts[l]] == VertexClass::Frontier {
                balance.current += pairing;
            }
        }
    }
    Ok(balance)
}

/// The boundary sum of the discrete multisymplectic form formula on a
/// domain, with the size of its terms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FormBalance {
    /// Σ_{β ∈ A} Σ_{l: v_l ∈ fr A} Ω^l_β(V, W).
    pub boundary: f64,
    /// Σ of the absolute values of the terms of every Ω^l_β(V, W) summed.
    pub scale: f64,
}

impl FormBalance {
    /// |boundary| / scale: zero to round-off (or to the accuracy of V and W)
    /// for first variations of a solution on the domain.
    pub fn relative_defect(&self) -> f64 {
        self.boundary.abs() / self.scale.max(f64::MIN_POSITIVE)
    }
}

/// The discrete multisymplectic form formula (Demoures–Gay-Balmaz–Ratiu
/// (33); Marsden–Patrick–Shkoller (5.6)) on any complex and fibre: with the
/// Cartan forms Θ^l_β = ⟨∂L_β/∂y_l, dy_l⟩ (seed 000 (30)) and
/// Ω^l_β = −dΘ^l_β, whose sum over l is −d(dL_β) = 0 (31), the sum
///
/// Σ_{β ∈ A} Σ_{l: v_l ∈ fr A} Ω^l_β(V, W),
/// Ω^l_β(V, W) = Σ_{m ≠ l} (V_lᵀ H_lm W_m − W_lᵀ H_lm V_m),
/// H_lm = ∂²L_β/∂y_l∂y_m ([`mixed_block`]),
///
/// vanishes when y solves the Euler–Lagrange equations on the interior of
/// A and V, W are first variations (solutions of the linearised
/// equations there): restricted to solutions, dL_A = Σ_{frontier} Θ^l, and
/// d² = 0. `v` and `w` hold V and W at every vertex in the fibre's chart at
/// y (left-trivialised on a group), where the chart Hessian at the centre
/// is symmetric, so the terms m = l cancel and are left out.
///
/// # Errors
/// [`Error::DimensionMismatch`] when `y`, `v`, `w` or `in_domain` do not
/// have one entry per vertex (per top cell).
pub fn multisymplectic_form_sum<F, L, C, const M: usize>(
    complex: &C,
    lag: &L,
    y: &[F::Point<f64>],
    (v, w): (&[SVector<f64, M>], &[SVector<f64, M>]),
    in_domain: &[bool],
) -> Result<FormBalance>
where
    F: Fibre<M>,
    L: DiscreteLagrangian<F, M>,
    C: TopCells + ?Sized,
{
    check_field(complex, y)?;
    check_field(complex, v)?;
    check_field(complex, w)?;
    let class = classify(complex, in_domain)?;
    let mut verts = [0; MAX_CELL_VERTICES];
    let mut buf = Vec::with_capacity(MAX_CELL_VERTICES);
    let mut balance = FormBalance {
        boundary: 0.0,
        scale: 0.0,
    };
    for c in (0..complex.cell_count()).filter(|&c| in_domain[c]) {
        let k = gather(complex, y, c, &mut verts, &mut buf);
        let cell = complex.cell(c);
        for l in (0..k).filter(|&l| class[verts[l]] == VertexClass::Frontier) {
            let (vl, wl) = (v[verts[l]], w[verts[l]]);
            for m in (0..k).filter(|&m| m != l) {
                let h = mixed_block::<F, L, M>(lag, &cell, &buf, l, m).1;
                let (t1, t2) = (vl.dot(&(h * w[verts[m]])), wl.dot(&(h * v[verts[m]])));
                balance.boundary += t1 - t2;
                balance.scale += t1.abs() + t2.abs();
            }
        }
    }
    Ok(balance)
}
