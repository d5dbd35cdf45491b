//! The Cosserat rod (note 003 §3; paper §6): the smooth density (6.1) over
//! ℝ³ × SO(3) and the closed-form discrete Lagrangian of Prop. 6.5 on the
//! leapfrog-embedded 2-D CFK lattice (6.2), with the §3.5 gradients (kinetic
//! sign corrected, note 003 §5 erratum 2).
//!
//! Coordinates x = (s, t) (material point, time); fibre [`PositionRotation`]
//! with chart (r + a, R exp(b̂)), so the jet is φ = [∂_s r, ∂_t r; Ω, ω]
//! with Ω̂ = Rᵀ∂_sR, ω̂ = Rᵀ∂_tR (body vectors).

use std::sync::Arc;

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use crate::ad::{Scalar, const_mat3_vec, mat3_vec};
use crate::complex::TopCell;
use crate::error::Result;
use crate::error::invalid;
use crate::field::discretize::error::CellError;
use crate::field::discretize::smooth::SmoothDensity;
use crate::field::fibre::{Fibre, Pose, PositionRotation, Rotations};
use crate::models::rod::potential::{NoPotential, RodPotential, nearest_point};

mod gradients;
mod lagrangian;
mod lane_run;
mod lane_step;
mod lanes;
mod loads;
mod shear;
pub use loads::RodLoads;
pub(super) use shear::CentredFrame;
pub use shear::ShearFrame;

/// The vertices of a level the rod's split step solves side by side (eight
/// in the documentation of its `vertex_lanes`: a group is one AVX-512
/// instruction wide).
const ROD_LANES: usize = 8;

/// Constant material parameters of the rod (6.1): mass density ρ ≥ 0,
/// inertia J (symmetric positive semidefinite), elasticities C₁, C₂
/// (symmetric positive definite) and unstressed linear strain e.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RodParameters {
    rho: f64,
    inertia: Matrix3<f64>,
    c1: Matrix3<f64>,
    c2: Matrix3<f64>,
    strain: Vector3<f64>,
}

fn symmetric(name: &str, m: &Matrix3<f64>) -> Result<()> {
    if !m.iter().all(|x| x.is_finite()) || (m - m.transpose()).amax() > 1e-12 * m.amax().max(1.0) {
        return Err(invalid(name, format!("{m}"), "must be finite and symmetric"));
    }
    Ok(())
}

impl RodParameters {
    /// Validated parameters.
    ///
    /// # Errors
    /// [`crate::error::Error::InvalidParameter`] naming `rho` (negative or not
    /// finite), `inertia` (not symmetric positive semidefinite), `c1`/`c2`
    /// (not symmetric positive definite) or `strain` (not finite).
    pub fn new(
        rho: f64,
        inertia: Matrix3<f64>,
        c1: Matrix3<f64>,
        c2: Matrix3<f64>,
        strain: Vector3<f64>,
    ) -> Result<Self> {
        if !(rho.is_finite() && rho >= 0.0) {
            return Err(invalid("rho", rho, "must be finite and non-negative"));
        }
        symmetric("inertia", &inertia)?;
        if inertia.symmetric_eigenvalues().min() < -1e-14 * inertia.amax() {
            return Err(invalid(
                "inertia",
                format!("{inertia}"),
                "must be positive semidefinite",
            ));
        }
        for (name, c) in [("c1", &c1), ("c2", &c2)] {
            symmetric(name, c)?;
            if c.cholesky().is_none() {
                return Err(invalid(name, format!("{c}"), "must be positive definite"));
            }
        }
        if !strain.iter().all(|x| x.is_finite()) {
            return Err(invalid("strain", format!("{strain}"), "must be finite"));
        }
        Ok(Self {
            rho,
            inertia,
            c1,
            c2,
            strain,
        })
    }

    /// Mass density ρ.
    pub fn rho(&self) -> f64 {
        self.rho
    }
    /// Inertia J.
    pub fn inertia(&self) -> &Matrix3<f64> {
        &self.inertia
    }
    /// Linear elasticity C₁.
    pub fn c1(&self) -> &Matrix3<f64> {
        &self.c1
    }
    /// Angular elasticity C₂.
    pub fn c2(&self) -> &Matrix3<f64> {
        &self.c2
    }
    /// Unstressed linear strain e.
    pub fn strain(&self) -> &Vector3<f64> {
        &self.strain
    }
}

