//! One scheme of §5.2 over the whole run, in `out/section_5_2/<scheme>/`
//! (`guo-k16/` for Guo at h = k/16):
//! * `blocks.csv` and `blocks.svg`: min/mean/max of the energy error E − E₀
//!   over consecutive blocks of 5000 levels (Figs. 5.7, 5.8, 5.11), with the
//!   min/mean/max of the high-frequency indicator max_i |Δ⁴y_i| per block
//!   (`high_frequency.svg`);
//! * `initial_energy.svg`, `final_energy.svg`: the energy error over the
//!   first and the last 5000 levels;
//! * `snapshots.npy` (10 waveforms spread over the run, unwrapped) and
//!   `final_waveform.svg` (mod 2π, Fig. 5.6);
//! * `collisions.csv`: the time of closest approach of every kink–antikink
//!   collision;
//! * `last_collision.npy` (rows: t, then the field at every node) and
//!   `last_collision.svg`: the waveform through the last collision with
//!   three time units of run after it, every half time unit, centred on the
//!   closest approach (Figs. 5.9, 5.10);
//! * Guo only, `companion_blocks.csv` and `companion_*.svg`: the energy the
//!   paper prints under (5.15) and the footnote-4 energy beside the
//!   exactly conserved E^{j+½} (Fig. 5.8).

use std::collections::VecDeque;
use std::path::Path;
use std::time::Instant;

use veselov::spacetime::{
    BlockAccumulator, BlockStats, CollisionCounter, FieldRun, FieldRunConfig, Lattice, Scheme, SineGordon,
    guo_printed_energy, rectangle_energy, run_lattice,
};
use veselov_cli::output::Table;
use veselov_cli::plot::Scale;

use crate::{BLOCK, plot, write_npy};

/// Frames kept through a collision, one every half time unit, half of them
/// after the closest approach.
const FRAMES: usize = 12;

/// The energies of Fig. 5.8 besides the conserved one, at every level.
struct Companions {
    /// The last three levels, physical values (oldest first).
    levels: VecDeque<Vec<f64>>,
    first: Option<[f64; 2]>,
    printed: BlockAccumulator,
    footnote4: BlockAccumulator,
    initial: Vec<[f64; 3]>,
    last: VecDeque<[f64; 3]>,
}

impl Companions {
    fn push(&mut self, lat: &Lattice, t: f64, level: usize, physical: impl Iterator<Item = f64>) {
        let mut buffer = if self.levels.len() == 3 {
            self.levels.pop_front().unwrap_or_default()
        } else {
            Vec::new()
        };
        buffer.clear();
        buffer.extend(physical);
        self.levels.push_back(buffer);
        if self.levels.len() < 3 {
            return;
        }
        let (a, b, c) = (&self.levels[0], &self.levels[1], &self.levels[2]);
        let e = [
            guo_printed_energy(&SineGordon, lat, a, b, c),
            rectangle_energy(&SineGordon, lat, b, c),
        ];
        let e0 = *self.first.get_or_insert(e);
        let d = [e[0] - e0[0], e[1] - e0[1]];
        self.printed.push(level, d[0]);
        self.footnote4.push(level, d[1]);
        let row = [t, d[0], d[1]];
        if self.initial.len() < BLOCK {
            self.initial.push(row);
        }
        if self.last.len() == BLOCK {
            self.last.pop_front();
        }
        self.last.push_back(row);
    }
}

fn time_window(run: &FieldRun, lat: &Lattice, range: std::ops::Range<usize>) -> (Vec<f64>, Vec<f64>) {
    let e0 = run.initial_energy;
    let range = range.start.min(run.energies.len())..range.end.min(run.energies.len());
    // energies[m] is E_{m+1}, of the levels (m + 1, m + 2).
    let t = range.clone().map(|m| lat.t(m + 1)).collect();
    let e = run.energies[range].iter().map(|e| e - e0).collect();
    (t, e)
}

fn block_columns(blocks: &[BlockStats]) -> [Vec<f64>; 3] {
    [
        blocks.iter().map(|b| b.min).collect(),
        blocks.iter().map(|b| b.mean).collect(),
        blocks.iter().map(|b| b.max).collect(),
    ]
}

