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

/// The displayable points of a series in display coordinates, decimated to
/// at most [`MAX_POINTS`]; `true` if decimation dropped points.
pub(super) fn prepare(series: &Series, xs: Scale, ys: Scale) -> (Vec<(f64, f64)>, bool) {
    let points: Vec<(f64, f64)> = series
        .x
        .iter()
        .zip(series.y)
        .filter_map(|(&x, &y)| Some((to_axis(x, xs)?, to_axis(y, ys)?)))
        .collect();
    if points.len() <= MAX_POINTS {
        (points, false)
    } else {
        (decimate(&points, MAX_POINTS), true)
    }
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