/// ½xᵀAx with A in f64.
fn quad<D: Scalar>(a: &Matrix3<f64>, x: &Vector3<D>) -> D {
    x.dot(&const_mat3_vec(a, x)) * 0.5
}

/// The rod density (6.1):
/// 𝓛 = ½[ρ|∂_t r|² + ωᵀJω − εᵀC₁ε − ΩᵀC₂Ω − P(s, r)], ε = Rᵀ∂_s r − e.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CosseratDensity<P = NoPotential> {
    /// Material parameters.
    pub parameters: RodParameters,
    /// External potential.
    pub potential: P,
}

impl CosseratDensity<NoPotential> {
    /// The free rod (P = 0).
    pub fn free(parameters: RodParameters) -> Self {
        Self {
            parameters,
            potential: NoPotential,
        }
    }
}

impl<P: RodPotential> SmoothDensity<PositionRotation, 6, 2> for CosseratDensity<P> {
    fn density<D: Scalar>(&self, x: &SVector<f64, 2>, y: &Pose<D>, jet: &SMatrix<D, 6, 2>) -> D {
        let col = |r: usize, c: usize| Vector3::new(jet[(r, c)], jet[(r + 1, c)], jet[(r + 2, c)]);
        let p = &self.parameters;
        let v = col(0, 1);
        let eps = y.rotation.matrix().transpose() * col(0, 0) - p.strain.map(D::from);
        v.dot(&v) * (0.5 * p.rho) + quad(&p.inertia, &col(3, 1))
            - quad(&p.c1, &eps)
            - quad(&p.c2, &col(3, 0))
            - self.potential.potential(x[0], &y.position) * 0.5
    }
}

/// Prop. 6.5: the rod's discrete Lagrangian on triangle β = (i, j, σ) of the
/// 2-D CFK lattice under the leapfrog map (6.2), one node at v₀ (Q_{v₀}).
/// Shape 0 is σ = + (v₁ = v₀ + (1, 0)), shape 1 is σ = − (the
/// [`crate::field::discretize::permutation`] order). With A_β = ΔsΔt/4, a = log(R₀ᵀR₁),
/// b = log(R₀ᵀR₂), g = (2r₁ − r₀ − r₂)/(σΔs), ε = R₀ᵀg − e,
/// u = (2a − b)/(σΔs), ω_d = b/Δt, v_d = (r₂ − r₀)/Δt:
///
/// L_β = A_β[½ρ|v_d|² + ½ω_dᵀJω_d − ½εᵀC₁ε − ½uᵀC₂u − ½P(s₀, r₀)],
/// s₀ = (i − j)Δs/2.
#[derive(Debug, Clone, PartialEq)]
pub struct CosseratCell<P = NoPotential> {
    /// The smooth density whose Q_{v₀} discretisation this is.
    pub density: CosseratDensity<P>,
    ds: f64,
    dt: f64,
    /// 1/Δs and 1/Δt: the cell quantities multiply by them (a division per
    /// component cost as much as the rest of a quantity).
    inv_ds: f64,
    inv_dt: f64,
    analytic: bool,
    /// The frame of the shear strain ([`ShearFrame`]).
    shear: ShearFrame,
    loads: Option<RodLoads>,
    /// Material parameters per material point s_k = kΔs/2 (k = 0, 1, …),
    /// replacing `density.parameters` where given ([`CosseratCell::with_profile`]).
    profile: Option<Arc<[RodParameters]>>,
    /// The split step's constant matrices, per entry of `profile` (one
    /// entry without a profile); rebuilt by every builder.
    constants: Arc<[StepConstants]>,
}

/// The constant matrices of the split vertex step (note 003 §3.6) at one
/// material point, computed once per rod rather than at every vertex.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct StepConstants {
    /// K = (ρΔs/(4Δt) + A_β c_r/(2Δt)) I + (Δt/(4Δs)) C₁: each cell based
    /// at v contributes ∂Leg_r/∂r₂ = −R₀KR₀ᵀ (with the linear damping c_r).
    pub(super) stiffness: Matrix3<f64>,
    /// K⁻¹ (`None` if K is numerically singular: the solve then fails).
    pub(super) compliance: Option<Matrix3<f64>>,
    /// κC₂ − λJ with κ = Δt/(4Δs), λ = Δs/(4Δt): the rotation equation's
    /// dx/db per cell ([`crate::models::rod::cosserat_step`]).
    pub(super) rotation_linear: Matrix3<f64>,
    /// ‖κC₂ − λJ‖_F.
    pub(super) rotation_linear_norm: f64,
    /// −2κC₂.
    pub(super) c2_minus_two_kappa: Matrix3<f64>,
}

