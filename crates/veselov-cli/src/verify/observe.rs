//! The observables of a refinement study ([`super::refine`]), read back
//! from the output files of a run: the final field on the coarsest run's
//! grid points, the energy at a common time, the tip displacement and the
//! first natural frequency of a free vibration.

use std::io::{Read, Seek, SeekFrom};
use std::path::Path;

use serde_json::Value;

use crate::error::CliError;
use crate::output::Table;
use crate::pipeline::readback::npy_info;

/// What a refinement study compares between its runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Observable {
    /// The field at the final time (`snapshots.npy`, last row), sampled at
    /// the nodes of the coarsest run.
    Field,
    /// The energy (`energy.csv`) at the time of the coarsest run's last row,
    /// interpolated linearly between the rows of the finer runs.
    Energy,
    /// The displacement of the free end at the final time (`summary.json`
    /// `tip_displacement`).
    Tip,
    /// The first natural frequency of a free vibration, in Hz: the best
    /// fitting sinusoid of the centreline's sagitta (`centerline.npy`).
    Frequency,
}

impl Observable {
    /// Every observable, in the order `--observable` lists them.
    pub const ALL: [Observable; 4] = [
        Observable::Field,
        Observable::Energy,
        Observable::Tip,
        Observable::Frequency,
    ];

    /// The name `--observable` takes.
    pub fn name(self) -> &'static str {
        match self {
            Observable::Field => "field",
            Observable::Energy => "energy",
            Observable::Tip => "tip-displacement",
            Observable::Frequency => "frequency",
        }
    }

    /// The quantity, for the table and the plot's axis.
    pub fn describe(self) -> &'static str {
        match self {
            Observable::Field => "max error of the final field at the coarsest nodes",
            Observable::Energy => "error of the final energy",
            Observable::Tip => "max error of the final tip displacement",
            Observable::Frequency => "error of the first frequency (Hz)",
        }
    }

    /// The observable named `name`, if any.
    pub fn named(name: &str) -> Option<Observable> {
        Self::ALL.into_iter().find(|o| o.name() == name)
    }
}

fn io(path: &Path, message: impl ToString) -> CliError {
    CliError::Io {
        path: path.to_path_buf(),
        message: message.to_string(),
    }
}

/// The grid of the coarsest run: the nodes per space axis and whether the
/// end nodes lie on the boundary (`closed`: Δx = L/(N − 1), a refinement by
/// r has r(N − 1) + 1 nodes; else Δx = L/N and rN nodes).
#[derive(Debug, Clone)]
pub struct Coarse {
    /// Nodes per space axis.
    pub nodes: Vec<usize>,
    /// Whether the end nodes are on the boundary.
    pub closed: bool,
}

impl Coarse {
    /// The stride of a grid of `fine` nodes over the coarse one on `axis`,
    /// if the coarse nodes are among its nodes.
    fn stride(&self, axis: usize, fine: usize) -> Option<usize> {
        let d = usize::from(self.closed);
        let (c, f) = (self.nodes[axis].checked_sub(d)?, fine.checked_sub(d)?);
        (c > 0 && f.is_multiple_of(c)).then(|| f / c)
    }
}

/// The last row of the float64 NPY file `path`, with its shape.
fn last_row(path: &Path) -> Result<(Vec<f64>, Vec<usize>), CliError> {
    let info = npy_info(path)?;
    let per_row: usize = info.shape.iter().skip(1).product();
    let rows = info.rows();
    if rows == 0 || per_row == 0 {
        return Err(io(path, "holds no rows"));
    }
    let mut f = std::fs::File::open(path).map_err(|e| io(path, e))?;
    let start = info.data_offset + (rows - 1) * 8 * per_row as u64;
    f.seek(SeekFrom::Start(start)).map_err(|e| io(path, e))?;
    let mut buf = vec![0u8; 8 * per_row];
    f.read_exact(&mut buf).map_err(|e| io(path, e))?;
    let row = buf
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]))
        .collect();
    Ok((row, info.shape))
}

/// The final field of the run in `dir` (`snapshots.npy`, rows of shape
/// nodes × … × components) at the nodes of `coarse`.
pub fn final_field(dir: &Path, coarse: &Coarse) -> Result<Vec<f64>, CliError> {
    let path = dir.join("snapshots.npy");
    let (row, shape) = last_row(&path)?;
    let axes = coarse.nodes.len();
    if shape.len() < 1 + axes {
        return Err(io(
            &path,
            format!("its shape {shape:?} has fewer than {axes} space axes"),
        ));
    }
    let fine = &shape[1..1 + axes];
    let components: usize = shape[1 + axes..].iter().product();
    let strides = (0..axes)
        .map(|a| coarse.stride(a, fine[a]))
        .collect::<Option<Vec<usize>>>()
        .ok_or_else(|| {
            io(
                &path,
                format!(
                    "its grid {fine:?} does not hold the coarsest run's nodes {:?}",
                    coarse.nodes
                ),
            )
        })?;
    let mut out = Vec::new();
    let mut index = vec![0usize; axes];
    loop {
        // Row-major offset of the coarse node `index` on the fine grid.
        let mut at = 0;
        for a in 0..axes {
            at = at * fine[a] + index[a] * strides[a];
        }
        out.extend_from_slice(&row[at * components..(at + 1) * components]);
        // The next coarse node, the last axis fastest.
        let mut a = axes;
        loop {
            if a == 0 {
                return Ok(out);
            }
            a -= 1;
            index[a] += 1;
            if index[a] < coarse.nodes[a] {
                break;
            }
            index[a] = 0;
        }
    }
}

