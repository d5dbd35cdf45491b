//! The keys of a scenario kind, read from the JSON schema that `schemars`
//! derives from the very `serde` structs the parser reads the file with:
//! their doc comments are the keys' meanings, and the extensions `unit`,
//! `default` and `x-type` (set with `#[schemars(extend(…))]` on a field)
//! their units, documented defaults and type names. The schema is therefore
//! the one source of truth for what a key is; a key without a meaning is a
//! gap that [`KeyDoc::undocumented`] names.

use schemars::JsonSchema;
use schemars::generate::SchemaSettings;
use serde_json::{Map, Value};

/// One key of a scenario kind, as the reference documents it.
#[derive(Debug, Clone, PartialEq)]
pub struct KeyDoc {
    /// Its table, dotted (`method`, `ends.start_motion`).
    pub table: String,
    /// Its name in the table.
    pub key: String,
    /// What it holds (`float`, `array of 3 floats`, …).
    pub ty: String,
    /// Whether the file must give it.
    pub required: bool,
    /// The documented default, as TOML.
    pub default: Option<String>,
    /// Its unit (SI).
    pub unit: Option<String>,
    /// The values it takes, where they are a list of names.
    pub allowed: Vec<String>,
    /// What it means: the field's doc comment.
    pub meaning: String,
}

impl KeyDoc {
    /// `table.key`.
    pub fn path(&self) -> String {
        format!("{}.{}", self.table, self.key)
    }

    /// Whether its meaning is missing.
    pub fn undocumented(&self) -> bool {
        self.meaning.trim().is_empty()
    }
}

/// A table of a scenario kind with its keys.
#[derive(Debug, Clone, PartialEq)]
pub struct TableDoc {
    /// Its name, dotted.
    pub name: String,
    /// Whether the file must have it.
    pub required: bool,
    /// What it holds.
    pub meaning: String,
    /// Its keys, in the order of the struct.
    pub keys: Vec<KeyDoc>,
}

/// The inlined JSON schema of the scenario struct `T`.
pub fn schema_of<T: JsonSchema>() -> Value {
    let generator = SchemaSettings::draft2020_12()
        .with(|s| s.inline_subschemas = true)
        .into_generator();
    generator.into_root_schema_for::<T>().to_value()
}

/// The order in which a reader meets the tables of a scenario file (the
/// schema's own order is alphabetical); the keys of a table stay in
/// alphabetical order.
const TABLE_ORDER: &[&str] = &[
    "model", "lattice", "method", "ends", "loads", "initial", "time", "output",
];

/// The tables of a scenario whose root schema is `root`, each with its keys;
/// a table inside a table (`[ends.start_motion]`) is listed after its parent.
pub fn tables(root: &Value) -> Vec<TableDoc> {
    let mut out = Vec::new();
    let required = required_set(root);
    let mut roots = properties(root);
    roots.sort_by_key(|(name, _)| TABLE_ORDER.iter().position(|t| t == name).unwrap_or(TABLE_ORDER.len()));
    for (name, schema) in roots {
        collect_table(name.clone(), required.contains(name), schema, &mut out);
    }
    out
}

fn collect_table(name: String, required: bool, schema: &Value, out: &mut Vec<TableDoc>) {
    let schema = non_null(schema);
    let inner_required = required_set(schema);
    let index = out.len();
    out.push(TableDoc {
        name: name.clone(),
        required,
        meaning: meaning(schema),
        keys: Vec::new(),
    });
    let mut nested = Vec::new();
    for (key, field) in properties(schema) {
        let plain = non_null(field);
        if plain.get("properties").is_some() {
            nested.push((format!("{name}.{key}"), inner_required.contains(key), field));
            continue;
        }
        out[index].keys.push(KeyDoc {
            table: name.clone(),
            key: key.clone(),
            ty: type_name(field),
            required: inner_required.contains(key),
            default: lookup(field, "default").map(toml_literal),
            unit: lookup(field, "unit").and_then(Value::as_str).map(str::to_string),
            allowed: allowed(field),
            meaning: meaning(field),
        });
    }
    for (n, r, s) in nested {
        collect_table(n, r, s, out);
    }
}

fn properties(schema: &Value) -> Vec<(&String, &Value)> {
    schema
        .get("properties")
        .and_then(Value::as_object)
        .map(|m| m.iter().collect())
        .unwrap_or_default()
}

fn required_set(schema: &Value) -> Vec<String> {
    let names = schema.get("required").and_then(Value::as_array);
    names
        .map(|a| a.iter().filter_map(Value::as_str).map(str::to_string).collect())
        .unwrap_or_default()
}

