//! ZSobol: one Owen-scrambled Sobol' sequence shared by all pixels in Morton
//! order, so that the error is distributed as blue noise across the image
//! (Ahmed & Wonka 2020). See [`ZSobol`].

use super::sobol::sample_unshuffled;
use crate::error::PatternError;
use crate::rng::{mix64, Seed};
use crate::sequence::Sequence;

/// The most index bits a [`ZSobol`] uses: `2·⌈log₂ max(width, height)⌉ +
/// log₂ spp ≤ 32` (Sobol' indices are 32-bit).
pub const ZSOBOL_MAX_INDEX_BITS: u32 = 32;

/// Largest accepted width and height.
const MAX_SIDE: u32 = 1 << 16;

/// Coordinates per sample: every `dim < 2³² − 2` (pairs `0..2³¹ − 1`).
const DIMS: u32 = u32::MAX - 1;

/// Seed purpose of the digit permutations of pair `p` (plus `p`).
const PERMUTE_PURPOSE: u64 = 0x5A53_4F42_0000_0000;
/// Seed purpose of the value scramble of coordinate `d` (plus `d`).
const VALUE_PURPOSE: u64 = 0x5A53_4F42_8000_0000;

/// The 24 permutations of `{0, 1, 2, 3}`, in lexicographic order.
const PERMUTATIONS: [[u8; 4]; 24] = permutations();

const fn permutations() -> [[u8; 4]; 24] {
    let mut out = [[0u8; 4]; 24];
    let mut n = 0;
    let mut a = 0;
    while a < 4 {
        let mut b = 0;
        while b < 4 {
            let mut c = 0;
            while c < 4 {
                if a != b && b != c && a != c {
                    out[n] = [a, b, c, 6 - a - b - c];
                    n += 1;
                }
                c += 1;
            }
            b += 1;
        }
        a += 1;
    }
    out
}

/// `(x, y)` interleaved: bit `k` of `x` at bit `2k`, bit `k` of `y` at
/// `2k + 1` (the Morton or Z-order code).
#[inline]
const fn morton(x: u32, y: u32) -> u64 {
    const fn spread(v: u32) -> u64 {
        let mut v = v as u64 & 0xFFFF_FFFF;
        v = (v | (v << 16)) & 0x0000_FFFF_0000_FFFF;
        v = (v | (v << 8)) & 0x00FF_00FF_00FF_00FF;
        v = (v | (v << 4)) & 0x0F0F_0F0F_0F0F_0F0F;
        v = (v | (v << 2)) & 0x3333_3333_3333_3333;
        (v | (v << 1)) & 0x5555_5555_5555_5555
    }
    spread(x) | (spread(y) << 1)
}

