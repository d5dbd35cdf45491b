//! Seed 000 §5's set-up (note 000 §15.2–§15.3): the beam of length
//! L = 0.8 m with a 0.01 m square section, Δs = 0.02 m, Δt = 0.04 s, marched
//! in space from the prescribed motion of its first two columns,
//!
//! g_0^0 = (I, 0),        g_0^{j+1} = g_0^j τ(Δt ξ_0),  ξ_0 = (0, −0.85, 0; 0, −0.1, 0),
//! g_1^0 = (I, (0,0,Δs)), g_1^{j+1} = g_1^j τ(Δt ξ_1),  ξ_1 = (0.06, −0.849, −0.04; −0.03, −0.1, 0),
//!
//! and the root strains η_0^j = τ⁻¹((g_0^j)⁻¹g_1^j)/Δs (Fig. 3 shows 𝐠_0,
//! j = 0..3). The data are material-independent; the paper gives no ρ, E,
//! ν nor shear factor (note 000 §15.2). Index convention: 41 space nodes
//! a = 0..40 (A − 1 = 40 ↔ s = L) and 51 real time nodes j = 0..50 plus the
//! slaved j = N = 51 (note 000 §15.2's recommended reading).

use nalgebra::SVector;

use crate::lie::{LieError, Retraction, RigidMotions, SE3};

/// Beam length L (m).
pub const LENGTH: f64 = 0.8;
/// Side of the square section (m).
pub const SIDE: f64 = 0.01;
/// Space step Δs (m).
pub const DS: f64 = 0.02;
/// Time step Δt (s).
pub const DT: f64 = 0.04;
/// Duration T (s).
pub const DURATION: f64 = 2.0;
/// Velocity ξ_0 of the column s = 0 ((ω; v), body frame).
pub const XI0: [f64; 6] = [0.0, -0.85, 0.0, 0.0, -0.1, 0.0];
/// Velocity ξ_1 of the column s = Δs.
pub const XI1: [f64; 6] = [0.06, -0.849, -0.04, -0.03, -0.1, 0.0];
/// Last real time node N − 1 = T/Δt = 50 (the slaved node is N = 51).
pub const LAST_TIME_NODE: usize = 50;
/// Last space node A − 1 = L/Δs = 40.
pub const LAST_SPACE_NODE: usize = 40;

/// The prescribed columns 𝐠_0 and 𝐠_1 at time nodes j = 0..=`last`,
/// advanced with the retraction `R` (the paper: Cayley).
pub fn prescribed_columns<R: Retraction<6, Family = RigidMotions>>(last: usize) -> (Vec<SE3<f64>>, Vec<SE3<f64>>) {
    let column = |start: SE3<f64>, xi: [f64; 6]| {
        let step = R::tau(&(SVector::from(xi) * DT));
        let mut g = Vec::with_capacity(last + 1);
        g.push(start);
        for j in 0..last {
            g.push(g[j].compose(&step));
        }
        g
    };
    (
        column(SE3::identity(), XI0),
        column(SE3::from_translation(nalgebra::Vector3::new(0.0, 0.0, DS)), XI1),
    )
}

/// The root strains η_0^j = τ⁻¹((g_0^j)⁻¹g_1^j)/Δs.
///
/// # Errors
/// [`LieError::NearCutLocus`] when a relative rotation reaches π.
pub fn root_strains<R: Retraction<6, Family = RigidMotions>>(
    col0: &[SE3<f64>],
    col1: &[SE3<f64>],
) -> Result<Vec<SVector<f64, 6>>, LieError> {
    col0.iter()
        .zip(col1)
        .map(|(g0, g1)| R::tau_inv(&g0.between(g1)).map(|x| x / DS))
        .collect()
}
