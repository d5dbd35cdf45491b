//! The rod's loads as discrete Lagrange–d'Alembert forces (seed 004's
//! formalism on the cells of Prop. 6.5): damping on each cell's time edge
//! and a ramped force and torque at one end ([`RodLoads`]).

use nalgebra::{SVector, Vector3};

use crate::ad::Scalar;
use crate::complex::TopCell;
use crate::error::Result;
use crate::error::invalid;
use crate::field::fibre::{Fibre, Pose, Rotations};
use crate::models::rod::cosserat::CosseratCell;
use crate::models::rod::potential::RodPotential;

impl<P: RodPotential> CosseratCell<P> {
    /// The force F^l_β of the loads at position `l` of `cell` (zero without
    /// loads): entry l of [`load_forces`](Self::load_forces), without its
    /// logarithm at the middle vertex, where no load acts.
    pub(super) fn force<D: Scalar>(&self, cell: &TopCell, y: &[Pose<D>], l: usize) -> SVector<D, 6> {
        let Some(loads) = &self.loads else {
            return SVector::from_element(D::zero());
        };
        if y.len() != 3 || l == 1 || l > 2 {
            return SVector::from_element(D::zero());
        }
        self.load_forces(loads, cell, y)[l]
    }

    /// (F⁰, F¹ = 0, F²) of `cell` at the values `y` (three of them): one
    /// logarithm b = log(R₀ᵀR₂) for the damping at both ends of the time
    /// edge ([`forces_with`](Self::forces_with)).
    pub(super) fn load_forces<D: Scalar>(&self, loads: &RodLoads, cell: &TopCell, y: &[Pose<D>]) -> [SVector<D, 6>; 3] {
        let b = if loads.damped() {
            Rotations::log(&y[0].rotation, &y[2].rotation).ok()
        } else {
            None
        };
        self.forces_with(loads, cell, &y[0], &y[2].position, b.as_ref())
    }

    /// F⁰ = F² = −(A_β/2)(c_r v_d; c_R ω_d) with b = log(R₀ᵀR₂) given: the
    /// damping work ∫∫ −(c_r ∂_t r·δr + c_R ω·η) ds dt by the trapezoidal
    /// rule on the time edge v₀v₂ of the cell.
    fn damping_force_with<D: Scalar>(
        &self,
        loads: &RodLoads,
        r0: &Vector3<D>,
        r2: &Vector3<D>,
        b: &Vector3<D>,
    ) -> SVector<D, 6> {
        let v = self.linear_damping(loads, r0, r2);
        let o = b * D::from(self.damping_weight() * loads.damping_angular);
        SVector::<D, 6>::new(v[0], v[1], v[2], o[0], o[1], o[2])
    }

    /// (F⁰, F¹ = 0, F²) of `cell` with base value y₀, last position r₂ and
    /// b = log(R₀ᵀR₂) (`None` when damped: the logarithm failed, NaN at 0
    /// and 2): the damping on the time edge at both ends, the end load at
    /// v₀. The split step calls it with the b it solved, without a
    /// logarithm.
    pub(in crate::models::rod) fn forces_with<D: Scalar>(
        &self,
        loads: &RodLoads,
        cell: &TopCell,
        y0: &Pose<D>,
        r2: &Vector3<D>,
        b: Option<&Vector3<D>>,
    ) -> [SVector<D, 6>; 3] {
        let zero = SVector::from_element(D::zero());
        let (mut first, mut last) = (zero, zero);
        if loads.damped() {
            let Some(b) = b else {
                let nan = SVector::from_element(D::from(f64::NAN));
                return [nan, zero, nan];
            };
            let damping = self.damping_force_with(loads, &y0.position, r2, b);
            first += damping;
            last += damping;
        }
        if let Some(load) = self.end_load_force(loads, cell, y0) {
            first += load;
        }
        [first, zero, last]
    }

    /// The end load's part of F⁰ as one vector ([`end_load`](Self::end_load)).
    fn end_load_force<D: Scalar>(&self, loads: &RodLoads, cell: &TopCell, y0: &Pose<D>) -> Option<SVector<D, 6>> {
        let (force, torque) = self.end_load(loads, cell, y0)?;
        Some(SVector::<D, 6>::new(
            force[0], force[1], force[2], torque[0], torque[1], torque[2],
        ))
    }

    /// −A_β/(2Δt): the weight of the damping forces on the time edge.
    pub(super) fn damping_weight(&self) -> f64 {
        -0.5 * self.area() / self.dt
    }