/// Run `scheme` at h = k/`ratio` to `t_end` and write its files.
pub fn run(
    root: &Path,
    scheme: Scheme,
    ratio: f64,
    t_end: f64,
    rel_tol: f64,
) -> Result<(), Box<dyn std::error::Error>> {
    let name = if ratio == 8.0 {
        scheme.name().to_string()
    } else {
        format!("{}-k{ratio}", scheme.name())
    };
    let dir = root.join(&name);
    std::fs::create_dir_all(&dir)?;
    let mut config = FieldRunConfig::sine_gordon_section_5_2(scheme, t_end)?;
    config.lattice = Lattice::periodic(255, 40.0, ratio)?;
    config.solver.rel_tol = rel_tol;
    config.keep_energies = true;
    config.energy_block = BLOCK;
    let lat = config.lattice;
    let total = (t_end / lat.dt()).ceil() as usize;
    config.snapshot_every = (total / 10).max(1);
    let sample = (0.5 / lat.dt()).round() as usize;
    let mut ring: VecDeque<Vec<f64>> = VecDeque::with_capacity(FRAMES);
    let mut last_collision: Vec<Vec<f64>> = Vec::new();
    // Samples still to take before the ring is centred on the latest collision.
    let mut pending: Option<usize> = None;
    let mut counter = CollisionCounter::new();
    let mut companions = (scheme == Scheme::Guo).then(|| Companions {
        levels: VecDeque::with_capacity(3),
        first: None,
        printed: BlockAccumulator::new(BLOCK),
        footnote4: BlockAccumulator::new(BLOCK),
        initial: Vec::new(),
        last: VecDeque::new(),
    });
    let start = Instant::now();
    let mut next_report = 0.1;
    let run = run_lattice(&config, |info| {
        let Some(values) = info.values else {
            return true;
        };
        let physical = values.iter().map(|v| v + info.recentred_by);
        if let Some(c) = companions.as_mut() {
            c.push(&lat, info.time, info.level, physical.clone());
        }
        if info.level.is_multiple_of(sample) {
            if ring.len() == FRAMES {
                ring.pop_front();
            }
            // Background near 0: subtract the 2π multiple nearest node 0.
            let shift = std::f64::consts::TAU * ((values[0] + info.recentred_by) / std::f64::consts::TAU).round();
            ring.push_back(
                std::iter::once(info.time)
                    .chain(physical.clone().map(|v| v - shift))
                    .collect(),
            );
            pending = match pending {
                Some(0) => {
                    last_collision = ring.iter().cloned().collect();
                    None
                }
                p => p.map(|n| n - 1),
            };
        }
        if counter.observe(info.time, values) {
            // Completed: the ring holds the frames up to now; wait until
            // half of them follow the closest approach.
            let dip = counter.times().last().copied().unwrap_or(info.time);
            let after = ring.iter().filter(|f| f[0] > dip).count();
            pending = Some((FRAMES / 2).saturating_sub(after + 1));
        }
        let done = info.level as f64 / info.total_levels as f64;
        if done >= next_report {
            eprintln!("{name}: {:>3.0}% (t = {:.0})", done * 100.0, info.time);
            next_report += 0.1;
        }
        true
    })?;
    let wall = start.elapsed().as_secs_f64();
    let levels = run.final_index - 1;
    println!(
        "{name}: {levels} levels to t = {:.1} in {wall:.1} s ({:.1} ns per node update, {:.3} iterations per level), \
         E0 = {:.9}, status {:?}",
        run.final_time,
        wall * 1e9 / (levels as f64 * lat.nodes() as f64),
        run.iterations as f64 / levels as f64,
        run.initial_energy,
        run.status
    );
    write_blocks(&dir, &name, &run, &lat)?;
    write_waveforms(&dir, &name, &run, &lat)?;
    write_collisions(&dir, &name, &run, &last_collision)?;
    if let Some(c) = companions {
        write_companions(&dir, &name, &run, &lat, c)?;
    }
    Ok(())
}

