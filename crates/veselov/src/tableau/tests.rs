use super::*;

/// Absolute tolerance against exact constants of magnitude ≤ 1 (two ulp of 1).
const TOL: f64 = 4e-16;
/// Tolerance for the order conditions evaluated in `f64`.
const ORDER_TOL: f64 = 1e-15;

fn close(got: &[f64], want: &[f64], what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: length");
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        assert!((g - w).abs() <= TOL, "{what}[{k}]: got {g:e}, want {w:e}");
    }
}

fn check_lobatto(c: &[f64], b: &[f64], a: &[f64], a_bar: &[f64]) {
    let (s, q) = (c.len(), gauss_lobatto(c.len()).expect("valid s"));
    close(&q.nodes, c, "Lobatto nodes");
    close(&q.weights, b, "Lobatto weights");
    let t = lobatto_iiia_iiib(s).expect("valid s");
    assert_eq!((t.s, t.order, &t.c, &t.b), (s, 2 * s - 2, &q.nodes, &q.weights));
    close(&t.a, a, "IIIA");
    close(&t.a_bar, a_bar, "IIIB");
}

fn rejects<T: fmt::Debug>(result: Result<T, TableauError>, needle: &str) {
    let message = result.expect_err("invalid input must be rejected").to_string();
    assert!(message.contains(needle), "{message:?} does not contain {needle:?}");
}

/// Largest residuals of B(kb): `Σ b_i c_i^{k−1} = 1/k`, C(kc): `Σ_j m_ij c_j^{k−1} = c_i^k/k`
/// and D(kd): `Σ_i b_i c_i^{k−1} m_ij = b_j (1 − c_j^k)/k`, all in `f64`.
fn residuals(b: &[f64], c: &[f64], m: &[f64], [kb, kc, kd]: [usize; 3]) -> [f64; 3] {
    let (s, mut r) = (c.len(), [0.0_f64; 3]);
    let pow = |x: f64, k: usize| x.powi(k as i32);
    for k in 1..=kb {
        r[0] = r[0].max(((0..s).map(|i| b[i] * pow(c[i], k - 1)).sum::<f64>() - 1.0 / k as f64).abs());
    }
    for (k, i) in (1..=kc).flat_map(|k| (0..s).map(move |i| (k, i))) {
        let lhs: f64 = (0..s).map(|j| m[i * s + j] * pow(c[j], k - 1)).sum();
        r[1] = r[1].max((lhs - pow(c[i], k) / k as f64).abs());
    }
    for (k, j) in (1..=kd).flat_map(|k| (0..s).map(move |j| (k, j))) {
        let lhs: f64 = (0..s).map(|i| b[i] * pow(c[i], k - 1) * m[i * s + j]).sum();
        r[2] = r[2].max((lhs - b[j] * (1.0 - pow(c[j], k)) / k as f64).abs());
    }
    r
}

#[test]
fn double_double_arithmetic_and_internal_accuracy() {
    let (two, three, tiny, half) = (Dd::from(2.0), Dd::from(3.0), 2f64.powi(-60), Dd::from(0.5));
    assert!((two.sqrt() * two.sqrt() - two).to_f64().abs() < 1e-31);
    assert!((Dd::ONE / three * three - Dd::ONE).to_f64().abs() < 1e-31);
    assert_eq!(((Dd::ONE + tiny.into()) - Dd::ONE).to_f64(), tiny);
    let x = Dd::from(1.0 + 2f64.powi(-30));
    assert_eq!((x * x - Dd::from(1.0 + 2f64.powi(-29))).to_f64(), tiny);
    // Lobatto s = 5 nodes 1/2 ± √21/14 and Gauss s = 2 entries 1/4 ∓ √3/6 before rounding.
    let (c, r) = (lobatto_dd(5).expect("valid s").0, Dd::from(21.0).sqrt() / 14.0.into());
    assert!((c[1] - (half - r)).to_f64().abs() < 1e-30 && (c[3] - (half + r)).to_f64().abs() < 1e-30);
    let a = collocation_dd(&gauss_dd(2).expect("valid s").0).expect("distinct nodes");
    let (r, q) = (Dd::from(3.0).sqrt() / 6.0.into(), Dd::from(0.25));
    assert!((a[1] - (q - r)).to_f64().abs() < 1e-30 && (a[2] - (q + r)).to_f64().abs() < 1e-30);
}

