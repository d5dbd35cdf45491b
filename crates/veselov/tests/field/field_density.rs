//! Generic cell densities: the assembled DELf equals the hand-coded (5.8),
//! (5.10), (5.12) residuals and the gradient of the discrete action; region
//! topology (§5.1); the discrete multisymplectic form formula (5.6).

use nalgebra::SVector;
use proptest::prelude::*;
use veselov::spacetime::{
    Boundary, CellLagrangian, CellShape, ComplexKleinGordon, GenericMarcher, Lattice, Node, NonlinearWave,
    RectangleRule, Region, SineGordon, Tangent, TriangleRule, action, delf_residual, multisymplectic_boundary_sum,
    node_value, split_symplectic_form, window,
};

type V1 = SVector<f64, 1>;

/// Hand-coded residuals at node (i, 0) of the three levels −1, 0, 1 (N = cos).
fn hand_residual(kind: &str, h: f64, k: f64, lv: &[Vec<f64>; 3], i: usize) -> f64 {
    let n = lv[1].len();
    let at = |j: i64, ii: i64| lv[(j + 1) as usize][ii.rem_euclid(n as i64) as usize];
    let i = i as i64;
    let np = |v: f64| -v.sin();
    let dk = |j: i64, ii: i64| at(j, ii + 1) - 2.0 * at(j, ii) + at(j, ii - 1);
    let dh = |ii: i64| at(1, ii) - 2.0 * at(0, ii) + at(-1, ii);
    let rect = |j: i64, ii: i64| 0.25 * (at(j, ii) + at(j + 1, ii) + at(j + 1, ii + 1) + at(j, ii + 1));
    let nbar = 0.25 * (np(rect(0, i)) + np(rect(0, i - 1)) + np(rect(-1, i)) + np(rect(-1, i - 1)));
    let space = (0.25 * dk(1, i) + 0.5 * dk(0, i) + 0.25 * dk(-1, i)) / (k * k);
    match kind {
        "triangle" => {
            let c1 = (at(0, i) + at(1, i) + at(1, i + 1)) / 3.0;
            let c2 = (at(-1, i) + at(0, i) + at(0, i + 1)) / 3.0;
            let c3 = (at(-1, i - 1) + at(0, i - 1) + at(0, i)) / 3.0;
            dk(0, i) / (k * k) - dh(i) / (h * h) + (np(c1) + np(c2) + np(c3)) / 3.0
        }
        "rectangle" => space - dh(i) / (h * h) + nbar,
        _ => space - (0.25 * dh(i + 1) + 0.5 * dh(i) + 0.25 * dh(i - 1)) / (h * h) + nbar,
    }
}

