//! The plain-text point file format of `linesample-lab spectrum --input`: one
//! point per line, its `D` coordinates (`1 ≤ D ≤ 3`) separated by whitespace.
//!
//! [`parse_points`] takes the text (not a path) so that it can be tested and
//! fuzzed on its own; the lab's file-reading wrapper adds the file name to the
//! messages. The rules:
//!
//! * blank lines and lines starting with `#` (after trimming) are skipped;
//! * `D` is the number of columns of the first data line, every other data line
//!   must have the same number;
//! * if the first data line is a single unsigned integer and the next data line
//!   has two or more columns, the first line is a point-count header (as UTK
//!   writes) and is skipped ([`PointSet::header`]);
//! * numbers are Rust `f64` literals (decimal, e.g. `0.25`, `2.5e-1`); NaN and
//!   infinities are rejected;
//! * coordinates outside `[0, 1)` are wrapped onto the torus, `x − ⌊x⌋`, and a
//!   result that rounds to 1 (a tiny negative `x`) is stored as 0
//!   ([`PointSet::wrapped`] counts them).

use linesample::num::frac;
use std::fmt;

/// A skipped point-count header line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Header {
    /// 1-based line number of the header.
    pub line: usize,
    /// The count the header states.
    pub count: u64,
    /// The number of points the file actually has after it.
    pub points: usize,
}

/// A parsed point file.
#[derive(Clone, Debug, PartialEq)]
pub struct PointSet {
    /// Coordinates per point, `1..=3`.
    pub dims: usize,
    /// Flat coordinates (`dims` per point), each in `[0, 1)`.
    pub coords: Vec<f64>,
    /// The point-count header line, if one was skipped.
    pub header: Option<Header>,
    /// How many coordinates were outside `[0, 1)` and were wrapped.
    pub wrapped: usize,
}

impl PointSet {
    /// Number of points.
    #[must_use]
    pub fn len(&self) -> usize {
        self.coords.len() / self.dims
    }

    /// Whether there are no points (never, for a parsed file).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.coords.is_empty()
    }
}

/// Why a point file was rejected. Lines and columns are 1-based.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PointFileError {
    /// No data line at all (empty, or only blank lines and comments).
    Empty,
    /// The first data line (`line`) has `columns` columns, not 1 to 3.
    Dimension {
        /// Line of the first data line.
        line: usize,
        /// Its number of columns.
        columns: usize,
    },
    /// Data line `line` has `columns` columns, but the first data line
    /// (`first_line`) has `dims`.
    Columns {
        /// The offending line.
        line: usize,
        /// Its number of columns.
        columns: usize,
        /// The first data line.
        first_line: usize,
        /// The columns of the first data line.
        dims: usize,
    },
    /// The token in `line`, `column` is not a number.
    NotANumber {
        /// Line.
        line: usize,
        /// Column.
        column: usize,
        /// The token as written.
        token: String,
    },
    /// The token in `line`, `column` is NaN or infinite.
    NotFinite {
        /// Line.
        line: usize,
        /// Column.
        column: usize,
        /// The token as written.
        token: String,
    },
}

impl PointFileError {
    /// The line the error is about (`None` for [`PointFileError::Empty`]).
    #[must_use]
    pub fn line(&self) -> Option<usize> {
        match self {
            Self::Empty => None,
            Self::Dimension { line, .. }
            | Self::Columns { line, .. }
            | Self::NotANumber { line, .. }
            | Self::NotFinite { line, .. } => Some(*line),
        }
    }
}

/// The message, starting with its location (`line L[, column C]: …`), without
/// the file name; the lab prints `FILE, {message}` when there is a line and
/// `FILE: {message}` otherwise.
impl fmt::Display for PointFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Empty => write!(f, "no points (the file is empty or only comments)"),
            Self::Dimension { line, columns } => write!(
                f,
                "line {line}: {columns} columns; expected 1 to 3 coordinates per point"
            ),
            Self::Columns {
                line,
                columns,
                first_line,
                dims,
            } => write!(
                f,
                "line {line}: {columns} columns, but the first point (line {first_line}) has \
                 {dims}"
            ),
            Self::NotANumber {
                line,
                column,
                token,
            } => write!(f, "line {line}, column {column}: '{token}' is not a number"),
            Self::NotFinite {
                line,
                column,
                token,
            } => write!(
                f,
                "line {line}, column {column}: '{token}' is not a finite number"
            ),
        }
    }
}

