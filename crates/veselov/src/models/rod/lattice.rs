//! The rod's leapfrog lattice (note 003 §3.2, node map (6.2)): material
//! points p = 0 … nodes − 1 at s = p·δ, δ = length / (nodes − 1), on the
//! 2-D CFK lattice with lattice spacings Δs = 2δ and Δt. Vertex (i, j) has
//! level w = i + j (time t = wΔt/2) and material point p = i − j; a level
//! holds every other material point, so each point is advanced by Δt every
//! two levels. The lattice is a periodic [`CfkTorus`] cut to the body by a
//! [`MaterialWindow`] (free ends).

use crate::complex::{CfkTorus, MaterialWindow};
use crate::error::{Error, Result};
use crate::field::fibre::Pose;
use crate::models::positive;

/// The leapfrog lattice of a rod of `nodes` material points.
#[derive(Clone, Debug, PartialEq)]
pub struct RodLattice {
    nodes: usize,
    length: f64,
    dt: f64,
    torus: CfkTorus,
    window: MaterialWindow,
}

impl RodLattice {
    /// A rod of `length` with `nodes` ≥ 3 material points, time step `dt`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `nodes`, `length` or `dt`.
    pub fn new(nodes: usize, length: f64, dt: f64) -> Result<Self> {
        positive("length", length)?;
        positive("dt", dt)?;
        if !(3..=u32::MAX as usize).contains(&nodes) {
            return Err(Error::InvalidParameter {
                name: "nodes".into(),
                value: nodes.to_string(),
                reason: "a rod needs at least 3 material points".into(),
            });
        }
        let last = nodes - 1;
        let torus = CfkTorus::new(2, &[(last.div_ceil(2) + 1).max(3)])?;
        let window = MaterialWindow::new(&torus, last)?;
        Ok(Self {
            nodes,
            length,
            dt,
            torus,
            window,
        })
    }

    /// Number of material points.
    pub fn nodes(&self) -> usize {
        self.nodes
    }
    /// Rod length.
    pub fn length(&self) -> f64 {
        self.length
    }
    /// Distance δ between neighbouring material points.
    pub fn spacing(&self) -> f64 {
        self.length / (self.nodes - 1) as f64
    }
    /// The lattice spacing Δs = 2δ of Prop. 6.5.
    pub fn ds(&self) -> f64 {
        2.0 * self.spacing()
    }
    /// The time step Δt (each material point advances by Δt every two levels).
    pub fn dt(&self) -> f64 {
        self.dt
    }
    /// The periodic lattice the rod lives on.
    pub fn torus(&self) -> &CfkTorus {
        &self.torus
    }
    /// The body's window on it.
    pub fn window(&self) -> MaterialWindow {
        self.window
    }
    /// Time of level w: wΔt/2.
    pub fn time(&self, level: i64) -> f64 {
        level as f64 * 0.5 * self.dt
    }

    /// The material point (node number) of the vertex with in-level index
    /// `index` at `level`, or `None` off the body.
    pub fn node(&self, level: i64, index: usize) -> Option<usize> {
        let v = self.torus.vertex(level, index);
        self.window
            .contains(&v)
            .then(|| self.window.material_point(&v) as usize)
    }

    /// The Cauchy data of the march (levels 0 … 3) sampled from a motion
    /// (s, t) ↦ (r, R), (6.4): y_v = (r, R)(x(v)). Vertices off the body get
    /// the value of the nearest end (never read).
    pub fn cauchy_data(&self, motion: impl Fn(f64, f64) -> Pose<f64>) -> Vec<Vec<Pose<f64>>> {
        (0..4_i64)
            .map(|w| {
                (0..self.torus.level_size())
                    .map(|i| {
                        let p = self.node(w, i).unwrap_or(0);
                        motion(p as f64 * self.spacing(), self.time(w))
                    })
                    .collect()
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_node_appears_once_per_pair_of_levels() {
        for nodes in [3, 4, 11, 12] {
            let l = RodLattice::new(nodes, 2.0, 0.1).expect("valid");
            for w in 5..9 {
                let mut seen: Vec<usize> = (0..l.torus().level_size())
                    .flat_map(|i| [l.node(w, i), l.node(w + 1, i)])
                    .flatten()
                    .collect();
                seen.sort_unstable();
                assert_eq!(seen, (0..nodes).collect::<Vec<_>>(), "nodes {nodes}, level {w}");
            }
        }
        assert!(RodLattice::new(2, 1.0, 0.1).is_err());
        assert!(
            RodLattice::new(5, 1.0, 0.0)
                .expect_err("invalid input")
                .to_string()
                .contains("dt")
        );
    }
}
