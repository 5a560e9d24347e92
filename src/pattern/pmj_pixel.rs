//! PMJ02 and PMJ02BN by pixel: precomputed tables of [`Pmj02`] realisations
//! ([`Pmj02Tables`]) and, per pixel, a random-access [`Sequence<2>`] over
//! them ([`Pmj02Pixel`]). The construction and its cost are documented on
//! [`Pmj02Tables`].

use super::sobol::{owen_rev, OwenKey};
use super::Pmj02;
use crate::error::PatternError;
use crate::hash::permute;
use crate::rng::{mix64, purpose_mix, Seed, GOLDEN_64};
use crate::sequence::Sequence;

/// Largest `sets` of a [`Pmj02Tables`]: `2¹⁶`.
pub const PMJ02_TABLES_MAX_SETS: u32 = 1 << 16;

/// Number of the isometries of the torus that [`Pmj02Tables`] applies to a
/// PMJ02BN set: the 8 symmetries of the square times the 4 half-period
/// translations, `32`.
pub const PMJ02BN_TRANSFORMS: u32 = 32;

/// Seed purpose of the table sets (`"PMJTAB"`), plus the set number.
const TABLE_PURPOSE: u64 = 0x504D_4A54_4142_0000;
/// Seed purpose of the per-pixel keys (`"PMJPIX"`).
const PIXEL_PURPOSE: u64 = 0x504D_4A50_4958_0000;
/// `purpose_mix(PIXEL_PURPOSE)`, so that a key costs one `mix64` of the seed.
const PIXEL_PREMIX: u64 = purpose_mix(PIXEL_PURPOSE);
/// Separates the pixel hash from other uses of `mix64` of `(x, y)`.
const PIXEL_SALT: u64 = 0x7069_786C_2D70_6D6A;
/// Salts of the value scrambles of the two coordinates of a pair.
const VALUE_SALT: [u64; 2] = [0x9A3C_5E71_0B2D_4F68, 0x1E5B_7D93_A4C6_E802];
/// Salt of the index permutations.
const PERM_SALT: u64 = 0x5F83_D1A9_6B4E_2C07;

/// Bits of a coordinate.
const BITS: u32 = 24;
/// `2²⁴ − 1`: all digits of a coordinate (the reflection `X ↦ 2²⁴ − 1 − X`).
const ONES: u32 = (1 << BITS) - 1;
/// The top digit of a coordinate (the translation by `1/2`).
const TOP: u32 = 1 << (BITS - 1);
/// Scale from a 24-bit integer to `[0, 1)`.
const TO_UNIT: f32 = 1.0 / 16_777_216.0;
/// Dimensions of the plain variant: every pair `0 … 2³¹ − 2`, complete.
const ALL_DIMS: u32 = u32::MAX - 1;

