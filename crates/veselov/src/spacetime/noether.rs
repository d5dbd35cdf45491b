//! Discrete Noether charges, the discrete multisymplectic form formula and
//! the mod-2π re-centring of S¹-valued fields (seed 002 §5.1).
//!
//! * Noether (5.7): for a vertical symmetry with generator `ξ` leaving `L`
//!   invariant, `J^l(Δ) = ⟨∂L/∂y^l, ξ(y^l)⟩`, `Σ_l J^l = 0`; on a periodic
//!   lattice the split charge `Q_j = Σ_i Σ_{l: vertex l on level j} J^l(cell(i,j))`
//!   (`J¹` for triangles, `J¹ + J⁴` for rectangles) is conserved.
//!   Example (derived): complex Klein–Gordon with triangles, `ξ(y) = Jy`,
//!   `Q_j = Σ_i ⟨−(y_{i,j+1} − y_ij)/h² + ⅓∇N(ȳ_ij), J y_ij⟩`.
//! * Multisymplectic form formula (5.6): for a solution and first variations
//!   `V, W`, `Σ_{cells ⊆ U touching ∂U} Σ_{l: vertex l ∈ ∂U} Ω^l(V, W) = 0`,
//!   `Ω^l(V, W) = Σ_m (V_lᵀ H_lm W_m − W_lᵀ H_lm V_m)`, `H_lm = ∂²L/∂y^l∂y^m`.

use nalgebra::SVector;

use crate::spacetime::density::{CellLagrangian, cell_gradient, cell_jet, gather};
use crate::spacetime::generic::node_value;
use crate::spacetime::lattice::Lattice;
use crate::spacetime::region::{Node, Region};

/// Split Noether charge `Q_j` of levels `j` (`y_j`) and `j+1` (`y_j1`)
/// for the generator `xi` (cells `i = 0..N` on periodic lattices,
/// `0..N−1` otherwise).
pub fn split_charge<L: CellLagrangian<DIM>, const DIM: usize>(
    lag: &L,
    lattice: &Lattice,
    y_j: &[SVector<f64, DIM>],
    y_j1: &[SVector<f64, DIM>],
    xi: impl Fn(&SVector<f64, DIM>) -> SVector<f64, DIM>,
) -> f64 {
    let shape = lag.shape();
    let nv = shape.vertices();
    let get = |(i, j): Node| node_value(lattice, if j == 0 { y_j } else { y_j1 }, i);
    let cells = if lattice.is_periodic() {
        lattice.nodes()
    } else {
        lattice.nodes() - 1
    };
    let mut q = 0.0;
    for i in 0..cells {
        let Some(v) = gather(shape, (i as i64, 0), &get) else {
            continue;
        };
        let g = cell_gradient(lag, &v[..nv]);
        for (l, &(_, dj)) in shape.offsets().iter().enumerate() {
            if dj == 0 {
                q += g[l].dot(&xi(&v[l]));
            }
        }
    }
    q
}

/// Shift charge of the wave equation (`N = 0`, symmetry `y ↦ y + s`):
/// `Σ_i (y_{i,j+1} − y_ij)` (the split charge up to the factor `−1/h²`).
pub fn shift_charge(y_j: &[f64], y_j1: &[f64]) -> f64 {
    y_j.iter().zip(y_j1).map(|(a, b)| b - a).sum()
}

/// Boundary sum of the discrete multisymplectic form formula (5.6) on a
/// region, and the sum of the absolute values of its terms (for a relative
/// check). `y`, `v`, `w` give the solution and two first variations at a
/// node (`None` outside the stored data).
pub fn multisymplectic_boundary_sum<L: CellLagrangian<DIM>, const DIM: usize>(
    lag: &L,
    region: &Region,
    y: &impl Fn(Node) -> Option<SVector<f64, DIM>>,
    v: &impl Fn(Node) -> Option<SVector<f64, DIM>>,
    w: &impl Fn(Node) -> Option<SVector<f64, DIM>>,
) -> (f64, f64) {
    let shape = lag.shape();
    let nv = shape.vertices();
    let boundary = region.boundary();
    let (mut sum, mut abs) = (0.0, 0.0);
    for c in region.cells() {
        let on_boundary: Vec<bool> = shape
            .offsets()
            .iter()
            .map(|&(di, dj)| boundary.contains(&(c.0 + di, c.1 + dj)))
            .collect();
        if !on_boundary.iter().any(|&b| b) {
            continue;
        }
        let (Some(yv), Some(vv), Some(wv)) = (gather(shape, c, y), gather(shape, c, v), gather(shape, c, w)) else {
            continue;
        };
        let jet = cell_jet(lag, &yv[..nv]);
        for l in 0..nv {
            if !on_boundary[l] {
                continue;
            }
            for m in 0..nv {
                let t1 = vv[l].dot(&(jet.hess[l][m] * wv[m]));
                let t2 = wv[l].dot(&(jet.hess[l][m] * vv[m]));
                sum += t1 - t2;
                abs += t1.abs() + t2.abs();
            }
        }
    }
    (sum, abs)
}

