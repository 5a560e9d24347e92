//! Direct light along lines across a rectangular area light
//! (`world::direct_light`, `world::direct_light_f32`), in a Cornell-box-like
//! scene: the light `(−0.24, 1.98, −0.22)` + `(0.47, 0, 0)`, `(0, 0, 0.38)`
//! (emitting down) in the room `[−1, 1] × [0, 2] × [−1, 1]`, a short box
//! (0.6 high, rotated −17° about `y`) and a tall one (1.2 high, +17°), each
//! six faces; a receiver's occluders are the box faces that face it
//! (`scene/tests/direct_light_f32.rs` builds the same scene). 64 receivers:
//! half on the floor (three in eight around the boxes), a quarter on the
//! back and left walls, a quarter on the boxes' faces; 256 lines each
//! (`φ = π(k + ½)/256`, a random offset in the light's offset range).
//!
//! The first group is the visibility + integral kernel, lines per second:
//! the `f64` path (`QuadLight::chord` + `DirectLight::line`, both per
//! line, from `f64` directions and the same offsets), the `f32` scalar twin (`DirectLight32::line_batch_scalar_f32`) and
//! the `f32` SIMD batch (`DirectLight32::line_batch_f32`), each with its
//! receiver prepared once. The second is the per-receiver set-up:
//! `Shadow::project_all` + `DirectLight::new`, and that plus
//! `DirectLight32::new`. The largest `|f32 − f64|` over the bench's lines
//! (relative to the largest value; the `f64` reference on the line the `f32`
//! inputs define, its direction normalised in `f64`) is printed first.
//!
//! Run: `cargo bench --bench direct_light`; criterion's `thrpt` is lines
//! (first group) or receivers (second group) per second on one core.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use linesample::Pcg32;
use linesample_scene::direct_light::{DirectLight, Parallelogram, QuadLight, Shadow};
use linesample_scene::direct_light_f32::DirectLight32;
use std::f64::consts::PI;
use std::hint::black_box;

const RECEIVERS: usize = 64;
const LINES: usize = 256;
/// Shadow capacity of the `f32` receivers.
const CAP: usize = 8;

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// A box standing on `base`, `size` before a rotation of `deg` about `+y`:
/// six faces with unit outward normals.
fn box_faces(base: [f64; 3], size: [f64; 3], deg: f64) -> Vec<(Parallelogram, [f64; 3])> {
    let (s, c) = deg.to_radians().sin_cos();
    let ex = [c * size[0], 0.0, -s * size[0]];
    let ey = [0.0, size[1], 0.0];
    let ez = [s * size[2], 0.0, c * size[2]];
    let o = [
        base[0] - 0.5 * (ex[0] + ez[0]),
        base[1],
        base[2] - 0.5 * (ex[2] + ez[2]),
    ];
    let (ox, oy, oz) = (add(o, ex), add(o, ey), add(o, ez));
    [
        (o, ez, ex),
        (oy, ex, ez),
        (o, ex, ey),
        (oz, ey, ex),
        (o, ey, ez),
        (ox, ez, ey),
    ]
    .iter()
    .map(|&(c, e1, e2)| {
        let f = Parallelogram::new(c, e1, e2).unwrap();
        let n = f.normal();
        let l = dot(n, n).sqrt();
        // `e1 × e2` points into the box for this edge order.
        (f, [-n[0] / l, -n[1] / l, -n[2] / l])
    })
    .collect()
}

/// The receivers: point, normal, and the faces facing it.
struct Receiver {
    x: [f64; 3],
    n: [f64; 3],
    faces: Vec<Parallelogram>,
}

fn receivers(faces: &[(Parallelogram, [f64; 3])], rng: &mut Pcg32) -> Vec<Receiver> {
    let mut u = || f64::from(rng.next_u32()) / 4_294_967_296.0;
    let inside = |x: [f64; 3]| {
        faces[..6]
            .iter()
            .all(|(f, n)| dot(sub(x, f.corner()), *n) < -1e-9)
            || faces[6..]
                .iter()
                .all(|(f, n)| dot(sub(x, f.corner()), *n) < -1e-9)
    };
    let mut out = Vec::new();
    while out.len() < RECEIVERS {
        let k = out.len() % 8;
        let (a, b) = (u(), u());
        let (x, n) = match k {
            0 => ([2.0 * a - 1.0, 0.0, 2.0 * b - 1.0], [0.0, 1.0, 0.0]),
            1..=3 => ([1.6 * a - 0.8, 0.0, 1.6 * b - 0.8], [0.0, 1.0, 0.0]),
            4 => ([2.0 * a - 1.0, 1.9 * b, -1.0], [0.0, 0.0, 1.0]),
            5 => ([-1.0, 1.9 * b, 2.0 * a - 1.0], [1.0, 0.0, 0.0]),
            _ => {
                // A box face other than the bottom.
                let (f, nrm) = faces[6 * (k % 2) + 1 + (u() * 5.0) as usize];
                let [e1, e2] = f.edges();
                let (p, q) = (0.01 + 0.98 * a, 0.01 + 0.98 * b);
                let x = core::array::from_fn(|j| f.corner()[j] + p * e1[j] + q * e2[j]);
                (x, nrm)
            }
        };
        if inside(x) {
            continue;
        }
        let front = faces
            .iter()
            .filter(|(f, nrm)| dot(sub(x, f.corner()), *nrm) > 0.0)
            .map(|(f, _)| *f)
            .collect();
        out.push(Receiver { x, n, faces: front });
    }
    out
}

