//! Section 10 of the report: volumetric caustics with photon points and
//! photon beams, read from the files `caustic::paper_runs` wrote under
//! `OUT/caustics/2d/` and `OUT/caustics/3d/`.

use std::fmt::Write as _;
use std::path::Path;

use serde_json::Value;

use super::esc;
use crate::experiments::caustic::{consistent, expected, Photons, SLOPE_SLACK};
use crate::fit::fit_sci;
use crate::scene::SceneSampler;

fn parse_est(s: &str) -> Option<Photons> {
    match s {
        "points" => Some(Photons::Points),
        "beams" => Some(Photons::Beams),
        _ => None,
    }
}

fn parse_sampler(s: &str) -> Option<SceneSampler> {
    match s {
        "random" => Some(SceneSampler::Random),
        "jittered" => Some(SceneSampler::Jittered),
        "sobol" => Some(SceneSampler::Sobol),
        _ => None,
    }
}

/// The section's HTML, or a note saying how to produce it.
///
/// # Errors
/// A file that exists but does not parse.
pub(in crate::experiments::paper) fn section_caustics(out_dir: &Path) -> crate::Result<String> {
    let dir = out_dir.join("caustics");
    let mut h = String::new();
    h.push_str(
        "<h2 id=\"caustics\">10 A rendering problem: volumetric caustics, photon points vs \
         photon beams</h2>\n",
    );
    if !dir.join("2d").join("caustics.csv").is_file() {
        h.push_str(
            "<p>Not run: a sharded <code>paper</code> run leaves the scenes out. Run \
             <code>linesample-lab scene scenes/caustic-2d.toml</code> and \
             <code>scenes/caustic-3d.toml</code> for these results.</p>\n",
        );
        return Ok(h);
    }
    h.push_str(
        "<p>A point light emits into an 18° cone above a glass ball (disk in flatland) of \
         radius 0.5 and index 1.5 in a homogeneous medium (σ<sub>s</sub> = 0.5, \
         σ<sub>a</sub> = 0.1 outside the glass; the glass itself is clear). The ball focuses \
         the light into a caustic below it. The one quantity estimated is the power scattered \
         inside a query ball Q (radius 0.2, centred on the caustic) per unit emitted power: \
         an indicator, so neither estimator needs a density-estimation kernel and both are \
         unbiased. Refraction is exact (Snell's law at both interfaces); Fresnel reflection \
         is modelled, the ray reflected at the entry is followed, and so are two internal \
         reflections (each leaves a ray); nothing else scatters. <b>Photon points</b> sample \
         the emission angle(s) <i>u</i> and a free-flight distance \
         <i>t</i> = −ln(1 − <i>s</i>)/σ<sub>t</sub> and score \
         σ<sub>s</sub>/σ<sub>t</sub>·1[x(t) ∈ Q]: a sample in 2D (flatland) or 3D. \
         <b>Photon beams</b> keep <i>u</i> and integrate over <i>s</i> in closed form: each \
         chord [a, b] of a ray inside Q gives \
         σ<sub>s</sub>/σ<sub>t</sub>·w·(e<sup>−σ<sub>t</sub>a</sup> − \
         e<sup>−σ<sub>t</sub>b</sup>): line samples along the distance axis with 1D (2D \
         scene) or 2D (3D scene) offsets.</p>\n",
    );
    // Images.
    h.push_str("<div class=\"figs\">");
    for d in ["2d", "3d"] {
        let summary: Value = std::fs::read(dir.join(d).join("fluence.json"))
            .ok()
            .and_then(|b| serde_json::from_slice(&b).ok())
            .unwrap_or(Value::Null);
        let what = if d == "2d" {
            "the whole plane".to_string()
        } else {
            format!(
                "the slab {} &lt; z &lt; {}",
                summary["slab"][0].as_f64().unwrap_or(f64::NAN),
                summary["slab"][1].as_f64().unwrap_or(f64::NAN)
            )
        };
        let _ = write!(
            h,
            "<figure><img src=\"caustics/{d}/fluence.png\" style=\"width:100%\"><figcaption>\
             {D} fluence (σ<sub>s</sub>φ, log scale over four decades) over {what}, from {} \
             jittered beams, each integrated in closed form over every pixel it crosses; the \
             glass (grey) and Q (cyan) outlined. Peak {:.3e} at ({:.3}, {:.3}).\
             </figcaption></figure>",
            summary["beams"].as_u64().unwrap_or(0),
            summary["peak"].as_f64().unwrap_or(f64::NAN),
            summary["peak_at"][0].as_f64().unwrap_or(f64::NAN),
            summary["peak_at"][1].as_f64().unwrap_or(f64::NAN),
            D = d.to_uppercase(),
        );
    }
    h.push_str("</div>\n");
    h.push_str(
        "<p>Inside the cone, light that misses the ball goes straight on (the bright wedges \
         beside it); the ball's shadow is dark but for the refracted light, which converges \
         into a cusp-shaped caustic whose bright axis runs down through Q (spherical \
         aberration: rays through the rim cross the axis nearer the ball than paraxial \
         ones). Fresnel reflection sends faint light sideways above the ball.</p>\n",
    );
    h.push_str(
        "<table><tr><th>dims</th><th>estimator</th><th>sampler</th>\
         <th>slope [95 %], 3 largest N</th><th>slope, all N</th><th>expected</th>\
         <th>verdict</th><th>max |z| vs reference</th><th>N to 1 %</th>\
         <th>time to 1 % (s)</th></tr>",
    );
    for d in ["2d", "3d"] {
        let path = dir.join(d).join("study").join("slopes.csv");
        let Ok(mut rdr) = csv::ReaderBuilder::new()
            .comment(Some(b'#'))
            .from_path(&path)
        else {
            let _ = write!(
                h,
                "<tr><td>{d}</td><td colspan=\"9\">the study did not run</td></tr>"
            );
            continue;
        };
        let rows: Vec<csv::StringRecord> = rdr
            .records()
            .collect::<Result<_, _>>()
            .map_err(|e| format!("{}: {e}", path.display()))?;
        // dims,estimator,sampler,slope,lo,hi,expected,expected_with_log,slope_all,last,zmax,n1,t1
        for r in &rows {
            slope_row(&mut h, r);
        }
    }
    h.push_str(
        "</table><p>Hover an expectation for its reason. Points see Q as a discontinuity \
         across a surface of their 2D or 3D sample space: jittered N<sup>−1−1/d</sup>. \
         Beams integrate that away: the beam value is a continuous function of the emission \
         angles, with square-root edges where a ray grazes Q (the chord 2√(r² − p²)), so \
         jittered beams reach N<sup>−3</sup> in 2D and N<sup>−2</sup> in 3D up to a factor \
         ln N from the strata next to those edges (hence the range). The slopes are fitted \
         over the three largest N: below them the strata are wider than Q's band in the \
         free-flight variable (about 0.07 of [0, 1)), and the points' variance falls like \
         random sampling's; in 3D the approach is slow (the all-N slope), and a slope between \
         N<sup>−1</sup> and the rate is called <i>pre-asymptotic</i>. The max |z| column \
         compares each row's mean with the reference (64 × 65,536 jittered beams): both \
         estimators are unbiased. Time to 1 % reads the fit at a relative RMSE of 1 % times \
         the measured time per photon (one thread). Files: \
         <a href=\"caustics/2d/caustics.csv\">2d/caustics.csv</a>, \
         <a href=\"caustics/3d/caustics.csv\">3d/caustics.csv</a>, and \
         <code>study/rows.csv</code>, <code>study/slopes.csv</code> beside them.</p>\n\
         <div class=\"figs\">",
    );
    for d in ["2d", "3d"] {
        let _ = write!(
            h,
            "<figure><img src=\"caustics/{d}/study/convergence.svg\"><figcaption>{D}: \
             variance against N.</figcaption></figure><figure>\
             <img src=\"caustics/{d}/study/time-to-error.svg\"><figcaption>{D}: relative RMSE \
             against time per estimate.</figcaption></figure>",
            D = d.to_uppercase()
        );
    }
    h.push_str("</div>\n");
    Ok(h)
}