#[test]
#[rustfmt::skip]
fn exact_tables() {
    check_lobatto(&[0.0, 1.0], &[0.5, 0.5], &[0.0, 0.0, 0.5, 0.5], &[0.5, 0.0, 0.5, 0.0]);
    let b = [1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0];
    let a = [0.0, 0.0, 0.0, 5.0 / 24.0, 1.0 / 3.0, -1.0 / 24.0, b[0], b[1], b[2]];
    let a_bar = [b[0], -1.0 / 6.0, 0.0, b[0], 1.0 / 3.0, 0.0, b[0], 5.0 / 6.0, 0.0];
    check_lobatto(&[0.0, 0.5, 1.0], &b, &a, &a_bar);

    let r = 5f64.sqrt();
    let b = [1.0 / 12.0, 5.0 / 12.0, 5.0 / 12.0, 1.0 / 12.0];
    let a = [
        0.0, 0.0, 0.0, 0.0,
        (11.0 + r) / 120.0, (25.0 - r) / 120.0, (25.0 - 13.0 * r) / 120.0, (-1.0 + r) / 120.0,
        (11.0 - r) / 120.0, (25.0 + 13.0 * r) / 120.0, (25.0 + r) / 120.0, (-1.0 - r) / 120.0,
        b[0], b[1], b[2], b[3],
    ];
    let a_bar = [
        b[0], (-1.0 - r) / 24.0, (-1.0 + r) / 24.0, 0.0,
        b[0], (25.0 + r) / 120.0, (25.0 - 13.0 * r) / 120.0, 0.0,
        b[0], (25.0 + 13.0 * r) / 120.0, (25.0 - r) / 120.0, 0.0,
        b[0], (11.0 - r) / 24.0, (11.0 + r) / 24.0, 0.0,
    ];
    check_lobatto(&[0.0, (5.0 - r) / 10.0, (5.0 + r) / 10.0, 1.0], &b, &a, &a_bar);

    let r = 21f64.sqrt();
    let b = [1.0 / 20.0, 49.0 / 180.0, 16.0 / 45.0, 49.0 / 180.0, 1.0 / 20.0];
    let (p, q, h, u, v) = (49.0 / 360.0, 8.0 / 45.0, b[0], 17.0 / 280.0, 3.0 / 280.0);
    let a = [
        0.0, 0.0, 0.0, 0.0, 0.0,
        u + 3.0 * r / 1960.0, p - r / 280.0, q - 32.0 * r / 735.0, p - 23.0 * r / 840.0, -v + 3.0 * r / 1960.0,
        13.0 / 320.0, p + 7.0 * r / 192.0, q, p - 7.0 * r / 192.0, 3.0 / 320.0,
        u - 3.0 * r / 1960.0, p + 23.0 * r / 840.0, q + 32.0 * r / 735.0, p + r / 280.0, -v - 3.0 * r / 1960.0,
        b[0], b[1], b[2], b[3], b[4],
    ];
    let a_bar = [
        h, -7.0 / 120.0 - r / 120.0, 1.0 / 15.0, -7.0 / 120.0 + r / 120.0, 0.0,
        h, p + r / 280.0, q - r / 21.0, p - 23.0 * r / 840.0, 0.0,
        h, p + r / 30.0, q, p - r / 30.0, 0.0,
        h, p + 23.0 * r / 840.0, q + r / 21.0, p - r / 280.0, 0.0,
        h, 119.0 / 360.0 - r / 120.0, 13.0 / 45.0, 119.0 / 360.0 + r / 120.0, 0.0,
    ];
    check_lobatto(&[0.0, 0.5 - r / 14.0, 0.5, 0.5 + r / 14.0, 1.0], &b, &a, &a_bar);

    let g = gauss(1).expect("valid s");
    close(&[g.c, g.b, g.a].concat(), &[0.5, 1.0, 0.5], "Gauss s = 1");
    let (r, g) = (3f64.sqrt() / 6.0, gauss(2).expect("valid s"));
    close(&[&g.c[..], &g.b].concat(), &[0.5 - r, 0.5 + r, 0.5, 0.5], "Gauss s = 2: c, b");
    close(&g.a, &[0.25, 0.25 - r, 0.25 + r, 0.25], "Gauss s = 2: a");
    assert_eq!(g.a, g.a_bar);
    let (r, p, q, g) = (15f64.sqrt(), 5.0 / 36.0, 2.0 / 9.0, gauss(3).expect("valid s"));
    close(&g.c, &[0.5 - r / 10.0, 0.5, 0.5 + r / 10.0], "Gauss s = 3: c");
    close(&g.b, &[5.0 / 18.0, 4.0 / 9.0, 5.0 / 18.0], "Gauss s = 3: b");
    let a = [
        p, q - r / 15.0, p - r / 30.0,
        p + r / 24.0, q, p - r / 24.0,
        p + r / 30.0, q + r / 15.0, p,
    ];
    close(&g.a, &a, "Gauss s = 3: a");
    let rule = gauss_legendre(3).expect("valid s");
    assert_eq!((rule.nodes, rule.weights), (g.c, g.b));
}

