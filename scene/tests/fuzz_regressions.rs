//! Inputs the fuzzers found in the effects (fuzz/fuzz_targets/caustic.rs),
//! kept as unit tests so every CI run checks them.

/// `caustic` fuzz target: a light 1.7e32 away from a glass ball of radius 7e-9
/// at −7.7e15. The ball is below `f64`'s resolution at that distance: the
/// computed entry point lay 10¹⁶ radii off the sphere, and the exit normal,
/// `(p − c)/r` with `p − c` underflowing to zero, was NaN. Such a photon now
/// passes the ball untouched: every direction is a unit vector.
#[test]
#[allow(clippy::excessive_precision)]
fn caustic_ball_below_the_scale_resolution_gives_no_nan() {
    use linesample::world::Sphere;
    use linesample_scene::caustic::{Caustic, ConeEmitter, Fresnel, Glass, Medium};
    let light = ConeEmitter::<2>::new(
        [1.6855791574909738e32, 2.598326e-317],
        [-7.469733515344477e304, 3.0517578124999997e-5],
        4.5464749174045745e-10,
    )
    .unwrap();
    let glass = Glass::<2>::new(
        [-7668389182680411.0, 5.9751104e-317],
        7.041529109796983e-9,
        1.985166331727569,
    )
    .unwrap();
    let medium = Medium::new(1.208981086533104e-23, 1.5147909700446086e-307).unwrap();
    let query = Sphere::<2>::new(
        [-4.2749537830014426e259, 3.5022215767669016e-260],
        2.5194700005352804e93,
    )
    .unwrap();
    let scene = Caustic::new(
        light,
        glass,
        medium,
        query,
        Fresnel::On {
            internal_reflections: 3,
        },
    )
    .unwrap();
    let path = scene.path([0.5, 2.3158576430456885e-23]);
    for s in path.segments() {
        let d = s.ray.dir().get();
        let n2: f64 = d.iter().map(|x| x * x).sum();
        assert!((n2 - 1.0).abs() <= 1e-15, "direction {d:?}");
    }
    assert!(scene.beam(&path).is_finite());
}
