//! Recursive-descent parser: source text to a constant-folded node array,
//! with names resolved against a symbol table and nesting bounded.

use super::ops::{CONSTANTS, Func, Node, Op, builtin};
use super::symbols::Symbol;
use super::{ExprError, ExprErrorKind, MAX_HEIGHT, MAX_NESTING, MIN_CHAIN, SymbolTable};

/// Recursive-descent parser building a constant-folded tree; each node is
/// stored with its height (the recursion depth of its evaluation).
pub(super) struct Parser<'a> {
    pub(super) src: &'a str,
    pub(super) pos: usize,
    pub(super) symbols: &'a SymbolTable,
    pub(super) nodes: Vec<(Node, usize)>,
    pub(super) links: Vec<(Op, usize)>,
    pub(super) used: Vec<String>,
    pub(super) nesting: usize,
}

impl Parser<'_> {
    pub(super) fn error(&self, kind: ExprErrorKind, offset: usize) -> ExprError {
        ExprError::new(kind, self.src, offset)
    }

    /// Skip whitespace and return the next character without consuming it.
    pub(super) fn peek(&mut self) -> Option<char> {
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

    pub(super) fn expr(&mut self) -> Result<usize, ExprError> {
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
            None if let Some(&(_, c)) = CONSTANTS.iter().find(|(n, _)| *n == name) => self.push(Node::Const(c)),
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
    use crate::expr::Expr;
    use crate::expr::test_support::{error, table, value};
    use num_dual::Dual2SVec64;

    /// A huge expression is not echoed: the message shows at most 60
    /// characters before the fault and 30 after it, and clips long names,
    /// with the caret still under the fault.
    #[test]
    fn messages_about_huge_inputs_stay_short() {
        let huge = format!("{}+ foo(x)", "x + ".repeat(250_000));
        let message = error(&huge).to_string();
        assert!(message.len() < 400, "{} bytes", message.len());
        assert!(message.contains("column 1000003"), "{message}");
        let lines: Vec<&str> = message.lines().collect();
        let caret = lines[2].chars().count() - 1;
        assert_eq!(lines[1].chars().nth(caret), Some('f'), "{message}");
        let name = "y".repeat(10_000);
        let message = error(&format!("x + {name}")).to_string();
        assert!(
            message.len() < 400 && message.contains("yyy…"),
            "{} bytes",
            message.len()
        );
        // A short expression is shown whole, caret under the fault.
        let message = error("2 + foo(x)").to_string();
        assert!(message.ends_with("  2 + foo(x)\n      ^"), "{message}");
    }

    /// `pi` and `e` are built in unless a declared name takes them; an unknown
    /// function's error lists the functions there are, each of which parses.
    #[test]
    fn built_in_constants_and_the_function_list() {
        assert_eq!(value("pi"), std::f64::consts::PI);
        assert_eq!(value("2*e^x"), 2.0 * std::f64::consts::E.powi(2));
        let mut t = SymbolTable::new();
        t.variable("e").expect("fresh");
        assert_eq!(
            Expr::parse("e + pi", &t).expect("parses").eval(&[1.0]),
            1.0 + std::f64::consts::PI
        );
        let message = error("2 + foo(x)").to_string();
        for f in crate::expr::FUNCTIONS {
            assert!(message.contains(f), "{message}");
            let arity = builtin(f).expect("listed functions exist").0;
            let call = if arity == 1 {
                format!("{f}(0.5)")
            } else {
                format!("{f}(0.5, 0.25)")
            };
            assert!(Expr::parse(&call, &table()).is_ok(), "{call}");
        }
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