/// One `slopes.csv` row (dims, estimator, sampler, slope, lo, hi, expected,
/// expected with log, slope over all N, last, max |z|, N and seconds to
/// 1 %) as a table row with its expectation and verdict.
fn slope_row(h: &mut String, r: &csv::StringRecord) {
    let f = |i: usize| r[i].parse::<f64>().unwrap_or(f64::NAN);
    let dims: usize = r[0].parse().unwrap_or(0);
    let (slope, lo, hi, e_lo, e_hi, all, zmax, n1, t1) =
        (f(3), f(4), f(5), f(6), f(7), f(8), f(10), f(11), f(12));
    let why = match (parse_est(&r[1]), parse_sampler(&r[2])) {
        (Some(e), Some(s)) => expected(dims, e, s).map_or("", |x| x.1),
        _ => "",
    };
    let (exp_text, verdict) = if e_lo.is_nan() {
        ("—".to_string(), "")
    } else {
        let t = if e_lo == e_hi {
            format!("{e_lo:+.2}")
        } else {
            format!("{e_lo:+.2} … {e_hi:+.2}")
        };
        (
            format!("<span title=\"{}\">{t}</span>", esc(why)),
            if consistent(lo, hi, e_lo, e_hi) {
                "consistent"
            } else if hi + SLOPE_SLACK >= e_lo && lo - SLOPE_SLACK <= -1.0 {
                // Between random's N^-1 and the rate.
                "pre-asymptotic"
            } else {
                "differs"
            },
        )
    };
    let _ = write!(
        h,
        "<tr><td>{dims}D</td><td>{}</td><td>{}</td>\
         <td>{slope:+.2} [{lo:+.2}, {hi:+.2}]</td><td>{all:+.2}</td><td>{exp_text}</td>\
         <td>{verdict}</td><td>{zmax:.2}</td><td>{}</td><td>{}</td></tr>",
        esc(&r[1]),
        esc(&r[2]),
        fit_sci(n1, 3),
        fit_sci(t1, 2),
    );
}
