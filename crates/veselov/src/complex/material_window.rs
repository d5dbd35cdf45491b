//! A finite material window of the 2-D CFK lattice: a body of finite extent
//! (a rod with free ends) marched in time on the periodic lattice
//! [`CfkTorus`] (note 003 §3.2, §3.7 "truncation for a free rod").
//!
//! The flow Δv = v + (1, 1) leaves the coordinate p = v₀ − v₁ unchanged; under
//! the leapfrog node map (6.2) it is the material point, s = pΔs/2. The window
//! keeps the vertices with 0 ≤ p ≤ `last` and the triangles whose three
//! vertices all lie in it; every other triangle is dropped from the action.
//! The discrete action of the finite body is then the sum of L_β over the
//! kept triangles, and its Euler–Lagrange equations at the end vertices are
//! the truncated stars of Def. 3.9 (an end vertex p = 0 keeps three of its
//! six triangles: (v, +) as v₀, (v − e₁, −) as v₁, (v − (1, 1), +) as v₂).
//!
//! On the torus of period N a vertex's p is known modulo 2N (the
//! identification v ~ v + N(e₀ − e₁) moves p by 2N); a window needs
//! 2N ≥ last + 2, so that the neighbours p = −1 and p = last + 1 of the ends
//! are never taken for points of the body.

use crate::complex::{CfkTorus, MAX_LATTICE_DIMENSION};
use crate::{Error, Result};

/// The shift of one level along e₁ split by the window's wrap 2N
/// ([`MaterialWindow::level_reduction`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LevelReduction {
    shift: i64,
    quotient: i64,
    remainder: i64,
}

/// The material window 0 ≤ p ≤ `last` of a 2-D CFK torus.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MaterialWindow {
    last: i64,
    /// 2N.
    wrap: i64,
    period: i64,
}

impl MaterialWindow {
    /// The window 0 ≤ p ≤ `last` on `torus` (2-D, period N with
    /// 2N ≥ last + 2); `last ≥ 2` so that every kept vertex lies in a kept
    /// triangle based at it.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `dimension` (not 2), `nodes`
    /// (`last` below 2) or `period` (too short for the window).
    pub fn new(torus: &CfkTorus, last: usize) -> Result<Self> {
        if torus.dimension() != 2 {
            return Err(Error::InvalidParameter {
                name: "dimension".into(),
                value: torus.dimension().to_string(),
                reason: "a material window is defined on the 2-D CFK lattice (one space, one time)".into(),
            });
        }
        if last < 2 {
            return Err(Error::InvalidParameter {
                name: "nodes".into(),
                value: (last + 1).to_string(),
                reason: "a finite body needs at least 3 material points".into(),
            });
        }
        let period = torus.periods()[0];
        let last_i = i64::try_from(last).map_err(|_| Error::InvalidParameter {
            name: "nodes".into(),
            value: last.to_string(),
            reason: "too many material points".into(),
        })?;
        if 2 * period < last + 2 {
            return Err(Error::InvalidParameter {
                name: "period".into(),
                value: period.to_string(),
                reason: format!(
                    "a window of {} material points needs a lattice period of at least {}",
                    last + 1,
                    last.div_ceil(2) + 1
                ),
            });
        }
        Ok(Self {
            last: last_i,
            wrap: 2 * period as i64,
            period: period as i64,
        })
    }

    /// The lattice period N the window was made for.
    pub fn period(&self) -> usize {
        self.period as usize
    }

    /// The last material point (the body is p = 0 ..= last).
    pub fn last(&self) -> i64 {
        self.last
    }

    /// The material point p of vertex `v` reduced to 0 ≤ p < 2N.
    pub fn material_point(&self, v: &[i64]) -> i64 {
        (v[0] - v[1]).rem_euclid(self.wrap)
    }

    /// The material point of a representative `u` given by
    /// [`unwrap`](Self::unwrap): v₀ − v₁, already in 0 ≤ p < 2N, so equal to
    /// [`material_point`](Self::material_point) without its reduction.
    #[inline]
    pub fn unwrapped_point(&self, u: &[i64]) -> i64 {
        u[0] - u[1]
    }

    /// Whether vertex `v` belongs to the body.
    pub fn contains(&self, v: &[i64]) -> bool {
        self.contains_point(self.material_point(v))
    }

    /// Whether the material point `p` (0 ≤ p < 2N, [`material_point`](Self::material_point))
    /// belongs to the body.
    #[inline]
    pub fn contains_point(&self, p: i64) -> bool {
        p <= self.last
    }

    /// The representative of `v` (modulo v ~ v + N(e₀ − e₁)) whose material
    /// point lies in 0 ≤ p < 2N: the coordinates a position-dependent
    /// Lagrangian reads s from. Its material point is
    /// [`unwrapped_point`](Self::unwrapped_point) (no reduction left to do).
    pub fn unwrap(&self, v: &[i64; MAX_LATTICE_DIMENSION]) -> [i64; MAX_LATTICE_DIMENSION] {
        // p − k·wrap ∈ [0, 2N) for k = ⌊p/wrap⌋: one division.
        let k = -(v[0] - v[1]).div_euclid(self.wrap);
        let mut out = *v;
        out[0] += k * self.period;
        out[1] -= k * self.period;
        out
    }