/// The bench's lines: stratified directions (`f32` and `f64`) and, per
/// receiver, random offsets in the light's offset range.
struct Lines {
    cs: Vec<f32>,
    ss: Vec<f32>,
    cs64: Vec<f64>,
    ss64: Vec<f64>,
    offsets: Vec<Vec<f32>>,
}

/// The light, the receivers with their shadows on it, and the generator
/// the lines' offsets continue from.
fn scene() -> (QuadLight, Vec<Receiver>, Vec<Vec<Shadow>>, Pcg32) {
    let light = QuadLight::new([-0.24, 1.98, -0.22], [0.47, 0.0, 0.0], [0.0, 0.0, 0.38]).unwrap();
    let mut faces = box_faces([0.33, 0.0, 0.30], [0.6, 0.6, 0.6], -17.0);
    faces.extend(box_faces([-0.33, 0.0, -0.28], [0.6, 1.2, 0.6], 17.0));
    let mut rng = Pcg32::new(2017, 7);
    let recs = receivers(&faces, &mut rng);
    let shadows: Vec<Vec<Shadow>> = recs
        .iter()
        .map(|r| {
            let mut s = vec![Shadow::EMPTY; r.faces.len()];
            let k = Shadow::project_all(&light, r.x, &r.faces, &mut s).unwrap();
            s.truncate(k);
            s
        })
        .collect();
    (light, recs, shadows, rng)
}

/// The [`Lines`] of `light`, offsets drawn from `rng`.
fn lines(light: &QuadLight, rng: &mut Pcg32) -> Lines {
    let mut cs = vec![0.0f32; LINES];
    let mut ss = vec![0.0f32; LINES];
    let mut cs64 = vec![0.0f64; LINES];
    let mut ss64 = vec![0.0f64; LINES];
    for k in 0..LINES {
        let phi = PI * (k as f64 + 0.5) / LINES as f64;
        (ss64[k], cs64[k]) = phi.sin_cos();
        cs[k] = cs64[k] as f32;
        ss[k] = ss64[k] as f32;
    }
    let offsets: Vec<Vec<f32>> = (0..RECEIVERS)
        .map(|_| {
            (0..LINES)
                .map(|k| {
                    let (lo, hi) = light.offset_range(f64::from(cs[k]), f64::from(ss[k]));
                    (lo + (hi - lo) * f64::from(rng.next_u32()) / 4_294_967_296.0) as f32
                })
                .collect()
        })
        .collect();
    Lines {
        cs,
        ss,
        cs64,
        ss64,
        offsets,
    }
}

/// The `f64` path of one line: `QuadLight::chord` + `DirectLight::line`.
fn line64(
    light: &QuadLight,
    dl: &DirectLight,
    c: f64,
    s: f64,
    o: f64,
    scratch: &mut [(f64, f64)],
) -> f64 {
    match light.chord(c, s, o) {
        Some(ch) => dl.line(&ch, scratch).unwrap(),
        None => 0.0,
    }
}

/// Prints the largest `|f32 − f64|` over the bench's lines, relative to
/// the largest value.
fn accuracy(
    light: &QuadLight,
    shadows: &[Vec<Shadow>],
    dls: &[DirectLight],
    dl32s: &[DirectLight32<CAP>],
    l: &Lines,
) {
    let max_scratch = shadows.iter().map(Vec::len).max().unwrap_or(0);
    let mut scratch = vec![(0.0, 0.0); max_scratch];
    let mut out = vec![0.0f32; LINES];
    let (mut worst, mut largest, mut hits) = (0.0f64, 0.0f64, 0usize);
    for ((dl, dl32), offsets) in dls.iter().zip(dl32s).zip(&l.offsets) {
        dl32.line_batch_f32(&l.cs, &l.ss, offsets, &mut out)
            .unwrap();
        for (k, &v) in out.iter().enumerate() {
            let (c, s, o) = (
                f64::from(l.cs[k]),
                f64::from(l.ss[k]),
                f64::from(offsets[k]),
            );
            let len = c.hypot(s);
            let want = line64(light, dl, c / len, s / len, o / len, &mut scratch);
            worst = worst.max((f64::from(v) - want).abs());
            largest = largest.max(want);
            hits += usize::from(want > 0.0);
        }
    }
    println!(
        "{RECEIVERS} receivers × {LINES} lines ({} shadows per receiver on average, {:.0} % of \
         the lines lit): max |f32 − f64| = {:.2e} of the largest value",
        shadows.iter().map(Vec::len).sum::<usize>() as f64 / RECEIVERS as f64,
        100.0 * hits as f64 / (RECEIVERS * LINES) as f64,
        worst / largest
    );
}