/// `sets` independent realisations of a [`Pmj02`] sequence (plain PMJ02 or
/// PMJ02BN), `N` points each, stored as 24-bit integer coordinates
/// (`[X, Y]` with `x = X·2⁻²⁴`), and random access per pixel into them:
/// [`Pmj02Tables::pixel`] gives pixel `(x, y)` as a [`Sequence<2>`]
/// ([`Pmj02Pixel`]) whose point `i` in dimensions `2p, 2p + 1` is a table
/// point, moved by a transform chosen by a hash of the seed, the pixel and the
/// pair `p`. PMJ02 generation is sequential (Christensen, Kensler & Kilpatrick
/// 2018[^1]; Pharr 2019[^2]), so a renderer that wants sample `i` of pixel
/// `(x, y)` in `O(1)` reads tables generated once, as pbrt-v4's
/// `PMJ02BNSampler` does with its precomputed PMJ02BN tables[^3]. `N` is a
/// power of two; `table[s·N + i]` is point `i` of set `s`.
///
/// # The per-pixel sequence
///
/// With `h` a hash of `(seed, x, y)` and `h_p` one of `(seed, x, y, p)`
/// (MurmurHash3 finalisers, [`mix64`], with this module's purposes), pair
/// `p` of the pixel reads
///
/// * **the set** `s = (s₀(h) + p) mod sets`, `s₀` uniform in `0 … sets − 1`:
///   the pairs of one pixel use distinct sets (the first `sets` pairs);
/// * **the index** `j = σ_p(i)`: for `p = 0` the table order itself, `j = i`;
///   for `p ≥ 1` a keyed random permutation of each batch
///   `[2ᵇ, 2ᵇ⁺¹)` (`i = 2ᵇ + l` goes to `2ᵇ + π(l)`, with `π` the permutation
///   of `[0, 2ᵇ)` of [`crate::hash::permute`] keyed by `(h_p, b)`; `0` and
///   `1` stay). A batch maps to itself, so **every power-of-two prefix
///   `0 … 2ᵏ − 1` of every pair is, as a set, the table's prefix**, moved by
///   the transform below;
/// * **the transform** `T_p`, applied to table point `j` of set `s`:
///   * plain PMJ02: an Owen (nested uniform) scramble of each coordinate,
///     keyed by `(h_p, coordinate)`: the hash-based scramble of Laine & Karras
///     and Burley[^4][^5] on the bit-reversed 24-digit word, as
///     [`super::Sobol`] scrambles its values: `T(X) =
///     reverse(owen(reverse(X·2⁸))) / 2⁸`, where `owen` changes bit `k` only
///     as a function of the bits below it, so digit `k` of `T(X)` is digit
///     `k` of `X` flipped by a function of the digits above it (Owen
///     1995[^6]);
///   * PMJ02BN: one of [`PMJ02BN_TRANSFORMS`] = 32 isometries of the torus,
///     `t = h_p mod 32` (its top five bits): optionally swap `X` and `Y`,
///     then XOR each coordinate with one of `0`, `2²³` (translation by
///     `1/2`), `2²⁴ − 1` (the reflection `X ↦ 2²⁴ − 1 − X`) or
///     `2²⁴ − 1 − 2²³` (both).
///
/// Coordinate `d` of point `i` is component `d mod 2` of pair `⌊d/2⌋`;
/// [`Sequence::point`] is pair 0. [`Sequence::sample`] and
/// [`Pmj02Pixel::sample_2d`] compute the same bits.
///
/// # Why each piece is needed
///
/// **Nets.** A nested scramble maps every elementary interval
/// `2⁻ᵃ × 2⁻⁽ᵏ⁻ᵃ⁾` onto an elementary interval of the same shape (the top
/// `a` digits of `T(X)` are a bijection of the top `a` digits of `X`), and
/// so do the 32 isometries (swapping exchanges the shapes `a` and `k − a`;
/// XOR with a constant is a digit-wise bijection). The permutation keeps each
/// batch. So every power-of-two prefix of every pair is a `(0, k, 2)`-net,
/// exactly as `f32` values, for both variants (`tests/pmj_pixel.rs`).
///
/// **Laws.** The law of a PMJ02 sequence is invariant under Owen scrambling
/// ([`Pmj02`] docs), so for a fixed key `T_p(P) ~ P` over the table seed:
/// pair 0 of every pixel has *exactly* the law of a fresh PMJ02 sequence,
/// and every power-of-two prefix of every pair that of a fresh PMJ02
/// prefix. With fixed (cached) tables, the scramble is the randomisation: a
/// nested uniform scramble of any fixed point is uniform, so estimates are
/// unbiased over seeds, and two pixels with independent ideal scrambles of
/// one set have exactly uncorrelated estimates (given the table, their
/// points are independent, each uniform). The hash-based scramble is a
/// `2⁶⁴`-key family, not the ideal one; the tests measure the marginals and
/// the correlations. PMJ02BN's law is not scramble-invariant (a scramble
/// moves points by up to a cell and would undo the blue noise), hence the
/// isometries, which keep every toroidal distance exactly (so every
/// nearest-neighbour distance and the spectrum of every power-of-two prefix)
/// and every dyadic interval. They are all of them: an isometry of the torus
/// is a symmetry of the square and a translation, and only translations by
/// `0` or `1/2` per axis keep the halves `[0, ½)`, `[½, 1)`.
///
/// **Distinct sets per pixel.** Two pairs of one pixel that read one set in
/// one order would be functions of the same points: for PMJ02BN, `(u₀, u₂)`
/// would be `(X, X ⊕ m)`, a deterministic relation and a *biased* estimate
/// of any integrand that couples the two pairs; for PMJ02, independent
/// scrambles flip the top digit of every `u₀` by one coin and of every `u₂`
/// by another, so `1[u₀ < ½]·1[u₂ < ½]` averages to `½` or `0`, never to
/// `¼`: its variance does not decrease with `N`. Hence `s₀ + p`.
///
/// **The batch permutation.** Distinct independent sets in table order are
/// not enough: the PMJ02 construction copies digits from point `i` to point
/// `N + i` (the new point lies in the same `2⁻ᵐ` cell), so the top `x` digit
/// of point `i` depends only on `i mod 4`, with the same pattern in every set
/// up to two coins. Index-aligned sets then give the same failure. Over
/// pairs of independent sets (`examples/pmj_pair_order.rs`), `N·Var` of the
/// estimate of `12(u₀ − ½)(u₂ − ½)` is 73 at `N = 256` and 292 at
/// `N = 1024`, growing with `N`, against 1 for independent uniform points;
/// of `1[u₀ < ½]·1[u₂ < ½]`, 8.0 and 32 against 0.19. Permuting each batch
/// of pair `p ≥ 1` pairs the points of two pairs at random, as Latin
/// hypercube sampling does: 1.04 and 1.08, 0.065 and 0.066 (an ideal nested
/// index scramble instead: 1.6 and 0.12, since it keeps aligned blocks).
/// [`crate::hash::permute`] has the pair law of an ideal Feistel network,
/// which is what a variance sees. The price: the prefixes that are not
/// powers of two of pairs `p ≥ 1` are other subsets of their batch than the
/// table's (still between the nets of `2^⌊log₂ n⌋` and `2^⌈log₂ n⌉` points);
/// pair 0 keeps the table order, so it (typically the position in the
/// pixel) stays progressive at every count.
///
/// # Variants and collisions
///
/// Plain PMJ02: every `(pixel, pair, coordinate)` has its own 64-bit scramble
/// key; two of them collide with probability about `2⁻⁶⁴`, and [`Sequence::dimensions`]
/// is `2³² − 2` (every pair; pairs `p` and `p + sets` share a set, with
/// independent scrambles and permutations).
///
/// PMJ02BN: a pair's point set (any power-of-two prefix) is one of
/// `32·sets` variants. The pairs `p < sets` of one pixel use distinct sets,
/// so no two coincide, and [`Sequence::dimensions`] is `2·sets`: there is no
/// further pair that would not repeat a set. Two different pixels' pairs
/// `p`, `q` (any `p`, `q`) read the same set with probability `1/sets` and
/// the same transform with probability `1/32`, independently: they have the
/// same point set, and so perfectly correlated errors on that pair, with
/// probability `1/(32·sets)` (`1/512` for 16 sets: about 8 100 of the
/// 4.1 million pairs of 4-neighbours in a 1920 × 1080 image, per pair). The
/// randomness of PMJ02BN is the tables': over seeds, a fixed table gives only
/// these variants, so for independent realisations generate new tables
/// (another table seed).
///
/// # Cost
///
/// Memory: `sets × N × 8` bytes (16 sets of 1024 points: 128 KiB; pbrt-v4's
/// size, 5 sets of 65536 points, 2.5 MiB). Generation: `sets` runs of
/// [`Pmj02::generate`], `O(N log N)` each, allocation-free with
/// [`Pmj02Tables::scratch_len`] words of scratch. Access: per coordinate
/// two (PMJ02BN, pair 0) to four (PMJ02, pairs `p ≥ 1`) [`mix64`] hashes,
/// for pairs `p ≥ 1` one [`crate::hash::permute`] (a key expansion and six
/// or eight Feistel rounds; an exact shuffle for batches of at most 16
/// points), for PMJ02 one scramble, and one table load: `O(1)`, no
/// allocation, no state. Measured with `benches/pmj.rs`, groups
/// `pmj_tables` and `pmj_pixel` (`cargo bench --bench pmj -- --warm-up-time 1
/// --measurement-time 3 --noplot 'pmj_(tables|pixel)'`), on the development
/// machine (two cores, quiet, one run; runs with the machine shared were up
/// to 30 % slower):
///
/// | | PMJ02 | PMJ02BN |
/// |---|---|---|
/// | generate 16 sets × 1024 points | 1.10 ms | 8.56 ms |
/// | one coordinate, pair 0 (dimensions 0, 1) | 30 ns | 14 ns |
/// | one coordinate, pairs 1–3 (dimensions 2–7) | 53 ns | 35 ns |
///
/// For reference, [`super::ZSobol::sample`] on the same loop (64 × 64
/// pixels, 16 samples, dimensions 2–7) takes 69 ns per coordinate.
///
/// [^1]: P. Christensen, A. Kensler, C. Kilpatrick, *Progressive Multi-Jittered
///   Sample Sequences*, Computer Graphics Forum 37(4) (EGSR), 2018.
/// [^2]: M. Pharr, *Efficient Generation of Points that Satisfy Two-Dimensional
///   Elementary Intervals*, JCGT 8(1), 2019.
/// [^3]: M. Pharr, W. Jakob, G. Humphreys, pbrt-v4 (the renderer of *Physically
///   Based Rendering*, 4th ed., 2023), `src/pbrt/util/pmj02tables.h`: 5
///   precomputed PMJ02BN sets of 65536 points, read by `PMJ02BNSampler`.
/// [^4]: S. Laine, T. Karras, *Stratified sampling for stochastic
///   transparency*, Computer Graphics Forum 30(4), 2011.
/// [^5]: B. Burley, *Practical Hash-based Owen Scrambling*, JCGT 9(4), 2020.
/// [^6]: A. B. Owen, *Randomly permuted (t,m,s)-nets and (t,s)-sequences*,
///   Monte Carlo and Quasi-Monte Carlo Methods in Scientific Computing, 1995.
///
/// # Example
///
/// ```
/// use linesample::pattern::{Pmj02, Pmj02Tables};
/// use linesample::sequence::Sequence;
/// use linesample::Seed;
///
/// let pmj = Pmj02::blue_noise(256)?;
/// let sets = 4;
/// let mut table = vec![[0u32; 2]; Pmj02Tables::table_len(pmj, sets)?];
/// let mut scratch = vec![0u32; Pmj02Tables::scratch_len(pmj)];
/// let tables = Pmj02Tables::generate(pmj, sets, Seed::new(1), &mut table, &mut scratch)?;
///
/// let px = tables.pixel(10, 20);
/// let seed = Seed::new(7); // one seed for the image
/// let [u, v] = px.point(3, seed)?; // sample 3, dimensions 0 and 1
/// assert_eq!(px.sample(3, 1, seed)?, v);
/// assert_eq!(px.sample_2d(3, 1, seed)?[0], px.sample(3, 2, seed)?); // pair 1
/// assert_eq!(px.dimensions(), 2 * sets); // PMJ02BN: one set per pair
/// # let _ = u;
/// # Ok::<(), linesample::PatternError>(())
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Pmj02Tables<T> {
    table: T,
    points: u32,
    sets: u32,
    blue_noise: bool,
}

