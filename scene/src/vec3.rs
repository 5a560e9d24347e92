//! Three-vector helpers shared by the scene model, the schema and the
//! effects' worlds (plain `f64` arithmetic, one rounding per operation).

/// `a + b`.
#[inline]
pub(crate) fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `a − b`.
#[inline]
pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `s·a`.
#[inline]
pub(crate) fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// `a·b` (the kernel's [`linesample::geom::dot`], by value).
#[inline]
pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    linesample::geom::dot(&a, &b)
}

/// `a × b`.
#[inline]
pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `|a|²`.
#[inline]
pub(crate) fn norm2(a: [f64; 3]) -> f64 {
    dot(a, a)
}

/// `|a|` (correctly rounded square root of [`norm2`]).
#[inline]
pub(crate) fn norm(a: [f64; 3]) -> f64 {
    libm::sqrt(norm2(a))
}

/// `a/|a|`.
#[inline]
pub(crate) fn unit(a: [f64; 3]) -> [f64; 3] {
    let l = norm(a);
    [a[0] / l, a[1] / l, a[2] / l]
}
