//! Section 8 of the report: the paper's ambient-occlusion scene, read from
//! the files the scene runs wrote under `OUT/ao/` (`scene::paper_runs`).

use std::fmt::Write as _;
use std::path::Path;

use serde_json::Value;

use super::esc;
use crate::experiments::paper::plan::Mode;
use crate::experiments::scene::{AO_SCENE_NAME, PAPER_PIXELS};
use crate::fit::fit_sci;

fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or(f64::NAN)
}

fn text(v: &Value) -> String {
    v.as_str().unwrap_or_default().to_string()
}

/// The section's HTML, or a note saying how to produce it when the scene
/// files are missing (a sharded paper run).
///
/// # Errors
/// A scene file that exists but does not parse.
pub(in crate::experiments::paper) fn section_scene(
    out_dir: &Path,
    mode: Mode,
) -> crate::Result<String> {
    let dir = out_dir.join("ao");
    let mut h = String::new();
    h.push_str("<h2 id=\"scene\">8 A rendering problem: ambient occlusion</h2>\n");
    let csv_path = dir.join("images").join("images.csv");
    if !csv_path.is_file() {
        let _ = writeln!(
            h,
            "<p>Not run: a sharded <code>paper</code> run leaves the scene out. Run \
             <code>linesample-lab scene {AO_SCENE_NAME}</code> and <code>linesample-lab scene \
             {AO_SCENE_NAME} --pixel 410,305</code> for these results.</p>"
        );
        return Ok(h);
    }
    let _ = writeln!(
        h,
        "<p>The authors' pbrt-v3 scene of eight spheres (<code>{AO_SCENE_NAME}</code>), with the \
         one effect it asks for: cosine-weighted ambient occlusion, normalised to 1 when nothing \
         occludes, maximum distance 500. A camera ray per pixel finds the shading point; every \
         estimate then uses the closed-form visibility of the spheres in a half-plane through \
         the normal (the occluded angle intervals of each sphere, merged, and \
         <code>∫|sin θ| cos θ dθ</code> over the visible pieces), so no ray is traced and \
         nothing else is simulated. A sample <code>(u, v)</code> gives the azimuth \
         <code>φ = πu</code> of the half-plane and the centre angle <code>θ</code> in it: points, \
         segments of length ℓ in θ (wrapping with period π; ℓ = π is the whole half-plane) and \
         lines (φ only). Every realisation has its own random toroidal shift.</p>"
    );
    // Images.
    let rows = read_csv(&csv_path)?;
    let _ = writeln!(
        h,
        "<h3>Images</h3><figure><img src=\"ao/images/sheet.png\" style=\"width:100%;\
         image-rendering:pixelated\"><figcaption>Columns: the reference, then points, segments \
         ℓ = 0.001, 0.1, 1, π, lines, and lines through the kernel's f32 SIMD batch \
         (multi-jittered, uniform centre density). Row 1: the \
         reference and every estimator at N = 16 samples per pixel (equal samples). Row 2: the \
         reference's standard error (log grey, 10⁻⁵ black to 10⁻² white) and every estimator at \
         the N whose measured time is closest to the lines' at N = 16 (equal time). Row 3: the \
         per-pixel variance at N = 16 over 8 realisations (log grey, 10⁻⁷ to 10⁻¹). Sky is \
         blue. Files: <a href=\"ao/images/images.csv\">images.csv</a>, one PNG per \
         image in <code>ao/images/</code>.</figcaption></figure>"
    );
    images_table(&mut h, &rows);
    h.push_str(
        "</table><p>Reading the images: a point sample casts one ray against every sphere \
         (a quadratic each); a line merges every sphere's occluded angle interval (an \
         <code>atan2</code> and an <code>acos</code> each in f64), so a point costs about half \
         an f64 line, and the f32 SIMD batch makes a line cheaper than a point. At equal time \
         the points get about twice the samples of the f64 lines and still have an MSE tens \
         of times larger. The sharp change of variance across each sphere at the height where \
         its normal is horizontal is real: just above it a narrow range of azimuths escapes \
         the ground (a narrow peak in the line integrand L(φ)), just below it none does.</p>\n",
    );
    // Pixels.
    for (x, y) in PAPER_PIXELS {
        pixel_section(&mut h, &dir, x, y)?;
    }
    h.push_str(PITFALLS);
    if mode == Mode::Reduced {
        h.push_str("<p><b>Reduced mode: tiny images and few realisations; do not cite.</b></p>\n");
    }
    Ok(h)
}

