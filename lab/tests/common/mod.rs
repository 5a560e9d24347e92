//! Helpers shared by the lab's integration tests: a temp directory per test,
//! the binary, and readers of the output formats.

#![allow(dead_code)]

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub const BIN: &str = env!("CARGO_BIN_EXE_linesample-lab");

/// A fresh, empty directory, removed on drop.
pub struct TempDir(tempfile::TempDir);

impl TempDir {
    pub fn new(tag: &str) -> Self {
        TempDir(
            tempfile::Builder::new()
                .prefix(&format!("linesample-lab-test-{tag}-"))
                .tempdir()
                .expect("create temp dir"),
        )
    }

    pub fn path(&self) -> &Path {
        self.0.path()
    }

    /// Every file below the directory (relative paths), sorted, leaving out
    /// the runner's state folders (`*.state/`).
    pub fn files(&self) -> Vec<PathBuf> {
        self.walk(false)
    }

    /// Every file, state folders included.
    pub fn all_files(&self) -> Vec<PathBuf> {
        self.walk(true)
    }

    fn walk(&self, state: bool) -> Vec<PathBuf> {
        fn walk(dir: &Path, root: &Path, state: bool, out: &mut Vec<PathBuf>) {
            for e in fs::read_dir(dir).expect("read_dir").flatten() {
                let p = e.path();
                if p.is_dir() {
                    if state || p.extension().is_none_or(|x| x != "state") {
                        walk(&p, root, state, out);
                    }
                } else {
                    out.push(p.strip_prefix(root).unwrap().to_path_buf());
                }
            }
        }
        let mut v = Vec::new();
        walk(self.path(), self.path(), state, &mut v);
        v.sort();
        v
    }
}

