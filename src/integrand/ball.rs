//! Ball integrand (stub: being implemented).
#![allow(unused_variables, clippy::all)]

use super::{Complex, Integrand};
use crate::error::ParamError;
use crate::geom::Direction;
use crate::primitive::Rays32;

/// Ball integrand (stub).
#[derive(Clone, Copy, Debug)]
pub struct Ball<const D: usize> {
    _p: [f64; D],
}

impl<const D: usize> Integrand<D> for Ball<D> {
    fn value_free(&self, x: &[f64; D]) -> f64 {
        unimplemented!()
    }
    fn segment_free(&self, p: &[f64; D], dir: &Direction<D>, t0: f64, t1: f64) -> f64 {
        unimplemented!()
    }
    fn segment_free_f32(&self, o: [f32; D], d: [f32; D], t0: f32, t1: f32) -> f32 {
        unimplemented!()
    }
    fn segment_free_batch_f32(
        &self,
        rays: &Rays32<'_, D>,
        out: &mut [f32],
    ) -> Result<(), ParamError> {
        unimplemented!()
    }
    fn value(&self, x: &[f64; D]) -> f64 {
        unimplemented!()
    }
    fn integral(&self) -> f64 {
        unimplemented!()
    }
    fn piece_integral(&self, p: &[f64; D], dir: &Direction<D>, t0: f64, t1: f64) -> f64 {
        unimplemented!()
    }
    fn max_value(&self) -> f64 {
        unimplemented!()
    }
    fn fourier(&self, k: &[i32; D]) -> Complex {
        unimplemented!()
    }
}
