//! Quadrature rules and Runge–Kutta tableaux for Galerkin variational integrators.
//!
//! Everything lives on the unit interval `[0, 1]` and is computed in double-double
//! arithmetic (about 106 significant bits); each coefficient is rounded to `f64` once,
//! at the very end, so the results are correct to the last bit or two.
//!
//! # Construction
//!
//! **Legendre polynomials** on `x ∈ [-1, 1]` come from the three-term recurrence
//! `(k+1) P_{k+1} = (2k+1) x P_k − k P_{k−1}`, with derivatives from
//! `P'_{k+1} = P'_{k−1} + (2k+1) P_k` and `P''_{k+1} = P''_{k−1} + (2k+1) P'_k`.
//! Roots are found by Newton's method in double-double, started from the classical
//! `f64` guesses `x ≈ −cos(π(i + 3/4)/(s + 1/2))` (roots of `P_s`) and
//! `x ≈ −cos(π i/(s − 1))` (roots of `P'_{s−1}`); only the negative half is solved
//! for and mirrored, so the rules are exactly symmetric. Nodes map by `t = (1 + x)/2`.
//!
//! * **Gauss–Legendre**, `s` nodes, degree `2s − 1`: `P_s(x_i) = 0`,
//!   `w_i = 1 / ((1 − x_i²) P'_s(x_i)²)` (already halved for `[0, 1]`).
//! * **Gauss–Lobatto**, `s ≥ 2` nodes, degree `2s − 3`: `x = ±1` and `P'_{s−1}(x_i) = 0`,
//!   `w_i = 1 / (s(s − 1) P_{s−1}(x_i)²)`, end weights `1 / (s(s − 1))`.
//!
//! **Collocation.** With `l_j` the Lagrange basis on the nodes `c`,
//! `a_ij = ∫_0^{c_i} l_j(t) dt = c_i Σ_k ω_k l_j(c_i τ_k)`, where `(τ_k, ω_k)` is the
//! `q = ⌊s/2⌋ + 1` point Gauss–Legendre rule, exact since `2q − 1 ≥ s − 1 = deg l_j`.
//! The basis is evaluated in product form `l_j(t) = Π_{k≠j} (t − c_k)/(c_j − c_k)`,
//! never through monomial coefficients, and always from the double-double nodes.
//!
//! **Tableaux.** Gauss: `a = ā` is the collocation matrix on the Gauss nodes (order `2s`).
//! Lobatto IIIA–IIIB (order `2s − 2`): `a` is the collocation matrix on the Lobatto nodes
//! (its last row is `∫_0^1 l_j = b_j`) and `ā_ij = b_j (1 − a_ji / b_i)`, which makes the
//! pair symplectic: `b_i ā_ij + b_j a_ji − b_i b_j = 0`.
//!
//! **Interpolation.** `l_ν'(t) = Σ_{m≠ν} Π_{k≠ν,m} (t − d_k) / Π_{k≠ν} (d_ν − d_k)`,
//! accumulated by the product rule.

use std::f64::consts::PI;
use std::fmt;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// Largest number of nodes accepted by the built-in rules and tableaux.
const MAX_NODES: usize = 20;

/// Invalid input to a function of this module: which argument, its value, and why.
///
/// Displayed as `name = value: reason`, e.g. `nodes[1] = NaN: points must be finite`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TableauError {
    /// The offending argument, e.g. `"s"` or `"nodes[1]"`.
    pub name: String,
    /// Its value, as text.
    pub value: String,
    /// Why it is rejected.
    pub reason: String,
}

impl TableauError {
    fn new(name: impl Into<String>, value: impl fmt::Debug, reason: impl Into<String>) -> Self {
        let (name, value, reason) = (name.into(), format!("{value:?}"), reason.into());
        Self { name, value, reason }
    }
}

impl fmt::Display for TableauError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} = {}: {}", self.name, self.value, self.reason)
    }
}

impl std::error::Error for TableauError {}

/// Unevaluated sum `hi + lo` with `|lo| ≤ ulp(hi)/2`: about 106 significant bits.
///
/// Built on the error-free transformations two-sum (Knuth) and two-product (one fused
/// multiply–add). The module needs only `+ − × ÷` on a few thousand numbers, which these
/// give in a few dozen lines; no well-kept pure-Rust crate is needed for such a small need.
#[derive(Debug, Clone, Copy, PartialEq)]
struct DoubleDouble {
    hi: f64,
    lo: f64,
}

type Dd = DoubleDouble;

