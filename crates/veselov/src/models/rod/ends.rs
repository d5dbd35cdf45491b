//! Boundary conditions at the rod's ends: free (the truncated action, the
//! default of [`RodLattice`]), clamped (r, R fixed) or driven (r, R given
//! functions of time), as Dirichlet data of the march
//! ([`CauchyMarcher::with_dirichlet`](crate::field::cauchy::CauchyMarcher::with_dirichlet)).
//! An end material point p (0 or the last) appears on every other level;
//! its value at level w is prescribed at time t = wΔt/2, and the equation at
//! that vertex holds with the (uncomputed) reaction of the support.

use std::sync::Arc;

use super::lattice::RodLattice;
use crate::field::cauchy::Dirichlet;
use crate::field::fibre::Pose;

/// The condition at one end of the rod.
#[derive(Clone, Default)]
pub enum EndCondition {
    /// No support: the end's star is truncated to the body.
    #[default]
    Free,
    /// Position and frame held fixed.
    Clamped(Pose<f64>),
    /// Position and frame prescribed as functions of time.
    Driven(Arc<dyn Fn(f64) -> Pose<f64> + Send + Sync>),
}

impl std::fmt::Debug for EndCondition {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            EndCondition::Free => write!(f, "Free"),
            EndCondition::Clamped(p) => write!(f, "Clamped({p:?})"),
            EndCondition::Driven(_) => write!(f, "Driven(..)"),
        }
    }
}

impl EndCondition {
    /// The prescribed value at time `t`, or `None` for a free end.
    pub fn value(&self, t: f64) -> Option<Pose<f64>> {
        match self {
            EndCondition::Free => None,
            EndCondition::Clamped(p) => Some(*p),
            EndCondition::Driven(f) => Some(f(t)),
        }
    }

    /// Whether the end is free.
    pub fn is_free(&self) -> bool {
        matches!(self, EndCondition::Free)
    }
}

/// The conditions at s = 0 (`start`) and s = length (`end`).
#[derive(Clone, Debug, Default)]
pub struct RodEnds {
    /// At material point 0.
    pub start: EndCondition,
    /// At the last material point.
    pub end: EndCondition,
}

impl RodEnds {
    /// The prescribed value at material point `p` and level `w` of `lattice`, if any.
    pub fn value(&self, lattice: &RodLattice, p: i64, w: i64) -> Option<Pose<f64>> {
        let last = lattice.nodes() as i64 - 1;
        let t = lattice.time(w);
        match p {
            0 => self.start.value(t),
            _ if p == last => self.end.value(t),
            _ => None,
        }
    }

    /// The Dirichlet data of the march, or `None` when both ends are free.
    pub fn dirichlet(&self, lattice: &RodLattice) -> Option<Dirichlet<Pose<f64>>> {
        if self.start.is_free() && self.end.is_free() {
            return None;
        }
        let (ends, lattice) = (self.clone(), lattice.clone());
        let window = lattice.window();
        Some(Arc::new(move |v: &[i64]| {
            ends.value(&lattice, window.material_point(v), v[0] + v[1])
        }))
    }

    /// Overwrites the end values of Cauchy data (levels `first_level` …,
    /// in-level index order, as [`RodLattice::cauchy_data`]) with the
    /// prescribed ones, so that data and conditions agree.
    pub fn apply(&self, lattice: &RodLattice, first_level: i64, data: &mut [Vec<Pose<f64>>]) {
        for (l, level) in data.iter_mut().enumerate() {
            let w = first_level + l as i64;
            for (i, y) in level.iter_mut().enumerate() {
                if let Some(value) = lattice.node(w, i).and_then(|p| self.value(lattice, p as i64, w)) {
                    *y = value;
                }
            }
        }
    }
}