/// The columns `t` and `energy` of `dir/energy.csv`.
fn energy_rows(dir: &Path) -> Result<(Vec<f64>, Vec<f64>), CliError> {
    let path = dir.join("energy.csv");
    let table = Table::read_csv(&path)?;
    match (table.column("t"), table.column("energy")) {
        (Some(t), Some(e)) if !t.is_empty() => Ok((t, e)),
        _ => Err(io(&path, "no rows with columns `t` and `energy`")),
    }
}

/// The time of the last energy row of the run in `dir`.
pub fn last_energy_time(dir: &Path) -> Result<f64, CliError> {
    let (t, _) = energy_rows(dir)?;
    t.last().copied().ok_or_else(|| io(&dir.join("energy.csv"), "no rows"))
}

/// The energy of the run in `dir` at time `at`, interpolated linearly
/// between the rows about it.
pub fn energy_at(dir: &Path, at: f64) -> Result<f64, CliError> {
    let (t, e) = energy_rows(dir)?;
    let tolerance = 1e-9 * at.abs().max(1.0);
    let i = t.partition_point(|&ti| ti < at - tolerance);
    if i < t.len() && (t[i] - at).abs() <= tolerance {
        return Ok(e[i]);
    }
    if i == 0 || i == t.len() {
        return Err(io(
            &dir.join("energy.csv"),
            format!("its rows do not bracket t = {}", crate::output::number(at)),
        ));
    }
    let w = (at - t[i - 1]) / (t[i] - t[i - 1]);
    Ok(e[i - 1] + w * (e[i] - e[i - 1]))
}

/// The tip displacement in the summary of a run.
pub fn tip(summary: &Value) -> Option<Vec<f64>> {
    summary
        .get("tip_displacement")?
        .as_array()?
        .iter()
        .map(Value::as_f64)
        .collect()
}

/// The first natural frequency (Hz) of the free vibration in `dir`.
///
/// The signal is the sagitta s(t) = (x_mid − (x_first + x_last)/2)·e of the
/// centreline, e the unit direction of its largest value. Its frequency is
/// the ω that fits it best over the whole run by least squares,
///
/// min over ω, a, b, c of Σ_j (s(t_j) − a cos ωt_j − b sin ωt_j − c)²,
///
/// f = ω/2π: higher modes, which shift the zero crossings of s, are nearly
/// orthogonal to the fit over a few periods. The search starts from the
/// zero crossings t₁ < … < t_m (half a period apart, f ≈ (m − 1)/(2(t_m −
/// t₁))) and is refined by golden section within a tenth of the fit's
/// spectral resolution 1/(t_end − t_0) around the best of a scan.
///
/// `None` when the run crosses zero fewer than twice (it is not a free
/// vibration, or too short to show half a period).
pub fn frequency(dir: &Path) -> Result<Option<f64>, CliError> {
    let path = dir.join("centerline.npy");
    let info = npy_info(&path)?;
    let (rows, points) = match info.shape[..] {
        [r, p, 3] if p >= 3 => (r, p),
        _ => {
            return Err(io(
                &path,
                format!("its shape {:?} is not rows × points × 3", info.shape),
            ));
        }
    };
    let (times, _) = energy_rows(dir)?;
    if times.len() != rows {
        return Err(io(
            &path,
            format!("{rows} rows, but energy.csv holds {} times", times.len()),
        ));
    }
    let mut f = std::fs::File::open(&path).map_err(|e| io(&path, e))?;
    f.seek(SeekFrom::Start(info.data_offset)).map_err(|e| io(&path, e))?;
    let mut buf = vec![0u8; 8 * 3 * points];
    let mut sagitta = Vec::with_capacity(rows);
    for _ in 0..rows {
        f.read_exact(&mut buf).map_err(|e| io(&path, e))?;
        let x = |i: usize, k: usize| {
            let b = &buf[8 * (3 * i + k)..8 * (3 * i + k + 1)];
            f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]])
        };
        // The middle point (the mean of the two middle ones for an even count).
        let mid = |k: usize| 0.5 * (x((points - 1) / 2, k) + x(points / 2, k));
        sagitta.push([0, 1, 2].map(|k| mid(k) - 0.5 * (x(0, k) + x(points - 1, k))));
    }
    let norm = |v: &[f64; 3]| v.iter().map(|c| c * c).sum::<f64>().sqrt();
    let Some(largest) = sagitta.iter().max_by(|a, b| norm(a).total_cmp(&norm(b))) else {
        return Ok(None);
    };
    let size = norm(largest);
    if !(size > 0.0 && size.is_finite()) {
        return Ok(None);
    }
    let e = largest.map(|c| c / size);
    let s: Vec<f64> = sagitta
        .iter()
        .map(|v| v[0] * e[0] + v[1] * e[1] + v[2] * e[2])
        .collect();
    let crossings = zero_crossings(&times, &s);
    let guess = match crossings[..] {
        [first, .., last] if last > first => (crossings.len() - 1) as f64 / (2.0 * (last - first)),
        _ => return Ok(None),
    };
    Ok(Some(best_fit_frequency(&times, &s, guess)))
}

