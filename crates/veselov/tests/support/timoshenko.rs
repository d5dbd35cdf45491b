//! Timoshenko beam theory for harmonic bending, the continuum reference of
//! the beam's and the rod's vibration tests: deflection w and section
//! rotation ψ with
//!
//! kGA(w'' − ψ') + ρAω²w = 0,   EIψ'' + kGA(w' − ψ) + ρIω²ψ = 0,
//!
//! a free end ψ' = 0, w' − ψ = 0, a clamped end w = ψ = 0. Solved by
//! shooting from s = 0 (RK4) over the two solutions that meet the end
//! conditions there, and bisection on the 2 × 2 determinant of the end
//! conditions at s = ℓ.

use nalgebra::Vector4;

use crate::rk4::rk4;

/// A uniform Timoshenko beam: ρA, ρI, EI, kGA and its length.
#[derive(Clone, Copy, Debug)]
pub struct Timoshenko {
    pub rho_a: f64,
    pub rho_i: f64,
    pub ei: f64,
    pub kga: f64,
    pub length: f64,
}

/// RK4 steps over the length.
const STEPS: usize = 4000;

impl Timoshenko {
    /// d/ds of (w, w', ψ, ψ') at frequency ω.
    fn rhs(&self, omega: f64, y: &Vector4<f64>) -> Vector4<f64> {
        let (w, dw, psi, dpsi) = (y[0], y[1], y[2], y[3]);
        let w2 = omega * omega;
        Vector4::new(
            dw,
            dpsi - self.rho_a * w2 * w / self.kga,
            dpsi,
            -(self.kga * (dw - psi) + self.rho_i * w2 * psi) / self.ei,
        )
    }

    /// (w, w', ψ, ψ') at s = ℓ from `y` at s = 0, with `observe` called at
    /// every RK4 node (k = 0 … [`STEPS`], s = kℓ/STEPS).
    fn shoot(&self, omega: f64, y: Vector4<f64>, observe: impl FnMut(usize, &Vector4<f64>)) -> Vector4<f64> {
        rk4(y, self.length, STEPS, |y| self.rhs(omega, y), observe)
    }

    /// The two starts at s = 0 that meet its end condition: a clamped end
    /// w = ψ = 0 (w' or ψ' free), a free end ψ' = 0, w' = ψ (w or ψ free).
    fn starts(clamped: bool) -> [Vector4<f64>; 2] {
        if clamped {
            [Vector4::new(0.0, 1.0, 0.0, 0.0), Vector4::new(0.0, 0.0, 0.0, 1.0)]
        } else {
            [Vector4::new(1.0, 0.0, 0.0, 0.0), Vector4::new(0.0, 1.0, 1.0, 0.0)]
        }
    }

    /// The free end's conditions (ψ', w' − ψ) at s = ℓ.
    fn free_end(y: &Vector4<f64>) -> (f64, f64) {
        (y[3], y[1] - y[2])
    }

    /// det of the end conditions at s = ℓ (free there) for frequency ω,
    /// the start clamped or free.
    pub fn end_determinant(&self, omega: f64, clamped: bool) -> f64 {
        let [a, b] = Self::starts(clamped).map(|y| Self::free_end(&self.shoot(omega, y, |_, _| {})));
        a.0 * b.1 - a.1 * b.0
    }

    /// The first `count` frequencies above `from`, bracketed on a grid of
    /// `step` and bisected.
    pub fn frequencies(&self, count: usize, clamped: bool, from: f64, step: f64) -> Vec<f64> {
        let mut roots = Vec::new();
        let mut w = from;
        let mut f = self.end_determinant(w, clamped);
        while roots.len() < count {
            let (w2, f2) = (w + step, self.end_determinant(w + step, clamped));
            if f.signum() != f2.signum() {
                let (mut lo, mut hi, mut flo) = (w, w2, f);
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    let fm = self.end_determinant(mid, clamped);
                    if fm.signum() == flo.signum() {
                        (lo, flo) = (mid, fm);
                    } else {
                        hi = mid;
                    }
                }
                roots.push(0.5 * (lo + hi));
            }
            (w, f) = (w2, f2);
        }
        roots
    }

    /// The free–free mode of frequency `omega` (a root of
    /// [`end_determinant`](Self::end_determinant)), as (w, ψ) at the RK4
    /// nodes s = kℓ/4000, scaled to w(0) = 1: the start meeting the end
    /// conditions at s = ℓ is the null vector of their 2 × 2 matrix.
    pub fn free_free_mode(&self, omega: f64) -> Vec<(f64, f64)> {
        let [a, b] = Self::starts(false);
        let (ea, eb) = (
            Self::free_end(&self.shoot(omega, a, |_, _| {})),
            Self::free_end(&self.shoot(omega, b, |_, _| {})),
        );
        // (α, β) with α·ea + β·eb = 0: the larger row's null vector.
        let (alpha, beta) = if ea.0.abs() + eb.0.abs() >= ea.1.abs() + eb.1.abs() {
            (eb.0, -ea.0)
        } else {
            (eb.1, -ea.1)
        };
        let mut mode = vec![(0.0, 0.0); STEPS + 1];
        self.shoot(omega, a * alpha + b * beta, |k, y| mode[k] = (y[0], y[2]));
        let scale = mode[0].0;
        mode.iter().map(|&(w, psi)| (w / scale, psi / scale)).collect()
    }

    /// Values of a mode at s ∈ [0, ℓ] by linear interpolation between the
    /// RK4 nodes (an error of O(h²), h = ℓ/4000).
    pub fn mode_at(&self, mode: &[(f64, f64)], s: f64) -> (f64, f64) {
        let x = (s / self.length * STEPS as f64).clamp(0.0, STEPS as f64);
        let k = (x.floor() as usize).min(STEPS - 1);
        let t = x - k as f64;
        let (a, b) = (mode[k], mode[k + 1]);
        (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1))
    }
}
