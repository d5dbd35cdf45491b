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

use std::fmt;

use num_dual::DualNum;

/// Deepest nesting of parentheses, signs, powers and calls the parser accepts.
const MAX_NESTING: usize = 256;
/// Tallest expression tree accepted, bounding the recursion of [`Expr::eval`].
const MAX_HEIGHT: usize = 128;
/// Shortest sequence `a + b + …` (counted in operators) evaluated as a loop
/// instead of a left-leaning tree: trees evaluate faster, loops keep long
/// sums within [`MAX_HEIGHT`].
const MIN_CHAIN: usize = 8;

/// What is wrong with a symbol declaration or an expression.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ExprErrorKind {
    /// The expression is empty or blank.
    Empty,
    /// A name that is neither a variable nor a constant of the symbol table.
    UnknownVariable(String),
    /// A call of a function the language does not have.
    UnknownFunction(String),
    /// A function name used without an argument list.
    NotCalled(String),
    /// A function called with the wrong number of arguments.
    WrongArity {
        /// The function.
        function: String,
        /// Arguments it takes.
        expected: usize,
        /// Arguments given.
        found: usize,
    },
    /// A malformed or out-of-range number (also a non-finite constant).
    InvalidNumber(String),
    /// A number, name or `(` was expected; `None` means the input ended.
    ExpectedOperand(Option<char>),
    /// A `(` that is never closed (the position is that of the `(`).
    UnclosedParen,
    /// A `)` without a matching `(`.
    UnmatchedParen,
    /// Something other than what the grammar allows here.
    Unexpected {
        /// What would have been valid.
        expected: &'static str,
        /// What was found.
        found: char,
    },
    /// A name declared twice in a [`SymbolTable`].
    DuplicateSymbol(String),
    /// A declared name that expressions could never refer to.
    InvalidName(String),
    /// Nesting deeper than the parser accepts, or a tree taller than evaluation allows.
    TooDeep,
}

impl fmt::Display for ExprErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Empty => write!(f, "empty expression"),
            Self::UnknownVariable(n) => write!(f, "unknown variable `{n}`"),
            Self::UnknownFunction(n) => write!(f, "unknown function `{n}`"),
            Self::NotCalled(n) => write!(f, "`{n}` is a function: call it as `{n}(...)`"),
            Self::WrongArity {
                function,
                expected,
                found,
            } => {
                let s = if *expected == 1 { "" } else { "s" };
                write!(f, "`{function}` takes {expected} argument{s}, found {found}")
            }
            Self::InvalidNumber(t) => write!(f, "invalid number `{t}`"),
            Self::ExpectedOperand(None) => write!(f, "expected a number, name or `(`, found the end of the input"),
            Self::ExpectedOperand(Some(c)) => write!(f, "expected a number, name or `(`, found `{c}`"),
            Self::UnclosedParen => write!(f, "unclosed `(`"),
            Self::UnmatchedParen => write!(f, "unmatched `)`"),
            Self::Unexpected { expected, found } => write!(f, "expected {expected}, found `{found}`"),
            Self::DuplicateSymbol(n) => write!(f, "`{n}` is declared twice"),
            Self::InvalidName(n) => write!(f, "`{n}` is not a valid name"),
            Self::TooDeep => write!(f, "expression nested too deeply"),
        }
    }
}

/// An error with its position: byte offset, and 1-based line and column.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExprError {
    /// What is wrong.
    pub kind: ExprErrorKind,
    /// Byte offset of the fault in `source`.
    pub offset: usize,
    /// 1-based line of the fault (always 1 for a one-line source).
    pub line: usize,
    /// 1-based column of the fault within its line, in characters.
    pub column: usize,
    /// The text the position refers to (for a symbol declaration, the name).
    pub source: String,
}

impl ExprError {
    fn new(kind: ExprErrorKind, source: &str, offset: usize) -> Self {
        let offset = offset.min(source.len());
        let before = &source[..offset];
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        ExprError {
            kind,
            offset,
            line: before.matches('\n').count() + 1,
            column: before[line_start..].chars().count() + 1,
            source: source.to_string(),
        }
    }
}