/// The squared residual of the least-squares fit of a cos ωt + b sin ωt + c
/// to the samples `s` at `t` (the normal equations, solved by LU).
fn residual(t: &[f64], s: &[f64], omega: f64) -> f64 {
    let mut a = nalgebra::Matrix3::<f64>::zeros();
    let mut b = nalgebra::Vector3::<f64>::zeros();
    let basis = |x: f64| nalgebra::Vector3::new((omega * x).cos(), (omega * x).sin(), 1.0);
    for (&x, &y) in t.iter().zip(s) {
        let v = basis(x);
        a += v * v.transpose();
        b += v * y;
    }
    let Some(c) = a.lu().solve(&b) else {
        return f64::INFINITY;
    };
    t.iter().zip(s).map(|(&x, &y)| (y - basis(x).dot(&c)).powi(2)).sum()
}

/// The frequency (Hz) of the sinusoid that best fits the samples `s` at
/// `t`, searched about `guess` (see [`frequency`]).
fn best_fit_frequency(t: &[f64], s: &[f64], guess: f64) -> f64 {
    let span = t.last().copied().unwrap_or(0.0) - t.first().copied().unwrap_or(0.0);
    let omega = std::f64::consts::TAU * guess;
    // The main lobe of the fit is about 2π/span wide: scan half of it on
    // either side of the guess, then refine about the best point.
    let half = (std::f64::consts::PI / span.max(f64::MIN_POSITIVE)).min(0.5 * omega);
    let scan = 40;
    let step = 2.0 * half / scan as f64;
    let best = (0..=scan)
        .map(|i| omega - half + step * i as f64)
        .min_by(|&x, &y| residual(t, s, x).total_cmp(&residual(t, s, y)))
        .unwrap_or(omega);
    let (mut lo, mut hi) = (best - step, best + step);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..80 {
        let (c, d) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if residual(t, s, c) < residual(t, s, d) {
            hi = d;
        } else {
            lo = c;
        }
    }
    0.5 * (lo + hi) / std::f64::consts::TAU
}

/// The times at which the samples `s` at `t` change sign, each the root of
/// the cubic through the four samples about it (the two nearest where the
/// change is at an end), found by bisection.
fn zero_crossings(t: &[f64], s: &[f64]) -> Vec<f64> {
    let mut out = Vec::new();
    for i in 0..s.len().saturating_sub(1) {
        if !(s[i] > 0.0 && s[i + 1] <= 0.0 || s[i] < 0.0 && s[i + 1] >= 0.0) {
            continue;
        }
        let lo = i.saturating_sub(1);
        let hi = (i + 2).min(s.len() - 1);
        let (ts, ss) = (&t[lo..=hi], &s[lo..=hi]);
        // Lagrange interpolation through the samples lo..=hi.
        let p = |x: f64| -> f64 {
            (0..ts.len())
                .map(|j| {
                    let w: f64 = (0..ts.len())
                        .filter(|&m| m != j)
                        .map(|m| (x - ts[m]) / (ts[j] - ts[m]))
                        .product();
                    ss[j] * w
                })
                .sum()
        };
        let (mut a, mut b) = (t[i], t[i + 1]);
        let sign_a = p(a).signum();
        for _ in 0..100 {
            let m = 0.5 * (a + b);
            if p(m).signum() == sign_a {
                a = m;
            } else {
                b = m;
            }
        }
        out.push(0.5 * (a + b));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The crossings of a sampled sine are found to the accuracy of a cubic
    /// through four samples: half a period apart.
    #[test]
    fn crossings_of_a_sine_are_half_a_period_apart() {
        let omega = 2.0 * std::f64::consts::PI * 1.3;
        let t: Vec<f64> = (0..400).map(|k| 0.01 * k as f64 + 0.003).collect();
        let s: Vec<f64> = t.iter().map(|&t| (omega * t).cos()).collect();
        let c = zero_crossings(&t, &s);
        assert!(c.len() >= 5, "{c:?}");
        let f = (c.len() - 1) as f64 / (2.0 * (c[c.len() - 1] - c[0]));
        assert!((f - 1.3).abs() < 1e-6, "{f}");
        // A second mode, 5.4 times faster and a tenth as large, moves the
        // crossings; the best fitting sinusoid keeps the first frequency.
        let s: Vec<f64> = t
            .iter()
            .map(|&t| (omega * t).cos() + 0.1 * (5.4 * omega * t + 0.3).cos())
            .collect();
        let f = best_fit_frequency(&t, &s, 1.25);
        assert!((f - 1.3).abs() < 2e-3, "{f}");
    }
}
