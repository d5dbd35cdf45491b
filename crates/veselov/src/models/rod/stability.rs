//! The step limit of the rod's march (note 003 §3.9; not in the paper).
//! The march is hyperbolic with lattice speed Δs/Δt; with the fastest wave
//! speed c of the rod — the largest of √(λ_max(C₁)/ρ) and
//! √(λ_max(J^{−½}C₂J^{−½})), componentwise √(C₁ᵢᵢ/ρ), √(C₂ᵢᵢ/Jᵢᵢ) for diagonal
//! parameters — the Courant number is ν = cΔt/Δs.
//!
//! A second limit comes from the shear coupling (Timoshenko's rotary
//! oscillator, absent from the note): at an unstressed straight state a
//! frame rotation θ strains the rod by ε = ê θ and meets the torque
//! −Kθ, K = êᵀC₁ê, against the inertia J, an oscillator of frequency
//! ω = √λ_max(J^{−½}KJ^{−½}) (√(κGA/(ρI)) for a beam, large for slender rods)
//! that the march treats explicitly: from the R-equation of note 003 §3.6,
//! J(θ_{k+1} − 2θ_k + θ_{k−1}) = −Δt²Kθ_k, stable for ωΔt < 2.
//!
//! The two couple (the Timoshenko spectrum's upper branch has
//! frequency² ≈ ω² + c²k²), so the step number is √(ν² + (ωΔt/2)²);
//! above [`COURANT_LIMIT`] the lattice
//! waves grow without bound, the rotations reach the cut locus, the vertex
//! Newton fails and the march stops with a typed error.

use crate::error::{Error, Result};
use nalgebra::Matrix3;

use crate::lie::so3;
use crate::models::rod::RodParameters;

/// The largest step number √((cΔt/Δs)² + (ωΔt/2)²) at which the march is stable.
pub const COURANT_LIMIT: f64 = 1.0;

/// The fastest wave speed c of the rod.
///
/// # Errors
/// [`Error::InvalidParameter`] naming `rho` or `inertia` when either
/// vanishes (infinitely fast waves: no explicit-like march is stable).
pub fn wave_speed(p: &RodParameters) -> Result<f64> {
    if p.rho() <= 0.0 {
        return Err(Error::InvalidParameter {
            name: "rho".into(),
            value: p.rho().to_string(),
            reason: "a massless rod has no finite wave speed, hence no stable step".into(),
        });
    }
    let linear = p.c1().symmetric_eigenvalues().max() / p.rho();
    let l_inv = inverse_inertia_root(p)?;
    let angular = (l_inv * p.c2() * l_inv.transpose()).symmetric_eigenvalues().max();
    Ok(linear.max(angular).sqrt())
}

/// L⁻¹ with J = LLᵀ.
fn inverse_inertia_root(p: &RodParameters) -> Result<Matrix3<f64>> {
    let chol = p.inertia().cholesky().ok_or_else(|| Error::InvalidParameter {
        name: "inertia".into(),
        value: format!("{}", p.inertia()),
        reason: "a rod with a vanishing moment of inertia has no finite angular wave speed".into(),
    })?;
    let l_inv = chol.l().try_inverse().ok_or_else(|| Error::InvalidParameter {
        name: "inertia".into(),
        value: format!("{}", p.inertia()),
        reason: "singular".into(),
    })?;
    Ok(l_inv)
}

/// The frequency ω of the shear–rotation oscillator,
/// ω² = λ_max(J^{−½}êᵀC₁êJ^{−½}), ê the hat matrix of the unstressed strain.
///
/// # Errors
/// As [`wave_speed`].
pub fn rotary_frequency(p: &RodParameters) -> Result<f64> {
    let l_inv = inverse_inertia_root(p)?;
    let e = so3::hat(p.strain());
    let k = e.transpose() * p.c1() * e;
    Ok((l_inv * k * l_inv.transpose())
        .symmetric_eigenvalues()
        .max()
        .max(0.0)
        .sqrt())
}

/// The step number √((cΔt/Δs)² + (ωΔt/2)²) (stable up to [`COURANT_LIMIT`]).
///
/// # Errors
/// As [`wave_speed`].
pub fn courant_number(p: &RodParameters, ds: f64, dt: f64) -> Result<f64> {
    Ok((wave_speed(p)? * dt / ds).hypot(0.5 * rotary_frequency(p)? * dt))
}

/// The largest Δt with step number [`COURANT_LIMIT`] for spacing Δs.
///
/// # Errors
/// As [`wave_speed`].
pub fn largest_step(p: &RodParameters, ds: f64) -> Result<f64> {
    Ok(COURANT_LIMIT / (wave_speed(p)? / ds).hypot(0.5 * rotary_frequency(p)?))
}

/// Whether a step above the limit is refused.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum StepCheck {
    /// Refuse Δt above the limit (the default).
    #[default]
    Enforce,
    /// Accept it (the run then stops with a vertex-solve error once the
    /// lattice waves have grown; for studying the limit).
    Override,
}

impl StepCheck {
    /// The Courant number of (Δs, Δt), refused above [`COURANT_LIMIT`] unless overridden.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `dt`, with the largest stable Δt.
    pub fn check(self, p: &RodParameters, ds: f64, dt: f64) -> Result<f64> {
        let nu = courant_number(p, ds, dt)?;
        if nu > COURANT_LIMIT && self == StepCheck::Enforce {
            return Err(Error::InvalidParameter {
                name: "dt".into(),
                value: dt.to_string(),
                reason: format!(
                    "step number √((c·dt/ds)² + (ω·dt/2)²) = {nu:.4} above the stability limit {COURANT_LIMIT} \
                     (wave speed c = {:.6e}, rotary frequency ω = {:.6e}, ds = {ds}: largest stable dt = {:.6e}); \
                     override the step check to run anyway",
                    wave_speed(p)?,
                    rotary_frequency(p)?,
                    largest_step(p, ds)?
                ),
            });
        }
        Ok(nu)
    }
}
