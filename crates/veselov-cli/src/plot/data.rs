//! From data to axes: points that can be shown, decimation, axis ranges and
//! the equal-aspect adjustment.

use super::{MAX_POINTS, Scale, Series};

/// Fraction of the data span added on each side of an axis range.
const PAD: f64 = 0.05;

/// `v` in display coordinates (`log₁₀ v` on a log axis), if it can be shown.
pub(super) fn to_axis(v: f64, scale: Scale) -> Option<f64> {
    match scale {
        Scale::Linear => v.is_finite().then_some(v),
        Scale::Log => (v.is_finite() && v > 0.0).then(|| v.log10()),
    }
}

/// The displayable points of a series in display coordinates, and `true`
/// if points were dropped. Beyond [`MAX_POINTS`] points, a time series
/// (non-decreasing `x`) is decimated to at most that many by [`decimate`];
/// a curve that turns back on itself (a phase portrait, an orbit) is thinned
/// along its path by [`thin_along_path`] instead, since keeping a few points
/// per bucket of a retraced orbit would join far-apart points by chords.
pub(super) fn prepare(series: &Series, xs: Scale, ys: Scale) -> (Vec<(f64, f64)>, bool) {
    let points: Vec<(f64, f64)> = series
        .x
        .iter()
        .zip(series.y)
        .filter_map(|(&x, &y)| Some((to_axis(x, xs)?, to_axis(y, ys)?)))
        .collect();
    if points.len() <= MAX_POINTS {
        (points, false)
    } else if points.windows(2).all(|w| w[0].0 <= w[1].0) {
        (decimate(&points, MAX_POINTS), true)
    } else {
        let thinned = thin_along_path(&points, PATH_TOLERANCE);
        let dropped = thinned.len() < points.len();
        (thinned, dropped)
    }
}

/// Largest distance, as a fraction of the data's extent on each axis, by
/// which [`thin_along_path`] may move the drawn path: a fifth of a pixel on
/// an 800-pixel-wide figure.
pub(super) const PATH_TOLERANCE: f64 = 2.5e-4;

/// `points` without those that lie within `tolerance` (a fraction of the
/// extent of the data on each axis) of the last point kept; the last point
/// is always kept. Every dropped point is within `tolerance` of the path
/// drawn, so no chord appears however often the curve retraces itself; the
/// count falls as much as the curve's resolution allows.
pub(super) fn thin_along_path(points: &[(f64, f64)], tolerance: f64) -> Vec<(f64, f64)> {
    let span = |f: fn(&(f64, f64)) -> f64| {
        extent(points.iter().map(f)).map_or(1.0, |(lo, hi)| if hi > lo { hi - lo } else { 1.0 })
    };
    let (sx, sy) = (span(|p| p.0), span(|p| p.1));
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(points.len().min(1 << 16));
    for (i, &p) in points.iter().enumerate() {
        let far = out.last().is_none_or(|q| {
            let (dx, dy) = ((p.0 - q.0) / sx, (p.1 - q.1) / sy);
            dx.abs().max(dy.abs()) > tolerance
        });
        if far || i + 1 == points.len() {
            out.push(p);
        }
    }
    out
}

/// At most `max_points` of `points`, in their original order: consecutive
/// buckets each keep their points of smallest and largest `x` and `y`. For a
/// time series (monotone `x`) these are the bucket's first and last points
/// and its extremes, so the drawn envelope, spikes included, is unchanged.
fn decimate(points: &[(f64, f64)], max_points: usize) -> Vec<(f64, f64)> {
    if points.len() <= max_points {
        return points.to_vec();
    }
    let buckets = (max_points / 4).max(1);
    let size = points.len().div_ceil(buckets);
    let mut out = Vec::with_capacity(max_points);
    for chunk in points.chunks(size) {
        // Indices of the smallest x, largest x, smallest y, largest y.
        let mut idx = [0usize; 4];
        for (i, p) in chunk.iter().enumerate() {
            if p.0 < chunk[idx[0]].0 {
                idx[0] = i;
            }
            if p.0 > chunk[idx[1]].0 {
                idx[1] = i;
            }
            if p.1 < chunk[idx[2]].1 {
                idx[2] = i;
            }
            if p.1 > chunk[idx[3]].1 {
                idx[3] = i;
            }
        }
        idx.sort_unstable();
        for (j, &i) in idx.iter().enumerate() {
            if j == 0 || i != idx[j - 1] {
                out.push(chunk[i]);
            }
        }
    }
    out
}

/// The round number to subtract from the data on an axis whose values
/// `[lo, hi]` (display coordinates) differ only in their sixth significant
/// digit or later, so that tick labels stay short: the midpoint rounded to
/// the first decimal place above the span, with the number of decimals that
/// place needs. `None` when no offset is needed.
pub(super) fn offset(data: Option<(f64, f64)>, scale: Scale) -> Option<(f64, usize)> {
    let (lo, hi) = data?;
    let (mid, span) = (0.5 * lo + 0.5 * hi, hi - lo);
    if scale == Scale::Log || !(span > 0.0 && span.is_finite()) || span >= 1e-5 * mid.abs() {
        return None;
    }
    let place = span.log10().floor() + 1.0;
    let unit = 10f64.powf(place);
    let rounded = (mid / unit).round() * unit;
    let decimals = (-place).clamp(0.0, 17.0) as usize;
    (rounded != 0.0 && rounded.is_finite()).then_some((rounded, decimals))
}

/// `label` with the offset subtracted from its axis named: `E − 14.5673`,
/// `E + 14.5673` for a negative offset.
pub(super) fn offset_label(label: &str, (offset, decimals): (f64, usize)) -> String {
    let text = format!("{:.*}", decimals, offset.abs());
    if offset < 0.0 {
        format!("{label} + {text}")
    } else {
        format!("{label} − {text}")
    }
}