fn write_blocks(dir: &Path, name: &str, run: &FieldRun, lat: &Lattice) -> Result<(), Box<dyn std::error::Error>> {
    let blocks = Table {
        header: ["t_start", "t_end", "min", "mean", "max", "hf_min", "hf_mean", "hf_max"]
            .map(String::from)
            .to_vec(),
        rows: run
            .energy_blocks
            .iter()
            .zip(&run.high_frequency_blocks)
            .map(|(b, f)| {
                vec![
                    lat.t(b.first_level),
                    lat.t(b.first_level + b.levels),
                    b.min,
                    b.mean,
                    b.max,
                    f.min,
                    f.mean,
                    f.max,
                ]
            })
            .collect(),
    };
    blocks.write_csv(&dir.join("blocks.csv"))?;
    let t: Vec<f64> = blocks.rows.iter().map(|r| r[0]).collect();
    let [lo, mean, hi] = block_columns(&run.energy_blocks);
    plot(
        &dir.join("blocks.svg"),
        &format!("{name}: energy error per block of {BLOCK} levels"),
        ("time t", "E − E₀"),
        &[("min", &t, &lo), ("mean", &t, &mean), ("max", &t, &hi)],
        Scale::Linear,
        false,
    )?;
    let [_, hf_mean, hf_max] = block_columns(&run.high_frequency_blocks);
    plot(
        &dir.join("high_frequency.svg"),
        &format!("{name}: max |4th difference| per block of {BLOCK} levels"),
        ("time t", "max_i |Δ⁴y_i|"),
        &[("block mean", &t, &hf_mean), ("block max", &t, &hf_max)],
        Scale::Linear,
        false,
    )?;
    let n = run.energies.len();
    for (file, title, range) in [
        ("initial_energy.svg", "initial", 0..BLOCK),
        ("final_energy.svg", "final", n.saturating_sub(BLOCK)..n),
    ] {
        let (t, e) = time_window(run, lat, range);
        plot(
            &dir.join(file),
            &format!("{name}: {title} energy error"),
            ("time t", "E − E₀"),
            &[("E − E₀", &t, &e)],
            Scale::Linear,
            false,
        )?;
    }
    if let (Some(first), Some(last)) = (run.energy_blocks.first(), run.energy_blocks.last()) {
        println!(
            "  energy: first block mean {:.3e} [{:.3e}, {:.3e}], last block mean {:.3e} [{:.3e}, {:.3e}]",
            first.mean, first.min, first.max, last.mean, last.min, last.max
        );
    }
    if let (Some(first), Some(last)) = (run.high_frequency_blocks.first(), run.high_frequency_blocks.last()) {
        println!(
            "  high-frequency indicator: first block max {:.3e}, last block max {:.3e}, run max {:.3e}",
            first.max, last.max, run.high_frequency_max
        );
    }
    Ok(())
}

fn write_waveforms(dir: &Path, name: &str, run: &FieldRun, lat: &Lattice) -> Result<(), Box<dyn std::error::Error>> {
    let snaps: Vec<Vec<f64>> = run
        .snapshots
        .iter()
        .map(|s| s.values.iter().map(|v| v + s.recentred_by).collect())
        .collect();
    write_npy(&dir.join("snapshots.npy"), &snaps)?;
    let x: Vec<f64> = (0..lat.nodes()).map(|i| lat.x(i)).collect();
    let wrapped: Vec<f64> = run
        .final_level
        .iter()
        .map(|v| v.rem_euclid(std::f64::consts::TAU))
        .collect();
    plot(
        &dir.join("final_waveform.svg"),
        &format!("{name}: waveform mod 2π at t = {:.0}", run.final_time),
        ("x", "φ mod 2π"),
        &[("φ", &x, &wrapped)],
        Scale::Linear,
        false,
    )?;
    Ok(())
}

