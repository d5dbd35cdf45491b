//! Saving and restoring what a stepper carries from step to step.
//!
//! A checkpoint is a flat list of `f64` words, written and read back bit for
//! bit by the caller (the library does no input or output). What goes in is
//! each stepper's business: the state itself for steppers that own it, and
//! whatever the next step depends on besides the state (predictors, Kahan
//! compensation terms, the carried spatial momentum).

use crate::error::{Error, Result};

/// Something whose step-to-step memory can be saved and restored exactly.
pub trait Checkpoint {
    /// Append the words that describe the carried data.
    fn save(&self, out: &mut Vec<f64>);
    /// Restore from words written by [`Checkpoint::save`] of the same kind of object.
    ///
    /// Words that do not fit leave the lattice marchers
    /// ([`FastMarcher`](crate::spacetime::FastMarcher),
    /// [`GenericMarcher`](crate::spacetime::GenericMarcher),
    /// [`CauchyMarcher`](crate::field::cauchy::CauchyMarcher)) and seed
    /// 000's [`Evolution000`](crate::evolution::marcher::Evolution000) as they
    /// were: they read every word before replacing anything. Other
    /// implementations (states, steppers' carries,
    /// observers) may be left partly restored by an error: restore into a
    /// fresh object, or discard it on error, as the command line's resume
    /// does.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] (`checkpoint`) if the words run out or do not fit.
    fn restore(&mut self, words: &mut Words<'_>) -> Result<()>;
}

/// A reader over checkpoint words.
#[derive(Debug, Clone)]
pub struct Words<'a> {
    data: &'a [f64],
    at: usize,
}

impl<'a> Words<'a> {
    /// Read from `data`.
    pub fn new(data: &'a [f64]) -> Self {
        Self { data, at: 0 }
    }

    /// The next `n` words.
    ///
    /// # Errors
    /// If fewer than `n` words are left.
    pub fn take(&mut self, n: usize) -> Result<&'a [f64]> {
        let end = self
            .at
            .checked_add(n)
            .filter(|&e| e <= self.data.len())
            .ok_or_else(|| Error::InvalidParameter {
                name: "checkpoint".into(),
                value: format!("{} words", self.data.len()),
                reason: format!("truncated: {n} more words needed at word {}", self.at),
            })?;
        let out = &self.data[self.at..end];
        self.at = end;
        Ok(out)
    }

    /// Consume the next word if it is exactly `tag` (a marker of an optional
    /// section that checkpoints of earlier versions lack).
    pub fn take_tag(&mut self, tag: f64) -> bool {
        let found = self.data.get(self.at) == Some(&tag);
        if found {
            self.at += 1;
        }
        found
    }

    /// The next word.
    ///
    /// # Errors
    /// If no word is left.
    pub fn one(&mut self) -> Result<f64> {
        Ok(self.take(1)?[0])
    }

    /// The next word read as a flag (`0` or `1`).
    ///
    /// # Errors
    /// If no word is left or it is neither 0 nor 1.
    pub fn flag(&mut self) -> Result<bool> {
        let x = self.one()?;
        if x == 0.0 {
            Ok(false)
        } else if x == 1.0 {
            Ok(true)
        } else {
            Err(Error::InvalidParameter {
                name: "checkpoint".into(),
                value: x.to_string(),
                reason: "expected a flag (0 or 1)".into(),
            })
        }
    }

    /// Fill `target` with the next `target.len()` words.
    ///
    /// # Errors
    /// If fewer words are left.
    pub fn fill(&mut self, target: &mut [f64]) -> Result<()> {
        target.copy_from_slice(self.take(target.len())?);
        Ok(())
    }

    /// The next word read as a count (its bits, as written by [`save_count`]).
    ///
    /// # Errors
    /// If no word is left or the count does not fit in `usize`.
    pub fn count(&mut self) -> Result<usize> {
        let bits = self.one()?.to_bits();
        usize::try_from(bits).map_err(|_| Error::InvalidParameter {
            name: "checkpoint".into(),
            value: bits.to_string(),
            reason: "a count too large for this machine".into(),
        })
    }

    /// Error unless every word was read.
    ///
    /// # Errors
    /// If words are left over.
    pub fn end(&self) -> Result<()> {
        if self.at == self.data.len() {
            Ok(())
        } else {
            Err(Error::InvalidParameter {
                name: "checkpoint".into(),
                value: format!("{} words", self.data.len()),
                reason: format!(
                    "{} words left over: written by another kind of run",
                    self.data.len() - self.at
                ),
            })
        }
    }
}

/// Save a count exactly (as the bits of one word), read back by [`Words::count`].
pub fn save_count(out: &mut Vec<f64>, n: usize) {
    out.push(f64::from_bits(n as u64));
}

/// Save an optional fixed-length record: a flag word, then the record (or zeros).
pub(crate) fn save_option(out: &mut Vec<f64>, record: Option<&[f64]>, len: usize) {
    match record {
        Some(r) => {
            out.push(1.0);
            out.extend_from_slice(r);
        }
        None => {
            out.push(0.0);
            out.extend(std::iter::repeat_n(0.0, len));
        }
    }
}

/// Read a record written by [`save_option`].
pub(crate) fn restore_option<'a>(words: &mut Words<'a>, len: usize) -> Result<Option<&'a [f64]>> {
    let present = words.flag()?;
    let record = words.take(len)?;
    Ok(present.then_some(record))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_round_trip_and_refuse_truncation() {
        let mut out = Vec::new();
        save_option(&mut out, Some(&[1.5, -0.0]), 2);
        save_option(&mut out, None, 2);
        let mut w = Words::new(&out);
        assert_eq!(restore_option(&mut w, 2).expect("first"), Some(&[1.5, -0.0][..]));
        assert_eq!(restore_option(&mut w, 2).expect("second"), None);
        assert!(w.end().is_ok());
        assert!(Words::new(&out[..4]).take(5).is_err());
        assert!(Words::new(&[2.0]).flag().is_err());
    }
}