/// The visibility + integral kernel, lines per second: `f64`, the `f32`
/// scalar twin and the `f32` SIMD batch.
fn line_kernel(
    c: &mut Criterion,
    light: &QuadLight,
    max_scratch: usize,
    dls: &[DirectLight],
    dl32s: &[DirectLight32<CAP>],
    l: &Lines,
) {
    let mut scratch = vec![(0.0, 0.0); max_scratch];
    let mut out = vec![0.0f32; LINES];
    let total = (RECEIVERS * LINES) as u64;
    let mut g = c.benchmark_group("direct light line kernel (visibility + integral)");
    g.throughput(Throughput::Elements(total));
    g.bench_function(
        BenchmarkId::new("f64 (chord + DirectLight::line)", total),
        |b| {
            b.iter(|| {
                let mut sum = 0.0;
                for (dl, offsets) in dls.iter().zip(&l.offsets) {
                    for ((&c, &s), &o) in l.cs64.iter().zip(&l.ss64).zip(offsets) {
                        sum += line64(light, dl, black_box(c), s, f64::from(o), &mut scratch);
                    }
                }
                sum
            })
        },
    );
    g.bench_function(
        BenchmarkId::new("f32 scalar twin (line_batch_scalar_f32)", total),
        |b| {
            b.iter(|| {
                for (dl32, offsets) in dl32s.iter().zip(&l.offsets) {
                    dl32.line_batch_scalar_f32(black_box(&l.cs), &l.ss, offsets, &mut out)
                        .unwrap();
                }
                out[LINES - 1]
            })
        },
    );
    g.bench_function(
        BenchmarkId::new("f32 SIMD batch (line_batch_f32)", total),
        |b| {
            b.iter(|| {
                for (dl32, offsets) in dl32s.iter().zip(&l.offsets) {
                    dl32.line_batch_f32(black_box(&l.cs), &l.ss, offsets, &mut out)
                        .unwrap();
                }
                out[LINES - 1]
            })
        },
    );
    g.finish();
}

/// The per-receiver set-up, receivers per second.
fn per_receiver(c: &mut Criterion, light: &QuadLight, recs: &[Receiver]) {
    let mut g = c.benchmark_group("direct light set-up per receiver");
    g.throughput(Throughput::Elements(RECEIVERS as u64));
    let mut buf = vec![Shadow::EMPTY; 12];
    g.bench_function("Shadow::project_all + DirectLight::new", |b| {
        b.iter(|| {
            let mut h = 0.0;
            for r in recs {
                let k = Shadow::project_all(light, black_box(r.x), &r.faces, &mut buf).unwrap();
                h += DirectLight::new(light, r.x, r.n, &buf[..k])
                    .unwrap()
                    .height();
            }
            h
        })
    });
    g.bench_function(
        "Shadow::project_all + DirectLight::new + DirectLight32::new",
        |b| {
            b.iter(|| {
                let mut m = 0usize;
                for r in recs {
                    let k = Shadow::project_all(light, black_box(r.x), &r.faces, &mut buf).unwrap();
                    let dl = DirectLight::new(light, r.x, r.n, &buf[..k]).unwrap();
                    m += dl.shadows().len();
                    m += DirectLight32::<CAP>::new(light, r.x, r.n, &buf[..k])
                        .unwrap()
                        .shadow_count();
                }
                m
            })
        },
    );
    g.finish();
}

/// Every group, in order, after the accuracy line.
fn direct_light(c: &mut Criterion) {
    let (light, recs, shadows, mut rng) = scene();
    let dls: Vec<DirectLight> = recs
        .iter()
        .zip(&shadows)
        .map(|(r, s)| DirectLight::new(&light, r.x, r.n, s).unwrap())
        .collect();
    let dl32s: Vec<DirectLight32<CAP>> = recs
        .iter()
        .zip(&shadows)
        .map(|(r, s)| DirectLight32::new(&light, r.x, r.n, s).unwrap())
        .collect();
    let l = lines(&light, &mut rng);
    accuracy(&light, &shadows, &dls, &dl32s, &l);
    let max_scratch = shadows.iter().map(Vec::len).max().unwrap_or(0);
    line_kernel(c, &light, max_scratch, &dls, &dl32s, &l);
    per_receiver(c, &light, &recs);
}

criterion_group!(benches, direct_light);
criterion_main!(benches);
