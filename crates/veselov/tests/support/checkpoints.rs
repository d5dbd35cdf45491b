//! Checks a marcher's checkpoint: the whole checkpoint resumes a march bit
//! for bit, and damaged ones are refused and leave the marcher as it was.

use veselov::run::{Checkpoint, Words};

/// `make` builds the marcher, `step` advances it one level and `bits` reads
/// the state compared; `damage` turns a checkpoint into the damaged ones.
/// A checkpoint saved after 5 levels resumes a fresh marcher, which after 4
/// more levels has the saved one's bits; a marcher 9 levels on refuses each
/// damaged checkpoint and, 3 levels later, has the bits of one never handed
/// them.
pub fn check_checkpoint<M: Checkpoint>(
    make: impl Fn() -> M,
    step: impl Fn(&mut M),
    bits: impl Fn(&M) -> Vec<u64>,
    damage: impl Fn(&[f64]) -> Vec<Vec<f64>>,
) {
    let march = |m: &mut M, levels: usize| (0..levels).for_each(|_| step(m));
    let mut saved_from = make();
    march(&mut saved_from, 5);
    let mut saved = Vec::new();
    saved_from.save(&mut saved);
    let mut resumed = make();
    resumed.restore(&mut Words::new(&saved)).expect("restore");
    march(&mut resumed, 4);
    march(&mut saved_from, 4);
    assert_eq!(bits(&resumed), bits(&saved_from), "a restored march differs");
    let (mut target, mut untouched) = (make(), make());
    march(&mut target, 9);
    march(&mut untouched, 9);
    for damaged in damage(&saved) {
        assert!(
            target.restore(&mut Words::new(&damaged)).is_err(),
            "a damaged checkpoint is accepted"
        );
    }
    march(&mut target, 3);
    march(&mut untouched, 3);
    assert_eq!(
        bits(&target),
        bits(&untouched),
        "a refused checkpoint changed the march"
    );
}