impl StepConstants {
    /// The constants of parameters `p` with spacings Δs, Δt and the linear
    /// damping c_r.
    pub(super) fn new(p: &RodParameters, ds: f64, dt: f64, damping_linear: f64) -> Self {
        let stiffness = Matrix3::identity() * (p.rho * ds / (4.0 * dt) + 0.25 * ds * dt * damping_linear / (2.0 * dt))
            + p.c1 * (dt / (4.0 * ds));
        let (kappa, lambda) = (dt / (4.0 * ds), ds / (4.0 * dt));
        let rotation_linear = p.c2 * kappa - p.inertia * lambda;
        Self {
            stiffness,
            compliance: stiffness.try_inverse(),
            rotation_linear,
            rotation_linear_norm: rotation_linear.norm(),
            c2_minus_two_kappa: p.c2 * (-2.0 * kappa),
        }
    }
}

/// The quantities of Prop. 6.5 on one triangle.
pub(super) struct Cell<D> {
    sigma: f64,
    s0: f64,
    a: Vector3<D>,
    b: Vector3<D>,
    eps: Vector3<D>,
    u: Vector3<D>,
    omega: Vector3<D>,
    v: Vector3<D>,
}

impl<P: RodPotential> CosseratCell<P> {
    /// The rod cell with spacings Δs, Δt.
    ///
    /// # Errors
    /// [`crate::error::Error::InvalidParameter`] unless Δs, Δt are positive and finite.
    pub fn new(density: CosseratDensity<P>, ds: f64, dt: f64) -> Result<Self> {
        for (name, v) in [("ds", ds), ("dt", dt)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(invalid(name, v, "must be positive and finite"));
            }
        }
        let constants = [StepConstants::new(&density.parameters, ds, dt, 0.0)].into();
        Ok(Self {
            density,
            ds,
            dt,
            inv_ds: ds.recip(),
            inv_dt: dt.recip(),
            analytic: true,
            shear: ShearFrame::Vertex,
            loads: None,
            profile: None,
            constants,
        })
    }

    /// The split step's constants for the current parameters and loads.
    fn rebuild_constants(&mut self) {
        let damping = self.loads.map_or(0.0, |l| l.damping_linear);
        let (ds, dt) = (self.ds, self.dt);
        self.constants = match &self.profile {
            None => [StepConstants::new(&self.density.parameters, ds, dt, damping)].into(),
            Some(profile) => profile.iter().map(|p| StepConstants::new(p, ds, dt, damping)).collect(),
        };
    }

    /// The split step's constants at the material coordinate `s0` (read as
    /// [`parameters_at`](Self::parameters_at)).
    pub(super) fn constants_at(&self, s0: f64) -> &StepConstants {
        match &self.profile {
            None => &self.constants[0],
            Some(profile) => &self.constants[nearest_point(s0, 0.5 * self.ds, profile.len())],
        }
    }

    /// The rod with material parameters varying along it: `profile[k]` at
    /// the material point s_k = kΔs/2 (k = 0 … nodes − 1). Each cell takes
    /// the parameters of its base vertex v₀ (Q_{v₀} of the density with
    /// s-dependent parameters); the two cells based at a vertex extend to
    /// either side of it, so the sampling is centred.
    ///
    /// # Errors
    /// [`crate::error::Error::InvalidParameter`] naming `profile` if it is empty.
    pub fn with_profile(mut self, profile: Vec<RodParameters>) -> Result<Self> {
        if profile.is_empty() {
            return Err(invalid(
                "profile",
                0,
                "needs the parameters of at least one material point",
            ));
        }
        self.profile = Some(profile.into());
        self.rebuild_constants();
        Ok(self)
    }

    /// The material coordinate s₀ = (i − j)Δs/2 of the base vertex v₀ of
    /// `cell` (leapfrog embedding (6.2)).
    pub fn material_coordinate(&self, cell: &TopCell) -> f64 {
        (cell.origin[0] - cell.origin[1]) as f64 * 0.5 * self.ds
    }

    /// The material parameters at the material coordinate `s0` (the
    /// profile's nearest point, clamped to its ends; the density's own
    /// parameters without a profile).
    pub fn parameters_at(&self, s0: f64) -> &RodParameters {
        match &self.profile {
            None => &self.density.parameters,
            Some(profile) => &profile[nearest_point(s0, 0.5 * self.ds, profile.len())],
        }
    }

    /// The rod with damping and an end load ([`RodLoads`]) as discrete
    /// Lagrange–d'Alembert forces.
    ///
    /// # Errors
    /// [`crate::error::Error::InvalidParameter`] naming the field of
    /// [`RodLoads`] at fault.
    pub fn with_loads(mut self, loads: RodLoads) -> Result<Self> {
        loads.validate()?;
        self.loads = Some(loads);
        self.rebuild_constants();
        Ok(self)
    }

    /// The loads, if any.
    pub fn loads(&self) -> Option<&RodLoads> {
        self.loads.as_ref()
    }

    /// Whether the core uses the closed forms — [`CosseratCell::gradients`]
    /// for the vertex gradients ∂L_β/∂y_l and the split vertex solve of note
    /// 003 §3.6 (a linear solve for the position, then a 3-D Newton for the
    /// rotation; [`crate::models::rod::cosserat_step`]) — (`true`, the default) or the
    /// dual-number passes over [`CosseratCell::try_cell_lagrangian`] and the
    /// generic 6-D Newton (`false`, the reference).
    #[must_use]
    pub fn with_analytic_gradients(mut self, on: bool) -> Self {
        self.analytic = on;
        self
    }

    /// Δs.
    pub fn ds(&self) -> f64 {
        self.ds
    }
    /// Δt.
    pub fn dt(&self) -> f64 {
        self.dt
    }
    /// The cell area A_β = ΔsΔt/4.
    pub fn area(&self) -> f64 {
        0.25 * self.ds * self.dt
    }

    fn cell<D: Scalar>(&self, cell: &TopCell, y: &[Pose<D>]) -> std::result::Result<Cell<D>, CellError> {
        let sigma = match cell.shape {
            0 => 1.0,
            1 => -1.0,
            _ => {
                return Err(CellError::Nodes {
                    cell: cell.index,
                    expected: 3,
                    got: 0,
                });
            }
        };
        if y.len() != 3 {
            return Err(CellError::Nodes {
                cell: cell.index,
                expected: 3,
                got: y.len(),
            });
        }
        let log = |to: usize| {
            Rotations::log(&y[0].rotation, &y[to].rotation).map_err(|source| CellError::Logarithm {
                cell: cell.index,
                from: 0,
                to,
                source,
            })
        };
        let (a, b) = (log(1)?, log(2)?);
        let s0 = self.material_coordinate(cell);
        let mut c = self.quantities(sigma, s0, [&y[0], &y[1], &y[2]], a, b);
        if self.shear == ShearFrame::Centred {
            c.eps = shear::centred_strain(&c.eps, &c.a, &self.parameters_at(s0).strain);
        }
        Ok(c)
    }

    /// The quantities of Prop. 6.5 from the cell's values and logarithms
    /// a = log(R₀ᵀR₁), b = log(R₀ᵀR₂) (R₂ itself is not read).
    pub(super) fn quantities<D: Scalar>(
        &self,
        sigma: f64,
        s0: f64,
        y: [&Pose<D>; 3],
        a: Vector3<D>,
        b: Vector3<D>,
    ) -> Cell<D> {
        let eps = self.linear_strain(sigma, s0, y[0], &y[1].position, &y[2].position);
        self.quantities_from_strain(sigma, s0, [y[0], y[2]], a, b, eps)
    }

    /// [`quantities`](Self::quantities) with ε already computed by
    /// [`linear_strain`](Self::linear_strain), from the values at positions
    /// 0 and 2.
    #[inline]
    pub(super) fn quantities_from_strain<D: Scalar>(
        &self,
        sigma: f64,
        s0: f64,
        y: [&Pose<D>; 2],
        a: Vector3<D>,
        b: Vector3<D>,
        eps: Vector3<D>,
    ) -> Cell<D> {
        let inv_sds = D::from(sigma * self.inv_ds);
        Cell {
            sigma,
            s0,
            u: (a * D::from(2.0) - b) * inv_sds,
            omega: b * D::from(self.inv_dt),
            v: (y[1].position - y[0].position) * D::from(self.inv_dt),
            a,
            b,
            eps,
        }
    }

    /// Prop. 6.5 with its failure named.
    ///
    /// # Errors
    /// [`CellError::Nodes`] for a shape other than 0, 1 or not 3 values;
    /// [`CellError::Logarithm`] at the cut locus.
    pub fn try_cell_lagrangian<D: Scalar>(&self, cell: &TopCell, y: &[Pose<D>]) -> std::result::Result<D, CellError> {
        let c = self.cell(cell, y)?;
        let p = self.parameters_at(c.s0);
        let l = c.v.dot(&c.v) * (0.5 * p.rho) + quad(&p.inertia, &c.omega)
            - quad(&p.c1, &c.eps)
            - quad(&p.c2, &c.u)
            - self.density.potential.potential(c.s0, &y[0].position) * 0.5;
        Ok(l * self.area())
    }
}

