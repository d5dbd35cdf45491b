//! The compiled expression: a flat, constant-folded node array and its
//! evaluation by a recursive walk over any automatic-differentiation scalar.

use num_dual::DualNum;

use super::ops::{Node, Op};
use super::parser::Parser;
use super::{ExprError, ExprErrorKind, SymbolTable};

/// A parsed, compiled expression. Evaluating it does not allocate: it walks a
/// flat, constant-folded node array over the variable slots of the
/// [`SymbolTable`] it was parsed against, recursing at most 128 levels deep.
#[derive(Debug, Clone, PartialEq)]
pub struct Expr {
    pub(super) source: String,
    pub(super) nodes: Vec<Node>,
    pub(super) links: Vec<(Op, usize)>,
    pub(super) root: usize,
    pub(super) used: Vec<String>,
}

impl Expr {
    /// Parse and compile `source`, resolving names against `symbols`.
    pub fn parse(source: &str, symbols: &SymbolTable) -> Result<Expr, ExprError> {
        let mut p = Parser {
            src: source,
            pos: 0,
            symbols,
            nodes: Vec::new(),
            links: Vec::new(),
            used: Vec::new(),
            nesting: 0,
        };
        if p.peek().is_none() {
            return Err(p.error(ExprErrorKind::Empty, 0));
        }
        let root = p.expr()?;
        match p.peek() {
            None => {}
            Some(')') => return Err(p.error(ExprErrorKind::UnmatchedParen, p.pos)),
            Some(found) => {
                let kind = ExprErrorKind::Unexpected {
                    expected: "an operator",
                    found,
                };
                return Err(p.error(kind, p.pos));
            }
        }
        Ok(Expr {
            source: source.to_string(),
            nodes: p.nodes.into_iter().map(|(node, _)| node).collect(),
            links: p.links,
            root,
            used: p.used,
        })
    }

    /// Evaluate over any AD scalar (or plain `f64`); `vars[slot]` supplies each variable.
    ///
    /// # Panics
    /// If `vars` has no entry for a slot the expression uses.
    #[inline]
    pub fn eval<D: DualNum<Primitive = f64> + Copy>(&self, vars: &[D]) -> D {
        self.walk(self.root, vars)
    }

    fn walk<D: DualNum<Primitive = f64> + Copy>(&self, n: usize, vars: &[D]) -> D {
        match self.nodes[n] {
            Node::Var(i) => vars[i],
            Node::Const(c) => D::from(c),
            Node::Unary(f, a) => f.apply(self.walk(a, vars)),
            Node::Binary(op, a, b) => match (self.nodes[a], self.nodes[b]) {
                (_, Node::Const(c)) => op.apply_rhs(self.walk(a, vars), c),
                (Node::Const(c), _) => op.apply_lhs(c, self.walk(b, vars)),
                _ => op.apply(self.walk(a, vars), self.walk(b, vars)),
            },
            Node::Chain(first, start, end) => self.chain(first, &self.links[start..end], vars),
        }
    }

    /// A long left-associative sequence, as a loop rather than a deep recursion.
    #[inline(never)]
    fn chain<D: DualNum<Primitive = f64> + Copy>(&self, first: usize, links: &[(Op, usize)], vars: &[D]) -> D {
        let mut acc = self.walk(first, vars);
        for &(op, b) in links {
            acc = match self.nodes[b] {
                Node::Const(c) => op.apply_rhs(acc, c),
                _ => op.apply(acc, self.walk(b, vars)),
            };
        }
        acc
    }

