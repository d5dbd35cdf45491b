//! Starting values of a variable step from the steps before it.
//!
//! The SEM step solves for `(q_{k+1}, h_k)` (note 001 §2.2). Along a run the
//! points `(t_j, q_j)` are samples of a smooth curve and the steps `h_j` a
//! smooth sequence, so the interpolation polynomial through the last three
//! points gives the velocity at `t_k` to `O(h²)` and the position at
//! `t_k + h` to `O(h³)`, and the linear extrapolation
//! `h ≈ h_{k−1} + (h_{k−1} − h_{k−2})` the step to `O(h²)` relative.

use nalgebra::SVector;

use crate::mechanics::state::continues;

/// `q(t_k + s) = q + s d₁ + s(s + h₁) d₂`.
struct Interpolant<const N: usize> {
    q: SVector<f64, N>,
    d1: SVector<f64, N>,
    d2: SVector<f64, N>,
    h1: f64,
}

/// The last (up to three) points `(t_j, q_j)` of a run, oldest first.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct StepHistory<const N: usize> {
    times: [f64; 3],
    points: [SVector<f64, N>; 3],
    len: usize,
}

impl<const N: usize> Default for StepHistory<N> {
    fn default() -> Self {
        Self {
            times: [0.0; 3],
            points: [SVector::zeros(); 3],
            len: 0,
        }
    }
}

impl<const N: usize> StepHistory<N> {
    /// Whether the newest point is `(t, q)`: the next step continues this history.
    pub(super) fn continues(&self, t: f64, q: &SVector<f64, N>) -> bool {
        self.len > 0 && continues(self.times[self.len - 1], &self.points[self.len - 1], t, q)
    }

    /// Forget every point.
    pub(super) fn clear(&mut self) {
        self.len = 0;
    }

    /// Append `(t, q)`, dropping the oldest point beyond three.
    pub(super) fn push(&mut self, t: f64, q: SVector<f64, N>) {
        if self.len == 3 {
            self.times.rotate_left(1);
            self.points.rotate_left(1);
            self.len = 2;
        }
        self.times[self.len] = t;
        self.points[self.len] = q;
        self.len += 1;
    }

    /// The predicted step: `h_{k−1} + (h_{k−1} − h_{k−2})` kept within
    /// `[½, 2]·h_{k−1}`, or `h_{k−1}` when only one earlier step is known.
    /// `None` with fewer than two points.
    pub(super) fn step(&self) -> Option<f64> {
        let t = &self.times;
        match self.len {
            2 => Some(t[1] - t[0]),
            3 => {
                let (h1, h2) = (t[2] - t[1], t[1] - t[0]);
                Some((2.0 * h1 - h2).clamp(0.5 * h1, 2.0 * h1))
            }
            _ => None,
        }
    }

    /// The interpolation polynomial through the points held (Newton's
    /// divided differences); `None` with fewer than two points.
    fn polynomial(&self) -> Option<Interpolant<N>> {
        let (t, q) = (&self.times, &self.points);
        let newest = self.len.checked_sub(1).filter(|&n| n > 0)?;
        let h1 = t[newest] - t[newest - 1];
        let d1 = (q[newest] - q[newest - 1]) / h1;
        let d2 = if newest == 2 {
            (d1 - (q[1] - q[0]) / (t[1] - t[0])) / (t[2] - t[0])
        } else {
            SVector::zeros()
        };
        Some(Interpolant {
            q: q[newest],
            d1,
            d2,
            h1,
        })
    }

    /// The predicted position at `t_k + h`, or `None` with fewer than two points.
    pub(super) fn position(&self, h: f64) -> Option<SVector<f64, N>> {
        let p = self.polynomial()?;
        Some(p.q + p.d1 * h + p.d2 * (h * (h + p.h1)))
    }

    /// The velocity at `t_k`, or `None` with fewer than two points.
    pub(super) fn velocity(&self) -> Option<SVector<f64, N>> {
        let p = self.polynomial()?;
        Some(p.d1 + p.d2 * p.h1)
    }

    /// Checkpoint words: the count, then three `(t, q)` records.
    pub(super) fn save(&self, out: &mut Vec<f64>) {
        out.push(self.len as f64);
        for (t, q) in self.times.iter().zip(&self.points) {
            out.push(*t);
            out.extend(q.iter());
        }
    }

    /// Restore what [`StepHistory::save`] wrote.
    pub(super) fn restore(&mut self, words: &mut crate::run::Words<'_>) -> crate::Result<()> {
        let len = words.one()?;
        if !(0.0..=3.0).contains(&len) || len.fract() != 0.0 {
            return Err(crate::Error::InvalidParameter {
                name: "checkpoint".into(),
                value: len.to_string(),
                reason: "SEM step history must hold 0 to 3 points".into(),
            });
        }
        self.len = len as usize;
        for j in 0..3 {
            self.times[j] = words.one()?;
            self.points[j] = SVector::from_column_slice(words.take(N)?);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector1;

    /// The three-point polynomial is exact for quadratics, on uneven steps.
    #[test]
    fn three_points_reproduce_a_quadratic() {
        let f = |t: f64| Vector1::new(1.0 - 2.0 * t + 3.0 * t * t);
        let mut hist = StepHistory::<1>::default();
        for t in [0.1, 0.25, 0.3] {
            hist.push(t, f(t));
        }
        let p = hist.position(0.07).expect("three points");
        assert!((p[0] - f(0.37)[0]).abs() < 1e-14, "{p:?}");
        let v = hist.velocity().expect("three points");
        assert!((v[0] - (-2.0 + 6.0 * 0.3)).abs() < 1e-13, "{v:?}");
        // h₁ = 0.05, h₂ = 0.15: 2h₁ − h₂ < 0 is kept at h₁/2.
        assert_eq!(hist.step(), Some(0.5 * (0.3 - 0.25)));
        hist.push(0.37, f(0.37));
        assert!(hist.continues(0.37, &f(0.37)));
        assert!(!hist.continues(0.3, &f(0.3)));
    }
}
