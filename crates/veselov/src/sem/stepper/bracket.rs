//! The fall-back of a step whose starts fail: a bracket scan of the energy
//! residual f(h) = E⁻(q_k, q_{k+1}(h), h) − E_k on [α, β]·h_{k−1} and regula
//! falsi on the sign change nearest h_{k−1} (module documentation of the
//! stepper).

use nalgebra::SVector;

use super::{SemIntegrator, SemState};
use crate::error::{Error, Result};
use crate::mechanics::Lagrangian;
use crate::solve::scalar::illinois;

impl<L: Lagrangian<N>, const N: usize> SemIntegrator<L, N> {
    /// The energy residual `f(h) = E⁻(q, q₁(h), h) − E` and `q₁(h)`.
    pub(super) fn energy_residual(
        &self,
        s: &SemState<N>,
        h: f64,
        guess: SVector<f64, N>,
    ) -> Option<(f64, SVector<f64, N>)> {
        let (q1, _) = self.solve_position(s.t, &s.q, &s.p, h, guess)?;
        let f = self.action.leaving(s.t, &s.q, &q1, h).2 - s.energy;
        f.is_finite().then_some((f, q1))
    }

    /// Bracket scan and regula falsi on `[α, β]·h_prev`.
    pub(super) fn bracketed(
        &self,
        index: usize,
        s: &SemState<N>,
        v: SVector<f64, N>,
    ) -> Result<(SVector<f64, N>, f64, usize)> {
        let (alpha, beta) = self.options.bracket;
        let n = self.options.samples.max(4);
        let scan = |sign: f64| -> Vec<(f64, f64)> {
            (0..n)
                .filter_map(|i| {
                    let h = sign * s.h * alpha * (beta / alpha).powf(i as f64 / (n - 1) as f64);
                    self.energy_residual(s, h, s.q + v * h).map(|(f, _)| (h, f))
                })
                .collect()
        };
        let grid = scan(1.0);
        // Sign changes, nearest to h_prev in log distance.
        let best = grid
            .windows(2)
            .filter(|w| w[0].1.signum() != w[1].1.signum() || w[0].1 == 0.0)
            .min_by(|a, b| {
                let da = ((a[0].0 * a[1].0).sqrt() / s.h).ln().abs();
                let db = ((b[0].0 * b[1].0).sqrt() / s.h).ln().abs();
                da.total_cmp(&db)
            })
            .map(|w| (w[0].0, w[1].0));
        if let Some((a, b)) = best {
            let mut evals = 0;
            let h = illinois(
                |h| {
                    evals += 1;
                    self.energy_residual(s, h, s.q + v * h).map(|(f, _)| f)
                },
                a,
                b,
                4.0 * f64::EPSILON,
                200,
            )
            .ok_or_else(|| Error::NoStepRoot {
                step: index,
                t: s.t,
                reason: "root refinement failed".into(),
            })?;
            let (_, q1) = self
                .energy_residual(s, h, s.q + v * h)
                .ok_or_else(|| Error::NoStepRoot {
                    step: index,
                    t: s.t,
                    reason: "momentum equation failed at the root".into(),
                })?;
            return Ok((q1, h, evals + n));
        }
        let near = format!(
            "no sign change of E_d − E for h in [{:.3e}, {:.3e}]",
            alpha * s.h,
            beta * s.h
        );
        if grid.len() < 2 {
            return Err(Error::NoStepRoot {
                step: index,
                t: s.t,
                reason: format!("{near}: momentum equation unsolvable"),
            });
        }
        if !self.action.rule().is_symmetric() {
            let back = scan(-1.0);
            if let Some(w) = back.windows(2).find(|w| w[0].1.signum() != w[1].1.signum()) {
                return Err(Error::NegativeStep {
                    step: index,
                    t: s.t,
                    h: 0.5 * (w[0].0 + w[1].0),
                });
            }
        }
        // An interior minimum of |f| that does not reach zero: a fold of the energy equation.
        let abs: Vec<f64> = grid.iter().map(|(_, f)| f.abs()).collect();
        let imin = abs
            .iter()
            .enumerate()
            .min_by(|a, b| a.1.total_cmp(b.1))
            .map_or(0, |(i, _)| i);
        if imin > 0 && imin + 1 < abs.len() {
            return Err(Error::DegenerateStep {
                step: index,
                t: s.t,
                reason: format!(
                    "{near}; |E_d − E| has a minimum {:.3e} at h = {:.3e} (c(q, p) ≈ 0)",
                    abs[imin], grid[imin].0
                ),
            });
        }
        Err(Error::NoStepRoot {
            step: index,
            t: s.t,
            reason: near,
        })
    }
}
