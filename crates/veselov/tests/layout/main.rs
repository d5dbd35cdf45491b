//! Source layout of the workspace: no file-level import cycle in the library
//! or the command, no source file over the house limit of 700 lines, and a
//! doc comment opening every folder module of the library.
//!
//! The import graph is read from the text with `std` alone (no parser). It is
//! a faithful port of the reference script `imports.py`, its heuristics
//! included, so that both report the same edges and the same cycles. A text
//! reading has limits: raw strings, char literals such as `'"'` and nested
//! block comments are not understood, nor is an item renamed by `as`.
//!
//! An edge `a.rs -> b.rs` means that `a.rs` names an item that `b.rs`
//! defines: a file depends on where an item is written, not on the module
//! that re-exports it, so a `pub use` facade does not hide a cycle and a
//! parent that only gathers its children does not make one. Hence:
//! - a private `use` path and an inline `crate::…`, `super::…`, `self::…` path
//!   in code are edges, to the file that defines the item they name;
//! - a `pub use` line (a re-export) and a `mod` declaration are not edges;
//! - test modules (`#[cfg(test)] mod NAME { … }`) are dropped: they sit
//!   beside the code they test and do not form the layering.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::Path;

/// The house rule: no source file over 700 lines.
const MAX_LINES: usize = 700;

/// The keywords that define a named item (`macro_rules!` with its bang).
const ITEM_KEYWORDS: &str = "fn struct enum trait type const static union macro_rules!";

/// Every `.rs` file under `src` (relative to this crate's manifest), keyed by
/// its path below `src` with `/` separators.
fn read_tree(src: &str) -> BTreeMap<String, String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join(src);
    let mut files = BTreeMap::new();
    let mut folders = vec![root.clone()];
    while let Some(folder) = folders.pop() {
        let entries = fs::read_dir(&folder).unwrap_or_else(|e| panic!("read {}: {e}", folder.display()));
        for entry in entries {
            let path = entry.expect("a readable directory entry").path();
            if path.is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|x| x == "rs") {
                let rel = path.strip_prefix(&root).expect("a file under the source root");
                let rel: Vec<_> = rel.iter().map(|c| c.to_string_lossy().into_owned()).collect();
                let text = fs::read_to_string(&path).unwrap_or_else(|e| panic!("read {}: {e}", path.display()));
                files.insert(rel.join("/"), text);
            }
        }
    }
    files
}

