//! The samples an effect's estimator draws: its sampler's pattern of `N`
//! points in the dimension the estimator needs
//! ([`linesample_scene::Effect::dims`], 1 to 3), shifted per realisation as
//! the effect says ([`linesample_scene::Effect::shifted`]), written as the
//! effect's samples ([`linesample_scene::Effect::Sample`]: a pattern of
//! fewer dimensions fills the first coordinates, the others are ½).
//!
//! Jittered patterns in `k ≥ 2` dimensions use the most balanced strata:
//! `N^{1/k}` per axis when `N` is a perfect `k`-th power, otherwise, for
//! `N = 2^m`, `2^⌊m/k⌋` per axis and `2^⌈m/k⌉` on the last `m mod k` axes
//! (for photon points that is the free-flight axis, whose band through the
//! query ball is the narrowest feature). Samplers that exist only in 2D
//! (multi-jittered, CMJ) serve a 1D estimator with the `u` coordinates of
//! their 2D pattern, whose projection is stratified into `N` strata (a 1D
//! jittered pattern).

use linesample::pattern::Pattern;
use linesample::Seed;
use linesample_scene::model::SceneSampler;
use linesample_scene::Effect;

use crate::io::buffer;
use crate::sampler::{self, DynPattern, PatternSpec, Sampler};
use crate::spec::ShiftMode;

/// A sampler's pattern of `N` points in one to three dimensions.
pub struct SamplePattern {
    pattern: Dims,
    n: usize,
}

/// The pattern in its dimension.
enum Dims {
    One(DynPattern<1>),
    Two(DynPattern<2>),
    Three(DynPattern<3>),
}

/// The most balanced jittered strata of `n` points in `k` dimensions (see
/// the module doc), or `None` when `n` is neither a perfect `k`-th power
/// nor a power of two.
#[must_use]
pub fn balanced_strata(n: usize, k: usize) -> Option<Vec<usize>> {
    if k <= 1 {
        return Some(vec![n]);
    }
    let root = (n as f64).powf(1.0 / k as f64).round() as usize;
    if root.checked_pow(k as u32) == Some(n) {
        return Some(vec![root; k]);
    }
    if !n.is_power_of_two() {
        return None;
    }
    let m = n.trailing_zeros() as usize;
    Some(
        (0..k)
            .map(|j| 1usize << (m / k + usize::from(j >= k - m % k)))
            .collect(),
    )
}

impl SamplePattern {
    /// The pattern of `sampler` with `n` points in `dims` (1 to 3)
    /// dimensions, toroidally shifted per realisation when `shift`; `label`
    /// names the estimator in an error.
    ///
    /// # Errors
    /// A sample count the sampler does not support, or a dimension it
    /// lacks.
    pub fn new(
        sampler: SceneSampler,
        dims: usize,
        n: usize,
        shift: bool,
        label: &str,
    ) -> crate::Result<Self> {
        let s = Sampler::from(sampler);
        let err = |e: String| format!("{label} with N = {n}: {e}");
        // A 1D estimator of a 2D-only sampler reads its `u` coordinates.
        let k = if dims == 1 && !s.dims().contains(&1) {
            2
        } else {
            dims
        };
        let mut spec = PatternSpec::simple(s, k, n);
        if s == Sampler::Jittered && k > 1 {
            spec.strata = Some(balanced_strata(n, k).ok_or_else(|| {
                err(format!(
                    "jittered in {k}D needs N a perfect {} or a power of two",
                    if k == 2 { "square" } else { "cube" }
                ))
            })?);
        }
        let pattern = match k {
            1 => Dims::One(sampler::build::<1>(&spec, shift).map_err(err)?.pattern),
            2 => Dims::Two(sampler::build::<2>(&spec, shift).map_err(err)?.pattern),
            3 => Dims::Three(sampler::build::<3>(&spec, shift).map_err(err)?.pattern),
            _ => return Err(err(format!("a {k}D pattern (1 to 3 dimensions)")).into()),
        };
        Ok(SamplePattern { pattern, n })
    }

    /// The pattern of `world`'s estimator `est` (`None`: the effect's
    /// reference) with `n` points under `--shift` `shift` (`None`: the
    /// effect's default), with the estimator it is for.
    ///
    /// # Errors
    /// A sample count the sampler does not support, or an estimator of more
    /// dimensions than the effect's samples hold.
    pub fn of<E: Effect>(
        world: &E,
        est: Option<&E::Estimator>,
        n: usize,
        shift: Option<ShiftMode>,
    ) -> crate::Result<(E::Estimator, Self)> {
        let shifted = E::shifted(est, shift.map(|s| s == ShiftMode::Random));
        let e = est.copied().unwrap_or_else(E::reference);
        let dims = world.dims(&e);
        let room = E::Sample::default().as_ref().len();
        if dims > room {
            return Err(format!(
                "internal error: {} needs {dims}D samples, the effect holds {room}",
                E::label(&e)
            )
            .into());
        }
        let p = Self::new(E::sampler(&e), dims, n, shifted, &E::label(&e))?;
        Ok((e, p))
    }

