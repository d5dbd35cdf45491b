//! What a step hands to the next: the spatial momentum π = Ad*_{g⁻¹}μ (and,
//! on the split path, ∇V) of the state it returned.
//!
//! Both integrators advance the spatial momentum, π_{k+1} = π_k + Ad*_{g_k⁻¹}∂_g L_d
//! (derived from μ_{k+1} = Ad_{F_k}ᵀν_k and ν_k = μ_k + ∂_g L_d), and return
//! μ_{k+1} = Ad_{g_{k+1}}ᵀπ_{k+1}. In exact arithmetic this is the same map as
//! μ_{k+1} = Ad_Fᵀν; in floating point a symmetry that makes the increment
//! vanish (∂_g L_d = 0 for a free body) keeps π **bit for bit**, instead of
//! letting it random-walk by a few ulps per step. When the state passed in is
//! not the one the previous step returned, π is recomputed from (g, μ).

use nalgebra::SVector;

use super::GroupState;
use crate::lie::{GroupFamily, LieGroup};

pub(crate) struct Carry<G: GroupFamily<N>, const N: usize> {
    g: G::Element<f64>,
    mu: SVector<f64, N>,
    pub(crate) spatial: SVector<f64, N>,
    pub(crate) gradient: SVector<f64, N>,
}

impl<G: GroupFamily<N>, const N: usize> Carry<G, N> {
    pub(crate) fn new(state: &GroupState<G, N>, spatial: SVector<f64, N>, gradient: SVector<f64, N>) -> Self {
        Self {
            g: state.g,
            mu: state.mu,
            spatial,
            gradient,
        }
    }

    /// The carried data if `state` is the state it was made for.
    pub(crate) fn matching(
        carry: &Option<Self>,
        state: &GroupState<G, N>,
    ) -> Option<(SVector<f64, N>, SVector<f64, N>)> {
        match carry {
            Some(c) if c.g == state.g && c.mu == state.mu => Some((c.spatial, c.gradient)),
            _ => None,
        }
    }
}

impl<G: GroupFamily<N>, const N: usize> Carry<G, N> {
    /// Checkpoint words: a flag, then the state it was made for (rotation,
    /// translation, μ), π and ∇V.
    pub(crate) fn save(carry: &Option<Self>, out: &mut Vec<f64>) {
        let record = carry.as_ref().map(|c| {
            let mut r: Vec<f64> = G::rotation(&c.g).iter().copied().collect();
            r.extend(G::translation(&c.g).iter());
            r.extend(c.mu.iter().chain(c.spatial.iter()).chain(c.gradient.iter()));
            r
        });
        crate::run::save_option(out, record.as_deref(), 12 + 3 * N);
    }

    /// Read what [`Carry::save`] wrote.
    pub(crate) fn restore(words: &mut crate::run::Words<'_>) -> crate::Result<Option<Self>> {
        Ok(crate::run::restore_option(words, 12 + 3 * N)?.map(|r| {
            let g = G::from_parts(
                nalgebra::Matrix3::from_column_slice(&r[..9]),
                SVector::from_column_slice(&r[9..12]),
            );
            let part = |k: usize| SVector::from_column_slice(&r[12 + k * N..12 + (k + 1) * N]);
            Self {
                g,
                mu: part(0),
                spatial: part(1),
                gradient: part(2),
            }
        }))
    }
}

/// Save an optional vector as checkpoint words.
pub(crate) fn save_vector<const N: usize>(v: &Option<SVector<f64, N>>, out: &mut Vec<f64>) {
    crate::run::save_option(out, v.as_ref().map(|v| v.as_slice()), N);
}

/// Read what [`save_vector`] wrote.
pub(crate) fn restore_vector<const N: usize>(
    words: &mut crate::run::Words<'_>,
) -> crate::Result<Option<SVector<f64, N>>> {
    Ok(crate::run::restore_option(words, N)?.map(SVector::from_column_slice))
}

/// π = Ad*_{g⁻¹}μ.
pub(crate) fn spatial_of<G: GroupFamily<N>, const N: usize>(state: &GroupState<G, N>) -> SVector<f64, N> {
    state.g.coadjoint() * state.mu
}
