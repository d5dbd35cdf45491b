//! Symplecticity defect `‖JᵀΩJ − Ω‖` of a one-step map.

use nalgebra::DMatrix;

use crate::mechanics::FlowJacobian;

/// `max |(JᵀΩJ − Ω)ᵢⱼ|` with `Ω = [[0, I], [−I, 0]]` on `(q, p)`, for the
/// Jacobian `J` of a map `(q, p) ↦ (q', p')` given in blocks. Zero for a
/// symplectic map; in floating point, a few round-offs times `‖J‖²`.
pub fn symplecticity_defect<const N: usize>(j: &FlowJacobian<N>) -> f64 {
    let mut full = DMatrix::<f64>::zeros(2 * N, 2 * N);
    full.view_mut((0, 0), (N, N)).copy_from(&j.qq);
    full.view_mut((0, N), (N, N)).copy_from(&j.qp);
    full.view_mut((N, 0), (N, N)).copy_from(&j.pq);
    full.view_mut((N, N), (N, N)).copy_from(&j.pp);
    let mut omega = DMatrix::<f64>::zeros(2 * N, 2 * N);
    for i in 0..N {
        omega[(i, N + i)] = 1.0;
        omega[(N + i, i)] = -1.0;
    }
    (full.transpose() * &omega * &full - omega).amax()
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::SMatrix;

    #[test]
    fn shear_is_symplectic_and_scaling_is_not() {
        let id = SMatrix::<f64, 2, 2>::identity();
        let shear = FlowJacobian {
            qq: id,
            qp: id * 0.3,
            pq: SMatrix::zeros(),
            pp: id,
        };
        assert!(symplecticity_defect(&shear) < 1e-16);
        let scale = FlowJacobian {
            qq: id * 1.1,
            qp: SMatrix::zeros(),
            pq: SMatrix::zeros(),
            pp: id,
        };
        assert!((symplecticity_defect(&scale) - 0.1).abs() < 1e-12);
    }
}
