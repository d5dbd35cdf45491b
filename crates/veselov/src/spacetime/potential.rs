//! Potentials `N(φ)` of nonlinear wave equations in the sign convention of
//! seed 002 (4.31)–(4.32):
//!
//! `𝓛 = ½(|φ_t|² − |φ_x|²) + N(φ)`,  PDE `φ_tt − φ_xx − ∇N(φ) = 0`.
//!
//! Models: sine-Gordon `N = cos φ` (`φ_tt − φ_xx + sin φ = 0`), the linear
//! wave equation `N = 0`, φ⁴ Klein–Gordon `N = −½m²φ² − ¼λφ⁴`
//! (`φ_tt − φ_xx + m²φ + λφ³ = 0`) and the O(2)-invariant complex
//! Klein–Gordon field `φ ∈ ℝ²`, `N = −½m²|φ|² − ¼λ|φ|⁴`.

use nalgebra::{SMatrix, SVector};
use num_dual::{Dual2_64, second_derivative};

use crate::ad::Scalar;

/// A potential `N: ℝ^DIM → ℝ`, written once generic over the scalar.
pub trait Potential<const DIM: usize>: Send + Sync {
    /// `N(y)`.
    fn potential<D: Scalar>(&self, y: &SVector<D, DIM>) -> D;

    /// ∇N(y_i) into `gradients[i]` and, if asked, ∇²N(y_i) into
    /// `hessians[i]`, for every point of `y` at once (equal lengths), with
    /// the bits of [`potential`](Self::potential) over a first-order dual
    /// number per direction (gradients only) or a second-order one (with
    /// the Hessians). `false` (the default): not provided, and nothing is
    /// written; callers then differentiate point by point. Models whose
    /// derivatives share transcendental calls across points override it.
    fn batch_derivatives(
        &self,
        _y: &[SVector<f64, DIM>],
        _gradients: &mut [SVector<f64, DIM>],
        _hessians: Option<&mut [SMatrix<f64, DIM, DIM>]>,
    ) -> bool {
        false
    }
}

/// `∇N(y)`, exact (one first-order dual pass over [`Potential::potential`]).
pub fn potential_gradient<P: Potential<DIM>, const DIM: usize>(
    potential: &P,
    y: &SVector<f64, DIM>,
) -> SVector<f64, DIM> {
    num_dual::gradient(
        |yd: SVector<num_dual::DualSVec64<DIM>, DIM>| potential.potential(&yd),
        y,
    )
    .1
}

/// A scalar potential with the values the fast lattice paths need.
pub trait ScalarPotential: Potential<1> {
    /// `(N(y), N′(y), N″(y))`. The default differentiates [`Potential`]
    /// exactly; models override it with closed forms sharing transcendental
    /// calls.
    fn jet(&self, y: f64) -> [f64; 3] {
        let (v, d1, d2) = second_derivative(|x: Dual2_64| self.potential(&SVector::from([x])), y);
        [v, d1, d2]
    }
    /// [`jet`](Self::jet) at every point of `y` into `values`, `first`
    /// and `second` (equal lengths), with its bits. The default calls
    /// `jet` point by point; sine-Gordon reduces and evaluates its
    /// arguments in vector lanes ([`crate::spacetime::trig::sin_cos_batch`]).
    ///
    /// # Panics
    /// If the slices differ in length (a caller's bug).
    fn jets(&self, y: &[f64], values: &mut [f64], first: &mut [f64], second: &mut [f64]) {
        assert!(
            y.len() == values.len() && y.len() == first.len() && y.len() == second.len(),
            "jets: lengths differ"
        );
        for (i, &x) in y.iter().enumerate() {
            [values[i], first[i], second[i]] = self.jet(x);
        }
    }
    /// A bound on `sup |N″|` if one exists (used for a posteriori stopping
    /// of fixed-point iterations: contraction constants).
    fn curvature_bound(&self) -> Option<f64> {
        None
    }
    /// The divided difference `(N(a) − N(b))/(a − b)`, `N′(a)` at `a = b`,
    /// evaluated stably. The default uses the direct quotient for
    /// `|a − b| ≥ 10⁻²` (cancellation error ≲ ε|N|/|a − b| ≤ 2·10⁻¹⁴|N|) and
    /// otherwise the 3-point Gauss–Legendre rule for `∫₀¹ N′(b + s(a − b)) ds`
    /// (exact for quintic `N′`; error ≤ |a − b|⁶ max|N⁽⁷⁾|/2·10⁶ < 10⁻¹⁸ max|N⁽⁷⁾|).
    fn divided_difference(&self, a: f64, b: f64) -> f64 {
        let d = a - b;
        if d.abs() >= 1e-2 {
            (self.jet(a)[0] - self.jet(b)[0]) / d
        } else {
            const S: f64 = 0.387_298_334_620_741_7; // √(3/5)/2
            let m = 0.5 * (a + b);
            (5.0 * (self.jet(m - S * d)[1] + self.jet(m + S * d)[1]) + 8.0 * self.jet(m)[1]) / 18.0
        }
    }
}