/// `Ok(N)` if `n` is a power of two (it is `≤ 2²⁴`, from [`Pmj02`]).
fn check_points(n: usize) -> Result<u32, PatternError> {
    if !n.is_power_of_two() {
        return Err(PatternError::PowerOfTwo {
            name: "n",
            value: n as u64,
        });
    }
    // Pmj02 has n ≤ 2^24.
    Ok(n as u32)
}

/// `sets · n` if `sets` is in range and the product fits `usize`.
fn checked_len(n: u32, sets: u32) -> Result<usize, PatternError> {
    let fit = u64::try_from(usize::MAX).unwrap_or(u64::MAX) / u64::from(n);
    let max = u64::from(PMJ02_TABLES_MAX_SETS).min(fit);
    if sets == 0 || u64::from(sets) > max {
        return Err(PatternError::Parameter {
            name: "sets",
            value: u64::from(sets),
            min: 1,
            max,
        });
    }
    Ok(sets as usize * n as usize)
}

/// Dimensions of a pixel's sequence: `2·sets` for PMJ02BN (one set per
/// pair), every pair for PMJ02.
const fn dimensions(blue_noise: bool, sets: u32) -> u32 {
    if blue_noise {
        2 * sets
    } else {
        ALL_DIMS
    }
}

/// The error of a `table` of length `got` where `expected` are needed.
fn table_length(expected: usize, got: usize) -> PatternError {
    PatternError::Parameter {
        name: "table",
        value: got as u64,
        min: expected as u64,
        max: expected as u64,
    }
}

