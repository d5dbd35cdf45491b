//! Time and space evolution on seed 000's 1+1 triangle lattice through the
//! core's flow marcher (Δ(j, a) = (j + 1, a) in time, (j, a + 1) in space),
//! held against the five-point recurrence the DCEL reduces to for the
//! Klein–Gordon equation u_tt = c²u_ss − m²u (note 000 §14):
//! (u^{j+1} − 2u^j + u^{j−1})/Δt² = c²(u_{a+1} − 2u_a + u_{a−1})/Δs² − m²u_a^j.

use nalgebra::SVector;
use veselov::ad::Scalar;
use veselov::complex::{SpacetimeLattice, TopCell, TopCells};
use veselov::field::cauchy::CauchyOptions;
use veselov::field::cell::DiscreteLagrangian;
use veselov::field::fibre::Euclidean;
use veselov::field::flow::FlowMarcher;

use crate::five_point;

/// ℒ_d(φ¹, φ², φ³) = ΔsΔt[½((φ² − φ¹)/Δt)² − ½c²((φ³ − φ¹)/Δs)² − ½m²(φ¹)²]
/// on △ = ((j,a), (j+1,a), (j,a+1)).
struct KleinGordon000 {
    dt: f64,
    ds: f64,
    c2: f64,
    m2: f64,
}

impl DiscreteLagrangian<Euclidean<1>, 1> for KleinGordon000 {
    fn cell_lagrangian<D: Scalar>(&self, _cell: &TopCell, y: &[SVector<D, 1>]) -> D {
        let v = (y[1][0] - y[0][0]) / D::from(self.dt);
        let e = (y[2][0] - y[0][0]) / D::from(self.ds);
        (v * v * 0.5 - e * e * (0.5 * self.c2) - y[0][0] * y[0][0] * (0.5 * self.m2)) * (self.ds * self.dt)
    }
}

const LAG: KleinGordon000 = KleinGordon000 {
    dt: 0.05,
    ds: 0.1,
    c2: 1.0,
    m2: 2.0,
};

fn smooth(j: usize, a: usize) -> f64 {
    let (t, s) = (j as f64 * LAG.dt, a as f64 * LAG.ds);
    (1.3 * s).sin() * (0.7 * t + 0.2).cos() + 0.3 * (2.1 * s - 0.4 * t).cos()
}

#[test]
fn time_evolution_is_the_five_point_scheme() {
    let (n, a_max) = (60, 20);
    let lat = SpacetimeLattice::seed000(n, a_max).expect("lattice");
    let vertex = |j: usize, a: usize| lat.vertex_at(a as i64, j as i64).expect("node");
    // Rows 0 and 1 and the two ends (Dirichlet, time-dependent) are data.
    let mut values = vec![SVector::<f64, 1>::zeros(); lat.vertex_count()];
    let mut known = vec![false; lat.vertex_count()];
    for j in 0..=n {
        for a in 0..=a_max {
            if j <= 1 || a == 0 || a == a_max {
                values[vertex(j, a)] = SVector::from([smooth(j, a)]);
                known[vertex(j, a)] = true;
            }
        }
    }
    // The reference: the explicit five-point recurrence.
    let mut u = vec![vec![0.0; a_max + 1]; n + 1];
    for j in 0..=n {
        for a in 0..=a_max {
            u[j][a] = smooth(j, a);
        }
    }
    let (r, dt2) = (LAG.c2 * LAG.dt * LAG.dt / (LAG.ds * LAG.ds), LAG.dt * LAG.dt);
    for j in 1..n {
        for a in 1..a_max {
            u[j + 1][a] =
                2.0 * u[j][a] - u[j - 1][a] + r * (u[j][a + 1] - 2.0 * u[j][a] + u[j][a - 1]) - dt2 * LAG.m2 * u[j][a];
        }
    }
    let mut m =
        FlowMarcher::<_, Euclidean<1>, _, 1>::new(&lat, LAG, values, known, CauchyOptions::default()).expect("marcher");
    // Row by row; within a row in order of a (the equation at (j, a) also
    // holds the unknown (j+1, a−1) through △_{a−1}^j).
    for j in 1..n {
        for a in 1..a_max {
            m.solve(vertex(j, a), vertex(j + 1, a)).expect("vertex solve");
        }
    }
    let mut worst: f64 = 0.0;
    for j in 0..=n {
        for a in 0..=a_max {
            worst = worst.max((m.values()[vertex(j, a)][0] - u[j][a]).abs());
        }
    }
    assert!(
        worst < 1e-12,
        "time evolution differs from the five-point scheme by {worst:e}"
    );
}

