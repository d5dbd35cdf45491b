//! The symbol table: the variables and constants an expression may name.

use super::{ExprError, ExprErrorKind};

#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Symbol {
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

    /// Number of declared variables: the length of the array [`Expr::eval`](super::Expr::eval) expects.
    pub fn len_variables(&self) -> usize {
        self.variables
    }

    pub(super) fn lookup(&self, name: &str) -> Option<Symbol> {
        self.entries.iter().find(|(n, _)| n == name).map(|&(_, s)| s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::expr::test_support::table;

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
}
