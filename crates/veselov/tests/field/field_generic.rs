//! The generic Newton marcher (any density, exact Hessians) agrees with the
//! fast paths, and handles Dirichlet and free boundaries.

use nalgebra::SVector;

use crate::checkpoints::check_checkpoint;
use veselov::spacetime::{
    Boundary, CellLagrangian, FastMarcher, GenericMarcher, InitialData, Lattice, Node, NonlinearWave, Phi4, Potential,
    RectangleRule, ScalarPotential, Scheme, SineGordon, SolverOptions, TriangleRule, Wave, delf_residual, node_value,
};

type V1 = SVector<f64, 1>;

fn lift(y: &[f64]) -> Vec<V1> {
    y.iter().map(|&v| V1::new(v)).collect()
}

fn compare<P: ScalarPotential + Potential<1> + Copy, L: CellLagrangian<1>>(pot: P, scheme: Scheme, lag: L) -> f64 {
    let lat = Lattice::periodic(32, 16.0, 4.0).expect("valid");
    let data = InitialData::Breather { omega: 0.6, x0: 8.0 };
    compare_on(pot, scheme, lag, lat, data)
}

fn compare_on<P: ScalarPotential + Potential<1> + Copy, L: CellLagrangian<1>>(
    pot: P,
    scheme: Scheme,
    lag: L,
    lat: Lattice,
    data: InitialData,
) -> f64 {
    let (y0, y1) = data.levels(&lat).expect("data");
    let opts = SolverOptions {
        rel_tol: 1e-15,
        ..SolverOptions::default()
    };
    let mut fast = FastMarcher::new(pot, scheme, lat, &y0, &y1, opts).expect("valid");
    let mut generic = GenericMarcher::new(lag, lat, lift(&y0), lift(&y1)).expect("valid");
    let mut worst: f64 = 0.0;
    for _ in 0..100 {
        fast.step().expect("fast step");
        generic.step().expect("generic step");
        for (a, b) in fast.current().iter().zip(generic.current()) {
            worst = worst.max((a - b[0]).abs());
        }
    }
    worst
}

#[test]
fn generic_marcher_agrees_with_the_fast_paths() {
    let (h, k) = (0.125, 0.5);
    let phi4 = Phi4 { m2: 1.0, lambda: 0.5 };
    let cases = [
        (
            "triangle sine-Gordon",
            compare(
                SineGordon,
                Scheme::Triangle,
                TriangleRule {
                    density: NonlinearWave(SineGordon),
                    dt: h,
                    dx: k,
                },
            ),
        ),
        (
            "triangle φ⁴",
            compare(
                phi4,
                Scheme::Triangle,
                TriangleRule {
                    density: NonlinearWave(phi4),
                    dt: h,
                    dx: k,
                },
            ),
        ),
        (
            "rectangle φ⁴",
            compare(
                phi4,
                Scheme::Rectangle,
                RectangleRule {
                    density: NonlinearWave(phi4),
                    dt: h,
                    dx: k,
                    symmetric: false,
                },
            ),
        ),
        (
            "symmetric rectangle sine-Gordon",
            compare(
                SineGordon,
                Scheme::SymmetricRectangle,
                RectangleRule {
                    density: NonlinearWave(SineGordon),
                    dt: h,
                    dx: k,
                    symmetric: true,
                },
            ),
        ),
    ];
    for (name, worst) in cases {
        println!("{name}: max |fast − generic| over 100 levels = {worst:e}");
        // Both solve the same equations to ~1 ulp per level; the levels are
        // O(1) and the linear error growth over 100 levels stays ≪ 1e-11.
        assert!(worst <= 1e-11, "{name}: {worst:e}");
    }
}

#[test]
fn generic_marcher_carries_the_winding_jump_across_the_seam() {
    // A travelling kink on a circle with a 2π winding: the generic path adds
    // the jump to the vertices the seam cells take from node 0, as the fast
    // path's ghost nodes do; the kink crosses the seam during the run.
    let (h, k) = (0.125, 0.5);
    let lat = Lattice::new(
        32,
        k,
        h,
        Boundary::Winding {
            jump: std::f64::consts::TAU,
        },
    )
    .expect("valid");
    let data = InitialData::Kink { x0: 12.0, speed: 0.5 };
    for (name, scheme, worst) in [
        (
            "triangle",
            Scheme::Triangle,
            compare_on(
                SineGordon,
                Scheme::Triangle,
                TriangleRule {
                    density: NonlinearWave(SineGordon),
                    dt: h,
                    dx: k,
                },
                lat,
                data,
            ),
        ),
        (
            "symmetric rectangle",
            Scheme::SymmetricRectangle,
            compare_on(
                SineGordon,
                Scheme::SymmetricRectangle,
                RectangleRule {
                    density: NonlinearWave(SineGordon),
                    dt: h,
                    dx: k,
                    symmetric: true,
                },
                lat,
                data,
            ),
        ),
    ] {
        println!("winding {name} ({scheme:?}): max |fast − generic| over 100 levels = {worst:e}");
        assert!(worst <= 1e-11, "{name}: {worst:e}");
    }
}

