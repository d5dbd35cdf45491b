//! Convergence-order fit: least-squares slope of `log(error)` against `log(h)`.

/// Result of a convergence-order fit.
#[derive(Debug, Clone, PartialEq)]
pub struct OrderFit {
    /// Fitted order (slope of log error vs log h).
    pub order: f64,
    /// Fitted log-constant: `error ≈ exp(intercept) · h^order`.
    pub intercept: f64,
    /// Indices of the points used.
    pub used: Vec<usize>,
}

/// Fit `error ≈ C h^p` by least squares in log-log coordinates over the
/// asymptotic range.
///
/// Points with `error ≤ floor` are masked as round-off plateau, and so is every
/// point with a smaller `h` than the first masked one (once the floor is
/// reached the errors no longer carry the truncation error). Points whose error
/// is not finite are masked too. Returns `None` with fewer than two usable
/// points.
pub fn fit_order(h: &[f64], error: &[f64], floor: f64) -> Option<OrderFit> {
    let mut idx: Vec<usize> = (0..h.len().min(error.len())).collect();
    idx.sort_by(|&a, &b| h[b].total_cmp(&h[a]));
    let mut used = Vec::new();
    for &i in &idx {
        if !(error[i].is_finite() && h[i].is_finite() && h[i] > 0.0) {
            continue;
        }
        if error[i] <= floor {
            break;
        }
        used.push(i);
    }
    if used.len() < 2 {
        return None;
    }
    let n = used.len() as f64;
    let xs: Vec<f64> = used.iter().map(|&i| h[i].ln()).collect();
    let ys: Vec<f64> = used.iter().map(|&i| error[i].ln()).collect();
    let mx = xs.iter().sum::<f64>() / n;
    let my = ys.iter().sum::<f64>() / n;
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    if sxx == 0.0 {
        return None;
    }
    let order = sxy / sxx;
    used.sort_unstable();
    Some(OrderFit {
        order,
        intercept: my - order * mx,
        used,
    })
}

/// Fit over the asymptotic range: the `points` smallest steps whose error
/// lies in `(floor, upper]` — below `floor` is the round-off plateau, above
/// `upper` the pre-asymptotic regime. Returns `None` with fewer than two.
pub fn fit_order_asymptotic(h: &[f64], error: &[f64], floor: f64, upper: f64, points: usize) -> Option<OrderFit> {
    let mut idx: Vec<usize> = (0..h.len().min(error.len()))
        .filter(|&i| error[i].is_finite() && error[i] > floor && error[i] <= upper)
        .collect();
    idx.sort_by(|&a, &b| h[a].total_cmp(&h[b]));
    idx.truncate(points);
    let hs: Vec<f64> = idx.iter().map(|&i| h[i]).collect();
    let es: Vec<f64> = idx.iter().map(|&i| error[i]).collect();
    let mut fit = fit_order(&hs, &es, floor)?;
    fit.used = fit.used.iter().map(|&k| idx[k]).collect();
    fit.used.sort_unstable();
    Some(fit)
}

/// Local convergence rates between consecutive points of a study sorted by
/// decreasing `h`: `r = ln(e_i/e_{i+1}) / ln(h_i/h_{i+1})`, paired with the
/// indices `(i, i+1)` of the two points (in the caller's order). Pairs with a
/// non-finite or non-positive error or step give no rate.
pub fn local_rates(h: &[f64], error: &[f64]) -> Vec<(usize, usize, f64)> {
    let mut idx: Vec<usize> = (0..h.len().min(error.len())).collect();
    idx.sort_by(|&a, &b| h[b].total_cmp(&h[a]));
    idx.windows(2)
        .filter_map(|w| {
            let (a, b) = (w[0], w[1]);
            let ok = |i: usize| error[i].is_finite() && error[i] > 0.0 && h[i].is_finite() && h[i] > 0.0;
            (ok(a) && ok(b) && h[a] > h[b]).then(|| (a, b, (error[a] / error[b]).ln() / (h[a] / h[b]).ln()))
        })
        .collect()
}