impl<'a> Pmj02Tables<&'a [[u32; 2]]> {
    /// Length of the `table` buffer of [`Pmj02Tables::generate`]:
    /// `sets × pmj.n()` points (8 bytes each).
    ///
    /// # Errors
    /// [`PatternError::PowerOfTwo`] (`"n"`) unless `pmj.n()` is a power of
    /// two; [`PatternError::Parameter`] (`"sets"`) unless `1 ≤ sets ≤`
    /// [`PMJ02_TABLES_MAX_SETS`] (and `sets × n` fits `usize`).
    pub fn table_len(pmj: Pmj02, sets: u32) -> Result<usize, PatternError> {
        checked_len(check_points(pmj.n())?, sets)
    }

    /// Length of the `scratch` buffer of [`Pmj02Tables::generate`] (`u32`
    /// words): [`Pmj02::scratch_len`], reused for every set.
    #[must_use]
    pub fn scratch_len(pmj: Pmj02) -> usize {
        pmj.scratch_len()
    }

    /// Generates `sets` independent realisations of `pmj` (PMJ02 or PMJ02BN,
    /// `N = pmj.n()` points, with its candidate count) into `table`: set `s`
    /// is [`Pmj02::generate`] with the seed `Seed(seed.stream(P + s))` (`P`
    /// this module's purpose), written to `table[s·N .. (s+1)·N]` as 24-bit
    /// integers. `scratch` is overwritten; its contents on entry do not
    /// matter. No allocation. Returns the tables, borrowing `table`.
    ///
    /// # Errors
    /// As [`Pmj02Tables::table_len`]; [`PatternError::Parameter`]
    /// (`"table"`, `min = max =` the length needed) unless
    /// `table.len() ==` [`Pmj02Tables::table_len`];
    /// [`PatternError::Scratch`] if `scratch.len() <`
    /// [`Pmj02Tables::scratch_len`]. Nothing is written on an error.
    pub fn generate(
        pmj: Pmj02,
        sets: u32,
        seed: Seed,
        table: &'a mut [[u32; 2]],
        scratch: &mut [u32],
    ) -> Result<Self, PatternError> {
        let len = Self::table_len(pmj, sets)?;
        if table.len() != len {
            return Err(table_length(len, table.len()));
        }
        if scratch.len() < pmj.scratch_len() {
            return Err(PatternError::Scratch {
                expected: pmj.scratch_len(),
                got: scratch.len(),
            });
        }
        let n = pmj.n();
        for (s, chunk) in table.chunks_exact_mut(n).enumerate() {
            let set_seed = Seed(seed.stream(TABLE_PURPOSE.wrapping_add(s as u64)));
            // [u32; 2] and [f32; 2] have one size and alignment: generate the
            // f32 points in place, then turn them into their (exact) integers.
            let out: &mut [[f32; 2]] = bytemuck::cast_slice_mut(chunk);
            pmj.generate(set_seed, out, scratch)?;
            for p in chunk.iter_mut() {
                *p = p.map(|bits| (f32::from_bits(bits) * 16_777_216.0) as u32);
            }
        }
        Ok(Pmj02Tables {
            table,
            points: n as u32,
            sets,
            blue_noise: pmj.is_blue_noise(),
        })
    }
}