/// Blue-noise error across pixels: the ZSobol sampler of Ahmed & Wonka[^1].
///
/// Every pixel takes its `spp` samples from **one** Owen-scrambled Sobol'
/// `(0, 2)`-sequence: pixel `(x, y)`'s sample `i` is point
///
/// `g = morton(x, y) · spp + i`
///
/// of the sequence, where `morton` interleaves the bits of `x` and `y`
/// (Z-order). An aligned `2ᵏ × 2ᵏ` block of pixels then owns an aligned block
/// of `4ᵏ·spp` consecutive indices, which in dimensions 0 and 1 of the Sobol'
/// sequence is a `(0, m, 2)`-net: the samples of neighbouring pixels are
/// stratified *together*, not only within each pixel, so their errors are
/// negatively correlated and the error image has little power at low
/// frequencies (blue noise), where independent per-pixel seeds give white
/// noise.
///
/// The Z-order itself would show as a regular pattern, so the index is
/// shuffled hierarchically, as Ahmed & Wonka shuffle the quad-tree of pixels:
/// read `g` as base-4 digits from the top (when `log₂ spp` is odd, the lowest
/// digit is a single bit), and replace each digit by its image under one of
/// the 24 permutations of `{0, 1, 2, 3}`, chosen by a hash of the seed, the
/// dimension pair, the digit's position and all digits above it (a lone low
/// bit is flipped or not by such a hash). A permutation that depends only on
/// higher digits maps every aligned block of indices onto an aligned block of
/// the same size, so every net property above survives; a different
/// permutation per dimension pair decorrelates the pairs, which all use
/// Sobol' dimensions 0 and 1 (the `(0, 2)`-sequence).
///
/// Coordinate `dim` of a sample is component `dim mod 2` of pair `⌊dim/2⌋`:
/// Sobol' dimension `dim mod 2` of the shuffled index, Owen-scrambled per
/// coordinate by the hash of Burley[^2] ([`Sobol`](super::Sobol) docs) with a
/// key from [`Seed::stream`]. There is no further index scramble: the digit
/// shuffle is one.
///
/// **Use one seed for the whole image** (not [`pixel_seed`]): the pixel is
/// in the index, and per-pixel seeds would make the pixels independent again,
/// which is exactly what this sampler avoids.
///
/// # Cost
///
/// One `mix64` per base-4 digit of the index (`⌈(2⌈log₂ max(w, h)⌉ + log₂
/// spp)/2⌉ ≤ 16`) per dimension pair, shared by the pair's two coordinates
/// ([`ZSobol::sample_2d`]), plus the Sobol' product and one scramble per
/// coordinate. No tables beyond the Sobol' ones, no allocation, no state:
/// every sample is random access. Measured in `benches/patterns.rs`
/// (`random_access/zsobol`).
///
/// # Limits
///
/// Width and height in `1..=65536`, `spp` a power of two, and the index must
/// fit 32 bits: `2⌈log₂ max(w, h)⌉ + log₂ spp ≤ 32` (e.g. 4096 × 4096 pixels
/// at up to 256 samples per pixel).
///
/// [^1]: A. G. M. Ahmed, P. Wonka, *Screen-space blue-noise diffusion of Monte
///   Carlo sampling error via hierarchical ordering of pixels*, ACM Trans.
///   Graph. 39(6), 2020.
/// [^2]: B. Burley, *Practical Hash-based Owen Scrambling*, JCGT 9(4), 2020.
///
/// [`pixel_seed`]: crate::sequence::pixel_seed
///
/// # Example
///
/// ```
/// use linesample::pattern::ZSobol;
/// use linesample::Seed;
///
/// let z = ZSobol::new(640, 480, 16)?;
/// let seed = Seed::new(7); // one seed for the image
/// let [u, v] = z.sample_2d(10, 20, 3, 0, seed)?; // pixel (10, 20), sample 3, pair 0
/// assert!((0.0..1.0).contains(&u) && (0.0..1.0).contains(&v));
/// assert_eq!(z.sample(10, 20, 3, 1, seed)?, v);
/// # Ok::<(), linesample::PatternError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ZSobol {
    width: u32,
    height: u32,
    log2_side: u32,
    log2_spp: u32,
}

impl ZSobol {
    /// A sampler for a `width × height` image with `spp` samples per pixel.
    ///
    /// # Errors
    /// [`PatternError::Parameter`] (`"width"`, `"height"`) unless in
    /// `1..=65536`; [`PatternError::Parameter`] (`"spp"`) for `spp = 0` or
    /// when the index would need more than [`ZSOBOL_MAX_INDEX_BITS`] bits
    /// (`max` is then the largest `spp` for this image);
    /// [`PatternError::PowerOfTwo`] (`"spp"`) unless `spp` is a power of two.
    pub fn new(width: u32, height: u32, spp: u32) -> Result<Self, PatternError> {
        for (name, v) in [("width", width), ("height", height)] {
            if v == 0 || v > MAX_SIDE {
                return Err(PatternError::Parameter {
                    name,
                    value: u64::from(v),
                    min: 1,
                    max: u64::from(MAX_SIDE),
                });
            }
        }
        let log2_side = width.max(height).next_power_of_two().trailing_zeros();
        let max_spp = 1u64 << (ZSOBOL_MAX_INDEX_BITS - 2 * log2_side);
        if spp == 0 || u64::from(spp) > max_spp {
            return Err(PatternError::Parameter {
                name: "spp",
                value: u64::from(spp),
                min: 1,
                max: max_spp,
            });
        }
        if !spp.is_power_of_two() {
            return Err(PatternError::PowerOfTwo {
                name: "spp",
                value: u64::from(spp),
            });
        }
        Ok(Self {
            width,
            height,
            log2_side,
            log2_spp: spp.trailing_zeros(),
        })
    }

    /// Image width in pixels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Image height in pixels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Samples per pixel.
    #[must_use]
    pub fn spp(&self) -> u32 {
        1 << self.log2_spp
    }

    /// Bits of the sequence index: `2⌈log₂ max(w, h)⌉ + log₂ spp`.
    #[must_use]
    pub fn index_bits(&self) -> u32 {
        2 * self.log2_side + self.log2_spp
    }

