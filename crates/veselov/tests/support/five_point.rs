//! The rolling-window time evolution of a Klein–Gordon cell Lagrangian on
//! ℝ¹, Dirichlet data at both ends, held against the explicit five-point
//! recurrence it reduces to (note 000 §14):
//! u^{j+1}_a = 2u^j_a − u^{j−1}_a + r(u^j_{a+1} − 2u^j_a + u^j_{a−1}) − μ u^j_a,
//! r = (cΔt/Δs)², μ = (mΔt)².

use nalgebra::SVector;
use veselov::evolution::marcher::{Direction, EndCondition, Evolution000};
use veselov::field::cauchy::CauchyOptions;
use veselov::field::cell::DiscreteLagrangian;
use veselov::field::fibre::Euclidean;

/// Steps [`Evolution000`] in time from levels 0 and 1 of `u`, with `u` at
/// a = 0 and a = `a_max` for every level, up to level `levels`, and returns
/// the largest difference from the recurrence (which starts from the same
/// levels and ends).
pub fn worst_difference_from_five_point<L>(
    lag: L,
    u: impl Fn(usize, usize) -> f64 + Copy + Send + Sync + 'static,
    a_max: usize,
    levels: usize,
    r: f64,
    mu: f64,
) -> f64
where
    L: DiscreteLagrangian<Euclidean<1>, 1>,
{
    let level = |j: usize| -> Vec<SVector<f64, 1>> { (0..=a_max).map(|a| SVector::from([u(j, a)])).collect() };
    let end = |a: usize| -> EndCondition<SVector<f64, 1>> {
        EndCondition::Prescribed(Box::new(move |j| SVector::from([u(j, a)])))
    };
    let mut evo = Evolution000::<Euclidean<1>, _, 1>::new(
        Direction::Time,
        lag,
        &level(0),
        &level(1),
        end(0),
        end(a_max),
        CauchyOptions::default(),
    )
    .expect("evolution");
    let (mut prev, mut cur): (Vec<f64>, Vec<f64>) = (
        (0..=a_max).map(|a| u(0, a)).collect(),
        (0..=a_max).map(|a| u(1, a)).collect(),
    );
    let mut worst: f64 = 0.0;
    for j in 1..levels {
        let mut next: Vec<f64> = (0..=a_max).map(|a| u(j + 1, a)).collect();
        for a in 1..a_max {
            next[a] = 2.0 * cur[a] - prev[a] + r * (cur[a + 1] - 2.0 * cur[a] + cur[a - 1]) - mu * cur[a];
        }
        evo.step().expect("level");
        assert_eq!(evo.level(), j + 1);
        for (a, x) in next.iter().enumerate() {
            worst = worst.max((evo.value(0, a)[0] - x).abs());
        }
        (prev, cur) = (cur, next);
    }
    worst
}