#[cfg(feature = "alloc")]
impl Pmj02Tables<alloc::vec::Vec<[u32; 2]>> {
    /// [`Pmj02Tables::generate`] into a new `Vec` (allocates the table and the
    /// scratch).
    ///
    /// # Errors
    /// As [`Pmj02Tables::table_len`].
    pub fn new(pmj: Pmj02, sets: u32, seed: Seed) -> Result<Self, PatternError> {
        let len = Pmj02Tables::table_len(pmj, sets)?;
        let mut table = alloc::vec![[0u32; 2]; len];
        let mut scratch = alloc::vec![0u32; pmj.scratch_len()];
        let Pmj02Tables {
            points, blue_noise, ..
        } = Pmj02Tables::generate(pmj, sets, seed, &mut table, &mut scratch)?;
        Ok(Pmj02Tables {
            table,
            points,
            sets,
            blue_noise,
        })
    }
}

impl<T: AsRef<[[u32; 2]]>> Pmj02Tables<T> {
    /// Tables from a stored `table` (e.g. the [`Pmj02Tables::table`] of an
    /// earlier [`Pmj02Tables::generate`], cached): `sets` sets of `n` points
    /// of PMJ02 (`blue_noise = false`) or PMJ02BN. The contents are not
    /// checked beyond the coordinate range: the guarantees of the type hold
    /// for a table that [`Pmj02Tables::generate`] wrote with these
    /// parameters.
    ///
    /// # Errors
    /// [`PatternError::ZeroPoints`] for `n = 0`,
    /// [`PatternError::TooManyPoints`] for `n >` [`super::PMJ02_MAX_POINTS`],
    /// then as [`Pmj02Tables::table_len`] and [`Pmj02Tables::generate`] for
    /// the length; [`PatternError::Parameter`] (`"table"`, `max = 2²⁴ − 1`,
    /// `value` the first bad coordinate) if a coordinate is `≥ 2²⁴`.
    pub fn from_table(
        table: T,
        n: usize,
        sets: u32,
        blue_noise: bool,
    ) -> Result<Self, PatternError> {
        let pmj = Pmj02::new(n)?;
        let len = Pmj02Tables::table_len(pmj, sets)?;
        let t = table.as_ref();
        if t.len() != len {
            return Err(table_length(len, t.len()));
        }
        if let Some(&bad) = t.iter().flatten().find(|&&c| c > ONES) {
            return Err(PatternError::Parameter {
                name: "table",
                value: u64::from(bad),
                min: 0,
                max: u64::from(ONES),
            });
        }
        Ok(Pmj02Tables {
            table,
            points: n as u32,
            sets,
            blue_noise,
        })
    }

