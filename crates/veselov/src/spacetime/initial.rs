//! Initial data (levels `j = 0, 1`) for the scalar schemes: the periodic
//! sine-Gordon kink–antikink of seed 002 §5.2, a single kink, the breather and
//! d'Alembert data for the wave equation. Where the exact solution is known,
//! level 1 is the exact solution at `t = h` (second-order-accurate start).

use std::f64::consts::{PI, TAU};

use nalgebra::SVector;

use crate::error::invalid;
use crate::error::{Error, Result};
use crate::spacetime::lattice::Lattice;
use crate::special::{complete_elliptic_k_complement, jacobi_elliptic_complement};

/// The exact periodic travelling kink of sine-Gordon on a circle of
/// circumference `L̃` with winding 2π (note 002 §2.2):
/// `φ̃(x) = π + 2·am(u − K(κ); κ)`, `u = x/(κ√(1−c²))`, modulus `κ = 1 − ε`
/// (parameter `m = κ²`), `P = 2K(κ)`, speed `c = √(1 − L̃²/(κ²P²))`.
/// `φ̃(0) = 0`, `φ̃(L̃) = 2π`, centred at `L̃/2`; `φ̃(x − ct)` solves
/// `φ_tt − φ_xx + sin φ = 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PeriodicKink {
    /// Circumference `L̃` of the kink's circle.
    pub period: f64,
    /// Modulus `κ`.
    pub kappa: f64,
    m1: f64,
    k: f64,
    /// Speed `c`.
    pub speed: f64,
    scale: f64,
}

fn special(e: crate::special::SpecialError) -> Error {
    invalid("kink data", e.to_string(), "special-function evaluation failed")
}

impl PeriodicKink {
    /// Kink of period `period` with modulus `κ = 1 − epsilon`.
    ///
    /// # Errors
    /// `period` or `epsilon` out of range (`0 < ε < 1`, `period > 0` and
    /// small enough that `c` is real).
    pub fn new(period: f64, epsilon: f64) -> Result<Self> {
        if !(period.is_finite() && period > 0.0) {
            return Err(invalid("period", period, "must be positive and finite"));
        }
        if !(epsilon > 0.0 && epsilon < 1.0) {
            return Err(invalid("epsilon", epsilon, "need 0 < ε < 1 (κ = 1 − ε)"));
        }
        let kappa = 1.0 - epsilon;
        let m1 = epsilon * (2.0 - epsilon); // 1 − κ²
        let k = complete_elliptic_k_complement(m1).map_err(special)?;
        let p = 2.0 * k;
        let s = period / (kappa * p); // √(1 − c²)
        if s >= 1.0 {
            return Err(invalid(
                "period",
                period,
                "too long for this ε: the kink speed would be imaginary",
            ));
        }
        Ok(Self {
            period,
            kappa,
            m1,
            k,
            speed: (1.0 - s * s).sqrt(),
            scale: kappa * s,
        })
    }
    /// `P = 2K(κ)`.
    pub fn p(&self) -> f64 {
        2.0 * self.k
    }
    /// `φ̃(x)` (any real `x`; `φ̃(x + L̃) = φ̃(x) + 2π`).
    pub fn profile(&self, x: f64) -> Result<f64> {
        let u = x / self.scale - self.k;
        Ok(PI + 2.0 * jacobi_elliptic_complement(u, self.m1).map_err(special)?.am)
    }
}

