//! Fig. 5.5: the (−1)^{i+j} mode of the symmetric rectangle scheme (5.12),
//! which exists on periodic lattices with an even number of nodes.
//!
//! [`natural`] runs the experiment as the paper did: the kink–antikink data
//! on N = 256 and N = 255 nodes, nothing added. Every 500 levels it records
//! the amplitude of the highest Fourier mode (the sawtooth (−1)^i for even
//! N; `highest_mode_amplitude`) and the high-frequency
//! indicator (`even_odd_natural.csv`, `even_odd_natural.svg`), and draws the
//! paper's four panels for each N (`fig5_5_N<N>_{a,b,c,d}.svg`): waveforms
//! through the first collision, the footnote-4 energy error over the first
//! 5000 levels, the waveform mod 2π at t ≈ 11855 (about 460 collisions;
//! the last level if the run is shorter) and the values at grid points
//! 1..16 there.
//!
//! [`seeded`] measures the mode's linear response instead: two runs per
//! lattice, one with ε(−1)^i (ε = 1e-10) added to both initial levels, and
//! the alternating part of their difference every 500 levels
//! (`even_odd_seeded.csv`, `even_odd_seeded.svg`). With N = 256 it grows
//! linearly, as 2εj (the mode (A + Bj)(−1)^{i+j} solves the scheme
//! linearised about any solution); with N = 255 the mode does not exist and
//! the response stays O(ε).

use std::path::Path;
use std::time::Instant;

use veselov::spacetime::{
    FastMarcher, FieldRunConfig, InitialData, Lattice, Scheme, SineGordon, SolverOptions, fourth_difference_max,
    highest_mode_amplitude, run_lattice,
};
use veselov_cli::output::Table;
use veselov_cli::plot::Scale;

use crate::{BLOCK, plot};

/// The paper's bottom panels are at t ≈ 11855.
const LATE: f64 = 11_855.0;
/// Times of the waveforms through the first collision (closest approach
/// near t = 19).
const COLLISION: [f64; 5] = [17.0, 18.0, 19.0, 20.0, 21.0];

/// The unperturbed runs and the four panels per lattice.
pub fn natural(root: &Path, t_end: f64, rel_tol: f64) -> Result<(), Box<dyn std::error::Error>> {
    std::fs::create_dir_all(root)?;
    let mut columns: Vec<Vec<[f64; 3]>> = Vec::new();
    for nodes in [256usize, 255] {
        let mut config = FieldRunConfig::sine_gordon_section_5_2(Scheme::SymmetricRectangle, t_end)?;
        config.lattice = Lattice::periodic(nodes, 40.0, 8.0)?;
        config.solver.rel_tol = rel_tol;
        config.keep_energies = true;
        config.energy_block = 0;
        let lat = config.lattice;
        let late_level = ((LATE.min(t_end) / lat.dt()).round() as usize).max(2);
        let collision_levels: Vec<usize> = COLLISION.iter().map(|t| (t / lat.dt()).round() as usize).collect();
        let mut column = Vec::new();
        let mut collision_frames: Vec<(f64, Vec<f64>)> = Vec::new();
        let mut late: Option<(f64, Vec<f64>)> = None;
        let start = Instant::now();
        let run = run_lattice(&config, |info| {
            let Some(values) = info.values else {
                return true;
            };
            let physical = || values.iter().map(|v| v + info.recentred_by).collect::<Vec<f64>>();
            if info.level.is_multiple_of(500) {
                column.push([
                    info.time,
                    highest_mode_amplitude(values),
                    fourth_difference_max(&lat, values),
                ]);
            }
            if collision_levels.contains(&info.level) {
                collision_frames.push((info.time, physical()));
            }
            if info.level == late_level {
                late = Some((info.time, physical()));
            }
            true
        })?;
        let late = late.unwrap_or((run.final_time, run.final_level.clone()));
        let first = column.first().copied().unwrap_or([f64::NAN; 3]);
        let halfway = column.get(column.len() / 2).copied().unwrap_or([f64::NAN; 3]);
        let last = column.last().copied().unwrap_or([f64::NAN; 3]);
        println!(
            "symmetric rectangle, N = {nodes}, unperturbed: t = {:.0} in {:.1} s, status {:?}; highest-mode amplitude {:.3e} at \
             t = {:.0}, {:.3e} at t = {:.0}, {:.3e} at t = {:.0}; max |Δ⁴y| {:.3e} → {:.3e}",
            run.final_time,
            start.elapsed().as_secs_f64(),
            run.status,
            first[1],
            first[0],
            halfway[1],
            halfway[0],
            last[1],
            last[0],
            first[2],
            last[2],
        );
        panels(
            root,
            nodes,
            &lat,
            &run.energies,
            run.initial_energy,
            &collision_frames,
            &late,
        )?;
        columns.push(column);
    }
    let table = Table {
        header: ["t", "amplitude_N256", "amplitude_N255", "hf_N256", "hf_N255"]
            .map(String::from)
            .to_vec(),
        rows: columns[0]
            .iter()
            .zip(&columns[1])
            .map(|(a, b)| vec![a[0], a[1], b[1], a[2], b[2]])
            .collect(),
    };
    table.write_csv(&root.join("even_odd_natural.csv"))?;
    let col = |k: usize| -> Vec<f64> { table.rows.iter().map(|r| r[k]).collect() };
    let (t, a256, a255) = (col(0), col(1), col(2));
    plot(
        &root.join("even_odd_natural.svg"),
        "Symmetric rectangle (5.12), no perturbation: highest-mode amplitude",
        ("time t", "amplitude of the highest mode"),
        &[("N = 256", &t, &a256), ("N = 255", &t, &a255)],
        Scale::Log,
        false,
    )?;
    Ok(())
}