/// `a + b = s + e` exactly.
fn two_sum(a: f64, b: f64) -> Dd {
    let s = a + b;
    let bb = s - a;
    Dd::new(s, (a - (s - bb)) + (b - bb))
}

/// `a + b = s + e` exactly, provided `|a| ≥ |b|`.
fn quick_two_sum(a: f64, b: f64) -> Dd {
    let s = a + b;
    Dd::new(s, b - (s - a))
}

/// `a · b = p + e` exactly.
fn two_prod(a: f64, b: f64) -> Dd {
    let p = a * b;
    Dd::new(p, a.mul_add(b, -p))
}

impl DoubleDouble {
    const ZERO: Self = Self::new(0.0, 0.0);
    const ONE: Self = Self::new(1.0, 0.0);

    const fn new(hi: f64, lo: f64) -> Self {
        Self { hi, lo }
    }

    /// Nearest `f64`.
    fn to_f64(self) -> f64 {
        self.hi + self.lo
    }

    /// Square root: one Newton correction of the `f64` root (Karp's method).
    #[cfg(test)]
    fn sqrt(self) -> Self {
        let x = 1.0 / self.hi.sqrt();
        let ax = self.hi * x;
        two_sum(ax, (self - two_prod(ax, ax)).hi * (x * 0.5))
    }
}

impl From<f64> for Dd {
    fn from(x: f64) -> Self {
        Self::new(x, 0.0)
    }
}

impl Neg for Dd {
    type Output = Self;
    fn neg(self) -> Self {
        Self::new(-self.hi, -self.lo)
    }
}

impl Add for Dd {
    type Output = Self;
    fn add(self, rhs: Self) -> Self {
        let (s, t) = (two_sum(self.hi, rhs.hi), two_sum(self.lo, rhs.lo));
        let u = quick_two_sum(s.hi, s.lo + t.hi);
        quick_two_sum(u.hi, u.lo + t.lo)
    }
}

impl Sub for Dd {
    type Output = Self;
    fn sub(self, rhs: Self) -> Self {
        self + (-rhs)
    }
}

impl Mul for Dd {
    type Output = Self;
    fn mul(self, rhs: Self) -> Self {
        let p = two_prod(self.hi, rhs.hi);
        quick_two_sum(p.hi, p.lo + (self.hi * rhs.lo + self.lo * rhs.hi))
    }
}

impl Div for Dd {
    type Output = Self;
    fn div(self, rhs: Self) -> Self {
        let q1 = self.hi / rhs.hi;
        let r = self - rhs * q1.into();
        let q2 = r.hi / rhs.hi;
        let q3 = (r - rhs * q2.into()).hi / rhs.hi;
        quick_two_sum(q1, q2) + q3.into()
    }
}

/// Nodes and weights on [0, 1].
#[derive(Debug, Clone, PartialEq)]
pub struct Quadrature {
    /// Nodes in increasing order.
    pub nodes: Vec<f64>,
    /// Weights, one per node.
    pub weights: Vec<f64>,
}

impl Quadrature {
    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Whether the rule has no nodes.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Polynomial degree integrated exactly: `2n − 1` for Gauss–Legendre, `2n − 3` for
    /// Gauss–Lobatto (`n` nodes).
    ///
    /// This is the largest degree any `n`-point rule can reach given which end points of
    /// `[0, 1]` it uses as nodes (each costs one degree), attained by the rules of this
    /// module; for a hand-made rule it is an upper bound. 0 for an empty rule.
    pub fn degree(&self) -> usize {
        let ends = [0.0, 1.0].iter().filter(|e| self.nodes.contains(e)).count();
        (2 * self.len()).saturating_sub(1 + ends)
    }
}

/// `(P_n(x), P'_n(x), P''_n(x))` for `n ≥ 1` by the three-term recurrences.
fn legendre(n: usize, x: Dd) -> (Dd, Dd, Dd) {
    let (mut p0, mut p1, mut d0, mut d1, mut e0, mut e1) = (Dd::ONE, x, Dd::ZERO, Dd::ONE, Dd::ZERO, Dd::ZERO);
    for k in 1..n {
        let (k, odd) = (k as f64, Dd::from((2 * k + 1) as f64));
        let p2 = (odd * x * p1 - Dd::from(k) * p0) / (k + 1.0).into();
        (p0, p1, d0, d1, e0, e1) = (p1, p2, d1, d0 + odd * p1, e1, e0 + odd * d1);
    }
    (p1, d1, e1)
}