/// Sine-Gordon: `N(φ) = cos φ`, `φ_tt − φ_xx + sin φ = 0`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SineGordon;

/// Points per group of [`SineGordon`]'s batched derivatives: the 24 star
/// cells of four 2+1 vertices (the metric solve's eight vertices take two
/// groups; a group of 8 took 2.4 % more instructions per vertex update,
/// one of 32 0.2 % more, one of 48 0.6 % more: its buffers' zeroing).
const BATCH: usize = 24;

impl Potential<1> for SineGordon {
    /// `cos y`; over dual numbers from its closed-form jet (`through_jet`).
    fn potential<D: Scalar>(&self, y: &SVector<D, 1>) -> D {
        through_jet(self, y[0]).unwrap_or_else(|| y[0].cos())
    }
    /// N′ = −sin and N″ = −cos from one [`sin_cos_batch`] over the points
    /// (the arguments reduced and the polynomials evaluated in vector
    /// lanes; the bits of [`ScalarPotential::jets`], without its N). The
    /// bits are those of the dual passes through `through_jet`:
    /// a first-order pass gives N′ itself; a second-order one, by the
    /// product rule of its `(½N″d + N′)d`, gives N′ + ½N″·0 and 2·(½N″).
    /// Points are taken in groups of `BATCH` (the stack buffers of a
    /// group).
    ///
    /// [`sin_cos_batch`]: crate::spacetime::trig::sin_cos_batch
    fn batch_derivatives(
        &self,
        y: &[SVector<f64, 1>],
        gradients: &mut [SVector<f64, 1>],
        mut hessians: Option<&mut [SMatrix<f64, 1, 1>]>,
    ) -> bool {
        if gradients.len() != y.len() || hessians.as_ref().is_some_and(|h| h.len() != y.len()) {
            return false;
        }
        // sin and cos of the points straight from the batch: N′ = −sin,
        // N″ = −cos, as `jets` gives them (N itself is not needed here).
        let (mut x, mut sin, mut cos) = ([0.0; BATCH], [0.0; BATCH], [0.0; BATCH]);
        for (k, points) in y.chunks(BATCH).enumerate() {
            let (at, count) = (k * BATCH, points.len());
            for (xi, p) in x.iter_mut().zip(points) {
                *xi = p[0];
            }
            crate::spacetime::trig::sin_cos_batch(&x[..count], &mut sin[..count], &mut cos[..count]);
            let jets = sin.iter().zip(&cos).map(|(s, c)| (-s, -c));
            let gradients = &mut gradients[at..at + count];
            match hessians.as_deref_mut() {
                Some(h) => {
                    for ((g, h), (d1, d2)) in gradients.iter_mut().zip(&mut h[at..at + count]).zip(jets) {
                        let half = 0.5 * d2;
                        g[0] = d1 + half * 0.0;
                        h[(0, 0)] = 2.0 * half;
                    }
                }
                None => {
                    for (g, (d1, _)) in gradients.iter_mut().zip(jets) {
                        g[0] = d1;
                    }
                }
            }
        }
        true
    }
}

