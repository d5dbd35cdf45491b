//! Nanoseconds per level update (with the discrete energy) of the fast
//! lattice schemes: sine-Gordon kink–antikink, N = 255, h = k/8 (seed 002
//! §5.2). Divide by 255 for the time per node update.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use veselov::spacetime::{FastMarcher, InitialData, Lattice, Scheme, SineGordon, SolverOptions};

/// Levels between restarts (keeps the solitons in the same regime).
const RESTART: usize = 20_000;

fn field_step(c: &mut Criterion) {
    let lat = Lattice::periodic(255, 40.0, 8.0).expect("valid lattice");
    let (y0, y1) = InitialData::KinkAntikink {
        epsilon: 1e-6,
        paper_start: true,
    }
    .levels(&lat)
    .expect("initial data");
    for scheme in Scheme::ALL {
        let fresh = || FastMarcher::new(SineGordon, scheme, lat, &y0, &y1, SolverOptions::default()).expect("valid");
        let mut m = fresh();
        for _ in 0..100 {
            m.step().expect("warm-up");
        }
        let mut k = 0usize;
        c.bench_function(&format!("sine-gordon/N=255/{}", scheme.name()), |b| {
            b.iter(|| {
                if k.is_multiple_of(RESTART) {
                    m = fresh();
                }
                m.step().expect("step");
                k += 1;
                black_box(m.energy())
            })
        });
        println!(
            "{}: {:.2} iterations per level",
            scheme.name(),
            m.total_iterations() as f64 / (m.level() - 1) as f64
        );
    }
}

criterion_group!(benches, field_step);
criterion_main!(benches);