/// The symplectic form of the space–time split (seed 002 §5.1, Fig. 5.3): on
/// a periodic lattice the marching (q_j, q_{j+1}) ↦ (q_{j+1}, q_{j+2}) is the
/// Moser–Veselov map of L̃(q⁰, q¹) = Σ_i L(cell(i) between the two levels),
/// and preserves ω_j(V, W) = Σ_{a,b} V⁰_aᵀ M_ab W¹_b − W⁰_aᵀ M_ab V¹_b,
/// M_ab = ∂²L̃/∂q⁰_a∂q¹_b, for any two first variations V, W. Returns ω_j and
/// the sum of the absolute values of its terms (for a relative check), for
/// the levels `y_j`, `y_j1` and the variations `(v_j, v_j1)`, `(w_j, w_j1)`.
pub fn split_symplectic_form<L: CellLagrangian<DIM>, const DIM: usize>(
    lag: &L,
    lattice: &Lattice,
    (y_j, y_j1): (&[SVector<f64, DIM>], &[SVector<f64, DIM>]),
    (v_j, v_j1): (&[SVector<f64, DIM>], &[SVector<f64, DIM>]),
    (w_j, w_j1): (&[SVector<f64, DIM>], &[SVector<f64, DIM>]),
) -> (f64, f64) {
    let shape = lag.shape();
    let nv = shape.vertices();
    let plain = |level: &[SVector<f64, DIM>], i: i64| {
        let n = lattice.nodes() as i64;
        lattice.is_periodic().then(|| level[i.rem_euclid(n) as usize])
    };
    let get_y = |(i, j): Node| node_value(lattice, if j == 0 { y_j } else { y_j1 }, i);
    let get_v = |(i, j): Node| plain(if j == 0 { v_j } else { v_j1 }, i);
    let get_w = |(i, j): Node| plain(if j == 0 { w_j } else { w_j1 }, i);
    let (mut sum, mut abs) = (0.0, 0.0);
    for i in 0..lattice.nodes() as i64 {
        let (Some(y), Some(v), Some(w)) = (
            gather(shape, (i, 0), &get_y),
            gather(shape, (i, 0), &get_v),
            gather(shape, (i, 0), &get_w),
        ) else {
            continue;
        };
        let jet = cell_jet(lag, &y[..nv]);
        for (l, &(_, dl)) in shape.offsets().iter().enumerate() {
            for (m, &(_, dm)) in shape.offsets().iter().enumerate() {
                if dl == 0 && dm == 1 {
                    let t1 = v[l].dot(&(jet.hess[l][m] * w[m]));
                    let t2 = w[l].dot(&(jet.hess[l][m] * v[m]));
                    sum += t1 - t2;
                    abs += t1.abs() + t2.abs();
                }
            }
        }
    }
    (sum, abs)
}

/// Re-centre stored levels of an S¹-valued field: subtract
/// `2π·round(y_0/2π)` (`y_0` = node 0 of the first level given) from all of
/// them. Returns the shift.
pub fn recentre_mod_2pi(levels: &mut [&mut [f64]]) -> f64 {
    let tau = std::f64::consts::TAU;
    let Some(first) = levels.first().and_then(|l| l.first()) else {
        return 0.0;
    };
    let s = tau * (first / tau).round();
    if s != 0.0 {
        for l in levels.iter_mut() {
            for v in l.iter_mut() {
                *v -= s;
            }
        }
    }
    s
}