/// `N(y)` for a dual number `y` carrying first or second derivatives, from
/// the potential's closed-form jet at the real part y₀: d = y − y₀ has no
/// real part and d³ = 0 in every such algebra (ε³ = 0 for second-order
/// duals; ε₁² = ε₂² = 0 for hyper-duals and nested first-order duals), so
/// N(y) = N(y₀) + N′(y₀)d + ½N″(y₀)d² exactly, and for first-order duals
/// (d² = 0) N(y₀) + N′(y₀)d. Sine-Gordon's jet shares one argument
/// reduction between sin and cos, where the scalar's own `cos` makes two
/// transcendental calls. `None` for `f64` and for higher orders.
#[inline]
fn through_jet<P: ScalarPotential, D: Scalar>(p: &P, y: D) -> Option<D> {
    match D::NDERIV {
        1 | 2 => {
            let y0 = y.re();
            let [f0, f1, f2] = p.jet(y0);
            let d = y - D::from(y0);
            Some(if D::NDERIV == 1 {
                d * f1 + f0
            } else {
                (d * (0.5 * f2) + f1) * d + f0
            })
        }
        _ => None,
    }
}

impl ScalarPotential for SineGordon {
    #[inline(always)]
    fn jet(&self, y: f64) -> [f64; 3] {
        let (s, c) = crate::spacetime::trig::sin_cos(y);
        [c, -s, -c]
    }
    /// (cos y, −sin y, −cos y) from one [`crate::spacetime::trig::sin_cos_batch`].
    fn jets(&self, y: &[f64], values: &mut [f64], first: &mut [f64], second: &mut [f64]) {
        assert!(y.len() == values.len(), "jets: lengths differ");
        crate::spacetime::trig::sin_cos_batch(y, first, second);
        for ((v, d1), d2) in values.iter_mut().zip(first.iter_mut()).zip(second.iter_mut()) {
            *v = *d2;
            *d1 = -*d1;
            *d2 = -*d2;
        }
    }
    fn curvature_bound(&self) -> Option<f64> {
        Some(1.0)
    }
    /// `(cos a − cos b)/(a − b) = −sin((a+b)/2)·sinc((a−b)/2)`: no cancellation.
    #[inline(always)]
    fn divided_difference(&self, a: f64, b: f64) -> f64 {
        let h = 0.5 * (a - b);
        let sinc = if h.abs() < 1e-4 {
            1.0 - h * h / 6.0 // next term h⁴/120 < 10⁻¹⁸
        } else {
            h.sin() / h
        };
        -(0.5 * (a + b)).sin() * sinc
    }
}

/// The linear wave equation: `N = 0`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Wave;

impl Potential<1> for Wave {
    fn potential<D: Scalar>(&self, _y: &SVector<D, 1>) -> D {
        D::zero()
    }
}

impl ScalarPotential for Wave {
    fn jet(&self, _y: f64) -> [f64; 3] {
        [0.0; 3]
    }
    fn curvature_bound(&self) -> Option<f64> {
        Some(0.0)
    }
    fn divided_difference(&self, _a: f64, _b: f64) -> f64 {
        0.0
    }
}

/// φ⁴ Klein–Gordon: `N(φ) = −½m²φ² − ¼λφ⁴`, PDE
/// `φ_tt − φ_xx + m²φ + λφ³ = 0`. `m² > 0, λ > 0` is the stable
/// (defocusing) model; `m² = −1, λ = 1` is the double well
/// `φ_tt − φ_xx − φ + φ³ = 0` with kinks `tanh(x/√2)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Phi4 {
    /// Mass term `m²`.
    pub m2: f64,
    /// Quartic coupling `λ`.
    pub lambda: f64,
}

impl Potential<1> for Phi4 {
    fn potential<D: Scalar>(&self, y: &SVector<D, 1>) -> D {
        let p2 = y[0] * y[0];
        -(p2 * (self.m2 * 0.5) + p2 * p2 * (self.lambda * 0.25))
    }
}

