//! The error type of the expression language: what went wrong and where in the source.

use std::fmt;

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
    /// A name declared twice in a [`SymbolTable`](super::SymbolTable).
    DuplicateSymbol(String),
    /// A declared name that expressions could never refer to.
    InvalidName(String),
    /// Nesting deeper than the parser accepts, or a tree taller than evaluation allows.
    TooDeep,
}

/// A name or token as a message shows it: at most 40 characters, then `…`.
fn clip(text: &str) -> String {
    match text.char_indices().nth(40) {
        Some((cut, _)) => format!("{}…", &text[..cut]),
        None => text.to_string(),
    }
}

impl fmt::Display for ExprErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Empty => write!(f, "empty expression"),
            Self::UnknownVariable(n) => write!(f, "unknown variable `{}`", clip(n)),
            Self::UnknownFunction(n) => write!(
                f,
                "unknown function `{}` (the functions are {})",
                clip(n),
                super::ops::FUNCTIONS.join(", ")
            ),
            Self::NotCalled(n) => write!(f, "`{n}` is a function: call it as `{n}(...)`", n = clip(n)),
            Self::WrongArity {
                function,
                expected,
                found,
            } => {
                let s = if *expected == 1 { "" } else { "s" };
                write!(f, "`{function}` takes {expected} argument{s}, found {found}")
            }
            Self::InvalidNumber(t) => write!(f, "invalid number `{}`", clip(t)),
            Self::ExpectedOperand(None) => write!(f, "expected a number, name or `(`, found the end of the input"),
            Self::ExpectedOperand(Some(c)) => write!(f, "expected a number, name or `(`, found `{c}`"),
            Self::UnclosedParen => write!(f, "unclosed `(`"),
            Self::UnmatchedParen => write!(f, "unmatched `)`"),
            Self::Unexpected { expected, found } => write!(f, "expected {expected}, found `{found}`"),
            Self::DuplicateSymbol(n) => write!(f, "`{}` is declared twice", clip(n)),
            Self::InvalidName(n) => write!(f, "`{}` is not a valid name", clip(n)),
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
    pub(super) fn new(kind: ExprErrorKind, source: &str, offset: usize) -> Self {
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

/// Characters of the offending line shown before and after the fault.
const CONTEXT: (usize, usize) = (60, 30);

impl fmt::Display for ExprError {
    /// The message, then the offending line (at most 60 characters before
    /// the fault and 30 after it, elided with `…`: a huge input is not
    /// echoed) with a caret under the fault.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.source.contains('\n') {
            writeln!(f, "{} at line {}, column {}", self.kind, self.line, self.column)?;
        } else {
            writeln!(f, "{} at column {}", self.kind, self.column)?;
        }
        let text = self.source.lines().nth(self.line.saturating_sub(1)).unwrap_or("");
        let at = self.column.saturating_sub(1);
        let first = at.saturating_sub(CONTEXT.0);
        let shown: String = text.chars().skip(first).take(at - first + CONTEXT.1).collect();
        let (lead, tail) = (
            if first > 0 { "…" } else { "" },
            if text.chars().count() > at + CONTEXT.1 {
                "…"
            } else {
                ""
            },
        );
        let pad: String = lead
            .chars()
            .chain(shown.chars())
            .take(at - first + lead.chars().count())
            .map(|c| if c == '\t' { '\t' } else { ' ' })
            .collect();
        writeln!(f, "  {lead}{shown}{tail}")?;
        write!(f, "  {pad}^")
    }
}

impl std::error::Error for ExprError {}
