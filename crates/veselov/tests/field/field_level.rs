//! The field core on seed 002's 1+1 lattices: whole-level Newton solves on
//! the triangle complex with the triangle rule reproduce the fast triangle
//! scheme (5.8) on sine-Gordon over a thousand levels, and the rectangle
//! complex with the symmetric rule reproduces (5.12); and a level solve
//! zeroes the Euler–Lagrange residual the momenta are made of, whatever the
//! gradient its Jacobian pass returns beside the blocks.

use nalgebra::{SMatrix, SVector};
use veselov::ad::Scalar;
use veselov::complex::{SpacetimeLattice, StarEntry, TopCell, TopCells};
use veselov::field::cauchy::CauchyOptions;
use veselov::field::cell::{DiscreteLagrangian, exact_gradient, mixed_block_dual};
use veselov::field::fibre::Euclidean;
use veselov::field::level_solve::solve_level;
use veselov::spacetime::{
    CellShape, CoreCell, FastMarcher, InitialData, Lattice, NonlinearWave, RectangleRule, Scheme, SineGordon,
    SolverOptions, TriangleRule,
};

type V1 = SVector<f64, 1>;

/// The first two levels of seed 002's kink–antikink on `lat`.
fn kink_antikink(lat: &Lattice) -> (Vec<f64>, Vec<f64>) {
    let data = InitialData::KinkAntikink {
        epsilon: 1e-6,
        paper_start: true,
    };
    data.levels(lat).expect("initial data")
}

/// Marches seed 002's kink–antikink on the complex of `shape` over `lat`
/// by whole-level solves of `lag` from the linear extrapolation of the two
/// levels below; after level j + 1 is solved, `after(j, complex, values)`.
fn march_levels<L: DiscreteLagrangian<Euclidean<1>, 1>>(
    shape: CellShape,
    lag: &L,
    lat: Lattice,
    levels: usize,
    mut after: impl FnMut(usize, &SpacetimeLattice, &[V1]),
) {
    let (y0, y1) = kink_antikink(&lat);
    let complex = SpacetimeLattice::seed002(shape, &lat, levels + 1).expect("complex");
    let n = lat.nodes();
    let vertex = |i: usize, j: usize| complex.vertex_at(i as i64, j as i64).expect("node");
    let mut values = vec![V1::zeros(); complex.vertex_count()];
    for i in 0..n {
        values[vertex(i, 0)] = V1::new(y0[i]);
        values[vertex(i, 1)] = V1::new(y1[i]);
    }
    for j in 1..levels {
        for i in 0..n {
            values[vertex(i, j + 1)] = values[vertex(i, j)] * 2.0 - values[vertex(i, j - 1)];
        }
        let equations: Vec<usize> = (0..n).map(|i| vertex(i, j)).collect();
        let unknowns: Vec<usize> = (0..n).map(|i| vertex(i, j + 1)).collect();
        solve_level::<_, Euclidean<1>, _, 1>(
            &complex,
            lag,
            &mut values,
            &equations,
            &unknowns,
            true,
            &CauchyOptions::default(),
            j + 1,
        )
        .expect("level solve");
        after(j, &complex, &values);
    }
}

fn compare<L: veselov::spacetime::CellLagrangian<1>>(scheme: Scheme, shape: CellShape, rule: &L, levels: usize) -> f64 {
    let lat = Lattice::periodic(48, 24.0, 4.0).expect("lattice");
    let (y0, y1) = kink_antikink(&lat);
    let opts = SolverOptions {
        rel_tol: 1e-15,
        ..SolverOptions::default()
    };
    let mut fast = FastMarcher::new(SineGordon, scheme, lat, &y0, &y1, opts).expect("fast marcher");
    let mut worst: f64 = 0.0;
    march_levels(shape, &CoreCell(rule), lat, levels, |j, complex, values| {
        fast.step().expect("fast step");
        // Both solve each level to round-off; their difference is round-off
        // carried along the march: bound it per level, relative to the field
        // (3e-14 ≈ 130 ulp per level; measured 6.5e-15 for the triangle and
        // 1.2e-14 for the box scheme, whose fast path stops on a 1e-15
        // correction rather than on the residual).
        let size = fast.current().iter().fold(1.0f64, |a, b| a.max(b.abs()));
        for (i, &y) in fast.current().iter().enumerate() {
            let v = complex.vertex_at(i as i64, j as i64 + 1).expect("node");
            worst = worst.max((values[v][0] - y).abs() / (size * j as f64));
        }
    });
    worst
}

