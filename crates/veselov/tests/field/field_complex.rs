//! Cellular complexes (seed 003 §2, note 003 §1 and tests T1–T7, T11's
//! combinatorial part): ∂∂ = 0, dd = 0, Stokes, counts, incidence, point
//! location, orientation, CFK → cubic, periodic wrap and the top-cell view of
//! every complex kind.

use std::collections::{BTreeMap, BTreeSet};

use veselov::Error;
use veselov::complex::window::factorial;
use veselov::complex::{
    Axis, CellComplex, CfkCell, CfkLattice, CfkWindow, Chain, Cochain, CubicCell, CubicLattice, CubicWindow,
    FiniteComplex, MAX_LATTICE_DIMENSION, Point, Simplicial, SimplicialMesh, SpacetimeKind, SpacetimeLattice,
    StarEntry, TopCells, carrier_cube, geometric_incidence, incidence_from_orientation, locate, orientation, validate,
    validate_cells,
};
use veselov::spacetime::Lattice;
use veselov::spacetime::lattice::{Boundary, CellShape};

use crate::shared::SplitMix;

fn point(xs: &[i64]) -> Point {
    let mut p = [0; MAX_LATTICE_DIMENSION];
    p[..xs.len()].copy_from_slice(xs);
    p
}

fn open_sizes(n: usize) -> Vec<usize> {
    match n {
        1 => vec![4],
        2 => vec![3, 2],
        3 => vec![2, 2, 1],
        _ => vec![1; n],
    }
}

fn periodic_sizes(n: usize) -> Vec<usize> {
    vec![3; n]
}

/// dd = 0: d(d δ_α) = 0 for every cell α (computed through cofaces only).
fn check_dd<K: FiniteComplex>(complex: &K) {
    for k in 0..=complex.dim() {
        for alpha in complex.cells(k) {
            let mut omega = Cochain::new();
            omega.set(alpha.clone(), 1.0);
            let dd = omega.coboundary(complex).coboundary(complex);
            assert!(dd.iter().next().is_none(), "dd ≠ 0 at {alpha:?}");
        }
    }
}

/// ⟨c, dω⟩ = ⟨∂c, ω⟩ for random integer chains and real cochains on every
/// dimension; dω comes from the cofaces, ∂c from the faces.
fn check_stokes<K: FiniteComplex>(complex: &K, rng: &mut SplitMix, trials: usize) {
    for k in 0..complex.dim() {
        let low = complex.cells(k);
        let high = complex.cells(k + 1);
        for _ in 0..trials {
            let mut c = Chain::new();
            for _ in 0..1 + rng.below(8) {
                c.add(high[rng.below(high.len())].clone(), rng.below(7) as i64 - 3);
            }
            let mut omega = Cochain::new();
            for a in &low {
                if rng.below(3) > 0 {
                    omega.set(a.clone(), 2.0 * rng.uniform() - 1.0);
                }
            }
            let lhs = c.pair(&omega.coboundary(complex));
            let rhs = c.boundary(complex).pair(&omega);
            assert!((lhs - rhs).abs() <= 1e-13 * (1.0 + lhs.abs()), "Stokes: {lhs} vs {rhs}");
        }
    }
}

#[test]
fn boundary_of_boundary_and_dd_vanish_on_windows() {
    for n in 1..=4 {
        let cubic = CubicWindow::open(&open_sizes(n)).expect("cubic window");
        validate(&cubic).expect("cubic window axioms");
        check_dd(&cubic);
        let cfk = CfkWindow::open(&open_sizes(n)).expect("CFK window");
        validate(&cfk).expect("CFK window axioms");
        check_dd(&cfk);
    }
}

#[test]
fn periodic_quotients_are_complexes() {
    for n in 1..=4 {
        let cubic = CubicWindow::periodic(&periodic_sizes(n)).expect("cubic torus");
        validate(&cubic).expect("cubic torus axioms");
        let cfk = CfkWindow::periodic(&periodic_sizes(n)).expect("CFK torus");
        validate(&cfk).expect("CFK torus axioms");
        if n <= 3 {
            check_dd(&cubic);
            check_dd(&cfk);
        }
    }
    // mixed axes: periodic in time-like axis 0, open in axis 1
    let mixed = CfkWindow::new(&[Axis::periodic(4), Axis::open(2)]).expect("mixed window");
    validate(&mixed).expect("mixed window axioms");
    check_dd(&mixed);
}

