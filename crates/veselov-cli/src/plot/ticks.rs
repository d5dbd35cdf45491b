//! Tick marks and their labels on linear and logarithmic axes.

use super::Scale;

/// Font size of the tick labels (the renderer draws them at this size).
pub(super) const TICK_LABEL_SIZE: u32 = 15;

/// Tick marks of one axis: labelled major ticks (with grid lines) and
/// unlabelled minor grid lines, at display coordinates.
#[derive(Debug, Default)]
pub(crate) struct Ticks {
    pub(crate) major: Vec<(f64, String)>,
    pub(crate) minor: Vec<f64>,
}

impl Ticks {
    /// The label of the major tick at `v`.
    pub(crate) fn label(&self, v: f64) -> String {
        self.major
            .iter()
            .min_by(|a, b| (a.0 - v).abs().total_cmp(&(b.0 - v).abs()))
            .map(|t| t.1.clone())
            .unwrap_or_default()
    }

    /// Estimated width in pixels of the widest label.
    pub(super) fn label_width(&self) -> u32 {
        let chars = self.major.iter().map(|t| t.1.chars().count()).max();
        // Noto Sans digits are 0.57 em wide.
        (0.6 * f64::from(TICK_LABEL_SIZE) * chars.unwrap_or(0) as f64).ceil() as u32
    }
}

/// A "nice" step (1, 2 or 5 times a power of ten) splitting `span` into
/// about `target` intervals, with the number of minor intervals per step.
fn nice_step(span: f64, target: usize) -> Option<(f64, usize)> {
    let raw = span / target.max(1) as f64;
    if !(raw.is_finite() && raw > 0.0) {
        return None;
    }
    let magnitude = 10f64.powf(raw.log10().floor());
    let m = raw / magnitude;
    let (nice, minor) = if m < 1.5 {
        (1.0, 5)
    } else if m < 3.5 {
        (2.0, 4)
    } else if m < 7.5 {
        (5.0, 5)
    } else {
        (10.0, 5)
    };
    let step = nice * magnitude;
    (step.is_finite() && step > 0.0).then_some((step, minor))
}

/// Multiples of `step` within `[lo, hi]` (none if there would be hundreds).
fn multiples(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    // The tolerance keeps a multiple that falls on an end despite rounding.
    let (first, last) = ((lo / step - 1e-9).ceil(), (hi / step + 1e-9).floor());
    if !(first.is_finite() && last.is_finite()) || last - first > 500.0 {
        return Vec::new();
    }
    let mut out = Vec::new();
    let mut k = first;
    while k <= last {
        let v = k * step;
        // Avoid labels such as "-0" or "1e-17" for zero.
        out.push(if v.abs() < 1e-9 * step { 0.0 } else { v });
        k += 1.0;
    }
    out
}

/// `v` in scientific notation with `digits` digits after the point, trailing
/// zeros dropped: `1e-12`, `2.5e3`.
fn scientific(v: f64, digits: usize) -> String {
    let s = format!("{:.*e}", digits.min(15), v);
    match s.split_once('e') {
        Some((mantissa, exp)) if mantissa.contains('.') => {
            let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
            format!("{mantissa}e{exp}")
        }
        _ => s,
    }
}

/// Digits after the point needed to tell multiples of `step` apart at `v`.
fn digits_for(v: f64, step: f64) -> usize {
    let e = v.abs().log10().floor();
    let step_e = step.log10().floor();
    (e - step_e).clamp(0.0, 15.0) as usize
}

/// Ticks of a linear axis over `[lo, hi]`.
fn linear_ticks(lo: f64, hi: f64, target: usize) -> Ticks {
    let Some((step, minor_per_step)) = nice_step(hi - lo, target) else {
        return Ticks::default();
    };
    let big = lo.abs().max(hi.abs());
    let scientific_labels = !(1e-3..1e5).contains(&big);
    let decimals = (-step.log10().floor()).clamp(0.0, 15.0) as usize;
    let major = multiples(lo, hi, step)
        .into_iter()
        .map(|v| {
            let label = if !scientific_labels {
                format!("{v:.decimals$}")
            } else if v == 0.0 {
                "0".to_string()
            } else {
                scientific(v, digits_for(v, step))
            };
            (v, label)
        })
        .collect();
    let minor_step = step / minor_per_step as f64;
    let minor = multiples(lo, hi, minor_step)
        .into_iter()
        .filter(|v| ((v / step).round() * step - v).abs() > 1e-6 * step)
        .collect();
    Ticks { major, minor }
}