#[test]
fn core_level_solves_reproduce_the_fast_triangle_scheme() {
    let rule = TriangleRule {
        density: NonlinearWave(SineGordon),
        dt: 0.125,
        dx: 0.5,
    };
    let worst = compare(Scheme::Triangle, CellShape::Triangle, &rule, 1000);
    println!("triangle: core vs fast over 1000 levels: {worst:e} per level, relative");
    assert!(worst < 3e-14, "core and fast triangle schemes differ by {worst:e}");
}

#[test]
fn core_level_solves_reproduce_the_symmetric_rectangle_scheme() {
    let rule = RectangleRule {
        density: NonlinearWave(SineGordon),
        dt: 0.125,
        dx: 0.5,
        symmetric: true,
    };
    let worst = compare(Scheme::SymmetricRectangle, CellShape::Rectangle, &rule, 300);
    println!("symmetric rectangle: core vs fast over 300 levels: {worst:e} per level, relative");
    assert!(
        worst < 3e-14,
        "core and fast symmetric-rectangle schemes differ by {worst:e}"
    );
}

/// A cell Lagrangian whose Jacobian pass ([`DiscreteLagrangian::analytic_block`])
/// returns the exact blocks but a gradient off by 1e-9 of its size: the
/// stand-in for a block evaluation whose by-product gradient is rounded
/// otherwise than the gradient the momenta use.
struct OffGradientBlocks<L>(L);

impl<L: DiscreteLagrangian<Euclidean<1>, 1>> DiscreteLagrangian<Euclidean<1>, 1> for OffGradientBlocks<L> {
    fn cell_lagrangian<D: Scalar>(&self, cell: &TopCell, y: &[SVector<D, 1>]) -> D {
        self.0.cell_lagrangian(cell, y)
    }
    fn analytic_block(&self, cell: &TopCell, y: &[V1], a: usize, b: usize) -> Option<(V1, SMatrix<f64, 1, 1>)> {
        let (g, block) = mixed_block_dual::<Euclidean<1>, L, 1>(&self.0, cell, y, a, b);
        Some((g * (1.0 + 1e-9), block))
    }
}

/// Solved levels of the symmetric rectangle scheme satisfy
/// Σ_β ∂L_β/∂y_v = 0 with the gradient of [`exact_gradient`] (which the
/// momenta and currents are made of) to the solve's tolerance, even when
/// the blocks' pass returns another gradient: the level solve takes its
/// residual from the former. (Zeroing the latter would leave a residual of
/// 1e-9 of the terms.)
#[test]
fn level_solves_zero_the_residual_the_momenta_are_made_of() {
    let rule = RectangleRule {
        density: NonlinearWave(SineGordon),
        dt: 0.125,
        dx: 0.5,
        symmetric: true,
    };
    let lag = OffGradientBlocks(CoreCell(&rule));
    let lat = Lattice::periodic(24, 12.0, 4.0).expect("lattice");
    let options = CauchyOptions::default();
    let (mut star, mut verts) = (Vec::<StarEntry>::new(), [0usize; 4]);
    let mut worst: f64 = 0.0;
    march_levels(CellShape::Rectangle, &lag, lat, 20, |j, complex, values| {
        // The solve's own measure: the largest residual over the largest
        // sum of term sizes of one equation.
        let (mut largest, mut terms): (f64, f64) = (0.0, 0.0);
        for i in 0..lat.nodes() {
            complex.star(complex.vertex_at(i as i64, j as i64).expect("node"), &mut star);
            let (mut residual, mut size) = (0.0, 0.0);
            for entry in &star {
                let k = complex.cell_vertices(entry.cell, &mut verts);
                let y: Vec<V1> = verts[..k].iter().map(|&v| values[v]).collect();
                let g = exact_gradient::<Euclidean<1>, _, 1>(&lag, &complex.cell(entry.cell), &y, entry.position)[0];
                residual += g;
                size += g.abs();
            }
            largest = largest.max(residual.abs());
            terms = terms.max(size);
        }
        worst = worst.max(largest / terms);
    });
    println!("largest relative Euler–Lagrange residual of the solved levels: {worst:.2e}");
    assert!(
        worst <= 100.0 * options.tolerance,
        "solved levels leave {worst:.2e} of the terms in the Euler–Lagrange equations"
    );
}