#[test]
fn infinite_lattices_satisfy_the_axioms_around_a_vertex() {
    for n in 1..=4 {
        let cfk = CfkLattice::new(n).expect("CFK lattice");
        let cubic = CubicLattice::new(n).expect("cubic lattice");
        let origin = point(&[1, -2, 3, 0]);
        let mut star = Vec::new();
        cfk.star_cells(&CfkCell::vertex(&origin), &mut star);
        let closure = closure(&cfk, &star);
        validate_cells(&cfk, closure.iter().copied()).expect("CFK axioms");
        cubic.star_cells(&CubicCell::vertex(&origin), &mut Vec::new());
        let mut cstar = Vec::new();
        cubic.star_cells(&CubicCell::vertex(&origin), &mut cstar);
        let cclosure = closure_of(&cubic, &cstar);
        validate_cells(&cubic, cclosure.iter().copied()).expect("cubic axioms");
    }
}

fn closure_of<K: CellComplex>(complex: &K, cells: &[K::Cell]) -> BTreeSet<K::Cell> {
    let mut all: BTreeSet<K::Cell> = cells.iter().cloned().collect();
    let mut frontier: Vec<K::Cell> = cells.to_vec();
    let mut faces = Vec::new();
    while let Some(c) = frontier.pop() {
        complex.faces(&c, &mut faces);
        for (a, _) in faces.drain(..) {
            if all.insert(a.clone()) {
                frontier.push(a);
            }
        }
    }
    all
}

fn closure(complex: &CfkLattice, cells: &[CfkCell]) -> BTreeSet<CfkCell> {
    closure_of(complex, cells)
}

#[test]
fn stokes_theorem_on_random_chains_and_cochains() {
    let mut rng = SplitMix(2024);
    for n in 1..=4 {
        check_stokes(&CubicWindow::open(&open_sizes(n)).expect("cubic"), &mut rng, 20);
        check_stokes(&CfkWindow::open(&open_sizes(n)).expect("CFK"), &mut rng, 20);
        check_stokes(
            &CubicWindow::periodic(&periodic_sizes(n.min(3))).expect("cubic torus"),
            &mut rng,
            10,
        );
        check_stokes(
            &CfkWindow::periodic(&periodic_sizes(n.min(3))).expect("CFK torus"),
            &mut rng,
            10,
        );
    }
    let mesh = SimplicialMesh::from_top_cells(&CfkWindow::open(&[3, 3, 2]).expect("CFK")).expect("mesh");
    check_stokes(&mesh, &mut rng, 30);
}

#[test]
fn cubic_counts() {
    for n in 1..=4 {
        let lattice = CubicLattice::new(n).expect("lattice");
        let v = CubicCell::vertex(&point(&[2, -1, 0, 5]));
        let mut star = Vec::new();
        lattice.star_cells(&v, &mut star);
        assert_eq!(star.len(), 1 << n, "|S_v| = 2^n");
        let mut neighbours = BTreeSet::new();
        for c in &star {
            assert_eq!(lattice.cell_dimension(c), n);
            let vs = lattice.vertices(c);
            assert_eq!(vs.len(), 1 << n, "2^n vertices per cell");
            assert!(vs.contains(&v));
            neighbours.extend(vs);
        }
        assert_eq!(neighbours.len(), 3usize.pow(n as u32), "3^n star-adjacent vertices");
        let torus = CubicWindow::periodic(&periodic_sizes(n)).expect("torus");
        let mut entries = Vec::new();
        for v in 0..torus.vertex_count() {
            torus.star(v, &mut entries);
            assert_eq!(entries.len(), 1 << n, "wrapped star has full size");
        }
    }
}

