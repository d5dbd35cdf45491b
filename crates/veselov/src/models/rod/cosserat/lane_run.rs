//! The rod's solve of a run of vertices of a Cauchy level
//! ([`DiscreteLagrangian::solve_vertex_run`](crate::field::cell::DiscreteLagrangian::solve_vertex_run)):
//! the vertices with whole stars gathered, in run order, into groups of
//! [`ROD_LANES`] solved side by side ([`crate::models::rod::cosserat::lane_step`]), the others —
//! the ends of the rod, a vertex whose cell carries the end load, the
//! vertices a group leaves, the last few of a run — by the scalar split
//! step. Every vertex gets the bits of its own
//! scalar step, so neither the grouping nor the partition of a level
//! among threads changes a result.

use nalgebra::{SVector, Vector3};

use crate::complex::TopCell;
use crate::field::cell::{SolvedVertex, VertexLane, VertexRun};
use crate::field::fibre::Pose;
use crate::field::legendre::CauchyOptions;
use crate::lie::so3::SO3;
use crate::models::rod::cosserat::lanes::{Lanes, M3, V3};
use crate::models::rod::cosserat::{CosseratCell, ROD_LANES};
use crate::models::rod::cosserat_step::split_solve;
use crate::models::rod::potential::RodPotential;

/// The equations of a group, lane by lane: each vertex's material
/// coordinate s₀, its value y₀ = (r₀, R₀), the values at its two cells'
/// middle vertices (shapes 0 and 1, σ = ±1), its momentum μ_v and the size
/// of μ_v's terms, and the value one flow step back.
pub(super) struct LaneInput<const L: usize> {
    pub(super) s0: [f64; L],
    pub(super) r0: V3<L>,
    pub(super) r0m: M3<L>,
    pub(super) r1: [V3<L>; 2],
    pub(super) r1m: [M3<L>; 2],
    pub(super) mu_r: V3<L>,
    pub(super) mu_q: V3<L>,
    pub(super) mu_scale: Lanes<L>,
    pub(super) previous_r: V3<L>,
    pub(super) previous_m: M3<L>,
}

impl<const L: usize> LaneInput<L> {
    fn new() -> Self {
        let (v, m) = ([Lanes::splat(0.0); 3], [[Lanes::splat(0.0); 3]; 3]);
        Self {
            s0: [0.0; L],
            r0: v,
            r0m: m,
            r1: [v; 2],
            r1m: [m; 2],
            mu_r: v,
            mu_q: v,
            mu_scale: Lanes::splat(0.0),
            previous_r: v,
            previous_m: m,
        }
    }

    /// Lane `l` from the vertex's star values `y` (cell σ's values at
    /// `y[σ]`), its momentum and the value one flow step back.
    fn set(&mut self, l: usize, s0: f64, y: &[[Pose<f64>; 3]; 2], lane: &VertexLane<Pose<f64>, 6>) {
        self.s0[l] = s0;
        set_pose(&mut self.r0, &mut self.r0m, l, &y[0][0]);
        for c in 0..2 {
            set_pose(&mut self.r1[c], &mut self.r1m[c], l, &y[c][1]);
        }
        set_pose(&mut self.previous_r, &mut self.previous_m, l, &lane.previous);
        for i in 0..3 {
            self.mu_r[i].0[l] = lane.mu[i];
            self.mu_q[i].0[l] = lane.mu[3 + i];
        }
        self.mu_scale.0[l] = lane.mu_scale;
    }

    /// Lane `l` a copy of lane 0 (a lane the group does not need).
    fn repeat_first(&mut self, l: usize) {
        self.s0[l] = self.s0[0];
        let copy = |x: &mut Lanes<L>| x.0[l] = x.0[0];
        let ([r1a, r1b], [m1a, m1b]) = (&mut self.r1, &mut self.r1m);
        for v in [
            &mut self.r0,
            r1a,
            r1b,
            &mut self.mu_r,
            &mut self.mu_q,
            &mut self.previous_r,
        ] {
            v.iter_mut().for_each(copy);
        }
        for m in [&mut self.r0m, m1a, m1b, &mut self.previous_m] {
            m.iter_mut().flatten().for_each(copy);
        }
        copy(&mut self.mu_scale);
    }
}