    /// `N`, the points per set (a power of two).
    #[must_use]
    pub fn points(&self) -> u32 {
        self.points
    }

    /// The number of sets.
    #[must_use]
    pub fn sets(&self) -> u32 {
        self.sets
    }

    /// Whether the sets are PMJ02BN.
    #[must_use]
    pub fn is_blue_noise(&self) -> bool {
        self.blue_noise
    }

    /// The table: point `i` of set `s` at `s·N + i`, coordinates as 24-bit
    /// integers (`x = X·2⁻²⁴`).
    #[must_use]
    pub fn table(&self) -> &[[u32; 2]] {
        self.table.as_ref()
    }

    /// The storage, back.
    #[must_use]
    pub fn into_inner(self) -> T {
        self.table
    }

    /// The memory of the table, `sets × N × 8` bytes.
    #[must_use]
    pub fn bytes(&self) -> usize {
        core::mem::size_of_val(self.table())
    }

    /// Dimensions of every pixel's sequence: `2³² − 2` for PMJ02 (every
    /// pair), `2·sets` for PMJ02BN (one set per pair; see the type docs).
    #[must_use]
    pub fn dimensions(&self) -> u32 {
        dimensions(self.blue_noise, self.sets)
    }

    /// Pixel `(x, y)` (any `u32` coordinates) as a [`Sequence<2>`] of `N`
    /// points ([`Pmj02Pixel`]). One hash; the seed comes with each sample.
    #[must_use]
    pub fn pixel(&self, x: u32, y: u32) -> Pmj02Pixel<'_> {
        Pmj02Pixel {
            table: self.table(),
            points: self.points,
            sets: self.sets,
            blue_noise: self.blue_noise,
            x,
            y,
            hash: mix64((u64::from(x) | u64::from(y) << 32) ^ PIXEL_SALT),
        }
    }
}

/// One pixel of a [`Pmj02Tables`], a [`Sequence<2>`] of `N` points: point
/// `i` in dimensions `2p, 2p + 1` is table point `σ_p(i)` of set
/// `(s₀ + p) mod sets`, moved by the pixel's transform of pair `p` (see
/// [`Pmj02Tables`]). `count` is `N`; [`Sequence::dimensions`] is
/// [`Pmj02Tables::dimensions`]. The `seed` passed to the methods selects the
/// transforms (one seed for the image, or one per run); the tables' own seed
/// was fixed when they were generated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pmj02Pixel<'a> {
    table: &'a [[u32; 2]],
    points: u32,
    sets: u32,
    blue_noise: bool,
    x: u32,
    y: u32,
    /// `mix64((x + 2³²·y) ⊕ salt)`, a bijection of the pixel.
    hash: u64,
}

/// The `t`-th of the 32 isometries: bit 0 swaps the coordinates, bits 1–2 and
/// 3–4 choose the XOR masks of `x` and `y` among `0`, `2²³` (translation by
/// `1/2`), `2²⁴ − 1` (reflection) and both.
#[inline(always)]
const fn isometry(p: [u32; 2], t: u32) -> [u32; 2] {
    const MASKS: [u32; 4] = [0, TOP, ONES, ONES ^ TOP];
    let q = if t & 1 == 1 { [p[1], p[0]] } else { p };
    [
        q[0] ^ MASKS[((t >> 1) & 3) as usize],
        q[1] ^ MASKS[((t >> 3) & 3) as usize],
    ]
}

/// Nested uniform scramble of a 24-bit coordinate: [`owen_rev`] of the
/// bit-reversed word, as [`super::Sobol`] scrambles its values.
#[inline(always)]
const fn scramble24(v: u32, k: OwenKey) -> u32 {
    owen_rev((v << (32 - BITS)).reverse_bits(), k).reverse_bits() >> (32 - BITS)
}