#[test]
fn cfk_counts() {
    let per_base: [&[usize]; 4] = [&[1, 1], &[1, 3, 2], &[1, 7, 12, 6], &[1, 15, 50, 60, 24]];
    for n in 1..=4 {
        let lattice = CfkLattice::new(n).expect("lattice");
        let p = point(&[3, 1, -4, 2]);
        let v = CfkCell::vertex(&p);
        let mut star = Vec::new();
        lattice.star_cells(&v, &mut star);
        assert_eq!(star.len(), factorial(n + 1), "|S_v| = (n+1)!");
        assert_eq!(star.iter().collect::<BTreeSet<_>>().len(), star.len());
        let neighbours: BTreeSet<CfkCell> = star.iter().flat_map(|c| lattice.vertices(c)).collect();
        assert_eq!(
            neighbours.len(),
            (1 << (n + 1)) - 1,
            "2^(n+1) − 1 star-adjacent vertices"
        );
        // k-cells with base v: collected from the closure of the stars of v and
        // of its neighbours (every cell based at v lies in S_v's closure)
        let based: Vec<CfkCell> = closure(&lattice, &star).into_iter().filter(|c| c.base == p).collect();
        for (k, &expected) in per_base[n - 1].iter().enumerate() {
            assert_eq!(
                based.iter().filter(|c| c.dimension() == k).count(),
                expected,
                "n = {n}, k = {k}"
            );
        }
        // the same counts from a torus: k-cells / vertices
        let torus = CfkWindow::periodic(&periodic_sizes(n)).expect("torus");
        for (k, &expected) in per_base[n - 1].iter().enumerate() {
            assert_eq!(
                torus.cells(k).len(),
                expected * torus.vertex_count(),
                "torus n = {n}, k = {k}"
            );
        }
        let mut entries = Vec::new();
        for v in 0..torus.vertex_count() {
            torus.star(v, &mut entries);
            assert_eq!(entries.len(), factorial(n + 1), "wrapped star has full size");
        }
    }
}

#[test]
fn each_cube_is_the_image_of_n_factorial_simplices() {
    for n in 1..=4 {
        let torus = CfkWindow::periodic(&periodic_sizes(n)).expect("torus");
        let mut images: BTreeMap<CubicCell, usize> = BTreeMap::new();
        for c in 0..torus.cell_count() {
            let cell = torus.top_cell(c);
            let cube = carrier_cube(&cell);
            assert_eq!(cube, CubicCell::cube(n, &cell.base), "(3.4): v + ½(1, …, 1)");
            *images.entry(cube).or_insert(0) += 1;
        }
        assert_eq!(images.len(), torus.extent().base_count());
        assert!(images.values().all(|&m| m == factorial(n)), "n! simplices per cube");
        // the images are exactly the cubes of the cubic torus
        let cubes = CubicWindow::periodic(&periodic_sizes(n)).expect("cubic torus");
        let expected: BTreeSet<CubicCell> = cubes.cells(n).into_iter().collect();
        assert_eq!(images.keys().copied().collect::<BTreeSet<_>>(), expected);
    }
}

#[test]
fn geometric_incidence_matches_the_closed_form() {
    for n in 1..=4 {
        let window = CfkWindow::open(&open_sizes(n)).expect("window");
        let mut faces = Vec::new();
        let mut checked = 0;
        for k in 1..=n {
            for beta in window.cells(k) {
                window.faces(&beta, &mut faces);
                assert_eq!(faces.len(), k + 1);
                for (alpha, s) in &faces {
                    assert_eq!(geometric_incidence(&beta, alpha), *s, "[{beta:?} : {alpha:?}]");
                    checked += 1;
                }
            }
        }
        assert!(checked > 0);
    }
}

