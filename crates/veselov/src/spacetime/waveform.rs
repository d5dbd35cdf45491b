//! Diagnostics of scalar waveforms on 1+1 lattices, for the experiments of
//! seed 002 §5.2: the high-frequency indicator (the largest fourth
//! difference), the amplitude of the even/odd (−1)^i mode, a kink–antikink
//! collision counter, and the two energies the paper prints besides the
//! schemes' own: the footnote-4 energy of the rectangle rule and the Guo
//! energy as printed under (5.15).
//!
//! Values are the physical (unwrapped) field of one level; on periodic and
//! winding lattices the neighbours across the seam carry the seam jump, as in
//! [`crate::spacetime::node_value`].

use crate::spacetime::lattice::Lattice;
use crate::spacetime::potential::ScalarPotential;

/// The value at node `i` (any integer on periodic and winding lattices,
/// `0..N` otherwise), the seam jump added once per wrap ([`Lattice::wrapped`]).
fn value_at(lattice: &Lattice, y: &[f64], i: i64) -> Option<f64> {
    let (k, wraps) = lattice.wrapped(i)?;
    Some(y.get(k)? + lattice.boundary().jump().unwrap_or(0.0) * wraps as f64)
}

/// The high-frequency indicator of seed 002 §5.2 (Figs. 5.9/5.10): the
/// largest fourth difference
/// `max_i |y_{i+2} − 4y_{i+1} + 6y_i − 4y_{i−1} + y_{i−2}|`
/// over the nodes whose stencil lies on the lattice. A smooth waveform gives
/// `k⁴ max|φ_xxxx|`; a sawtooth `a(−1)^i` adds `16a`.
pub fn fourth_difference_max(lattice: &Lattice, y: &[f64]) -> f64 {
    let fourth = |w: [f64; 5]| (w[4] - 4.0 * w[3] + 6.0 * w[2] - 4.0 * w[1] + w[0]).abs();
    let interior = y
        .windows(5)
        .map(|w| fourth([w[0], w[1], w[2], w[3], w[4]]))
        .fold(0.0, f64::max);
    // The (at most four) nodes whose stencil crosses the seam or the ends.
    let n = y.len() as i64;
    let at = |i: i64| value_at(lattice, y, i);
    let seam = [0, 1, n - 2, n - 1]
        .into_iter()
        .filter(|&i| (0..n).contains(&i))
        .filter_map(|i| Some(fourth([at(i - 2)?, at(i - 1)?, at(i)?, at(i + 1)?, at(i + 2)?])))
        .fold(0.0, f64::max);
    interior.max(seam)
}

/// The amplitude `a` of the real Fourier mode `a cos(θ_K i + ψ)` of highest
/// wavenumber `θ_K = 2π⌊N/2⌋/N` in a periodic level: `|ŷ_K|/N` for even
/// `N`, where the mode is the sawtooth `a(−1)^i` of the symmetric rectangle
/// scheme's parasitic solution `(A + Bj)(−1)^{i+j}` (Fig. 5.5), and
/// `2|ŷ_K|/N` for odd `N`, where no such solution exists
/// (`ŷ_K = Σ_i y_i e^{iθ_K i}`). A constant contributes nothing and a smooth
/// waveform only its exponentially small content at that wavenumber.
pub fn highest_mode_amplitude(y: &[f64]) -> f64 {
    let n = y.len();
    if n == 0 {
        return 0.0;
    }
    if n.is_multiple_of(2) {
        let s: f64 = y.chunks_exact(2).map(|p| p[0] - p[1]).sum();
        return s.abs() / n as f64;
    }
    let theta = std::f64::consts::TAU * (n / 2) as f64 / n as f64;
    let (re, im) = y.iter().enumerate().fold((0.0, 0.0), |(re, im), (i, v)| {
        let (s, c) = (theta * i as f64).sin_cos();
        (re + v * c, im + v * s)
    });
    2.0 * re.hypot(im) / n as f64
}