impl ScalarPotential for Phi4 {
    fn jet(&self, y: f64) -> [f64; 3] {
        let y2 = y * y;
        [
            -(0.5 * self.m2 * y2 + 0.25 * self.lambda * y2 * y2),
            -(self.m2 * y + self.lambda * y2 * y),
            -(self.m2 + 3.0 * self.lambda * y2),
        ]
    }
    /// Exact: `(N(a) − N(b))/(a − b) = −½m²(a + b) − ¼λ(a + b)(a² + b²)`.
    fn divided_difference(&self, a: f64, b: f64) -> f64 {
        -(0.5 * self.m2 * (a + b) + 0.25 * self.lambda * (a + b) * (a * a + b * b))
    }
}

/// O(2)-invariant complex Klein–Gordon field `φ = (Re, Im) ∈ ℝ²`:
/// `N(φ) = −½m²|φ|² − ¼λ|φ|⁴`, PDE `φ_tt − φ_xx + (m² + λ|φ|²)φ = 0`.
/// Invariant under the phase rotation generated by `J = [[0, −1], [1, 0]]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ComplexKleinGordon {
    /// Mass term `m²`.
    pub m2: f64,
    /// Quartic coupling `λ`.
    pub lambda: f64,
}

impl Potential<2> for ComplexKleinGordon {
    fn potential<D: Scalar>(&self, y: &SVector<D, 2>) -> D {
        let r2 = y[0] * y[0] + y[1] * y[1];
        -(r2 * (self.m2 * 0.5) + r2 * r2 * (self.lambda * 0.25))
    }
}

/// Any potential gives the smooth nonlinear-wave density
/// `𝓛 = ½(|φ_t|² − |φ_x|²) + N(φ)` (seed 002 (4.32)).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct NonlinearWave<P>(pub P);