/// Index `i` with its batch `[2ᵇ, 2ᵇ⁺¹)` permuted by a key from `kpair`
/// (`0` and `1` stay).
#[inline(always)]
fn batch_permuted(i: u32, kpair: u64) -> u32 {
    if i < 2 {
        return i;
    }
    let b = 31 - i.leading_zeros();
    let base = 1u32 << b;
    let key = mix64((kpair ^ PERM_SALT).wrapping_add(u64::from(b).wrapping_mul(GOLDEN_64)));
    base + permute(i - base, base, (key >> 32) as u32)
}

/// A table coordinate as an `f32` in `[0, 1)` (exact).
#[inline(always)]
fn to_f32(v: u32) -> f32 {
    v as f32 * TO_UNIT
}

impl Pmj02Pixel<'_> {
    /// The pixel's column and row.
    #[must_use]
    pub fn position(&self) -> (u32, u32) {
        (self.x, self.y)
    }

    /// Dimensions `2·pair` and `2·pair + 1` of point `index`.
    ///
    /// # Errors
    /// [`PatternError::Range`] if `index ≥ N`, then
    /// [`PatternError::Dimension`] (`dim = 2·pair`, saturating) if
    /// `2·pair + 1 ≥` [`Sequence::dimensions`].
    pub fn sample_2d(&self, index: u64, pair: u32, seed: Seed) -> Result<[f32; 2], PatternError> {
        let i = self.check_index(index)?;
        let max = self.dims();
        if pair >= max / 2 {
            return Err(PatternError::Dimension {
                dim: pair.saturating_mul(2),
                max,
            });
        }
        let (q, kpair) = self.locate(i, pair, seed);
        Ok([
            to_f32(self.transform(q, kpair, 0)),
            to_f32(self.transform(q, kpair, 1)),
        ])
    }

    fn dims(&self) -> u32 {
        dimensions(self.blue_noise, self.sets)
    }

    fn check_index(&self, index: u64) -> Result<u32, PatternError> {
        let n = u64::from(self.points);
        if index >= n {
            return Err(PatternError::Range {
                first: index,
                len: 1,
                n,
            });
        }
        Ok(index as u32)
    }

    /// The table point that pair `pair` of point `i` reads, and the pair's key.
    #[inline(always)]
    fn locate(&self, i: u32, pair: u32, seed: Seed) -> ([u32; 2], u64) {
        // mix64(σ ⊕ premix ⊕ pixel hash): a bijection of the pixel hash for
        // each seed, so distinct pixels get distinct keys.
        let kpix = seed.stream_premixed(PIXEL_PREMIX ^ self.hash);
        let kpair = mix64(kpix.wrapping_add((u64::from(pair) + 1).wrapping_mul(GOLDEN_64)));
        let sets = u64::from(self.sets);
        let s0 = ((kpix >> 32) * sets) >> 32;
        let s = (s0 + u64::from(pair) % sets) % sets;
        let j = if pair == 0 {
            i
        } else {
            batch_permuted(i, kpair)
        };
        // s < sets and j < N: inside the table (its length is sets·N).
        (
            self.table[s as usize * self.points as usize + j as usize],
            kpair,
        )
    }

    /// Coordinate `c` of the table point `q` under the pair's transform.
    #[inline(always)]
    fn transform(&self, q: [u32; 2], kpair: u64, c: usize) -> u32 {
        if self.blue_noise {
            isometry(q, (kpair >> 59) as u32)[c]
        } else {
            scramble24(q[c], OwenKey::from_stream(mix64(kpair ^ VALUE_SALT[c])))
        }
    }
}