#[test]
fn orientation_round_trip() {
    let mut rng = SplitMix(7);
    for n in 1..=4 {
        let window = CfkWindow::open(&open_sizes(n)).expect("window");
        for k in 0..=n {
            for beta in window.cells(k) {
                let ordered = window.vertices(&beta);
                let o = orientation(&window, &ordered).expect("(2.6)");
                assert_eq!(o, beta.orientation(), "(2.6) = sgn of the sort of (min S_a)");
                let mut faces = Vec::new();
                window.faces(&beta, &mut faces);
                for j in 0..ordered.len().min(k + 1) {
                    if k == 0 {
                        break;
                    }
                    let s = incidence_from_orientation(&window, &ordered, j).expect("(2.7)");
                    let face = window
                        .simplex(&[&ordered[..j], &ordered[j + 1..]].concat())
                        .expect("face");
                    assert_eq!(s, window.incidence(&beta, &face), "(2.7) at j = {j}");
                }
                // o(v∘φ) = o(v) sgn φ for a random transposition
                if k >= 1 {
                    let (a, b) = (rng.below(k + 1), rng.below(k + 1));
                    if a != b {
                        let mut swapped = ordered.clone();
                        swapped.swap(a, b);
                        assert_eq!(orientation(&window, &swapped).expect("(2.6)"), -o);
                    }
                }
            }
        }
    }
    // periodic quotients: vertex sets are lifted across the seam
    for n in 2..=3 {
        let torus = CfkWindow::periodic(&periodic_sizes(n)).expect("torus");
        for k in 1..=n {
            for beta in torus.cells(k) {
                let ordered = torus.vertices(&beta);
                assert_eq!(torus.simplex(&ordered), Some(beta), "vertex set → cell across the seam");
                assert_eq!(orientation(&torus, &ordered).expect("(2.6)"), beta.orientation());
                for j in 0..=k {
                    let face = torus
                        .simplex(&[&ordered[..j], &ordered[j + 1..]].concat())
                        .expect("face");
                    assert_eq!(
                        incidence_from_orientation(&torus, &ordered, j).expect("(2.7)"),
                        torus.incidence(&beta, &face)
                    );
                }
            }
        }
    }
    // the mesh: incidences → orientations → incidences
    let mesh = SimplicialMesh::from_top_cells(&CfkWindow::open(&[2, 2, 1]).expect("window")).expect("mesh");
    for k in 1..=3 {
        for beta in mesh.cells(k) {
            let ordered = mesh.vertices(&beta);
            assert_eq!(
                orientation(&mesh, &ordered).expect("(2.6)"),
                1,
                "a cell is positive on its own order"
            );
            for j in 0..=k {
                let face = mesh
                    .simplex(&[&ordered[..j], &ordered[j + 1..]].concat())
                    .expect("face");
                assert_eq!(
                    incidence_from_orientation(&mesh, &ordered, j).expect("(2.7)"),
                    mesh.incidence(&beta, &face)
                );
            }
        }
    }
}

#[test]
fn example_2_19() {
    let p = [5.4, 2.1, 4.3, -1.7, 6.0];
    let beta = locate(&p, 1e-9).expect("locate");
    assert_eq!(beta.base, point(&[5, 2, 4, -2, 6]));
    assert_eq!(beta, CfkCell::new(&beta.base, &[&[0], &[2, 3], &[1]]).expect("cell"));
    let vertices: Vec<Point> = (0..=3).map(|a| beta.vertex_at(a)).collect();
    assert_eq!(
        vertices,
        vec![
            point(&[5, 2, 4, -2, 6]),
            point(&[6, 2, 4, -2, 6]),
            point(&[6, 2, 5, -1, 6]),
            point(&[6, 3, 5, -1, 6])
        ]
    );
    assert_eq!(veselov::complex::cfk_geometry::volume_axes(&beta), vec![0, 1, 2]);
    let alpha = CfkCell::new(&beta.base, &[&[0, 2, 3], &[1]]).expect("face");
    assert_eq!(veselov::complex::cfk_geometry::volume_axes(&alpha), vec![0, 1]);
    assert_eq!(beta.face(1), Some((alpha, 1)), "α = β∖{{v1}}, closed form [β:α] = +1");
    assert_eq!(geometric_incidence(&beta, &alpha), 1, "Def. 2.18 [β:α] = +1");
    // exact point location with exactly representable fractions
    let exact = locate(&[5.5, 2.125, 4.25, -1.75, 6.0], 0.0).expect("locate");
    assert_eq!(
        exact,
        CfkCell::new(&point(&[5, 2, 4, -2, 6]), &[&[0], &[2, 3], &[1]]).expect("cell")
    );
}

#[test]
fn point_location_lands_in_the_open_hull() {
    let mut rng = SplitMix(99);
    for n in 1..=MAX_LATTICE_DIMENSION {
        for _ in 0..200 {
            let p: Vec<f64> = (0..n).map(|_| 20.0 * rng.uniform() - 10.0).collect();
            let c = locate(&p, 0.0).expect("locate");
            // p = v₀ + Σ_a f_a e_{S_a}, 1 > f_1 > … > f_k > 0: barycentric weights positive
            let mut f = vec![0.0; c.dimension() + 2];
            f[0] = 1.0;
            for (i, &x) in p.iter().enumerate() {
                let frac = x - c.base[i] as f64;
                let l = c.labels[i] as usize;
                if l == 0 {
                    assert_eq!(frac, 0.0);
                } else {
                    f[l] = frac;
                }
            }
            assert!(f.windows(2).all(|w| w[0] > w[1]), "decreasing fractions {f:?}");
        }
    }
    // T6: in 2-D, (i,j,+) is positive in weight order, (i,j,−) negative
    let plus = locate(&[0.7, 0.2], 0.0).expect("locate");
    let minus = locate(&[0.2, 0.7], 0.0).expect("locate");
    assert_eq!((plus.orientation(), minus.orientation()), (1, -1));
    let det = |c: &CfkCell| {
        let (v0, v1, v2) = (c.vertex_at(0), c.vertex_at(1), c.vertex_at(2));
        (v1[0] - v0[0]) * (v2[1] - v0[1]) - (v1[1] - v0[1]) * (v2[0] - v0[0])
    };
    assert_eq!((det(&plus), det(&minus)), (1, -1));
}