/// Counts the kink–antikink collisions of a sine-Gordon field with no net
/// winding. Between collisions the waveform climbs over a full 2π (a kink
/// and an antikink), so its range `max y − min y` is about 2π; when the two
/// pass through each other the field flattens and the range falls towards
/// 0. A collision is counted when the range falls below π after having been
/// above 3π/2 (hysteresis, so that a dip is counted once), and it is dated by
/// the level of the smallest range within the dip (closest approach).
#[derive(Debug, Clone, PartialEq)]
pub struct CollisionCounter {
    armed: bool,
    in_dip: bool,
    dip_min: f64,
    dip_time: f64,
    times: Vec<f64>,
}

impl Default for CollisionCounter {
    fn default() -> Self {
        Self::new()
    }
}

impl CollisionCounter {
    /// Range below which a collision is under way.
    pub const LOW: f64 = std::f64::consts::PI;
    /// Range above which the solitons are apart again.
    pub const HIGH: f64 = 1.5 * std::f64::consts::PI;

    /// A counter that waits for the solitons to be apart before counting.
    pub fn new() -> Self {
        Self {
            armed: false,
            in_dip: false,
            dip_min: f64::INFINITY,
            dip_time: f64::NAN,
            times: Vec::new(),
        }
    }

    /// Feed the level at time `t`; returns `true` when this level completes
    /// a collision (its range has risen back above [`Self::HIGH`]).
    pub fn observe(&mut self, t: f64, y: &[f64]) -> bool {
        let (lo, hi) = y
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
        let range = hi - lo;
        if self.in_dip {
            if range < self.dip_min {
                self.dip_min = range;
                self.dip_time = t;
            }
            if range > Self::HIGH {
                self.in_dip = false;
                self.armed = true;
                self.times.push(self.dip_time);
                return true;
            }
        } else if range > Self::HIGH {
            self.armed = true;
        } else if self.armed && range < Self::LOW {
            self.in_dip = true;
            self.armed = false;
            self.dip_min = range;
            self.dip_time = t;
        }
        false
    }

    /// Completed collisions.
    pub fn count(&self) -> usize {
        self.times.len()
    }

    /// Times of closest approach of the completed collisions.
    pub fn times(&self) -> &[f64] {
        &self.times
    }
}

/// The footnote-4 energy of seed 002 between levels j (`y_j`) and j+1
/// (`y_j1`), for the rectangle schemes (5.10)/(5.12):
/// `E = k Σ_i [½T² + ½D² − N(ȳ)]` over the cells (i, j) with
/// `T = (y_{i,j+1} − y_ij + y_{i+1,j+1} − y_{i+1,j})/(2h)`,
/// `D = (y_{i+1,j} − y_ij + y_{i+1,j+1} − y_{i,j+1})/(2k)` and `ȳ` the mean of
/// the four corners (cells with a corner off a non-periodic lattice are
/// skipped). The paper draws this energy for every scheme of §5.2, Guo's
/// included (Fig. 5.8).
pub fn rectangle_energy<P: ScalarPotential>(potential: &P, lattice: &Lattice, y_j: &[f64], y_j1: &[f64]) -> f64 {
    let (h, k) = (lattice.dt(), lattice.dx());
    let mut e = 0.0;
    for i in 0..y_j.len() as i64 {
        let corners = (
            value_at(lattice, y_j, i),
            value_at(lattice, y_j, i + 1),
            value_at(lattice, y_j1, i),
            value_at(lattice, y_j1, i + 1),
        );
        if let (Some(a), Some(b), Some(c), Some(d)) = corners {
            let t = (c - a + d - b) / (2.0 * h);
            let x = (b - a + d - c) / (2.0 * k);
            e += 0.5 * (t * t + x * x) - potential.jet(0.25 * (a + b + c + d))[0];
        }
    }
    e * k
}