/// Lane `l` of a position and a rotation matrix.
#[inline(always)]
fn set_pose<const L: usize>(r: &mut V3<L>, m: &mut M3<L>, l: usize, y: &Pose<f64>) {
    let rotation = y.rotation.matrix();
    for i in 0..3 {
        r[i].0[l] = y.position[i];
        for j in 0..3 {
            m[i][j].0[l] = rotation[(i, j)];
        }
    }
}

impl<P: RodPotential> CosseratCell<P> {
    /// `solve_vertex_run` of the rod (see the module documentation): groups
    /// of [`ROD_LANES`] vertices whose stars are whole by
    /// [`solve_group`](Self::solve_group), every other vertex (and every
    /// vertex a group leaves) by the scalar split step; `false` (solve one
    /// at a time) without the closed forms or for a run that is not a
    /// rod's.
    pub(super) fn solve_run<R>(
        &self,
        run: &R,
        options: &CauchyOptions,
        gradients: &mut [SVector<f64, 6>],
        stride: usize,
        solved: &mut [SolvedVertex<Pose<f64>>],
    ) -> bool
    where
        R: VertexRun<Pose<f64>, 6>,
    {
        let len = run.len();
        let terms_per_vertex = if self.loads.is_some() { 12 } else { 6 };
        if !self.analytic
            || run.dimension() != 2
            || stride < terms_per_vertex
            || gradients.len() < len * stride
            || solved.len() < len
        {
            return false;
        }
        let scalar = |k: usize, terms: &mut [SVector<f64, 6>]| {
            let star = |shape: usize, out: &mut [Pose<f64>]| run.star(k, shape, out);
            let lane = run.lane(k);
            split_solve(self, &star, &lane.mu, lane.mu_scale, &lane.previous, options, terms)
        };
        // Groups of vertices with whole stars, in run order; a vertex whose
        // star is cut by the window (an end of the rod), the vertices a
        // group leaves and the last few of a run alone.
        let mut group = LaneInput::<ROD_LANES>::new();
        let mut slots = [0; ROD_LANES];
        let mut count = 0;
        let mut y = [[Pose::new(Vector3::zeros(), SO3::identity()); 3]; 2];
        let solve_group = |group: &mut LaneInput<ROD_LANES>,
                           slots: &[usize; ROD_LANES],
                           count: usize,
                           solved: &mut [SolvedVertex<Pose<f64>>],
                           gradients: &mut [SVector<f64, 6>]| {
            // A short group repeats its first vertex in the lanes it does not need.
            for l in count..ROD_LANES {
                group.repeat_first(l);
            }
            let done = solve_group_dispatched(self, group, options, slots, count, solved, gradients, stride)
                .unwrap_or([false; ROD_LANES]);
            for (&j, _) in slots.iter().zip(done).take(count).filter(|(_, d)| !d) {
                solved[j] = scalar(j, &mut gradients[j * stride..(j + 1) * stride]);
            }
        };
        for k in 0..len {
            let cells = if run.lanes() >= ROD_LANES {
                run.star(k, 0, &mut y[0]).zip(run.star(k, 1, &mut y[1]))
            } else {
                None
            };
            // A vertex whose cell carries the end load is solved alone.
            let loaded = |cell: &TopCell| self.loads.is_some_and(|l| self.end_load(&l, cell, &y[0][0]).is_some());
            let Some((cell, _)) = cells.filter(|(a, b)| !loaded(a) && !loaded(b)) else {
                solved[k] = scalar(k, &mut gradients[k * stride..(k + 1) * stride]);
                continue;
            };
            group.set(count, self.material_coordinate(&cell), &y, &run.lane(k));
            slots[count] = k;
            count += 1;
            if count == ROD_LANES {
                solve_group(&mut group, &slots, count, solved, gradients);
                count = 0;
            }
        }
        // The last few: a group padded with copies if it is at least half
        // full, else one at a time.
        if 2 * count >= ROD_LANES {
            solve_group(&mut group, &slots, count, solved, gradients);
        } else {
            for &j in &slots[..count] {
                solved[j] = scalar(j, &mut gradients[j * stride..(j + 1) * stride]);
            }
        }
        true
    }
}