fn is_word(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

fn word_at(s: &[char], i: usize) -> bool {
    s.get(i).is_some_and(|&c| is_word(c))
}

fn starts(s: &[char], at: usize, lit: &str) -> bool {
    lit.chars().enumerate().all(|(k, c)| s.get(at + k) == Some(&c))
}

/// The length of the whitespace run at `at`.
fn spaces(s: &[char], at: usize) -> usize {
    let rest = s.get(at..).unwrap_or_default();
    rest.iter().take_while(|c| c.is_whitespace()).count()
}

/// `s` with each match replaced by `with`, left to right as a regex
/// substitution: `end(i)` is the end of the match at `i`, if any (never `i`).
fn substitute(s: &[char], with: &str, mut end: impl FnMut(usize) -> Option<usize>) -> Vec<char> {
    let (mut out, mut i) = (Vec::with_capacity(s.len()), 0);
    while i < s.len() {
        if let Some(j) = end(i) {
            out.extend(with.chars());
            i = j;
        } else {
            out.push(s[i]);
            i += 1;
        }
    }
    out
}

/// Comments and string literals hold no import. As the script, three passes
/// in turn: line comments, block comments (not nested), then string contents
/// (an escape takes any character but a newline), and test modules dropped.
fn clean(src: &str) -> Vec<char> {
    let s: Vec<char> = src.chars().collect();
    let to_eol = |s: &[char], i| i + s[i..].iter().take_while(|&&c| c != '\n').count();
    let s = substitute(&s, "", |i| starts(&s, i, "//").then(|| to_eol(&s, i)));
    let block = |i| (i + 2..s.len()).find(|&j| starts(&s, j, "*/")).map(|j| j + 2);
    let s = substitute(&s, "", |i| starts(&s, i, "/*").then(|| block(i)).flatten());
    let s = substitute(&s, "\"\"", |i| (s[i] == '"').then(|| string_end(&s, i)).flatten());
    substitute(&s, "", |i| test_module_at(&s, i))
}

/// Just past the closing quote of the string literal opening at `open`.
fn string_end(s: &[char], open: usize) -> Option<usize> {
    let mut j = open + 1;
    loop {
        match *s.get(j)? {
            '"' => return Some(j + 1),
            '\\' if s.get(j + 1).is_some_and(|&c| c != '\n') => j += 2,
            '\\' => return None,
            _ => j += 1,
        }
    }
}

/// Where an optional `pub`, `pub(…)` prefix (with its trailing whitespace)
/// may end, in the order the script's regex tries them; `at` itself last.
fn pub_prefix_ends(s: &[char], at: usize) -> Vec<usize> {
    let mut ends = Vec::new();
    if starts(s, at, "pub") {
        let paren = (s.get(at + 3) == Some(&'(')).then(|| (at + 4..s.len()).find(|&k| s[k] == ')'));
        for j in paren.flatten().map(|k| k + 1).into_iter().chain([at + 3]) {
            let w = spaces(s, j);
            if w > 0 {
                ends.push(j + w);
            }
        }
    }
    ends.push(at);
    ends
}

/// `#[cfg(test)] (pub(…) )?mod NAME { … }` at `at`: just past its body
/// (braces matched by count).
fn test_module_at(s: &[char], at: usize) -> Option<usize> {
    if !starts(s, at, "#[cfg(test)]") {
        return None;
    }
    let i = at + 12 + spaces(s, at + 12);
    let open = pub_prefix_ends(s, i).into_iter().find_map(|j| {
        let w = spaces(s, j + 3);
        let name = s.get(j + 3 + w..)?.iter().take_while(|&&c| is_word(c)).count();
        let k = j + 3 + w + name + spaces(s, j + 3 + w + name);
        (starts(s, j, "mod") && w > 0 && name > 0 && s.get(k) == Some(&'{')).then_some(k + 1)
    })?;
    let (mut depth, mut j) = (1, open);
    while depth > 0 && j < s.len() {
        depth += i32::from(s[j] == '{') - i32::from(s[j] == '}');
        j += 1;
    }
    Some(j)
}

/// A `(pub(…) )?use TREE;` statement at `at`: its end, whether it is `pub`,
/// and its tree.
fn use_at(s: &[char], at: usize) -> Option<(usize, bool, String)> {
    if s[at] != 'p' && s[at] != 'u' {
        return None;
    }
    pub_prefix_ends(s, at).into_iter().find_map(|from| {
        let w = spaces(s, from + 3);
        let q = from + 3 + w;
        let semi = (q..s.len()).find(|&k| s[k] == ';')?;
        // `[^;]+` takes one character at least: the last blank if need be.
        let begin = if semi > q { q } else { q - usize::from(w >= 2) };
        let matched = starts(s, from, "use") && w > 0 && begin < semi;
        matched.then(|| (semi + 1, from > at, s[begin..semi].iter().collect()))
    })
}

/// `path as alias` names `path`.
fn strip_alias(t: &str) -> &str {
    let alias = t.trim_end_matches(is_word);
    let blanks = |x: &str| x.trim_end().len() < x.len();
    match alias.trim_end().strip_suffix("as") {
        Some(before) if alias.len() < t.len() && blanks(alias) && blanks(before) => before.trim_end(),
        _ => t,
    }
}

/// A path's segments, trimmed, empty ones left out.
fn segments(t: &str) -> Vec<String> {
    let segs = t.split("::").map(str::trim);
    segs.filter(|x| !x.is_empty()).map(String::from).collect()
}

/// A use tree as flat paths: `a::{b, c::{self, d as e}, f::*}` gives `a::b`,
/// `a::c::self`, `a::c::d`, `a::f::*`.
fn expand(tree: &str) -> Vec<Vec<String>> {
    let tree = tree.trim();
    let Some(open) = tree.find('{') else {
        return vec![segments(strip_alias(tree))];
    };
    let prefix = segments(&tree[..open]);
    let last = tree.chars().last().map_or(0, char::len_utf8);
    let close = tree.rfind('}').unwrap_or(tree.len() - last);
    let (mut parts, mut depth, mut cur) = (Vec::new(), 0, String::new());
    for ch in tree.get(open + 1..close).unwrap_or("").chars() {
        if ch == ',' && depth == 0 {
            parts.push(std::mem::take(&mut cur));
            continue;
        }
        depth += i32::from(ch == '{') - i32::from(ch == '}');
        cur.push(ch);
    }
    parts.push(cur);
    let paths = parts.iter().filter(|p| !p.trim().is_empty()).flat_map(|p| expand(p));
    paths.map(|e| [prefix.clone(), e].concat()).collect()
}

/// One source file, cleaned and read.
struct Source {
    text: Vec<char>,
    /// Its `use` paths, flat, with whether the statement is `pub`.
    uses: Vec<(bool, Vec<String>)>,
    /// The `crate::…`, `super::…`, `self::…` paths in its code.
    inline: Vec<Vec<String>>,
    /// Where a name follows an item keyword (`fn NAME`, `struct NAME`, …).
    definitions: Vec<usize>,
}

impl Source {
    fn new(src: &str) -> Self {
        let text = clean(src);
        // `use` statements, flat; the code left after them holds the inline paths.
        let mut uses = Vec::new();
        let body = substitute(&text, "", |i| {
            let (end, is_pub, tree) = use_at(&text, i)?;
            uses.extend(expand(&tree).into_iter().map(|p| (is_pub, p)));
            Some(end)
        });
        let mut inline = Vec::new();
        substitute(&body, "", |i| {
            let boundary = i == 0 || !is_word(body[i - 1]);
            let roots = ["crate", "super", "self"];
            let root = roots.into_iter().find(|k| boundary && starts(&body, i, k))?;
            let mut end = i + root.len();
            while starts(&body, end, "::") && word_at(&body, end + 2) {
                end += 2 + body[end + 2..].iter().take_while(|&&c| is_word(c)).count();
            }
            if end == i + root.len() {
                return None;
            }
            let path: String = body[i..end].iter().collect();
            inline.push(path.split("::").map(String::from).collect());
            Some(end)
        });
        let mut definitions = Vec::new();
        for at in (0..text.len()).filter(|&at| at == 0 || !is_word(text[at - 1])) {
            for kw in ITEM_KEYWORDS.split(' ').filter(|kw| starts(&text, at, kw)) {
                let w = spaces(&text, at + kw.len());
                if w > 0 {
                    definitions.push(at + kw.len() + w);
                }
            }
        }
        Source {
            text,
            uses,
            inline,
            definitions,
        }
    }

    /// Whether an item keyword is followed by `name` (whole word).
    fn defines(&self, name: &str) -> bool {
        let name: Vec<char> = name.chars().collect();
        let last = name.last().is_some_and(|&c| is_word(c));
        self.definitions.iter().any(|&n| {
            self.text.get(n..n + name.len()) == Some(&name[..]) && last != word_at(&self.text, n + name.len())
        })
    }
}

/// The module path `module::name`.
fn child(module: &[String], name: &str) -> Vec<String> {
    [module, &[name.to_string()]].concat()
}

/// A crate's files and module tree.
struct Crate {
    files: BTreeMap<String, Source>,
    /// Module path (`["field", "cauchy"]`) to the file that holds it.
    modules: BTreeMap<Vec<String>, String>,
}

impl Crate {
    fn read(src: &str) -> Self {
        let raw = read_tree(src);
        let mut modules = BTreeMap::new();
        for rel in raw.keys() {
            let mut parts: Vec<String> = rel[..rel.len() - 3].split('/').map(String::from).collect();
            // The binary's root beside a library root is another crate.
            if parts == ["main"] && raw.contains_key("lib.rs") {
                continue;
            }
            // `lib.rs`, `mod.rs` (and a `main.rs`) name their folder.
            if matches!(parts.last().map(String::as_str), Some("mod" | "lib" | "main")) {
                parts.pop();
            }
            modules.insert(parts, rel.clone());
        }
        let files = raw.iter().map(|(rel, text)| (rel.clone(), Source::new(text))).collect();
        Crate { files, modules }
    }

    /// The file that defines the item `path` names from module `current`:
    /// walk the module segments, then look for the item in that module's
    /// file, then through that module's `use`s (private ones included: a
    /// child reaches them by `super::`), globs included; else the module's
    /// file itself. `None` for a path outside the crate (`std`, a dependency).
    fn resolve(&self, current: &[String], path: &[String], depth: usize) -> Option<&String> {
        if depth > 20 || path.is_empty() {
            return None;
        }
        // Where the path starts: the crate root, this module, a parent (one
        // per `super`), or a child module named without `self::`.
        let supers = path.iter().take_while(|s| *s == "super").count();
        let parent = &current[..current.len().saturating_sub(supers)];
        let (mut module, mut segs) = match path[0].as_str() {
            "crate" => (Vec::new(), &path[1..]),
            "self" => (current.to_vec(), &path[1..]),
            "super" => (parent.to_vec(), &path[supers..]),
            first if self.modules.contains_key(&child(current, first)) => (current.to_vec(), path),
            _ => return None,
        };
        while let Some(first) = segs.first()
            && self.modules.contains_key(&child(&module, first))
        {
            module.push(first.clone());
            segs = &segs[1..];
        }
        let file = self.modules.get(&module)?;
        let Some(name) = segs.first().filter(|s| *s != "*" && *s != "self") else {
            return Some(file);
        };
        let source = &self.files[file];
        if source.defines(name) {
            return Some(file);
        }
        for (_, p) in &source.uses {
            if p.last() == Some(name)
                && let Some(r) = self.resolve(&module, p, depth + 1)
            {
                return Some(r);
            }
            if p.last().is_some_and(|s| s == "*") {
                let through = child(&p[..p.len() - 1], name);
                if let Some(r) = self.resolve(&module, &through, depth + 1).filter(|r| *r != file) {
                    return Some(r);
                }
            }
        }
        Some(file)
    }

    /// File-level edges: private `use` paths and inline paths, resolved.
    fn edges(&self) -> BTreeMap<&String, BTreeSet<&String>> {
        let file_module: BTreeMap<_, _> = self.modules.iter().map(|(m, f)| (f, m)).collect();
        let mut edges = BTreeMap::new();
        for (rel, source) in &self.files {
            let Some(module) = file_module.get(rel) else { continue };
            let uses = source.uses.iter().filter(|(is_pub, _)| !is_pub).map(|(_, p)| p);
            for path in uses.chain(&source.inline) {
                if let Some(to) = self.resolve(module, path, 0).filter(|to| *to != rel) {
                    edges.entry(rel).or_insert_with(BTreeSet::new).insert(to);
                }
            }
        }
        edges
    }
}

/// Strongly connected components of more than one file (Kosaraju): the
/// files in the order a depth-first search finishes them; then, latest first,
/// each grows a component of the files it reaches along reversed edges that
/// no earlier one took.
fn cycles<'a>(edges: &BTreeMap<&'a String, BTreeSet<&'a String>>) -> Vec<Vec<&'a String>> {
    type Next<'n, 'a> = &'n dyn Fn(&'a String) -> Vec<&'a String>;
    fn visit<'a>(v: &'a String, next: Next<'_, 'a>, seen: &mut BTreeSet<&'a String>, out: &mut Vec<&'a String>) {
        if seen.insert(v) {
            for w in next(v) {
                visit(w, next, seen, out);
            }
            out.push(v);
        }
    }
    let forward = |v: &'a String| edges.get(v).map_or(Vec::new(), |s| s.iter().copied().collect());
    let backward = |v: &'a String| edges.iter().filter(|e| e.1.contains(v)).map(|e| *e.0).collect();
    let (mut seen, mut order) = (BTreeSet::new(), Vec::new());
    for &v in edges.keys() {
        visit(v, &forward, &mut seen, &mut order);
    }
    let (mut seen, mut found) = (BTreeSet::new(), Vec::new());
    for &v in order.iter().rev() {
        let mut component = Vec::new();
        visit(v, &backward, &mut seen, &mut component);
        if component.len() > 1 {
            component.sort();
            found.push(component);
        }
    }
    found.sort();
    found
}

