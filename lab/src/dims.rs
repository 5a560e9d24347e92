//! The one place where a run-time dimension becomes const generics.

/// `with_dims!($d, $e, f(args))` calls `$f::<D, E>($args…)` for the point dimension `$d` and the sample
/// dimension `$e` (`E = D` for points and segments, `E = D − 1` for line
/// offsets), over the pairs the lab supports: (1,1), (2,2), (3,3), (2,1),
/// (3,2). Any other pair is an error naming both.
///
/// `with_dims!(domain $d, f(args))` calls `$f::<D, D − 1>` for a domain of
/// dimension 2 or 3 (estimators: `D` for points and segments, `D − 1` for line
/// offsets). It instantiates only the two pairs a domain needs, so the
/// kernel's generic estimator code is not also compiled for impossible pairs
/// (which measurably changed LLVM's inlining of the line estimator: 10 %
/// slower).
#[macro_export]
macro_rules! with_dims {
    (domain $d:expr, $f:ident($($arg:expr),* $(,)?)) => {
        match $d {
            2 => $f::<2, 1>($($arg),*),
            3 => $f::<3, 2>($($arg),*),
            d => Err(format!("internal error: a {d}-dimensional domain").into()),
        }
    };
    ($d:expr, $e:expr, $f:ident($($arg:expr),* $(,)?)) => {
        match ($d, $e) {
            (1, 1) => $f::<1, 1>($($arg),*),
            (2, 2) => $f::<2, 2>($($arg),*),
            (3, 3) => $f::<3, 3>($($arg),*),
            (2, 1) => $f::<2, 1>($($arg),*),
            (3, 2) => $f::<3, 2>($($arg),*),
            (d, e) => Err(format!(
                "internal error: no {e}-dimensional samples for {d}-dimensional points"
            ).into()),
        }
    };
}
