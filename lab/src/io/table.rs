//! Tables as CSV through `serde` and `csv`: one row type per table, its field
//! names the header, and number formats chosen per field with the
//! `serialize_with` helpers below (so every table keeps its documented,
//! round-trip number format).

use serde::{Serialize, Serializer};

use crate::{LabError, Result};

/// CSV text: the header (the row type's field names), then one line per
/// row. Nothing precedes the header, so `pandas.read_csv`, Python's
/// `csv.DictReader` and spreadsheets read it as it is; what a file's
/// readers should know besides its rows (the command, the rules behind a
/// column) goes into its run's manifest ([`FileGroup::add_csv`] and
/// [`crate::experiments::OutputManifest::notes`]).
///
/// # Errors
/// [`LabError::Csv`] if a row cannot be serialised (a bug in a row type).
///
/// [`FileGroup::add_csv`]: crate::io::FileGroup::add_csv
pub fn csv<R: Serialize>(rows: &[R]) -> Result<Vec<u8>> {
    let mut w = csv::WriterBuilder::new()
        .terminator(csv::Terminator::Any(b'\n'))
        .from_writer(Vec::new());
    for r in rows {
        w.serialize(r)?;
    }
    w.into_inner()
        .map_err(|e| LabError::Internal(format!("CSV: {}", e.error())))
}

/// Rust's shortest round-trip scientific form, e.g. `1.2345e-5`, `5e-1`.
///
/// # Errors
/// Those of the serializer.
pub fn sci<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    s.collect_str(&format_args!("{v:e}"))
}

/// Fixed point with one decimal, e.g. `12.3`.
///
/// # Errors
/// Those of the serializer.
pub fn fixed1<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    s.collect_str(&format_args!("{v:.1}"))
}

/// Fixed point with four decimals, or an empty field for `None`.
///
/// # Errors
/// Those of the serializer.
pub fn opt_fixed4<S: Serializer>(v: &Option<f64>, s: S) -> Result<S::Ok, S::Error> {
    match v {
        Some(v) => s.collect_str(&format_args!("{v:.4}")),
        None => s.serialize_str(""),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Serialize)]
    struct Row {
        n: usize,
        #[serde(serialize_with = "sci")]
        v: f64,
        #[serde(serialize_with = "fixed1")]
        t: f64,
        #[serde(serialize_with = "opt_fixed4")]
        o: Option<f64>,
        name: String,
    }

    #[test]
    fn formats_and_header_first() {
        let rows = [
            Row {
                n: 16,
                v: 1.2345e-5,
                t: 12.34,
                o: Some(0.5),
                name: "a.txt".into(),
            },
            Row {
                n: 64,
                v: 0.5,
                t: 1.0,
                o: None,
                name: String::new(),
            },
        ];
        let s = String::from_utf8(csv(&rows).unwrap()).unwrap();
        assert_eq!(
            s,
            "n,v,t,o,name\n16,1.2345e-5,12.3,0.5000,a.txt\n64,5e-1,1.0,,\n"
        );
    }
}