fn check_delf<L: CellLagrangian<1>>(lag: &L, kind: &str, h: f64, k: f64, lv: &[Vec<f64>; 3]) {
    let lat = Lattice::new(lv[1].len(), k, h, Boundary::Periodic).expect("valid");
    let get = |(i, j): Node| {
        let l: Vec<V1> = lv[(j + 1) as usize].iter().map(|&v| V1::new(v)).collect();
        node_value(&lat, &l, i)
    };
    for i in 0..lv[1].len() {
        let generic = delf_residual(lag, &get, (i as i64, 0))[0];
        let hand = hand_residual(kind, h, k, lv, i);
        // Both are sums of terms of size ≤ 4·max|y|/h² + 4·max|y|/k² + 1.
        let scale = 4.0 * 3.0 / (h * h) + 4.0 * 3.0 / (k * k) + 1.0;
        assert!(
            (generic - hand).abs() <= 1e-14 * scale,
            "{kind} node {i}: {generic} vs {hand}"
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]
    #[test]
    fn assembled_delf_matches_printed_residuals(
        data in proptest::collection::vec(-3.0f64..3.0, 21),
        h in 0.02f64..0.5,
        k in 0.05f64..0.5,
    ) {
        let lv = [data[0..7].to_vec(), data[7..14].to_vec(), data[14..21].to_vec()];
        let dens = NonlinearWave(SineGordon);
        check_delf(&TriangleRule { density: dens, dt: h, dx: k }, "triangle", h, k, &lv);
        check_delf(&RectangleRule { density: dens, dt: h, dx: k, symmetric: false }, "rectangle", h, k, &lv);
        check_delf(&RectangleRule { density: dens, dt: h, dx: k, symmetric: true }, "symmetric", h, k, &lv);
    }
}

/// A small deterministic pseudo-random sequence (no external crates).
fn noise(seed: u64, n: usize) -> Vec<f64> {
    let mut s = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    (0..n)
        .map(|_| {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        })
        .collect()
}

fn check_action_gradient<L: CellLagrangian<1>>(lag: &L) {
    // Values on a 9×7 patch of ℤ², the node (4, 3) is interior.
    let vals = noise(7, 63);
    let base = |(i, j): Node| ((0..9).contains(&i) && (0..7).contains(&j)).then(|| V1::new(vals[(i * 7 + j) as usize]));
    let region = window(lag.shape(), 0, 8, 0, 6);
    let p = (4, 3);
    assert!(region.interior().contains(&p));
    let eps = 1e-5;
    let shifted = |d: f64| move |q: Node| base(q).map(|v| if q == p { v.add_scalar(d) } else { v });
    let fd = (action(lag, &region, &shifted(eps)) - action(lag, &region, &shifted(-eps))) / (2.0 * eps);
    let exact = delf_residual(lag, &base, p)[0];
    // Central differences: truncation ε²/6·|S'''| ~ 1e-10·|S'''|, round-off
    // ε_mach·Σ|L|/ε ~ 1e-11·Σ|L|; relative 1e-7 leaves a wide margin.
    assert!((fd - exact).abs() <= 1e-7 * (1.0 + exact.abs()), "{fd} vs {exact}");
}

#[test]
fn delf_is_the_gradient_of_the_discrete_action() {
    let d = NonlinearWave(SineGordon);
    check_action_gradient(&TriangleRule {
        density: d,
        dt: 0.3,
        dx: 0.5,
    });
    check_action_gradient(&RectangleRule {
        density: d,
        dt: 0.3,
        dx: 0.5,
        symmetric: false,
    });
    check_action_gradient(&RectangleRule {
        density: d,
        dt: 0.3,
        dx: 0.5,
        symmetric: true,
    });
}

#[test]
fn region_topology_of_windows() {
    let full = Region::new(CellShape::Triangle, (0..=4).flat_map(|i| (0..=3).map(move |j| (i, j))));
    assert!(!full.is_regular(), "a full triangle window is not regular");
    let w = window(CellShape::Triangle, 0, 4, 0, 3);
    assert!(w.is_regular());
    assert!(
        !w.contains((0, 3)) && !w.contains((4, 0)),
        "corners (i0, j1), (i1, j0) dropped"
    );
    assert_eq!(w.nodes().len(), 20 - 2);
    // interior of a triangle window: i in 1..=3, j in 1..=2
    let int: Vec<Node> = w.interior().into_iter().collect();
    assert_eq!(int, vec![(1, 1), (1, 2), (2, 1), (2, 2), (3, 1), (3, 2)]);
    let r = window(CellShape::Rectangle, 0, 4, 0, 3);
    assert_eq!(r.nodes().len(), 20);
    assert!(r.is_regular());
    assert_eq!(r.boundary().len(), 20 - 6);
    let single = Region::new(CellShape::Rectangle, [(0, 0), (5, 5)]);
    assert!(single.interior().is_empty());
    assert!(!single.is_regular());
}

/// Two noisy smooth levels on `n` nodes and two random first variations,
/// all determined by `seed`.
fn seeded_start<const DIM: usize>(
    n: usize,
    seed: u64,
) -> (
    Vec<SVector<f64, DIM>>,
    Vec<SVector<f64, DIM>>,
    Tangent<DIM>,
    Tangent<DIM>,
) {
    let vec_of = |s: u64, amp: f64, base: &dyn Fn(usize) -> f64| -> Vec<SVector<f64, DIM>> {
        let r = noise(s, n * DIM);
        (0..n)
            .map(|i| SVector::from_fn(|a, _| base(i) * (1.0 + a as f64) + amp * r[i * DIM + a]))
            .collect()
    };
    let w = 2.0 * std::f64::consts::PI / n as f64;
    let y0 = vec_of(seed, 0.1, &|i| (w * i as f64).sin());
    let y1 = vec_of(seed + 1, 0.1, &|i| (w * i as f64).sin() + 0.05 * (w * i as f64).cos());
    let tv = (vec_of(seed + 2, 1.0, &|_| 0.0), vec_of(seed + 3, 1.0, &|_| 0.0));
    let tw = (vec_of(seed + 4, 1.0, &|_| 0.0), vec_of(seed + 5, 1.0, &|_| 0.0));
    (y0, y1, tv, tw)
}

/// March with two first variations and evaluate (5.6) on a window.
fn msff<L: CellLagrangian<DIM> + Clone, const DIM: usize>(lag: L, lat: Lattice, seed: u64) -> (f64, f64) {
    let n = lat.nodes();
    let levels = 10;
    let (y0, y1, mut tv, mut tw) = seeded_start::<DIM>(n, seed);
    let mut ys = vec![y0.clone(), y1.clone()];
    let mut vs = vec![tv.0.clone(), tv.1.clone()];
    let mut ws = vec![tw.0.clone(), tw.1.clone()];
    let mut m = GenericMarcher::new(lag.clone(), lat, y0, y1).expect("valid");
    for _ in 2..levels {
        let mut ts = [tv, tw];
        m.step_with_tangents(&mut ts).expect("step");
        [tv, tw] = ts;
        ys.push(m.current().to_vec());
        vs.push(tv.1.clone());
        ws.push(tw.1.clone());
    }
    let getter = |data: &Vec<Vec<SVector<f64, DIM>>>| {
        let data = data.clone();
        move |(i, j): Node| {
            (0..data.len() as i64)
                .contains(&j)
                .then(|| node_value(&lat, &data[j as usize], i))
                .flatten()
        }
    };
    let region = window(lag.shape(), 2, n as i64 - 3, 0, levels as i64 - 1);
    assert!(region.is_regular());
    multisymplectic_boundary_sum(&lag, &region, &getter(&ys), &getter(&vs), &getter(&ws))
}

#[test]
fn discrete_multisymplectic_form_formula() {
    let lat = Lattice::new(16, 0.2, 0.1, Boundary::Periodic).expect("valid");
    let d = NonlinearWave(SineGordon);
    let cases: Vec<(&str, (f64, f64))> = vec![
        (
            "triangle",
            msff(
                TriangleRule {
                    density: d,
                    dt: 0.1,
                    dx: 0.2,
                },
                lat,
                11,
            ),
        ),
        (
            "rectangle",
            msff(
                RectangleRule {
                    density: d,
                    dt: 0.1,
                    dx: 0.2,
                    symmetric: false,
                },
                lat,
                12,
            ),
        ),
        (
            "symmetric",
            msff(
                RectangleRule {
                    density: d,
                    dt: 0.1,
                    dx: 0.2,
                    symmetric: true,
                },
                lat,
                13,
            ),
        ),
        (
            "complex-kg triangle",
            msff(
                TriangleRule {
                    density: NonlinearWave(ComplexKleinGordon { m2: 1.0, lambda: 0.5 }),
                    dt: 0.1,
                    dx: 0.2,
                },
                lat,
                14,
            ),
        ),
    ];
    for (name, (sum, abs)) in cases {
        println!("{name}: boundary sum {sum:e}, Σ|terms| {abs:e}");
        assert!(abs > 1.0, "{name}: non-trivial terms");
        assert!(sum.abs() <= 1e-10 * abs, "{name}: {sum:e} vs {abs:e}");
    }
}

/// The space–time split map (q_j, q_{j+1}) ↦ (q_{j+1}, q_{j+2}) is symplectic:
/// ω_j(V, W) of [`split_symplectic_form`] stays constant along the marching
/// for two first variations, to round-off relative to the size of its
/// terms (1e-12), for triangles and both rectangle rules on sine-Gordon and
/// for the complex Klein–Gordon field.
#[test]
fn space_time_split_map_is_symplectic() {
    fn check<L: CellLagrangian<DIM> + Clone, const DIM: usize>(lag: L, lat: Lattice, seed: u64) -> f64 {
        let n = lat.nodes();
        let (y0, y1, mut tv, mut tw) = seeded_start::<DIM>(n, seed);
        let mut m = GenericMarcher::new(lag.clone(), lat, y0, y1).expect("valid");
        let form = |m: &GenericMarcher<L, DIM>, tv: &Tangent<DIM>, tw: &Tangent<DIM>| {
            split_symplectic_form(&lag, &lat, (m.previous(), m.current()), (&tv.0, &tv.1), (&tw.0, &tw.1))
        };
        // Not vacuous: the same pairing with M replaced by the identity is not
        // conserved.
        let flat = |tv: &Tangent<DIM>, tw: &Tangent<DIM>| -> f64 {
            (0..n).map(|a| tv.0[a].dot(&tw.1[a]) - tw.0[a].dot(&tv.1[a])).sum()
        };
        let (omega0, scale) = form(&m, &tv, &tw);
        let flat0 = flat(&tv, &tw);
        assert!(
            omega0.abs() > 1e-3 * scale,
            "ω₀ = {omega0:e} is not a meaningful test value"
        );
        let (mut worst, mut flat_change): (f64, f64) = (0.0, 0.0);
        for _ in 0..20 {
            let mut ts = [tv, tw];
            m.step_with_tangents(&mut ts).expect("step");
            [tv, tw] = ts;
            let (omega, abs) = form(&m, &tv, &tw);
            worst = worst.max((omega - omega0).abs() / abs.max(scale));
            flat_change = flat_change.max((flat(&tv, &tw) - flat0).abs() / flat0.abs());
        }
        assert!(flat_change > 1e-6, "the flat pairing changed only by {flat_change:e}");
        worst
    }
    let lat = Lattice::new(16, 0.2, 0.1, Boundary::Periodic).expect("valid");
    let d = NonlinearWave(SineGordon);
    let (dt, dx) = (0.1, 0.2);
    let defects = [
        check(TriangleRule { density: d, dt, dx }, lat, 21),
        check(
            RectangleRule {
                density: d,
                dt,
                dx,
                symmetric: false,
            },
            lat,
            22,
        ),
        check(
            RectangleRule {
                density: d,
                dt,
                dx,
                symmetric: true,
            },
            lat,
            23,
        ),
        check(
            TriangleRule {
                density: NonlinearWave(ComplexKleinGordon { m2: 1.0, lambda: 0.5 }),
                dt,
                dx,
            },
            lat,
            24,
        ),
    ];
    println!("split symplectic defects {defects:?}");
    for d in defects {
        assert!(d <= 1e-12, "defect {d:e}");
    }
}
