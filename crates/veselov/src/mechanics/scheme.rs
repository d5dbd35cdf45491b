//! Discrete Lagrangians of Galerkin type: the method description.
//!
//! Every method of the core is one instance of the Galerkin discrete Lagrangian
//! (Marsden & West 2001, §2.6; seed 004 §4.3): the curve on `[t_k, t_k + h]` is the
//! polynomial through control points `Q⁰ = q_k, Q¹, …, Qᵐ = q_{k+1}` placed at
//! `τ = d_0 = 0 < d_1 < … < d_m = 1`, and the action is a quadrature `(bᵢ, cᵢ)`:
//!
//! `L_d(q_k, q_{k+1}) = ext_{Q¹..Q^{m−1}} h Σᵢ bᵢ L(t_k + cᵢh, Σ_ν M_{iν} Q^ν, Σ_ν D_{iν} Q^ν / h)`
//!
//! with `M_{iν} = l_ν(cᵢ)`, `D_{iν} = l'_ν(cᵢ)` the Lagrange basis on the control
//! nodes. The instances:
//!
//! | method | control nodes | quadrature | order |
//! |---|---|---|---|
//! | midpoint | 0, 1 | c = ½ | 2 |
//! | trapezoid | 0, 1 | c = 0, 1, b = ½, ½ | 2 |
//! | α-rule | 0, 1 | c = α | 2 if α = ½, else 1 |
//! | Galerkin Lobatto, s stages | s Lobatto nodes | same nodes | 2s − 2 |
//! | Galerkin Gauss, s stages | s + 1 Lobatto nodes | s Gauss nodes | 2s |
//!
//! Each also records the equivalent partitioned Runge–Kutta tableau (Lobatto
//! IIIA–IIIB, Gauss, and `a = α, ā = 1 − α` for the α-rule), used by the fast path
//! for separable Lagrangians and by the predictor.

use crate::error::{Error, Result};
use crate::tableau::{self, PartitionedTableau};

/// The largest number of stages supported by the built-in families.
pub const MAX_STAGES: usize = 10;

/// Which family a scheme belongs to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// Midpoint rule `L_d = h L((q₀+q₁)/2, (q₁−q₀)/h)`.
    Midpoint,
    /// Trapezoid rule `L_d = h/2 [L(q₀, v) + L(q₁, v)]`, `v = (q₁ − q₀)/h`.
    Trapezoid,
    /// Generalised midpoint `L_d = h L((1−α)q₀ + αq₁, (q₁−q₀)/h)`, `α ∈ [0, 1]`.
    Alpha(f64),
    /// Galerkin with `s` Lobatto nodes (control points and quadrature), order `2s − 2`.
    GalerkinLobatto(usize),
    /// Galerkin with `s` Gauss quadrature nodes and degree-`s` curves, order `2s`.
    GalerkinGauss(usize),
}

impl Method {
    /// Short name, as used in scenario files.
    pub fn name(&self) -> &'static str {
        match self {
            Method::Midpoint => "midpoint",
            Method::Trapezoid => "trapezoid",
            Method::Alpha(_) => "alpha",
            Method::GalerkinLobatto(_) => "galerkin-lobatto",
            Method::GalerkinGauss(_) => "galerkin-gauss",
        }
    }
}

/// A Galerkin discrete Lagrangian: control nodes, quadrature and interpolation
/// matrices, plus the equivalent partitioned Runge–Kutta tableau.
#[derive(Debug, Clone, PartialEq)]
pub struct GalerkinScheme {
    method: Method,
    order: usize,
    control: Vec<f64>,
    nodes: Vec<f64>,
    weights: Vec<f64>,
    /// `values[i * (m+1) + ν] = l_ν(cᵢ)`.
    values: Vec<f64>,
    /// `derivatives[i * (m+1) + ν] = l'_ν(cᵢ)`.
    derivatives: Vec<f64>,
    /// `extrapolation[ν * (m+1) + μ] = l_μ(1 + d_ν)`: predictor from the previous step.
    extrapolation: Vec<f64>,
    prk: PartitionedTableau,
    /// `prk_extrapolation[i * s + j] = l̃_j(1 + c_i)`, Lagrange basis on the quadrature nodes.
    prk_extrapolation: Vec<f64>,
}

fn tab_err(e: impl std::fmt::Display, name: &str, value: String) -> Error {
    Error::InvalidParameter {
        name: name.to_string(),
        value,
        reason: e.to_string(),
    }
}