/// Ticks of a logarithmic axis over `[lo, hi]`, given in decades
/// (`log₁₀` of the data); labels in scientific notation.
fn log_ticks(lo: f64, hi: f64, target: usize) -> Ticks {
    if !(lo.is_finite() && hi.is_finite() && hi > lo) {
        return Ticks::default();
    }
    let (first, last) = (lo.ceil() as i64, hi.floor() as i64);
    let decades = last - first + 1;
    if decades >= 3 {
        // Label every k-th decade, k = 1, 2, 5, 10, 20, 50, ...
        let mut k = 1i64;
        let mut scale = 1i64;
        let mut mantissas = [2, 5, 10].into_iter().cycle();
        while decades > k * (target.max(1) as i64 + 1) {
            match mantissas.next() {
                Some(10) | None => {
                    scale *= 10;
                    k = scale;
                }
                Some(m) => k = m * scale,
            }
        }
        let major: Vec<(f64, String)> = (first..=last)
            .filter(|e| e.rem_euclid(k) == 0)
            .map(|e| (e as f64, format!("1e{e}")))
            .collect();
        let minor = if k == 1 && decades <= 16 {
            // 2, 3, ..., 9 times each power of ten.
            (first - 1..=last)
                .flat_map(|e| (2..10).map(move |m| e as f64 + f64::from(m).log10()))
                .filter(|v| (lo..=hi).contains(v))
                .collect()
        } else if decades <= 60 {
            (first..=last)
                .filter(|e| e.rem_euclid(k) != 0)
                .map(|e| e as f64)
                .collect()
        } else {
            Vec::new()
        };
        return Ticks { major, minor };
    }
    // Up to two decades: 1, 2 and 5 times powers of ten.
    let candidates = |ms: &'static [u32]| {
        (lo.floor() as i64 - 1..=hi.ceil() as i64).flat_map(move |e| {
            ms.iter()
                .map(move |&m| (e as f64 + f64::from(m).log10(), format!("{m}e{e}")))
        })
    };
    let major: Vec<(f64, String)> = candidates(&[1, 2, 5]).filter(|t| (lo..=hi).contains(&t.0)).collect();
    if major.len() >= 2 {
        let minor = candidates(&[1, 2, 3, 4, 5, 6, 7, 8, 9])
            .filter(|t| !major.iter().any(|m| m.1 == t.1))
            .map(|t| t.0)
            .filter(|v| (lo..=hi).contains(v))
            .collect();
        return Ticks { major, minor };
    }
    // Narrower still: evenly spaced values, placed on the log axis.
    let (a, b) = (10f64.powf(lo), 10f64.powf(hi));
    let Some((step, _)) = nice_step(b - a, target.min(5)) else {
        return Ticks::default();
    };
    let major = multiples(a, b, step)
        .into_iter()
        .filter(|&v| v > 0.0)
        .map(|v| (v.log10(), scientific(v, digits_for(v, step))))
        .collect();
    Ticks {
        major,
        minor: Vec::new(),
    }
}

/// The ticks of a linear axis over `range`, `length` pixels long, about one
/// labelled tick per `spacing` pixels: those of the plots' own axes, for a
/// figure drawn by other means (the centreline animation).
pub(crate) fn linear_axis_ticks(range: (f64, f64), length: u32, spacing: u32) -> Ticks {
    ticks(range, Scale::Linear, length, spacing)
}

/// Ticks for an axis of `scale` over `range`, about one per `spacing` pixels
/// of its `length`.
pub(super) fn ticks(range: (f64, f64), scale: Scale, length: u32, spacing: u32) -> Ticks {
    let target = (length / spacing).clamp(3, 10) as usize;
    match scale {
        Scale::Linear => linear_ticks(range.0, range.1, target),
        Scale::Log => log_ticks(range.0, range.1, target),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_labels() {
        let t = linear_ticks(-0.05, 1.05, 6);
        let labels: Vec<&str> = t.major.iter().map(|m| m.1.as_str()).collect();
        assert_eq!(labels, ["0.0", "0.2", "0.4", "0.6", "0.8", "1.0"]);
        let t = log_ticks(-12.3, -3.7, 6);
        assert!(t.major.iter().any(|m| m.1 == "1e-12"), "{t:?}");
        let t = log_ticks(0.1, 0.9, 6);
        let labels: Vec<&str> = t.major.iter().map(|m| m.1.as_str()).collect();
        assert_eq!(labels, ["2e0", "5e0"]);
        let t = linear_ticks(0.0, 1e6, 6);
        assert!(t.major.iter().any(|m| m.1 == "2e5"), "{t:?}");
        assert_eq!(scientific(1.5e-7, 3), "1.5e-7");
    }

    /// A tick at zero reads "0…", never "-0…", whatever round-off put it
    /// at; labels carry the decimals of the tick spacing.
    #[test]
    fn zero_is_never_negative_and_decimals_follow_the_spacing() {
        for (lo, hi) in [(-0.3, 0.7), (-1e-17 - 0.25, 0.25), (-3.0, 1.0), (-0.0105, 0.0095)] {
            let t = linear_ticks(lo, hi, 6);
            assert!(t.major.iter().any(|m| m.0 == 0.0), "{t:?}");
            // A label with a minus sign is a negative number, never −0.
            assert!(
                t.major
                    .iter()
                    .all(|m| !m.1.starts_with('-') || m.1.parse::<f64>().is_ok_and(|v| v < 0.0)),
                "{t:?}"
            );
        }
        let labels = |lo, hi| -> Vec<String> { linear_ticks(lo, hi, 5).major.into_iter().map(|m| m.1).collect() };
        assert_eq!(labels(0.0, 0.5), ["0.0", "0.1", "0.2", "0.3", "0.4", "0.5"]);
        assert_eq!(labels(0.0, 100.0), ["0", "20", "40", "60", "80", "100"]);
    }
}