impl fmt::Display for ExprError {
    /// The message, then the offending line with a caret under the fault.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.source.contains('\n') {
            writeln!(f, "{} at line {}, column {}", self.kind, self.line, self.column)?;
        } else {
            writeln!(f, "{} at column {}", self.kind, self.column)?;
        }
        let text = self.source.lines().nth(self.line.saturating_sub(1)).unwrap_or("");
        let pad: String = text
            .chars()
            .take(self.column.saturating_sub(1))
            .map(|c| if c == '\t' { '\t' } else { ' ' })
            .collect();
        writeln!(f, "  {text}")?;
        write!(f, "  {pad}^")
    }
}

impl std::error::Error for ExprError {}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Symbol {
    Variable(usize),
    Constant(f64),
}

/// The names expressions may use: variables, numbered by slot in declaration
/// order, and constants, which are folded into expressions when they are parsed.
#[derive(Debug, Clone, Default)]
pub struct SymbolTable {
    entries: Vec<(String, Symbol)>,
    variables: usize,
}

impl SymbolTable {
    /// An empty table.
    pub fn new() -> Self {
        Self::default()
    }

    fn declare(&mut self, name: &str, symbol: Symbol) -> Result<(), ExprError> {
        let valid = name.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
            && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
        let kind = if !valid {
            ExprErrorKind::InvalidName(name.to_string())
        } else if self.lookup(name).is_some() {
            ExprErrorKind::DuplicateSymbol(name.to_string())
        } else {
            self.entries.push((name.to_string(), symbol));
            return Ok(());
        };
        Err(ExprError::new(kind, name, 0))
    }

    /// Declare a variable and return its slot: `0, 1, 2, …` in declaration order.
    /// Fails if the name is taken or is not an identifier.
    pub fn variable(&mut self, name: &str) -> Result<usize, ExprError> {
        let slot = self.variables;
        self.declare(name, Symbol::Variable(slot))?;
        self.variables += 1;
        Ok(slot)
    }

    /// Declare a named constant. Fails if the name is taken or is not an
    /// identifier, or if the value is not finite.
    pub fn constant(&mut self, name: &str, value: f64) -> Result<(), ExprError> {
        if !value.is_finite() {
            return Err(ExprError::new(
                ExprErrorKind::InvalidNumber(format!("{name} = {value}")),
                name,
                0,
            ));
        }
        self.declare(name, Symbol::Constant(value))
    }

    /// Number of declared variables: the length of the array [`Expr::eval`] expects.
    pub fn len_variables(&self) -> usize {
        self.variables
    }

    fn lookup(&self, name: &str) -> Option<Symbol> {
        self.entries.iter().find(|(n, _)| n == name).map(|&(_, s)| s)
    }
}