impl GalerkinScheme {
    /// Build the scheme for `method`.
    pub fn new(method: Method) -> Result<Self> {
        match method {
            Method::Midpoint => Self::two_point(method, &[0.5], &[1.0], 2, 0.5),
            Method::Trapezoid => {
                let prk = tableau::lobatto_iiia_iiib(2).map_err(|e| tab_err(e, "stages", "2".into()))?;
                Self::assemble(method, 2, vec![0.0, 1.0], vec![0.0, 1.0], vec![0.5, 0.5], prk)
            }
            Method::Alpha(alpha) => {
                if !(alpha.is_finite() && (0.0..=1.0).contains(&alpha)) {
                    return Err(Error::InvalidParameter {
                        name: "alpha".into(),
                        value: alpha.to_string(),
                        reason: "α must lie in [0, 1]".into(),
                    });
                }
                let order = if alpha == 0.5 { 2 } else { 1 };
                Self::two_point(method, &[alpha], &[1.0], order, alpha)
            }
            Method::GalerkinLobatto(s) => {
                if !(2..=MAX_STAGES).contains(&s) {
                    return Err(Error::InvalidParameter {
                        name: "stages".into(),
                        value: s.to_string(),
                        reason: format!("Galerkin Lobatto needs 2 ≤ stages ≤ {MAX_STAGES}"),
                    });
                }
                let prk = tableau::lobatto_iiia_iiib(s).map_err(|e| tab_err(e, "stages", s.to_string()))?;
                let nodes = prk.c.clone();
                let weights = prk.b.clone();
                Self::assemble(method, 2 * s - 2, nodes.clone(), nodes, weights, prk)
            }
            Method::GalerkinGauss(s) => {
                if !(1..=MAX_STAGES).contains(&s) {
                    return Err(Error::InvalidParameter {
                        name: "stages".into(),
                        value: s.to_string(),
                        reason: format!("Galerkin Gauss needs 1 ≤ stages ≤ {MAX_STAGES}"),
                    });
                }
                let prk = tableau::gauss(s).map_err(|e| tab_err(e, "stages", s.to_string()))?;
                let control = if s == 1 {
                    vec![0.0, 1.0]
                } else {
                    tableau::gauss_lobatto(s + 1)
                        .map_err(|e| tab_err(e, "stages", s.to_string()))?
                        .nodes
                };
                let (nodes, weights) = (prk.c.clone(), prk.b.clone());
                Self::assemble(method, 2 * s, control, nodes, weights, prk)
            }
        }
    }

    fn two_point(method: Method, c: &[f64], b: &[f64], order: usize, alpha: f64) -> Result<Self> {
        let prk = PartitionedTableau {
            name: method.name().to_string(),
            s: 1,
            order,
            c: c.to_vec(),
            b: b.to_vec(),
            a: vec![alpha],
            a_bar: vec![1.0 - alpha],
        };
        Self::assemble(method, order, vec![0.0, 1.0], c.to_vec(), b.to_vec(), prk)
    }

    fn assemble(
        method: Method,
        order: usize,
        control: Vec<f64>,
        nodes: Vec<f64>,
        weights: Vec<f64>,
        prk: PartitionedTableau,
    ) -> Result<Self> {
        let bad = |e: tableau::TableauError| tab_err(e, "method", method.name().to_string());
        let interp = tableau::lagrange_interpolation(&control, &nodes).map_err(bad)?;
        let shifted: Vec<f64> = control.iter().map(|d| 1.0 + d).collect();
        let extrap = tableau::lagrange_interpolation(&control, &shifted).map_err(bad)?;
        let prk_shifted: Vec<f64> = prk.c.iter().map(|c| 1.0 + c).collect();
        let prk_extrapolation = if prk.s == 1 {
            vec![1.0]
        } else {
            tableau::lagrange_interpolation(&prk.c, &prk_shifted)
                .map_err(bad)?
                .values
        };
        Ok(Self {
            method,
            order,
            control,
            nodes,
            weights,
            values: interp.values,
            derivatives: interp.derivatives,
            extrapolation: extrap.values,
            prk,
            prk_extrapolation,
        })
    }

    /// Midpoint rule.
    pub fn midpoint() -> Self {
        Self::two_point(Method::Midpoint, &[0.5], &[1.0], 2, 0.5).expect("built-in midpoint tables")
    }

    /// The method this scheme implements.
    pub fn method(&self) -> Method {
        self.method
    }
    /// Classical order of the resulting integrator.
    pub fn order(&self) -> usize {
        self.order
    }
    /// Number of control intervals `m` (control points `Q⁰..Qᵐ`).
    pub fn intervals(&self) -> usize {
        self.control.len() - 1
    }
    /// Number of quadrature nodes.
    pub fn quadrature_len(&self) -> usize {
        self.nodes.len()
    }
    /// Control nodes `d_ν` on `[0, 1]`.
    pub fn control_nodes(&self) -> &[f64] {
        &self.control
    }
    /// Quadrature nodes `cᵢ`.
    pub fn quadrature_nodes(&self) -> &[f64] {
        &self.nodes
    }
    /// Quadrature weights `bᵢ`.
    pub fn quadrature_weights(&self) -> &[f64] {
        &self.weights
    }
    /// `l_ν(cᵢ)`.
    #[inline]
    pub fn value(&self, i: usize, nu: usize) -> f64 {
        self.values[i * self.control.len() + nu]
    }
    /// `l'_ν(cᵢ)`.
    #[inline]
    pub fn derivative(&self, i: usize, nu: usize) -> f64 {
        self.derivatives[i * self.control.len() + nu]
    }
    /// `l_μ(1 + d_ν)`: extrapolation of the previous step's curve to this step's control nodes.
    #[inline]
    pub fn extrapolation(&self, nu: usize, mu: usize) -> f64 {
        self.extrapolation[nu * self.control.len() + mu]
    }
    /// The equivalent partitioned Runge–Kutta tableau.
    pub fn tableau(&self) -> &PartitionedTableau {
        &self.prk
    }
    /// `l̃_j(1 + cᵢ)` on the quadrature nodes (stage-value predictor).
    #[inline]
    pub fn stage_extrapolation(&self, i: usize, j: usize) -> f64 {
        self.prk_extrapolation[i * self.prk.s + j]
    }
    /// Human-readable description, e.g. `galerkin-gauss (s = 2, order 4)`.
    pub fn describe(&self) -> String {
        match self.method {
            Method::Alpha(a) => format!("alpha (α = {a}, order {})", self.order),
            Method::GalerkinLobatto(s) | Method::GalerkinGauss(s) => {
                format!("{} (s = {s}, order {})", self.method.name(), self.order)
            }
            _ => format!("{} (order {})", self.method.name(), self.order),
        }
    }
}
