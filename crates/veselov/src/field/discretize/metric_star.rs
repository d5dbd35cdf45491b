//! [`MidpointRule`]'s vertex solve for a density with a diagonal jet metric
//! ([`SmoothDensity::diagonal_jet_metric`]: 𝓛 = ½ Σ_{k,a} η_a φ_{ka}² + V(x, y),
//! e.g. the nonlinear waves of seed 002 (4.32) in any dimension).
//!
//! The vertex equation Leg_v(z) = Σ_β ∂L_β/∂y₀ = μ_v (note 003 §2.4) sums,
//! over the cells β based at v whose last vertex z is unknown,
//!
//! ∂L_β/∂y₀ = vol_β·(Σ_a η_a φ_{·a}(z) c_{0a} + ∇V(x̄_β, ȳ_β(z))/(N + 1)),
//!
//! with φ_{ka}(z) = φ̃_{ka} + (z − y₀)_k c_{Na} and ȳ_β(z) = (s_β + z)/(N + 1)
//! (φ̃ and s_β the known vertices' parts, [`PartialFrame`]), and
//!
//! ∂²L_β/∂y₀∂z = vol_β·(b_β I + ∇²V(ȳ_β(z))/(N + 1)²),  b_β = Σ_a η_a c_{0a} c_{Na}.
//!
//! An evaluation of the equation is one evaluation of V per cell (over
//! M-direction dual numbers; second order for the Jacobian; all the star's
//! cells at once where the density batches them,
//! [`SmoothDensity::jet_free_derivatives`], with the same bits) and the jet
//! term from the partial frame, with the weights η_a c_{0a} and b_β formed
//! once per vertex. The residual is computed by the operations of the
//! rule's own gradients ([`metric_gradient_from`]), so Newton zeroes the
//! equation the marcher's momenta are made of (a residual of another
//! rounding, affine in z, let the translation momenta of a free field drift
//! by 6e-12 relative over 1000 levels instead of 2e-14). The solved cells' gradients for the
//! marcher are formed once at the accepted z, from ∇V of the last
//! evaluation at that very point: the operations and bits of
//! [`DiscreteLagrangian::analytic_gradients`](crate::field::cell::DiscreteLagrangian::analytic_gradients),
//! which a restored march recomputes from the values.

use nalgebra::{SMatrix, SVector};

use super::affine::MidpointRule;
use super::affine_chain::{
    AffineFrame, MAX_STAR, PartialFrame, metric_coefficients, metric_gradient, metric_gradient_from, metric_product,
};
use super::nodes::NodeMap;
use super::smooth::SmoothDensity;
use crate::field::cell::SolvedVertex;
use crate::field::fibre::Euclidean;
use crate::field::legendre::{CauchyOptions, solve_legendre};

/// One star cell's constants in the unknown z.
#[derive(Clone, Copy)]
struct StarTerm<const N: usize> {
    /// η_a c_{0a}.
    weights: SVector<f64, N>,
    /// vol_β b_β = vol_β Σ_a η_a c_{0a} c_{Na}.
    slope: f64,
}

impl<const N: usize> StarTerm<N> {
    fn new<const M: usize>(partial: &PartialFrame<M, N>, eta: &SVector<f64, N>) -> Self {
        let weights = metric_coefficients(&partial.inverse, eta, 0);
        let slope = metric_product(&partial.inverse, &weights, N);
        Self {
            weights,
            slope: slope * partial.volume,
        }
    }
}

