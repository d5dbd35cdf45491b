//! Scenarios built in Python: a dict (as JSON) turned into the command's
//! TOML, and overrides of single keys for ensembles.

use serde_json::Value;

/// TOML text of the JSON object `json`.
pub fn to_toml(json: &str) -> Result<String, String> {
    let value: Value = serde_json::from_str(json).map_err(|e| e.to_string())?;
    let table = toml_table(&value, "").map_err(|(key, m)| format!("`{key}`: {m}"))?;
    Ok(table.to_string())
}

/// `value` (a JSON object) as a TOML table; errors name the key.
fn toml_table(value: &Value, at: &str) -> Result<toml::Table, (String, String)> {
    match toml_value(value, at)? {
        toml::Value::Table(t) => Ok(t),
        _ => Err((at.to_string(), "expected a table (a dict)".into())),
    }
}

fn toml_value(value: &Value, at: &str) -> Result<toml::Value, (String, String)> {
    let join = |k: &str| {
        if at.is_empty() {
            k.to_string()
        } else {
            format!("{at}.{k}")
        }
    };
    Ok(match value {
        Value::Null => return Err((at.to_string(), "None has no TOML form; leave the key out".into())),
        Value::Bool(b) => toml::Value::Boolean(*b),
        Value::Number(n) => match (n.as_i64(), n.as_f64()) {
            (Some(i), _) => toml::Value::Integer(i),
            (None, Some(x)) => toml::Value::Float(x),
            (None, None) => return Err((at.to_string(), format!("{n} is out of range"))),
        },
        Value::String(s) => toml::Value::String(s.clone()),
        Value::Array(items) => toml::Value::Array(
            items
                .iter()
                .enumerate()
                .map(|(i, v)| toml_value(v, &format!("{at}[{i}]")))
                .collect::<Result<_, _>>()?,
        ),
        Value::Object(map) => {
            let mut t = toml::Table::new();
            for (k, v) in map {
                t.insert(k.clone(), toml_value(v, &join(k))?);
            }
            toml::Value::Table(t)
        }
    })
}

/// The scenario `text` with each key of the JSON object `overrides`
/// replaced: a dotted key (`"initial.q"`) names a nested key, and a table
/// value is merged key by key into the table it replaces. Errors carry the
/// key at fault when there is one.
pub fn merge(text: &str, overrides: &str) -> Result<String, (Option<String>, String)> {
    let mut base: toml::Table = toml::from_str(text).map_err(|e| (None, e.to_string()))?;
    let value: Value = serde_json::from_str(overrides).map_err(|e| (None, e.to_string()))?;
    let Value::Object(map) = &value else {
        return Err((None, "an override is a dict of keys and values".into()));
    };
    for (key, v) in map {
        let new = toml_value(v, key).map_err(|(k, m)| (Some(k), m))?;
        let mut parts: Vec<&str> = key.split('.').collect();
        let Some(last) = parts.pop().filter(|l| !l.is_empty()) else {
            return Err((Some(key.clone()), "empty key".into()));
        };
        let mut table = &mut base;
        for p in parts {
            let entry = table
                .entry(p.to_string())
                .or_insert_with(|| toml::Value::Table(toml::Table::new()));
            table = match entry {
                toml::Value::Table(t) => t,
                _ => return Err((Some(key.clone()), format!("`{p}` is not a table"))),
            };
        }
        put(table, last, new);
    }
    Ok(base.to_string())
}

/// Set `table[key] = value`, merging tables into tables.
fn put(table: &mut toml::Table, key: &str, value: toml::Value) {
    match (table.get_mut(key), value) {
        (Some(toml::Value::Table(old)), toml::Value::Table(new)) => {
            for (k, v) in new {
                put(old, &k, v);
            }
        }
        (_, value) => {
            table.insert(key.to_string(), value);
        }
    }
}
