use veselov::diagnostics::*;
use veselov::mechanics::*;
use veselov::models::*;
fn main() {
    let k = Kepler::new(0.5).unwrap();
    for method in [
        Method::Midpoint,
        Method::Trapezoid,
        Method::GalerkinLobatto(3),
        Method::GalerkinGauss(2),
    ] {
        let x0 = k.initial_state();
        let h = 0.01;
        let mut g = GalerkinIntegrator::new(k.system(), GalerkinScheme::new(method).unwrap(), h).unwrap();
        let mut f = SeparableIntegrator::new(k.system(), GalerkinScheme::new(method).unwrap(), h).unwrap();
        let tg = integrate(&mut g, x0, 628, 1);
        let tf = integrate(&mut f, x0, 628, 1);
        let d = (tg.last().q - tf.last().q).amax();
        let e = energy_series(&k.system(), &tg.states).unwrap();
        let j = momentum_series(&Kepler::angular_symmetry(), &tg.states);
        let (_, jac) = g.flow_jacobian(&x0).unwrap();
        println!(
            "{method:?}: gen-vs-fast {d:e} iters {} / {} fallback {} energy err {:e} J err {:e} sympl {:e} q_end {:?}",
            tg.mean_iterations(),
            tf.mean_iterations(),
            tf.fallback_steps,
            e.max_abs_error(),
            j.max_abs_error(),
            symplecticity_defect(&jac),
            tg.last().q.as_slice()
        );
    }
}
