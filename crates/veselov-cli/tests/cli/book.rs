//! Every complete scenario shown in the user guide or the README (a ```toml
//! block with a `[model]` table and a `[method]`, `[time]` or `[lattice]`
//! table) parses and validates as the command would read it; fragments (one
//! table, or tables without `[model]`) are not scenarios and are skipped.

use std::path::{Path, PathBuf};

use veselov_cli::route::check_text;

use crate::common::workspace_root;

fn pages(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("book directory").flatten() {
        let path = entry.path();
        if path.is_dir() {
            pages(&path, out);
        } else if path.extension().and_then(|e| e.to_str()) == Some("md") {
            out.push(path);
        }
    }
}

/// The ```toml blocks of a Markdown page.
fn toml_blocks(text: &str) -> Vec<String> {
    let mut blocks = Vec::new();
    let mut current: Option<String> = None;
    for line in text.lines() {
        let fence = line.trim_start();
        match &mut current {
            None if fence.starts_with("```toml") => current = Some(String::new()),
            Some(block) if fence.starts_with("```") => {
                blocks.push(std::mem::take(block));
                current = None;
            }
            Some(block) => {
                block.push_str(line);
                block.push('\n');
            }
            None => {}
        }
    }
    blocks
}

#[test]
fn every_scenario_in_the_book_parses() {
    let root = workspace_root();
    let mut files = vec![root.join("README.md")];
    pages(&root.join("docs/src"), &mut files);
    let (mut checked, mut failures) = (0, Vec::new());
    for file in files {
        let text = std::fs::read_to_string(&file).expect("page");
        for (i, block) in toml_blocks(&text).into_iter().enumerate() {
            let has = |table: &str| block.lines().any(|l| l.trim() == table);
            if !has("[model]") || !["[method]", "[time]", "[lattice]"].iter().any(|t| has(t)) {
                continue;
            }
            checked += 1;
            if let Err(e) = check_text(&file, &block) {
                failures.push(format!("{} (toml block {}): {e}", file.display(), i + 1));
            }
        }
    }
    assert!(checked >= 10, "only {checked} scenarios found in the book");
    assert!(
        failures.is_empty(),
        "scenarios in the book that do not parse:\n{}",
        failures.join("\n")
    );
}