/// Root of `P_n` (`derivative = false`) or of `P'_n` by Newton's method in double-double.
fn legendre_root(n: usize, guess: f64, derivative: bool) -> Option<Dd> {
    let mut x = Dd::from(guess);
    for _ in 0..60 {
        let (p, dp, d2p) = legendre(n, x);
        let (f, df) = if derivative { (dp, d2p) } else { (p, dp) };
        let dx = f / df;
        if !dx.hi.is_finite() {
            break;
        }
        x = x - dx;
        if dx.hi.abs() < 1e-25 {
            return Some(x);
        }
    }
    None
}

/// Error for a Newton iteration that failed or found misplaced nodes (not expected).
fn no_convergence(family: &str, s: usize) -> TableauError {
    TableauError::new("s", s, format!("Newton iteration for the {family} nodes failed"))
}

/// Checks the supported range of a family.
fn check_stages(family: &str, s: usize, min: usize) -> Result<(), TableauError> {
    if (min..=MAX_NODES).contains(&s) {
        return Ok(());
    }
    let reason = format!("{family} needs {min} ≤ s ≤ {MAX_NODES}");
    Err(TableauError::new("s", s, reason))
}

/// Checks that the nodes on `[-1, 1]` are increasing and maps them to `t = (1 + x)/2`.
fn to_unit_interval(x: &[Dd], family: &str) -> Result<Vec<Dd>, TableauError> {
    if x.windows(2).any(|p| (p[1] - p[0]).hi <= 0.0) || x.iter().any(|v| v.hi.abs() > 1.0) {
        return Err(no_convergence(family, x.len()));
    }
    Ok(x.iter().map(|&v| (Dd::ONE + v) * 0.5.into()).collect())
}

/// Gauss–Legendre rule on `[0, 1]` in double-double (any `s ≥ 1`).
fn gauss_dd(s: usize) -> Result<(Vec<Dd>, Vec<Dd>), TableauError> {
    let mut x = vec![Dd::ZERO; s];
    for i in 0..s / 2 {
        let guess = -(PI * (i as f64 + 0.75) / (s as f64 + 0.5)).cos();
        let root = legendre_root(s, guess, false).ok_or_else(|| no_convergence("Gauss–Legendre", s))?;
        (x[i], x[s - 1 - i]) = (root, -root);
    }
    let mut w = vec![Dd::ZERO; s];
    for i in 0..s.div_ceil(2) {
        let dp = legendre(s, x[i]).1;
        w[i] = Dd::ONE / ((Dd::ONE - x[i] * x[i]) * dp * dp);
        w[s - 1 - i] = w[i];
    }
    Ok((to_unit_interval(&x, "Gauss–Legendre")?, w))
}

/// Gauss–Lobatto rule on `[0, 1]` in double-double (any `s ≥ 2`).
fn lobatto_dd(s: usize) -> Result<(Vec<Dd>, Vec<Dd>), TableauError> {
    let n = s - 1;
    let mut x = vec![Dd::ZERO; s];
    (x[0], x[n]) = (-Dd::ONE, Dd::ONE);
    for i in 1..=(s - 2) / 2 {
        let guess = -(PI * i as f64 / n as f64).cos();
        let root = legendre_root(n, guess, true).ok_or_else(|| no_convergence("Gauss–Lobatto", s))?;
        (x[i], x[n - i]) = (root, -root);
    }
    let scale = Dd::from((s * n) as f64);
    let mut w = vec![Dd::ONE / scale; s];
    for i in 1..s.div_ceil(2) {
        let p = legendre(n, x[i]).0;
        w[i] = Dd::ONE / (scale * p * p);
        w[n - i] = w[i];
    }
    Ok((to_unit_interval(&x, "Gauss–Lobatto")?, w))
}

/// `(l_j(t), l_j'(t))` for the Lagrange basis on distinct `nodes`, in product form; the
/// derivative is accumulated by the product rule.
fn lagrange(nodes: &[Dd], j: usize, t: Dd) -> (Dd, Dd) {
    let (mut p, mut dp, mut denominator) = (Dd::ONE, Dd::ZERO, Dd::ONE);
    for (_, &d) in nodes.iter().enumerate().filter(|&(k, _)| k != j) {
        (p, dp, denominator) = (p * (t - d), dp * (t - d) + p, denominator * (nodes[j] - d));
    }
    (p / denominator, dp / denominator)
}

