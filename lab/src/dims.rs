//! The one place where a run-time dimension becomes const generics.

/// Calls `$f::<D, E>($args…)` for the point dimension `$d` and the sample
/// dimension `$e` (`E = D` for points and segments, `E = D − 1` for line
/// offsets), over the pairs the lab supports: (1,1), (2,2), (3,3), (2,1),
/// (3,2). Any other pair is an error naming both.
#[macro_export]
macro_rules! with_dims {
    ($d:expr, $e:expr, $f:ident($($arg:expr),* $(,)?)) => {
        match ($d, $e) {
            (1, 1) => $f::<1, 1>($($arg),*),
            (2, 2) => $f::<2, 2>($($arg),*),
            (3, 3) => $f::<3, 3>($($arg),*),
            (2, 1) => $f::<2, 1>($($arg),*),
            (3, 2) => $f::<3, 2>($($arg),*),
            (d, e) => Err(format!(
                "internal error: no {e}-dimensional samples for {d}-dimensional points"
            )),
        }
    };
}