    /// The split −w = q·2N + r (0 ≤ r < 2N) of the shift w along e₁ that
    /// takes level 0's vertices to level w's (one division for the whole
    /// level), for [`unwrap_shifted`](Self::unwrap_shifted).
    pub fn level_reduction(&self, w: i64) -> LevelReduction {
        LevelReduction {
            shift: w,
            quotient: (-w).div_euclid(self.wrap),
            remainder: (-w).rem_euclid(self.wrap),
        }
    }

    /// [`unwrap`](Self::unwrap) of u + w·e₁ for a representative `u`
    /// (0 ≤ u₀ − u₁ < 2N, as [`unwrap`](Self::unwrap) gives) and `level`
    /// = [`level_reduction`](Self::level_reduction)(w): the same
    /// coordinates, with a comparison in place of the division. The
    /// material point u₀ − u₁ − w = (u₀ − u₁ + r) + q·2N has
    /// u₀ − u₁ + r ∈ [0, 4N), so ⌊p/2N⌋ = q + [u₀ − u₁ + r ≥ 2N].
    #[inline]
    pub fn unwrap_shifted(
        &self,
        u: &[i64; MAX_LATTICE_DIMENSION],
        level: LevelReduction,
    ) -> [i64; MAX_LATTICE_DIMENSION] {
        let t = u[0] - u[1] + level.remainder;
        let k = -(level.quotient + i64::from(t >= self.wrap));
        let step = k * self.period;
        let shift = [step, level.shift - step];
        std::array::from_fn(|i| if i < 2 { u[i] + shift[i] } else { u[i] })
    }

    /// Whether the path simplex (v, σ) based at `v` lies in the body: its
    /// vertices are v, v + e_{σ(0)} and v + (1, 1), with material points
    /// p, p ± 1, p.
    pub fn contains_cell(&self, v: &[i64], perm: &[usize]) -> bool {
        self.contains_cell_at(self.material_point(v), perm)
    }

    /// [`contains_cell`](Self::contains_cell) for the simplex based at the
    /// material point `p` (0 ≤ p < 2N): without the reduction (an integer
    /// division) where the caller has p at hand.
    #[inline]
    pub fn contains_cell_at(&self, p: i64, perm: &[usize]) -> bool {
        let q = if perm[0] == 0 { p + 1 } else { p - 1 };
        p <= self.last && (0..=self.last).contains(&q)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::complex::permutation;

    #[test]
    fn ends_keep_half_stars_and_short_periods_are_refused() {
        let torus = CfkTorus::new(2, &[6]).expect("torus");
        let w = MaterialWindow::new(&torus, 10).expect("2N = 12 ≥ 12");
        assert!(MaterialWindow::new(&torus, 11).is_err());
        assert!(MaterialWindow::new(&torus, 1).is_err());
        assert!(MaterialWindow::new(&CfkTorus::new(3, &[6, 6]).expect("torus"), 4).is_err());
        let (plus, minus) = (permutation(2, 0), permutation(2, 1));
        // p = 0: only the + cell; p = last: only the − cell; inside both.
        assert!(w.contains_cell(&[3, 3], &plus) && !w.contains_cell(&[3, 3], &minus));
        assert!(!w.contains_cell(&[8, -2], &plus) && w.contains_cell(&[8, -2], &minus));
        assert!(w.contains_cell(&[5, 0], &plus) && w.contains_cell(&[5, 0], &minus));
        // Outside points, also across the wrap.
        assert!(!w.contains(&[0, 1]) && !w.contains(&[6, -5]) && w.contains(&[6, -4]));
        assert_eq!(w.unwrap(&[0, 2, 0, 0, 0, 0, 0, 0])[..2], [6, -4]);
        // The representative's material point is v₀ − v₁, and the tests at
        // a known point agree with those from coordinates.
        for v0 in -30..30 {
            for v1 in -30..30 {
                let v = [v0, v1, 0, 0, 0, 0, 0, 0];
                let u = w.unwrap(&v);
                let p = w.unwrapped_point(&u);
                assert_eq!(p, w.material_point(&v), "{v:?}");
                assert_eq!(w.contains_point(p), w.contains(&v));
                for perm in [&plus, &minus] {
                    assert_eq!(w.contains_cell_at(p, perm), w.contains_cell(&v, perm));
                }
            }
        }
    }

    /// A representative shifted by a level's reduction is the
    /// representative of the shifted vertex, for shifts across many wraps
    /// either way (the ends of every range included).
    #[test]
    fn level_reductions_unwrap_as_a_division_does() {
        let torus = CfkTorus::new(2, &[6]).expect("torus");
        let window = MaterialWindow::new(&torus, 10).expect("window");
        for w in (-100..100).chain([i64::MIN / 4, i64::MAX / 4, -(1 << 40) - 5, (1 << 40) + 7]) {
            let level = window.level_reduction(w);
            for v0 in -15..15 {
                for v1 in -15..15 {
                    let u = window.unwrap(&[v0, v1, 0, 0, 0, 0, 0, 0]);
                    let mut shifted = u;
                    shifted[1] += w;
                    assert_eq!(
                        window.unwrap_shifted(&u, level),
                        window.unwrap(&shifted),
                        "u {u:?}, w {w}"
                    );
                }
            }
        }
    }
}
