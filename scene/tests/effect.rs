//! The scene layer: the model's geometry, the worlds built from a scene
//! through [`Effect`], and what each effect's rules say.

use linesample::Seed;
use linesample_scene::ao::world::{ao_lines, EstimatorSpec, World};
use linesample_scene::ao::CentrePdf;
use linesample_scene::camera::Camera;
use linesample_scene::caustic::world::{
    CausticWorld, Estimator as CausticEstimator, Photons, REFERENCE,
};
use linesample_scene::direct_light::world::{DlEstimator, DlWorld};
use linesample_scene::model::{
    BoxDef, CausticScene, EffectParams, Estimators, FluenceDef, LightDef, Orientation, Primitive,
    QuadDef, Scene, SceneSampler, SphereDef,
};
use linesample_scene::{CameraEffect, Effect, Error};

fn camera() -> Camera {
    Camera {
        from: [0.0, 5.0, 0.001],
        at: [0.0, 0.0, 0.0],
        up: [0.0, 1.0, 0.0],
        fov_deg: 30.0,
        width: 32,
        height: 32,
    }
}

fn ao_scene(spheres: Vec<SphereDef>) -> Scene {
    Scene {
        camera: camera(),
        spheres,
        quads: Vec::new(),
        boxes: Vec::new(),
        light: None,
        effect: EffectParams::AmbientOcclusion {
            max_distance: 100.0,
        },
        estimators: Estimators::default(),
    }
}

