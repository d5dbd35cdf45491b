//! Ensemble members: the scenario text with some keys replaced.

/// The scenario `text` with the keys of the TOML document `overrides`
/// replaced; a table replaces a table key by key (so `initial = { q = … }`
/// keeps `initial.p`). Both are parsed by the `toml` crate, which reads
/// every number exactly.
pub fn merge(text: &str, overrides: &str) -> Result<String, String> {
    let mut base: toml::Table = toml::from_str(text).map_err(|e| e.to_string())?;
    let new: toml::Table = toml::from_str(overrides).map_err(|e| e.to_string())?;
    for (k, v) in new {
        put(&mut base, &k, v);
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
