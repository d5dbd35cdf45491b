//! Scalar root finding on a bracket: the Illinois variant of regula falsi,
//! safeguarded by bisection (Dowell & Jarratt 1971). A dozen lines; the
//! bracketing logic around it is problem-specific, so no crate is needed.

/// A root of `f` in `[a, b]` given `f(a)·f(b) ≤ 0`, to relative tolerance `tol`
/// in the argument. Returns `None` if the bracket is invalid or `f` is not finite.
pub fn illinois(
    mut f: impl FnMut(f64) -> Option<f64>,
    mut a: f64,
    mut b: f64,
    tol: f64,
    max_iter: usize,
) -> Option<f64> {
    let mut fa = f(a)?;
    let mut fb = f(b)?;
    if fa == 0.0 {
        return Some(a);
    }
    if fb == 0.0 {
        return Some(b);
    }
    if fa.signum() == fb.signum() {
        return None;
    }
    let mut side = 0i8;
    for _ in 0..max_iter {
        let mut c = (a * fb - b * fa) / (fb - fa);
        if !c.is_finite() || c <= a.min(b) || c >= a.max(b) {
            c = 0.5 * (a + b);
        }
        let fc = f(c)?;
        if fc == 0.0 || (b - a).abs() <= tol * c.abs().max(f64::MIN_POSITIVE) {
            return Some(c);
        }
        if fc.signum() == fb.signum() {
            b = c;
            fb = fc;
            if side == -1 {
                fa *= 0.5;
            }
            side = -1;
        } else {
            a = c;
            fa = fc;
            if side == 1 {
                fb *= 0.5;
            }
            side = 1;
        }
    }
    Some(0.5 * (a + b))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_roots_and_rejects_bad_brackets() {
        let r = illinois(|x| Some(x * x * x - 2.0), 0.0, 2.0, 1e-15, 200).expect("root");
        assert!((r - 2f64.cbrt()).abs() < 1e-14);
        assert!(illinois(|x| Some(x * x + 1.0), -1.0, 1.0, 1e-15, 100).is_none());
    }
}