    /// The (unshuffled) sequence index of pixel `(x, y)`'s sample `sample`:
    /// `morton(x, y) · spp + sample`.
    ///
    /// # Errors
    /// [`PatternError::Parameter`] (`"x"`, `"y"`) outside the image;
    /// [`PatternError::Range`] if `sample ≥ spp`.
    pub fn index(&self, x: u32, y: u32, sample: u32) -> Result<u32, PatternError> {
        for (name, v, n) in [("x", x, self.width), ("y", y, self.height)] {
            if v >= n {
                return Err(PatternError::Parameter {
                    name,
                    value: u64::from(v),
                    min: 0,
                    max: u64::from(n - 1),
                });
            }
        }
        if sample >= self.spp() {
            return Err(PatternError::Range {
                first: u64::from(sample),
                len: 1,
                n: u64::from(self.spp()),
            });
        }
        // Fits: morton(x, y) < 4^log2_side and the index has ≤ 32 bits.
        Ok(((morton(x, y) << self.log2_spp) | u64::from(sample)) as u32)
    }

    /// The hierarchical digit shuffle of index `g` for dimension pair `pair`
    /// (see the type docs): each base-4 digit, from the top, through the
    /// permutation `hash(seed, pair, position, higher digits) mod 24`.
    #[inline]
    fn shuffled(&self, g: u32, pair: u32, seed: Seed) -> u32 {
        let key = seed.stream(PERMUTE_PURPOSE + u64::from(pair));
        let g64 = u64::from(g);
        let low = self.log2_spp & 1;
        let mut out = 0u32;
        let mut s = self.index_bits();
        while s >= low + 2 {
            s -= 2;
            let digit = (g >> s) & 3;
            let above = g64 >> (s + 2);
            let h = mix64(key ^ (above | (u64::from(s) << 40)));
            // ⌊h_hi · 24 / 2³²⌋: uniform over the 24 permutations up to 2⁻²⁹.
            let p = (((h >> 32) * 24) >> 32) as usize;
            out |= u32::from(PERMUTATIONS[p][digit as usize]) << s;
        }
        if low == 1 {
            let h = mix64(key ^ ((g64 >> 1) | (1u64 << 46)));
            out |= (g & 1) ^ (h >> 63) as u32;
        }
        out
    }

    /// Coordinates `2·pair` and `2·pair + 1` of pixel `(x, y)`'s sample
    /// `sample`: Sobol' dimensions 0 and 1 of the index shuffled for `pair`,
    /// each Owen-scrambled, in `[0, 1 − 2⁻²⁴]`.
    ///
    /// # Errors
    /// As [`ZSobol::index`]; [`PatternError::Dimension`] if `pair ≥ 2³¹ − 1`
    /// (coordinates from `2³² − 2` on).
    pub fn sample_2d(
        &self,
        x: u32,
        y: u32,
        sample: u32,
        pair: u32,
        seed: Seed,
    ) -> Result<[f32; 2], PatternError> {
        let g = self.index(x, y, sample)?;
        self.pair_at(g, pair, seed)
    }

    /// Coordinate `dim` of pixel `(x, y)`'s sample `sample`: component
    /// `dim mod 2` of [`ZSobol::sample_2d`] for pair `⌊dim/2⌋`.
    ///
    /// # Errors
    /// As [`ZSobol::index`]; [`PatternError::Dimension`] for
    /// `dim ≥ 2³² − 2`.
    pub fn sample(
        &self,
        x: u32,
        y: u32,
        sample: u32,
        dim: u32,
        seed: Seed,
    ) -> Result<f32, PatternError> {
        let g = self.index(x, y, sample)?;
        self.coordinate_at(g, dim, seed)
    }

    /// Pixel `(x, y)` as a [`Sequence<2>`] of its `spp` samples.
    ///
    /// # Errors
    /// As [`ZSobol::index`] for the pixel.
    pub fn pixel(&self, x: u32, y: u32) -> Result<ZSobolPixel, PatternError> {
        self.index(x, y, 0)?;
        Ok(ZSobolPixel { z: *self, x, y })
    }

