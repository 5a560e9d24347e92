//! glam interop (`--features glam`): patterns fill `[Vec2]`, `[Vec3]` in place
//! and `[Vec3A]` through a stack buffer, bit for bit as `fill` into arrays.
#![cfg(feature = "glam")]

use glam::{Vec2, Vec3, Vec3A};
use linesample::pattern::{
    CorrelatedMultiJittered, Halton, Jittered, NRooks, Pattern, PatternGlam, Random, Sobol,
};
use linesample::{PatternError, Seed};

const SEEDS: [Seed; 2] = [Seed(5), Seed(0x0123_4567_89AB_CDEF)];

fn fill_vec2(p: &dyn Pattern<2>, seed: Seed, out: &mut [Vec2]) {
    p.fill_glam(seed, out).unwrap();
}

fn fill_vec3(p: &dyn Pattern<3>, seed: Seed, out: &mut [Vec3]) {
    p.fill_glam(seed, out).unwrap();
}

fn same2(v: Vec2, a: [f32; 2]) -> bool {
    v.x.to_bits() == a[0].to_bits() && v.y.to_bits() == a[1].to_bits()
}

fn same3(x: f32, y: f32, z: f32, a: [f32; 3]) -> bool {
    [x, y, z].map(f32::to_bits) == a.map(f32::to_bits)
}

#[test]
fn vec2_and_vec3_slices_fill_bit_for_bit() {
    let p2: [Box<dyn Pattern<2>>; 4] = [
        Box::new(Jittered::new([7, 9]).unwrap()),
        Box::new(Sobol::<2>::new(100).unwrap()),
        Box::new(CorrelatedMultiJittered::new(60).unwrap().shifted()),
        Box::new(Random::<2>::new(3).unwrap()),
    ];
    let p3: [Box<dyn Pattern<3>>; 4] = [
        Box::new(Jittered::new([2, 3, 5]).unwrap()),
        Box::new(Halton::<3>::new(129).unwrap()),
        Box::new(NRooks::<3>::new(77).unwrap().shifted()),
        Box::new(Random::<3>::new(1).unwrap()),
    ];
    for seed in SEEDS {
        for p in &p2 {
            let n = p.len();
            let mut want = vec![[0.0f32; 2]; n];
            p.fill(seed, &mut want).unwrap();
            let mut v = vec![Vec2::splat(-1.0); n];
            fill_vec2(p.as_ref(), seed, &mut v);
            assert!(v.iter().zip(&want).all(|(&v, &a)| same2(v, a)));
        }
        for p in &p3 {
            let n = p.len();
            let mut want = vec![[0.0f32; 3]; n];
            p.fill(seed, &mut want).unwrap();
            let mut v = vec![Vec3::splat(-1.0); n];
            fill_vec3(p.as_ref(), seed, &mut v);
            assert!(v.iter().zip(&want).all(|(v, &a)| same3(v.x, v.y, v.z, a)));
        }
    }
}

#[test]
fn ranges_fill_bit_for_bit() {
    let p2 = Sobol::<2>::new(1000).unwrap();
    let p3 = Jittered::new([10, 10, 10]).unwrap();
    let mut want2 = vec![[0.0f32; 2]; 1000];
    let mut want3 = vec![[0.0f32; 3]; 1000];
    for seed in SEEDS {
        p2.fill(seed, &mut want2).unwrap();
        p3.fill(seed, &mut want3).unwrap();
        for (first, len) in [(0, 0), (0, 1), (3, 61), (500, 64), (937, 63), (1, 999)] {
            let mut v2 = vec![Vec2::ZERO; len];
            p2.fill_range_glam(seed, first, &mut v2).unwrap();
            let mut v3 = vec![Vec3::ZERO; len];
            p3.fill_range_glam(seed, first, &mut v3).unwrap();
            let mut va = vec![Vec3A::ZERO; len];
            p3.fill_range_glam(seed, first, &mut va).unwrap();
            for i in 0..len {
                assert!(same2(v2[i], want2[first + i]), "first {first} i {i}");
                let w = want3[first + i];
                assert!(same3(v3[i].x, v3[i].y, v3[i].z, w), "first {first} i {i}");
                assert!(same3(va[i].x, va[i].y, va[i].z, w), "first {first} i {i}");
            }
        }
    }
}

#[test]
fn vec3a_fills_bit_for_bit_at_every_chunk_boundary() {
    // The Vec3A path works in chunks of 64 points: lengths below, at and
    // around multiples of 64.
    for n in [1, 2, 63, 64, 65, 127, 128, 129, 200, 1000] {
        let patterns: [Box<dyn Pattern<3>>; 3] = [
            Box::new(Sobol::<3>::new(n).unwrap()),
            Box::new(Random::<3>::new(n).unwrap()),
            Box::new(NRooks::<3>::new(n).unwrap().shifted()),
        ];
        for p in &patterns {
            for seed in SEEDS {
                let mut want = vec![[0.0f32; 3]; n];
                p.fill(seed, &mut want).unwrap();
                let mut va = vec![Vec3A::splat(-1.0); n];
                p.fill_glam(seed, &mut va).unwrap();
                for (i, (v, &a)) in va.iter().zip(&want).enumerate() {
                    assert!(same3(v.x, v.y, v.z, a), "n {n} i {i}");
                }
            }
        }
    }
}

