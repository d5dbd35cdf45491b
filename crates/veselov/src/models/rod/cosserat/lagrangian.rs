//! Prop. 6.5's cell as a discrete Lagrangian of the field core: its value,
//! closed-form gradients and forces, the split step of note 003 §3.6 for a
//! vertex ([`crate::models::rod::cosserat_step`]) and for a run of vertices
//! in vector lanes, and the suitability check of Cor. 6.3.

use nalgebra::SVector;

use super::{CosseratCell, ROD_LANES};
use crate::ad::Scalar;
use crate::complex::TopCell;
use crate::field::cell::{DiscreteLagrangian, SolvedVertex, VertexRun, VertexStar};
use crate::field::discretize::error::CellError;
use crate::field::discretize::suitability::{CellCheck, check_rotations};
use crate::field::fibre::{Fibre, Pose, PositionRotation};
use crate::field::legendre::CauchyOptions;
use crate::models::rod::cosserat_step::split_solve;
use crate::models::rod::potential::RodPotential;

impl<P: RodPotential> DiscreteLagrangian<PositionRotation, 6> for CosseratCell<P> {
    /// Prop. 6.5; NaN on an unsuitable cell (see [`CellCheck::check_cell`]).
    fn cell_lagrangian<D: Scalar>(&self, cell: &TopCell, y: &[Pose<D>]) -> D {
        self.try_cell_lagrangian(cell, y).unwrap_or(D::from(f64::NAN))
    }

    /// The exact gradients of Prop. 6.5 ([`CosseratCell::gradients`]) when
    /// enabled; NaN on an unsuitable cell, as the AD path.
    fn analytic_gradients(&self, cell: &TopCell, y: &[Pose<f64>], out: &mut [SVector<f64, 6>]) -> bool {
        if !self.analytic {
            return false;
        }
        match self.gradients(cell, y) {
            Ok(g) => out[..3].copy_from_slice(&g),
            Err(_) => out[..3].fill(SVector::from_element(f64::NAN)),
        }
        true
    }

    fn has_forces(&self) -> bool {
        self.loads.is_some()
    }

    /// The loads act at the cell's time edge v₀v₂ (damping) and at v₀ (end
    /// load), never at the middle vertex v₁.
    fn has_force_at(&self, l: usize) -> bool {
        self.loads.is_some() && l != 1
    }

    fn cell_force<D: Scalar>(&self, cell: &TopCell, y: &[Pose<D>], l: usize) -> SVector<D, 6> {
        self.force(cell, y, l)
    }

    /// F⁰, F¹ = 0 and F² with one logarithm, log(R₀ᵀR₂), for the damping
    /// at both ends of the time edge; each the bits of
    /// [`cell_force`](DiscreteLagrangian::cell_force) at its position.
    fn cell_forces(&self, cell: &TopCell, y: &[Pose<f64>], out: &mut [SVector<f64, 6>]) {
        let n = y.len().min(out.len());
        out[..n].fill(SVector::zeros());
        let Some(loads) = &self.loads else {
            return;
        };
        if y.len() != 3 || n < 3 {
            return;
        }
        out[..3].copy_from_slice(&self.load_forces(loads, cell, y));
    }

    /// The split step of note 003 §3.6 ([`crate::models::rod::cosserat_step`]) when the
    /// closed forms are enabled; it writes the solved cells' gradients.
    fn solve_last_vertex(
        &self,
        star: &VertexStar<'_, Pose<f64>>,
        mu: &SVector<f64, 6>,
        mu_scale: f64,
        previous: &Pose<f64>,
        options: &CauchyOptions,
        gradients: &mut [SVector<f64, 6>],
    ) -> Option<SolvedVertex<Pose<f64>>> {
        self.analytic
            .then(|| split_solve(self, star, mu, mu_scale, previous, options, gradients))
    }

    /// Eight with the closed forms (the split step of eight vertices side
    /// by side in vector lanes), else 1.
    fn vertex_lanes(&self) -> usize {
        if self.analytic { ROD_LANES } else { 1 }
    }

    /// A rod is always confined to its material window.
    fn solves_confined_runs(&self) -> bool {
        true
    }

    /// The split step of every vertex of the run, eight at a time where
    /// their stars are whole (in vector lanes), else one at a time; each
    /// vertex with the bits of its own split step.
    fn solve_vertex_run<R>(
        &self,
        run: &R,
        options: &CauchyOptions,
        gradients: &mut [SVector<f64, 6>],
        stride: usize,
        solved: &mut [SolvedVertex<Pose<f64>>],
    ) -> bool
    where
        R: VertexRun<Pose<f64>, 6>,
    {
        self.solve_run(run, options, gradients, stride, solved)
    }
}

impl<P: RodPotential> CellCheck<PositionRotation, 6> for CosseratCell<P> {
    /// Cor. 6.3 (two of tr(R₀ᵀR₁), tr(R₁ᵀR₂), tr(R₂ᵀR₀) above 1 — the nodes
    /// of (6.2) are never collinear), finite values, both logarithms and a
    /// finite L_β.
    fn check_cell(&self, cell: &TopCell, y: &[Pose<f64>]) -> std::result::Result<(), CellError> {
        if !y.iter().all(PositionRotation::is_finite) {
            return Err(CellError::NonFinite {
                cell: cell.index,
                what: "vertex value",
            });
        }
        let value = self.try_cell_lagrangian(cell, y)?;
        check_rotations(y.iter().map(|p| &p.rotation)).map_err(|reason| CellError::Unsuitable {
            cell: cell.index,
            reason,
        })?;
        if value.is_finite() {
            Ok(())
        } else {
            Err(CellError::NonFinite {
                cell: cell.index,
                what: "discrete Lagrangian",
            })
        }
    }
}