/// (x; y) ∈ ℝ⁶.
#[inline]
fn join(x: Vector3<f64>, y: Vector3<f64>) -> SVector<f64, 6> {
    SVector::<f64, 6>::new(x[0], x[1], x[2], y[0], y[1], y[2])
}

impl<P: RodPotential> CosseratCell<P> {
    /// ∇_{r₀}L_β = −(ρΔs/4)v_d + (σΔt/4)R₀C₁ε − (ΔsΔt/8)∇_rP(s₀, r₀)
    /// (note 003 §3.5, kinetic sign corrected; ∇_rP by forward-mode AD),
    /// with the shear's `frame` in place of R₀ (R₀ or R₀E, [`ShearFrame`]).
    pub(crate) fn position_gradient(
        &self,
        sigma: f64,
        s0: f64,
        y0: &Pose<f64>,
        frame: &Matrix3<f64>,
        v: &Vector3<f64>,
        eps: &Vector3<f64>,
    ) -> Vector3<f64> {
        let p = self.parameters_at(s0);
        let grad_p = self.density.potential.gradient(s0, &y0.position);
        -v * (p.rho * self.ds / 4.0) + mat3_vec(frame, &(p.c1 * eps)) * (sigma * self.dt / 4.0)
            - grad_p * (self.ds * self.dt / 8.0)
    }