/// Initial data of a scalar field.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum InitialData {
    /// Seed 002 §5.2: kink at `L/8`, antikink at `7L/8` on the circle of
    /// length `L` (the lattice length; 40 in the paper), each the
    /// [`PeriodicKink`] of period `L/4` with `κ = 1 − epsilon`.
    /// Level 1: `paper_start = false` takes the exact travelling shifts of both
    /// solitons; `true` the paper's `y_{i1} = y_{i0} + hφ̇` (first order for the
    /// antikink).
    KinkAntikink {
        /// `ε` in `κ = 1 − ε` (paper: 10⁻⁶).
        epsilon: f64,
        /// Use the paper's first-order second level.
        paper_start: bool,
    },
    /// A sine-Gordon kink `4·arctan(exp(γ(x − x0 − ct)))` (use a winding
    /// boundary with jump 2π).
    Kink {
        /// Initial position.
        x0: f64,
        /// Speed `c`, `|c| < 1`.
        speed: f64,
    },
    /// The sine-Gordon breather
    /// `4·arctan((√(1−ω²)/ω)·sin(ωt)/cosh(√(1−ω²)(x − x0)))`.
    Breather {
        /// Frequency `0 < ω < 1`.
        omega: f64,
        /// Centre.
        x0: f64,
    },
    /// Wave equation (`N = 0`): `φ = ½(f(x − t) + f(x + t)) + v t`,
    /// `f(x) = A·exp(sin(2π m x/L))` (`L` the lattice length), plus a uniform
    /// drift `v t`.
    DAlembert {
        /// Amplitude `A`.
        amplitude: f64,
        /// Mode number `m ≥ 1`.
        mode: u32,
        /// Uniform velocity `v`.
        drift: f64,
    },
}

impl InitialData {
    fn validate(&self) -> Result<()> {
        match *self {
            InitialData::Kink { speed, x0 } => {
                if speed.is_nan() || speed.abs() >= 1.0 {
                    return Err(invalid("speed", speed, "need |c| < 1"));
                }
                if !x0.is_finite() {
                    return Err(invalid("x0", x0, "must be finite"));
                }
            }
            InitialData::Breather { omega, x0 } => {
                if !(omega > 0.0 && omega < 1.0) {
                    return Err(invalid("omega", omega, "need 0 < ω < 1"));
                }
                if !x0.is_finite() {
                    return Err(invalid("x0", x0, "must be finite"));
                }
            }
            InitialData::DAlembert {
                amplitude, mode, drift, ..
            } => {
                if !(amplitude.is_finite() && drift.is_finite()) {
                    return Err(invalid("amplitude", amplitude, "amplitude and drift must be finite"));
                }
                if mode == 0 {
                    return Err(invalid("mode", mode, "must be ≥ 1"));
                }
            }
            InitialData::KinkAntikink { .. } => {}
        }
        Ok(())
    }

    /// The exact solution at time `t` on the lattice nodes, where known
    /// (`None` for the kink–antikink pair).
    ///
    /// # Errors
    /// Invalid parameters (named).
    pub fn exact(&self, lattice: &Lattice, t: f64) -> Result<Option<Vec<f64>>> {
        self.validate()?;
        let n = lattice.nodes();
        let xs = (0..n).map(|i| lattice.x(i));
        Ok(match *self {
            InitialData::KinkAntikink { .. } => None,
            InitialData::Kink { x0, speed } => {
                let g = 1.0 / (1.0 - speed * speed).sqrt();
                Some(xs.map(|x| 4.0 * (g * (x - x0 - speed * t)).exp().atan()).collect())
            }
            InitialData::Breather { omega, x0 } => {
                let s = (1.0 - omega * omega).sqrt();
                Some(
                    xs.map(|x| 4.0 * (s / omega * (omega * t).sin() / (s * (x - x0)).cosh()).atan())
                        .collect(),
                )
            }
            InitialData::DAlembert { amplitude, mode, drift } => {
                let w = TAU * f64::from(mode) / lattice.length();
                let f = |x: f64| amplitude * (w * x).sin().exp();
                Some(xs.map(|x| 0.5 * (f(x - t) + f(x + t)) + drift * t).collect())
            }
        })
    }

