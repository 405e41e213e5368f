//! # spine-rng: the workspace's one seeded random generator
//!
//! SplitMix64 (Steele, Lea and Flood 2014, the seeding generator of `java.util.SplittableRandom`):
//! 64 bits of state, a fixed sequence for each seed, written out here so that no dependency
//! upgrade can change a seeded result. `rand`'s `StdRng` is documented as not reproducible across
//! `rand` versions; every seeded algorithm of the workspace (the multi-start of eq. (33), the
//! genetic algorithm of eq. (37), the random fixtures) draws from this generator instead.
//!
//! ```
//! use spine_rng::SplitMix64;
//! let mut rng = SplitMix64::new(1);
//! let u = rng.next_f64();
//! assert!((0.0..1.0).contains(&u));
//! assert_eq!(SplitMix64::new(1).next_u64(), SplitMix64::new(1).next_u64()); // same seed, same draw
//! assert!(rng.below(7) < 7);
//! ```
#![forbid(unsafe_code)]

/// SplitMix64: the same seed gives the same sequence on every machine.
#[derive(Clone, Debug)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)` (53 random bits).
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `[lo, hi)`.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }

    /// Uniform in `0..n` (`n ≥ 1`), without modulo bias (Lemire's multiply-and-reject).
    pub fn below(&mut self, n: usize) -> usize {
        assert!(n > 0, "below(0)");
        let n = n as u64;
        let threshold = n.wrapping_neg() % n;
        loop {
            let m = (self.next_u64() as u128) * (n as u128);
            if (m as u64) >= threshold {
                return (m >> 64) as usize;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::SplitMix64;

    #[test]
    fn the_sequence_is_splitmix64s() {
        // The reference values of SplitMix64 from seed 1234567 (Vigna's splitmix64.c).
        let mut rng = SplitMix64::new(1234567);
        let first: Vec<u64> = (0..3).map(|_| rng.next_u64()).collect();
        assert_eq!(first, [6457827717110365317, 3203168211198807973, 9817491932198370423]);
    }

    #[test]
    fn below_is_within_range_and_covers_it() {
        let mut rng = SplitMix64::new(3);
        let mut seen = [0usize; 5];
        for _ in 0..5000 {
            seen[rng.below(5)] += 1;
        }
        assert!(seen.iter().all(|&c| (800..1200).contains(&c)), "{seen:?}");
    }
}