/// [`CosseratCell::solve_group`] compiled for the widest vector
/// instructions the processor has (the same bits in every version: no
/// product and sum is contracted into one rounding).
#[multiversion::multiversion(targets("x86_64+avx2+avx512f", "x86_64+avx2"))]
#[allow(clippy::too_many_arguments)]
fn solve_group_dispatched<P: RodPotential, const L: usize>(
    cell: &CosseratCell<P>,
    v: &LaneInput<L>,
    options: &CauchyOptions,
    slots: &[usize; L],
    count: usize,
    solved: &mut [SolvedVertex<Pose<f64>>],
    gradients: &mut [SVector<f64, 6>],
    stride: usize,
) -> Option<[bool; L]> {
    cell.solve_group(v, options, slots, count, solved, gradients, stride)
}

#[cfg(test)]
mod tests {
    use nalgebra::Matrix3;

    use super::*;
    use crate::complex::TopCell;
    use crate::field::legendre::VertexOutcome;
    use crate::lie::so3;
    use crate::models::rod::cosserat::{CosseratDensity, RodParameters};
    use crate::models::rod::potential::LinearPotential;

    const L: usize = ROD_LANES;
    const DS: f64 = 0.05;
    const DT: f64 = 0.01;

    /// Material parameters with full J and C₂ (every entry of the
    /// equations at work).
    fn parameters(scale: f64) -> RodParameters {
        let inertia = Matrix3::new(2.0, 0.1, 0.0, 0.1, 1.5, 0.2, 0.0, 0.2, 1.0) * 1e-3;
        let c2 = Matrix3::new(3.0, 0.2, 0.1, 0.2, 2.0, 0.0, 0.1, 0.0, 4.0) * 1e-2 * scale;
        let c1 = Matrix3::new(5.0, 0.3, 0.0, 0.3, 4.0, 0.1, 0.0, 0.1, 9.0) * scale;
        RodParameters::new(1.3, inertia, c1, c2, Vector3::new(0.0, 0.0, 1.0)).expect("valid")
    }

    /// The star, momentum and solution of a vertex at material point k: a
    /// bent, moving rod near the vertex (angles between neighbours up to
    /// about `bend`), μ the momentum the solution (r₂, R₂) satisfies.
    struct Vertex {
        cells: [TopCell; 2],
        y: [[Pose<f64>; 3]; 2],
        lane: VertexLane<Pose<f64>, 6>,
    }