/// Runs the lab in `dir` with `args`.
pub fn lab(dir: &TempDir, args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(dir.path())
        .output()
        .expect("run linesample-lab")
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Asserts success, printing stderr otherwise.
pub fn ok(o: &Output, what: &str) {
    assert!(o.status.success(), "{what}: {}", stderr(o));
}

/// Asserts a clean failure: non-zero, one `error: ` line mentioning `want`.
pub fn fails_with(o: &Output, want: &str, what: &str) {
    let err = stderr(o);
    assert!(!o.status.success(), "{what} succeeded");
    assert!(err.starts_with("error: "), "{what}: {err}");
    assert!(
        err.contains(want),
        "{what}: {err:?} should mention {want:?}"
    );
}

/// Parses a point file and checks it has `n` lines of `d` numbers in `[0, 1)`.
pub fn check_points(path: &Path, n: usize, d: usize) -> Vec<Vec<f32>> {
    let text = fs::read_to_string(path).expect("read points");
    assert!(text.ends_with('\n'), "{}: no final newline", path.display());
    let pts: Vec<Vec<f32>> = text
        .lines()
        .map(|line| {
            assert!(!line.contains("  ") && !line.starts_with(' ') && !line.ends_with(' '));
            line.split(' ')
                .map(|t| {
                    t.parse::<f32>()
                        .unwrap_or_else(|_| panic!("bad number {t:?}"))
                })
                .collect()
        })
        .collect();
    assert_eq!(pts.len(), n, "{}", path.display());
    for p in &pts {
        assert_eq!(p.len(), d);
        assert!(p.iter().all(|x| (0.0..1.0).contains(x)), "{p:?}");
    }
    pts
}

/// The number of `<circle` elements of a well-formed SVG.
pub fn circles(path: &Path) -> usize {
    let svg = fs::read_to_string(path).expect("read svg");
    assert!(svg.trim_start().starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    svg.matches("<circle").count()
}

/// A CSV's notes, header and rows. The file must start with its header
/// (no comment line): the notes are those its run's manifest keeps for it
/// (`notes[<file name>]` of the `manifest.json`, or of the one
/// `*manifest.json`, in its folder), each as `# <note>`.
pub fn csv_table(path: &Path) -> (Vec<String>, Vec<String>, Vec<Vec<String>>) {
    let text = fs::read_to_string(path).expect("read csv");
    assert!(text.ends_with('\n'));
    assert!(
        !text.starts_with('#'),
        "{}: a CSV must start with its header",
        path.display()
    );
    let mut rest = text.lines();
    let header: Vec<String> = rest
        .next()
        .expect("header")
        .split(',')
        .map(str::to_owned)
        .collect();
    let rows = rest
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect();
    (csv_notes(path), header, rows)
}

/// The notes the run's manifest keeps for the CSV at `path`, as `# <note>`.
pub fn csv_notes(path: &Path) -> Vec<String> {
    let dir = path.parent().expect("a folder");
    let name = path.file_name().unwrap().to_string_lossy().into_owned();
    let mut manifests: Vec<PathBuf> = fs::read_dir(dir)
        .expect("read the CSV's folder")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.to_string_lossy().ends_with("manifest.json"))
        .collect();
    manifests.sort();
    let mut notes = Vec::new();
    for m in manifests {
        let v: serde_json::Value = serde_json::from_slice(&fs::read(&m).unwrap()).unwrap();
        if let Some(a) = v["notes"][name.as_str()].as_array() {
            notes.extend(a.iter().map(|n| format!("# {}", n.as_str().unwrap())));
        }
    }
    notes
}

/// No `.tmp` file anywhere below `dir` (state folders included).
pub fn no_tmp_files(dir: &TempDir) {
    let files = dir.all_files();
    assert!(
        files.iter().all(|f| !f.to_string_lossy().ends_with(".tmp")),
        "{files:?}"
    );
}

/// Width, height and pixels (8-bit grey) of a PNG file.
pub fn png_gray(path: &Path) -> (u32, u32, Vec<u8>) {
    let dec = png::Decoder::new(std::io::BufReader::new(
        fs::File::open(path).expect("open png"),
    ));
    let mut r = dec.read_info().expect("png header");
    let mut buf = vec![0; r.output_buffer_size().expect("size")];
    let info = r.next_frame(&mut buf).expect("png data");
    assert_eq!(
        info.color_type,
        png::ColorType::Grayscale,
        "{}",
        path.display()
    );
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

pub fn png_size(path: &Path) -> (u32, u32) {
    let (w, h, _) = png_gray(path);
    (w, h)
}

pub const SPECTRUM_HEADER: &str = "radius,mean_np,std_error,count";
pub const CONVERGENCE_HEADER: &str =
    "n,realisations,mean,mean_se,exact,bias_z,variance,variance_se,var_times_n";

/// `(radius, mean, se, count)` rows of a spectrum CSV, checking the header.
pub fn spectrum_rows(path: &Path) -> Vec<(usize, f64, f64, u64)> {
    let (comments, header, rows) = csv_table(path);
    assert!(comments.is_empty(), "{comments:?}");
    assert_eq!(header.join(","), SPECTRUM_HEADER);
    rows.iter()
        .map(|r| {
            assert_eq!(r.len(), 4, "{r:?}");
            (
                r[0].parse().unwrap(),
                r[1].parse().unwrap(),
                r[2].parse().unwrap(),
                r[3].parse().unwrap(),
            )
        })
        .collect()
}

/// Full-grid frequency counts of the rings `round(|ν|) = r`, `r = 0..=k`, in
/// `d` dimensions (exact integer rule: `r² − r < |ν|² ≤ r² + r`).
pub fn ring_counts(k: i64, d: u32) -> Vec<u64> {
    let mut c = vec![0u64; k as usize + 1];
    let w = 2 * k + 1;
    for i in 0..w.pow(d) {
        let mut m = 0;
        let mut rest = i;
        for _ in 0..d {
            let j = rest % w - k;
            rest /= w;
            m += j * j;
        }
        if let Some(r) = (0..=k).find(|&r| m <= r * r + r) {
            c[r as usize] += 1;
        }
    }
    c
}

/// The bias check of a convergence row, from the row's own sample variance:
/// `SE = √(s²/R)` (recomputed here, and the CSV's `mean_se` and `bias_z` must
/// agree with it), then `|mean − exact| ≤ 5·SE` (tests/README.md: one z-check,
/// α = 5.7e-7; the smallest bias it detects for sure is 5·SE, printed relative
/// to the exact value).
pub fn check_bias(mean: f64, mean_se: f64, exact: f64, z: f64, var: f64, r: u64, what: &str) {
    let se = (var / r as f64).sqrt();
    assert!(
        (mean_se / se - 1.0).abs() <= 1e-9,
        "{what}: mean_se {mean_se:e} vs √(s²/R) = {se:e}"
    );
    let z_here = (mean - exact) / se;
    assert!(
        (z - z_here).abs() <= 1e-6 * z_here.abs().max(1.0),
        "{what}: bias_z {z} vs (mean − exact)/SE = {z_here}"
    );
    println!(
        "{what}: bias z = {z_here:+.2}; detects a relative bias of {:.1e}",
        5.0 * se / exact.abs()
    );
    assert!(
        z_here.abs() <= 5.0,
        "{what}: mean {mean} vs exact {exact}: |z| = {:.2} > 5 (SE {se:e})",
        z_here.abs()
    );
}