/// A floor `[-1, 1]²` at `y = 0`, a `0.4 × 0.4` light facing down at
/// `y = 2`, and the given extra quads.
fn dl_scene(panels: Vec<QuadDef>) -> Scene {
    let mut quads = vec![QuadDef {
        corner: [-1.0, 0.0, -1.0],
        edge1: [0.0, 0.0, 2.0],
        edge2: [2.0, 0.0, 0.0],
        albedo: [0.5; 3],
    }];
    quads.extend(panels);
    Scene {
        camera: camera(),
        spheres: Vec::new(),
        quads,
        boxes: Vec::new(),
        light: Some(LightDef {
            corner: [-0.2, 2.0, -0.2],
            edge1: [0.4, 0.0, 0.0],
            edge2: [0.0, 0.0, 0.4],
            radiance: [1.0; 3],
        }),
        effect: EffectParams::DirectLight,
        estimators: Estimators::default(),
    }
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Each face's `edge1 × edge2` points away from the box's centre and has
/// the face's area, and the six area vectors of a closed box sum to zero.
#[test]
fn box_faces_are_outward_and_close_the_box() {
    for rot in [0.0, 17.0, 90.0, -33.0, 180.0] {
        let b = BoxDef {
            base: [0.3, 0.1, -0.2],
            size: [0.6, 1.2, 0.4],
            rotation_deg: rot,
            albedo: [0.5; 3],
        };
        let centre = [b.base[0], b.base[1] + 0.5 * b.size[1], b.base[2]];
        let mut sum = [0.0f64; 3];
        let mut area = 0.0;
        for (c, e1, e2) in b.faces() {
            let n = cross(e1, e2);
            let mid: Vec<f64> = (0..3).map(|k| c[k] + 0.5 * (e1[k] + e2[k])).collect();
            let out: f64 = (0..3).map(|k| n[k] * (mid[k] - centre[k])).sum();
            assert!(out > 0.0, "rotation {rot}: a face's normal points inwards");
            for k in 0..3 {
                sum[k] += n[k];
            }
            area += (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        }
        let (w, h, d) = (b.size[0], b.size[1], b.size[2]);
        let want = 2.0 * (w * h + w * d + h * d);
        assert!(
            (area - want).abs() < 1e-14 * want,
            "rotation {rot}: area {area}"
        );
        assert!(
            sum.iter().all(|s| s.abs() < 1e-15),
            "rotation {rot}: {sum:?}"
        );
    }
}

/// A world refuses a scene of the other effect, a direct-light scene
/// without a light, and geometry the kernel refuses, naming the item.
#[test]
fn worlds_refuse_what_they_cannot_build() {
    let ao = ao_scene(vec![SphereDef {
        centre: [0.0, -1.0, 0.0],
        radius: 1.0,
    }]);
    assert!(matches!(
        DlWorld::from_scene(ao.clone()),
        Err(Error::WrongEffect { .. })
    ));
    assert!(matches!(
        World::from_scene(dl_scene(Vec::new())),
        Err(Error::WrongEffect { .. })
    ));
    let mut dark = dl_scene(Vec::new());
    dark.light = None;
    assert!(matches!(
        DlWorld::from_scene(dark),
        Err(Error::WrongEffect { .. })
    ));
    let mut bad = ao.clone();
    bad.spheres.push(SphereDef {
        centre: [0.0; 3],
        radius: 0.0,
    });
    let e = World::from_scene(bad).unwrap_err();
    assert!(
        matches!(
            e,
            Error::Item {
                what: "sphere",
                index: 1,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(e.to_string().starts_with("sphere[1]: "), "{e}");
    let mut flat = dl_scene(Vec::new());
    flat.quads[0].edge2 = flat.quads[0].edge1;
    let e = DlWorld::from_scene(flat).unwrap_err();
    assert!(
        matches!(
            e,
            Error::Item {
                what: "quad",
                index: 0,
                ..
            }
        ),
        "{e:?}"
    );
}

/// AO through the trait: on a lone sphere nothing occludes the top, so
/// every estimator of every density gives exactly 1 there (the
/// normalisation); next to a second sphere the line estimator from samples
/// `u` is the mean of the whole lines at `φ = πu`, as `ao_lines` computes
/// them on its own path.
#[test]
fn ao_estimates_through_the_trait() {
    let ground = SphereDef {
        centre: [0.0, -1.0, 0.0],
        radius: 1.0,
    };
    let world = World::from_scene(ao_scene(vec![ground])).unwrap();
    let px = CameraEffect::pixel(&world, 16, 16).expect("the centre pixel sees the sphere");
    let mut scratch = Effect::scratch(&world);
    let samples: Vec<[f32; 2]> = (0..16)
        .map(|k| [(k as f32 + 0.5) / 16.0, ((k * 7) % 16) as f32 / 16.0 + 0.01])
        .collect();
    for primitive in [Primitive::Points, Primitive::Segments, Primitive::Lines] {
        for pdf in [CentrePdf::Uniform, CentrePdf::SolidAngle, CentrePdf::Cosine] {
            let est = EstimatorSpec {
                primitive,
                length: if primitive == Primitive::Segments {
                    0.5
                } else {
                    0.0
                },
                pdf,
                sampler: SceneSampler::Jittered,
                simd: false,
            };
            let v =
                Effect::estimate(&world, &px, &est, &samples, Seed::new(1), &mut scratch).unwrap();
            // Lines: the visible measure of a whole unoccluded line is 1.
            // Cosine points: g/p is 1 at every sample (p ∝ g). The others
            // are means of g/p, exact only in expectation.
            if primitive == Primitive::Lines
                || (pdf == CentrePdf::Cosine && primitive == Primitive::Points)
            {
                assert!((v - 1.0).abs() < 1e-12, "{primitive:?} {pdf:?}: {v}");
            } else {
                assert!(v.is_finite() && v > 0.0, "{primitive:?} {pdf:?}: {v}");
            }
        }
    }
    let near = SphereDef {
        centre: [0.35, 0.25, 0.0],
        radius: 0.3,
    };
    let scene = ao_scene(vec![ground, near]);
    let spheres = scene.kernel_spheres().unwrap();
    let world = World::from_scene(scene).unwrap();
    let px = world.pixel(16, 16).unwrap();
    let mut scratch = world.scratch();
    let lines = EstimatorSpec {
        primitive: Primitive::Lines,
        length: 0.0,
        pdf: CentrePdf::Uniform,
        sampler: SceneSampler::Jittered,
        simd: false,
    };
    let v = Effect::estimate(&world, &px, &lines, &samples, Seed::new(1), &mut scratch).unwrap();
    let phis: Vec<f64> = samples
        .iter()
        .map(|s| std::f64::consts::PI * f64::from(s[0]))
        .collect();
    let want = ao_lines(&spheres, 100.0, px.frame.point, px.frame.normal, &phis).unwrap();
    assert!(want < 0.999, "the second sphere must occlude: {want}");
    assert!((v - want).abs() < 1e-12, "{v} vs {want}");
}

/// The effects' shift rules: AO shifts every pattern (the reference's too)
/// unless told not to; direct light shifts only Sobol′ by default and never
/// its reference.
#[test]
fn shift_rules() {
    let ao = EstimatorSpec {
        primitive: Primitive::Points,
        length: 0.0,
        pdf: CentrePdf::Uniform,
        sampler: SceneSampler::Jittered,
        simd: false,
    };
    assert!(World::shifted(None, None));
    assert!(World::shifted(Some(&ao), None));
    assert!(!World::shifted(Some(&ao), Some(false)));
    assert!(!World::shifted(None, Some(false)));
    let dl = |sampler| DlEstimator {
        lines: Some(Orientation::Edge1),
        sampler,
        simd: false,
    };
    assert!(!DlWorld::shifted(None, None));
    assert!(!DlWorld::shifted(None, Some(true)));
    assert!(!DlWorld::shifted(Some(&dl(SceneSampler::Jittered)), None));
    assert!(DlWorld::shifted(Some(&dl(SceneSampler::Sobol)), None));
    assert!(DlWorld::shifted(
        Some(&dl(SceneSampler::Jittered)),
        Some(true)
    ));
    assert!(!DlWorld::shifted(
        Some(&dl(SceneSampler::Sobol)),
        Some(false)
    ));
    let dlw = DlWorld::from_scene(dl_scene(Vec::new())).unwrap();
    let aow = World::from_scene(ao_scene(vec![SphereDef {
        centre: [0.0, -100.0, 0.0],
        radius: 100.0,
    }]))
    .unwrap();
    assert_eq!(dlw.dims(&dl(SceneSampler::Jittered)), 1);
    assert_eq!(
        dlw.dims(&DlEstimator {
            lines: Some(Orientation::Stratified),
            ..dl(SceneSampler::Jittered)
        }),
        2
    );
    assert_eq!(aow.dims(&ao), 2);
    assert_eq!(
        aow.dims(&EstimatorSpec {
            primitive: Primitive::Lines,
            ..ao
        }),
        1
    );
}

/// A free-standing panel just under the light hides all of it from the
/// floor point below: the hidden fraction is 1 and every estimate 0. Without
/// the panel nothing is hidden: the `f32` lines are their `f64` twins within
/// the batch's bound away from boundaries (about `100 ε₃₂`, the module
/// docs), and points and lines on midpoint rules are Lambert's exact value
/// within the midpoint rule's own error bound.
#[test]
fn a_free_standing_quad_casts_its_shadow() {
    let panel = QuadDef {
        corner: [-0.5, 1.9, -0.5],
        edge1: [1.0, 0.0, 0.0],
        edge2: [0.0, 0.0, 1.0],
        albedo: [0.5; 3],
    };
    // Points: the 16 × 16 midpoint grid of the light; lines: 16 midpoint
    // offsets (the second coordinate is unused).
    const M: usize = 16;
    let mid = |k: usize| (k as f32 + 0.5) / M as f32;
    let grid: Vec<[f32; 2]> = (0..M * M).map(|k| [mid(k / M), mid(k % M)]).collect();
    let offsets: Vec<[f32; 2]> = (0..M).map(|k| [mid(k), 0.5]).collect();
    let ests = [
        DlEstimator {
            lines: None,
            sampler: SceneSampler::Jittered,
            simd: false,
        },
        DlEstimator {
            lines: Some(Orientation::Edge1),
            sampler: SceneSampler::Jittered,
            simd: false,
        },
        DlEstimator {
            lines: Some(Orientation::Edge1),
            sampler: SceneSampler::Jittered,
            simd: true,
        },
    ];
    for (with_panel, hidden_want) in [(true, 1.0), (false, 0.0)] {
        let panels = if with_panel { vec![panel] } else { Vec::new() };
        let world = DlWorld::from_scene(dl_scene(panels)).unwrap();
        let px = world.surface_point([0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.5; 3], Some(0));
        let hidden = world.hidden_fraction(&px, 64).unwrap();
        assert!(
            (hidden - hidden_want).abs() < 1e-12,
            "panel {with_panel}: hidden {hidden}"
        );
        assert_eq!(
            Effect::extra(&world, &px).unwrap(),
            Some(hidden as f32),
            "the extra quantity is the hidden fraction"
        );
        let mut scratch = world.scratch();
        let vs: Vec<f64> = ests
            .iter()
            .map(|e| {
                let samples = if e.lines.is_none() { &grid } else { &offsets };
                Effect::estimate(&world, &px, e, samples, Seed::new(3), &mut scratch).unwrap()
            })
            .collect();
        if with_panel {
            assert!(vs.iter().all(|&v| v == 0.0), "{vs:?}");
        } else {
            let f32_bound = 100.0 * f64::from(f32::EPSILON) * vs[1];
            assert!(vs[1] > 0.0 && (vs[2] - vs[1]).abs() <= f32_bound, "{vs:?}");
            let (exact, points_bound, lines_bound) = unshadowed(0.2, 2.0, M);
            assert!(
                (vs[0] - exact).abs() <= points_bound,
                "points {vs:?} vs {exact}"
            );
            assert!(
                (vs[1] - exact).abs() <= lines_bound,
                "lines {vs:?} vs {exact}"
            );
        }
    }
}

/// The floor point's unshadowed integral `E = ∫ h²/(x² + z² + h²)² dA` over
/// the light `[−a, a]²` at height `h` (both facing each other, so
/// `cos θ = cos θ' = h/r`), by Lambert's formula in its rectangle-corner
/// form `E = 4F(a, a)`, `F(X, Z) = ½[X/p · atan(Z/p) + Z/q · atan(X/q)]`,
/// `p = √(X² + h²)`, `q = √(Z² + h²)`; with the error bounds of the
/// midpoint rules on `m` strata per side (step `δ = 2a/m`): lines integrate
/// `x` exactly, so `|E_m − E| ≤ 2a δ² max|g''|/24` for the line integral
/// `g(z)`; points `≤ 4a² δ² (max|f_xx| + max|f_zz|)/24`. The second
/// derivatives are maxima of central differences (step `10⁻⁴`) over a fine
/// grid, with a 1 % margin for the differencing.
fn unshadowed(a: f64, h: f64, m: usize) -> (f64, f64, f64) {
    let corner = |x: f64, z: f64| {
        let (p, q) = ((x * x + h * h).sqrt(), (z * z + h * h).sqrt());
        0.5 * (x / p * (z / p).atan() + z / q * (x / q).atan())
    };
    let exact = 4.0 * corner(a, a);
    // g(z) = ∫_{−a}^{a} h²/(x² + c²)² dx, c² = z² + h².
    let g = |z: f64| {
        let c = (z * z + h * h).sqrt();
        2.0 * h * h * (a / (2.0 * c * c * (a * a + c * c)) + (a / c).atan() / (2.0 * c * c * c))
    };
    let f = |x: f64, z: f64| h * h / (x * x + z * z + h * h).powi(2);
    let d = 1e-4;
    let second = |v: &dyn Fn(f64) -> f64, t: f64| (v(t + d) - 2.0 * v(t) + v(t - d)) / (d * d);
    let ts: Vec<f64> = (0..=200)
        .map(|i| -a + 2.0 * a * f64::from(i) / 200.0)
        .collect();
    let g2 = ts.iter().map(|&t| second(&g, t).abs()).fold(0.0, f64::max);
    let mut f2 = 0.0f64;
    for &x in &ts {
        for &z in &ts {
            let fxx = second(&|t| f(t, z), x).abs();
            let fzz = second(&|t| f(x, t), z).abs();
            f2 = f2.max(fxx + fzz);
        }
    }
    let step = 2.0 * a / m as f64;
    let lines = 1.01 * 2.0 * a * step * step * g2 / 24.0;
    let points = 1.01 * 4.0 * a * a * step * step * f2 / 24.0;
    (exact, points, lines)
}

/// The shipped 2D caustic scene (`scenes/caustic-2d.toml`) in `dims`
/// dimensions (3D: the same numbers with `z = 0`).
fn caustic_scene(dims: usize) -> CausticScene {
    CausticScene {
        dims,
        light: [0.0, 2.0, 0.0],
        axis: [0.0, -1.0, 0.0],
        cone_deg: 18.0,
        glass_centre: [0.0; 3],
        glass_radius: 0.5,
        ior: 1.5,
        fresnel: true,
        internal_reflections: 2,
        sigma_s: 0.5,
        sigma_a: 0.1,
        query_centre: [0.05, -1.0, 0.0],
        query_radius: 0.2,
        fluence: FluenceDef {
            centre: [0.0, -0.4, 0.0],
            size: [3.2, 3.2],
            width: 8,
            height: 8,
            beams: 64,
            thickness: (dims == 3).then_some(0.1),
        },
        samplers: vec![SceneSampler::Random, SceneSampler::Jittered],
    }
}

/// The caustic through the trait: each estimator reads as many coordinates
/// as [`Effect::dims`] says (points `D`, beams `D − 1`) and ignores the
/// rest, its estimate is the mean of the kernel's photon of each sample,
/// and only Sobol′ patterns shift by default (never the reference).
#[test]
fn caustic_estimates_through_the_trait() {
    for dims in [2, 3] {
        let world = CausticWorld::from_scene(caustic_scene(dims)).unwrap();
        assert_eq!(CausticWorld::KIND, "volumetric-caustic");
        let points = CausticEstimator {
            photons: Photons::Points,
            sampler: SceneSampler::Jittered,
        };
        let beams = CausticEstimator {
            photons: Photons::Beams,
            ..points
        };
        assert_eq!(world.dims(&points), dims);
        assert_eq!(world.dims(&beams), dims - 1);
        // A 64 × 64 midpoint grid of the coordinates each estimator reads;
        // the unused ones set to `pad`.
        let grid = |est: &CausticEstimator, pad: f32| -> Vec<[f32; 3]> {
            let k = world.dims(est);
            (0..4096)
                .map(|i| {
                    let c = [(i % 64) as f32, (i / 64) as f32, ((i * 37) % 64) as f32];
                    core::array::from_fn(|j| if j < k { (c[j] + 0.5) / 64.0 } else { pad })
                })
                .collect()
        };
        world.scratch(); // the caustic needs none: `()`
        for est in [points, beams] {
            let a = world
                .estimate(&(), &est, &grid(&est, 0.5), Seed::new(1), &mut ())
                .unwrap();
            let b = world
                .estimate(&(), &est, &grid(&est, 0.9), Seed::new(2), &mut ())
                .unwrap();
            assert_eq!(
                a,
                b,
                "{dims}D {}: unused coordinates changed it",
                est.label()
            );
            assert!(a.is_finite() && a > 0.0, "{dims}D {}: {a}", est.label());
        }
        // The beams' estimate is the kernel's mean, in the same order.
        let s = grid(&beams, 0.5);
        let want = match dims {
            2 => {
                let k = caustic_scene(2).kernel::<2>().unwrap();
                s.iter()
                    .map(|p| k.beam_sample([f64::from(p[0]), 0.0]))
                    .sum::<f64>()
            }
            _ => {
                let k = caustic_scene(3).kernel::<3>().unwrap();
                s.iter()
                    .map(|p| k.beam_sample([f64::from(p[0]), f64::from(p[1])]))
                    .sum::<f64>()
            }
        } / 4096.0;
        let got = world
            .estimate(&(), &beams, &s, Seed::new(3), &mut ())
            .unwrap();
        assert_eq!(got, want, "{dims}D beams");
        assert_eq!(
            world
                .estimate(&(), &beams, &[], Seed::new(4), &mut ())
                .unwrap(),
            0.0
        );
    }
    let sobol = CausticEstimator {
        photons: Photons::Points,
        sampler: SceneSampler::Sobol,
    };
    let jit = CausticEstimator {
        sampler: SceneSampler::Jittered,
        ..sobol
    };
    assert!(!CausticWorld::shifted(None, Some(true)));
    assert!(CausticWorld::shifted(Some(&sobol), None));
    assert!(!CausticWorld::shifted(Some(&jit), None));
    assert!(CausticWorld::shifted(Some(&jit), Some(true)));
    assert!(!CausticWorld::shifted(Some(&sobol), Some(false)));
    assert_eq!(CausticWorld::reference(), REFERENCE);
}
