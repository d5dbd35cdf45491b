//! Rerun the sine-Gordon experiments of seed 002 §5.2 and plot them.
//!
//! ```text
//! cargo run --release -p veselov-cli --example sine_gordon_section_5_2 -- [t_end] [schemes] [rel_tol]
//! ```
//!
//! Defaults: t_end = 129000 (≈ 5000 kink–antikink collisions, 6.58 million
//! levels), schemes `triangle,symmetric-rectangle,vu-quoc-li,guo`, level-solve
//! tolerance 1e-13. Lattice convention: node (i, j) with i = space and
//! j = time; N = 255 nodes on a circle of length 40, so the paper's
//! k = 40/255 is `dx` and its h = k/8 is `dt`.
//!
//! For each scheme, in `out/section_5_2/<scheme>/`:
//! * `blocks.csv` and `blocks.svg`: min/mean/max of the energy error
//!   E − E₀ over consecutive blocks of 5000 levels (Figs. 5.7, 5.8, 5.11);
//! * `initial_energy.svg`, `final_energy.svg`: the energy error over the first
//!   and the last 5000 levels;
//! * `snapshots.npy` (10 waveforms spread over the run, unwrapped) and
//!   `final_waveform.svg` (mod 2π, Fig. 5.6).
//!
//! Then the even/odd experiment of Fig. 5.5: the symmetric rectangle scheme
//! with N = 256 and N = 255 up to t = min(t_end, 12000), measuring the
//! response to a seeded ε(−1)^i perturbation every 500 levels
//! (`out/section_5_2/even_odd.csv` and `.svg`): with even N the (−1)^{i+j}
//! mode of (5.12) grows linearly, with odd N it cannot exist.
//!
//! Wall time of each run and ns per node update are printed.

use std::path::{Path, PathBuf};
use std::time::Instant;

use veselov::field::{
    FastMarcher, FieldRun, FieldRunConfig, InitialData, Lattice, Scheme, SineGordon, SolverOptions, run_lattice,
};
use veselov_cli::output::{Table, npy_header_shape};
use veselov_cli::plot::{Figure, Scale, Series, draw};

const BLOCK: usize = 5000;

fn plot(path: &Path, title: &str, y_label: &str, series: Vec<Series>, y_scale: Scale) -> Result<(), String> {
    let fig = Figure {
        title,
        x_label: "time t",
        y_label,
        x_scale: Scale::Linear,
        y_scale,
        series,
        markers: false,
        equal_aspect: false,
    };
    draw(path, &fig).map_err(|e| e.to_string())
}