impl<L, X, const N: usize> MidpointRule<L, X, N>
where
    X: NodeMap<N>,
{
    /// Solves Leg_v(z) = μ_v by the generic Newton
    /// ([`solve_legendre`]) from `start` over the star's cells `frames`
    /// (`None`: not in the action) and writes their gradients at the solved
    /// z into `gradients` (the marcher's layout, N + 1 per cell, zero at the
    /// base vertex and for absent cells).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn solve_metric_star<const M: usize>(
        &self,
        eta: &SVector<f64, N>,
        frames: &[Option<PartialFrame<M, N>>],
        mu: &SVector<f64, M>,
        mu_scale: f64,
        start: SVector<f64, M>,
        options: &CauchyOptions,
        gradients: &mut [SVector<f64, M>],
    ) -> SolvedVertex<SVector<f64, M>>
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
    {
        let w = AffineFrame::<M, N>::mean_weight();
        let blank = StarTerm {
            weights: SVector::zeros(),
            slope: 0.0,
        };
        let mut terms = [blank; MAX_STAR];
        for (term, partial) in terms.iter_mut().zip(frames) {
            if let Some(partial) = partial {
                *term = StarTerm::new(partial, eta);
            }
        }
        // The cells in the action (indices into `frames`) and their
        // centres: an evaluation differentiates V at all of them at once.
        let active = || frames.iter().enumerate().filter_map(|(c, p)| Some((c, p.as_ref()?)));
        let count = active().count();
        let mut centres = [SVector::<f64, N>::zeros(); MAX_STAR];
        for (centre, (_, partial)) in centres.iter_mut().zip(active()) {
            *centre = partial.centre;
        }
        let centres = &centres[..count];
        let mut values = [SVector::<f64, M>::zeros(); MAX_STAR];
        let mut hessians = [SMatrix::<f64, M, M>::zeros(); MAX_STAR];
        // ∇V of each active cell at the last evaluation; `written` is its z
        // when that was a residual-only one (a Jacobian evaluation takes ∇V
        // from its second-order pass, which the stored gradients do not use).
        let mut potential_gradients = [SVector::<f64, M>::zeros(); MAX_STAR];
        let mut written: Option<SVector<f64, M>> = None;
        let (z, outcome) = solve_legendre::<Euclidean<M>, M>(mu, mu_scale, start, options, |z, mut jacobian| {
            let (mut leg, mut scale) = (SVector::<f64, M>::zeros(), 0.0);
            for (value, (_, partial)) in values.iter_mut().zip(active()) {
                *value = partial.value(z);
            }
            let dvs = &mut potential_gradients[..count];
            let asked = jacobian.is_some().then_some(&mut hessians[..count]);
            self.jet_free_batch(centres, &values[..count], dvs, asked);
            if let Some(j) = jacobian.as_deref_mut() {
                j.fill(0.0);
            }
            for (k, (c, partial)) in active().enumerate() {
                let term = &terms[c];
                if let Some(j) = jacobian.as_deref_mut() {
                    *j += SMatrix::<f64, M, M>::identity() * term.slope + hessians[k] * (w * w * partial.volume);
                }
                let dv = &potential_gradients[k];
                let g = metric_gradient_from(|k, a| partial.jet_entry(z, k, a), &term.weights, dv, partial.volume);
                leg += g;
                scale += g.amax();
            }
            written = if jacobian.is_none() { Some(*z) } else { None };
            (leg, scale)
        });
        if outcome.failure.is_some() {
            return SolvedVertex {
                value: z,
                outcome,
                gradients_written: false,
                forces_written: false,
            };
        }
        if written != Some(z) {
            for (value, (_, partial)) in values.iter_mut().zip(active()) {
                *value = partial.value(&z);
            }
            self.jet_free_batch(centres, &values[..count], &mut potential_gradients[..count], None);
        }
        let width = N + 1;
        gradients.fill(SVector::zeros());
        for (k, (c, partial)) in active().enumerate() {
            let out = &mut gradients[c * width..(c + 1) * width];
            let frame = partial.complete(&z);
            for (l, g) in out.iter_mut().enumerate().skip(1) {
                *g = metric_gradient(&frame, eta, &potential_gradients[k], l);
            }
        }
        SolvedVertex {
            value: z,
            outcome,
            gradients_written: true,
            forces_written: false,
        }
    }
}
