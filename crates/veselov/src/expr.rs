//! Mathematical expressions for custom systems, parsed once and evaluated
//! generically over the AD scalar so that every derivative stays exact.
//!
//! Grammar (EBNF):
//! ```text
//! expr    = term { ("+" | "-") term } ;
//! term    = unary { ("*" | "/") unary } ;
//! unary   = ("-" | "+") unary | power ;
//! power   = primary [ "^" unary ] ;            (* right-associative; -x^2 = -(x^2); 2^-1 allowed *)
//! primary = number | name | name "(" expr { "," expr } ")" | "(" expr ")" ;
//! ```
//! Functions: `sin cos tan exp log sqrt abs pow(a, b) sinh cosh tanh asin acos
//! atan atan2(y, x)`. `abs` is not differentiable at 0 (its derivative there is
//! taken as that of the sign). Powers with an integer constant exponent use
//! `powi` (exact), other constant exponents `powf`, and a variable exponent
//! `exp(b·ln a)`.
//!
//! Names are resolved at parse time against a [`SymbolTable`]: variables map to
//! slots of the evaluation array, constants are folded in. Evaluation walks a
//! flat node array recursively: no allocation per call.

use std::fmt;

use crate::ad::Scalar;

/// A parse error with its position in the source.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExprError {
    /// What is wrong.
    pub message: String,
    /// Byte offset into the source.
    pub offset: usize,
    /// 1-based column (in characters).
    pub column: usize,
    /// The source expression.
    pub source: String,
}

impl fmt::Display for ExprError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{} at column {}", self.message, self.column)?;
        writeln!(f, "  {}", self.source)?;
        write!(f, "  {}^", " ".repeat(self.column.saturating_sub(1)))
    }
}

impl std::error::Error for ExprError {}

#[derive(Debug, Clone, PartialEq)]
enum Symbol {
    Variable(usize),
    Constant(f64),
}

/// Names known to expressions: variables (evaluation slots) and constants.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SymbolTable {
    names: Vec<(String, Symbol)>,
    variables: usize,
}

