//! glam types through the world-space forms: `DVec3`/`DVec2` into the `f64`
//! constructors, `Vec3`/`Vec3A`/`Vec2` into the `f32` twins, with results
//! bit-identical to the array calls.

use linesample::glam::{DVec2, DVec3, Vec2, Vec3, Vec3A};
use linesample::world::{Direction, Gaussian, HalfSpace, Ray, Slab, Sphere};

#[test]
fn f64_constructors_take_dvec() {
    let c = DVec3::new(1e6, -2.0, 3.5);
    let s = Sphere::new(c, 2.0).unwrap();
    let sa = Sphere::new([1e6, -2.0, 3.5], 2.0).unwrap();
    assert_eq!(s, sa);
    let ray = Ray::new(DVec3::new(0.0, -1.0, 3.0), DVec3::new(1.0, 0.0, 0.0)).unwrap();
    let raya = Ray::new([0.0, -1.0, 3.0], [1.0, 0.0, 0.0]).unwrap();
    assert_eq!(ray, raya);
    assert_eq!(s.hit(&ray), sa.hit(&raya));
    assert_eq!(
        Ray::through(DVec3::ZERO, c).unwrap(),
        Ray::through([0.0; 3], [1e6, -2.0, 3.5]).unwrap()
    );
    assert_eq!(
        Direction::new(DVec2::new(3.0, 4.0)).unwrap().get(),
        [0.6, 0.8]
    );
    let g = Gaussian::with_peak(c, 0.5, 2.0).unwrap();
    let ga = Gaussian::with_peak([1e6, -2.0, 3.5], 0.5, 2.0).unwrap();
    assert_eq!(g.line(&ray).to_bits(), ga.line(&raya).to_bits());
    assert_eq!(
        HalfSpace::new(DVec3::Z, 1.0).unwrap(),
        HalfSpace::new([0.0, 0.0, 1.0], 1.0).unwrap()
    );
    assert_eq!(
        Slab::new(DVec2::Y, -1.0, 1.0).unwrap(),
        Slab::new([0.0, 1.0], -1.0, 1.0).unwrap()
    );
}

#[test]
fn f32_twins_take_vec3_vec3a_vec2() {
    let s = Sphere::new([1.0, 2.0, 3.0], 1.5).unwrap();
    let g = Gaussian::normalised([1.0, 2.0, 3.0], 0.7).unwrap();
    let h = HalfSpace::new([1.0, 1.0, 0.0], 0.5).unwrap();
    let o = [0.25f32, 1.5, -4.0];
    let d = [0.1f32, 0.05, 1.0];
    let want = s.segment_f32(o, d, 0.0, 9.0).to_bits();
    assert_eq!(
        s.segment_f32(Vec3::from(o), Vec3::from(d), 0.0, 9.0)
            .to_bits(),
        want
    );
    assert_eq!(
        s.segment_f32(Vec3A::from(o), Vec3A::from(d), 0.0, 9.0)
            .to_bits(),
        want
    );
    let want = g.transmittance_f32(o, d, 0.0, 9.0, 2.0).to_bits();
    assert_eq!(
        g.transmittance_f32(Vec3A::from(o), Vec3::from(d), 0.0, 9.0, 2.0)
            .to_bits(),
        want
    );
    assert_eq!(
        h.segment_f32(Vec3::from(o), Vec3A::from(d), 0.0, 9.0)
            .to_bits(),
        h.segment_f32(o, d, 0.0, 9.0).to_bits()
    );
    let disk = Sphere::new([0.0, 0.0], 1.0).unwrap();
    assert_eq!(
        disk.segment_f32(
            Vec2::new(-2.0, 0.5),
            Vec2::X,
            f32::NEG_INFINITY,
            f32::INFINITY
        )
        .to_bits(),
        disk.segment_f32([-2.0, 0.5], [1.0, 0.0], f32::NEG_INFINITY, f32::INFINITY)
            .to_bits()
    );
}