/// Collocation matrix `a_ij = ∫_0^{c_i} l_j` in double-double (row-major).
fn collocation_dd(c: &[Dd]) -> Result<Vec<Dd>, TableauError> {
    let s = c.len();
    let (tau, omega) = gauss_dd(s / 2 + 1)?;
    let mut a = vec![Dd::ZERO; s * s];
    for (i, &ci) in c.iter().enumerate() {
        for j in 0..s {
            let terms = tau.iter().zip(&omega).map(|(&t, &w)| w * lagrange(c, j, ci * t).0);
            a[i * s + j] = ci * terms.fold(Dd::ZERO, Add::add);
        }
    }
    Ok(a)
}

/// Rounds to `f64`.
fn round(v: &[Dd]) -> Vec<f64> {
    v.iter().map(|x| x.to_f64()).collect()
}

/// Rounds a double-double rule to `f64`.
fn rounded_rule((t, w): (Vec<Dd>, Vec<Dd>)) -> Quadrature {
    Quadrature {
        nodes: round(&t),
        weights: round(&w),
    }
}

/// Rounds to `f64`, rejecting results that overflowed for badly scaled `points`.
fn round_finite(v: &[Dd], name: &str, points: &[f64]) -> Result<Vec<f64>, TableauError> {
    let r = round(v);
    if r.iter().all(|x| x.is_finite()) {
        return Ok(r);
    }
    let reason = "badly scaled points: coefficients overflow";
    Err(TableauError::new(name, points, reason))
}

/// Checks that points are finite and, if `distinct`, non-empty and pairwise distinct.
fn validate(name: &str, xs: &[f64], distinct: bool) -> Result<Vec<Dd>, TableauError> {
    if distinct && xs.is_empty() {
        return Err(TableauError::new(name, xs, "at least one point is required"));
    }
    for (i, &x) in xs.iter().enumerate() {
        if !x.is_finite() {
            return Err(TableauError::new(format!("{name}[{i}]"), x, "points must be finite"));
        }
        if let Some(k) = xs[..i].iter().position(|&y| distinct && y == x) {
            let reason = format!("repeats {name}[{k}]; points must be distinct");
            return Err(TableauError::new(format!("{name}[{i}]"), x, reason));
        }
    }
    Ok(xs.iter().map(|&x| Dd::from(x)).collect())
}

/// Gauss–Legendre rule with `s` nodes (`1 ≤ s ≤ 20`) on `[0, 1]`, degree `2s − 1`;
/// the nodes are the roots of `P_s(2t − 1)`.
pub fn gauss_legendre(s: usize) -> Result<Quadrature, TableauError> {
    check_stages("a Gauss–Legendre rule", s, 1)?;
    gauss_dd(s).map(rounded_rule)
}

/// Gauss–Lobatto rule with `s` nodes (`2 ≤ s ≤ 20`) on `[0, 1]`, degree `2s − 3`; the nodes
/// are 0, 1 and the roots of `P'_{s−1}(2t − 1)`.
pub fn gauss_lobatto(s: usize) -> Result<Quadrature, TableauError> {
    check_stages("a Gauss–Lobatto rule", s, 2)?;
    lobatto_dd(s).map(rounded_rule)
}

/// Collocation matrix a_ij = ∫_0^{c_i} l_j(t) dt, l_j the Lagrange basis on the nodes c
/// (row-major s×s).
///
/// The nodes must be finite and distinct; they are taken as exact and the integrals are
/// evaluated in double-double.
pub fn collocation_matrix(nodes: &[f64]) -> Result<Vec<f64>, TableauError> {
    let c = validate("nodes", nodes, true)?;
    round_finite(&collocation_dd(&c)?, "nodes", nodes)
}

/// Lagrange interpolation matrices from control points d_0..d_m to evaluation points c_i:
/// values[i*(m+1)+nu] = l_nu(c_i), derivatives[i*(m+1)+nu] = l_nu'(c_i).
#[derive(Debug, Clone, PartialEq)]
pub struct Interpolation {
    /// `values[i * n_control + nu] = l_nu(c_i)`.
    pub values: Vec<f64>,
    /// `derivatives[i * n_control + nu] = l_nu'(c_i)`.
    pub derivatives: Vec<f64>,
    /// Number of evaluation points `c_i` (rows).
    pub n_eval: usize,
    /// Number of control points `m + 1` (columns).
    pub n_control: usize,
}

