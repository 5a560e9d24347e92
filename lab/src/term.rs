//! Printing that never panics: `println!` panics when stdout is a closed pipe
//! (`linesample-lab … | head -1`), which would abort a run whose files are
//! already written or still to be computed. [`crate::out!`] and [`crate::err!`] write a
//! line and ignore write errors, so a reader that stops early only loses
//! text.

use std::fmt::Arguments;
use std::io::Write;

/// Writes `args` and a newline to stdout, ignoring errors.
pub fn out_line(args: Arguments<'_>) {
    let _ = writeln!(std::io::stdout().lock(), "{args}");
}

/// Writes `args` and a newline to stderr, ignoring errors.
pub fn err_line(args: Arguments<'_>) {
    let _ = writeln!(std::io::stderr().lock(), "{args}");
}

/// `println!` that ignores a closed stdout.
#[macro_export]
macro_rules! out {
    ($($t:tt)*) => {
        $crate::term::out_line(format_args!($($t)*))
    };
}

/// `eprintln!` that ignores a closed stderr.
#[macro_export]
macro_rules! err {
    ($($t:tt)*) => {
        $crate::term::err_line(format_args!($($t)*))
    };
}