/// Every cell appears in the star of each of its vertices at its position,
/// stars are sorted, and their total size is the number of (cell, vertex)
/// incidences.
fn check_top_cells(complex: &dyn TopCells) {
    let mut out = vec![0usize; complex.max_cell_vertices()];
    let mut star: Vec<StarEntry> = Vec::new();
    let mut total = 0;
    for c in 0..complex.cell_count() {
        assert_eq!(complex.cell(c).index, c);
        let m = complex.cell_vertices(c, &mut out);
        assert!(m <= complex.max_cell_vertices());
        let distinct: BTreeSet<usize> = out[..m].iter().copied().collect();
        assert_eq!(distinct.len(), m, "distinct vertices in cell {c}");
        for (position, &v) in out[..m].iter().enumerate() {
            assert!(v < complex.vertex_count());
            complex.star(v, &mut star);
            assert!(
                star.contains(&StarEntry { cell: c, position }),
                "cell {c} in the star of {v}"
            );
        }
        total += m;
    }
    let mut star_total = 0;
    for v in 0..complex.vertex_count() {
        complex.star(v, &mut star);
        assert!(star.windows(2).all(|w| w[0].cell < w[1].cell), "star of {v} sorted");
        for e in &star {
            complex.cell_vertices(e.cell, &mut out);
            assert_eq!(out[e.position], v);
        }
        star_total += star.len();
    }
    assert_eq!(star_total, total);
}

#[test]
fn top_cells_of_every_kind_are_consistent() {
    for n in 1..=4 {
        check_top_cells(&CubicWindow::open(&open_sizes(n)).expect("cubic"));
        check_top_cells(&CubicWindow::periodic(&periodic_sizes(n)).expect("cubic torus"));
        check_top_cells(&CfkWindow::open(&open_sizes(n)).expect("CFK"));
        let torus = CfkWindow::periodic(&periodic_sizes(n)).expect("CFK torus");
        check_top_cells(&torus);
        for c in 0..torus.cell_count() {
            let cell = torus.cell(c);
            let top = torus.top_cell(c);
            assert_eq!(cell.origin, top.base);
            assert!(cell.shape < factorial(n));
            assert_eq!(CfkCell::top_from_index(n, &cell.origin, cell.shape), top);
            assert_eq!(torus.top_index(&top), Some(c));
        }
    }
    for n in 1..=4 {
        let cubes = CubicWindow::periodic(&periodic_sizes(n)).expect("cubic torus");
        for c in 0..cubes.cell_count() {
            assert_eq!(cubes.top_index(&cubes.top_cell(c)), Some(c));
            assert_eq!(cubes.cell(c).origin, cubes.top_cell(c).base());
        }
    }
    check_top_cells(&CfkWindow::new(&[Axis::periodic(5), Axis::open(3), Axis::open(1)]).expect("mixed"));
    check_top_cells(&SimplicialMesh::from_top_cells(&CfkWindow::open(&[2, 3]).expect("CFK")).expect("mesh"));
    for boundary in [Boundary::Periodic, Boundary::Free] {
        let lattice = Lattice::new(6, 0.1, 0.05, boundary).expect("lattice");
        for shape in [CellShape::Triangle, CellShape::Rectangle] {
            check_top_cells(&SpacetimeLattice::seed002(shape, &lattice, 4).expect("seed 002"));
        }
    }
    check_top_cells(&SpacetimeLattice::seed000(3, 4).expect("seed 000"));
    check_top_cells(&SpacetimeLattice::new(SpacetimeKind::Seed000Triangle, Axis::periodic(5), 2).expect("periodic"));
}

