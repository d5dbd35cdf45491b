//! Checkpoints of a march.

use super::CauchyMarcher;
use crate::field::cell::DiscreteLagrangian;
use crate::field::fibre::{Fibre, read_points};
use crate::run::{Checkpoint, Words};
use crate::solve::SmallLu;
use crate::{Error, Result};

/// Marks the section of kept Jacobian factors.
const KEPT_FACTORS_TAG: f64 = -17.0;

/// A checkpoint of a march: the level and the 2n known levels above the
/// cut, each value by its coordinates ([`Fibre::write`], read back exactly
/// by [`Fibre::read`]); the cell gradients are recomputed from them by the
/// same operations as during the march (a model's own vertex solve that
/// writes them, [`DiscreteLagrangian::solve_last_vertex`], must compute them
/// from the stored values too); then, when the marcher's own vertex solves
/// kept any, the factors of their Newton Jacobians, on which the next
/// levels' iterations depend (a section that checkpoints of earlier
/// versions lack: restored from one of those, the march starts with fresh
/// Jacobians and continues to round-off, not bit for bit). So the restored
/// march continues bit for bit. Dirichlet data are part of the set-up, not
/// of the checkpoint.
impl<F, L, const M: usize> Checkpoint for CauchyMarcher<F, L, M>
where
    F: Fibre<M>,
    F::Point<f64>: Send + Sync,
    L: DiscreteLagrangian<F, M>,
{
    fn save(&self, out: &mut Vec<f64>) {
        let n = self.torus.dimension() as i64;
        out.push(self.level as f64);
        let mut c = [0.0; 16];
        let k = F::COORDINATES.min(c.len());
        for w in self.level - n..self.level + n {
            if let Some(level) = self.level_values(w) {
                for y in level {
                    F::write(y, &mut c[..k]);
                    out.extend_from_slice(&c[..k]);
                }
            }
        }
        if self.kept.iter().any(|slot| !slot.is_empty()) {
            // Per slot (level modulo n) and vertex, tag 2: factors follow;
            // tag 3: none.
            out.push(KEPT_FACTORS_TAG);
            let size = self.torus.level_size();
            for slot in &self.kept {
                for i in 0..size {
                    SmallLu::save_kept(&slot.get(i).copied().flatten(), out);
                }
            }
        }
    }

    fn restore(&mut self, words: &mut Words<'_>) -> Result<()> {
        let level = words.one()?;
        if !(level.is_finite() && level.fract() == 0.0 && level.abs() < 2f64.powi(52)) {
            return Err(Error::InvalidParameter {
                name: "checkpoint".into(),
                value: level.to_string(),
                reason: "not a level number".into(),
            });
        }
        // Everything is read before anything is replaced: a damaged
        // checkpoint leaves the marcher as it was.
        let level = level as i64;
        let n = self.torus.dimension() as i64;
        let size = self.torus.level_size();
        let levels = read_points::<F, M>(words, 2 * n as usize * size, |i| {
            format!("vertex {} of stored level {}", i % size, i / size)
        })?;
        let mut kept = Vec::new();
        if words.take_tag(KEPT_FACTORS_TAG) {
            for _ in 0..n as usize * size {
                kept.push(SmallLu::restore_kept(words)?);
            }
        }
        self.level = level;
        self.start_level = level;
        self.forces_level = None;
        for (l, values) in levels.chunks_exact(size).enumerate() {
            let slot = self.value_slot(level - n + l as i64);
            self.values[slot * size..(slot + 1) * size].copy_from_slice(values);
        }
        for (s, slot) in self.kept.iter_mut().enumerate() {
            slot.clear();
            slot.extend_from_slice(kept.get(s * size..(s + 1) * size).unwrap_or_default());
        }
        self.fill_gradients();
        Ok(())
    }
}