/// The schema without the `null` alternative of an `Option`.
fn non_null(schema: &Value) -> &Value {
    for combinator in ["anyOf", "oneOf"] {
        if let Some(alternatives) = schema.get(combinator).and_then(Value::as_array) {
            let rest: Vec<&Value> = alternatives.iter().filter(|s| !is_null(s)).collect();
            if rest.len() == 1 && schema.get("x-type").is_none() {
                return rest[0];
            }
        }
    }
    schema
}

fn is_null(schema: &Value) -> bool {
    schema.get("type").and_then(Value::as_str) == Some("null")
}

/// `name` on the field's schema or on its non-null alternative.
fn lookup<'a>(schema: &'a Value, name: &str) -> Option<&'a Value> {
    schema.get(name).or_else(|| non_null(schema).get(name))
}

/// The doc comment: schemars puts a first paragraph of several in `title`.
fn meaning(schema: &Value) -> String {
    let text = |s: &Value, k: &str| s.get(k).and_then(Value::as_str).map(str::to_string);
    let parts: Vec<String> = [schema, non_null(schema)]
        .iter()
        .flat_map(|s| [text(s, "title"), text(s, "description")])
        .flatten()
        .collect();
    let mut unique: Vec<String> = Vec::new();
    for p in parts {
        if !unique.contains(&p) {
            unique.push(p);
        }
    }
    unique.join(" ").replace('\n', " ")
}

fn allowed(schema: &Value) -> Vec<String> {
    lookup(schema, "enum")
        .and_then(Value::as_array)
        .map(|v| v.iter().filter_map(Value::as_str).map(str::to_string).collect())
        .unwrap_or_default()
}

/// A short name of what the schema accepts.
pub fn type_name(schema: &Value) -> String {
    if let Some(t) = schema.get("x-type").and_then(Value::as_str) {
        return t.to_string();
    }
    let schema = non_null(schema);
    if let Some(t) = schema.get("x-type").and_then(Value::as_str) {
        return t.to_string();
    }
    for combinator in ["anyOf", "oneOf"] {
        if let Some(alternatives) = schema.get(combinator).and_then(Value::as_array) {
            let names: Vec<String> = alternatives.iter().filter(|s| !is_null(s)).map(type_name).collect();
            return names.join(" or ");
        }
    }
    let kind = match schema.get("type") {
        Some(Value::String(s)) => s.as_str(),
        Some(Value::Array(a)) => a
            .iter()
            .filter_map(Value::as_str)
            .find(|s| *s != "null")
            .unwrap_or("any"),
        _ => "any",
    };
    match kind {
        "number" => "float".to_string(),
        "integer" if schema.get("minimum").and_then(Value::as_f64) == Some(0.0) => "integer ≥ 0".to_string(),
        "integer" => "integer".to_string(),
        "boolean" => "bool".to_string(),
        "string" => "string".to_string(),
        "array" => array_name(schema),
        "object" => match schema.get("additionalProperties") {
            Some(v @ Value::Object(_)) => format!("table of {}", plural(&type_name(v))),
            _ => "table".to_string(),
        },
        other => other.to_string(),
    }
}

fn array_name(schema: &Value) -> String {
    let item = schema
        .get("items")
        .or_else(|| schema.get("prefixItems").and_then(|p| p.get(0)))
        .map(type_name)
        .unwrap_or_else(|| "value".to_string());
    let min = schema.get("minItems").and_then(Value::as_u64);
    let max = schema.get("maxItems").and_then(Value::as_u64);
    match (min, max) {
        (Some(a), Some(b)) if a == b => format!("array of {a} {}", plural(&item)),
        _ => format!("array of {}", plural(&item)),
    }
}

fn plural(name: &str) -> String {
    match name {
        "float" | "string" | "bool" => format!("{name}s"),
        "integer ≥ 0" => "integers ≥ 0".to_string(),
        other => other.to_string(),
    }
}

/// A JSON value written as TOML.
pub fn toml_literal(value: &Value) -> String {
    match value {
        Value::String(s) => format!("\"{s}\""),
        Value::Array(a) => format!("[{}]", a.iter().map(toml_literal).collect::<Vec<_>>().join(", ")),
        Value::Object(m) => inline_table(m),
        other => other.to_string(),
    }
}

fn inline_table(m: &Map<String, Value>) -> String {
    let items: Vec<String> = m.iter().map(|(k, v)| format!("{k} = {}", toml_literal(v))).collect();
    format!("{{ {} }}", items.join(", "))
}