#[test]
fn order_conditions_and_structure() {
    let (mut worst_gauss, mut worst_lobatto) = ([0.0_f64; 4], [0.0_f64; 5]);
    for s in 1..=MAX_NODES {
        let t = gauss(s).expect("valid s");
        assert_eq!((t.s, t.order, &t.a), (s, 2 * s, &t.a_bar));
        assert!(t.c.windows(2).all(|w| w[0] < w[1]) && t.c[0] > 0.0 && t.c[s - 1] < 1.0);
        let [rb, rc, rd] = residuals(&t.b, &t.c, &t.a, [2 * s, s, s]);
        for (w, r) in worst_gauss.iter_mut().zip([rb, rc, rd, t.symplecticity_defect()]) {
            assert!(r <= ORDER_TOL, "Gauss s = {s}: residual {r:e}");
            *w = w.max(r);
        }
        let q = gauss_legendre(s).expect("valid s");
        assert_eq!((q.len(), q.degree(), q.is_empty()), (s, 2 * s - 1, false));
    }
    for s in 2..=MAX_NODES {
        let t = lobatto_iiia_iiib(s).expect("valid s");
        assert_eq!((t.s, t.order, t.b[0]), (s, 2 * s - 2, 1.0 / (s * s - s) as f64));
        assert!(t.c.windows(2).all(|w| w[0] < w[1]) && t.c[0] == 0.0 && t.c[s - 1] == 1.0);
        let [rb, rc, _] = residuals(&t.b, &t.c, &t.a, [2 * s - 2, s, 0]);
        let [_, rc_bar, rd_bar] = residuals(&t.b, &t.c, &t.a_bar, [0, s - 2, s]);
        let r = [rb, rc, rc_bar, rd_bar, t.symplecticity_defect()];
        for (w, r) in worst_lobatto.iter_mut().zip(r) {
            assert!(r <= ORDER_TOL, "Lobatto s = {s}: residual {r:e}");
            *w = w.max(r);
        }
        // IIIA: first row 0, last row b; IIIB: first column b_1, last column 0; b symmetric.
        let column = |m: &[f64], j: usize| (0..s).map(|i| m[i * s + j]).collect::<Vec<_>>();
        let iiia = t.a[..s].iter().all(|&x| x == 0.0) && t.a[s * s - s..] == t.b[..];
        let iiib = column(&t.a_bar, 0) == vec![t.b[0]; s] && column(&t.a_bar, s - 1) == vec![0.0; s];
        assert!(
            iiia && iiib && t.b.iter().eq(t.b.iter().rev()),
            "Lobatto structure, s = {s}"
        );
        assert_eq!(gauss_lobatto(s).expect("valid s").degree(), 2 * s - 3);
    }
    eprintln!("worst: Gauss (B, C, D, sympl.) {worst_gauss:?}, Lobatto (B, C, C̄, D̄, sympl.) {worst_lobatto:?}");
}

