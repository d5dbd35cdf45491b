//! Nanoseconds per step of the Lie-group variational integrators.

use criterion::{Criterion, criterion_group, criterion_main};

mod common;
use common::{RESTART, bench_steps};
use nalgebra::{Matrix3, Vector3, Vector6};
use veselov::lgvi::{GroupState, GroupStepMap, LieGroupIntegrator, SplitLieIntegrator};
use veselov::lie::{CayleyMap, ExpMap, GroupFamily, RigidMotions, Rotations, SE3, so3};
use veselov::models::{FreeRigidBody, FreeRigidBodySE3, HeavyTop};

fn bench_group<G: GroupFamily<N>, const N: usize>(
    c: &mut Criterion,
    name: &str,
    mut map: impl GroupStepMap<G, N>,
    x0: GroupState<G, N>,
) {
    bench_steps(c, name, x0, RESTART, |k, x| map.step(k, x).expect("step").0);
}

fn lgvi(c: &mut Criterion) {
    let inertia = Matrix3::new(2.0, 0.1, -0.05, 0.1, 3.0, 0.2, -0.05, 0.2, 4.5);
    let body = FreeRigidBody::new(inertia).expect("valid");
    let top = HeavyTop::new(inertia, 1.5, Vector3::new(0.1, -0.05, 0.8), 9.81).expect("valid");
    let x0 = GroupState::<Rotations, 3>::new(
        0.0,
        so3::exp(&Vector3::new(0.3, -0.7, 0.4)),
        inertia * Vector3::new(1.1, -0.4, 0.9),
    );
    let h = 0.01;
    bench_group(
        c,
        "rigid-body/cayley/split",
        SplitLieIntegrator::<Rotations, CayleyMap, _, 3>::new(body, h).expect("valid"),
        x0,
    );
    bench_group(
        c,
        "rigid-body/exp/split",
        SplitLieIntegrator::<Rotations, ExpMap, _, 3>::new(body, h).expect("valid"),
        x0,
    );
    bench_group(
        c,
        "rigid-body/cayley/general",
        LieGroupIntegrator::<Rotations, CayleyMap, _, 3>::new(body, h).expect("valid"),
        x0,
    );
    bench_group(
        c,
        "heavy-top/cayley/split",
        SplitLieIntegrator::<Rotations, CayleyMap, _, 3>::new(top, h).expect("valid"),
        x0,
    );
    bench_group(
        c,
        "heavy-top/exp/split",
        SplitLieIntegrator::<Rotations, ExpMap, _, 3>::new(top, h).expect("valid"),
        x0,
    );
    bench_group(
        c,
        "heavy-top/cayley/general",
        LieGroupIntegrator::<Rotations, CayleyMap, _, 3>::new(top, h).expect("valid"),
        x0,
    );
    let flyer = FreeRigidBodySE3::new(inertia, 2.5).expect("valid");
    let y0 = GroupState::<RigidMotions, 6>::new(
        0.0,
        SE3::new(so3::exp(&Vector3::new(0.3, -0.7, 0.4)), Vector3::new(1.0, -2.0, 0.5)),
        Vector6::new(2.0, -1.0, 3.0, 0.7, 1.2, -0.4),
    );
    bench_group(
        c,
        "rigid-body-se3/cayley/split",
        SplitLieIntegrator::<RigidMotions, CayleyMap, _, 6>::new(flyer, h).expect("valid"),
        y0,
    );
}

criterion_group!(benches, lgvi);
criterion_main!(benches);