/// Values and derivatives of the Lagrange basis on `control` (finite, distinct, taken as
/// exact) at the finite points `eval_at`, computed in double-double.
pub fn lagrange_interpolation(control: &[f64], eval_at: &[f64]) -> Result<Interpolation, TableauError> {
    let d = validate("control", control, true)?;
    let c = validate("eval_at", eval_at, false)?;
    let (values, derivatives): (Vec<Dd>, Vec<Dd>) = c
        .iter()
        .flat_map(|&t| (0..d.len()).map(move |nu| (nu, t)))
        .map(|(nu, t)| lagrange(&d, nu, t))
        .unzip();
    Ok(Interpolation {
        values: round_finite(&values, "control", control)?,
        derivatives: round_finite(&derivatives, "control", control)?,
        n_eval: c.len(),
        n_control: d.len(),
    })
}

/// A partitioned Runge–Kutta tableau (a, ā, b, c), row-major s×s matrices.
#[derive(Debug, Clone, PartialEq)]
pub struct PartitionedTableau {
    /// Human-readable name, e.g. `"Lobatto IIIA-IIIB, s = 3"`.
    pub name: String,
    /// Number of stages.
    pub s: usize,
    /// Classical order of the pair.
    pub order: usize,
    /// Nodes `c_i`.
    pub c: Vec<f64>,
    /// Weights `b_i`, shared by both parts (`b̄ = b`).
    pub b: Vec<f64>,
    /// Matrix `a` (positions), row-major.
    pub a: Vec<f64>,
    /// Matrix `ā` (momenta), row-major.
    pub a_bar: Vec<f64>,
}

impl PartitionedTableau {
    /// Entry `a_ij`. Panics unless `i, j < s`.
    pub fn a(&self, i: usize, j: usize) -> f64 {
        assert!(i < self.s && j < self.s, "index ({i}, {j}) out of range");
        self.a[i * self.s + j]
    }

    /// Entry `ā_ij`. Panics unless `i, j < s`.
    pub fn a_bar(&self, i: usize, j: usize) -> f64 {
        assert!(i < self.s && j < self.s, "index ({i}, {j}) out of range");
        self.a_bar[i * self.s + j]
    }

    /// max over i,j of |b_i ā_ij + b̄_j a_ji − b_i b_j| (symplecticity condition for PRK; zero here)
    pub fn symplecticity_defect(&self) -> f64 {
        let (s, b) = (self.s, &self.b);
        let defect = |i: usize, j: usize| (b[i] * self.a_bar(i, j) + b[j] * self.a(j, i) - b[i] * b[j]).abs();
        (0..s * s).map(|k| defect(k / s, k % s)).fold(0.0, f64::max)
    }
}

/// Lobatto IIIA–IIIB pair with `s` stages (`2 ≤ s ≤ 20`), order `2s − 2`: `a` is the
/// collocation matrix on the Lobatto nodes (IIIA), `ā_ij = b_j (1 − a_ji / b_i)` (IIIB).
pub fn lobatto_iiia_iiib(s: usize) -> Result<PartitionedTableau, TableauError> {
    check_stages("a Lobatto IIIA-IIIB pair", s, 2)?;
    let (c, b) = lobatto_dd(s)?;
    let mut a = collocation_dd(&c)?;
    a[(s - 1) * s..].copy_from_slice(&b);
    let a_bar: Vec<Dd> = (0..s * s)
        .map(|k| (k / s, k % s))
        .map(|(i, j)| b[j] * (Dd::ONE - a[j * s + i] / b[i]))
        .collect();
    let name = format!("Lobatto IIIA-IIIB, s = {s}");
    Ok(rounded_tableau(name, 2 * s - 2, [&c, &b, &a, &a_bar]))
}

/// Gauss–Legendre collocation method with `s` stages (`1 ≤ s ≤ 20`), order `2s`, as a
/// partitioned tableau with `a = ā`.
pub fn gauss(s: usize) -> Result<PartitionedTableau, TableauError> {
    check_stages("a Gauss method", s, 1)?;
    let (c, b) = gauss_dd(s)?;
    let a = collocation_dd(&c)?;
    Ok(rounded_tableau(format!("Gauss, s = {s}"), 2 * s, [&c, &b, &a, &a]))
}

/// Rounds the double-double `[c, b, a, ā]` of an `s`-stage tableau to `f64`.
fn rounded_tableau(name: String, order: usize, [c, b, a, a_bar]: [&[Dd]; 4]) -> PartitionedTableau {
    let (c, b, a, a_bar, s) = (round(c), round(b), round(a), round(a_bar), c.len());
    PartitionedTableau {
        name,
        s,
        order,
        c,
        b,
        a,
        a_bar,
    }
}

#[cfg(test)]
mod tests;
