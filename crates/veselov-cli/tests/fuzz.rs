//! Mutation fuzzing of the shipped examples: extreme numbers (0, negative,
//! 1e-300, 1e300, NaN, ±inf), deleted and duplicated lines, wrong types and
//! truncation. Every outcome must be a clean error (non-zero exit, a message
//! starting with `error:` after any warnings the run gave first, each a line
//! of its own starting with `warning:`; no panic, no signal) or a completed
//! run whose outputs are all finite; a run may also end as interrupted by
//! its time limit, never hang past it.
//!
//! A quarter of the runs that leave a checkpoint are then resumed
//! (`--resume`) with the same scenario, with its `t_end` doubled, or with a
//! further mutation of it. The same outcomes are allowed, and a resume
//! refused because its scenario is not the run's own (its message says
//! "being resumed") must leave every file of the run byte for byte as it
//! was.
//!
//! The default suite runs a fast seeded subset; the long run is
//!
//! ```sh
//! cargo test --release -p veselov-cli --test fuzz -- --ignored
//! ```
//!
//! (`VESELOV_FUZZ_CASES` and `VESELOV_FUZZ_SEED` change its size, 5000 by
//! default, and its seed).

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

mod common;
use common::Scratch;

/// xorshift64*: a seeded generator without dependencies.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

const EXTREMES: &[&str] = &[
    "0", "0.0", "-1.0", "-3", "1e-300", "1e300", "-1e300", "nan", "inf", "-inf", "5e19", "2e18",
];
const WRONG: &[&str] = &["\"text\"", "true", "[1.0, 2.0]", "{ a = 1 }", "[]", "1"];

/// One random mutation of `text`.
fn mutate(text: &str, rng: &mut Rng) -> String {
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let values: Vec<usize> = (0..lines.len())
        .filter(|&i| lines[i].contains('=') && !lines[i].trim_start().starts_with('#'))
        .collect();
    match rng.below(6) {
        0 | 1 if !values.is_empty() => {
            // An extreme number in place of a number of a value line.
            let i = values[rng.below(values.len())];
            let (key, value) = lines[i]
                .split_once('=')
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .unwrap_or_default();
            let numbers: Vec<(usize, usize)> = number_spans(&value);
            let x = EXTREMES[rng.below(EXTREMES.len())];
            lines[i] = match numbers.get(rng.below(numbers.len())) {
                Some(&(a, b)) if !numbers.is_empty() => format!("{key}={}{x}{}", &value[..a], &value[b..]),
                _ => format!("{key}= {x}"),
            };
        }
        2 if !values.is_empty() => {
            let i = values[rng.below(values.len())];
            let key = lines[i].split_once('=').map(|(k, _)| k.to_string()).unwrap_or_default();
            lines[i] = format!("{key}= {}", WRONG[rng.below(WRONG.len())]);
        }
        3 if !lines.is_empty() => {
            lines.remove(rng.below(lines.len()));
        }
        4 if !lines.is_empty() => {
            let i = rng.below(lines.len());
            let l = lines[i].clone();
            lines.insert(i, l);
        }
        _ => {
            let joined = lines.join("\n");
            let mut cut = rng.below(joined.len());
            while !joined.is_char_boundary(cut) {
                cut -= 1;
            }
            return joined[..cut].to_string();
        }
    }
    lines.join("\n") + "\n"
}

/// Byte spans of the numbers in a TOML value.
fn number_spans(value: &str) -> Vec<(usize, usize)> {
    let b = value.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let starts = b[i].is_ascii_digit() || (b[i] == b'-' && i + 1 < b.len() && b[i + 1].is_ascii_digit());
        let inside_word = i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_' || b[i - 1] == b'"');
        if starts && !inside_word {
            let a = i;
            i += 1;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b"+-.".contains(&b[i])) {
                i += 1;
            }
            out.push((a, i));
        } else {
            i += 1;
        }
    }
    out
}

fn examples() -> Vec<(String, String)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut out: Vec<(String, String)> = std::fs::read_dir(&dir)
        .expect("examples")
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .map(|p| {
            let name = p
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            let text = std::fs::read_to_string(&p).expect("example");
            (name, text)
        })
        .collect();
    out.sort();
    out
}

/// All numbers of every CSV file in `dir` are finite.
fn outputs_finite(dir: &Path) -> Result<(), String> {
    for entry in std::fs::read_dir(dir).map_err(|e| e.to_string())? {
        let p = entry.map_err(|e| e.to_string())?.path();
        if p.extension().is_some_and(|x| x == "csv") {
            let text = std::fs::read_to_string(&p).map_err(|e| e.to_string())?;
            for line in text.lines().skip(1) {
                for v in line.split(',') {
                    match v.trim().parse::<f64>() {
                        Ok(x) if x.is_finite() => {}
                        _ => return Err(format!("{}: value `{v}`", p.display())),
                    }
                }
            }
        }
    }
    Ok(())
}

/// The bytes of every file in `dir`, by name.
fn files(dir: &Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .filter_map(|e| e.ok())
        .filter_map(|e| {
            let bytes = std::fs::read(e.path()).ok()?;
            Some((e.file_name().to_string_lossy().into_owned(), bytes))
        })
        .collect()
}