#[test]
fn seed_002_lattices_follow_the_field_conventions() {
    let lattice = Lattice::new(5, 0.1, 0.05, Boundary::Dirichlet { left: 0.0, right: 0.0 }).expect("lattice");
    let tri = SpacetimeLattice::seed002(CellShape::Triangle, &lattice, 3).expect("triangles");
    assert_eq!((tri.vertex_count(), tri.cell_count()), (15, 8));
    let mut out = [0usize; 4];
    for c in 0..tri.cell_count() {
        let cell = tri.cell(c);
        let (i, j) = (cell.origin[0], cell.origin[1]);
        assert_eq!(tri.cell_vertices(c, &mut out), 3);
        let expected: Vec<usize> = CellShape::Triangle
            .offsets()
            .iter()
            .map(|&(di, dj)| tri.vertex_at(i + di, j + dj).expect("node"))
            .collect();
        assert_eq!(&out[..3], expected.as_slice());
        assert_eq!(tri.node(out[1]), (i, j + 1));
    }
    let periodic = Lattice::periodic(4, 1.0, 2.0).expect("periodic");
    let rect = SpacetimeLattice::seed002(CellShape::Rectangle, &periodic, 3).expect("rectangles");
    assert_eq!((rect.vertex_count(), rect.cell_count()), (12, 8));
    let mut star = Vec::new();
    rect.star(rect.vertex_at(0, 1).expect("node"), &mut star);
    assert_eq!(star.len(), 4, "interior node of a periodic rectangle lattice");
    assert_eq!(rect.cell_vertices(3, &mut out), 4);
    assert_eq!(&out[..4], &[3, 7, 4, 0], "R(3,0) wraps to node 0");
}

#[test]
fn seed_000_lattice_has_the_slaved_row_and_column() {
    let (n, a) = (3usize, 4usize);
    let beam = SpacetimeLattice::seed000(n, a).expect("beam");
    assert_eq!((beam.vertex_count(), beam.cell_count()), ((n + 1) * (a + 1), n * a));
    let mut star = Vec::new();
    // node (j, a) has index j·(A+1) + a in the seed's own (time, space) order
    let index = |j: usize, s: usize| j * (a + 1) + s;
    let mut out = [0usize; 3];
    for c in 0..beam.cell_count() {
        let cell = beam.cell(c);
        let (j, s) = (cell.origin[0] as usize, cell.origin[1] as usize);
        assert_eq!(cell.shape, SpacetimeKind::Seed000Triangle.tag());
        beam.cell_vertices(c, &mut out);
        assert_eq!(out, [index(j, s), index(j + 1, s), index(j, s + 1)]);
    }
    beam.star(index(n, a), &mut star);
    assert!(star.is_empty(), "corner (N, A) is in no triangle");
    for j in 0..n {
        beam.star(index(j, a), &mut star);
        assert!(star.iter().all(|e| e.position == 2), "column A only as vertex 3");
    }
    for s in 0..a {
        beam.star(index(n, s), &mut star);
        assert!(star.iter().all(|e| e.position == 1), "row N only as vertex 2");
    }
    beam.star(index(1, 2), &mut star);
    assert_eq!(star.len(), 3);
}

#[test]
fn mesh_orientation_and_boundaries() {
    // a CFK torus in weight order is not coherently oriented ((i,j,−) is negative)
    let torus = CfkWindow::periodic(&[3, 4]).expect("torus");
    let mesh = SimplicialMesh::from_top_cells(&torus).expect("mesh");
    validate(&mesh).expect("mesh axioms");
    assert!(matches!(mesh.check_orientation(), Err(Error::Complex { .. })));
    let oriented = mesh.oriented().expect("orientable");
    oriented.check_orientation().expect("coherent");
    // a closed oriented surface has no boundary
    let all = Chain::characteristic(oriented.cells(2));
    assert!(all.boundary(&oriented).is_zero());
    // an open square: the boundary is a cycle of 4·side edges
    let square = SimplicialMesh::from_top_cells(&CfkWindow::open(&[3, 3]).expect("square"))
        .expect("mesh")
        .oriented()
        .expect("orientable");
    let boundary = Chain::characteristic(square.cells(2)).boundary(&square);
    assert_eq!(boundary.iter().count(), 12);
    assert!(boundary.boundary(&square).is_zero());
    // the 1+1 triangle lattices as simplicial complexes
    let beam = SimplicialMesh::from_top_cells(&SpacetimeLattice::seed000(3, 4).expect("beam")).expect("mesh");
    validate(&beam).expect("beam axioms");
    beam.check_orientation()
        .expect("translates of one triangle share no edge");
    let lattice = Lattice::periodic(5, 1.0, 1.0).expect("lattice");
    let tri = SpacetimeLattice::seed002(CellShape::Triangle, &lattice, 3).expect("triangles");
    validate(&SimplicialMesh::from_top_cells(&tri).expect("mesh")).expect("triangle axioms");
    assert!(
        SimplicialMesh::from_top_cells(
            &SpacetimeLattice::seed002(CellShape::Rectangle, &lattice, 3).expect("rectangles")
        )
        .is_err()
    );
    // the same counts of cells as the implicit window
    for k in 0..=2 {
        assert_eq!(mesh.cells(k).len(), torus.cells(k).len());
    }
}