/// Fails listing every cycle of files (with the edges inside it) in `src`.
fn assert_no_import_cycle(src: &str) {
    let krate = Crate::read(src);
    let edges = krate.edges();
    let found = cycles(&edges);
    let count: usize = edges.values().map(BTreeSet::len).sum();
    let (files, n) = (krate.files.len(), found.len());
    println!("{src}: {files} files, {count} edges, {n} cycles");
    let mut report = String::new();
    for component in &found {
        let names: Vec<&str> = component.iter().map(|f| f.as_str()).collect();
        report += &format!("\n  cycle: {}", names.join(" "));
        for from in component {
            for to in edges[from].iter().filter(|to| component.contains(to)) {
                report += &format!("\n    {from} -> {to}");
            }
        }
    }
    assert!(found.is_empty(), "{src}: {n} file-level import cycle(s):{report}");
}

#[test]
fn library_has_no_import_cycle() {
    assert_no_import_cycle("src");
}

// the command crate's cycles are removed by the layout of one folder per kind
#[test]
fn command_has_no_import_cycle() {
    assert_no_import_cycle("../veselov-cli/src");
}

#[test]
fn no_source_file_over_the_line_limit() {
    let mut long = Vec::new();
    for src in ["src", "../veselov-cli/src"] {
        for (rel, text) in read_tree(src) {
            let lines = text.lines().count();
            if lines > MAX_LINES {
                long.push(format!("\n  {src}/{rel}: {lines} lines"));
            }
        }
    }
    assert!(long.is_empty(), "files over {MAX_LINES} lines:{}", long.concat());
}

#[test]
fn folder_modules_open_with_a_doc_comment() {
    let mut bare = Vec::new();
    for (rel, text) in read_tree("src") {
        if (rel == "lib.rs" || rel.ends_with("/mod.rs")) && !text.starts_with("//!") {
            bare.push(rel);
        }
    }
    assert!(bare.is_empty(), "folder modules without a `//!` opening: {bare:?}");
}
