//! The scenario key reference: generated from the schema the parser reads,
//! complete (every key has a meaning), the same as the book's reference
//! pages, covering every key of every shipped example; and `veselov new
//! KIND` writes a scenario that runs.
//!
//! After changing a key, regenerate the book's pages with
//! `VESELOV_BLESS=1 cargo test -p veselov-cli --test cli keys::`.

use std::path::{Path, PathBuf};

use veselov_cli::keys::{self, key_paths, markdown, template, undocumented};
use veselov_cli::route::{self, KINDS};

use crate::common::{Scratch, run_scenario, veselov, workspace_root};

fn reference_page(kind: &str) -> PathBuf {
    workspace_root()
        .join("docs/src/reference/keys")
        .join(format!("{kind}.md"))
}

#[test]
fn every_key_the_parser_accepts_has_a_meaning() {
    let gaps: Vec<String> = KINDS
        .iter()
        .flat_map(|k| {
            undocumented(*k)
                .into_iter()
                .map(move |key| format!("{}: {key}", k.name()))
        })
        .collect();
    assert!(
        gaps.is_empty(),
        "keys without a doc comment in their schema:\n{}",
        gaps.join("\n")
    );
}

#[test]
fn the_book_reference_is_what_veselov_keys_prints() {
    let bless = std::env::var_os("VESELOV_BLESS").is_some();
    let mut stale = Vec::new();
    for kind in KINDS {
        let page = reference_page(kind.name());
        let expected = markdown(*kind);
        if bless {
            std::fs::write(&page, &expected).expect("write the reference page");
        }
        let found = std::fs::read_to_string(&page).unwrap_or_default();
        if found != expected {
            stale.push(page.display().to_string());
        }
    }
    assert!(
        stale.is_empty(),
        "reference pages differ from `veselov keys KIND` (regenerate with VESELOV_BLESS=1): {stale:?}"
    );
}

/// `table.key` for every key of a parsed scenario file; a table-valued key
/// the kind documents as one key (`model.params`) is not descended into.
fn file_keys(table: &toml::Table, prefix: &str, documented: &[String], out: &mut Vec<String>) {
    for (key, value) in table {
        let path = if prefix.is_empty() {
            key.clone()
        } else {
            format!("{prefix}.{key}")
        };
        match value.as_table() {
            Some(inner) if !documented.contains(&path) => file_keys(inner, &path, documented, out),
            _ => out.push(path),
        }
    }
}

#[test]
fn every_key_of_every_shipped_example_is_documented() {
    let mut missing = Vec::new();
    let mut examples = 0;
    for entry in std::fs::read_dir(workspace_root().join("examples")).expect("examples/") {
        let path = entry.expect("entry").path();
        if path.extension().and_then(|e| e.to_str()) != Some("toml") {
            continue;
        }
        examples += 1;
        let text = std::fs::read_to_string(&path).expect("example");
        let kind = route::kind(&path, &text).expect("the example's kind");
        let documented = key_paths(kind);
        let table: toml::Table = toml::from_str(&text).expect("TOML");
        let mut found = Vec::new();
        file_keys(&table, "", &documented, &mut found);
        for key in found.into_iter().filter(|k| !documented.contains(k)) {
            missing.push(format!("{}: {key}", path.display()));
        }
    }
    assert!(examples >= 30, "only {examples} examples found");
    assert!(
        missing.is_empty(),
        "keys of shipped examples missing from the reference:\n{}",
        missing.join("\n")
    );
}

#[test]
fn veselov_keys_and_new_name_the_kinds() {
    let out = veselov().args(["keys", "rod"]).assert().success();
    let text = String::from_utf8_lossy(&out.get_output().stdout).into_owned();
    assert!(text.starts_with("# Cosserat rod scenarios"), "{text}");
    let err = veselov().args(["new", "sphere"]).assert().failure();
    let message = String::from_utf8_lossy(&err.get_output().stderr).into_owned();
    for name in keys::kind_names() {
        assert!(message.contains(name), "{message}");
    }
}

/// `veselov new KIND` for every kind writes a scenario that runs as it is,
/// and every key it leaves out is written, commented, at its default.
#[test]
fn every_template_runs() {
    let scratch = Scratch::new("keys-templates");
    for kind in KINDS {
        let text = template(*kind).expect("template");
        for key in key_paths(*kind) {
            let name = key.rsplit('.').next().expect("key");
            assert!(
                text.contains(&format!("{name} = ")),
                "{}: template lacks {key}",
                kind.name()
            );
        }
        let file = scratch.join(format!("{}.toml", kind.name()));
        std::fs::write(&file, &text).expect("write template");
        run_scenario(scratch.join(kind.name()), &file).success();
        assert!(Path::new(&scratch.join(kind.name()).join("summary.json")).exists());
    }
}