/// Run one mutated scenario into `work/out` (resuming the run there when
/// `resume`); `Err` describes a forbidden outcome.
fn run_case(work: &Path, text: &str, limit: f64, resume: bool) -> Result<&'static str, String> {
    let file = work.join("case.toml");
    std::fs::write(&file, text).map_err(|e| e.to_string())?;
    let out = work.join("out");
    let before = if resume {
        files(&out)
    } else {
        let _ = std::fs::remove_dir_all(&out);
        Default::default()
    };
    let mode = if resume { "--resume" } else { "--out" };
    let mut child = Command::new(env!("CARGO_BIN_EXE_veselov"))
        .args(["run", "--quiet", "--force", "--time-limit", &limit.to_string(), mode])
        .arg(&out)
        .arg(&file)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| e.to_string())?;
    let start = Instant::now();
    // The time limit plus room for the preflight, the plots and a loaded machine.
    let hard = Duration::from_secs_f64(limit + 30.0);
    let status = loop {
        if let Some(s) = child.try_wait().map_err(|e| e.to_string())? {
            break s;
        }
        if start.elapsed() > hard {
            let _ = child.kill();
            return Err("hang past the time limit".into());
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let mut stderr = String::new();
    if let Some(mut e) = child.stderr.take() {
        use std::io::Read;
        let _ = e.read_to_string(&mut stderr);
    }
    if status.code().is_none() {
        return Err(format!("killed by a signal: {stderr}"));
    }
    if stderr.contains("panicked") || stderr.contains("memory allocation") {
        return Err(format!("panic or abort: {stderr}"));
    }
    if status.success() {
        let summary = std::fs::read_to_string(out.join("summary.json")).map_err(|e| e.to_string())?;
        if !summary.contains("\"status\": \"ok\"") {
            return Err(format!("exit 0 without status ok: {summary}"));
        }
        outputs_finite(&out)?;
        return Ok("completed");
    }
    // Warnings given before the run (e.g. a rod's step close to its
    // stability limit) are always shown; the error follows them.
    let message = stderr.lines().find(|l| !l.starts_with("warning: ")).unwrap_or_default();
    if !message.starts_with("error: ") {
        return Err(format!("unclean error: {stderr}"));
    }
    if resume && stderr.contains("being resumed") && files(&out) != before {
        return Err(format!("a refused resume changed the run's files: {stderr}"));
    }
    if resume && stderr.contains("being resumed") {
        return Ok("refused resume");
    }
    Ok(if stderr.contains("interrupted") {
        "interrupted"
    } else {
        "error"
    })
}

/// `text` with its `t_end` doubled (as it is when it has none).
fn longer(text: &str) -> String {
    text.lines()
        .map(|l| match l.split_once('=') {
            Some((key, value)) if key.trim() == "t_end" => {
                let value = value.split('#').next().unwrap_or_default().trim();
                match value.parse::<f64>() {
                    Ok(t) => format!("{key}= {:?}", 2.0 * t),
                    Err(_) => l.to_string(),
                }
            }
            _ => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n")
        + "\n"
}

fn fuzz(cases: usize, seed: u64, limit: f64) {
    let work = Scratch::new(&format!("fuzz-{seed}"));
    let examples = examples();
    let mut rng = Rng(seed | 1);
    let mut counts = std::collections::BTreeMap::new();
    let mut failures = Vec::new();
    for case in 0..cases {
        let (name, text) = &examples[case % examples.len()];
        let mut mutated = mutate(text, &mut rng);
        if rng.below(3) == 0 {
            mutated = mutate(&mutated, &mut rng);
        }
        let first = run_case(&work, &mutated, limit, false);
        let resumable = matches!(first, Ok("completed" | "interrupted")) && work.join("out/checkpoint.json").exists();
        match first {
            Ok(kind) => *counts.entry(kind).or_insert(0usize) += 1,
            Err(why) => failures.push(format!("case {case} ({name}):\n{mutated}\n=> {why}")),
        }
        if resumable && rng.below(4) == 0 {
            let again = match rng.below(3) {
                0 => mutated.clone(),
                1 => longer(&mutated),
                _ => mutate(&mutated, &mut rng),
            };
            match run_case(&work, &again, limit, true) {
                Ok(kind) => *counts.entry(kind).or_insert(0usize) += 1,
                Err(why) => failures.push(format!("case {case} ({name}), resumed:\n{again}\n=> {why}")),
            }
        }
    }
    eprintln!(
        "fuzz: {cases} cases, seed {seed}: {counts:?}, {} forbidden",
        failures.len()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn mutated_examples_fail_cleanly_or_complete() {
    fuzz(2 * examples().len(), 0x5eed_0011, 2.0);
}

#[test]
#[ignore = "long run: cargo test --release -p veselov-cli --test fuzz -- --ignored"]
fn mutated_examples_long_run() {
    let cases = std::env::var("VESELOV_FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(5000);
    let seed = std::env::var("VESELOV_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0xF022);
    fuzz(cases, seed, 5.0);
}
