//! Fuzzes the lab's point-file parser `linesample_lab::pointfile::parse_points`
//! on arbitrary text and on generated files.
//!
//! The parser's source file is compiled into this target directly (it needs
//! only `std` and the kernel), so the fuzz build does not compile the lab and
//! its plotting, CLI and image dependencies (most of that build's time).
//!
//! Checks:
//! * never a panic; a parsed file has `1 ≤ D ≤ 3`, a whole number of points, every
//!   coordinate finite and in `[0, 1)`, and as many points as data lines (minus a
//!   header);
//! * an error's claims hold on the text: the named line exists and is a data line,
//!   and for `NotANumber` / `NotFinite` the named column of that line is the token,
//!   which indeed fails to parse / parses to NaN or ±∞; for `Columns` the line has
//!   that many columns; `Empty` only when there is no data line;
//! * generated files (coordinates written with `{}` or `{:e}`, random separators,
//!   comments, blank lines, an optional count header) parse back to exactly the
//!   written numbers, wrapped by `x − ⌊x⌋` (a result that rounds to 1 is 0), with
//!   the wrap count and header reported.
//!
//! Run: `cargo fuzz run --sanitizer none pointfile`.

#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
#[path = "../../lab/src/pointfile.rs"]
#[allow(dead_code)]
mod pointfile;

use pointfile::{parse_points, PointFileError};

#[derive(Arbitrary, Debug)]
struct Generated {
    dims: u8,
    values: Vec<f64>,
    seps: Vec<u8>,
    header: bool,
    exp: bool,
}

#[derive(Arbitrary, Debug)]
enum Input {
    Text(String),
    File(Generated),
}

fn data_lines(text: &str) -> Vec<(usize, Vec<&str>)> {
    text.lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'))
        .map(|(i, l)| (i, l.split_whitespace().collect()))
        .collect()
}

fn check_text(text: &str) {
    let lines = data_lines(text);
    match parse_points(text) {
        Ok(p) => {
            assert!((1..=3).contains(&p.dims));
            assert_eq!(p.coords.len() % p.dims, 0);
            assert!(
                p.coords.iter().all(|x| (0.0..1.0).contains(x)),
                "{:?}",
                p.coords
            );
            let header = usize::from(p.header.is_some());
            assert_eq!(p.len() + header, lines.len());
        }
        Err(PointFileError::Empty) => assert!(lines.is_empty()),
        Err(e) => {
            let line = e.line().expect("a located error");
            let (_, toks) = lines
                .iter()
                .find(|(l, _)| *l == line)
                .unwrap_or_else(|| panic!("{e}: line {line} is not a data line"));
            match &e {
                PointFileError::Dimension { columns, .. } => {
                    assert_eq!(toks.len(), *columns);
                    assert!(!(1..=3).contains(columns));
                }
                PointFileError::Columns { columns, dims, .. } => {
                    assert_eq!(toks.len(), *columns);
                    assert_ne!(columns, dims);
                }
                PointFileError::NotANumber { column, token, .. } => {
                    assert_eq!(toks[column - 1], token);
                    assert!(token.parse::<f64>().is_err());
                }
                PointFileError::NotFinite { column, token, .. } => {
                    assert_eq!(toks[column - 1], token);
                    assert!(!token.parse::<f64>().unwrap().is_finite());
                }
                PointFileError::Empty => unreachable!(),
            }
        }
    }
}

fn wrap(x: f64) -> f64 {
    let w = x - x.floor();
    if w >= 1.0 {
        0.0
    } else {
        w
    }
}

fn check_generated(g: &Generated) {
    let dims = 1 + usize::from(g.dims % 3);
    let vals: Vec<f64> = g
        .values
        .iter()
        .copied()
        .filter(|x| x.is_finite())
        .take(dims * 64)
        .collect();
    let n = vals.len() / dims;
    let vals = &vals[..n * dims];
    let mut sep = g.seps.iter().cycle();
    let mut next = || sep.next().copied().unwrap_or(0);
    let mut text = String::new();
    if g.header && dims > 1 {
        text.push_str(&format!("# header\n{n}\n"));
    }
    for p in vals.chunks_exact(dims) {
        match next() % 8 {
            0 => text.push_str("\n"),
            1 => text.push_str("  # a comment 1 2 x\n"),
            _ => {}
        }
        for (j, x) in p.iter().enumerate() {
            if j > 0 {
                text.push_str(["\t", " ", "  \t "][usize::from(next() % 3)]);
            }
            if g.exp {
                text.push_str(&format!("{x:e}"));
            } else {
                text.push_str(&format!("{x}"));
            }
        }
        text.push_str(if next() % 2 == 0 { "\n" } else { " \r\n" });
    }
    let got = parse_points(&text);
    if n == 0 {
        assert!(matches!(got, Err(PointFileError::Empty)) || g.header && dims > 1);
        return;
    }
    let p = got.unwrap_or_else(|e| panic!("{e} for\n{text}"));
    assert_eq!(p.dims, dims);
    assert_eq!(
        p.header.map(|h| (h.count, h.points)),
        (g.header && dims > 1).then_some((n as u64, n))
    );
    // Coordinates in [0, 1) (−0.0 included) are kept as written, others wrapped.
    let want: Vec<u64> = vals
        .iter()
        .map(|&x| if (0.0..1.0).contains(&x) { x } else { wrap(x) }.to_bits())
        .collect();
    let have: Vec<u64> = p.coords.iter().map(|x| x.to_bits()).collect();
    assert_eq!(have, want, "coordinates differ for\n{text}");
    let wrapped = vals.iter().filter(|x| !(0.0..1.0).contains(*x)).count();
    assert_eq!(p.wrapped, wrapped);
}

fuzz_target!(|inp: Input| match inp {
    Input::Text(t) => check_text(&t),
    Input::File(g) => {
        check_generated(&g);
    }
});