fn write_collisions(
    dir: &Path,
    name: &str,
    run: &FieldRun,
    last_collision: &[Vec<f64>],
) -> Result<(), Box<dyn std::error::Error>> {
    let times = run.collision_times.as_slice();
    Table {
        header: vec!["collision".into(), "t".into()],
        rows: times
            .iter()
            .enumerate()
            .map(|(i, &t)| vec![(i + 1) as f64, t])
            .collect(),
    }
    .write_csv(&dir.join("collisions.csv"))?;
    let period = match times {
        [first, .., last] => (last - first) / (times.len() - 1) as f64,
        _ => f64::NAN,
    };
    println!(
        "  collisions: {} to t = {:.0} (2ct/L = {:.1} with c = 0.7773), mean interval {period:.4}",
        times.len(),
        run.final_time,
        2.0 * 0.7773 * run.final_time / 40.0
    );
    if last_collision.is_empty() {
        return Ok(());
    }
    write_npy(&dir.join("last_collision.npy"), last_collision)?;
    let nodes = last_collision[0].len() - 1;
    let x: Vec<f64> = (0..nodes).map(|i| 40.0 * i as f64 / nodes as f64).collect();
    let labels: Vec<String> = last_collision.iter().map(|f| format!("t = {:.1}", f[0])).collect();
    let curves: Vec<(&str, &[f64], &[f64])> = last_collision
        .iter()
        .zip(&labels)
        .step_by(3)
        .map(|(f, label)| (label.as_str(), x.as_slice(), &f[1..]))
        .collect();
    plot(
        &dir.join("last_collision.svg"),
        &format!("{name}: waveforms through the last collision"),
        ("x", "φ (background near 0)"),
        &curves,
        Scale::Linear,
        false,
    )?;
    Ok(())
}

fn write_companions(
    dir: &Path,
    name: &str,
    run: &FieldRun,
    lat: &Lattice,
    c: Companions,
) -> Result<(), Box<dyn std::error::Error>> {
    let printed = c.printed.finish();
    let footnote4 = c.footnote4.finish();
    let rows: Vec<Vec<f64>> = printed
        .iter()
        .zip(&footnote4)
        .zip(&run.energy_blocks)
        .map(|((p, f), e)| {
            vec![
                lat.t(p.first_level),
                lat.t(p.first_level + p.levels),
                e.min,
                e.mean,
                e.max,
                p.min,
                p.mean,
                p.max,
                f.min,
                f.mean,
                f.max,
            ]
        })
        .collect();
    let header = [
        "t_start",
        "t_end",
        "conserved_min",
        "conserved_mean",
        "conserved_max",
        "printed_min",
        "printed_mean",
        "printed_max",
        "footnote4_min",
        "footnote4_mean",
        "footnote4_max",
    ];
    let table = Table {
        header: header.map(String::from).to_vec(),
        rows,
    };
    table.write_csv(&dir.join("companion_blocks.csv"))?;
    let col = |k: usize| -> Vec<f64> { table.rows.iter().map(|r| r[k]).collect() };
    let t = col(0);
    let (conserved, printed_mean, footnote4_mean) = (col(3), col(6), col(9));
    plot(
        &dir.join("companion_blocks.svg"),
        &format!("{name}: block means of three energy errors"),
        ("time t", "E − E₀ (block mean)"),
        &[
            ("conserved E^{j+½}", &t, &conserved),
            ("printed (5.15)", &t, &printed_mean),
            ("footnote 4", &t, &footnote4_mean),
        ],
        Scale::Linear,
        false,
    )?;
    for (file, title, rows) in [
        ("companion_initial.svg", "initial", c.initial.clone()),
        ("companion_final.svg", "final", c.last.iter().copied().collect()),
    ] {
        let t: Vec<f64> = rows.iter().map(|r| r[0]).collect();
        let p: Vec<f64> = rows.iter().map(|r| r[1]).collect();
        let f: Vec<f64> = rows.iter().map(|r| r[2]).collect();
        plot(
            &dir.join(file),
            &format!("{name}: {title} printed and footnote-4 energy errors"),
            ("time t", "E − E₀"),
            &[("printed (5.15)", &t, &p), ("footnote 4", &t, &f)],
            Scale::Linear,
            false,
        )?;
    }
    let spread = |b: &[BlockStats]| {
        let lo = b.iter().map(|x| x.min).fold(f64::INFINITY, f64::min);
        let hi = b.iter().map(|x| x.max).fold(f64::NEG_INFINITY, f64::max);
        hi - lo
    };
    let drift = |b: &[BlockStats]| match b {
        [first, .., last] => last.mean - first.mean,
        _ => f64::NAN,
    };
    println!(
        "  energies: conserved spread {:.3e} (drift of block means {:.3e}); printed spread {:.3e} (drift {:.3e}); \
         footnote-4 spread {:.3e} (drift {:.3e})",
        spread(&run.energy_blocks),
        drift(&run.energy_blocks),
        spread(&printed),
        drift(&printed),
        spread(&footnote4),
        drift(&footnote4)
    );
    Ok(())
}