impl std::error::Error for PointFileError {}

/// Parses the text of a point file (rules in the [module docs](self)).
///
/// # Errors
/// [`PointFileError`], naming the line (and column) of the first problem.
pub fn parse_points(text: &str) -> Result<PointSet, PointFileError> {
    let data: Vec<(usize, Vec<&str>)> = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'))
        .map(|(i, l)| (i, l.split_whitespace().collect()))
        .collect();
    let mut rows = &data[..];
    let mut header = None;
    if let [(line, first), (_, second), ..] = rows {
        if first.len() == 1 && second.len() > 1 {
            if let Ok(count) = first[0].parse::<u64>() {
                header = Some(Header {
                    line: *line,
                    count,
                    points: rows.len() - 1,
                });
                rows = &rows[1..];
            }
        }
    }
    let Some((first_line, first)) = rows.first() else {
        return Err(PointFileError::Empty);
    };
    let dims = first.len();
    if !(1..=3).contains(&dims) {
        return Err(PointFileError::Dimension {
            line: *first_line,
            columns: dims,
        });
    }
    let mut coords = Vec::with_capacity(rows.len() * dims);
    let mut wrapped = 0usize;
    for (line, toks) in rows {
        if toks.len() != dims {
            return Err(PointFileError::Columns {
                line: *line,
                columns: toks.len(),
                first_line: *first_line,
                dims,
            });
        }
        for (c, t) in toks.iter().enumerate() {
            let x: f64 = t.parse().map_err(|_| PointFileError::NotANumber {
                line: *line,
                column: c + 1,
                token: (*t).to_string(),
            })?;
            if !x.is_finite() {
                return Err(PointFileError::NotFinite {
                    line: *line,
                    column: c + 1,
                    token: (*t).to_string(),
                });
            }
            if (0.0..1.0).contains(&x) {
                coords.push(x);
            } else {
                wrapped += 1;
                coords.push(frac(x));
            }
        }
    }
    Ok(PointSet {
        dims,
        coords,
        header,
        wrapped,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_wrap_and_comments() {
        let p = parse_points("# c\n3\n0.5 1.25\n\n-0.25 0\n-1e-300 0.75\n").unwrap();
        assert_eq!(p.dims, 2);
        assert_eq!(p.coords, vec![0.5, 0.25, 0.75, 0.0, 0.0, 0.75]);
        assert_eq!(
            p.header,
            Some(Header {
                line: 2,
                count: 3,
                points: 3
            })
        );
        assert_eq!(p.wrapped, 3);
        assert_eq!(p.len(), 3);
    }

    #[test]
    fn errors_name_line_and_column() {
        assert_eq!(parse_points("# only\n\n"), Err(PointFileError::Empty));
        let e = parse_points("0.1 0.2\n0.3 x\n").unwrap_err();
        assert_eq!(e.to_string(), "line 2, column 2: 'x' is not a number");
        let e = parse_points("0.1\n\ninf\n").unwrap_err();
        assert_eq!(
            e.to_string(),
            "line 3, column 1: 'inf' is not a finite number"
        );
        let e = parse_points("1 2 3 4\n").unwrap_err();
        assert_eq!(
            e.to_string(),
            "line 1: 4 columns; expected 1 to 3 coordinates per point"
        );
        let e = parse_points("0.1 0.2\n0.3\n").unwrap_err();
        assert_eq!(e.line(), Some(2));
        assert_eq!(
            e.to_string(),
            "line 2: 1 columns, but the first point (line 1) has 2"
        );
    }
}