/// Smallest and largest of `values`, or `None` if there are none.
pub(super) fn extent(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    values.fold(None, |acc, v| match acc {
        None => Some((v, v)),
        Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
    })
}

/// The axis range for data spanning `[lo, hi]` (display coordinates), with
/// a margin, never degenerate and always finite.
pub(super) fn axis_range(data: Option<(f64, f64)>, scale: Scale) -> (f64, f64) {
    let Some((lo, hi)) = data else {
        // Nothing to show: a unit frame (1 to 10 on a log axis).
        return (0.0, 1.0);
    };
    // Halves first, so that extreme values cannot overflow.
    let mid = 0.5 * lo + 0.5 * hi;
    let half = 0.5 * hi - 0.5 * lo;
    let constant = match scale {
        Scale::Linear => half <= 1e-12 * lo.abs().max(hi.abs()),
        Scale::Log => half <= 1e-12,
    };
    let half = if !constant {
        half * (1.0 + 2.0 * PAD)
    } else {
        match scale {
            Scale::Linear if mid == 0.0 => 1.0,
            Scale::Linear => 0.1 * mid.abs(),
            Scale::Log => 0.5,
        }
    };
    (
        (mid - half).clamp(-f64::MAX, f64::MAX),
        (mid + half).clamp(-f64::MAX, f64::MAX),
    )
}

/// Widen the shorter of two ranges so that both have the same number of
/// units per pixel on a plotting area of `pixels` (width, height).
pub(super) fn equalise(x: (f64, f64), y: (f64, f64), pixels: (u32, u32)) -> ((f64, f64), (f64, f64)) {
    let (w, h) = (f64::from(pixels.0.max(1)), f64::from(pixels.1.max(1)));
    let per_pixel = ((x.1 - x.0) / w).max((y.1 - y.0) / h);
    if !per_pixel.is_finite() || per_pixel <= 0.0 {
        return (x, y);
    }
    let widen = |(lo, hi): (f64, f64), len: f64| {
        if (hi - lo) / len >= per_pixel {
            return (lo, hi);
        }
        let mid = 0.5 * lo + 0.5 * hi;
        let half = 0.5 * per_pixel * len;
        (mid - half, mid + half)
    };
    (widen(x, w), widen(y, h))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Largest distance between consecutive points, as a fraction of the
    /// extent of the data (the longest chord the drawn line would have).
    fn longest_chord(points: &[(f64, f64)]) -> f64 {
        let span = |f: fn(&(f64, f64)) -> f64| extent(points.iter().map(f)).map_or(1.0, |(lo, hi)| hi - lo);
        let (sx, sy) = (span(|p| p.0), span(|p| p.1));
        points
            .windows(2)
            .map(|w| ((w[1].0 - w[0].0) / sx).abs().max(((w[1].1 - w[0].1) / sy).abs()))
            .fold(0.0, f64::max)
    }

    #[test]
    fn a_retraced_orbit_is_thinned_along_its_path_without_chords() {
        // 100 turns of an ellipse, 1000 points per turn: consecutive points
        // are 0.3 % of the extent apart.
        let n = 100_000;
        let angle = |i: usize| i as f64 * std::f64::consts::TAU / 1000.0;
        let x: Vec<f64> = (0..n).map(|i| 2.0 * angle(i).cos() + 0.3).collect();
        let y: Vec<f64> = (0..n).map(|i| angle(i).sin()).collect();
        let series = Series {
            label: "orbit",
            x: &x,
            y: &y,
        };
        let all: Vec<(f64, f64)> = x.iter().copied().zip(y.iter().copied()).collect();
        let (points, _) = prepare(&series, Scale::Linear, Scale::Linear);
        assert!(
            longest_chord(&points) <= 1.01 * longest_chord(&all),
            "{}",
            longest_chord(&points)
        );
        // Every dropped point lies within the tolerance of a kept one.
        for p in all.iter().step_by(97) {
            let near = points
                .iter()
                .any(|q| ((p.0 - q.0) / 4.0).abs().max(((p.1 - q.1) / 2.0).abs()) <= PATH_TOLERANCE);
            assert!(near, "{p:?} is not near the drawn path");
        }
        // The bucket decimation of time series would have drawn chords.
        let buckets = decimate(&all, MAX_POINTS);
        assert!(longest_chord(&buckets) > 0.1, "{}", longest_chord(&buckets));
        // A dense retraced curve loses most of its repeats.
        let thin = thin_along_path(&all, 0.01);
        assert!(thin.len() < n / 2 && thin.last() == all.last());
    }

    #[test]
    fn values_that_differ_far_into_their_digits_get_a_round_offset() {
        // An energy near −14.5672875 varying by 1e-8.
        let (o, decimals) = offset(Some((-14.567_287_51, -14.567_287_49)), Scale::Linear).expect("an offset");
        assert!((o + 14.567_287_5).abs() < 1e-12, "{o}");
        assert_eq!(offset_label("E", (o, decimals)), "E + 14.5672875");
        assert_eq!(offset_label("x", (2.5, 1)), "x − 2.5");
        // Ordinary ranges, zero-centred data and log axes keep their values.
        assert_eq!(offset(Some((1.0, 2.0)), Scale::Linear), None);
        assert_eq!(offset(Some((-1e-9, 1e-9)), Scale::Linear), None);
        assert_eq!(offset(Some((3.0, 3.0 + 1e-9)), Scale::Log), None);
        assert_eq!(offset(Some((3.0, 3.0)), Scale::Linear), None);
    }
}