impl Sequence<2> for Pmj02Pixel<'_> {
    fn count(&self) -> u64 {
        u64::from(self.points)
    }

    fn dimensions(&self) -> u32 {
        self.dims()
    }

    fn point(&self, index: u64, seed: Seed) -> Result<[f32; 2], PatternError> {
        self.sample_2d(index, 0, seed)
    }

    fn sample(&self, index: u64, dim: u32, seed: Seed) -> Result<f32, PatternError> {
        let i = self.check_index(index)?;
        let max = self.dims();
        if dim >= max {
            return Err(PatternError::Dimension { dim, max });
        }
        let (q, kpair) = self.locate(i, dim / 2, seed);
        Ok(to_f32(self.transform(q, kpair, (dim % 2) as usize)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    extern crate std;
    use std::vec::Vec;

    /// Toroidal distance² on the 2²⁴ grid.
    fn d2(a: [u32; 2], b: [u32; 2]) -> u64 {
        (0..2)
            .map(|j| {
                let d = a[j].wrapping_sub(b[j]) & ONES;
                let d = u64::from(d.min((1 << BITS) - d));
                d * d
            })
            .sum()
    }

    /// Whether the first `2ᵏ` points are a `(0, k, 2)`-net.
    fn is_net(p: &[[u32; 2]], k: u32) -> bool {
        let n = 1usize << k;
        (0..=k).all(|a| {
            let mut seen = std::vec![false; n];
            p[..n].iter().all(|q| {
                let c = (((q[0] >> (BITS - a)) << (k - a)) | (q[1] >> (BITS - (k - a)))) as usize;
                !core::mem::replace(&mut seen[c], true)
            })
        })
    }

    fn table(bn: bool) -> Vec<[u32; 2]> {
        let pmj = if bn {
            Pmj02::blue_noise(256).unwrap()
        } else {
            Pmj02::new(256).unwrap()
        };
        let mut t = std::vec![[0u32; 2]; 256];
        let mut s = std::vec![0u32; pmj.scratch_len()];
        Pmj02Tables::generate(pmj, 1, Seed(5), &mut t, &mut s).unwrap();
        t
    }

    #[test]
    fn the_32_isometries_are_distinct_keep_distances_and_nets() {
        let pts = table(true);
        for k in 0..=8 {
            assert!(is_net(&pts, k));
        }
        let mut images: Vec<[u32; 2]> = Vec::new();
        for t in 0..PMJ02BN_TRANSFORMS {
            let moved: Vec<[u32; 2]> = pts.iter().map(|&p| isometry(p, t)).collect();
            images.push(moved[3]);
            for k in 0..=8 {
                assert!(is_net(&moved, k), "transform {t}, prefix 2^{k}");
            }
            for (i, &a) in pts.iter().enumerate() {
                for &b in &pts[..i] {
                    assert_eq!(d2(a, b), d2(isometry(a, t), isometry(b, t)), "t {t}");
                }
                assert!(moved[i][0] <= ONES && moved[i][1] <= ONES);
            }
            // Corner cases of the grid: wrap-around distances.
            for (a, b) in [
                ([0, 0], [ONES, 0]),
                ([0, 5], [TOP, ONES]),
                ([1, 2], [3, ONES]),
            ] {
                assert_eq!(d2(a, b), d2(isometry(a, t), isometry(b, t)));
            }
        }
        // A point off every symmetry axis has 32 distinct images.
        let p = [0x12_3456, 0x0A_BCDE];
        let mut all: Vec<[u32; 2]> = (0..32).map(|t| isometry(p, t)).collect();
        all.sort_unstable();
        all.dedup();
        assert_eq!(all.len(), 32);
    }

    #[test]
    fn the_scramble_is_a_triangular_bijection_of_24_bits() {
        let key = OwenKey::from_stream(0xDEAD_BEEF_1234_5678);
        // Bijection on the top b digits for every b (so intervals go to
        // intervals), and into 24 bits.
        for b in [1u32, 3, 8, 12] {
            let mut seen = std::vec![false; 1 << b];
            for top in 0..1u32 << b {
                let v = top << (BITS - b);
                let w = scramble24(v, key);
                assert!(w <= ONES);
                assert!(!core::mem::replace(
                    &mut seen[(w >> (BITS - b)) as usize],
                    true
                ));
                // The top b digits of the image depend on the top b digits only.
                for low in [1u32, 0x5_5555, (1 << (BITS - b)) - 1] {
                    let low = low & ((1 << (BITS - b)) - 1);
                    assert_eq!(scramble24(v | low, key) >> (BITS - b), w >> (BITS - b));
                }
            }
        }
    }

    #[test]
    fn batch_permutation_keeps_batches_and_is_a_bijection() {
        for kpair in [0u64, 1, 0x9E37_79B9_7F4A_7C15] {
            let img: Vec<u32> = (0..1024).map(|i| batch_permuted(i, kpair)).collect();
            for (i, &j) in img.iter().enumerate() {
                let i = i as u32;
                assert_eq!(i.max(1).ilog2(), j.max(1).ilog2(), "{i} -> {j}");
            }
            let mut s = img.clone();
            s.sort_unstable();
            assert_eq!(s, (0..1024).collect::<Vec<_>>());
            assert_ne!(img, (0..1024).collect::<Vec<_>>());
        }
    }
}
