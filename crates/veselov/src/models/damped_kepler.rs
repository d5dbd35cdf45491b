//! Kepler problem with linear drag `F = −c v`: the orbit decays and spirals in.

use nalgebra::SVector;

use crate::ad::Scalar;
use crate::error::{Error, Result};
use crate::mechanics::Force;

/// Linear drag `F = −c v`, `c ≥ 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearDrag {
    /// Drag coefficient `c`.
    pub coefficient: f64,
}

impl LinearDrag {
    /// Drag with `c ≥ 0`.
    pub fn new(coefficient: f64) -> Result<Self> {
        if !(coefficient.is_finite() && coefficient >= 0.0) {
            return Err(Error::InvalidParameter {
                name: "drag".into(),
                value: coefficient.to_string(),
                reason: "must be finite and ≥ 0".into(),
            });
        }
        Ok(Self { coefficient })
    }
}

impl<const N: usize> Force<N> for LinearDrag {
    fn force<D: Scalar>(&self, _t: D, _q: &SVector<D, N>, v: &SVector<D, N>) -> SVector<D, N> {
        v * D::from(-self.coefficient)
    }
}
