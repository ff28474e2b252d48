//! Sample placement: a jittered rank-1 lattice for the pixel and AO samples, cosine-weighted
//! hemisphere directions, and a hash for per-primitive random numbers.

use glam::Vec3;

/// The generator `g` of the rank-1 lattice `i ↦ (i / n, (i·g mod n) / n)` used for `n` samples:
/// the integer nearest to `n / φ` (the Fibonacci lattice's choice, which spreads points evenly in
/// 2D) made coprime with `n`, so `i ↦ i·g mod n` is a permutation and both coordinates are
/// stratified (one sample in each of the `n` columns and each of the `n` rows).
pub fn lattice_generator(n: u32) -> u32 {
    if n <= 2 {
        return 1;
    }
    let golden = 0.618_034_f64;
    let mut g = ((f64::from(n) * golden).round() as u32).clamp(1, n - 1);
    while gcd(g, n) != 1 {
        g += 1;
    }
    g
}

fn gcd(mut a: u32, mut b: u32) -> u32 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// Point `i` of `n` of the jittered lattice with generator `g`: column `i`, row `i·g mod n`,
/// each moved by a jitter `(j0, j1)` in `[0, 1)²` inside its cell.
pub fn lattice_point(i: u32, n: u32, g: u32, j0: f32, j1: f32) -> (f32, f32) {
    let row = (u64::from(i) * u64::from(g) % u64::from(n)) as f32;
    let inv = 1.0 / n as f32;
    (
        ((i as f32 + j0) * inv).min(1.0 - f32::EPSILON),
        ((row + j1) * inv).min(1.0 - f32::EPSILON),
    )
}

/// A cosine-weighted direction in the hemisphere around the unit normal `n`, from `(u0, u1)` in
/// `[0, 1)²` (Malley's method: a uniform disk point lifted to the hemisphere). The density is
/// `cos θ / π`, so the mean visibility of such directions is the ambient occlusion.
pub fn cosine_hemisphere(n: Vec3, u0: f32, u1: f32) -> Vec3 {
    let r = u0.sqrt();
    let phi = std::f32::consts::TAU * u1;
    let (s, c) = phi.sin_cos();
    let z = (1.0 - u0).max(0.0).sqrt();
    let (t, b) = n.any_orthonormal_pair();
    (t * (r * c) + b * (r * s) + n * z).normalize()
}

/// A well-mixed 64-bit hash (SplitMix64's finalizer) of `key` and `index`.
pub fn hash2(key: u64, index: u64) -> u64 {
    let mut z = key ^ index.wrapping_mul(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// `hash2` as a uniform number in `[0, 1)`.
pub fn hash_unit(key: u64, index: u64) -> f32 {
    (hash2(key, index) >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
}

/// The GPU's per-strand random number (`strand_random` in `ppll_build.wgsl`: a PCG-style hash
/// of `strand · 2 + salt`, top 24 bits over 2^24), which stands in for Scheuermann's shift and
/// noise textures. Mirrored bit for bit so both shade a strand alike.
pub fn strand_random(strand: u32, salt: u32) -> f32 {
    let x = strand.wrapping_mul(2).wrapping_add(salt);
    let mut h = x.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    h = ((h >> ((h >> 28) + 4)) ^ h).wrapping_mul(277_803_737);
    h = (h >> 22) ^ h;
    (h >> 8) as f32 / 16_777_216.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_is_stratified_in_both_axes() {
        for n in [1u32, 2, 3, 4, 16, 60, 64, 100, 257] {
            let g = lattice_generator(n);
            assert_eq!(gcd(g, n), 1);
            let mut cols = vec![0; n as usize];
            let mut rows = vec![0; n as usize];
            for i in 0..n {
                let (x, y) = lattice_point(i, n, g, 0.5, 0.5);
                cols[(x * n as f32) as usize] += 1;
                rows[(y * n as f32) as usize] += 1;
            }
            assert!(
                cols.iter().all(|&c| c == 1) && rows.iter().all(|&c| c == 1),
                "n {n}"
            );
        }
    }

    #[test]
    fn cosine_hemisphere_has_mean_cosine_two_thirds() {
        // E[cos θ] under the density cos θ / π is 2/3; every direction is above the surface.
        let n = Vec3::new(0.3, -0.5, 0.8).normalize();
        let k = 200u32;
        let mut sum = 0.0;
        for i in 0..k {
            for j in 0..k {
                let d =
                    cosine_hemisphere(n, (i as f32 + 0.5) / k as f32, (j as f32 + 0.5) / k as f32);
                assert!((d.length() - 1.0).abs() < 1e-5);
                let c = d.dot(n);
                assert!(c >= 0.0);
                sum += c;
            }
        }
        let mean = sum / (k * k) as f32;
        assert!((mean - 2.0 / 3.0).abs() < 1e-3, "{mean}");
    }

    #[test]
    fn strand_random_matches_the_wgsl_hash() {
        // hash_u32(0) with x = 0: h = 2891336453; shift = (h >> 28) + 4 = 14;
        // ((h >> 14) ^ h) * 277803737, then (h >> 22) ^ h — computed in u64 by hand here.
        let x: u64 = 2_891_336_453;
        let h = (((x >> ((x >> 28) + 4)) ^ x) * 277_803_737) & 0xffff_ffff;
        let h = (h >> 22) ^ h;
        assert_eq!(strand_random(0, 0), (h >> 8) as f32 / 16_777_216.0);
        for s in 0..1000 {
            let r = strand_random(s, 1);
            assert!((0.0..1.0).contains(&r));
        }
        assert_ne!(strand_random(1, 0), strand_random(1, 1));
    }
}