    /// Realisation `seed` into `out` (resized to `N`), through `buf`.
    ///
    /// # Errors
    /// An allocation failure or the pattern's error.
    pub fn fill<S: Copy + Default + AsMut<[f32]>>(
        &self,
        seed: Seed,
        out: &mut Vec<S>,
        buf: &mut Buffers,
    ) -> crate::Result<()> {
        match &self.pattern {
            Dims::One(p) => fill_from(p.as_ref(), self.n, seed, &mut buf.one, out),
            Dims::Two(p) => fill_from(p.as_ref(), self.n, seed, &mut buf.two, out),
            Dims::Three(p) => fill_from(p.as_ref(), self.n, seed, &mut buf.three, out),
        }
    }
}

/// `n` points of `p` for `seed` through `tmp`, copied into the first `D`
/// coordinates of `out`'s samples (the others ½).
fn fill_from<const D: usize, S: Copy + Default + AsMut<[f32]>>(
    p: &(dyn Pattern<D> + Send + Sync),
    n: usize,
    seed: Seed,
    tmp: &mut Vec<[f32; D]>,
    out: &mut Vec<S>,
) -> crate::Result<()> {
    if tmp.len() != n {
        *tmp = buffer::filled(n, [0.0; D], "samples")?;
    }
    p.fill(seed, tmp)?;
    if out.len() != n {
        *out = buffer::filled(n, S::default(), "samples")?;
    }
    for (o, x) in out.iter_mut().zip(tmp.iter()) {
        let o = o.as_mut();
        o.fill(0.5);
        o[..D].copy_from_slice(x);
    }
    Ok(())
}

/// The pattern buffers of [`SamplePattern::fill`], one per dimension.
#[derive(Default)]
pub struct Buffers {
    one: Vec<[f32; 1]>,
    two: Vec<[f32; 2]>,
    three: Vec<[f32; 3]>,
}

/// An estimator with its pattern at one `N`.
pub type Plan<E> = (<E as Effect>::Estimator, SamplePattern);

/// The buffers of [`estimate`]: the effect's, the samples and the
/// pattern's.
pub type Scratch<E> = (<E as Effect>::Scratch, Vec<<E as Effect>::Sample>, Buffers);

/// Fresh [`Scratch`] for `world`.
pub fn scratch<E: Effect>(world: &E) -> Scratch<E> {
    (world.scratch(), Vec::new(), Buffers::default())
}

/// One estimate at `query` with `plan` from realisation `seed`: fill the
/// pattern, then [`Effect::estimate`].
///
/// # Errors
/// The pattern's or the effect's error.
pub fn estimate<E: Effect>(
    world: &E,
    query: &E::Query,
    (est, pattern): &Plan<E>,
    seed: Seed,
    (scratch, samples, buf): &mut Scratch<E>,
) -> crate::Result<f64> {
    pattern.fill(seed, samples, buf)?;
    Ok(world.estimate(query, est, samples, seed, scratch)?)
}

#[cfg(test)]
mod tests {
    use super::balanced_strata;

    #[test]
    fn strata_are_balanced_and_multiply_to_n() {
        assert_eq!(balanced_strata(4096, 2), Some(vec![64, 64]));
        assert_eq!(balanced_strata(4096, 3), Some(vec![16, 16, 16]));
        assert_eq!(balanced_strata(2048, 2), Some(vec![32, 64]));
        assert_eq!(balanced_strata(2048, 3), Some(vec![8, 16, 16]));
        assert_eq!(balanced_strata(1024, 3), Some(vec![8, 8, 16]));
        assert_eq!(balanced_strata(100, 2), Some(vec![10, 10]));
        assert_eq!(balanced_strata(27, 3), Some(vec![3, 3, 3]));
        assert_eq!(balanced_strata(7, 1), Some(vec![7]));
        assert_eq!(balanced_strata(12, 2), None);
        for m in 0..20 {
            for k in 1..=3 {
                let s = balanced_strata(1 << m, k).unwrap();
                assert_eq!(s.iter().product::<usize>(), 1 << m);
                assert!(s.iter().max().unwrap() / s.iter().min().unwrap() <= 2);
            }
        }
    }
}