    /// Levels `j = 0` and `j = 1`.
    ///
    /// # Errors
    /// Invalid parameters (named), or special-function failures.
    pub fn levels(&self, lattice: &Lattice) -> Result<(Vec<f64>, Vec<f64>)> {
        self.validate()?;
        let h = lattice.dt();
        if let InitialData::KinkAntikink { epsilon, paper_start } = *self {
            let l = lattice.length();
            let q = l / 4.0;
            let kink = PeriodicKink::new(q, epsilon)?;
            let c = kink.speed;
            let field = |x: f64, shift_kink: f64, shift_anti: f64| -> Result<f64> {
                let x = x.rem_euclid(l);
                Ok(if x < q {
                    kink.profile(x - shift_kink)?
                } else if x < 3.0 * q {
                    TAU
                } else {
                    TAU - kink.profile(x - 3.0 * q + shift_anti)?
                })
            };
            let n = lattice.nodes();
            let mut y0 = Vec::with_capacity(n);
            let mut y1 = Vec::with_capacity(n);
            for i in 0..n {
                let x = lattice.x(i);
                let v0 = field(x, 0.0, 0.0)?;
                y0.push(v0);
                let xm = x.rem_euclid(l);
                let v1 = if paper_start && xm >= 3.0 * q {
                    // y_{i1} = y_{i0} + hφ̇, φ̇ = −(φ(x − hc) − φ(x))/h
                    2.0 * v0 - field(x, 0.0, -c * h)?
                } else {
                    field(x, c * h, c * h)?
                };
                y1.push(v1);
            }
            return Ok((y0, y1));
        }
        match (self.exact(lattice, 0.0)?, self.exact(lattice, h)?) {
            (Some(a), Some(b)) => Ok((a, b)),
            _ => Err(invalid(
                "initial data",
                format!("{self:?}"),
                "no exact solution available",
            )),
        }
    }

    /// The soliton speed of the kink–antikink data (`None` otherwise).
    ///
    /// # Errors
    /// Invalid parameters.
    pub fn kink_antikink_speed(&self, lattice: &Lattice) -> Result<Option<f64>> {
        match *self {
            InitialData::KinkAntikink { epsilon, .. } => {
                Ok(Some(PeriodicKink::new(lattice.length() / 4.0, epsilon)?.speed))
            }
            _ => Ok(None),
        }
    }
}

/// Two consecutive levels (j = 0, 1) of a vector field.
pub type Levels<const DIM: usize> = (Vec<SVector<f64, DIM>>, Vec<SVector<f64, DIM>>);

/// The travelling plane wave φ = A (cos(κx − ωt), sin(κx − ωt)) of the
/// complex Klein–Gordon equation φ_tt − φ_xx + (m² + λ|φ|²)φ = 0
/// ([`ComplexKleinGordon`](crate::spacetime::ComplexKleinGordon)): |φ| = A is constant,
/// so it is an exact solution when ω² = κ² + m² + λA², κ = 2π·mode/L.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ComplexPlaneWave {
    /// Amplitude A.
    pub amplitude: f64,
    /// Mode number (κ = 2π·mode/L; may be negative or zero).
    pub mode: i32,
    /// m².
    pub m2: f64,
    /// λ.
    pub lambda: f64,
}

impl ComplexPlaneWave {
    /// ω = √(κ² + m² + λA²) for the lattice length L.
    ///
    /// # Errors
    /// Non-finite parameters or ω² ≤ 0 (named).
    pub fn omega(&self, lattice: &Lattice) -> Result<f64> {
        for (name, v) in [("amplitude", self.amplitude), ("m2", self.m2), ("lambda", self.lambda)] {
            if !v.is_finite() {
                return Err(invalid(name, v, "must be finite"));
            }
        }
        let kappa = TAU * f64::from(self.mode) / lattice.length();
        let w2 = kappa * kappa + self.m2 + self.lambda * self.amplitude * self.amplitude;
        if w2 > 0.0 {
            Ok(w2.sqrt())
        } else {
            Err(invalid(
                "m2",
                self.m2,
                "κ² + m² + λA² must be positive for a travelling plane wave",
            ))
        }
    }

    /// The exact field at time t on the nodes.
    ///
    /// # Errors
    /// As [`omega`](Self::omega).
    pub fn exact(&self, lattice: &Lattice, t: f64) -> Result<Vec<SVector<f64, 2>>> {
        let w = self.omega(lattice)?;
        let kappa = TAU * f64::from(self.mode) / lattice.length();
        Ok((0..lattice.nodes())
            .map(|i| {
                let phase = kappa * lattice.x(i) - w * t;
                SVector::<f64, 2>::new(phase.cos(), phase.sin()) * self.amplitude
            })
            .collect())
    }

    /// Levels j = 0 and j = 1 (the exact solution at t = 0 and t = dt).
    ///
    /// # Errors
    /// As [`omega`](Self::omega).
    pub fn levels(&self, lattice: &Lattice) -> Result<Levels<2>> {
        Ok((self.exact(lattice, 0.0)?, self.exact(lattice, lattice.dt())?))
    }
}