#[test]
fn collocation_matrix_from_f64_nodes() {
    let g = gauss(4).expect("valid s");
    let a = collocation_matrix(&g.c).expect("distinct nodes");
    assert!(a.iter().zip(&g.a).all(|(x, y)| (x - y).abs() <= TOL));
    let c = [0.1, 0.4, 0.9, 1.3, -0.2];
    let r = residuals(&[], &c, &collocation_matrix(&c).expect("distinct nodes"), [0, 5, 0])[1];
    assert!(r <= 8.0 * f64::EPSILON, "C(5) residual {r:e}");
    assert_eq!(collocation_matrix(&[0.7]).expect("one node"), vec![0.7]);
}

#[test]
fn lagrange_reproduces_polynomials() {
    let eval = [-0.5, 0.0, 0.25, 0.5, 0.7, 1.0, 1.5];
    let (lobatto, gauss) = (gauss_lobatto(7).expect("valid s"), gauss_legendre(5).expect("valid s"));
    let mut sets = vec![vec![0.3], lobatto.nodes, gauss.nodes];
    sets.extend((1..=6).map(|m| (0..=m).map(|k| k as f64 / m as f64).collect()));
    let mut worst = 0.0_f64;
    for d in &sets {
        let (li, n) = (lagrange_interpolation(d, &eval).expect("distinct points"), d.len());
        let shape = (li.n_eval, li.n_control, li.values.len(), li.derivatives.len());
        assert_eq!(shape, (7, n, 7 * n, 7 * n));
        for (k, (i, &t)) in (0..n as i32).flat_map(|k| eval.iter().enumerate().map(move |e| (k, e))) {
            // Error of Σ_ν d_ν^k l_ν(t) relative to the size of its terms.
            let apply = |m: &[f64], want: f64| {
                let terms = (0..n).map(|nu| d[nu].powi(k) * m[i * n + nu]);
                (terms.clone().sum::<f64>() - want).abs() / terms.map(f64::abs).sum::<f64>().max(1.0)
            };
            let derivative = f64::from(k) * t.powi((k - 1).max(0));
            let e = apply(&li.values, t.powi(k)).max(apply(&li.derivatives, derivative));
            assert!(e <= 4.0 * f64::EPSILON, "n = {n}, k = {k}, t = {t}: {e:e}");
            worst = worst.max(e);
        }
    }
    eprintln!("Lagrange worst relative residual: {worst:e}");
}

#[test]
fn quadrature_degree_from_node_layout() {
    let rule = |nodes: &[f64]| Quadrature {
        nodes: nodes.to_vec(),
        weights: vec![1.0; nodes.len()],
    };
    let degrees = [&[0.5][..], &[0.0], &[0.0, 1.0], &[0.25, 0.75], &[0.0, 0.5, 1.0], &[]].map(|n| rule(n).degree());
    assert_eq!(degrees, [1, 0, 1, 3, 3, 0]);
    assert!(rule(&[]).is_empty() && rule(&[0.0, 0.5, 1.0]).len() == 3);
}

#[test]
fn bad_input_is_rejected() {
    for s in [0, MAX_NODES + 1] {
        let needle = format!("s = {s}");
        rejects(gauss_legendre(s), &needle);
        rejects(gauss(s), &needle);
        rejects(gauss_lobatto(s), &needle);
        rejects(lobatto_iiia_iiib(s), &needle);
    }
    rejects(gauss_lobatto(1), "s = 1");
    rejects(lobatto_iiia_iiib(1), "s = 1");
    rejects(collocation_matrix(&[]), "nodes = []");
    rejects(collocation_matrix(&[0.0, 0.5, 0.5]), "nodes[2] = 0.5: repeats nodes[1]");
    rejects(collocation_matrix(&[0.0, f64::NAN]), "nodes[1] = NaN");
    rejects(collocation_matrix(&[f64::INFINITY, 1.0]), "nodes[0] = inf");
    rejects(lagrange_interpolation(&[0.0, 1.0, 0.0], &[0.5]), "control[2] = 0.0");
    rejects(lagrange_interpolation(&[], &[0.5]), "control = []");
    rejects(
        lagrange_interpolation(&[0.5], &[f64::NEG_INFINITY]),
        "eval_at[0] = -inf",
    );
    rejects(lagrange_interpolation(&[0.0, 1e-300, 1e300], &[0.5]), "overflow");
    let e: Box<dyn std::error::Error> = Box::new(TableauError::new("s", 0, "why"));
    assert_eq!(e.to_string(), "s = 0: why");
}
