//! The array keys of every kind of scenario — vectors such as
//! `gravity = [0.0, 0.0, -9.81]`, lists such as `initial.q` — read as the
//! file gives them, whatever their length and entries, and checked in one
//! place against what the key expects: an array of the wrong length, or
//! with an entry that is not a finite number (or not a string, or not an
//! integer), is refused with an error naming the key (and the entry), for
//! example "`initial.velocity`: expected 3 numbers, got 6". The parser alone
//! would read a fixed-length array's first entries and drop the rest.

use std::marker::PhantomData;
use std::path::Path;

use serde::Deserialize;

use super::key_error;
use crate::error::CliError;

/// What an entry of an array key may be: a number ([`f64`]), a string
/// ([`String`], an expression) or an integer ([`i64`]).
pub trait Entry: Sized {
    /// The entries' name in a message, plural: "numbers".
    const PLURAL: &'static str;
    /// The JSON schema of one entry (for the key reference).
    fn entry_schema() -> serde_json::Value;
    /// The entry `v`, or what is wrong with it.
    fn entry(v: &toml::Value) -> Result<Self, String>;
}

impl Entry for f64 {
    const PLURAL: &'static str = "numbers";
    fn entry_schema() -> serde_json::Value {
        serde_json::json!({ "type": "number" })
    }
    /// A finite float, or an integer (as the nearest float).
    fn entry(v: &toml::Value) -> Result<Self, String> {
        match v {
            toml::Value::Integer(i) => Ok(*i as f64),
            toml::Value::Float(x) if x.is_finite() => Ok(*x),
            toml::Value::Float(x) => Err(format!("expected a finite number, got {x}")),
            other => Err(format!("expected a number, got {}", describe(other))),
        }
    }
}

impl Entry for String {
    const PLURAL: &'static str = "strings";
    fn entry_schema() -> serde_json::Value {
        serde_json::json!({ "type": "string" })
    }
    fn entry(v: &toml::Value) -> Result<Self, String> {
        match v {
            toml::Value::String(s) => Ok(s.clone()),
            other => Err(format!("expected a string, got {}", describe(other))),
        }
    }
}

impl Entry for i64 {
    const PLURAL: &'static str = "integers";
    fn entry_schema() -> serde_json::Value {
        serde_json::json!({ "type": "integer" })
    }
    fn entry(v: &toml::Value) -> Result<Self, String> {
        match v {
            toml::Value::Integer(i) => Ok(*i),
            other => Err(format!("expected an integer, got {}", describe(other))),
        }
    }
}

/// A value as a message quotes it: its kind and, for a scalar, the value
/// (a string cut to 40 characters).
fn describe(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => match s.char_indices().nth(40) {
            Some((cut, _)) => format!("the string \"{}…\"", &s[..cut]),
            None => format!("the string \"{s}\""),
        },
        toml::Value::Integer(i) => format!("the integer {i}"),
        toml::Value::Float(x) => format!("the number {x}"),
        toml::Value::Boolean(b) => format!("the boolean {b}"),
        toml::Value::Datetime(d) => format!("the date {d}"),
        toml::Value::Array(a) => format!("an array of {} entries", a.len()),
        toml::Value::Table(_) => "a table".to_string(),
    }
}

/// The entries of the array `raw` given for `key` in `file`: `lengths` lists
/// the lengths it may have (any length when empty), `note` follows the
/// count in the message ("expected 2 numbers{note}, got 3").
///
/// # Errors
/// A value that is not an array or has another length names `key`; an
/// entry that is not a `T` names `key[i]`.
fn entries<T: Entry>(
    raw: &toml::Value,
    file: &Path,
    key: &str,
    lengths: &[usize],
    note: &str,
) -> Result<Vec<T>, CliError> {
    let expected = match lengths {
        [] => format!("an array of {}", T::PLURAL),
        [n] => format!("{n} {}", T::PLURAL),
        [rest @ .., last] => format!(
            "{} or {last} {}",
            rest.iter().map(usize::to_string).collect::<Vec<_>>().join(", "),
            T::PLURAL
        ),
    };
    let toml::Value::Array(items) = raw else {
        return Err(key_error(
            file,
            key,
            format!("expected {expected}{note} in brackets, got {}", describe(raw)),
        ));
    };
    if !lengths.is_empty() && !lengths.contains(&items.len()) {
        return Err(key_error(
            file,
            key,
            format!("expected {expected}{note}, got {}", items.len()),
        ));
    }
    items
        .iter()
        .enumerate()
        .map(|(i, v)| T::entry(v).map_err(|m| key_error(file, &format!("{key}[{i}]"), m)))
        .collect()
}

/// Reads any TOML value: the check comes after, naming the key.
fn raw<'de, D: serde::Deserializer<'de>>(deserializer: D) -> Result<toml::Value, D::Error> {
    toml::Value::deserialize(deserializer)
}

/// An array key of exactly `N` entries of `T` (a vector of 3 numbers, the
/// 3 expressions of a curve), unchecked until [`Array::values`].
#[derive(Debug, Clone)]
pub struct Array<T, const N: usize> {
    raw: toml::Value,
    entries: PhantomData<T>,
}

impl<'de, T, const N: usize> Deserialize<'de> for Array<T, N> {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        raw(deserializer).map(|raw| Self {
            raw,
            entries: PhantomData,
        })
    }
}