fn write_npy(path: &Path, rows: &[Vec<f64>]) -> Result<(), Box<dyn std::error::Error>> {
    let mut bytes = npy_header_shape(&[rows.len(), rows.first().map_or(0, Vec::len)]);
    for v in rows.iter().flatten() {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    std::fs::write(path, bytes)?;
    Ok(())
}

fn energy_window(run: &FieldRun, lat: &Lattice, range: std::ops::Range<usize>) -> (Vec<f64>, Vec<f64>) {
    let e0 = run.initial_energy;
    let range = range.start.min(run.energies.len())..range.end.min(run.energies.len());
    // energies[m] is E_{m+1}, of the levels (m + 1, m + 2).
    let t = range.clone().map(|m| lat.t(m + 1)).collect();
    let e = run.energies[range].iter().map(|e| e - e0).collect();
    (t, e)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let t_end: f64 = args.next().map(|s| s.parse()).transpose()?.unwrap_or(129_000.0);
    let schemes: Vec<Scheme> = match args.next() {
        Some(list) => list
            .split(',')
            .map(|s| Scheme::from_name(s).ok_or_else(|| format!("unknown scheme `{s}`")))
            .collect::<Result<_, _>>()?,
        None => vec![
            Scheme::Triangle,
            Scheme::SymmetricRectangle,
            Scheme::VuQuocLi,
            Scheme::Guo,
        ],
    };
    let rel_tol: f64 = args.next().map(|s| s.parse()).transpose()?.unwrap_or(1e-13);
    let root = PathBuf::from("out/section_5_2");
    for scheme in schemes {
        let dir = root.join(scheme.name());
        std::fs::create_dir_all(&dir)?;
        let mut config = FieldRunConfig::sine_gordon_section_5_2(scheme, t_end)?;
        config.solver.rel_tol = rel_tol;
        config.keep_energies = true;
        let lat = config.lattice;
        let total = (t_end / lat.dt()).ceil() as usize;
        config.snapshot_every = (total / 10).max(1);
        let start = Instant::now();
        let mut next_report = 0.1;
        let run = run_lattice(&config, |info| {
            let done = info.level as f64 / info.total_levels as f64;
            if done >= next_report {
                eprintln!("{}: {:>3.0}% (t = {:.0})", scheme.name(), done * 100.0, info.time);
                next_report += 0.1;
            }
            true
        })?;
        let wall = start.elapsed().as_secs_f64();
        let levels = run.final_index - 1;
        println!(
            "{}: {levels} levels to t = {:.1} in {wall:.1} s ({:.1} ns per node update, {:.3} iterations per level), \
             E0 = {:.9}, status {:?}",
            scheme.name(),
            run.final_time,
            wall * 1e9 / (levels as f64 * lat.nodes() as f64),
            run.iterations as f64 / levels as f64,
            run.initial_energy,
            run.status
        );
        let blocks = Table {
            header: ["t_start", "t_end", "min", "mean", "max"].map(String::from).to_vec(),
            rows: run
                .energy_blocks
                .iter()
                .map(|b| {
                    vec![
                        lat.t(b.first_level),
                        lat.t(b.first_level + b.levels),
                        b.min,
                        b.mean,
                        b.max,
                    ]
                })
                .collect(),
        };
        blocks.write_csv(&dir.join("blocks.csv"))?;
        let t: Vec<f64> = blocks.rows.iter().map(|r| r[0]).collect();
        let col = |k: usize| -> Vec<f64> { blocks.rows.iter().map(|r| r[k]).collect() };
        let (lo, mean, hi) = (col(2), col(3), col(4));
        let title = format!("{}: energy error per block of {BLOCK} levels", scheme.name());
        plot(
            &dir.join("blocks.svg"),
            &title,
            "E − E₀",
            vec![
                Series {
                    label: "min",
                    x: &t,
                    y: &lo,
                },
                Series {
                    label: "mean",
                    x: &t,
                    y: &mean,
                },
                Series {
                    label: "max",
                    x: &t,
                    y: &hi,
                },
            ],
            Scale::Linear,
        )?;
        let (t0, e0) = energy_window(&run, &lat, 0..BLOCK);
        plot(
            &dir.join("initial_energy.svg"),
            &format!("{}: initial energy error", scheme.name()),
            "E − E₀",
            vec![Series {
                label: "E − E₀",
                x: &t0,
                y: &e0,
            }],
            Scale::Linear,
        )?;
        let n = run.energies.len();
        let (t1, e1) = energy_window(&run, &lat, n.saturating_sub(BLOCK)..n);
        plot(
            &dir.join("final_energy.svg"),
            &format!("{}: final energy error", scheme.name()),
            "E − E₀",
            vec![Series {
                label: "E − E₀",
                x: &t1,
                y: &e1,
            }],
            Scale::Linear,
        )?;
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
        let fig = Figure {
            title: &format!("{}: waveform mod 2π at t = {:.0}", scheme.name(), run.final_time),
            x_label: "x",
            y_label: "φ mod 2π",
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            series: vec![Series {
                label: "φ",
                x: &x,
                y: &wrapped,
            }],
            markers: false,
            equal_aspect: false,
        };
        draw(&dir.join("final_waveform.svg"), &fig).map_err(|e| e.to_string())?;
        if let (Some(first), Some(last)) = (run.energy_blocks.first(), run.energy_blocks.last()) {
            println!(
                "  first block mean {:.3e} [{:.3e}, {:.3e}], last block mean {:.3e} [{:.3e}, {:.3e}]",
                first.mean, first.min, first.max, last.mean, last.min, last.max
            );
        }
    }
    even_odd(&root, t_end.min(12_000.0), rel_tol)
}

/// Fig. 5.5: the (−1)^{i+j} mode of the symmetric rectangle scheme. Two runs
/// per lattice, one with the kink–antikink data and one with ε(−1)^i added to
/// both initial levels (ε = 1e-10); the alternating part |Σ_i (−1)^i Δy_i|/N
/// of their difference is the mode's response. With N = 256 it grows
/// linearly, as 2εj (the mode (A + Bj)(−1)^{i+j} solves the scheme linearised
/// about any solution); with N = 255 the mode does not exist and it stays
/// O(ε).
fn even_odd(root: &Path, t_end: f64, rel_tol: f64) -> Result<(), Box<dyn std::error::Error>> {
    let eps = 1e-10;
    std::fs::create_dir_all(root)?;
    let mut columns: Vec<Vec<(f64, f64)>> = Vec::new();
    for nodes in [256usize, 255] {
        let lattice = Lattice::periodic(nodes, 40.0, 8.0)?;
        let data = InitialData::KinkAntikink {
            epsilon: 1e-6,
            paper_start: true,
        };
        let (y0, y1) = data.levels(&lattice)?;
        let seeded = |y: &[f64]| -> Vec<f64> {
            y.iter()
                .enumerate()
                .map(|(i, v)| if i % 2 == 0 { v + eps } else { v - eps })
                .collect()
        };
        let opts = SolverOptions {
            rel_tol,
            ..SolverOptions::default()
        };
        let mut plain = FastMarcher::new(SineGordon, Scheme::SymmetricRectangle, lattice, &y0, &y1, opts)?;
        let mut kicked = FastMarcher::new(
            SineGordon,
            Scheme::SymmetricRectangle,
            lattice,
            &seeded(&y0),
            &seeded(&y1),
            opts,
        )?;
        let levels = (t_end / lattice.dt()).ceil() as usize;
        let start = Instant::now();
        let mut column = Vec::new();
        for j in 2..=levels {
            plain.step()?;
            kicked.step()?;
            if j % 500 == 0 {
                // The alternating part of the difference: a smooth difference
                // (e.g. a slightly shifted kink) sums to ~0 against (−1)^i.
                let d: f64 = plain
                    .current()
                    .iter()
                    .zip(kicked.current())
                    .enumerate()
                    .map(|(i, (a, b))| if i % 2 == 0 { b - a } else { a - b })
                    .sum();
                column.push((plain.time(), d.abs() / nodes as f64));
            }
        }
        println!(
            "symmetric rectangle, N = {nodes}: t = {:.0} in {:.1} s, response to ε(−1)^i: {:.3e} (ε = {eps:e})",
            plain.time(),
            start.elapsed().as_secs_f64(),
            column.last().map_or(f64::NAN, |c| c.1),
        );
        columns.push(column);
    }
    let table = Table {
        header: vec!["t".into(), "response_N256".into(), "response_N255".into()],
        rows: columns[0]
            .iter()
            .zip(&columns[1])
            .map(|(a, b)| vec![a.0, a.1, b.1])
            .collect(),
    };
    table.write_csv(&root.join("even_odd.csv"))?;
    let t: Vec<f64> = table.rows.iter().map(|r| r[0]).collect();
    let even: Vec<f64> = table.rows.iter().map(|r| r[1]).collect();
    let odd: Vec<f64> = table.rows.iter().map(|r| r[2]).collect();
    plot(
        &root.join("even_odd.svg"),
        "Symmetric rectangle (5.12): response to ε(−1)^i",
        "|Σ(−1)^i Δy_i|/N",
        vec![
            Series {
                label: "N = 256",
                x: &t,
                y: &even,
            },
            Series {
                label: "N = 255",
                x: &t,
                y: &odd,
            },
        ],
        Scale::Log,
    )?;
    Ok(())
}