    /// The linear damping force of F⁰ = F² with r₀ and r₂ at the cell's
    /// time edge: −(A_β/2)c_r (r₂ − r₀)/Δt.
    pub(in crate::models::rod) fn linear_damping<D: Scalar>(
        &self,
        loads: &RodLoads,
        r0: &Vector3<D>,
        r2: &Vector3<D>,
    ) -> Vector3<D> {
        (r2 - r0) * D::from(self.damping_weight() * loads.damping_linear)
    }

    /// The end load's part of F⁰ at the loaded end's cell, (Δt f(t) F,
    /// Δt f(t) R₀ᵀτ), `None` on every other cell.
    pub(in crate::models::rod) fn end_load<D: Scalar>(
        &self,
        loads: &RodLoads,
        cell: &TopCell,
        y0: &Pose<D>,
    ) -> Option<(Vector3<D>, Vector3<D>)> {
        let p = cell.origin[0] - cell.origin[1];
        let inside = if loads.tip == 0 { 0 } else { 1 };
        if p != loads.tip || cell.shape != inside {
            return None;
        }
        // Δt·(F; R₀ᵀτ) at the loaded end: each of its vertices stands for
        // the time Δt between its level and the one two above.
        let t = (cell.origin[0] + cell.origin[1]) as f64 * 0.5 * self.dt;
        let k = self.dt * loads.ramp_factor(t);
        let torque = y0.rotation.matrix().transpose() * loads.end_torque.map(D::from);
        let force = loads.end_force * k;
        Some((force.map(D::from), torque * D::from(k)))
    }
}

/// Damping and an end load of the rod, as the discrete Lagrange–d'Alembert
/// forces of [`CosseratCell::with_loads`] (seed 004's formalism):
///
/// * damping forces −c_r∂_t r and body torques −c_Rω per unit length, by
///   the trapezoidal rule on each cell's time edge:
///   F⁰_β = F²_β = −(A_β/2)(c_r v_d; c_R ω_d), F¹_β = 0;
/// * a force F and a torque τ (spatial frame) at the end material point
///   `tip` (0 or the last), switched on at `start` and ramped linearly from
///   zero over `ramp` (time t = wΔt/2 of level w): each vertex of that end
///   receives the impulse Δt·f(t)·(F; R_vᵀτ) (left-trivialised),
///   f = [`RodLoads::ramp_factor`], on the cell based at it that lies in the
///   body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RodLoads {
    /// Linear damping coefficient c_r per unit length (≥ 0).
    pub damping_linear: f64,
    /// Angular damping coefficient c_R per unit length (≥ 0).
    pub damping_angular: f64,
    /// Force at the loaded end (spatial frame).
    pub end_force: Vector3<f64>,
    /// Torque at the loaded end (spatial frame).
    pub end_torque: Vector3<f64>,
    /// Material point of the loaded end (0 or the last point of the rod).
    pub tip: i64,
    /// Ramp duration (0: applied at full strength from `start` on).
    pub ramp: f64,
    /// Time at which the end load is switched on (lattice time wΔt/2;
    /// before it the end load is zero).
    pub start: f64,
}

impl RodLoads {
    pub(super) fn validate(&self) -> Result<()> {
        for (name, v) in [
            ("damping_linear", self.damping_linear),
            ("damping_angular", self.damping_angular),
            ("ramp", self.ramp),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(invalid(name, v, "must be finite and non-negative"));
            }
        }
        if !self.start.is_finite() {
            return Err(invalid("start", self.start, "must be finite"));
        }
        for (name, v) in [("end_force", self.end_force), ("end_torque", self.end_torque)] {
            if !v.iter().all(|x| x.is_finite()) {
                return Err(invalid(name, format!("{v}"), "must be finite"));
            }
        }
        if self.tip < 0 {
            return Err(invalid("tip", self.tip, "must be a material point (0 or the last)"));
        }
        Ok(())
    }

    /// Whether either damping coefficient is positive (the forces F⁰ = F²
    /// on the cells' time edges are then not zero).
    pub fn damped(&self) -> bool {
        self.damping_linear > 0.0 || self.damping_angular > 0.0
    }

    /// The fraction of the end load applied at time t:
    /// clamp((t − start)/ramp, 0, 1) (a step at `start` without a ramp).
    pub fn ramp_factor(&self, t: f64) -> f64 {
        crate::models::end_load::ramp_factor(t, self.start, self.ramp)
    }
}