#[test]
fn the_cast_is_in_place() {
    let p2 = Jittered::new([4, 4]).unwrap();
    let p3 = Sobol::<3>::new(16).unwrap();
    let mut v2 = [Vec2::ZERO; 16];
    let mut v3 = [Vec3::ZERO; 16];
    let (ptr2, ptr3) = (v2.as_ptr() as usize, v3.as_ptr() as usize);
    // The slices the fills write are the caller's memory, reinterpreted.
    let a2: &mut [[f32; 2]] = bytemuck::cast_slice_mut(&mut v2);
    assert_eq!((a2.as_ptr() as usize, a2.len()), (ptr2, 16));
    let a3: &mut [[f32; 3]] = bytemuck::cast_slice_mut(&mut v3);
    assert_eq!((a3.as_ptr() as usize, a3.len()), (ptr3, 16));
    // And the fill through the cast writes exactly what `fill_range` writes
    // into that memory.
    let seed = Seed(9);
    p2.fill_glam(seed, &mut v2).unwrap();
    p3.fill_glam(seed, &mut v3).unwrap();
    let (mut w2, mut w3) = ([[0.0f32; 2]; 16], [[0.0f32; 3]; 16]);
    p2.fill(seed, &mut w2).unwrap();
    p3.fill(seed, &mut w3).unwrap();
    assert_eq!(bytemuck::cast_slice::<Vec2, [f32; 2]>(&v2), &w2[..]);
    assert_eq!(bytemuck::cast_slice::<Vec3, [f32; 3]>(&v3), &w3[..]);
    assert_eq!(core::mem::size_of::<Vec3>(), 12);
    assert_eq!(core::mem::size_of::<Vec3A>(), 16);
}

/// A pattern that records where its fills write: proves that `fill_glam`
/// hands the caller's own memory to the pattern (no intermediate copy).
struct Probe {
    n: usize,
    seen: core::cell::Cell<usize>,
}

impl<const D: usize> Pattern<D> for Probe {
    fn len(&self) -> usize {
        self.n
    }
    fn fill_range(&self, _: Seed, first: usize, out: &mut [[f32; D]]) -> Result<(), PatternError> {
        self.seen.set(out.as_ptr() as usize);
        for (i, p) in out.iter_mut().enumerate() {
            *p = [((first + i) as f32) / 1024.0; D];
        }
        Ok(())
    }
    fn fill_range_scalar(
        &self,
        s: Seed,
        f: usize,
        out: &mut [[f32; D]],
    ) -> Result<(), PatternError> {
        self.fill_range(s, f, out)
    }
    fn fill_range_soa(
        &self,
        _: Seed,
        first: usize,
        out: [&mut [f32]; D],
    ) -> Result<(), PatternError> {
        for col in out {
            for (i, x) in col.iter_mut().enumerate() {
                *x = ((first + i) as f32) / 1024.0;
            }
        }
        Ok(())
    }
}

#[test]
fn the_pattern_writes_into_the_callers_slice() {
    let probe = Probe {
        n: 10,
        seen: core::cell::Cell::new(0),
    };
    let mut v2 = [Vec2::ZERO; 10];
    PatternGlam::<Vec2>::fill_glam(&probe, Seed(0), &mut v2).unwrap();
    assert_eq!(probe.seen.get(), v2.as_ptr() as usize);
    assert_eq!(v2[3], Vec2::splat(3.0 / 1024.0));
    let mut v3 = [Vec3::ZERO; 10];
    PatternGlam::<Vec3>::fill_range_glam(&probe, Seed(0), 2, &mut v3[..8]).unwrap();
    assert_eq!(probe.seen.get(), v3.as_ptr() as usize);
    assert_eq!(v3[0], Vec3::splat(2.0 / 1024.0));
    // Vec3A goes through the stack buffer: a different address, same values.
    let mut va = [Vec3A::ZERO; 10];
    PatternGlam::<Vec3A>::fill_glam(&probe, Seed(0), &mut va).unwrap();
    assert_ne!(probe.seen.get(), va.as_ptr() as usize);
    assert_eq!(va[9], Vec3A::splat(9.0 / 1024.0));
}

#[test]
fn errors_are_the_fills_errors_and_write_nothing() {
    let seed = Seed(1);
    let p3 = Sobol::<3>::new(100).unwrap();
    let p2 = Jittered::new([5, 5]).unwrap();

    let mut v3 = vec![Vec3::ONE; 99];
    assert_eq!(
        p3.fill_glam(seed, &mut v3),
        Err(PatternError::OutputLength {
            expected: 100,
            got: 99
        })
    );
    let mut va = vec![Vec3A::ONE; 101];
    assert_eq!(
        p3.fill_glam(seed, &mut va),
        Err(PatternError::OutputLength {
            expected: 100,
            got: 101
        })
    );
    // A range past N is rejected as a whole, before any chunk is written.
    let mut va = vec![Vec3A::ONE; 70];
    assert_eq!(
        p3.fill_range_glam(seed, 31, &mut va),
        Err(PatternError::Range {
            first: 31,
            len: 70,
            n: 100
        })
    );
    assert!(va.iter().all(|&v| v == Vec3A::ONE));
    assert_eq!(
        p3.fill_range_glam(seed, usize::MAX, &mut va[..2]),
        Err(PatternError::Range {
            first: usize::MAX as u64,
            len: 2,
            n: 100
        })
    );
    let mut v2 = vec![Vec2::ONE; 3];
    assert_eq!(
        p2.fill_range_glam(seed, 23, &mut v2),
        Err(PatternError::Range {
            first: 23,
            len: 3,
            n: 25
        })
    );
    assert!(v2.iter().all(|&v| v == Vec2::ONE));
    // An empty range at the end is fine.
    assert_eq!(p3.fill_range_glam(seed, 100, &mut va[..0]), Ok(()));
}