/// The equal-samples and equal-time rows of `images.csv` as a table (its
/// opening; the caller closes it).
pub(super) fn images_table(h: &mut String, rows: &[csv::StringRecord]) {
    h.push_str(
        "<table><tr><th>estimator</th><th>N</th><th>seconds</th><th>s per sample</th>\
         <th>MSE vs reference</th><th>mean variance</th><th>shown as</th></tr>",
    );
    for r in rows {
        let (es, et) = (&r[6] == "true", &r[7] == "true");
        if !(es || et) {
            continue;
        }
        let shown = match (es, et) {
            (true, true) => "equal samples, equal time",
            (true, false) => "equal samples",
            _ => "equal time",
        };
        let _ = write!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{:.3}</td><td>{:.2e}</td><td>{:.3e}</td><td>{}</td>\
             <td>{shown}</td></tr>",
            esc(&r[0]),
            &r[1],
            r[2].parse::<f64>().unwrap_or(f64::NAN),
            r[3].parse::<f64>().unwrap_or(f64::NAN),
            r[4].parse::<f64>().unwrap_or(f64::NAN),
            if r[5].is_empty() || &r[5] == "NaN" {
                String::new()
            } else {
                format!("{:.3e}", r[5].parse::<f64>().unwrap_or(f64::NAN))
            }
        );
    }
}

/// One studied pixel: its reference, slopes with verdicts, and the
/// spectral predictions with the theory images.
///
/// # Errors
/// A study file that exists but does not parse.
fn pixel_section(h: &mut String, dir: &Path, x: u32, y: u32) -> crate::Result<()> {
    let stem = format!("pixel-{x}-{y}");
    let json = dir.join(&stem).join(format!("{stem}.json"));
    let Ok(bytes) = std::fs::read(&json) else {
        let _ = write!(h, "<p>Pixel ({x}, {y}): not run.</p>");
        return Ok(());
    };
    let v: Value =
        serde_json::from_slice(&bytes).map_err(|e| format!("{}: {e}", json.display()))?;
    let rel = format!("ao/{stem}/{stem}");
    let _ = writeln!(
        h,
        "<h3 id=\"{stem}\">Pixel ({x}, {y})</h3><p>Reference AO <b>{:.6} ± {:.1e}</b> ({}). \
         Files: <a href=\"{rel}.json\">{stem}.json</a>, <a href=\"{rel}.csv\">{stem}.csv</a>, \
         <a href=\"{rel}-slopes.csv\">slopes</a>.</p>\
         <div class=\"figs\"><figure><img src=\"{rel}.svg\"><figcaption>Variance against N \
         (uniform centre density): measured ±1 SE, fitted power law, hollow: the spectral \
         prediction.</figcaption></figure></div>",
        num(&v["reference"]["value"]),
        num(&v["reference"]["se"]),
        esc(&text(&v["reference"]["method"]))
    );
    h.push_str(
        "<table><tr><th>estimator</th><th>N</th><th>slope [95 %]</th><th>theory</th>\
         <th>verdict</th><th>fit χ²/dof</th><th>s to 1 % RMSE</th><th>why</th></tr>",
    );
    for s in v["slopes"].as_array().into_iter().flatten() {
        let (slope, lo, hi, th) = (
            num(&s["slope"]),
            num(&s["ci95_low"]),
            num(&s["ci95_high"]),
            num(&s["theory"]),
        );
        let log = s["theory_log_power"].as_u64().unwrap_or(0) > 0;
        let verdict = match s["verdict"].as_str().unwrap_or("") {
            v @ "consistent" => format!("<span class=\"v ok\">{v}</span>"),
            v @ ("log factor" | "pre-asymptotic") => {
                format!("<span class=\"v pre\">{v}</span>")
            }
            v @ ("infinite variance" | "no fit") => format!("<span class=\"v na\">{v}</span>"),
            v => format!("<span class=\"v bad\">{}</span>", esc(v)),
        };
        let _ = write!(
            h,
            "<tr><td>{}</td><td>{}–{}</td><td>{slope:.2} [{lo:.2}, {hi:.2}]</td><td>{}</td>\
             <td>{verdict}</td><td>{:.1}</td><td>{}</td><td>{}</td></tr>",
            esc(&text(&s["estimator"])),
            s["n_min"],
            s["n_max"],
            if th.is_nan() {
                "–".into()
            } else {
                format!("N^{th}{}", if log { " log N" } else { "" })
            },
            num(&s["fit_chi2_dof"]),
            if s["verdict"] == "infinite variance" {
                "–".into()
            } else {
                fit_sci(num(&s["seconds_to_1pct"]), 2)
            },
            esc(&match text(&s["error"]) {
                e if e.is_empty() => text(&s["theory_note"]),
                e => e,
            })
        );
    }
    h.push_str(
        "</table><p>Verdicts: consistent if the theory lies in the 95 % interval widened by \
         ±0.15; \"log factor\" if the slope is shallower than a theory with a log N factor by \
         less than 0.5 (a plain fit over these N reads about 0.2–0.3 shallower); \
         \"pre-asymptotic\" if the slope between the two largest N is consistent (the \
         same widened rule); the \
         centre densities that vanish where a segment's mean does not have infinite \
         variance, so their \"slopes\" mean nothing (large χ²).</p>\n",
    );
    pixel_predictions(h, &v, dir, &stem);
    Ok(())
}

