//! Hénon–Heiles system `V = ½(x² + y²) + x²y − y³/3`, unit mass.

use nalgebra::{SVector, Vector2};

use crate::ad::Scalar;
use crate::mechanics::{PhaseState, Potential, SeparableLagrangian};

/// The Hénon–Heiles potential.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct HenonHeiles;

impl HenonHeiles {
    /// The Lagrangian system (unit mass).
    pub fn system(&self) -> SeparableLagrangian<Self, 2> {
        SeparableLagrangian::unit_mass(*self)
    }
    /// Energy `H = ½|p|² + V(q)`.
    pub fn energy(&self, x: &PhaseState<2>) -> f64 {
        0.5 * x.p.norm_squared() + self.potential(0.0, &x.q)
    }
    /// A bounded chaotic-regime initial state with energy 1/8.
    pub fn initial_state() -> PhaseState<2> {
        let q = Vector2::new(0.0, 0.1);
        let v = 2.0 * (0.125 - HenonHeiles.potential(0.0, &q));
        PhaseState::new(0.0, q, Vector2::new(v.sqrt(), 0.0))
    }
}

impl Potential<2> for HenonHeiles {
    #[inline]
    fn potential<D: Scalar>(&self, _t: D, q: &SVector<D, 2>) -> D {
        let (x, y) = (q[0], q[1]);
        (x * x + y * y) * 0.5 + x * x * y - y * y * y / 3.0
    }
}