    /// The strain term of ∇_{R₀}L_β: A_β (R₀ᵀg)^ C₁ε (note 003 §3.5), with
    /// R₀ᵀg = ε + e.
    #[inline]
    pub(crate) fn strain_torque(&self, s0: f64, eps: &Vector3<f64>) -> Vector3<f64> {
        let p = self.parameters_at(s0);
        (eps + p.strain).cross(&(p.c1 * eps)) * self.area()
    }

    /// ε = R₀ᵀg − e of Prop. 6.5, g = (2r₁ − r₀ − r₂)/(σΔs): the one place
    /// the strain is computed (cell quantities and the split step alike).
    #[inline]
    pub(crate) fn linear_strain<D: Scalar>(
        &self,
        sigma: f64,
        s0: f64,
        y0: &Pose<D>,
        r1: &Vector3<D>,
        r2: &Vector3<D>,
    ) -> Vector3<D> {
        let g = (r1 * D::from(2.0) - y0.position - r2) * D::from(sigma * self.inv_ds);
        y0.rotation.matrix().transpose() * g - self.parameters_at(s0).strain.map(D::from)
    }

    /// The discrete energy of one cell: A_β times the sum of ½ρ|v_d|²,
    /// ½ω_dᵀJω_d, ½εᵀC₁ε, ½uᵀC₂u and ½P(s₀, r₀) (kinetic plus elastic plus
    /// potential: the terms of Prop. 6.5 with the potential ones' sign
    /// reversed). Summed over the cells of one slab of duration Δt and
    /// divided by Δt it is the rod's energy at that time; not exactly
    /// conserved (the march conserves the discrete momenta exactly and keeps
    /// this energy bounded).
    ///
    /// # Errors
    /// As [`CosseratCell::try_cell_lagrangian`].
    pub fn cell_energy(&self, cell: &TopCell, y: &[Pose<f64>]) -> std::result::Result<f64, CellError> {
        let c = self.cell(cell, y)?;
        let p = self.parameters_at(c.s0);
        let e = c.v.dot(&c.v) * (0.5 * p.rho)
            + quad(&p.inertia, &c.omega)
            + quad(&p.c1, &c.eps)
            + quad(&p.c2, &c.u)
            + self.density.potential.potential(c.s0, &y[0].position) * 0.5;
        Ok(e * self.area())
    }
}

impl<P: RodPotential> CosseratCell<P> {
    /// The cell with its shear strain in `frame` ([`ShearFrame`]); the
    /// closed forms and the split step follow it.
    #[must_use]
    pub fn with_shear_frame(mut self, frame: ShearFrame) -> Self {
        self.shear = frame;
        self
    }

    /// The frame of the shear strain.
    pub fn shear_frame(&self) -> ShearFrame {
        self.shear
    }
}