/// The spectral predictions of a pixel beside its measurements, and the
/// theory images the study wrote.
fn pixel_predictions(h: &mut String, v: &Value, dir: &Path, stem: &str) {
    // Predictions.
    let preds: Vec<&Value> = v["convergence"]
        .as_array()
        .into_iter()
        .flatten()
        .filter(|r| r["predicted_variance"].is_f64())
        .collect();
    if !preds.is_empty() {
        h.push_str(
            "<p><b>The theory applied to this pixel.</b> The integrand over the sample \
             domain, <code>f(u, v) = π V |sin θ| cos θ</code> on a 1024² grid, its \
             pre-filtered versions (segments: a box of width ℓ/π along v; lines: L(u) = ∫ f \
             dv on 16384 azimuths), their Fourier coefficients (NUFFT) and each sampler's \
             expected periodogram give the variance <code>(1/N) Σ ⟨N·P(j)⟩ |ĝ(j)|²</code> \
             (energy beyond the frequency grid counted as white):</p>\
             <table><tr><th>estimator</th><th>N</th><th>measured ± SE</th><th>predicted</th>\
             <th>predicted / measured</th></tr>",
        );
        for r in preds {
            let (m, se, p) = (
                num(&r["variance"]),
                num(&r["variance_se"]),
                num(&r["predicted_variance"]),
            );
            let _ = write!(
                h,
                "<tr><td>{}</td><td>{}</td><td>{m:.3e} ± {se:.1e}</td><td>{p:.3e}</td>\
                 <td>{:.3}</td></tr>",
                esc(&text(&r["estimator"])),
                r["n"],
                p / m
            );
        }
        let figs = [
            (
                "integrand",
                "f(u, v): u (azimuth) across, θ = π/2 at the top",
            ),
            ("segments-1", "pre-filtered by segments ℓ = 1"),
            ("segments-pi", "by whole lines (ℓ = π)"),
            (
                "integrand-spectrum",
                "|f̂(j)|², j ∈ [−128, 128]², log grey 10⁻¹² to 10⁻²",
            ),
            ("segments-1-spectrum", "|f̂(j)|² sinc²(j_v ℓ/π), ℓ = 1"),
            (
                "mj-offsets-spectrum",
                "⟨N·P⟩ of multi-jittered offsets, N = 256 (log grey 10⁻² to 10^0.5)",
            ),
        ];
        h.push_str("</table><div class=\"spectra\">");
        for (name, caption) in figs {
            let file = format!("{stem}-{name}.png");
            if dir.join(stem).join(&file).is_file() {
                let _ = write!(
                    h,
                    "<figure class=\"sp\"><img src=\"ao/{stem}/{file}\" \
                     style=\"width:256px\"><figcaption>{caption}</figcaption></figure>"
                );
            }
        }
        h.push_str("</div>\n");
    }
}

/// Where theory and measurement part, and the pitfalls.
const PITFALLS: &str = "<h3>Where theory and measurement part, and the pitfalls</h3><ul>\
         <li><b>The integrand is not periodic in φ.</b> The half-plane at φ + π is the one at φ \
         traversed the other way: <code>f(u + 1, v) = f(u, 1 − v)</code>. On the torus the \
         samples live on, the seam u = 0 is a straight jump parallel to the segments (the \
         bright horizontal line j_v = 0 of the spectra), which segments shorter than π do not \
         pre-filter: they keep the point rate N^−1.5 (only the constant falls), where a \
         periodic integrand would give N^−2 log N. That rate is asymptotic: where the jump is \
         small beside the silhouettes' energy (pixel (300, 290)), long segments read between \
         −1.5 and −2 over these N. The spectral prediction needs no rate model and follows \
         the measurement at both pixels. Whole lines integrate θ out and \
         <code>L(φ)</code> is periodic.</li>\
         <li><b>2D jitter stalls for long segments.</b> A segment of length π is a line, but \
         jittered 2D centres put only √N strata along φ: N^−2, against N^−3 log N for \
         multi-jittered centres (N strata along φ, the line rate).</li>\
         <li><b>Vanishing centre densities give infinite variance.</b> The solid-angle and \
         cosine densities are 0 at the normal (θ = 0), where a segment's mean is not: the \
         estimate grows like 1/|θ_c| and its second moment like ∫ dθ/|θ| (log-divergent; \
         weight about ℓ², so it shows for long segments): the fitted \"slopes\" of those rows \
         are shallow with a large χ², and more samples do not fix it. Points are fine (their \
         integrand vanishes with the density).</li>\
         <li><b>Prediction limits.</b> The prediction uses frequencies |j| ≤ 128 in 2D: for \
         multi-jittered whole-line segments above N ≈ 256 the sampling spectrum is still \
         suppressed along the j_u axis beyond the grid, so the white tail over-predicts.</li>\
         </ul>\n";

/// The records of the CSV at `path` (its header first).
///
/// # Errors
/// A file that cannot be read or parsed, naming it.
pub(super) fn read_csv(path: &Path) -> crate::Result<Vec<csv::StringRecord>> {
    let mut rdr = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_path(path)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    rdr.records()
        .collect::<Result<_, _>>()
        .map_err(|e| format!("{}: {e}", path.display()).into())
}
