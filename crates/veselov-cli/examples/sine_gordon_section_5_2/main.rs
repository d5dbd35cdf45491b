//! Rerun the sine-Gordon experiments of seed 002 §5.2 and plot them.
//!
//! ```text
//! cargo run --release -p veselov-cli --example sine_gordon_section_5_2 -- [t_end] [schemes] [rel_tol]
//! ```
//!
//! Defaults: t_end = 129000 (≈ 5000 kink–antikink collisions, 6.58 million
//! levels at h = k/8), schemes `triangle,symmetric-rectangle,vu-quoc-li,guo,guo-k16`
//! (`guo-k16` is Guo's scheme at h = k/16, as the paper ran it for Fig. 5.8),
//! level-solve tolerance 1e-13. Lattice convention: node (i, j) with
//! i = space and j = time; N = 255 nodes on a circle of length 40, so the
//! paper's k = 40/255 is `dx` and its h = k/8 is `dt`.
//!
//! For each scheme, in `out/section_5_2/<scheme>/` (see [`scheme_run`]):
//! energy blocks (Figs. 5.7, 5.8, 5.11), initial and final energy errors,
//! the final waveform (Fig. 5.6), the high-frequency indicator per block, the
//! collision times, the waveforms through the last collision (Figs. 5.9,
//! 5.10) and, for Guo, the printed and footnote-4 energies beside the
//! conserved one (Fig. 5.8).
//!
//! Then the even/odd experiment of Fig. 5.5 (see [`even_odd`]): the
//! symmetric rectangle scheme with N = 256 and N = 255 to t = min(t_end,
//! 12500), first as the paper ran it (no perturbation: the four panels and
//! the natural growth of the (−1)^{i+j} mode), then seeded with ε(−1)^i to
//! measure the mode's linear response.
//!
//! Wall time of each run and ns per node update are printed.

mod even_odd;
mod scheme_run;

use std::path::{Path, PathBuf};

use veselov::spacetime::Scheme;
use veselov_cli::output::npy_header_shape;
use veselov_cli::plot::{Figure, Scale, Series, draw};

/// Energy and high-frequency statistics are taken over blocks of this many levels.
pub const BLOCK: usize = 5000;

/// Draw one figure of curves `(label, x, y)`.
pub fn plot(
    path: &Path,
    title: &str,
    (x_label, y_label): (&str, &str),
    curves: &[(&str, &[f64], &[f64])],
    y_scale: Scale,
    markers: bool,
) -> Result<(), String> {
    let fig = Figure {
        title,
        x_label,
        y_label,
        x_scale: Scale::Linear,
        y_scale,
        series: curves.iter().map(|&(label, x, y)| Series { label, x, y }).collect(),
        markers,
        equal_aspect: false,
    };
    draw(path, &fig).map_err(|e| e.to_string())
}

/// Write rows of equal length as a 2-D NPY array.
pub fn write_npy(path: &Path, rows: &[Vec<f64>]) -> Result<(), Box<dyn std::error::Error>> {
    let mut bytes = npy_header_shape(&[rows.len(), rows.first().map_or(0, Vec::len)]);
    for v in rows.iter().flatten() {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    std::fs::write(path, bytes)?;
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let t_end: f64 = args.next().map(|s| s.parse()).transpose()?.unwrap_or(129_000.0);
    let runs: Vec<(Scheme, f64)> = args
        .next()
        .unwrap_or_else(|| "triangle,symmetric-rectangle,vu-quoc-li,guo,guo-k16".into())
        .split(',')
        .map(|s| match s {
            "guo-k16" => Ok((Scheme::Guo, 16.0)),
            _ => Scheme::from_name(s)
                .map(|scheme| (scheme, 8.0))
                .ok_or_else(|| format!("unknown scheme `{s}` (or `guo-k16`)")),
        })
        .collect::<Result<_, _>>()?;
    let rel_tol: f64 = args.next().map(|s| s.parse()).transpose()?.unwrap_or(1e-13);
    let root = PathBuf::from("out/section_5_2");
    for (scheme, ratio) in runs {
        scheme_run::run(&root, scheme, ratio, t_end, rel_tol)?;
    }
    let t_even_odd = t_end.min(12_500.0);
    even_odd::natural(&root, t_even_odd, rel_tol)?;
    even_odd::seeded(&root, t_even_odd, rel_tol)
}