#[test]
fn bad_input_is_a_typed_error() {
    let invalid = |r: Result<(), Error>, name: &str| match r {
        Err(Error::InvalidParameter { name: got, .. }) => assert!(got.contains(name), "{got} vs {name}"),
        other => panic!("expected InvalidParameter({name}), got {other:?}"),
    };
    invalid(CubicWindow::open(&[2, 0]).map(|_| ()), "axes[1].cells");
    invalid(CfkWindow::periodic(&[3, 2]).map(|_| ()), "axes[1].cells");
    invalid(CfkWindow::open(&[]).map(|_| ()), "dimension");
    invalid(
        CfkWindow::open(&[1; MAX_LATTICE_DIMENSION + 1]).map(|_| ()),
        "dimension",
    );
    invalid(CfkLattice::new(0).map(|_| ()), "dimension");
    invalid(CubicLattice::new(MAX_LATTICE_DIMENSION + 1).map(|_| ()), "dimension");
    invalid(CfkWindow::open(&[usize::MAX / 2, usize::MAX / 2]).map(|_| ()), "cells");
    invalid(SimplicialMesh::new(4, &[[0, 1, 1]]).map(|_| ()), "cells[0]");
    invalid(SimplicialMesh::new(3, &[[0, 1, 2], [0, 1, 3]]).map(|_| ()), "cells[1]");
    invalid(SimplicialMesh::new(3, &[[0, 1, 2], [2, 1, 0]]).map(|_| ()), "cells[1]");
    invalid(SimplicialMesh::new::<[usize; 3]>(3, &[]).map(|_| ()), "cells");
    invalid(
        SimplicialMesh::new(4, &[vec![0, 1, 2], vec![1, 2]]).map(|_| ()),
        "cells[1]",
    );
    invalid(locate(&[0.5, f64::NAN], 0.0).map(|_| ()), "p[1]");
    invalid(locate(&[0.5], -1.0).map(|_| ()), "tol");
    invalid(SpacetimeLattice::seed000(0, 3).map(|_| ()), "time_cells");
    invalid(
        SpacetimeLattice::new(SpacetimeKind::Seed002Triangle, Axis::periodic(2), 2).map(|_| ()),
        "space.cells",
    );
    // non-manifold: three triangles on one edge
    let fan = SimplicialMesh::new(5, &[[0, 1, 2], [1, 0, 3], [0, 1, 4]]).expect("mesh");
    assert!(
        matches!(fan.check_orientation(), Err(Error::Complex { ref reason, .. }) if reason.contains("non-manifold"))
    );
    assert!(matches!(fan.oriented(), Err(Error::Complex { .. })));
    // inconsistent: two triangles inducing the same orientation on {0, 1}
    let bad = SimplicialMesh::new(4, &[[0, 1, 2], [0, 1, 3]]).expect("mesh");
    assert!(
        matches!(bad.check_orientation(), Err(Error::Complex { ref reason, .. }) if reason.contains("inconsistently"))
    );
    bad.oriented()
        .expect("fixable")
        .check_orientation()
        .expect("coherent after flipping");
    // a Möbius strip is not orientable
    let mobius =
        SimplicialMesh::new(6, &[[0, 1, 3], [1, 3, 4], [1, 2, 4], [2, 4, 5], [2, 5, 3], [5, 3, 0]]).expect("mesh");
    assert!(matches!(mobius.oriented(), Err(Error::Complex { ref reason, .. }) if reason.contains("orientable")));
}
