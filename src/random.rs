//! Counter-based randomness (DESIGN §4): a value is a hash of
//! (scene seed, stream, symbol identifier, slot), never the next draw of a
//! shared generator, so it does not depend on evaluation order.

/// What a random number is for; part of its key.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u64)]
pub enum Stream {
    /// Choice among the probability parts of a production.
    Choice = 1,
    /// `!`/`#` in a condition or max age (also keyed by the step).
    Condition = 2,
    /// `!`/`#` in the age and parameter expressions of a right side.
    Parameter = 3,
    /// `!`/`#` in growth functions: fixed for the symbol's life.
    Growth = 4,
    /// `?21`: per L-structure and repetition.
    Repetition = 5,
    /// Sample positions of a pixel, keyed by (frame, pixel).
    Pixel = 6,
}

/// SplitMix64 finaliser: a bijective, well-mixed 64-bit hash step.
#[inline]
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Key of (seed, stream, a, b).
#[inline]
pub fn key(seed: u64, stream: Stream, a: u64, b: u64) -> u64 {
    let mut h = mix(seed ^ 0x9e37_79b9_7f4a_7c15);
    h = mix(h ^ stream as u64);
    h = mix(h ^ a);
    mix(h.wrapping_add(b.wrapping_mul(0x9e37_79b9_7f4a_7c15)))
}

/// Uniform value in [0, 1) for slot `slot` of a key.
#[inline]
pub fn unit(key: u64, slot: u64) -> f64 {
    unit_of(key, slot_hash(slot))
}

/// The part of [`unit`] that depends on the slot alone: a caller drawing
/// the same slots of many keys (a pixel's sample offsets) hashes them
/// once.
#[inline]
pub fn slot_hash(slot: u64) -> u64 {
    mix(slot.wrapping_add(0x632b_e59b_d9b4_e019))
}

/// [`unit`] of a slot given its [`slot_hash`].
#[inline]
pub fn unit_of(key: u64, slot_hash: u64) -> f64 {
    let h = mix(key ^ slot_hash);
    (h >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_and_keyed() {
        let k = key(1, Stream::Choice, 7, 0);
        assert_eq!(unit(k, 3), unit(key(1, Stream::Choice, 7, 0), 3));
        assert_ne!(unit(k, 3), unit(key(2, Stream::Choice, 7, 0), 3));
        let n = 100_000;
        let mean: f64 = (0..n)
            .map(|i| unit(key(9, Stream::Growth, i, 0), 0))
            .sum::<f64>()
            / n as f64;
        assert!((mean - 0.5).abs() < 0.005, "{mean}");
        assert!((0..n).all(|i| (0.0..1.0).contains(&unit(k, i))));
    }
}
