//! The scenario key reference, generated from the schema the parser uses:
//! [`schema`] reads every key's type, default, unit, allowed values and
//! meaning from the `serde` structs of a kind (through `schemars`), and
//! [`render`] writes them as Markdown (`veselov keys KIND`, the book's
//! reference pages) or as a commented scenario (`veselov new KIND`).

pub mod render;
pub mod schema;

pub use render::{key_paths, markdown, method_summary, template, undocumented};
pub use schema::{KeyDoc, TableDoc, tables};

use crate::kinds::ScenarioKind;
use crate::route::KINDS;

/// The kind called `name` in `veselov keys` (`mechanics`, `rigid`,
/// `lattice`, `cfk`, `beam`, `rod`).
pub fn kind_named(name: &str) -> Option<&'static dyn ScenarioKind> {
    KINDS.iter().copied().find(|k| k.name() == name)
}

/// The names of every kind, in the order of the table of kinds.
pub fn kind_names() -> Vec<&'static str> {
    KINDS.iter().map(|k| k.name()).collect()
}
