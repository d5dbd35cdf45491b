//! `veselov verify` for rigid-body scenarios: convergence study of the
//! Lie-group integrator ([`crate::verify::Study`]) against RK4 on the
//! continuous Euler–Poincaré equations.

use veselov::lgvi::{GroupState, SplitLieIntegrator, SplitReducedLagrangian, integrate_group, rk4_group_reference};
use veselov::lie::{CayleyMap, ExpMap, GroupFamily, Retraction};

use super::RigidJob;
use super::schema::LoadedRigid;
use crate::error::CliError;
use crate::pipeline::manifest::prepare_dir;
use crate::scenario::{output_dir, step_count};
use crate::verify::{STATE_ERROR, Study, TIME_STEP, VerifyJob, note_adjusted, study_steps};

impl RigidJob for VerifyJob {
    /// Convergence study against RK4 on the continuous Euler–Poincaré
    /// equations with 16 times the largest step count.
    fn go<G, L, const N: usize>(
        self,
        loaded: &LoadedRigid,
        l: L,
        x0: GroupState<G, N>,
        _conserved: &[(&str, usize)],
        retraction: &str,
    ) -> Result<(), CliError>
    where
        G: GroupFamily<N>,
        ExpMap: Retraction<N, Family = G>,
        CayleyMap: Retraction<N, Family = G>,
        L: SplitReducedLagrangian<G, N> + Clone,
    {
        self.time_step_study(&loaded.path)?;
        let s = &loaded.scenario;
        let t_end = match s.time.t_end {
            Some(t) => t,
            None => x0.t + step_count(&s.time, s.method.dt) as f64 * s.method.dt,
        };
        let span = t_end - x0.t;
        let (steps, dts) = study_steps(&loaded.path, &self.dts, span)?;
        note_adjusted(&self.dts, &dts, self.quiet);
        let n_ref = 16 * steps.iter().copied().max().unwrap_or(1);
        let reference = rk4_group_reference::<G, CayleyMap, L, N>(&l, &x0, t_end, n_ref)
            .map_err(|e| CliError::Setup(format!("reference run failed: {e}")))?;
        let dir = prepare_dir(
            &self
                .out
                .clone()
                .unwrap_or_else(|| output_dir(&loaded.path, &s.output, None).join("verify")),
            self.force,
        )?;
        let study = Study {
            method: format!("lie-group trapezoid, {retraction} retraction"),
            order: 2,
            reference: format!("RK4 on the Euler–Poincaré equations, {n_ref} steps"),
            t_end,
            scale: reference.mu.amax().max(1.0),
            interrupt: self.interrupt.clone(),
            error_label: STATE_ERROR.into(),
            step: TIME_STEP,
            extra: serde_json::Value::Null,
            caveat: None,
        };
        let error = |x: &GroupState<G, N>| {
            let dr = (G::rotation(&x.g) - G::rotation(&reference.g)).amax();
            let dx = (G::translation(&x.g) - G::translation(&reference.g)).amax();
            dr.max(dx).max((x.mu - reference.mu).amax())
        };
        study.run(&dir, &dts, &steps, self.quiet, |n, h| {
            let setup = |e: veselov::Error| CliError::Setup(e.to_string());
            let traj = if retraction == "exp" {
                let mut map = SplitLieIntegrator::<G, ExpMap, L, N>::new(l.clone(), h).map_err(setup)?;
                integrate_group(&mut map, x0, n, n)
            } else {
                let mut map = SplitLieIntegrator::<G, CayleyMap, L, N>::new(l.clone(), h).map_err(setup)?;
                integrate_group(&mut map, x0, n, n)
            };
            Ok(match traj.failure {
                Some(e) => Err(e),
                None => Ok(error(traj.last())),
            })
        })
    }
}
