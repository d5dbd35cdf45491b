//! Suitability of discretised cells (note 003 §2.5 item 5, Def. 5.9;
//! Lemma 5.5; Cor. 6.3 for the rod): the check a marcher calls, and the
//! fibre-level geodesic-ball criterion.

use nalgebra::SVector;

use super::error::CellError;
use crate::complex::TopCell;
use crate::field::fibre::{Euclidean, Fibre, PositionRotation, RigidMotions, Rotations};
use crate::lie::SO3;

/// Suitability check of a discretised cell (Def. 5.9).
pub trait CellCheck<F: Fibre<M>, const M: usize> {
    /// `Ok` if the cell is suitable for the vertex values `y` (ordered as the
    /// cell's vertices) and the discrete Lagrangian is finite there; else the
    /// reason, naming the cell.
    ///
    /// # Errors
    /// A [`CellError`] naming `cell.index`.
    fn check_cell(&self, cell: &TopCell, y: &[F::Point<f64>]) -> std::result::Result<(), CellError>;
}

/// A fibre-level sufficient condition for the simplicial geodesic
/// interpolation (Def. 5.4) to be well defined (Lemma 5.5).
pub trait GeodesicBall<const M: usize>: Fibre<M> {
    /// `Ok` if the vertex values of a simplex lie in a ball where Lemma 5.5
    /// applies; else why not.
    ///
    /// # Errors
    /// A message for [`CellError::Unsuitable`].
    fn check_simplex(y: &[Self::Point<f64>]) -> std::result::Result<(), String>;
}

impl<const M: usize> GeodesicBall<M> for Euclidean<M> {
    /// Always suitable (flat, affine interpolation, Prop. 5.20).
    fn check_simplex(_y: &[SVector<f64, M>]) -> std::result::Result<(), String> {
        Ok(())
    }
}

/// Some vertex u whose rotation is within π/2 of every other one,
/// tr(R_uᵀR_v) > 1: then all data lie in the geodesic ball of radius ρ < π/2
/// around R_u, where K = 1/4 < (π/(4ρ))² and the injectivity radius π > 2ρ
/// (Lemma 5.5). For a triangle this is exactly Cor. 6.3 (two of the three
/// pairwise traces > 1 share a vertex).
pub fn check_rotations<'a>(r: impl Iterator<Item = &'a SO3<f64>> + Clone) -> std::result::Result<(), String> {
    let mut best = f64::NEG_INFINITY;
    for (u, ru) in r.clone().enumerate() {
        let worst = r
            .clone()
            .enumerate()
            .filter(|&(v, _)| v != u)
            .map(|(_, rv)| (ru.matrix().transpose() * rv.matrix()).trace())
            .fold(f64::INFINITY, f64::min);
        if worst > 1.0 {
            return Ok(());
        }
        best = best.max(worst);
    }
    Err(format!(
        "no vertex rotation is within π/2 of all the others (best min trace tr(R_uᵀR_v) = {best}, needs > 1; Cor. 6.3)"
    ))
}

impl GeodesicBall<3> for Rotations {
    fn check_simplex(y: &[SO3<f64>]) -> std::result::Result<(), String> {
        check_rotations(y.iter())
    }
}

impl GeodesicBall<6> for PositionRotation {
    /// The rotation part's criterion; the ℝ³ factor is flat (product split (5.6)).
    fn check_simplex(y: &[<Self as Fibre<6>>::Point<f64>]) -> std::result::Result<(), String> {
        check_rotations(y.iter().map(|p| &p.rotation))
    }
}

impl GeodesicBall<6> for RigidMotions {
    /// The rotation part's criterion (the group chart's log needs the rotation
    /// angles below π).
    fn check_simplex(y: &[<Self as Fibre<6>>::Point<f64>]) -> std::result::Result<(), String> {
        check_rotations(y.iter().map(|g| g.rotation()))
    }
}