    /// The source text.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// Names of the variables the expression uses, in order of first appearance.
    pub fn used_variables(&self) -> Vec<String> {
        self.used.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::super::ops::Func;
    use super::*;
    use crate::expr::test_support::table;
    use nalgebra::SVector;
    use num_dual::{Dual2SVec64, Dual64};

    #[test]
    fn functions_and_first_derivatives() {
        type Exact = fn(f64) -> (f64, f64);
        let cases: &[(&str, Exact)] = &[
            ("sin(x)", |x| (x.sin(), x.cos())),
            ("cos(x)", |x| (x.cos(), -x.sin())),
            ("tan(x)", |x| (x.tan(), 1.0 / x.cos().powi(2))),
            ("exp(x)", |x| (x.exp(), x.exp())),
            ("log(x)", |x| (x.ln(), 1.0 / x)),
            ("ln(x)", |x| (x.ln(), 1.0 / x)),
            ("sqrt(x)", |x| (x.sqrt(), 0.5 / x.sqrt())),
            ("abs(x - 1)", |x| ((x - 1.0).abs(), -1.0)),
            ("sinh(x)", |x| (x.sinh(), x.cosh())),
            ("cosh(x)", |x| (x.cosh(), x.sinh())),
            ("tanh(x)", |x| (x.tanh(), 1.0 / x.cosh().powi(2))),
            ("asin(x)", |x| (x.asin(), 1.0 / (1.0 - x * x).sqrt())),
            ("acos(x)", |x| (x.acos(), -1.0 / (1.0 - x * x).sqrt())),
            ("atan(x)", |x| (x.atan(), 1.0 / (1.0 + x * x))),
            ("atan2(x, 2)", |x| (x.atan2(2.0), 2.0 / (4.0 + x * x))),
            ("atan2(1, x)", |x| (1f64.atan2(x), -1.0 / (1.0 + x * x))),
            ("x^3", |x| (x.powi(3), 3.0 * x * x)),
            ("pow(x, 3)", |x| (x.powi(3), 3.0 * x * x)),
            ("x^-2", |x| (x.powi(-2), -2.0 / x.powi(3))),
            ("x^2.5", |x| (x.powf(2.5), 2.5 * x.powf(1.5))),
            ("pow(x, 2.5)", |x| (x.powf(2.5), 2.5 * x.powf(1.5))),
            ("2^x", |x| (2f64.powf(x), 2f64.powf(x) * 2f64.ln())),
            ("x^x", |x| (x.powf(x), x.powf(x) * (x.ln() + 1.0))),
            ("c*x/3 - 2/x", |x| (x / 6.0 - 2.0 / x, 1.0 / 6.0 + 2.0 / (x * x))),
        ];
        let x = 0.3;
        let vars = [
            Dual64::from(x).derivative(),
            Dual64::from(2.0),
            Dual64::from(0.0),
            Dual64::from(0.0),
        ];
        for (src, exact) in cases {
            let e = Expr::parse(src, &table()).expect(src);
            let (d, (v, dv)) = (e.eval(&vars), exact(x));
            assert!((d.re - v).abs() <= 4e-16 * v.abs(), "{src}: {} vs {v}", d.re);
            assert!((d.eps - dv).abs() <= 1e-14 * dv.abs(), "{src}: {} vs {dv}", d.eps);
            assert!(
                (e.eval(&[x, 2.0, 0.0, 0.0]) - v).abs() <= 4e-16 * v.abs(),
                "{src} in f64"
            );
        }
        // Integer exponents compile to powi, real ones to powf, variable ones to powd: bit-exact.
        for src in ["x^3", "pow(x, 3)", "x^(1+2)", "x^2.5", "2^x"] {
            let e = Expr::parse(src, &table()).expect(src);
            let xd = vars[0];
            let want = match src {
                "x^2.5" => xd.powf(2.5),
                "2^x" => Dual64::from(2.0).powd(xd),
                _ => xd.powi(3),
            };
            assert_eq!((e.eval(&vars).re, e.eval(&vars).eps), (want.re, want.eps), "{src}");
        }
        assert!(matches!(
            Expr::parse("x^3", &table()).expect("ok").nodes.last(),
            Some(Node::Unary(Func::PowI(3), _))
        ));
        // `abs` at 0: the derivative taken is that of the side of the sign of zero.
        let e = Expr::parse("abs(x)", &table()).expect("ok");
        assert_eq!(e.eval(&[Dual64::from(0.0).derivative()]).eps, 1.0);
        assert_eq!(e.eval(&[Dual64::from(-0.0).derivative()]).eps, -1.0);
    }

    #[test]
    fn hessian_of_kepler_lagrangian() {
        let e = Expr::parse("0.5*(x_dot^2 + y_dot^2) + 1/sqrt(x^2 + y^2)", &table()).expect("parses");
        let p = SVector::<f64, 4>::new(0.7, -1.3, 0.4, 0.9);
        let (value, grad, h) = num_dual::hessian(|v: SVector<Dual2SVec64<4>, 4>| e.eval(v.as_slice()), &p);
        let r = p[0].hypot(p[1]);
        assert!((value - (0.5 * (p[2] * p[2] + p[3] * p[3]) + 1.0 / r)).abs() <= 1e-15 * value);
        assert!((grad[0] + p[0] / r.powi(3)).abs() <= 1e-15 * grad[0].abs());
        for i in 0..4 {
            for j in 0..4 {
                let delta = if i == j { 1.0 } else { 0.0 };
                let exact = match (i < 2, j < 2) {
                    (true, true) => 3.0 * p[i] * p[j] / r.powi(5) - delta / r.powi(3),
                    (false, false) => delta,
                    _ => 0.0,
                };
                assert!(
                    (h[(i, j)] - exact).abs() <= 1e-14 * exact.abs(),
                    "H[{i},{j}] = {} vs {exact}",
                    h[(i, j)]
                );
            }
        }
    }
}
