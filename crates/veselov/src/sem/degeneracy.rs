//! The energy equation's degeneracy at a start (note 001 §3.3): eliminating
//! `q_{k+1}` through the momentum equation, the discrete energy of a step
//! `h` from `(q, p)` is
//!
//! `E_d(q, p, h) = H(q, p) + c(q, p)·hʳ + a(q, p)·hʳ⁺¹ + O(hʳ⁺²)`,
//!
//! `r` the rule's order ([`SemRule::order`](super::SemRule::order)), and the
//! step of a run solves `c·hʳ + a·hʳ⁺¹ ≈ E − H_k`. Where `c` vanishes (the
//! degeneracy set: for the left-point rule (3.18), `c = −pᵀM⁻¹∇V`, every
//! turning point and every crossing of a critical point of `V`), the
//! leading term no longer sets the step: started there, the left-point
//! rule's steps grow in proportion to the time since the turning point,
//! whatever `h₀` (measured on Kepler from pericentre: `h_k ≈ κ·(t_k − t_p)`,
//! `κ = 0.154, 0.479, 0.823` at `e = 0.1, 0.3, 0.5`), and the run does not
//! converge as `h₀` shrinks.
//!
//! Where `c` vanishes identically along the motion (a circular Kepler orbit,
//! `c = −p·∇V ≡ 0`), the step equation is `a·hʳ⁺¹ = E − H_k` with `E − H_k`
//! nearly constant, and the steps stay within a bounded factor of `h₀`
//! (2.73 over a circular Kepler orbit, for `h₀ = 0.02` and `0.005` alike):
//! the degeneracy that matters is `c` crossing zero, not `c` staying there.
//!
//! [`StartExpansion`] measures the two terms at the first step from three
//! first steps `h₀, h₀/2, h₀/4` (no derivative of `L` beyond the step's own),
//! at the start and again one step `h₀` later, so that a run can say when
//! it starts on or near that set and crosses it.

/// The leading and next terms of `E_d(h₀) − H` at a start (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StartExpansion {
    /// `c·h₀ʳ`: the term that sets the step away from the degeneracy set.
    pub leading: f64,
    /// `a·h₀ʳ⁺¹`: the next one.
    pub next: f64,
    /// `c·h₀ʳ` one step `h₀` later (at `(q₁, p₁)`).
    pub leading_after_step: f64,
}

impl StartExpansion {
    /// `|c·h₀ʳ| / |a·h₀ʳ⁺¹|`, the leading term against the next (`+∞` when
    /// both vanish, as for an energy that does not depend on the step).
    /// Well away from the degeneracy set it grows like `1/h₀`; on it, it is
    /// round-off.
    pub fn dominance(&self) -> f64 {
        if self.next == 0.0 {
            return f64::INFINITY;
        }
        (self.leading / self.next).abs()
    }

    /// `|Δ(c·h₀ʳ)| / |a·h₀ʳ⁺¹|` over the first step: how fast `c` moves
    /// against the next term. Round-off where `c` stays zero along the
    /// motion; about `|ċ|/|a|` (for the left-point rule) where it crosses
    /// zero.
    pub fn drift(&self) -> f64 {
        let change = self.leading_after_step - self.leading;
        if self.next == 0.0 {
            return if change == 0.0 { 0.0 } else { f64::INFINITY };
        }
        (change / self.next).abs()
    }

    /// From the discrete energies `e = [E_d(h₀), E_d(h₀/2), E_d(h₀/4)]` of a
    /// rule of order `r`: with `D₁ = e₀ − e₁`, `D₂ = e₁ − e₂`, the next term
    /// is `B/(1 − 2^{−r−1})` with `B = 2D₁ − 2^{r+1}D₂`, the leading one
    /// `(D₁ − B)/(1 − 2^{−r})` (the three-point elimination of `H`).
    /// `leading_after_step` is that of the energies `after`, one step later.
    pub fn from_energies(e: [f64; 3], after: [f64; 3], r: usize) -> Self {
        let (leading, next) = terms(e, r);
        Self {
            leading,
            next,
            leading_after_step: terms(after, r).0,
        }
    }
}

/// The leading and next terms of `E_d` from its values at `h, h/2, h/4`.
fn terms(e: [f64; 3], r: usize) -> (f64, f64) {
    let two_r = 2f64.powi(r as i32);
    let (d1, d2) = (e[0] - e[1], e[1] - e[2]);
    let b = 2.0 * d1 - 2.0 * two_r * d2;
    ((d1 - b) / (1.0 - 1.0 / two_r), b / (1.0 - 0.5 / two_r))
}

#[cfg(test)]
mod tests {
    use super::StartExpansion;

    #[test]
    fn the_elimination_recovers_the_terms_of_a_cubic() {
        for r in [1usize, 2] {
            let (h, c, a) = (0.01, -0.3, 0.7);
            let e = |h: f64| 2.5 + c * h.powi(r as i32) + a * h.powi(r as i32 + 1);
            let x = StartExpansion::from_energies([e(h), e(h / 2.0), e(h / 4.0)], [0.0; 3], r);
            let (leading, next) = (c * h.powi(r as i32), a * h.powi(r as i32 + 1));
            // Differences of values of size 2.5, amplified by the elimination's
            // coefficients (at most 16): a few dozen ulps of 2.5.
            let roundoff = 64.0 * f64::EPSILON * 2.5;
            assert!((x.leading - leading).abs() < roundoff, "{r}: {x:?}");
            assert!((x.next - next).abs() < roundoff, "{r}: {x:?}");
        }
    }
}
