//! Sorting the packed edge keys (`(a << 32) | b`) and vertex lists that every sweep
//! builds, by least-significant-digit radix: eight-bit digits, the digits on which all
//! keys agree skipped (with fewer than 2¹⁶ vertices, four of the eight are sorted). The order is
//! that of `sort_unstable` (keys are plain integers: equal keys are indistinguishable),
//! so the remesher's output does not change; it costs a few passes over the keys where
//! a comparison sort costs about log₂ n, and the sweeps sort tens of thousands of keys
//! dozens of times per pass (a fifth of the remesher's instructions went to sorting on a
//! coarse anisotropic input). Hand-written: thirty lines, where no crate of the
//! dependency tree sorts by radix.

/// Below this many keys a comparison sort is as fast.
const SMALL: usize = 256;

/// Sorts `keys` ascending, in place, with `scratch` as the second buffer (its contents
/// are lost; kept by the caller to spare an allocation per call).
pub(super) fn sort_u64(keys: &mut Vec<u64>, scratch: &mut Vec<u64>) {
    let n = keys.len();
    if n < SMALL {
        keys.sort_unstable();
        return;
    }
    // Only the digits on which the keys differ: those where the bits of all keys ORed
    // and ANDed differ.
    let (and, or) = keys.iter().fold((u64::MAX, 0u64), |(a, o), &k| (a & k, o | k));
    // Every slot is written before it is read: no need to clear what is there.
    scratch.resize(n, 0);
    for d in (0..8).filter(|d| ((and ^ or) >> (8 * d)) & 0xff != 0) {
        let mut start = [0usize; 256];
        for &k in keys.iter() {
            start[((k >> (8 * d)) & 0xff) as usize] += 1;
        }
        let mut sum = 0;
        for s in start.iter_mut() {
            let c = *s;
            *s = sum;
            sum += c;
        }
        for &k in keys.iter() {
            let b = ((k >> (8 * d)) & 0xff) as usize;
            scratch[start[b]] = k;
            start[b] += 1;
        }
        std::mem::swap(keys, scratch);
    }
}

/// Sorts `v` ascending (vertex indices), through [`sort_u64`].
pub(super) fn sort_u32(v: &mut [u32]) {
    if v.len() < SMALL {
        v.sort_unstable();
        return;
    }
    let mut keys: Vec<u64> = v.iter().map(|&x| x as u64).collect();
    sort_u64(&mut keys, &mut Vec::new());
    for (x, k) in v.iter_mut().zip(keys) {
        *x = k as u32;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against the standard library's sort, on keys like the remesher's (two vertex
    /// indices packed, many repeats) and on full 64-bit keys, at sizes around the
    /// small-input cut.
    #[test]
    fn sorts_as_sort_unstable() {
        let mut s = 12345u64;
        let mut rnd = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            s >> 1
        };
        let mut scratch = Vec::new();
        for &n in &[0usize, 1, 255, 256, 257, 1000, 40_000] {
            for packed in [true, false] {
                let mut keys: Vec<u64> = (0..n)
                    .map(|_| {
                        let x = rnd();
                        if packed {
                            ((x % 3000) << 32) | ((x >> 20) % 3000)
                        } else {
                            x ^ (x << 7)
                        }
                    })
                    .collect();
                let mut want = keys.clone();
                want.sort_unstable();
                sort_u64(&mut keys, &mut scratch);
                assert_eq!(keys, want, "n = {n}, packed = {packed}");
                let mut small: Vec<u32> = want.iter().map(|&k| k as u32).rev().collect();
                let mut want32 = small.clone();
                want32.sort_unstable();
                sort_u32(&mut small);
                assert_eq!(small, want32, "n = {n}");
            }
        }
    }
}