    fn pair_at(&self, g: u32, pair: u32, seed: Seed) -> Result<[f32; 2], PatternError> {
        if pair >= DIMS / 2 {
            return Err(PatternError::Dimension {
                dim: pair.saturating_mul(2),
                max: DIMS,
            });
        }
        let t = self.shuffled(g, pair, seed);
        let d = 2 * u64::from(pair);
        Ok([
            sample_unshuffled(t, 0, seed.stream(VALUE_PURPOSE + d)),
            sample_unshuffled(t, 1, seed.stream(VALUE_PURPOSE + d + 1)),
        ])
    }

    fn coordinate_at(&self, g: u32, dim: u32, seed: Seed) -> Result<f32, PatternError> {
        if dim >= DIMS {
            return Err(PatternError::Dimension { dim, max: DIMS });
        }
        let t = self.shuffled(g, dim / 2, seed);
        let c = (dim % 2) as usize;
        Ok(sample_unshuffled(
            t,
            c,
            seed.stream(VALUE_PURPOSE + u64::from(dim)),
        ))
    }
}

/// The samples of one pixel of a [`ZSobol`] image, as a [`Sequence<2>`]:
/// point `i` is [`ZSobol::sample_2d`] of pair 0, coordinate `dim` is
/// [`ZSobol::sample`]. `count` is `spp`; every `dim < 2³² − 2` exists.
/// The `seed` passed to its methods is the image's seed, the same for every
/// pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ZSobolPixel {
    z: ZSobol,
    x: u32,
    y: u32,
}

impl ZSobolPixel {
    /// The pixel's column and row.
    #[must_use]
    pub fn position(&self) -> (u32, u32) {
        (self.x, self.y)
    }

    fn index(&self, i: u64) -> Result<u32, PatternError> {
        let spp = u64::from(self.z.spp());
        if i >= spp {
            return Err(PatternError::Range {
                first: i,
                len: 1,
                n: spp,
            });
        }
        self.z.index(self.x, self.y, i as u32)
    }
}

impl Sequence<2> for ZSobolPixel {
    fn count(&self) -> u64 {
        u64::from(self.z.spp())
    }
    fn dimensions(&self) -> u32 {
        DIMS
    }
    fn point(&self, index: u64, seed: Seed) -> Result<[f32; 2], PatternError> {
        let g = self.index(index)?;
        self.z.pair_at(g, 0, seed)
    }
    fn sample(&self, index: u64, dim: u32, seed: Seed) -> Result<f32, PatternError> {
        let g = self.index(index)?;
        self.z.coordinate_at(g, dim, seed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    extern crate std;
    use std::vec::Vec;

    #[test]
    fn permutations_are_the_24_distinct_ones() {
        for (i, p) in PERMUTATIONS.iter().enumerate() {
            let mut seen = [false; 4];
            for &v in p {
                seen[v as usize] = true;
            }
            assert!(seen.iter().all(|&s| s), "{p:?}");
            assert!(PERMUTATIONS[..i].iter().all(|q| q != p), "{p:?} repeated");
        }
    }

    #[test]
    fn morton_interleaves() {
        assert_eq!(morton(0, 0), 0);
        assert_eq!(morton(1, 0), 1);
        assert_eq!(morton(0, 1), 2);
        assert_eq!(morton(3, 3), 15);
        assert_eq!(morton(0xFFFF, 0), 0x5555_5555);
        assert_eq!(morton(5, 9), 0b1001_0011);
    }

    #[test]
    fn the_shuffle_is_a_bijection_that_keeps_aligned_blocks() {
        for (w, spp) in [(4u32, 1u32), (4, 2), (8, 4), (2, 8)] {
            let z = ZSobol::new(w, w, spp).unwrap();
            let n = 1u32 << z.index_bits();
            for pair in [0u32, 1, 7] {
                let img: Vec<u32> = (0..n).map(|g| z.shuffled(g, pair, Seed(3))).collect();
                let mut sorted = img.clone();
                sorted.sort_unstable();
                assert_eq!(sorted, (0..n).collect::<Vec<_>>(), "w {w} spp {spp}");
                // Every aligned block of 2^b indices goes to an aligned
                // block, for b at a digit boundary.
                let low = z.log2_spp & 1;
                for b in (0..=z.index_bits()).filter(|b| *b == 0 || (b - low).is_multiple_of(2)) {
                    for start in (0..n).step_by(1 << b) {
                        let hi = img[start as usize] >> b;
                        assert!(
                            (start..start + (1 << b)).all(|g| img[g as usize] >> b == hi),
                            "w {w} spp {spp} block {start}+2^{b}"
                        );
                    }
                }
            }
        }
    }
}
