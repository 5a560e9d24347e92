//! Pinned outputs. Each sampler's points for a fixed seed are hashed (FNV-1a over
//! the `f32` bit patterns) and compared with values recorded when the generator
//! was written. CI runs this file in the AVX2 build and in the baseline SSE2
//! build, so it also proves that both builds produce the same bits. A change here
//! is a value-breaking change: it needs a changelog entry and a version bump.

use linesample::pattern::{
    CorrelatedMultiJittered, Halton, Jittered, MultiJittered, NRooks, Pattern, Random, Sobol,
};
use linesample::Seed;

fn fnv<const D: usize>(p: &dyn Pattern<D>) -> u64 {
    let mut v = vec![[0.0f32; D]; p.len()];
    p.fill(Seed::new(42), &mut v).unwrap();
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for q in &v {
        for x in q {
            for b in x.to_bits().to_le_bytes() {
                h ^= u64::from(b);
                h = h.wrapping_mul(0x0000_0100_0000_01b3);
            }
        }
    }
    h
}

#[test]
fn pinned_pattern_hashes() {
    let got = [
        ("random2", fnv(&Random::<2>::new(1000).unwrap())),
        ("random3", fnv(&Random::<3>::new(1000).unwrap())),
        ("jittered2", fnv(&Jittered::<2>::new([25, 40]).unwrap())),
        ("jittered3", fnv(&Jittered::<3>::new([10, 10, 10]).unwrap())),
        ("nrooks3", fnv(&NRooks::<3>::new(1000).unwrap())),
        ("mj", fnv(&MultiJittered::new(1000).unwrap())),
        ("cmj", fnv(&CorrelatedMultiJittered::new(1000).unwrap())),
        (
            "cmj-shifted",
            fnv(&CorrelatedMultiJittered::new(1000).unwrap().shifted()),
        ),
        ("sobol3", fnv(&Sobol::<3>::new(1000).unwrap())),
        ("halton3", fnv(&Halton::<3>::new(1000).unwrap())),
    ];
    let want: [(&str, u64); 10] = [
        ("random2", 0x0343f5a28c040fc0),
        ("random3", 0x0af396c96c9cdf85),
        ("jittered2", 0x6ecefd0db465393e),
        ("jittered3", 0x374d3681f0864a59),
        ("nrooks3", 0x37e671758fb62a33),
        ("mj", 0xe7f0a89fbc5868f8),
        ("cmj", 0x5e9464558335f6af),
        ("cmj-shifted", 0xbdc925a5a9f3704f),
        ("sobol3", 0x9dead7a7bebd9111),
        ("halton3", 0x6a3e4cf2c812002f),
    ];
    for g in &got {
        println!("        (\"{}\", {:#018x}),", g.0, g.1); // to re-pin deliberately
    }
    for (g, w) in got.iter().zip(want.iter()) {
        assert_eq!(g.0, w.0);
        assert_eq!(g.1, w.1, "{}: value-breaking change", g.0);
    }
}
