//! What the tests and benchmarks of both smartmesh crates share: small seedable generators
//! whose sequences never change, so that a random case found once is the same case on every
//! machine and in every later run; the structured meshes built on them ([`grid`]); the
//! command-line helpers ([`cli`]); the public fixtures, round trips and interop programs of
//! the format tests ([`formats`]); the set-ups and measures of the tests in space ([`space`]);
//! the skips that say so in every run ([`skip`]).
//!
//! Hand-written rather than `rand`: the tests pin exact sequences (a failing case is
//! reported by its seed), and a dependency's generator may change its stream between
//! versions. The CLI helpers take the binary as an argument: only the integration tests of
//! the `smartmesh` package can name it. This crate depends on `smartmesh-formats` alone
//! (never on `smartmesh`, whose unit tests use it).
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod cli;
pub mod formats;
pub mod grid;
pub mod measure;
pub mod skip;
pub mod space;

/// What a seedable test generator offers; each generator gives [`Generator::next_u64`].
pub trait Generator {
    /// The next 64 random bits.
    fn next_u64(&mut self) -> u64;

    /// Uniform in [0, 1), from the 53 high bits.
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi).
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform in `0..n` (`0` when `n` is 0), by the remainder.
    fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n.max(1) as u64) as usize
    }

    /// A fair coin: whether the lowest bit is 0.
    fn bit(&mut self) -> bool {
        self.next_u64() & 1 == 0
    }

    /// Uniform in `lo..=hi`, by the remainder.
    fn int(&mut self, lo: usize, hi: usize) -> usize {
        lo + (self.next_u64() % (hi - lo + 1) as u64) as usize
    }
}

/// splitmix64 (Steele, Lea and Flood 2014): any seed, zero included, gives a full stream.
#[derive(Debug, Clone)]
pub struct SplitMix64(pub u64);

impl Generator for SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
}

/// xorshift64* (Vigna 2016). The seed must not be 0: the stream would stay 0.
#[derive(Debug, Clone)]
pub struct XorShift64Star(pub u64);

impl Generator for XorShift64Star {
    fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first outputs of splitmix64 from seed 0 (the reference implementation's) and of
    /// xorshift64* from seed 1 (worked by hand: the state becomes 2^25 + 1 before the
    /// multiplication): the streams the tests' seeds were chosen against.
    #[test]
    fn streams_are_the_reference_ones() {
        let mut s = SplitMix64(0);
        assert_eq!(s.next_u64(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(s.next_u64(), 0x6E78_9E6A_A1B9_65F4);
        let mut x = XorShift64Star(1);
        assert_eq!(x.next_u64(), 0x47E4_CE4B_896C_DD1D);
    }

    #[test]
    fn unit_is_in_the_half_open_interval() {
        let mut s = SplitMix64(7);
        for _ in 0..10_000 {
            let u = s.unit();
            assert!((0.0..1.0).contains(&u));
        }
        assert_eq!(XorShift64Star(3).below(0), 0);
    }
}
