//! The built-in operations, applied to any automatic-differentiation scalar,
//! and the node of a compiled expression that refers to them.

use num_dual::DualNum;

/// A one-argument operation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Func {
    Neg,
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
    PowI(i32),
    PowF(f64),
}

impl Func {
    #[inline]
    pub(super) fn apply<D: DualNum<Primitive = f64> + Copy>(self, x: D) -> D {
        match self {
            Func::Neg => -x,
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
            Func::PowI(n) => x.powi(n),
            Func::PowF(p) => x.powf(p),
        }
    }
}

/// A two-argument operation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Op {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    Atan2,
}

impl Op {
    #[inline]
    pub(super) fn apply<D: DualNum<Primitive = f64> + Copy>(self, a: D, b: D) -> D {
        match self {
            Op::Add => a + b,
            Op::Sub => a - b,
            Op::Mul => a * b,
            Op::Div => a / b,
            Op::Pow => a.powd(b),
            Op::Atan2 => a.atan2(b),
        }
    }

    /// `a op c` with a constant right operand.
    #[inline]
    pub(super) fn apply_rhs<D: DualNum<Primitive = f64> + Copy>(self, a: D, c: f64) -> D {
        match self {
            Op::Add => a + c,
            Op::Sub => a - c,
            Op::Mul => a * c,
            Op::Div => a / c,
            // Not produced by the parser: constant exponents become `PowI`/`PowF`.
            Op::Pow => a.powd(D::from(c)),
            Op::Atan2 => a.atan2(D::from(c)),
        }
    }

    /// `c op b` with a constant left operand.
    #[inline]
    pub(super) fn apply_lhs<D: DualNum<Primitive = f64> + Copy>(self, c: f64, b: D) -> D {
        match self {
            Op::Add => b + c,
            Op::Sub => -b + c,
            Op::Mul => b * c,
            Op::Div => b.recip() * c,
            Op::Pow => D::from(c).powd(b),
            Op::Atan2 => D::from(c).atan2(b),
        }
    }
}

/// The names of the built-in functions, as the evaluator knows them.
pub const FUNCTIONS: [&str; 16] = [
    "sin", "cos", "tan", "exp", "log", "ln", "sqrt", "abs", "sinh", "cosh", "tanh", "asin", "acos", "atan", "pow",
    "atan2",
];

/// The built-in constants: names that are not declared in the symbol table
/// mean these (a declared name takes precedence).
pub const CONSTANTS: [(&str, f64); 2] = [("pi", std::f64::consts::PI), ("e", std::f64::consts::E)];

/// The built-in functions: name → (arity, operation).
pub(super) fn builtin(name: &str) -> Option<(usize, Result<Func, Op>)> {
    let f = match name {
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
        "pow" => return Some((2, Err(Op::Pow))),
        "atan2" => return Some((2, Err(Op::Atan2))),
        _ => return None,
    };
    Some((1, Ok(f)))
}

/// Expression tree node; children are indices into the node array.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Node {
    Var(usize),
    Const(f64),
    Unary(Func, usize),
    Binary(Op, usize, usize),
    /// `first op₁ x₁ op₂ x₂ …` evaluated left to right, links in `links[start..end]`.
    Chain(usize, usize, usize),
}
