//! Geometry of the CFK lattice (seed 003 Prop. 2.15, Cor. 2.16, Def. 2.18,
//! eq. (3.4); note 003 §1.4–1.5): point location, supporting subspaces and
//! volume forms, the geometric incidence of Def. 2.18 (used to test the closed
//! form of [`CfkCell::face`]), and the CFK → cubic map.

use crate::complex::MAX_LATTICE_DIMENSION;
use crate::complex::cfk::CfkCell;
use crate::complex::cubic::CubicCell;
use crate::complex::window::{Point, check_dimension};
use crate::error::Result;
use crate::error::invalid;

/// Point location (Prop. 2.15, Cor. 2.16): the unique cell whose open hull
/// contains `p`. With c = ⌊p⌋ and f = p − c, the indices with equal nonzero f_i
/// form the subsets, sorted by decreasing f: (c, (S₁, …, S_k)).
///
/// Fractional parts within `tol` of each other are taken equal, below `tol`
/// zero, and above 1 − `tol` as one (the point is rounded up along that
/// axis); `tol = 0` is exact.
///
/// # Errors
/// [`crate::Error::InvalidParameter`] for a dimension outside
/// 1..=[`MAX_LATTICE_DIMENSION`], a non-finite or out-of-range coordinate,
/// or a negative or non-finite `tol`.
pub fn locate(p: &[f64], tol: f64) -> Result<CfkCell> {
    check_dimension(p.len())?;
    if !(tol.is_finite() && (0.0..0.5).contains(&tol)) {
        return Err(invalid("tol", tol, "must be finite and in [0, 0.5)"));
    }
    let mut base: Point = [0; MAX_LATTICE_DIMENSION];
    let mut frac = [0.0f64; MAX_LATTICE_DIMENSION];
    for (i, &x) in p.iter().enumerate() {
        if !(x.is_finite() && x.abs() < 1e15) {
            return Err(invalid(&format!("p[{i}]"), x, "must be finite and below 1e15 in size"));
        }
        let mut c = x.floor();
        let mut f = x - c;
        if f > 1.0 - tol {
            c += 1.0;
            f = 0.0;
        } else if f < tol {
            f = 0.0;
        }
        base[i] = c as i64;
        frac[i] = f;
    }
    let mut order: Vec<usize> = (0..p.len()).filter(|&i| frac[i] > 0.0).collect();
    order.sort_by(|&a, &b| frac[b].total_cmp(&frac[a]));
    let mut cell = CfkCell::vertex(&base);
    let mut last = f64::NAN;
    for &i in &order {
        if last.is_nan() || last - frac[i] > tol {
            cell.k += 1;
            last = frac[i];
        }
        cell.labels[i] = cell.k;
    }
    Ok(cell)
}

/// The axes (i₁ < … < i_k) of the volume form vol_α = dx_{i₁} ∧ … ∧ dx_{i_k}
/// of a cell: the sorted {min S₁, …, min S_k}.
pub fn volume_axes(cell: &CfkCell) -> Vec<usize> {
    let mut axes: Vec<usize> = (1..=cell.dimension())
        .map(|a| cell.subset(a).trailing_zeros() as usize)
        .collect();
    axes.sort_unstable();
    axes
}

/// A basis of the tangent space of the supporting subspace H_α: the
/// indicator vectors e_{S_a}, a = 1..k.
pub fn tangent_basis(cell: &CfkCell) -> Vec<Point> {
    (1..=cell.dimension())
        .map(|a| {
            let mask = cell.subset(a);
            let mut e = [0; MAX_LATTICE_DIMENSION];
            for (i, x) in e.iter_mut().enumerate() {
                *x = i64::from(mask >> i & 1 == 1);
            }
            e
        })
        .collect()
}