/// Fit over the asymptotic range found from the local rates: among the points
/// above the round-off `floor` (as in [`fit_order`]), start from the two
/// finest and add coarser points while the local rate to the next coarser
/// point stays within `tolerance` of the mean of the rates taken so far.
/// Pre-asymptotic coarse steps, whose rates drift, are left out. Returns
/// `None` with fewer than two points above the floor.
pub fn fit_order_auto(h: &[f64], error: &[f64], floor: f64, tolerance: f64) -> Option<OrderFit> {
    let above = fit_order(h, error, floor)?.used;
    let hs: Vec<f64> = above.iter().map(|&i| h[i]).collect();
    let es: Vec<f64> = above.iter().map(|&i| error[i]).collect();
    // Rates from the finest pair towards coarser ones.
    let rates: Vec<(usize, usize, f64)> = local_rates(&hs, &es).into_iter().rev().collect();
    let (&(a, b, first), rest) = rates.split_first()?;
    let (mut keep, mut sum) = (vec![a, b], first);
    for &(coarse, _, r) in rest {
        if (r - sum / (keep.len() - 1) as f64).abs() > tolerance {
            break;
        }
        keep.push(coarse);
        sum += r;
    }
    let kh: Vec<f64> = keep.iter().map(|&k| hs[k]).collect();
    let ke: Vec<f64> = keep.iter().map(|&k| es[k]).collect();
    let mut fit = fit_order(&kh, &ke, floor)?;
    fit.used = fit.used.iter().map(|&k| above[keep[k]]).collect();
    fit.used.sort_unstable();
    Some(fit)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_slope_and_masks_plateau() {
        let h: Vec<f64> = (0..8).map(|k| 0.5_f64.powi(k)).collect();
        let e: Vec<f64> = h.iter().map(|h| (3.0 * h.powi(4)).max(1e-6)).collect();
        let fit = fit_order(&h, &e, 2e-6).expect("enough points");
        assert!((fit.order - 4.0).abs() < 1e-12, "{fit:?}");
        assert!(fit.used.len() < 8);
        assert!(fit_order(&h[..1], &e[..1], 0.0).is_none());
        // Pre-asymptotic large steps (order 6 there) are excluded by `upper`.
        let e2: Vec<f64> = h.iter().map(|h| 3.0 * h.powi(4) + 50.0 * h.powi(6)).collect();
        let fit = fit_order_asymptotic(&h, &e2, 1e-12, 1e-2, 3).expect("enough points");
        assert!((fit.order - 4.0).abs() < 0.05, "{fit:?}");
        assert_eq!(fit.used, vec![5, 6, 7]);
    }

    /// The automatic range drops the pre-asymptotic coarse steps and the
    /// round-off plateau, and keeps every point of a clean power law.
    #[test]
    fn automatic_range_finds_the_asymptotic_points() {
        let h: Vec<f64> = (0..16).map(|k| 0.5_f64.powi(k)).collect();
        // Order 2 with a large h⁴ term (local rates near 4 down to h ≈ 0.01),
        // then a round-off plateau at 1e-11 (from h = 2⁻¹⁴ on).
        let e: Vec<f64> = h.iter().map(|h| (1e-3 * h * h + 20.0 * h.powi(4)).max(1e-11)).collect();
        let fit = fit_order_auto(&h, &e, 2e-11, 0.2).expect("enough points");
        assert!((fit.order - 2.0).abs() < 0.05, "{fit:?}");
        assert!(
            !fit.used.contains(&0) && fit.used.contains(&10) && !fit.used.contains(&15),
            "{fit:?}"
        );
        // The plain fit over every point above the floor is pulled far off.
        assert!(fit_order(&h, &e, 2e-11).expect("fit").order > 2.5);
        let clean: Vec<f64> = h.iter().map(|h| 3.0 * h.powi(3)).collect();
        let fit = fit_order_auto(&h, &clean, 0.0, 0.2).expect("enough points");
        assert_eq!(fit.used.len(), h.len());
        assert!((fit.order - 3.0).abs() < 1e-12);
        let rates = local_rates(&h, &clean);
        assert_eq!(rates.len(), h.len() - 1);
        assert!(rates.iter().all(|r| (r.2 - 3.0).abs() < 1e-12));
    }
}
