//! Fuzzes the volumetric-caustic kernel (`linesample_scene::caustic`) with
//! arbitrary lights, glass balls, media, query balls and samples: a rejected
//! parameter is fine; a panic, a NaN, or a value the physics forbids is not.
//!
//! Oracles (exact consequences of the definitions, up to a few ulp):
//! * a path has `1 ≤ len ≤ MAX_SEGMENTS` segments with finite origins, unit
//!   directions, weights in `[0, 1]` and starts `≥ 0`; the escaping weight is
//!   at most 1;
//! * the beam estimate is finite, `≥ 0`, and at most `σ_s/σ_t` (a photon
//!   scatters at most once in total);
//! * the point estimate is finite, `≥ 0`, and at most `σ_s/σ_t · Σ_k w_k`.
//!
//! Run: `cargo fuzz run --sanitizer none caustic`.

#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use linesample::world::Sphere;
use linesample_scene::caustic::{
    Caustic, ConeEmitter, Fresnel, Glass, Medium, PhotonPath, MAX_SEGMENTS,
};

const U: f64 = f64::EPSILON;

/// Raw values, mapped into the accepted ranges (so almost every input
/// reaches the tracer), then the whole scene scaled by `10^k`, `k ∈ −6 … 6`
/// (lengths up, coefficients down): huge and tiny scenes alike. `raw`
/// passes the values unmapped instead (the constructors must reject what
/// they do not accept, without panicking).
#[derive(Arbitrary, Debug)]
struct Case<const D: usize> {
    raw: bool,
    scale: u8,
    light: [f64; D],
    axis: [f64; D],
    cone: f64,
    glass: [f64; D],
    radius: f64,
    ior: f64,
    sigma: [f64; 2],
    query: [f64; D],
    query_radius: f64,
    fresnel: Option<u8>,
    samples: Vec<([f64; 2], f64)>,
}

#[derive(Arbitrary, Debug)]
enum Input {
    D2(Case<2>),
    D3(Case<3>),
}

fn check_path<const D: usize>(p: &PhotonPath<D>) -> f64 {
    let segs = p.segments();
    assert!(!segs.is_empty() && segs.len() <= MAX_SEGMENTS);
    let mut total = 0.0;
    for g in segs {
        let o = g.ray.origin();
        let d = g.ray.dir().get();
        assert!(o.iter().all(|x| x.is_finite()), "origin {o:?}");
        let n2: f64 = d.iter().map(|x| x * x).sum();
        assert!((n2 - 1.0).abs() <= 16.0 * U, "direction {d:?}");
        assert!(
            (0.0..=1.0 + 4.0 * U).contains(&g.weight),
            "weight {}",
            g.weight
        );
        assert!(g.start >= 0.0 && g.length >= 0.0, "{g:?}");
        total += g.weight;
    }
    assert!(
        p.escaping_weight() <= 1.0 + 16.0 * U,
        "{}",
        p.escaping_weight()
    );
    total
}

fn unit(x: f64) -> f64 {
    if x.is_finite() {
        x.abs().fract()
    } else {
        0.5
    }
}

fn run<const D: usize>(c: &Case<D>) {
    let k = f64::from(i32::from(c.scale % 13) - 6);
    let sc = 10f64.powf(k);
    let map = |v: &[f64; D]| -> [f64; D] {
        if c.raw {
            *v
        } else {
            core::array::from_fn(|j| (unit(v[j]) - 0.5) * 8.0 * sc)
        }
    };
    let pick = |raw: f64, mapped: f64| if c.raw { raw } else { mapped };
    let cone = pick(c.cone, (0.01 + 0.99 * unit(c.cone)) * core::f64::consts::PI);
    let radius = pick(c.radius, 10f64.powf(-3.0 + 3.5 * unit(c.radius)) * sc);
    let ior = pick(c.ior, 1.0 + 3.0 * unit(c.ior));
    let sigma_s = pick(c.sigma[0], 10f64.powf(-3.0 + 5.0 * unit(c.sigma[0])) / sc);
    let sigma_a = pick(c.sigma[1], 10f64.powf(-3.0 + 5.0 * unit(c.sigma[1])) / sc);
    let query_radius = pick(
        c.query_radius,
        10f64.powf(-4.0 + 4.5 * unit(c.query_radius)) * sc,
    );
    let Ok(light) = ConeEmitter::<D>::new(map(&c.light), c.axis, cone) else {
        return;
    };
    let Ok(glass) = Glass::<D>::new(map(&c.glass), radius, ior) else {
        return;
    };
    let Ok(medium) = Medium::new(sigma_s, sigma_a) else {
        return;
    };
    let Ok(query) = Sphere::<D>::new(map(&c.query), query_radius) else {
        return;
    };
    let fresnel = match c.fresnel {
        None => Fresnel::Off,
        Some(k) => Fresnel::On {
            internal_reflections: u32::from(k % 10),
        },
    };
    let Ok(scene) = Caustic::new(light, glass, medium, query, fresnel) else {
        return;
    };
    let albedo = medium.sigma_s() / medium.sigma_t();
    for (u, s) in c.samples.iter().take(64) {
        let u = [unit(u[0]), unit(u[1])];
        let path = scene.path(u);
        let total = check_path(&path);
        let beam = scene.beam(&path);
        assert!(
            beam.is_finite() && beam >= 0.0 && beam <= albedo * (1.0 + 64.0 * U),
            "beam {beam:e}, albedo {albedo:e}"
        );
        let point = scene.point(&path, unit(*s));
        assert!(
            point.is_finite() && point >= 0.0 && point <= albedo * total * (1.0 + 16.0 * U),
            "point {point:e}"
        );
    }
}

fuzz_target!(|input: Input| match input {
    Input::D2(c) => run(&c),
    Input::D3(c) => run(&c),
});