/// The sign of an integer determinant (fraction-free elimination).
fn det_sign(mut m: Vec<Vec<i128>>) -> i8 {
    let k = m.len();
    let mut sign = 1i8;
    let mut prev = 1i128;
    for c in 0..k {
        let Some(p) = (c..k).find(|&r| m[r][c] != 0) else {
            return 0;
        };
        if p != c {
            m.swap(p, c);
            sign = -sign;
        }
        for r in c + 1..k {
            for j in c + 1..k {
                m[r][j] = (m[r][j] * m[c][c] - m[r][c] * m[c][j]) / prev;
            }
            m[r][c] = 0;
        }
        prev = m[c][c];
    }
    sign * m[k - 1][k - 1].signum() as i8
}

/// vol(columns): the determinant of the rows `axes` of the given columns.
fn volume_sign(axes: &[usize], columns: &[Point]) -> i8 {
    if axes.is_empty() {
        return 1;
    }
    let m = axes
        .iter()
        .map(|&i| columns.iter().map(|c| i128::from(c[i])).collect())
        .collect();
    det_sign(m)
}

/// The geometric incidence of Def. 2.18: for a face α = β∖{v} of β,
/// \[β:α\] vol_α ∼ i_{v̄−v} vol_β on the tangent space of H_α (v̄ ∈ α any vertex),
/// i.e. the sign of vol_β(v̄ − v, t₁, …, t_{k−1}) · vol_α(t₁, …, t_{k−1}) for a
/// basis t of H_α. Returns 0 when α is not a face of β.
pub fn geometric_incidence(beta: &CfkCell, alpha: &CfkCell) -> i8 {
    let k = beta.dimension();
    if k == 0 || alpha.dimension() + 1 != k {
        return 0;
    }
    let vb: Vec<Point> = (0..=k).map(|a| beta.vertex_at(a)).collect();
    let va: Vec<Point> = (0..k).map(|a| alpha.vertex_at(a)).collect();
    let missing: Vec<&Point> = vb.iter().filter(|p| !va.contains(p)).collect();
    if missing.len() != 1 || va.iter().any(|p| !vb.contains(p)) {
        return 0;
    }
    let mut u = va[0];
    for (x, y) in u.iter_mut().zip(missing[0]) {
        *x -= y;
    }
    let t = tangent_basis(alpha);
    let mut columns = vec![u];
    columns.extend(t.iter().copied());
    volume_sign(&volume_axes(beta), &columns) * volume_sign(&volume_axes(alpha), &t)
}

/// The carrier cube of a CFK cell: the cubic cell whose open cube contains
/// the open hull of the simplex, doubled coordinate 2v_i + [i ∈ ∪S_a]. On top
/// cells this is the map (3.4), i(v, σ) = v + ½(1, …, 1).
pub fn carrier_cube(cell: &CfkCell) -> CubicCell {
    let mut doubled = [0; MAX_LATTICE_DIMENSION];
    for (i, d) in doubled.iter_mut().enumerate() {
        *d = 2 * cell.base[i] + i64::from(cell.labels[i] > 0);
    }
    CubicCell { doubled }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integer_determinant_signs() {
        assert_eq!(det_sign(vec![vec![2]]), 1);
        assert_eq!(det_sign(vec![vec![0, 1], vec![1, 0]]), -1);
        assert_eq!(det_sign(vec![vec![1, 2], vec![2, 4]]), 0);
        assert_eq!(det_sign(vec![vec![0, 2, 1], vec![1, 0, 0], vec![0, 1, 3]]), -1);
        assert_eq!(det_sign(vec![vec![1, 2, 3], vec![4, 5, 6], vec![7, 8, 10]]), -1);
        assert_eq!(
            det_sign(vec![
                vec![2, 1, 0, 0],
                vec![1, 3, 0, 0],
                vec![0, 0, 0, 1],
                vec![0, 0, 1, 0]
            ]),
            -1
        );
    }

    #[test]
    fn lattice_points_locate_to_vertices() {
        let c = locate(&[3.0, -2.0], 0.0).expect("locate");
        assert_eq!((c.dimension(), c.base[0], c.base[1]), (0, 3, -2));
        let rounded = locate(&[2.9999999999, -2.0], 1e-6).expect("locate");
        assert_eq!(rounded, c);
        let edge = locate(&[0.25, 0.25, 0.0], 0.0).expect("locate");
        assert_eq!((edge.dimension(), edge.subset(1)), (1, 0b011));
    }
}
