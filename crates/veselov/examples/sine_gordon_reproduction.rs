//! Rerun the sine-Gordon experiment of seed 002 §5.2: kink–antikink on a
//! circle of length 40, N = 255, h = k/8, up to t = 129000 (≈ 5000
//! collisions), for the triangle (5.8), symmetric rectangle (5.12),
//! Vu-Quoc–Li (5.14) and Guo (5.15) schemes.
//!
//! ```text
//! cargo run --release -p veselov --example sine_gordon_reproduction -- [t_end] [scheme,scheme,...] [rel_tol]
//! ```
//!
//! `rel_tol` (default 1e-13) is the level-solve tolerance; Guo's exactly
//! conserved energy `E^{j+½}` stays at round-off only with tight solves
//! (e.g. 1e-16), otherwise it drifts with the accumulated solve error.
//!
//! Writes `out/sine_gordon_<scheme>_blocks.csv` (min/mean/max of the energy
//! error over blocks of 5000 levels, as in Figs. 5.7, 5.8, 5.11) and
//! `out/sine_gordon_<scheme>_final.csv` (the final waveform mod 2π), and
//! prints the wall time of each run.

use std::fs::{File, create_dir_all};
use std::io::{BufWriter, Write};
use std::time::Instant;

use veselov::field::{FieldRunConfig, Scheme, run_lattice};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let t_end: f64 = match args.next() {
        Some(s) => s.parse()?,
        None => 129_000.0,
    };
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
    let rel_tol: f64 = match args.next() {
        Some(s) => s.parse()?,
        None => 1e-13,
    };
    create_dir_all("out")?;
    for scheme in schemes {
        let mut config = FieldRunConfig::sine_gordon_section_5_2(scheme, t_end)?;
        config.solver.rel_tol = rel_tol;
        let lat = config.lattice;
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
            "{}: {} levels to t = {:.1} in {:.2} s ({:.1} ns per node update, {:.3} iterations per level), E0 = {:.9}, status {:?}",
            scheme.name(),
            levels,
            run.final_time,
            wall,
            wall * 1e9 / (levels as f64 * lat.nodes() as f64),
            run.iterations as f64 / levels as f64,
            run.initial_energy,
            run.status
        );
        let mut f = BufWriter::new(File::create(format!("out/sine_gordon_{}_blocks.csv", scheme.name()))?);
        writeln!(f, "block,t_start,t_end,min,mean,max")?;
        for (b, s) in run.energy_blocks.iter().enumerate() {
            let (t0, t1) = (lat.t(s.first_level), lat.t(s.first_level + s.levels));
            writeln!(f, "{b},{t0},{t1},{:e},{:e},{:e}", s.min, s.mean, s.max)?;
        }
        let mut f = BufWriter::new(File::create(format!("out/sine_gordon_{}_final.csv", scheme.name()))?);
        writeln!(f, "x,y")?;
        for (i, y) in run.final_level.iter().enumerate() {
            writeln!(f, "{},{}", lat.x(i), y.rem_euclid(std::f64::consts::TAU))?;
        }
        if let Some((first, last)) = run.energy_blocks.first().zip(run.energy_blocks.last()) {
            println!(
                "  first block mean {:.3e} [{:.3e}, {:.3e}], last block mean {:.3e} [{:.3e}, {:.3e}]",
                first.mean, first.min, first.max, last.mean, last.min, last.max
            );
        }
    }
    Ok(())
}
