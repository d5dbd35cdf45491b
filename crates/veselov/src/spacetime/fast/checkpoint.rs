//! Saving and restoring a [`FastMarcher`]: every buffer a level depends on,
//! read back in full before anything is replaced.

use crate::error::Result;
use crate::error::invalid;
use crate::run::{Checkpoint, Words, save_count};
use crate::spacetime::fast::FastMarcher;

/// Everything a level depends on besides the construction data: the stored
/// levels, the extrapolation and potential-derivative caches and the
/// counters, so that a restored marcher continues bit for bit. (The cyclic
/// factorisation depends on the lattice only and is rebuilt by `new`.)
impl<P> Checkpoint for FastMarcher<P> {
    fn save(&self, out: &mut Vec<f64>) {
        for count in [self.level, self.filled, self.a_filled, self.last_iterations] {
            save_count(out, count);
        }
        out.push(f64::from_bits(self.total_iterations));
        out.push(self.energy);
        for v in self.buffers() {
            out.extend_from_slice(v);
        }
    }

    fn restore(&mut self, w: &mut Words<'_>) -> Result<()> {
        // Every word is read before anything is replaced: a damaged
        // checkpoint leaves the marcher as it was.
        let counts = [w.count()?, w.count()?, w.count()?, w.count()?];
        let (total_iterations, energy) = (w.one()?.to_bits(), w.one()?);
        let [_, filled, a_filled, _] = counts;
        if filled > self.levels.len() || a_filled > self.a_hist.len().max(1) {
            return Err(invalid(
                "checkpoint",
                filled,
                "more stored levels than this marcher holds",
            ));
        }
        let mut stored = Vec::with_capacity(self.levels.len() + self.a_hist.len() + 8);
        for v in self.buffers() {
            stored.push(w.take(v.len())?);
        }
        [self.level, self.filled, self.a_filled, self.last_iterations] = counts;
        self.total_iterations = total_iterations;
        self.energy = energy;
        for (v, words) in self.buffers_mut().zip(stored) {
            v.copy_from_slice(words);
        }
        Ok(())
    }
}

impl<P> FastMarcher<P> {
    /// The buffers a checkpoint holds, in its order.
    fn buffers(&self) -> impl Iterator<Item = &Vec<f64>> {
        self.levels.iter().chain(&self.a_hist).chain([
            &self.next,
            &self.prev_a,
            &self.cur_a,
            &self.cur_v,
            &self.cur_d2,
            &self.at,
            &self.base,
            &self.delta,
        ])
    }

    /// [`buffers`](Self::buffers), to be written.
    fn buffers_mut(&mut self) -> impl Iterator<Item = &mut Vec<f64>> {
        self.levels.iter_mut().chain(&mut self.a_hist).chain([
            &mut self.next,
            &mut self.prev_a,
            &mut self.cur_a,
            &mut self.cur_v,
            &mut self.cur_d2,
            &mut self.at,
            &mut self.base,
            &mut self.delta,
        ])
    }
}