impl<T: Entry, const N: usize> schemars::JsonSchema for Array<T, N> {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        format!("ArrayOf{N}{}", T::PLURAL).into()
    }
    fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
        schemars::json_schema!({
            "type": "array",
            "items": T::entry_schema(),
            "minItems": N,
            "maxItems": N,
        })
    }
}

impl<T: Entry, const N: usize> Array<T, N> {
    /// The `N` entries, given for `key` in `file`.
    ///
    /// # Errors
    /// Another length names `key` ("expected 3 numbers, got 6"); an entry
    /// that is not a `T` (a number: a finite float or an integer) names
    /// `key[i]`.
    pub fn values(&self, file: &Path, key: &str) -> Result<[T; N], CliError> {
        let v = entries::<T>(&self.raw, file, key, &[N], "")?;
        <[T; N]>::try_from(v).map_err(|v| key_error(file, key, format!("expected {N} {}, got {}", T::PLURAL, v.len())))
    }

    /// [`values`](Self::values) of an optional key, `default` without it.
    ///
    /// # Errors
    /// As [`values`](Self::values).
    pub fn or(given: &Option<Self>, file: &Path, key: &str, default: [T; N]) -> Result<[T; N], CliError> {
        match given {
            Some(a) => a.values(file, key),
            None => Ok(default),
        }
    }
}

/// An array key whose length the scenario sets elsewhere (one value per
/// coordinate) or which takes one of a few lengths (3 or 9), unchecked
/// until [`List::values`].
#[derive(Debug, Clone)]
pub struct List<T> {
    raw: toml::Value,
    entries: PhantomData<T>,
}

impl<'de, T> Deserialize<'de> for List<T> {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        raw(deserializer).map(|raw| Self {
            raw,
            entries: PhantomData,
        })
    }
}

impl<T: Entry> schemars::JsonSchema for List<T> {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        format!("ListOf{}", T::PLURAL).into()
    }
    fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
        schemars::json_schema!({ "type": "array", "items": T::entry_schema() })
    }
}

impl<T: Entry> List<T> {
    /// The entries, given for `key` in `file`: `lengths` lists the lengths
    /// the key takes (any when empty), `note` follows the count in the
    /// message ("expected 2 numbers (model `kepler` has coordinates x, y),
    /// got 3").
    ///
    /// # Errors
    /// Another length names `key`; an entry that is not a `T` names `key[i]`.
    pub fn values(&self, file: &Path, key: &str, lengths: &[usize], note: &str) -> Result<Vec<T>, CliError> {
        entries::<T>(&self.raw, file, key, lengths, note)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Deserialize)]
    struct Keys {
        v: Option<Array<f64, 3>>,
        e: Option<Array<String, 3>>,
        l: Option<List<i64>>,
    }

    fn parse(text: &str) -> Keys {
        toml::from_str(text).expect("any array parses")
    }

    fn message(r: Result<impl std::fmt::Debug, CliError>) -> String {
        r.expect_err("refused").to_string()
    }

    #[test]
    fn an_array_of_another_length_or_with_a_bad_entry_is_refused_naming_the_key() {
        let f = Path::new("s.toml");
        let k = parse("v = [0, 0, 1, 9, \"text\", true]");
        let v = k.v.expect("given");
        assert_eq!(
            message(v.values(f, "initial.velocity")),
            "s.toml: `initial.velocity`: expected 3 numbers, got 6"
        );
        let k = parse("v = [0, 0]");
        assert!(message(k.v.expect("given").values(f, "g")).ends_with("expected 3 numbers, got 2"));
        let k = parse("v = [0, \"x\", 1]");
        assert_eq!(
            message(k.v.expect("given").values(f, "g")),
            "s.toml: `g[1]`: expected a number, got the string \"x\""
        );
        let k = parse("v = [0, nan, 1]");
        assert!(message(k.v.expect("given").values(f, "g")).contains("`g[1]`: expected a finite number, got NaN"));
        let k = parse("v = 3");
        assert!(
            message(k.v.expect("given").values(f, "g")).contains("expected 3 numbers in brackets, got the integer 3")
        );
        let k = parse("e = [\"s\", \"0\", 1]");
        assert!(message(k.e.expect("given").values(f, "p")).contains("`p[2]`: expected a string"));
        let k = parse("l = [1, 2, 3, 4]");
        let l = k.l.expect("given");
        assert!(message(l.values(f, "n", &[2], " (nx, ny)")).ends_with("expected 2 integers (nx, ny), got 4"));
        assert!(message(l.values(f, "n", &[3, 9], "")).ends_with("expected 3 or 9 integers, got 4"));
        assert_eq!(l.values(f, "n", &[], "").expect("any length"), [1, 2, 3, 4]);
    }

    #[test]
    fn a_well_formed_array_reads_its_entries() {
        let f = Path::new("s.toml");
        let k = parse("v = [1, -2.5, 3e2]\ne = [\"s\", \"0\", \"1\"]");
        assert_eq!(k.v.expect("given").values(f, "v").expect("valid"), [1.0, -2.5, 300.0]);
        assert_eq!(k.e.expect("given").values(f, "e").expect("valid"), ["s", "0", "1"]);
        assert_eq!(Array::<f64, 3>::or(&None, f, "v", [0.0; 3]).expect("default"), [0.0; 3]);
    }
}