impl<const DIM: usize, P: Potential<DIM>> crate::spacetime::density::Density<DIM> for NonlinearWave<P> {
    fn density<D: Scalar>(&self, phi: &SVector<D, DIM>, phi_t: &SVector<D, DIM>, phi_x: &SVector<D, DIM>) -> D {
        let mut kin = D::zero();
        for a in 0..DIM {
            kin += phi_t[a] * phi_t[a] - phi_x[a] * phi_x[a];
        }
        kin * 0.5 + self.0.potential(phi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The exact gradient is the field equation's force: −sin φ for
    /// sine-Gordon, −(m² + λ|φ|²)φ for the complex Klein–Gordon field.
    #[test]
    fn the_potential_gradient_is_the_force_of_the_field_equation() {
        for phi in [-2.0, 0.0, 0.3, 1.7] {
            let g = potential_gradient(&SineGordon, &SVector::<f64, 1>::new(phi));
            assert!((g[0] + f64::sin(phi)).abs() <= 2.0 * f64::EPSILON, "{phi}: {g}");
        }
        let kg = ComplexKleinGordon { m2: 1.5, lambda: 0.7 };
        let y = SVector::<f64, 2>::new(0.4, -1.1);
        let expected = -y * (kg.m2 + kg.lambda * y.norm_squared());
        assert!(
            (potential_gradient(&kg, &y) - expected).amax() <= 4.0 * f64::EPSILON,
            "{expected}"
        );
    }

    /// Sine-Gordon's batched derivatives are the bits of the dual passes
    /// the rules would otherwise make point by point (first order for the
    /// gradients alone, second order with the Hessians), for batches of
    /// every length up to two groups and points of both signs, signed
    /// zeros and a NaN; the default batch provides nothing.
    #[test]
    fn sine_gordon_batch_derivatives_are_the_bits_of_the_dual_passes() {
        use num_dual::{Dual2_64, Dual64};
        let mut points = vec![0.0, -0.0, 1e-300, f64::NAN, 3.0e5, -7.25];
        points.extend((0..60).map(|k| (k as f64 * 0.731).sin() * 9.0 + k as f64 * 0.01));
        let bits = |v: f64| if v.is_nan() { u64::MAX } else { v.to_bits() };
        for len in [0, 1, 2, 3, 5, 6, 8, 9, 17, points.len()] {
            let y: Vec<SVector<f64, 1>> = points[..len].iter().map(|&v| SVector::from([v])).collect();
            let mut g = vec![SVector::zeros(); len];
            let mut h = vec![SMatrix::zeros(); len];
            assert!(SineGordon.batch_derivatives(&y, &mut g, None));
            for (p, gi) in y.iter().zip(&g) {
                let first = SineGordon.potential(&SVector::from([Dual64::new(p[0], 1.0)]));
                assert_eq!(bits(gi[0]), bits(first.eps), "gradient at {:e}", p[0]);
            }
            assert!(SineGordon.batch_derivatives(&y, &mut g, Some(&mut h)));
            for ((p, gi), hi) in y.iter().zip(&g).zip(&h) {
                let second = SineGordon.potential(&SVector::from([Dual2_64::new(p[0], 1.0, 0.0)]));
                assert_eq!(bits(gi[0]), bits(second.v1), "gradient with the Hessian at {:e}", p[0]);
                assert_eq!(bits(hi[(0, 0)]), bits(second.v2), "Hessian at {:e}", p[0]);
            }
        }
        // The jets of a whole lattice level: the bits of `jet`, point by
        // point, for the batched sine-Gordon and the default alike.
        let n = points.len();
        let (mut v, mut d1, mut d2) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        SineGordon.jets(&points, &mut v, &mut d1, &mut d2);
        for (i, &p) in points.iter().enumerate() {
            let want = SineGordon.jet(p).map(bits);
            assert_eq!([bits(v[i]), bits(d1[i]), bits(d2[i])], want, "jets at {p:e}");
        }
        Exp.jets(&points[6..], &mut v[6..], &mut d1[6..], &mut d2[6..]);
        assert_eq!(bits(d2[9]), bits(Exp.jet(points[9])[2]));
        // Mismatched lengths are refused without writing.
        let y = [SVector::from([1.0]); 3];
        assert!(!SineGordon.batch_derivatives(&y, &mut [SVector::zeros(); 2], None));
        assert!(!Exp.batch_derivatives(&y, &mut [SVector::zeros(); 3], None));
    }

    /// `N = eˣ` through the default (AD) jet and divided difference.
    struct Exp;
    impl Potential<1> for Exp {
        fn potential<D: Scalar>(&self, y: &SVector<D, 1>) -> D {
            y[0].exp()
        }
    }
    impl ScalarPotential for Exp {}

    /// Sine-Gordon's potential over dual numbers through its jet equals the
    /// scalar's own `cos` in value and every derivative (first-order,
    /// multi-direction, second-order, hyper-dual and nested duals), to the
    /// last bits of the two sin/cos implementations; `f64` keeps `cos`.
    #[test]
    fn sine_gordon_through_its_jet_equals_the_scalars_cosine() {
        use num_dual::{Dual2_64, Dual64, DualNum, DualSVec, DualSVec64, HyperDual64};
        let close = |a: f64, b: f64| (a - b).abs() <= 4.0 * f64::EPSILON * (1.0 + b.abs());
        let sg = |y: f64| -> [f64; 4] {
            let d = Dual64::new(y, 0.7);
            let v = DualSVec64::<3>::new(y, num_dual::Derivative::some(nalgebra::SVector::from([0.3, -1.1, 2.0])));
            let h = HyperDual64::new(y, 0.4, -0.9, 0.25);
            let q = Dual2_64::new(y, 0.6, -0.2);
            let (pd, pv, ph, pq) = (
                SineGordon.potential(&SVector::from([d])),
                SineGordon.potential(&SVector::from([v])),
                SineGordon.potential(&SVector::from([h])),
                SineGordon.potential(&SVector::from([q])),
            );
            let (cd, cv, ch, cq) = (d.cos(), v.cos(), h.cos(), q.cos());
            let parts = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| close(*x, *y));
            let ok = [
                parts(&[pd.re, pd.eps], &[cd.re, cd.eps]),
                parts(
                    pv.eps.unwrap_generic(nalgebra::Const::<3>, nalgebra::U1).as_slice(),
                    cv.eps.unwrap_generic(nalgebra::Const::<3>, nalgebra::U1).as_slice(),
                ) && close(pv.re, cv.re),
                parts(
                    &[ph.re, ph.eps1, ph.eps2, ph.eps1eps2],
                    &[ch.re, ch.eps1, ch.eps2, ch.eps1eps2],
                ),
                parts(&[pq.re, pq.v1, pq.v2], &[cq.re, cq.v1, cq.v2]),
            ];
            ok.map(f64::from)
        };
        for &y in &[0.0, 1e-9, 0.3, -1.7, 3.2, 10.0, -250.0, 1e5] {
            assert_eq!(sg(y), [1.0; 4], "y = {y}");
            assert_eq!(SineGordon.potential(&SVector::from([y])).to_bits(), y.cos().to_bits());
        }
        // Nested first-order duals (the vertex Jacobian blocks).
        type Outer = DualSVec<DualSVec64<1>, 1>;
        let inner = DualSVec64::<1>::new(0.8, num_dual::Derivative::some(SVector::from([0.5])));
        let y = Outer::new(
            inner,
            num_dual::Derivative::some(SVector::from([DualSVec64::<1>::from_re(-1.3)])),
        );
        let (p, c) = (SineGordon.potential(&SVector::from([y])), y.cos());
        let outer = |x: &Outer| x.eps.unwrap_generic(nalgebra::Const::<1>, nalgebra::U1)[0];
        let flat = |x: &Outer| {
            let o = outer(x);
            [
                x.re.re,
                x.re.eps.unwrap_generic(nalgebra::Const::<1>, nalgebra::U1)[0],
                o.re,
                o.eps.unwrap_generic(nalgebra::Const::<1>, nalgebra::U1)[0],
            ]
        };
        for (a, b) in flat(&p).iter().zip(flat(&c)) {
            assert!(close(*a, b), "nested duals: {:?} vs {:?}", flat(&p), flat(&c));
        }
        assert_eq!(Outer::NDERIV, 2);
    }

    #[test]
    fn default_jet_and_divided_difference() {
        let [v, d1, d2] = Exp.jet(0.3);
        let e = 0.3f64.exp();
        assert!((v - e).abs() <= 1e-15 && (d1 - e).abs() <= 1e-15 && (d2 - e).abs() <= 1e-15);
        for &b in &[-1.0f64, 0.2, 2.0] {
            for &d in &[0.5f64, 2e-2, 1e-2, 9.9e-3, 1e-4, 1e-9, 0.0, -1e-6, -0.3] {
                let a = b + d;
                // exact: e^b (e^d − 1)/d, with expm1 for accuracy
                let exact = if d == 0.0 { b.exp() } else { b.exp() * d.exp_m1() / d };
                let got = Exp.divided_difference(a, b);
                assert!(
                    (got - exact).abs() <= 3e-14 * exact.abs(),
                    "a = {a}, b = {b}: {got} vs {exact}"
                );
            }
        }
    }

    #[test]
    fn closed_forms_match_the_generic_definitions() {
        for &y in &[-7.0, -1.0, 0.0, 0.4, 3.0, 12.5] {
            let sg = SineGordon.jet(y);
            let (v, d1, d2) = second_derivative(|x: Dual2_64| SineGordon.potential(&SVector::from([x])), y);
            assert!((sg[0] - v).abs() <= 1e-15 && (sg[1] - d1).abs() <= 1e-15 && (sg[2] - d2).abs() <= 1e-15);
            let p = Phi4 { m2: 0.7, lambda: -0.3 };
            let pj = p.jet(y);
            let (v, d1, d2) = second_derivative(|x: Dual2_64| p.potential(&SVector::from([x])), y);
            assert!((pj[0] - v).abs() <= 1e-12 * v.abs().max(1.0));
            assert!((pj[1] - d1).abs() <= 1e-12 * d1.abs().max(1.0));
            assert!((pj[2] - d2).abs() <= 1e-12 * d2.abs().max(1.0));
            for &d in &[1.0, 1e-3, 1e-8, 0.0] {
                let a = y + d;
                let direct = if d == 0.0 { sg[1] } else { (a.cos() - y.cos()) / (a - y) };
                let tol = if d >= 1e-3 { 1e-12 } else { 1e-7 }; // the direct quotient loses ~ε/d
                assert!((SineGordon.divided_difference(a, y) - direct).abs() <= tol);
            }
        }
    }
}
