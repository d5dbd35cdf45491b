//! The figures of a run, drawn from its trajectory table (so `veselov plot`
//! can redraw them from the CSV alone).

use std::path::Path;

use crate::error::CliError;
use crate::output::Table;
use crate::plot::{Figure, Scale, Series, draw};

pub(crate) fn plot_err(e: crate::plot::PlotError) -> CliError {
    CliError::Io {
        path: e.path.clone(),
        message: e.message,
    }
}

/// |E(t) − E(0)| against t on a log scale.
pub(crate) fn draw_energy_error(path: &Path, title: &str, t: &[f64], e: &[f64]) -> Result<(), CliError> {
    let e0 = e.first().copied().unwrap_or(0.0);
    let err: Vec<f64> = e.iter().map(|x| (x - e0).abs()).collect();
    draw_log_error(path, (title, "|E(t) − E(0)|", "energy"), t, &err)
}

/// One error curve against time on a log scale: (title, y label, legend).
fn draw_log_error(
    path: &Path,
    (title, y_label, label): (&str, &str, &str),
    t: &[f64],
    y: &[f64],
) -> Result<(), CliError> {
    let fig = Figure {
        title,
        x_label: "time t",
        y_label,
        x_scale: Scale::Linear,
        y_scale: Scale::Log,
        series: vec![Series { label, x: t, y }],
        markers: false,
        equal_aspect: false,
    };
    draw(path, &fig).map_err(plot_err)
}

/// Labelled curves (label, x, y) on linear axes.
pub(crate) fn draw_curves(
    path: &Path,
    (title, x_label, y_label): (&str, &str, &str),
    curves: &[(String, Vec<f64>, Vec<f64>)],
    equal_aspect: bool,
) -> Result<(), CliError> {
    let fig = Figure {
        title,
        x_label,
        y_label,
        x_scale: Scale::Linear,
        y_scale: Scale::Linear,
        series: curves.iter().map(|(label, x, y)| Series { label, x, y }).collect(),
        markers: false,
        equal_aspect,
    };
    draw(path, &fig).map_err(plot_err)
}

/// The columns `names` of a CSV table as changes from their first value,
/// against its column `x`, in one figure.
pub(crate) fn draw_changes(
    path: &Path,
    table: &Table,
    x: &str,
    names: &[&str],
    labels: (&str, &str),
) -> Result<(), CliError> {
    let Some(xs) = table.column(x) else { return Ok(()) };
    let curves: Vec<(String, Vec<f64>, Vec<f64>)> = names
        .iter()
        .filter_map(|n| {
            let v = table.column(n)?;
            let v0 = v.first().copied().unwrap_or(0.0);
            Some((n.to_string(), xs.clone(), v.iter().map(|y| y - v0).collect()))
        })
        .collect();
    draw_curves(path, (labels.0, x, labels.1), &curves, false)
}

/// The coordinate columns of a trajectory table, each with its momentum
/// column: the columns `c` before `energy` for which `p_c` also exists, or
/// `q<i>` with `p<i>` (see [`crate::kinds::mechanics::run::trajectory_header`]).
pub fn coordinate_columns(table: &Table) -> Vec<(String, String)> {
    let before_energy = table.header.iter().take_while(|h| *h != "energy");
    let pairs = |p: &dyn Fn(&str) -> Option<String>| -> Vec<(String, String)> {
        before_energy
            .clone()
            .skip(1)
            .filter_map(|q| {
                let p = p(q)?;
                table.header.contains(&p).then(|| (q.clone(), p))
            })
            .collect()
    };
    let named = pairs(&|q| Some(format!("p_{q}")));
    if !named.is_empty() {
        return named;
    }
    pairs(&|q| {
        q.strip_prefix('q')
            .filter(|i| i.parse::<usize>().is_ok())
            .map(|i| format!("p{i}"))
    })
}

