//! A seeded random generator of our own, so that seeded runs are the same everywhere: the
//! workspace's one generator, [`spine_rng::SplitMix64`].

pub use spine_rng::SplitMix64;
