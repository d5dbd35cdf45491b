//! The exact Jacobian of a [`GalerkinIntegrator`] step by the implicit
//! function theorem on the converged stage equations.

use nalgebra::{SMatrix, SVector};

use super::{GalerkinIntegrator, Mode};
use crate::error::Result;
use crate::mechanics::force::Force;
use crate::mechanics::lagrangian::Lagrangian;
use crate::mechanics::state::{FlowJacobian, PhaseState};

impl<L: Lagrangian<N>, const N: usize, F: Force<N>> GalerkinIntegrator<L, N, F> {
    /// Exact Jacobian of the step `(q_k, p_k) ↦ (q_{k+1}, p_{k+1})` at `state`,
    /// by the implicit function theorem on the converged stage equations.
    pub fn flow_jacobian(&mut self, state: &PhaseState<N>) -> Result<(PhaseState<N>, FlowJacobian<N>)> {
        let (next, _) = self.step_report(0, state)?;
        let m = self.scheme.intervals();
        self.eval_hessians(state.t);
        let dim = N * m;
        self.fill_jacobian(Mode::Step);
        self.jacobian_kept = false;
        self.lu.factor("flow Jacobian")?;
        let h_col0: Vec<SMatrix<f64, N, N>> = (0..=m).map(|nu| self.action_hessian_block(nu, 0)).collect();
        let h_last: Vec<SMatrix<f64, N, N>> = (0..=m).map(|mu| self.action_hessian_block(m, mu)).collect();
        let mut jac: FlowJacobian<N> = FlowJacobian {
            qq: SMatrix::zeros(),
            qp: SMatrix::zeros(),
            pq: SMatrix::zeros(),
            pp: SMatrix::zeros(),
        };
        let mut rhs = vec![0.0; dim];
        for wrt_p in [false, true] {
            for j in 0..N {
                // Right-hand side −(H_{ν0} δq + δ_{ν0} δp).
                for rb in 0..m {
                    for a in 0..N {
                        rhs[rb * N + a] = if wrt_p {
                            if rb == 0 && a == j { -1.0 } else { 0.0 }
                        } else {
                            -h_col0[rb][(a, j)]
                        };
                    }
                }
                self.lu.solve(&mut rhs);
                let dq_next: SVector<f64, N> = SVector::from_fn(|a, _| rhs[(m - 1) * N + a]);
                let mut dp_next: SVector<f64, N> = if wrt_p {
                    SVector::zeros()
                } else {
                    h_last[0].column(j).into_owned()
                };
                for mu in 1..=m {
                    let dq_mu = SVector::<f64, N>::from_fn(|a, _| rhs[(mu - 1) * N + a]);
                    dp_next += h_last[mu] * dq_mu;
                }
                if wrt_p {
                    jac.qp.set_column(j, &dq_next);
                    jac.pp.set_column(j, &dp_next);
                } else {
                    jac.qq.set_column(j, &dq_next);
                    jac.pq.set_column(j, &dp_next);
                }
            }
        }
        Ok((next, jac))
    }
}
