//! The paper's AO scene, shared by `scene/tests/occlusion.rs` and
//! `scene/benches/occlusion.rs` (included there by path).

/// The paper's AO scene (Singh, Miller & Jarosz 2017, from their pbrt-v3
/// scene): centres and radii, the last the ground.
pub const SCENE: [([f64; 3], f64); 8] = [
    ([0.75, 0.125, 7.0], 0.125),
    ([1.25, 0.25, 6.0], 0.25),
    ([1.75, 0.6, 4.0], 0.5),
    ([1.0, 1.5, 0.0], 1.0),
    ([-1.5, 2.5, -2.0], 1.25),
    ([-4.5, 3.5, -2.5], 1.5),
    ([0.0, 0.75, 4.0], 0.75),
    ([0.0, -1000.0, 0.0], 1000.0),
];

/// [`SCENE`] as kernel spheres.
pub fn spheres() -> Vec<linesample::world::Sphere<3>> {
    SCENE
        .iter()
        .map(|&(c, r)| linesample::world::Sphere::new(c, r).unwrap())
        .collect()
}