    fn vertex<Q: RodPotential>(cell: &CosseratCell<Q>, k: i64, bend: f64, next: &mut impl FnMut() -> f64) -> Vertex {
        let mut random = |size: f64| Vector3::new(next(), next(), next()) * size;
        let rotation = so3::exp(&random(1.0));
        let y0 = Pose::new(Vector3::new(0.01 * k as f64, 0.02, DS * k as f64), rotation);
        let middle = |sigma: f64, w: Vector3<f64>, noise: Vector3<f64>| {
            let along = rotation.act(&Vector3::new(0.0, 0.0, 0.5 * DS * sigma));
            Pose::new(y0.position + along + noise, rotation.compose(&so3::exp(&w)))
        };
        let mid = [
            middle(1.0, random(bend), random(1e-3)),
            middle(-1.0, random(bend), random(1e-3)),
        ];
        let (velocity, spin) = (random(0.1), random(2.0));
        let top = Pose::new(y0.position + velocity * DT, rotation.compose(&so3::exp(&(spin * DT))));
        let previous = Pose::new(
            y0.position - velocity * DT + random(1e-6),
            rotation.compose(&so3::exp(&(spin * -DT + random(1e-6)))),
        );
        let cells = [0, 1].map(|shape| {
            let mut origin = [0; crate::complex::MAX_LATTICE_DIMENSION];
            origin[0] = k;
            TopCell {
                index: 0,
                shape,
                origin,
            }
        });
        let mut mu = SVector::<f64, 6>::zeros();
        for (c, m) in cells.iter().zip(&mid) {
            mu += cell.gradients(c, &[y0, *m, top]).expect("suitable")[0];
        }
        Vertex {
            cells,
            y: [[y0, mid[0], top], [y0, mid[1], top]],
            lane: VertexLane {
                mu,
                mu_scale: mu.amax(),
                previous,
            },
        }
    }

    fn scalar<Q: RodPotential>(
        cell: &CosseratCell<Q>,
        v: &Vertex,
        options: &CauchyOptions,
    ) -> (SolvedVertex<Pose<f64>>, Vec<SVector<f64, 6>>) {
        let star = |shape: usize, out: &mut [Pose<f64>]| {
            let y = v.y.get(shape)?;
            out[..3].copy_from_slice(y);
            Some(v.cells[shape])
        };
        let stride = if cell.loads().is_some() { 12 } else { 6 };
        let mut terms = vec![SVector::repeat(f64::NAN); stride];
        let s = split_solve(
            cell,
            &star,
            &v.lane.mu,
            v.lane.mu_scale,
            &v.lane.previous,
            options,
            &mut terms,
        );
        (s, terms)
    }

    fn same_outcome(a: &VertexOutcome, b: &VertexOutcome) -> bool {
        a.iterations == b.iterations
            && a.jacobians == b.jacobians
            && a.relative_residual.to_bits() == b.relative_residual.to_bits()
            && a.failure == b.failure
    }