fn run_bounded<L: CellLagrangian<1> + Clone>(lag: L, lat: Lattice) -> (f64, Vec<f64>) {
    let n = lat.nodes();
    let w = std::f64::consts::PI / (n - 1) as f64;
    let y0: Vec<f64> = (0..n)
        .map(|i| (w * i as f64).sin() + 0.3 * (3.0 * w * i as f64).sin())
        .collect();
    let mut m = GenericMarcher::new(lag.clone(), lat, lift(&y0), lift(&y0)).expect("valid");
    let mut worst: f64 = 0.0;
    let mut ends = Vec::new();
    for _ in 0..50 {
        let before: Vec<V1> = m.previous().to_vec();
        let mid: Vec<V1> = m.current().to_vec();
        m.step().expect("step");
        let after = m.current().to_vec();
        let get = |(i, j): Node| match j {
            -1 => node_value(&lat, &before, i),
            0 => node_value(&lat, &mid, i),
            1 => node_value(&lat, &after, i),
            _ => None,
        };
        let active = match lat.boundary() {
            Boundary::Dirichlet { .. } => 1..n - 1,
            _ => 0..n,
        };
        for i in active {
            worst = worst.max(delf_residual(&lag, &get, (i as i64, 0))[0].abs());
        }
        ends.push(after[0][0]);
        ends.push(after[n - 1][0]);
    }
    (worst, ends)
}

#[test]
fn dirichlet_and_free_boundaries() {
    let (h, k) = (0.05, 0.1);
    let dir = Lattice::new(21, k, h, Boundary::Dirichlet { left: 0.0, right: 0.0 }).expect("valid");
    let tri = TriangleRule {
        density: NonlinearWave(SineGordon),
        dt: h,
        dx: k,
    };
    let (res, ends) = run_bounded(tri, dir);
    println!("Dirichlet triangles: max residual {res:e}");
    // Residual terms are O(|y|/h²) = O(400); Newton converges to round-off.
    assert!(res <= 1e-9, "{res:e}");
    assert!(ends.iter().all(|&v| v == 0.0), "Dirichlet values stay fixed");
    let free = Lattice::new(21, k, h, Boundary::Free).expect("valid");
    let rect = RectangleRule {
        density: NonlinearWave(Wave),
        dt: h,
        dx: k,
        symmetric: true,
    };
    let (res, ends) = run_bounded(rect, free);
    println!("free rectangles: max residual {res:e}");
    assert!(res <= 1e-9, "{res:e}");
    assert!(ends.iter().any(|&v| v.abs() > 1e-3), "free ends move");
}

/// Both 1+1 marchers refuse a damaged checkpoint (cut short by one word)
/// and are left as they were: they go on bit for bit as marchers never
/// handed it; the whole checkpoint resumes a march bit for bit.
#[test]
fn a_damaged_checkpoint_leaves_the_marchers_as_they_were() {
    let lat = Lattice::periodic(32, 16.0, 4.0).expect("valid");
    let (y0, y1) = InitialData::Breather { omega: 0.6, x0: 8.0 }
        .levels(&lat)
        .expect("data");
    let rule = RectangleRule {
        density: NonlinearWave(SineGordon),
        dt: lat.dt(),
        dx: lat.dx(),
        symmetric: true,
    };
    let fast = || {
        FastMarcher::new(
            SineGordon,
            Scheme::SymmetricRectangle,
            lat,
            &y0,
            &y1,
            SolverOptions::default(),
        )
        .expect("valid")
    };
    let generic = || GenericMarcher::new(rule, lat, lift(&y0), lift(&y1)).expect("valid");
    let cut_short = |saved: &[f64]| vec![saved[..saved.len() - 1].to_vec()];
    check_checkpoint(
        fast,
        |m| {
            m.step().expect("fast step");
        },
        |m| m.current().iter().chain(m.previous()).map(|x| x.to_bits()).collect(),
        cut_short,
    );
    check_checkpoint(
        generic,
        |m| m.step().expect("generic step"),
        |m| m.current().iter().chain(m.previous()).map(|x| x[0].to_bits()).collect(),
        cut_short,
    );
}