/// The Guo energy as printed under (5.15) (summation index corrected to i),
/// at level j from levels j−1, j, j+1:
/// `E_j = k Σ_i [½(y_{i,j+1} − y_ij)(y_ij − y_{i,j−1})/h² + ½((y_{i+1,j} − y_ij)/k)² − N(y_ij)]`.
/// Scheme (5.15) does not conserve it exactly (its conserved energy is
/// `E^{j+½}`, see [`crate::spacetime::Scheme::Guo`]); the two differ by O(h²).
pub fn guo_printed_energy<P: ScalarPotential>(
    potential: &P,
    lattice: &Lattice,
    y_jm1: &[f64],
    y_j: &[f64],
    y_j1: &[f64],
) -> f64 {
    let (h, k) = (lattice.dt(), lattice.dx());
    let mut e = 0.0;
    for i in 0..y_j.len() {
        let Some(right) = value_at(lattice, y_j, i as i64 + 1) else {
            continue;
        };
        let x = (right - y_j[i]) / k;
        e += 0.5 * (y_j1[i] - y_j[i]) * (y_j[i] - y_jm1[i]) / (h * h) + 0.5 * x * x - potential.jet(y_j[i])[0];
    }
    e * k
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spacetime::{Boundary, SineGordon};

    #[test]
    fn fourth_difference_of_a_cubic_vanishes_and_of_a_sawtooth_is_sixteen_times_it() {
        let lat = Lattice::new(12, 0.1, 0.05, Boundary::Free).expect("lattice");
        let cubic: Vec<f64> = (0..12).map(|i| f64::from(i).powi(3) - 2.0 * f64::from(i)).collect();
        assert!(fourth_difference_max(&lat, &cubic) < 1e-9);
        let periodic = Lattice::new(12, 0.1, 0.05, Boundary::Periodic).expect("lattice");
        let saw: Vec<f64> = (0..12).map(|i| if i % 2 == 0 { 0.25 } else { -0.25 }).collect();
        assert!((fourth_difference_max(&periodic, &saw) - 16.0 * 0.25).abs() < 1e-14);
        assert!((highest_mode_amplitude(&saw) - 0.25).abs() < 1e-15);
        // Odd N: a constant is invisible, the highest real mode is measured
        // with its amplitude.
        let theta = std::f64::consts::TAU * 6.0 / 13.0;
        let odd: Vec<f64> = (0..13)
            .map(|i| 3.0 + 0.5 * (theta * f64::from(i) + 0.3).cos())
            .collect();
        assert!((highest_mode_amplitude(&odd) - 0.5).abs() < 1e-14);
        assert!(highest_mode_amplitude(&[2.0; 13]) < 1e-14);
        assert_eq!(highest_mode_amplitude(&[]), 0.0);
        // A winding ramp is smooth across the seam.
        let wind = Lattice::new(12, 0.1, 0.05, Boundary::Winding { jump: 12.0 }).expect("lattice");
        let ramp: Vec<f64> = (0..12).map(f64::from).collect();
        assert!(fourth_difference_max(&wind, &ramp) < 1e-12);
    }

    #[test]
    fn counter_counts_each_dip_once_and_dates_its_bottom() {
        let mut c = CollisionCounter::new();
        let level = |range: f64| vec![0.0, range];
        // Starts inside a dip (not armed): not counted.
        for (t, r) in [(0.0, 1.0), (1.0, 6.0), (2.0, 3.0), (3.0, 0.5), (4.0, 0.2), (5.0, 2.0)] {
            assert!(!c.observe(t, &level(r)));
        }
        // Wobbles between π and 3π/2 do not complete it.
        assert!(!c.observe(6.0, &level(4.0)));
        assert!(c.observe(7.0, &level(6.2)));
        assert_eq!(c.times(), &[4.0]);
        assert!(!c.observe(8.0, &level(3.0)));
        assert_eq!(c.count(), 1);
    }

    #[test]
    fn printed_guo_energy_of_a_resting_vacuum_is_minus_the_potential() {
        let lat = Lattice::periodic(10, 10.0, 4.0).expect("lattice");
        let y = vec![0.0; 10];
        assert!((guo_printed_energy(&SineGordon, &lat, &y, &y, &y) + 10.0).abs() < 1e-12);
        assert!((rectangle_energy(&SineGordon, &lat, &y, &y) + 10.0).abs() < 1e-12);
    }
}
