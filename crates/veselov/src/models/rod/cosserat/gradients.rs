//! The closed-form gradients of Prop. 6.5's cell (note 003 §3.5), with
//! the shear in either frame ([`ShearFrame`]).

use nalgebra::{Matrix3, SVector, Vector3};

use crate::complex::TopCell;
use crate::field::discretize::error::CellError;
use crate::field::fibre::Pose;
use crate::lie::so3;
use crate::models::rod::cosserat::{Cell, CentredFrame, CosseratCell, ShearFrame, join};
use crate::models::rod::cosserat_step::{RotationArm, RotationEquation};
use crate::models::rod::potential::RodPotential;

impl<P: RodPotential> CosseratCell<P> {
    /// The closed-form gradients of note 003 §3.5 (kinetic sign corrected):
    /// [(∇_{r_k}L_β; ∇_{R_k}L_β)]_{k=0,1,2} in the chart of
    /// [`PositionRotation`](crate::field::fibre::PositionRotation) (Euclidean, then left-trivialised), with
    /// D_a = dlog a, D_b = dlog b (left-trivialised, Def. 6.9):
    ///
    /// * ∇_{r₀} = −(ρΔs/4)v_d + (σΔt/4)R₀C₁ε − (ΔsΔt/8)∇_rP(s₀, r₀)
    /// * ∇_{r₁} = −(σΔt/2)R₀C₁ε
    /// * ∇_{r₂} = (ρΔs/4)v_d + (σΔt/4)R₀C₁ε
    /// * ∇_{R₀} = −(Δs/4)D_bJω_d + A_β (R₀ᵀg)^ C₁ε + (σΔt/4)(2D_a − D_b)C₂u
    /// * ∇_{R₁} = −(σΔt/2)D_aᵀC₂u
    /// * ∇_{R₂} = (Δs/4)D_bᵀJω_d + (σΔt/4)D_bᵀC₂u
    ///
    /// ∇_rP is exact (forward-mode AD of the potential). With the centred
    /// shear frame ([`ShearFrame::Centred`]) R₀ becomes R₀E in the shear
    /// terms of ∇_{r_k}, and the shear's rotation terms are those of the
    /// module `cosserat::shear` (one at R₁ besides R₀).
    ///
    /// # Errors
    /// As [`CosseratCell::try_cell_lagrangian`].
    pub fn gradients(&self, cell: &TopCell, y: &[Pose<f64>]) -> std::result::Result<[SVector<f64, 6>; 3], CellError> {
        let c = self.cell(cell, y)?;
        let r0 = y[0].rotation.matrix();
        let da = so3::dexp_inv(&(-c.a));
        let db = so3::dexp_inv(&(-c.b));
        let arm = RotationArm { a: c.a, da };
        let equation = RotationEquation::new(self.constants_at(c.s0), &[arm], 0.0);
        // The shear's frame and rotation gradients at the base vertex and,
        // centred, at the middle one.
        let tau = self.strain_torque(c.s0, &c.eps);
        let (frame, base_torque, middle_torque) = match self.shear {
            ShearFrame::Vertex => (*r0, tau, None),
            ShearFrame::Centred => {
                let centred = CentredFrame::at(&c.a);
                let (base, middle) = centred.torques(&da, &tau);
                (r0 * centred.rotation, base, Some(middle))
            }
        };
        let first = join(
            self.position_gradient(c.sigma, c.s0, &y[0], &frame, &c.v, &c.eps),
            equation.value_with(&c.b, &db) + base_torque,
        );
        let [second, third] = self.later_gradients(&c, &frame, middle_torque.as_ref(), &da, &db);
        Ok([first, second, third])
    }

    /// The gradients at positions 1 and 2 (note 003 §3.5), from the cell's
    /// quantities, the shear's frame (R₀, or R₀E centred: see [`ShearFrame`]),
    /// the centred shear's torque at R₁ (`middle_torque`, added to ∇_{R₁};
    /// `None` in R₀'s frame), D_a and D_b:
    /// (−(σΔt/2)R₀C₁ε; −(σΔt/2)D_aᵀC₂u) and
    /// ((ρΔs/4)v_d + (σΔt/4)R₀C₁ε; D_bᵀ((Δs/4)Jω_d + (σΔt/4)C₂u)).
    #[inline]
    pub(in crate::models::rod) fn later_gradients(
        &self,
        c: &Cell<f64>,
        frame: &Matrix3<f64>,
        middle_torque: Option<&Vector3<f64>>,
        da: &Matrix3<f64>,
        db: &Matrix3<f64>,
    ) -> [SVector<f64, 6>; 2] {
        let p = self.parameters_at(c.s0);
        let (ds, st) = (self.ds, c.sigma * self.dt);
        let c1e = frame * (p.c1 * c.eps);
        let c2u = p.c2 * c.u;
        let mut middle_rotation = -(da.transpose() * c2u) * (st / 2.0);
        if let Some(torque) = middle_torque {
            middle_rotation += torque;
        }
        [
            join(-c1e * (st / 2.0), middle_rotation),
            join(
                c.v * (p.rho * ds / 4.0) + c1e * (st / 4.0),
                db.transpose() * (p.inertia * c.omega * (ds / 4.0) + c2u * (st / 4.0)),
            ),
        ]
    }
}