/// The four panels of Fig. 5.5 for the lattice of `nodes` nodes.
fn panels(
    root: &Path,
    nodes: usize,
    lat: &Lattice,
    energies: &[f64],
    e0: f64,
    collision: &[(f64, Vec<f64>)],
    (t_late, late): &(f64, Vec<f64>),
) -> Result<(), Box<dyn std::error::Error>> {
    let x: Vec<f64> = (0..nodes).map(|i| lat.x(i)).collect();
    let labels: Vec<String> = collision.iter().map(|(t, _)| format!("t = {t:.1}")).collect();
    let curves: Vec<(&str, &[f64], &[f64])> = collision
        .iter()
        .zip(&labels)
        .map(|((_, y), label)| (label.as_str(), x.as_slice(), y.as_slice()))
        .collect();
    let file = |panel: &str| root.join(format!("fig5_5_N{nodes}_{panel}.svg"));
    plot(
        &file("a"),
        &format!("(5.12), N = {nodes}: waveforms through the first collision"),
        ("x", "φ"),
        &curves,
        Scale::Linear,
        false,
    )?;
    let window = &energies[..energies.len().min(BLOCK)];
    // energies[m] is the footnote-4 energy of the levels (m + 1, m + 2).
    let t: Vec<f64> = (0..window.len()).map(|m| lat.t(m + 1)).collect();
    let e: Vec<f64> = window.iter().map(|e| e - e0).collect();
    plot(
        &file("b"),
        &format!("(5.12), N = {nodes}: footnote-4 energy error, first {BLOCK} levels"),
        ("time t", "E − E₀"),
        &[("E − E₀", &t, &e)],
        Scale::Linear,
        false,
    )?;
    let wrapped: Vec<f64> = late.iter().map(|v| v.rem_euclid(std::f64::consts::TAU)).collect();
    plot(
        &file("c"),
        &format!("(5.12), N = {nodes}: waveform mod 2π at t = {t_late:.0}"),
        ("x", "φ mod 2π"),
        &[("φ", &x, &wrapped)],
        Scale::Linear,
        false,
    )?;
    let points: Vec<f64> = (1..=16).map(|i| i as f64).collect();
    let values: Vec<f64> = late[1..=16]
        .iter()
        .map(|v| v.rem_euclid(std::f64::consts::TAU))
        .collect();
    plot(
        &file("d"),
        &format!("(5.12), N = {nodes}: grid points 1..16 at t = {t_late:.0}"),
        ("grid point i", "φ mod 2π"),
        &[("φ_i", &points, &values)],
        Scale::Linear,
        true,
    )?;
    Ok(())
}

/// The response to a seeded ε(−1)^i perturbation.
pub fn seeded(root: &Path, t_end: f64, rel_tol: f64) -> Result<(), Box<dyn std::error::Error>> {
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
            "symmetric rectangle, N = {nodes}, seeded: t = {:.0} in {:.1} s, response to ε(−1)^i: {:.3e} (ε = {eps:e})",
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
    table.write_csv(&root.join("even_odd_seeded.csv"))?;
    let col = |k: usize| -> Vec<f64> { table.rows.iter().map(|r| r[k]).collect() };
    let (t, even, odd) = (col(0), col(1), col(2));
    plot(
        &root.join("even_odd_seeded.svg"),
        "Symmetric rectangle (5.12), seeded: response to ε(−1)^i",
        ("time t", "|Σ(−1)^i Δy_i|/N"),
        &[("N = 256", &t, &even), ("N = 255", &t, &odd)],
        Scale::Log,
        false,
    )?;
    Ok(())
}