/// A one-argument operation.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Func {
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
    fn apply<D: DualNum<Primitive = f64> + Copy>(self, x: D) -> D {
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
enum Op {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    Atan2,
}

impl Op {
    #[inline]
    fn apply<D: DualNum<Primitive = f64> + Copy>(self, a: D, b: D) -> D {
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
    fn apply_rhs<D: DualNum<Primitive = f64> + Copy>(self, a: D, c: f64) -> D {
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
    fn apply_lhs<D: DualNum<Primitive = f64> + Copy>(self, c: f64, b: D) -> D {
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

/// Expression tree node; children are indices into the node array.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Node {
    Var(usize),
    Const(f64),
    Unary(Func, usize),
    Binary(Op, usize, usize),
    /// `first op₁ x₁ op₂ x₂ …` evaluated left to right, links in `links[start..end]`.
    Chain(usize, usize, usize),
}

/// A parsed, compiled expression. Evaluating it does not allocate: it walks a
/// flat, constant-folded node array over the variable slots of the
/// [`SymbolTable`] it was parsed against, recursing at most 128 levels deep.
#[derive(Debug, Clone, PartialEq)]
pub struct Expr {
    source: String,
    nodes: Vec<Node>,
    links: Vec<(Op, usize)>,
    root: usize,
    used: Vec<String>,
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

/// The built-in functions: name → (arity, operation).
fn builtin(name: &str) -> Option<(usize, Result<Func, Op>)> {
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

/// Recursive-descent parser building a constant-folded tree; each node is
/// stored with its height (the recursion depth of its evaluation).
struct Parser<'a> {
    src: &'a str,
    pos: usize,
    symbols: &'a SymbolTable,
    nodes: Vec<(Node, usize)>,
    links: Vec<(Op, usize)>,
    used: Vec<String>,
    nesting: usize,
}

impl Parser<'_> {
    fn error(&self, kind: ExprErrorKind, offset: usize) -> ExprError {
        ExprError::new(kind, self.src, offset)
    }

    /// Skip whitespace and return the next character without consuming it.
    fn peek(&mut self) -> Option<char> {
        let rest = &self.src[self.pos..];
        self.pos += rest.len() - rest.trim_start().len();
        self.src[self.pos..].chars().next()
    }

    fn bump(&mut self) {
        self.pos += self.src[self.pos..].chars().next().map_or(0, char::len_utf8);
    }

    fn constant(&self, i: usize) -> Option<f64> {
        match self.nodes[i].0 {
            Node::Const(c) => Some(c),
            _ => None,
        }
    }

    /// Add a node, folding it if its operands are constants. Fails if the
    /// tree grows taller than [`MAX_HEIGHT`].
    fn push(&mut self, node: Node) -> Result<usize, ExprError> {
        let folded = match node {
            Node::Unary(f, a) => self.constant(a).map(|x| f.apply(x)),
            Node::Binary(op, a, b) => self.constant(a).zip(self.constant(b)).map(|(x, y)| op.apply(x, y)),
            Node::Var(_) | Node::Const(_) | Node::Chain(..) => None,
        };
        let entry = match (folded, node) {
            (Some(c), _) => (Node::Const(c), 1),
            (None, Node::Var(_) | Node::Const(_)) => (node, 1),
            (None, Node::Unary(_, a)) => (node, self.nodes[a].1 + 1),
            (None, Node::Binary(_, a, b)) => (node, self.nodes[a].1.max(self.nodes[b].1) + 1),
            (None, Node::Chain(first, start, end)) => {
                let links = self.links[start..end].iter().map(|&(_, b)| self.nodes[b].1);
                (node, links.fold(self.nodes[first].1, usize::max) + 1)
            }
        };
        if entry.1 > MAX_HEIGHT {
            return Err(self.error(ExprErrorKind::TooDeep, self.pos));
        }
        self.nodes.push(entry);
        Ok(self.nodes.len() - 1)
    }

    /// `base ^ exponent`, specialised on a constant exponent.
    fn power_node(&mut self, base: usize, exponent: usize) -> Result<usize, ExprError> {
        match self.constant(exponent) {
            Some(n) if n.fract() == 0.0 && n.abs() <= f64::from(i32::MAX) => {
                self.push(Node::Unary(Func::PowI(n as i32), base))
            }
            Some(n) => self.push(Node::Unary(Func::PowF(n), base)),
            None => self.push(Node::Binary(Op::Pow, base, exponent)),
        }
    }

    /// A left-associative sequence `operand { op operand }` with the two
    /// operators in `ops`. A constant prefix is folded; from [`MIN_CHAIN`]
    /// operators on, a [`Node::Chain`] keeps long sums and products shallow.
    fn sequence(
        &mut self,
        ops: [(char, Op); 2],
        operand: fn(&mut Self) -> Result<usize, ExprError>,
    ) -> Result<usize, ExprError> {
        let mut first = operand(self)?;
        let mut rest = Vec::new();
        loop {
            let op = match self.peek() {
                Some(c) if c == ops[0].0 => ops[0].1,
                Some(c) if c == ops[1].0 => ops[1].1,
                _ => break,
            };
            self.bump();
            let rhs = operand(self)?;
            if rest.is_empty() && self.constant(first).is_some() && self.constant(rhs).is_some() {
                first = self.push(Node::Binary(op, first, rhs))?;
            } else {
                rest.push((op, rhs));
            }
        }
        if rest.len() < MIN_CHAIN {
            return rest
                .into_iter()
                .try_fold(first, |lhs, (op, rhs)| self.push(Node::Binary(op, lhs, rhs)));
        }
        let start = self.links.len();
        self.links.extend(rest);
        self.push(Node::Chain(first, start, self.links.len()))
    }

    fn expr(&mut self) -> Result<usize, ExprError> {
        self.sequence([('+', Op::Add), ('-', Op::Sub)], Self::term)
    }

    fn term(&mut self) -> Result<usize, ExprError> {
        self.sequence([('*', Op::Mul), ('/', Op::Div)], Self::factor)
    }

    /// Every recursion of the grammar passes through here: the nesting guard.
    fn factor(&mut self) -> Result<usize, ExprError> {
        if self.nesting == MAX_NESTING {
            return Err(self.error(ExprErrorKind::TooDeep, self.pos));
        }
        self.nesting += 1;
        let result = match self.peek() {
            Some('-') => {
                self.bump();
                self.factor().and_then(|a| self.push(Node::Unary(Func::Neg, a)))
            }
            Some('+') => {
                self.bump();
                self.factor()
            }
            _ => self.power(),
        };
        self.nesting -= 1;
        result
    }

    fn power(&mut self) -> Result<usize, ExprError> {
        let base = self.atom()?;
        if self.peek() != Some('^') {
            return Ok(base);
        }
        self.bump();
        let exponent = self.factor()?;
        self.power_node(base, exponent)
    }

    fn atom(&mut self) -> Result<usize, ExprError> {
        let next = self.peek();
        let start = self.pos;
        match next {
            Some('(') => {
                self.bump();
                let inner = self.expr()?;
                self.close(start, "`)` or an operator")?;
                Ok(inner)
            }
            Some(c) if c.is_ascii_digit() || c == '.' => self.number(start),
            Some(c) if c.is_ascii_alphabetic() || c == '_' => self.name(start),
            _ => Err(self.error(ExprErrorKind::ExpectedOperand(next), start)),
        }
    }

    /// Consume the `)` matching the `(` at `open`.
    fn close(&mut self, open: usize, expected: &'static str) -> Result<(), ExprError> {
        match self.peek() {
            Some(')') => {
                self.bump();
                Ok(())
            }
            None => Err(self.error(ExprErrorKind::UnclosedParen, open)),
            Some(found) => Err(self.error(ExprErrorKind::Unexpected { expected, found }, self.pos)),
        }
    }

    fn number(&mut self, start: usize) -> Result<usize, ExprError> {
        let bytes = self.src.as_bytes();
        let scan = |mut i: usize, ok: fn(u8) -> bool| {
            while i < bytes.len() && ok(bytes[i]) {
                i += 1;
            }
            i
        };
        let mut end = scan(start, |b| b.is_ascii_digit() || b == b'.');
        if end < bytes.len() && matches!(bytes[end], b'e' | b'E') {
            end += 1;
            if end < bytes.len() && matches!(bytes[end], b'+' | b'-') {
                end += 1;
            }
            end = scan(end, |b| b.is_ascii_digit());
        }
        let text = &self.src[start..end];
        match text.parse::<f64>() {
            Ok(value) if value.is_finite() => {
                self.pos = end;
                self.push(Node::Const(value))
            }
            _ => Err(self.error(ExprErrorKind::InvalidNumber(text.to_string()), start)),
        }
    }

    fn name(&mut self, start: usize) -> Result<usize, ExprError> {
        let rest = &self.src[start..];
        let len = rest
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .unwrap_or(rest.len());
        let name = &rest[..len];
        self.pos = start + len;
        if self.peek() == Some('(') {
            let open = self.pos;
            self.bump();
            return self.call(name, start, open);
        }
        match self.symbols.lookup(name) {
            Some(Symbol::Variable(slot)) => {
                if !self.used.iter().any(|u| u == name) {
                    self.used.push(name.to_string());
                }
                self.push(Node::Var(slot))
            }
            Some(Symbol::Constant(c)) => self.push(Node::Const(c)),
            None if builtin(name).is_some() => Err(self.error(ExprErrorKind::NotCalled(name.to_string()), start)),
            None => Err(self.error(ExprErrorKind::UnknownVariable(name.to_string()), start)),
        }
    }

    /// A call of `name` (at `start`) whose `(` at `open` has been consumed.
    fn call(&mut self, name: &str, start: usize, open: usize) -> Result<usize, ExprError> {
        let Some((arity, op)) = builtin(name) else {
            return Err(self.error(ExprErrorKind::UnknownFunction(name.to_string()), start));
        };
        let mut args = Vec::with_capacity(arity);
        if self.peek() == Some(')') {
            self.bump();
        } else {
            loop {
                args.push(self.expr()?);
                if self.peek() != Some(',') {
                    break self.close(open, "`,`, `)` or an operator")?;
                }
                self.bump();
            }
        }
        match (op, args.as_slice()) {
            (Ok(f), &[a]) => self.push(Node::Unary(f, a)),
            (Err(Op::Pow), &[a, b]) => self.power_node(a, b),
            (Err(op), &[a, b]) => self.push(Node::Binary(op, a, b)),
            _ => {
                let function = name.to_string();
                let kind = ExprErrorKind::WrongArity {
                    function,
                    expected: arity,
                    found: args.len(),
                };
                Err(self.error(kind, start))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::SVector;
    use num_dual::{Dual2SVec64, Dual64};

    fn table() -> SymbolTable {
        let mut t = SymbolTable::new();
        for (slot, name) in ["x", "y", "x_dot", "y_dot"].into_iter().enumerate() {
            assert_eq!(t.variable(name).expect("fresh name"), slot);
        }
        t.constant("c", 0.5).expect("fresh name");
        t
    }

    fn value(src: &str) -> f64 {
        Expr::parse(src, &table()).expect(src).eval(&[2.0, 3.0, 0.5, -1.0])
    }

    fn error(src: &str) -> ExprError {
        Expr::parse(src, &table()).expect_err(src)
    }

    #[test]
    fn precedence_and_associativity() {
        let cases = [
            ("2^3^2", 512.0),
            ("-2^2", -4.0),
            ("2*-3", -6.0),
            ("(1+2)*3", 9.0),
            ("8/4/2", 1.0),
            ("1-2-3", -4.0),
            ("2^-1", 0.5),
            ("x^y^2", 512.0),
            ("-x^2", -4.0),
            ("x*-y", -6.0),
            ("(x+1)*y", 9.0),
            ("8/x/2", 2.0),
            ("x-y-1", -2.0),
            ("x - -y + +c", 5.5),
            ("10 - x*y", 4.0),
            ("1 + x*y", 7.0),
            ("3*x^2", 12.0),
            ("1e-3*1E3 + .5 + 2. - c", 3.0),
            ("x+x+x+x+x+x+x+x+x+x - y*y*y*y*y*y*y*y*y/y/y/y/y/y/y/y/y", 17.0),
        ];
        for (src, want) in cases {
            assert_eq!(value(src), want, "{src}");
        }
    }

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

    #[test]
    fn errors_carry_kind_and_column() {
        use ExprErrorKind as K;
        let arity = |function: &str, expected, found| K::WrongArity {
            function: function.into(),
            expected,
            found,
        };
        let unexpected = |expected, found| K::Unexpected { expected, found };
        let cases = [
            ("0.5*(x_dot^2 + z^2)", K::UnknownVariable("z".into()), 16),
            ("2 + foo(x)", K::UnknownFunction("foo".into()), 5),
            ("sin(x, y)", arity("sin", 1, 2), 1),
            ("1 + pow(x)", arity("pow", 2, 1), 5),
            ("atan2()", arity("atan2", 2, 0), 1),
            ("2 +", K::ExpectedOperand(None), 4),
            ("2 * )", K::ExpectedOperand(Some(')')), 5),
            ("(1+2", K::UnclosedParen, 1),
            ("x*(1+(2)", K::UnclosedParen, 3),
            ("sin(x", K::UnclosedParen, 4),
            ("1+2)", K::UnmatchedParen, 4),
            ("1..2", K::InvalidNumber("1..2".into()), 1),
            ("x + 1e", K::InvalidNumber("1e".into()), 5),
            ("1e999", K::InvalidNumber("1e999".into()), 1),
            ("", K::Empty, 1),
            ("  ", K::Empty, 1),
            ("2 x", unexpected("an operator", 'x'), 3),
            ("(1 2)", unexpected("`)` or an operator", '2'), 4),
            ("pow(x; 2)", unexpected("`,`, `)` or an operator", ';'), 6),
            ("x·y + z", unexpected("an operator", '·'), 2),
            ("é + z", K::ExpectedOperand(Some('é')), 1),
            ("x +\u{a0}\u{a0}z", K::UnknownVariable("z".into()), 6),
            ("x + sqrt", K::NotCalled("sqrt".into()), 5),
        ];
        for (src, kind, column) in cases {
            let e = error(src);
            assert_eq!((&e.kind, e.column, e.line), (&kind, column, 1), "{src}");
            assert_eq!(src[..e.offset].chars().count() + 1, column, "{src}");
        }
        let shown = error("0.5*(x_dot^2 + z^2)").to_string();
        assert_eq!(
            shown,
            "unknown variable `z` at column 16\n  0.5*(x_dot^2 + z^2)\n                 ^"
        );
        let e = error("x +\n\t2 * q");
        assert_eq!((e.line, e.column, e.offset), (2, 6, 9));
        assert_eq!(
            e.to_string(),
            "unknown variable `q` at line 2, column 6\n  \t2 * q\n  \t    ^"
        );
    }

    #[test]
    fn symbol_table_errors() {
        let mut t = table();
        assert_eq!(
            t.variable("x").expect_err("taken").kind,
            ExprErrorKind::DuplicateSymbol("x".into())
        );
        assert_eq!(
            t.constant("y", 1.0).expect_err("taken").kind,
            ExprErrorKind::DuplicateSymbol("y".into())
        );
        assert_eq!(
            t.variable("c").expect_err("taken").kind,
            ExprErrorKind::DuplicateSymbol("c".into())
        );
        let e = t.constant("x", 2.0).expect_err("taken");
        assert_eq!(
            (e.column, e.to_string()),
            (1, "`x` is declared twice at column 1\n  x\n  ^".to_string())
        );
        for bad in ["", "x dot", "2x", "x-1"] {
            assert_eq!(
                t.variable(bad).expect_err(bad).kind,
                ExprErrorKind::InvalidName(bad.into())
            );
        }
        assert!(matches!(
            t.constant("k", f64::NAN),
            Err(ExprError {
                kind: ExprErrorKind::InvalidNumber(_),
                ..
            })
        ));
        assert_eq!(t.len_variables(), 4);
        assert_eq!(t.variable("z").expect("fresh"), 4);
    }

    #[test]
    fn folding_and_bookkeeping() {
        let e = Expr::parse("2*3*c + y*x + sin(0)*x - x", &table()).expect("parses");
        assert_eq!(e.source(), "2*3*c + y*x + sin(0)*x - x");
        assert_eq!(e.used_variables(), ["y", "x"]);
        let mut n = e.root;
        while let Node::Binary(_, lhs, _) = e.nodes[n] {
            n = lhs;
        }
        assert_eq!(e.nodes[n], Node::Const(3.0));
        assert_eq!(e.eval(&[2.0, 3.0]), 7.0);
        let e = Expr::parse("1 + 2 + x + 3 + 4 + 5 + 6 + 7 + 8 + 9 + 10", &table()).expect("parses");
        assert!(matches!(e.nodes[e.root], Node::Chain(f, 0, 9) if e.nodes[f] == Node::Const(3.0)));
        assert_eq!(e.eval(&[1.0]), 56.0);
        let e = Expr::parse("-(2^0.5 * atan2(1, 1)) + c", &table()).expect("parses");
        assert_eq!(e.nodes[e.root], Node::Const(-(2f64.sqrt() * 1f64.atan2(1.0)) + 0.5));
        assert!(e.used_variables().is_empty());
    }

    #[test]
    fn size_limits() {
        // Long sums evaluate as loops: no deep recursion.
        let long = format!("x{}", " + x".repeat(100_000));
        assert_eq!(Expr::parse(&long, &table()).expect("parses").eval(&[0.5]), 50_000.5);
        let nested = |open: &str, n| format!("{}x{}", open.repeat(n), ")".repeat(n));
        assert_eq!(error(&nested("(", 100_000)).kind, ExprErrorKind::TooDeep);
        assert_eq!(error(&nested("sin(", MAX_HEIGHT)).kind, ExprErrorKind::TooDeep);
        let tallest = Expr::parse(&nested("sin(", MAX_HEIGHT - 1), &table()).expect("parses");
        let vars: Vec<Dual2SVec64<4>> = (0..4).map(|i| Dual2SVec64::from(0.1 * i as f64)).collect();
        assert!(tallest.eval(&vars).re.abs() < 1.0);
    }
}