/// Energy error (for a forced system, with a `work` column: the energy
/// balance error and the energy change beside the work), momentum errors
/// (changes, when forced), phase portrait of the first coordinate, (with two
/// coordinates) the orbit in their plane and (rigid bodies) the body angular
/// momentum.
pub fn draw_all(dir: &Path, table: &Table, format: &str) -> Result<(), CliError> {
    let coordinates = coordinate_columns(table);
    let Some(t) = table.column("t") else { return Ok(()) };
    let file = |name: &str| dir.join(format!("{name}.{format}"));
    // A forced system (a `work` column) does not conserve E: plot the energy
    // balance error |E − E₀ − W| and the energy change beside the work.
    let work = table.column("work");
    match (table.column("energy"), &work) {
        (Some(e), Some(w)) => {
            let e0 = e.first().copied().unwrap_or(0.0);
            let balance: Vec<f64> = e.iter().zip(w).map(|(e, w)| (e - e0 - w).abs()).collect();
            draw_log_error(
                &file("energy_balance"),
                (
                    "Energy balance error (forced system)",
                    "|E(t) − E(0) − W(t)|",
                    "energy balance",
                ),
                &t,
                &balance,
            )?;
            let change: Vec<f64> = e.iter().map(|e| e - e0).collect();
            draw_curves(
                &file("energy_change"),
                ("Energy change and work of the forces", "time t", "E(t) − E(0), W(t)"),
                &[
                    ("E(t) − E(0)".to_string(), t.clone(), change),
                    ("W(t)".to_string(), t.clone(), w.clone()),
                ],
                false,
            )?;
        }
        (Some(e), None) => draw_energy_error(&file("energy_error"), "Energy error", &t, &e)?,
        _ => {}
    }
    let momenta: Vec<(String, Vec<f64>)> = table
        .header
        .iter()
        .filter(|h| h.starts_with("J_"))
        .filter_map(|h| {
            let c = table.column(h)?;
            let c0 = c.first().copied().unwrap_or(0.0);
            Some((h.clone(), c.iter().map(|x| (x - c0).abs()).collect()))
        })
        .collect();
    if !momenta.is_empty() {
        // Forces break the symmetries: then the momentum maps change, and the
        // plot says so rather than calling the change an error. A momentum
        // conserved exactly (every |J − J₀| = 0) has nothing to show on a log
        // scale: it is drawn on a linear one and the title says so.
        let exact = momenta.iter().all(|(_, y)| y.iter().all(|v| *v == 0.0));
        let fig = Figure {
            title: match (work.is_some(), exact) {
                (true, _) => "Momentum-map changes (forced system)",
                (false, true) => "Momentum-map errors: exactly 0 at every row",
                (false, false) => "Momentum-map errors",
            },
            x_label: "time t",
            y_label: "|J(t) − J(0)|",
            x_scale: Scale::Linear,
            y_scale: if exact { Scale::Linear } else { Scale::Log },
            series: momenta
                .iter()
                .map(|(name, y)| Series { label: name, x: &t, y })
                .collect(),
            markers: false,
            equal_aspect: false,
        };
        draw(&file("momentum_error"), &fig).map_err(plot_err)?;
    }
    if let Some((q, p)) = coordinates.first()
        && let (Some(qs), Some(ps)) = (table.column(q), table.column(p))
    {
        let label = format!("({q}, {p})");
        let fig = Figure {
            title: "Phase portrait",
            x_label: q,
            y_label: p,
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            series: vec![Series {
                label: &label,
                x: &qs,
                y: &ps,
            }],
            markers: false,
            equal_aspect: false,
        };
        draw(&file("phase"), &fig).map_err(plot_err)?;
    }
    if let (Some(p0), Some(p1), Some(p2)) = (table.column("Pi0"), table.column("Pi1"), table.column("Pi2")) {
        let fig = Figure {
            title: "Body angular momentum",
            x_label: "time t",
            y_label: "Π (body frame)",
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            series: vec![
                Series {
                    label: "Pi0",
                    x: &t,
                    y: &p0,
                },
                Series {
                    label: "Pi1",
                    x: &t,
                    y: &p1,
                },
                Series {
                    label: "Pi2",
                    x: &t,
                    y: &p2,
                },
            ],
            markers: false,
            equal_aspect: false,
        };
        draw(&file("body_momentum"), &fig).map_err(plot_err)?;
    }
    if let [(a, _), (b, _)] = coordinates.as_slice()
        && let (Some(qa), Some(qb)) = (table.column(a), table.column(b))
    {
        let fig = Figure {
            title: "Orbit in the configuration plane",
            x_label: a,
            y_label: b,
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            series: vec![Series {
                label: "orbit",
                x: &qa,
                y: &qb,
            }],
            markers: false,
            equal_aspect: true,
        };
        draw(&file("orbit"), &fig).map_err(plot_err)?;
    }
    Ok(())
}

/// Log-log plot of a convergence study with a reference slope.
pub fn draw_convergence(
    path: &Path,
    dt: &[f64],
    err: &[f64],
    order: usize,
    fitted: Option<f64>,
    (step_label, error_label): (&str, &str),
) -> Result<(), CliError> {
    // Reference line h^order through the smallest-h point with a usable error.
    let anchor = dt
        .iter()
        .zip(err)
        .filter(|(_, e)| **e > 0.0 && e.is_finite())
        .min_by(|a, b| a.0.total_cmp(b.0));
    let reference: Vec<f64> = match anchor {
        Some((&h0, &e0)) => dt.iter().map(|h| e0 * (h / h0).powi(order as i32)).collect(),
        None => vec![f64::NAN; dt.len()],
    };
    let measured = match fitted {
        Some(p) => format!("measured (fitted order {p:.2})"),
        None => "measured".to_string(),
    };
    let slope = format!("slope {order}");
    let fig = Figure {
        title: "Convergence at the final time",
        x_label: step_label,
        y_label: error_label,
        x_scale: Scale::Log,
        y_scale: Scale::Log,
        series: vec![
            Series {
                label: &measured,
                x: dt,
                y: err,
            },
            Series {
                label: &slope,
                x: dt,
                y: &reference,
            },
        ],
        markers: true,
        equal_aspect: false,
    };
    draw(path, &fig).map_err(plot_err)
}
