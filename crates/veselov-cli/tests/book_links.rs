//! The user guide (`docs/src/**/*.md`) and the README link only to files
//! that exist: every relative Markdown link and image target, and every
//! page listed in `docs/src/SUMMARY.md`. Web (`http:`, `https:`), `mailto:`
//! and same-page (`#anchor`) links are not checked; a relative target's
//! `#fragment` is dropped before the check.

use std::fs;
use std::path::{Path, PathBuf};

fn repository() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .ancestors()
        .nth(2)
        .expect("the crate lies two levels below the repository root")
        .to_path_buf()
}

/// The Markdown files under `dir`, recursively, in a stable order.
fn markdown_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("directory entry").path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            markdown_files(&path, out);
        } else if path.extension().is_some_and(|x| x == "md") {
            out.push(path);
        }
    }
}

/// `text` without its fenced code blocks (```` ``` ```` or `~~~`) and inline
/// code spans, which may contain brackets and parentheses that are not links.
fn prose(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut fence: Option<&str> = None;
    for line in text.lines() {
        let trimmed = line.trim_start();
        match fence {
            Some(f) => {
                if trimmed.starts_with(f) {
                    fence = None;
                }
                out.push('\n');
                continue;
            }
            None => {
                if trimmed.starts_with("```") {
                    fence = Some("```");
                    out.push('\n');
                    continue;
                }
                if trimmed.starts_with("~~~") {
                    fence = Some("~~~");
                    out.push('\n');
                    continue;
                }
            }
        }
        // Drop inline code spans: text between matching runs of backticks.
        let mut rest = line;
        while let Some(start) = rest.find('`') {
            out.push_str(&rest[..start]);
            let ticks = rest[start..].chars().take_while(|&c| c == '`').count();
            let after = &rest[start + ticks..];
            let closing = "`".repeat(ticks);
            match after.find(&closing) {
                Some(end) => rest = &after[end + ticks..],
                None => {
                    rest = after;
                    break;
                }
            }
        }
        out.push_str(rest);
        out.push('\n');
    }
    out
}

/// The targets of the inline links and images `[text](target)` /
/// `![alt](target "title")` and of the reference definitions `[label]: target`
/// in `text`.
fn link_targets(text: &str) -> Vec<String> {
    let text = prose(text);
    let mut targets = Vec::new();
    let bytes = text.as_bytes();
    let mut i = 0;
    while i + 1 < bytes.len() {
        if bytes[i] == b']' && bytes[i + 1] == b'(' {
            let start = i + 2;
            // The target ends at the matching closing parenthesis.
            let mut depth = 1;
            let mut j = start;
            while j < bytes.len() && depth > 0 {
                match bytes[j] {
                    b'(' => depth += 1,
                    b')' => depth -= 1,
                    b'\n' => break,
                    _ => {}
                }
                j += 1;
            }
            if depth == 0 {
                let inside = text[start..j - 1].trim();
                let target = if let Some(stripped) = inside.strip_prefix('<') {
                    stripped.split('>').next().unwrap_or("")
                } else {
                    inside.split_whitespace().next().unwrap_or("")
                };
                targets.push(target.to_string());
            }
            i = j.max(i + 1);
        } else {
            i += 1;
        }
    }
    for line in text.lines() {
        let line = line.trim_start();
        if let Some(rest) = line.strip_prefix('[')
            && let Some((label, target)) = rest.split_once("]:")
            && !label.is_empty()
            && !label.starts_with('^')
            && let Some(target) = target.split_whitespace().next()
        {
            targets.push(target.trim_matches(|c| c == '<' || c == '>').to_string());
        }
    }
    targets
}

/// Whether `target` is checked as a relative file path.
fn is_relative(target: &str) -> bool {
    let lower = target.to_ascii_lowercase();
    !(target.is_empty()
        || target.starts_with('#')
        || lower.starts_with("http:")
        || lower.starts_with("https:")
        || lower.starts_with("mailto:"))
}

/// The broken relative links of the Markdown file `file`, one message each.
fn broken_links(file: &Path) -> Vec<String> {
    let text = fs::read_to_string(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    let dir = file.parent().expect("a file has a directory");
    link_targets(&text)
        .into_iter()
        .filter(|t| is_relative(t))
        .filter_map(|target| {
            let path = target.split('#').next().unwrap_or("");
            if path.is_empty() {
                return None;
            }
            let resolved = dir.join(path);
            (!resolved.exists()).then(|| format!("{}: broken link `{target}`", file.display()))
        })
        .collect()
}

/// The pages SUMMARY.md lists (its link targets), relative to `docs/src`.
fn summary_pages(summary: &Path) -> Vec<String> {
    let text = fs::read_to_string(summary).unwrap_or_else(|e| panic!("{}: {e}", summary.display()));
    link_targets(&text).into_iter().filter(|t| is_relative(t)).collect()
}

#[test]
fn every_relative_link_and_image_of_the_guide_and_the_readme_exists() {
    let root = repository();
    let mut files = Vec::new();
    markdown_files(&root.join("docs/src"), &mut files);
    assert!(
        files.len() > 10,
        "the guide's pages were not found under {}",
        root.join("docs/src").display()
    );
    files.push(root.join("README.md"));
    let broken: Vec<String> = files.iter().flat_map(|f| broken_links(f)).collect();
    assert!(
        broken.is_empty(),
        "{} broken link(s):\n{}",
        broken.len(),
        broken.join("\n")
    );
}

#[test]
fn every_page_of_the_summary_exists() {
    let src = repository().join("docs/src");
    let pages = summary_pages(&src.join("SUMMARY.md"));
    assert!(pages.len() > 10, "SUMMARY.md lists too few pages: {pages:?}");
    let missing: Vec<String> = pages
        .iter()
        .filter(|p| !src.join(p.split('#').next().unwrap_or("")).is_file())
        .map(|p| format!("docs/src/SUMMARY.md: page `{p}` does not exist"))
        .collect();
    assert!(missing.is_empty(), "{}", missing.join("\n"));
}

#[test]
fn the_link_extraction_sees_links_images_and_references_but_not_code() {
    let text = "See [a](a.md#x) and ![p](images/p.png \"title\"), [web](https://example.org), \
                [top](#top), `[not](code.md)`.\n\n```rust\nlet x = [1](2);\n```\n\n[ref]: ref.md\n";
    assert_eq!(
        link_targets(text),
        ["a.md#x", "images/p.png", "https://example.org", "#top", "ref.md"]
    );
    let relative: Vec<String> = link_targets(text).into_iter().filter(|t| is_relative(t)).collect();
    assert_eq!(relative, ["a.md#x", "images/p.png", "ref.md"]);
}