#[test]
fn space_evolution_is_the_five_point_scheme() {
    let (n, a_max) = (20, 30);
    let lat = SpacetimeLattice::seed000(n, a_max).expect("lattice");
    let vertex = |j: usize, a: usize| lat.vertex_at(a as i64, j as i64).expect("node");
    // Columns 0 and 1 and the first and last rows (Dirichlet in time) are data.
    let mut values = vec![SVector::<f64, 1>::zeros(); lat.vertex_count()];
    let mut known = vec![false; lat.vertex_count()];
    for j in 0..=n {
        for a in 0..=a_max {
            if a <= 1 || j == 0 || j == n {
                values[vertex(j, a)] = SVector::from([smooth(j, a)]);
                known[vertex(j, a)] = true;
            }
        }
    }
    let mut u = vec![vec![0.0; a_max + 1]; n + 1];
    for j in 0..=n {
        for a in 0..=a_max {
            u[j][a] = smooth(j, a);
        }
    }
    let q = LAG.ds * LAG.ds / LAG.c2;
    for a in 1..a_max {
        for j in 1..n {
            let utt = (u[j + 1][a] - 2.0 * u[j][a] + u[j - 1][a]) / (LAG.dt * LAG.dt);
            u[j][a + 1] = 2.0 * u[j][a] - u[j][a - 1] + q * (utt + LAG.m2 * u[j][a]);
        }
    }
    let mut m =
        FlowMarcher::<_, Euclidean<1>, _, 1>::new(&lat, LAG, values, known, CauchyOptions::default()).expect("marcher");
    for a in 1..a_max {
        for j in 1..n {
            m.solve(vertex(j, a), vertex(j, a + 1)).expect("vertex solve");
        }
    }
    let mut worst: f64 = 0.0;
    let mut size: f64 = 0.0;
    for j in 0..=n {
        for a in 0..=a_max {
            worst = worst.max((m.values()[vertex(j, a)][0] - u[j][a]).abs());
            size = size.max(u[j][a].abs());
        }
    }
    // Space marching amplifies high temporal frequencies (note 000 §14):
    // compare relative to the solution's size.
    assert!(
        worst <= 1e-11 * size,
        "space evolution differs from the five-point scheme by {worst:e} (size {size:e})"
    );
}

#[test]
fn a_flow_outside_the_star_is_refused() {
    let lat = SpacetimeLattice::seed000(4, 4).expect("lattice");
    let vertex = |j: usize, a: usize| lat.vertex_at(a as i64, j as i64).expect("node");
    let known: Vec<bool> = (0..lat.vertex_count()).map(|v| lat.node(v).1 <= 1).collect();
    let values = vec![SVector::<f64, 1>::zeros(); lat.vertex_count()];
    let mut m =
        FlowMarcher::<_, Euclidean<1>, _, 1>::new(&lat, LAG, values, known, CauchyOptions::default()).expect("marcher");
    let err = m
        .solve(vertex(1, 1), vertex(2, 2))
        .expect_err("(2,2) is not in a cell with (1,1)");
    assert!(err.to_string().contains("does not admit"), "{err}");
}

/// The rolling-window evolution with a cell Lagrangian that does not split
/// (every ∂L/∂y_l may depend on every vertex) and time-dependent Dirichlet
/// data at both ends: the schedule it checks once must hold as every level
/// solves it (the prescribed end of the new level is known then), and the
/// levels are the five-point scheme's.
#[test]
fn rolling_window_with_prescribed_ends_is_the_five_point_scheme() {
    let (r, mu) = (LAG.c2 * LAG.dt * LAG.dt / (LAG.ds * LAG.ds), LAG.dt * LAG.dt * LAG.m2);
    let worst = five_point::worst_difference_from_five_point(LAG, smooth, 12, 40, r, mu);
    assert!(
        worst < 1e-12,
        "rolling window differs from the five-point scheme by {worst:e}"
    );
}