impl SymbolTable {
    /// An empty table.
    pub fn new() -> Self {
        Self::default()
    }
    fn check_new(&self, name: &str) -> Result<(), ExprError> {
        if self.names.iter().any(|(n, _)| n == name) {
            return Err(ExprError {
                message: format!("`{name}` is declared twice"),
                offset: 0,
                column: 1,
                source: name.to_string(),
            });
        }
        Ok(())
    }
    /// Declare a variable; returns its slot (slots are numbered in declaration order).
    pub fn variable(&mut self, name: &str) -> Result<usize, ExprError> {
        self.check_new(name)?;
        let slot = self.variables;
        self.names.push((name.to_string(), Symbol::Variable(slot)));
        self.variables += 1;
        Ok(slot)
    }
    /// Declare a named constant.
    pub fn constant(&mut self, name: &str, value: f64) -> Result<(), ExprError> {
        self.check_new(name)?;
        self.names.push((name.to_string(), Symbol::Constant(value)));
        Ok(())
    }
    /// Number of variables (the length `eval` expects).
    pub fn len_variables(&self) -> usize {
        self.variables
    }
    fn lookup(&self, name: &str) -> Option<&Symbol> {
        self.names.iter().find(|(n, _)| n == name).map(|(_, s)| s)
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Func {
    Sin,
    Cos,
    Tan,
    Exp,
    Log,
    Sqrt,
    Abs,
    Sinh,
    Cosh,
    Tanh,
    Asin,
    Acos,
    Atan,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Node {
    Const(f64),
    Var(usize),
    Neg(usize),
    Add(usize, usize),
    Sub(usize, usize),
    Mul(usize, usize),
    Div(usize, usize),
    PowI(usize, i32),
    PowF(usize, f64),
    Pow(usize, usize),
    Call(Func, usize),
    Atan2(usize, usize),
}

/// A parsed expression.
#[derive(Debug, Clone, PartialEq)]
pub struct Expr {
    source: String,
    nodes: Vec<Node>,
    root: usize,
    used: Vec<String>,
}

impl Expr {
    /// Parse `source` against `symbols`.
    pub fn parse(source: &str, symbols: &SymbolTable) -> Result<Expr, ExprError> {
        let mut p = Parser {
            src: source,
            pos: 0,
            symbols,
            nodes: Vec::new(),
            used: Vec::new(),
        };
        p.skip_ws();
        if p.pos >= source.len() {
            return Err(p.error("empty expression", 0));
        }
        let root = p.expr()?;
        p.skip_ws();
        if p.pos < source.len() {
            let msg = if source[p.pos..].starts_with(')') {
                "unbalanced `)`"
            } else {
                "unexpected input"
            };
            return Err(p.error(msg, p.pos));
        }
        Ok(Expr {
            source: source.to_string(),
            nodes: p.nodes,
            root,
            used: p.used,
        })
    }

    /// The source text.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// Names of the variables the expression uses.
    pub fn used_variables(&self) -> Vec<String> {
        self.used.clone()
    }

    /// Evaluate with `vars[slot]` for each variable.
    pub fn eval<D: Scalar>(&self, vars: &[D]) -> D {
        eval_node(&self.nodes, self.root, vars)
    }
}

/// Evaluate node `i` of `nodes` recursively.
fn eval_node<D: Scalar>(nodes: &[Node], i: usize, v: &[D]) -> D {
    let e = |j: usize| eval_node(nodes, j, v);
    match nodes[i] {
        Node::Const(c) => D::from(c),
        Node::Var(s) => v[s],
        Node::Neg(a) => -e(a),
        Node::Add(a, b) => e(a) + e(b),
        Node::Sub(a, b) => e(a) - e(b),
        Node::Mul(a, b) => e(a) * e(b),
        Node::Div(a, b) => e(a) / e(b),
        Node::PowI(a, n) => e(a).powi(n),
        Node::PowF(a, x) => e(a).powf(x),
        Node::Pow(a, b) => e(a).powd(e(b)),
        Node::Atan2(a, b) => e(a).atan2(e(b)),
        Node::Call(f, a) => {
            let x = e(a);
            match f {
                Func::Sin => x.sin(),
                Func::Cos => x.cos(),
                Func::Tan => x.tan(),
                Func::Exp => x.exp(),
                Func::Log => x.ln(),
                Func::Sqrt => x.sqrt(),
                Func::Abs => x.abs(),
                Func::Sinh => x.sinh(),
                Func::Cosh => x.cosh(),
                Func::Tanh => x.tanh(),
                Func::Asin => x.asin(),
                Func::Acos => x.acos(),
                Func::Atan => x.atan(),
            }
        }
    }
}

struct Parser<'a> {
    src: &'a str,
    pos: usize,
    symbols: &'a SymbolTable,
    nodes: Vec<Node>,
    used: Vec<String>,
}

impl Parser<'_> {
    fn error(&self, message: &str, offset: usize) -> ExprError {
        ExprError {
            message: message.to_string(),
            offset,
            column: self.src[..offset.min(self.src.len())].chars().count() + 1,
            source: self.src.to_string(),
        }
    }
    fn skip_ws(&mut self) {
        while self.src[self.pos..].starts_with(|c: char| c.is_whitespace()) {
            self.pos += 1;
        }
    }
    fn peek(&mut self) -> Option<char> {
        self.skip_ws();
        self.src[self.pos..].chars().next()
    }
    fn eat(&mut self, c: char) -> bool {
        if self.peek() == Some(c) {
            self.pos += c.len_utf8();
            true
        } else {
            false
        }
    }
    fn constant_of(&self, i: usize) -> Option<f64> {
        match self.nodes[i] {
            Node::Const(c) => Some(c),
            _ => None,
        }
    }
    /// Push a node, folding it to a constant when all its inputs are constant.
    fn push(&mut self, node: Node) -> usize {
        let inputs: &[usize] = match &node {
            Node::Const(_) | Node::Var(_) => &[],
            Node::Neg(a) | Node::PowI(a, _) | Node::PowF(a, _) | Node::Call(_, a) => std::slice::from_ref(a),
            Node::Add(a, _)
            | Node::Sub(a, _)
            | Node::Mul(a, _)
            | Node::Div(a, _)
            | Node::Pow(a, _)
            | Node::Atan2(a, _) => std::slice::from_ref(a),
        };
        let second = match node {
            Node::Add(_, b)
            | Node::Sub(_, b)
            | Node::Mul(_, b)
            | Node::Div(_, b)
            | Node::Pow(_, b)
            | Node::Atan2(_, b) => Some(b),
            _ => None,
        };
        let foldable = !inputs.is_empty()
            && inputs
                .iter()
                .chain(second.iter())
                .all(|&i| self.constant_of(i).is_some());
        self.nodes.push(node);
        let last = self.nodes.len() - 1;
        if foldable {
            self.nodes[last] = Node::Const(eval_node::<f64>(&self.nodes, last, &[]));
        }
        last
    }
    fn expr(&mut self) -> Result<usize, ExprError> {
        let mut a = self.term()?;
        loop {
            if self.eat('+') {
                let b = self.term()?;
                a = self.push(Node::Add(a, b));
            } else if self.eat('-') {
                let b = self.term()?;
                a = self.push(Node::Sub(a, b));
            } else {
                return Ok(a);
            }
        }
    }
    fn term(&mut self) -> Result<usize, ExprError> {
        let mut a = self.unary()?;
        loop {
            if self.eat('*') {
                let b = self.unary()?;
                a = self.push(Node::Mul(a, b));
            } else if self.eat('/') {
                let b = self.unary()?;
                a = self.push(Node::Div(a, b));
            } else {
                return Ok(a);
            }
        }
    }
    fn unary(&mut self) -> Result<usize, ExprError> {
        if self.eat('-') {
            let a = self.unary()?;
            return Ok(self.push(Node::Neg(a)));
        }
        if self.eat('+') {
            return self.unary();
        }
        self.power()
    }
    fn power(&mut self) -> Result<usize, ExprError> {
        let base = self.primary()?;
        if self.eat('^') {
            let exponent = self.unary()?;
            return Ok(self.pow(base, exponent));
        }
        Ok(base)
    }
    fn pow(&mut self, base: usize, exponent: usize) -> usize {
        match self.constant_of(exponent) {
            Some(x) if x.fract() == 0.0 && x.abs() <= i32::MAX as f64 => self.push(Node::PowI(base, x as i32)),
            Some(x) => self.push(Node::PowF(base, x)),
            None => self.push(Node::Pow(base, exponent)),
        }
    }
    fn primary(&mut self) -> Result<usize, ExprError> {
        let start = {
            self.skip_ws();
            self.pos
        };
        match self.peek() {
            None => Err(self.error("expected a number, name or `(`", start)),
            Some('(') => {
                self.pos += 1;
                let e = self.expr()?;
                if !self.eat(')') {
                    return Err(self.error("expected `)`", self.pos));
                }
                Ok(e)
            }
            Some(c) if c.is_ascii_digit() || c == '.' => self.number(start),
            Some(c) if c.is_ascii_alphabetic() || c == '_' => self.name(start),
            Some(c) => Err(self.error(&format!("unexpected `{c}`"), start)),
        }
    }
    fn number(&mut self, start: usize) -> Result<usize, ExprError> {
        let bytes = self.src.as_bytes();
        let mut end = start;
        while end < bytes.len() && (bytes[end].is_ascii_digit() || bytes[end] == b'.') {
            end += 1;
        }
        if end < bytes.len() && (bytes[end] == b'e' || bytes[end] == b'E') {
            let mut k = end + 1;
            if k < bytes.len() && (bytes[k] == b'+' || bytes[k] == b'-') {
                k += 1;
            }
            if k < bytes.len() && bytes[k].is_ascii_digit() {
                while k < bytes.len() && bytes[k].is_ascii_digit() {
                    k += 1;
                }
                end = k;
            }
        }
        let text = &self.src[start..end];
        let value: f64 = text
            .parse()
            .map_err(|_| self.error(&format!("invalid number `{text}`"), start))?;
        self.pos = end;
        Ok(self.push(Node::Const(value)))
    }
    fn name(&mut self, start: usize) -> Result<usize, ExprError> {
        let bytes = self.src.as_bytes();
        let mut end = start;
        while end < bytes.len() && (bytes[end].is_ascii_alphanumeric() || bytes[end] == b'_') {
            end += 1;
        }
        let name = &self.src[start..end];
        self.pos = end;
        if self.peek() == Some('(') {
            self.pos += 1;
            let mut args = vec![self.expr()?];
            while self.eat(',') {
                args.push(self.expr()?);
            }
            if !self.eat(')') {
                return Err(self.error("expected `)` or `,`", self.pos));
            }
            let arity = |n: usize| -> Result<(), ExprError> {
                if args.len() == n {
                    Ok(())
                } else {
                    Err(self.error(&format!("`{name}` takes {n} argument(s), got {}", args.len()), start))
                }
            };
            let func = match name {
                "sin" => Func::Sin,
                "cos" => Func::Cos,
                "tan" => Func::Tan,
                "exp" => Func::Exp,
                "log" | "ln" => Func::Log,
                "sqrt" => Func::Sqrt,
                "abs" => Func::Abs,
                "sinh" => Func::Sinh,
                "cosh" => Func::Cosh,
                "tanh" => Func::Tanh,
                "asin" => Func::Asin,
                "acos" => Func::Acos,
                "atan" => Func::Atan,
                "pow" => {
                    arity(2)?;
                    return Ok(self.pow(args[0], args[1]));
                }
                "atan2" => {
                    arity(2)?;
                    return Ok(self.push(Node::Atan2(args[0], args[1])));
                }
                _ => return Err(self.error(&format!("unknown function `{name}`"), start)),
            };
            arity(1)?;
            return Ok(self.push(Node::Call(func, args[0])));
        }
        match self.symbols.lookup(name) {
            Some(Symbol::Variable(slot)) => {
                if !self.used.iter().any(|u| u == name) {
                    self.used.push(name.to_string());
                }
                Ok(self.push(Node::Var(*slot)))
            }
            Some(Symbol::Constant(c)) => Ok(self.push(Node::Const(*c))),
            None => Err(self.error(&format!("unknown variable `{name}`"), start)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_dual::Dual64;

    fn table() -> SymbolTable {
        let mut t = SymbolTable::new();
        for n in ["x", "y", "x_dot", "y_dot"] {
            t.variable(n).expect("fresh");
        }
        t.constant("c", 0.5).expect("fresh");
        t
    }

    fn value(src: &str) -> f64 {
        Expr::parse(src, &table()).expect("parses").eval(&[2.0, 3.0, 0.5, -1.0])
    }

    #[test]
    fn precedence_and_associativity() {
        assert_eq!(value("2^3^2"), 512.0);
        assert_eq!(value("-2^2"), -4.0);
        assert_eq!(value("2*-3"), -6.0);
        assert_eq!(value("(1+2)*3"), 9.0);
        assert_eq!(value("8/4/2"), 1.0);
        assert_eq!(value("1-2-3"), -4.0);
        assert_eq!(value("2^-1"), 0.5);
        assert_eq!(value("x*c + y"), 4.0);
        assert_eq!(value("1e-3*1E3 + .5"), 1.5);
    }

    #[test]
    fn functions_and_derivatives() {
        let t = table();
        type ValueAndSlope = fn(f64) -> (f64, f64);
        let cases: &[(&str, ValueAndSlope)] = &[
            ("sin(x)", |x| (x.sin(), x.cos())),
            ("cos(x)", |x| (x.cos(), -x.sin())),
            ("tan(x)", |x| (x.tan(), 1.0 / (x.cos() * x.cos()))),
            ("exp(x)", |x| (x.exp(), x.exp())),
            ("log(x)", |x| (x.ln(), 1.0 / x)),
            ("sqrt(x)", |x| (x.sqrt(), 0.5 / x.sqrt())),
            ("abs(-x)", |x| (x, 1.0)),
            ("x^3", |x| (x * x * x, 3.0 * x * x)),
            ("pow(x, 3)", |x| (x * x * x, 3.0 * x * x)),
            ("x^2.5", |x| (x.powf(2.5), 2.5 * x.powf(1.5))),
            ("2^x", |x| (2f64.powf(x), 2f64.powf(x) * 2f64.ln())),
            ("tanh(x)", |x| (x.tanh(), 1.0 - x.tanh() * x.tanh())),
            ("atan(x)", |x| (x.atan(), 1.0 / (1.0 + x * x))),
            ("atan2(1, x)", |x| (1f64.atan2(x), -1.0 / (1.0 + x * x))),
        ];
        for (src, f) in cases {
            let e = Expr::parse(src, &t).expect("parses");
            let x = 0.7;
            let d = e.eval(&[
                Dual64::from(x).derivative(),
                Dual64::from(0.0),
                Dual64::from(0.0),
                Dual64::from(0.0),
            ]);
            let (v, dv) = f(x);
            assert!((d.re - v).abs() <= 1e-15 * v.abs().max(1.0), "{src}: {} vs {v}", d.re);
            assert!(
                (d.eps - dv).abs() <= 1e-14 * dv.abs().max(1.0),
                "{src}: {} vs {dv}",
                d.eps
            );
        }
        assert!(matches!(
            Expr::parse("x^3", &t).expect("ok").nodes.last(),
            Some(Node::PowI(_, 3))
        ));
    }

    #[test]
    fn hessian_of_kepler_lagrangian() {
        let mut t = SymbolTable::new();
        for n in ["x", "y"] {
            t.variable(n).expect("fresh");
        }
        let e = Expr::parse("0.5*(x^2 + y^2) + 1/sqrt(x^2 + y^2)", &t).expect("parses");
        let p = nalgebra::SVector::<f64, 2>::new(0.6, -0.8);
        let (_, _, h) = num_dual::hessian(
            |v: nalgebra::SVector<num_dual::Dual2SVec64<2>, 2>| e.eval(&[v[0], v[1]]),
            &p,
        );
        let r2: f64 = p.norm_squared();
        let r = r2.sqrt();
        for i in 0..2 {
            for j in 0..2 {
                let delta = if i == j { 1.0 } else { 0.0 };
                let exact = delta + 3.0 * p[i] * p[j] / r.powi(5) - delta / r.powi(3);
                assert!((h[(i, j)] - exact).abs() <= 1e-14 * exact.abs().max(1.0), "{i}{j}");
            }
        }
    }

    #[test]
    fn errors_point_at_the_fault() {
        let t = table();
        let cases = [
            ("0.5*(x_dot^2 + z^2)", "unknown variable `z`", 16),
            ("foo(x)", "unknown function `foo`", 1),
            ("sin(x, y)", "takes 1 argument", 1),
            ("2 +", "expected a number", 4),
            ("(1+2", "expected `)`", 5),
            ("1+2)", "unbalanced", 4),
            ("1..2", "invalid number", 1),
            ("", "empty", 1),
        ];
        for (src, msg, column) in cases {
            let e = Expr::parse(src, &t).expect_err(src);
            assert!(e.message.contains(msg), "{src}: {}", e.message);
            assert_eq!(e.column, column, "{src}: {e}");
            assert!(e.to_string().contains('^'));
        }
        let mut t = table();
        assert!(t.variable("x").is_err());
        assert!(t.constant("c", 1.0).is_err());
    }

    #[test]
    fn constants_are_folded() {
        let e = Expr::parse("2*3 + x", &table()).expect("parses");
        assert!(e.nodes.contains(&Node::Const(6.0)));
        assert_eq!(e.used_variables(), vec!["x".to_string()]);
    }
}
