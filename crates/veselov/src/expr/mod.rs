//! Mathematical expressions for user-defined systems: parsed and compiled once,
//! then evaluated generically over any automatic-differentiation scalar, so every
//! derivative of a Lagrangian or force written as text is exact.
//!
//! # Grammar (EBNF)
//! ```text
//! expr   = term , { ( "+" | "-" ) , term } ;
//! term   = factor , { ( "*" | "/" ) , factor } ;
//! factor = ( "-" | "+" ) , factor | power ;
//! power  = atom , [ "^" , factor ] ;
//! atom   = number | name | call | "(" , expr , ")" ;
//! call   = name , "(" , [ expr , { "," , expr } ] , ")" ;
//! number = ( digits , [ "." , [ digits ] ] | "." , digits ) , [ ( "e" | "E" ) , [ "+" | "-" ] , digits ] ;
//! name   = ( letter | "_" ) , { letter | digit | "_" } ;
//! ```
//! Whitespace between tokens is ignored. `^` is right-associative (`2^3^2 = 2^9`)
//! and binds tighter than a sign on its left but accepts one on its right:
//! `-x^2 = -(x^2)`, `2^-1 = 0.5`.
//!
//! # Functions
//! `sin cos tan exp log sqrt abs sinh cosh tanh asin acos atan` (one argument;
//! `log` is the natural logarithm, `ln` is accepted as an alias) and
//! `pow(a, b)`, `atan2(y, x)` (two arguments). `abs` is not differentiable at 0:
//! there its derivative is taken as `+1` (at `+0.0`) or `-1` (at `-0.0`).
//!
//! # Constants
//! `pi` and `e` are built in; a variable or constant declared with the same
//! name takes precedence (a coordinate may be called `e`).
//!
//! # Powers
//! `a^b` and `pow(a, b)` compile according to the exponent: an integer-valued
//! constant uses `powi` (exact, fast), any other constant `powf`, and a
//! non-constant exponent `powd`, i.e. `exp(b·ln a)`, which needs `a > 0`.
//!
//! # Names, compilation and evaluation
//! Names are resolved when parsing against a [`SymbolTable`]: variables become
//! slots of the array passed to [`Expr::eval`], constants are substituted and
//! every constant subexpression is folded (with constants `m` and `g`,
//! `2*m*g*x` multiplies `x` by one number). Folding never reorders operations:
//! `x*2*3` is evaluated as written. Constant operands stay plain `f64`, so
//! `c*x` scales a dual number rather than multiplying two.
//!
//! Evaluation is a recursive walk of a flat node array: no allocation per
//! call, recursion at most 128 levels deep (taller expressions are refused),
//! and sums or products of more than 8 operands are looped over rather than
//! nested. A postfix program run on a fixed-size stack array was measured as
//! the alternative (release build, Kepler Lagrangian, ns per call, tree walk
//! vs stack): `f64` 34 vs 22 and `Dual64` 38 vs 26, but `DualSVec64<2>` 47 vs
//! 91, `HyperDualSVec64<2, 2>` 72 vs 136 and `Dual2SVec64<4>` 130 vs 237. The
//! stack machine copies every result through memory, which costs more than it
//! saves once the scalar is a vector dual; the integrators evaluate with
//! those, so the tree walk is used.
//!
//! # Files
//! `error.rs` holds the error type, `symbols.rs` the symbol table, `ops.rs`
//! the built-in operations, `parser.rs` the parser and `eval.rs` the compiled
//! expression and its evaluation; this file holds the limits they share.

mod error;
mod eval;
mod ops;
mod parser;
mod symbols;

pub use error::{ExprError, ExprErrorKind};
pub use eval::Expr;
pub use ops::{CONSTANTS, FUNCTIONS};
pub use symbols::SymbolTable;

/// Deepest nesting of parentheses, signs, powers and calls the parser accepts.
pub const MAX_NESTING: usize = 256;
/// Tallest expression tree accepted, bounding the recursion of [`Expr::eval`].
pub const MAX_HEIGHT: usize = 128;
/// Shortest sequence `a + b + …` (counted in operators) evaluated as a loop
/// instead of a left-leaning tree: trees evaluate faster, loops keep long
/// sums within [`MAX_HEIGHT`].
const MIN_CHAIN: usize = 8;

/// Shared fixtures of the expression tests.
#[cfg(test)]
mod test_support {
    use super::{Expr, ExprError, SymbolTable};

    pub(super) fn table() -> SymbolTable {
        let mut t = SymbolTable::new();
        for (slot, name) in ["x", "y", "x_dot", "y_dot"].into_iter().enumerate() {
            assert_eq!(t.variable(name).expect("fresh name"), slot);
        }
        t.constant("c", 0.5).expect("fresh name");
        t
    }

    pub(super) fn value(src: &str) -> f64 {
        Expr::parse(src, &table()).expect(src).eval(&[2.0, 3.0, 0.5, -1.0])
    }

    pub(super) fn error(src: &str) -> ExprError {
        Expr::parse(src, &table()).expect_err(src)
    }
}