    /// Solves `vertices` (the first `count` of them) as one group and
    /// checks every lane the group solved against the scalar split step,
    /// bit for bit; returns how many lanes it solved.
    fn check_group<Q: RodPotential>(cell: &CosseratCell<Q>, vertices: &[Vertex], options: &CauchyOptions) -> usize {
        let count = vertices.len();
        let mut input = LaneInput::<L>::new();
        for (l, v) in vertices.iter().enumerate() {
            input.set(l, cell.material_coordinate(&v.cells[0]), &v.y, &v.lane);
        }
        for l in count..L {
            input.repeat_first(l);
        }
        let slots: [usize; L] = std::array::from_fn(|l| l);
        let blank = scalar(cell, &vertices[0], options).0;
        let mut solved = [blank; L];
        let stride = if cell.loads().is_some() { 12 } else { 6 };
        let mut gradients = vec![SVector::<f64, 6>::repeat(f64::NAN); stride * L];
        let done = solve_group_dispatched(
            cell,
            &input,
            options,
            &slots,
            count,
            &mut solved,
            &mut gradients,
            stride,
        )
        .unwrap_or([false; L]);
        for (l, v) in vertices.iter().enumerate().filter(|&(l, _)| done[l]) {
            let (s, terms) = scalar(cell, v, options);
            let mut c = [[0.0; 12]; 2];
            PositionRotation::write(&s.value, &mut c[0]);
            PositionRotation::write(&solved[l].value, &mut c[1]);
            assert_eq!(c[0].map(f64::to_bits), c[1].map(f64::to_bits), "lane {l}: value");
            assert!(
                same_outcome(&s.outcome, &solved[l].outcome),
                "lane {l}: {:?} vs {:?}",
                s.outcome,
                solved[l].outcome
            );
            assert!(s.gradients_written && solved[l].gradients_written);
            assert_eq!(s.forces_written, solved[l].forces_written);
            assert_eq!(solved[l].forces_written, cell.loads().is_some());
            for (a, b) in terms.iter().zip(&gradients[stride * l..stride * (l + 1)]) {
                assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits), "lane {l}: gradients");
            }
        }
        done.iter().take(count).filter(|&&d| d).count()
    }

    use crate::field::fibre::{Fibre, PositionRotation};

    /// Groups of realistic vertices (several material points, stiff and
    /// soft rods, with and without a potential, at round-off and at the
    /// default tolerance, full and padded) give every lane the bits of the
    /// scalar step; a lane driven far from the series branches or to the
    /// iteration limit is left to the scalar step (or the whole group).
    #[test]
    fn groups_give_each_vertex_the_bits_of_the_scalar_step() {
        let mut next = crate::test_support::uniform(0x7f4a_7c15_9e37_79b9);
        let tolerances = [1e-16, CauchyOptions::default().tolerance];
        let free = CosseratCell::new(CosseratDensity::free(parameters(1.0)), DS, DT).expect("spacings");
        let stiff = CosseratCell::new(CosseratDensity::free(parameters(1e3)), DS, DT).expect("spacings");
        let weighted = CosseratCell::new(
            CosseratDensity {
                parameters: parameters(1.0),
                potential: LinearPotential {
                    gradient: Vector3::new(0.0, -9.81, 0.3),
                },
            },
            DS,
            DT,
        )
        .expect("spacings");
        let damped = free
            .clone()
            .with_loads(crate::models::rod::cosserat::RodLoads {
                damping_linear: 0.7,
                damping_angular: 0.05,
                end_force: Vector3::new(0.1, 0.0, 0.0),
                end_torque: Vector3::new(0.0, 0.02, 0.0),
                tip: 0,
                ramp: 0.0,
                start: 0.0,
            })
            .expect("loads");
        let profiled = free
            .clone()
            .with_profile((0..20).map(|k| parameters(1.0 + 0.1 * k as f64)).collect())
            .expect("profile");
        for tolerance in tolerances {
            let options = CauchyOptions {
                tolerance,
                ..CauchyOptions::default()
            };
            for trial in 0..8 {
                let bend = [0.001, 0.01, 0.05][trial % 3];
                for cell in [&free, &stiff, &profiled, &damped] {
                    let vertices: Vec<Vertex> = (0..L as i64).map(|k| vertex(cell, k + 1, bend, &mut next)).collect();
                    assert_eq!(check_group(cell, &vertices, &options), L, "trial {trial}");
                    // Padded: the first five.
                    assert_eq!(check_group(cell, &vertices[..5], &options), 5);
                }
                let vertices: Vec<Vertex> = (0..L as i64)
                    .map(|k| vertex(&weighted, k + 1, bend, &mut next))
                    .collect();
                assert_eq!(check_group(&weighted, &vertices, &options), L);
            }
        }
        // A lane whose momentum asks for a quarter turn leaves the series:
        // the group is left to the scalar step (nothing solved, nothing
        // wrong).
        let options = CauchyOptions::default();
        let mut vertices: Vec<Vertex> = (0..L as i64).map(|k| vertex(&free, k + 1, 0.01, &mut next)).collect();
        vertices[3].lane.mu[4] += 1e3 * vertices[3].lane.mu_scale.max(1.0);
        let solved = check_group(&free, &vertices, &options);
        assert!(solved < L, "{solved}");
        // A lane with too few iterations allowed is left alone; the others
        // are solved.
        let short = CauchyOptions {
            max_iterations: 1,
            tolerance: 1e-16,
        };
        let vertices: Vec<Vertex> = (0..L as i64).map(|k| vertex(&free, k + 1, 0.01, &mut next)).collect();
        let solved = check_group(&free, &vertices, &short);
        assert!(solved < L, "every lane solved within one iteration");
    }
}
