//! The paper's files: the machine-readable tables at fixed names, one data
//! CSV per figure, the figures (SVG plots, PNG spectra), the manifest and the
//! self-contained `index.html` that shows them. Written as one file group:
//! all appear, or none change.

use std::fmt::Write as _;
use std::path::Path;
use std::time::{SystemTime, UNIX_EPOCH};

mod caustic_section;
mod direct_section;
mod scene_section;

pub(super) use caustic_section::section_caustics;
pub(super) use direct_section::section_direct;
pub(super) use scene_section::section_scene;
mod sections;
mod tables;

use super::plan::{Config, Curve, Mode};
use super::results::{Results, SLOPE_TOLERANCE};
use super::theory::Theory;
use super::{Cell, Paper, KIND};
use crate::experiments::OutputManifest;
use crate::io::{self, FileGroup};
use crate::runner::RunInfo;
use crate::Result;
use sections::{
    key_results, section_cost, section_directions, section_edge, section_offsets,
    section_predictions, section_rates, section_segments, section_spectra, verdict_counts,
};
use tables::{cost_csv, curves_csv, prediction_csv, rates_csv};

/// The `paper` output formats (its `--help`).
pub const FORMATS: &str = concat!(
    "\
Output (OUT = --out, default out/paper):
  OUT/index.html      the report: what was run (command, version, seeds, threads,
                      date, total time), the rate tables with verdicts, every
                      figure, and links to the files each was drawn from. It opens
                      from disk (no server, no network, no scripts).
  OUT/rates.csv       table,dims,primitive,sampler,integrand,theory_slope,log_factor,
                      n_min,n_max,measured_slope,slope_ci_low,slope_ci_high,verdict,
                      then regime,beta,alpha,pattern_dims,last_slope,curve: one row
                      per curve and table (segments: one per regime around
                      N* = length^-d). table is rates, segments, directions,
                      offsets or edge; log_factor is none, log N or (log N)^p; the
                      measured slope is fitted with the theory's log factor divided
                      out (the report states the fit, the N range rule and the
                      verdict rule); verdict is consistent, not consistent,
                      pre-asymptotic, not fitted, or pitfall (not homogenised).
  OUT/prediction.csv  case,dims,primitive,sampler,integrand,n,predicted,predicted_se,
                      measured,measured_se,ratio,ratio_se, then rel_diff,z,
                      resolves_5pc,agrees: the spectral variance prediction (mean
                      periodogram of the pattern times the integrand's power
                      spectrum; its SE from the spread of the per-realisation
                      predictions) against the measured variance of the same
                      estimator; ratio = predicted/measured with its delta-method
                      SE from the two SEs.
  OUT/cost.csv        integrand,dims,primitive,sampler,n,rmse,seconds_per_estimate,
                      evaluations_per_estimate, then relative_rmse,curve: RMSE about
                      the exact integral against the wall time of one estimate on
                      one thread and its closed-form evaluations (one per primitive).
  OUT/time-to-error.csv, OUT/simd.csv, OUT/nufft.csv, OUT/directions.csv,
  OUT/curves.csv      the other tables of the report (headers name the columns).
  OUT/figures/*.svg, *.png and the *.csv each figure was drawn from.
  OUT/manifest.json   command, reproducing command, configuration (the whole plan
                      with its seeds), version, threads, wall time, time per cell.

rates.csv, prediction.csv, curves.csv, directions.csv and the figure CSVs hold no
measured times: they are byte-identical for any --threads and for a sharded run
merged with `merge`. cost.csv, time-to-error.csv, simd.csv, nufft.csv and the
report's timing sections measure this machine.

Names are the lab's CLI names: samplers random, jittered, poisson-disk, ccvt,
multi-jittered, sobol; integrands disk, ball, gaussian, edge; primitives points,
segments, lines. Numbers use Rust's shortest round-trip formatting.

Runs: one cell per curve and N, per spectral prediction, and per timing case
(timing cells run alone, after the others), kept in OUT.state/ (resume, --fresh,
--shard, merge, progress: see `linesample-lab --help`).

",
    crate::files_note!()
);

/// HTML-escapes `s`.
pub(super) fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// `YYYY-MM-DD HH:MM UTC` of the system clock (civil-from-days, Hinnant's
/// algorithm; one date does not justify a date-time dependency).
fn utc_now() -> String {
    let t = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let days = (t / 86_400) as i64;
    let (h, m) = ((t % 86_400) / 3600, (t % 3600) / 60);
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let mo = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(mo <= 2);
    format!("{y:04}-{mo:02}-{d:02} {h:02}:{m:02} UTC")
}

pub(super) fn integrand_name(c: &Curve) -> &'static str {
    c.run.integrand.kind.name()
}

pub(super) fn fmt_opt(v: Option<f64>) -> String {
    v.map_or_else(String::new, |x| format!("{x:e}"))
}

/// Staged files and the HTML that shows them.
pub(super) struct Out<'a> {
    dir: &'a Path,
    group: FileGroup,
    files: Vec<String>,
}

impl Out<'_> {
    pub(super) fn add(&mut self, rel: &str, bytes: &[u8]) -> Result<()> {
        self.group.add_bytes(self.dir.join(rel), bytes)?;
        self.files.push(rel.to_string());
        Ok(())
    }

    /// Stages a CSV table and keeps its notes for the manifest.
    fn add_table(&mut self, rel: &str, t: &tables::Table) -> Result<()> {
        self.add(rel, &t.bytes)?;
        self.group.note(rel, &t.notes);
        Ok(())
    }
}

const CSS: &str = "body{font-family:system-ui,sans-serif;max-width:1200px;margin:0 auto;padding:1em 2em;color:#222;line-height:1.45}\
h1{font-size:1.6em;margin-bottom:.2em}h2{border-bottom:2px solid #ddd;padding-bottom:.2em;margin-top:2em}\
table{border-collapse:collapse;margin:.6em 0;font-size:.92em}td,th{border:1px solid #ccc;padding:.25em .6em;text-align:left}\
th{background:#f3f3f3}code{background:#f5f5f5;padding:0 .2em}.run{background:#f7f9fc;border:1px solid #d5deeb;padding:.6em 1em;border-radius:6px}\
.run td{border:none;padding:.1em .8em .1em 0;vertical-align:top}.v{padding:.05em .45em;border-radius:4px;font-size:.9em;white-space:nowrap}\
.ok{background:#d8f0d8}.pre{background:#fff0c2}.bad{background:#f7d0d0}.na{background:#e6e6e6}\
.figs{display:flex;flex-wrap:wrap;gap:1em}.figs figure{margin:0;flex:1 1 540px;max-width:600px}.figs img{width:100%;border:1px solid #eee}\
.spectra{display:flex;flex-wrap:wrap;gap:.8em}.sp{margin:0}.sp img{width:160px;image-rendering:pixelated;border:1px solid #ccc;margin-right:2px}\
figcaption{font-size:.85em;color:#555}.summary{font-size:1.05em}nav a{margin-right:1em}";

/// A scene part's report section: read from the run's folder (a note
/// saying how to produce it when its files are missing).
pub type SceneSection = fn(&Path, Mode) -> Result<String>;

/// Writes every file of the report (one group), with the scene parts'
/// `sections` after the paper's own, and prints a summary (unless
/// `quiet`); returns the results.
///
/// # Errors
/// A drawing or I/O error.
pub fn complete(
    exp: &Paper,
    cells: &[Cell],
    info: &RunInfo,
    out_dir: &Path,
    quiet: bool,
    sections: &[SceneSection],
) -> Result<Results> {
    let cfg = exp.config();
    let res = exp.results(cells)?;
    let mut out = Out {
        dir: out_dir,
        group: FileGroup::new(),
        files: Vec::new(),
    };
    out.add_table("rates.csv", &rates_csv(cfg, &res)?)?;
    out.add_table("prediction.csv", &prediction_csv(cfg, &res)?)?;
    out.add_table("cost.csv", &cost_csv(cfg, &res)?)?;
    let all: Vec<usize> = (0..cfg.curves.len()).collect();
    out.add_table("curves.csv", &curves_csv(cfg, &res, &all)?)?;

    let mut body = String::new();
    body.push_str(&section_rates(&mut out, cfg, &res)?);
    body.push_str(&section_segments(&mut out, cfg, &res)?);
    body.push_str(&section_directions(&mut out, cfg, &res)?);
    body.push_str(&section_offsets(&mut out, cfg, &res)?);
    body.push_str(&section_edge(&mut out, cfg, &res)?);
    body.push_str(&section_spectra(&mut out, exp, cells)?);
    body.push_str(&section_cost(&mut out, cfg, &res)?);
    body.push_str(&section_predictions(cfg, &res));
    for section in sections {
        body.push_str(&section(out_dir, cfg.mode)?);
    }

    let reproduce = format!(
        "linesample-lab paper --mode {} --seed {}",
        cfg.mode.name(),
        cfg.seed
    );
    let mut files = out.files.clone();
    files.push("index.html".into());
    let manifest =
        OutputManifest::new(KIND, reproduce.clone(), cfg, info, files).with_notes(&out.group);
    let manifest_bytes = io::json(&manifest)?;
    let html = page(cfg, &res, info, &reproduce, &body);
    out.add("index.html", html.as_bytes())?;
    out.add("manifest.json", &manifest_bytes)?;
    let Out { group, .. } = out;
    group.commit()?;
    if !quiet {
        crate::out!("{}", summary(cfg, &res).trim_end());
        crate::out!(
            "total wall time {:.1} s; wrote {}",
            info.wall.as_secs_f64(),
            out_dir.join("index.html").display()
        );
    }
    Ok(res)
}

/// The printed summary: the rate tables.
#[must_use]
pub fn summary(cfg: &Config, res: &Results) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<10} {:<58} {:>14} {:>11} {:>24}  verdict",
        "table", "curve", "theory", "N", "slope [95 %]"
    );
    for r in &res.rates {
        let c = &cfg.curves[r.curve];
        let mut label = c.label();
        if !r.regime.is_empty() {
            label.push_str(&format!(" ({})", r.regime));
        }
        let _ = writeln!(
            s,
            "{:<10} {:<58} {:>14} {:>11} {:>24}  {}",
            r.table.name(),
            label,
            r.theory.map_or("-".into(), |t: Theory| t.rate()),
            format!("{}-{}", r.n_min, r.n_max),
            r.fit.map_or("-".into(), |f| format!(
                "{:.3} [{:.3}, {:.3}]",
                f.slope, f.ci_low, f.ci_high
            )),
            r.verdict.name()
        );
    }
    let agree = res.predictions.iter().filter(|p| p.agrees).count();
    let _ = writeln!(
        s,
        "verdicts: {}; predictions: {agree} of {} agree with the measurement (weighted mean \
         predicted/measured - 1: {:+.2} % ± {:.2} %)",
        verdict_counts(res),
        res.predictions.len(),
        100.0 * res.pooled_rel.0,
        100.0 * res.pooled_rel.1
    );
    s
}

fn page(cfg: &Config, res: &Results, info: &RunInfo, reproduce: &str, body: &str) -> String {
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>linesample-lab paper report</title><style>{CSS}</style></head><body>\n"
    );
    h.push_str(
        "<h1>Variance and convergence of Monte Carlo point, segment and line sampling</h1>\n\
         <p>A reproduction, on this machine, of the convergence analysis of Singh, Miller &amp; \
         Jarosz, <i>Variance and Convergence Analysis of Monte Carlo Line and Segment Sampling</i>, \
         EGSR 2017 (Computer Graphics Forum 36(4)), with the <code>linesample</code> kernel: every \
         estimate uses closed-form point, segment and line integrals; every number below links to \
         the file it came from.</p>\n",
    );
    let threads = info.threads;
    let r_by: Vec<String> = {
        let mut v: Vec<(String, u64)> = Vec::new();
        for c in &cfg.curves {
            let s = c.run.sampler.name().to_string();
            if !v.iter().any(|x| x.0 == s) {
                v.push((s, c.run.realisations));
            }
        }
        v.into_iter().map(|(s, r)| format!("{s} {r}")).collect()
    };
    let _ = writeln!(
        h,
        "<div class=\"run\"><table>\
         <tr><td>command</td><td><code>{}</code></td></tr>\
         <tr><td>reproduce</td><td><code>{}</code></td></tr>\
         <tr><td>version</td><td>linesample-lab {}</td></tr>\
         <tr><td>mode, seed</td><td>{} (R per N: {}), seed {}</td></tr>\
         <tr><td>machine</td><td>{threads} worker thread(s)</td></tr>\
         <tr><td>date</td><td>{}</td></tr>\
         <tr><td>time</td><td>{:.1} s this invocation ({} cells computed, {} resumed from the state folder); \
         cells took {:.1} s in total</td></tr></table></div>",
        esc(&crate::runner::command_line()),
        esc(reproduce),
        env!("CARGO_PKG_VERSION"),
        cfg.mode.name(),
        esc(&r_by.join(", ")),
        cfg.seed,
        utc_now(),
        info.wall.as_secs_f64(),
        info.computed,
        info.resumed,
        info.cell_seconds.iter().sum::<f64>()
    );
    let agree = res.predictions.iter().filter(|p| p.agrees).count();
    let _ = writeln!(
        h,
        "<p class=\"summary\"><b>Rate verdicts:</b> {} (of {} rows). <b>Spectral predictions:</b> \
         {agree} of {} agree with the measured variance (weighted mean predicted/measured − 1: \
         {:+.2} % ± {:.2} %).{}</p>",
        verdict_counts(res),
        res.rates.len(),
        res.predictions.len(),
        100.0 * res.pooled_rel.0,
        100.0 * res.pooled_rel.1,
        if cfg.mode == Mode::Reduced {
            " <b>This is the reduced check mode: few N, few realisations, fewer samplers; do not cite it.</b>"
        } else {
            ""
        }
    );
    h.push_str(
        "<nav><a href=\"#key\">key results</a><a href=\"#method\">method</a><a href=\"#rates\">1 rates</a><a href=\"#segments\">2 segments</a>\
         <a href=\"#directions\">3 directions</a><a href=\"#offsets\">4 offsets</a><a href=\"#edge\">5 edge</a>\
         <a href=\"#spectra\">6 spectra</a><a href=\"#cost\">7 cost</a><a href=\"#prediction\">prediction</a><a href=\"#scene\">8 AO scene</a><a href=\"#direct\">9 direct light</a><a href=\"#caustics\">10 caustics</a>\
         <a href=\"#files\">files</a></nav>\n",
    );
    h.push_str(&key_results(cfg, res));
    let _ = write!(
        h,
        "<h2 id=\"method\">Method</h2>\n<ul>\
         <li><b>Homogenised:</b> every realisation adds an independent uniform random toroidal \
         shift to its pattern (Cranley–Patterson rotation), so the estimators are unbiased and \
         the variance is the spectral sum of the theory; the straight-edge table randomises the \
         edge position instead (section 5).</li>\
         <li><b>Variance:</b> the unbiased sample variance of R independent estimates per N, \
         with its standard error from the fourth central moment (error bars ±1 SE).</li>\
         <li><b>Slope:</b> weighted least squares of <code>ln(Var/(ln N)^p)</code> against \
         <code>ln N</code>, p the power of log N of the theory (0 if none), weights \
         <code>(Var/SE)²</code>; 95 % interval <code>±1.96·SE</code>, widened to \
         <code>±t(dof)·SE·√(χ²/dof)</code> when the residuals exceed their errors. Range: the \
         upper two thirds of a curve's N values (at least three; the smallest N are the most \
         pre-asymptotic); segments are fitted on each side of N* separately, on all their N.</li>\
         <li><b>Verdict:</b> <span class=\"v ok\">consistent</span> if the theory slope lies in \
         the 95 % interval widened by ±{SLOPE_TOLERANCE} (what a fit over one to three decades of \
         N can resolve against sub-leading terms); else <span class=\"v pre\">pre-asymptotic</span> \
         if the slope between the two largest N (with its own 95 % interval, widened the same \
         way) is consistent; else <span class=\"v bad\">not consistent</span>.</li>\
         <li><b>Realisations:</b> R per N as listed above: enough that the 95 % interval of every \
         slope is narrower than ±0.2 in quick mode (about 1.96·√(2/R)/√(Σ(ln N − mean)²) for \
         near-Gaussian estimates), so rates 1/3 apart (the smallest gap between theory classes \
         in these tables, 3D jitter against random) are told apart; Poisson disk and CCVT cost \
         10–1000× more per pattern and get fewer.</li>\
         <li><b>Theory inputs</b> per row: β (sampler: random and Poisson disk 0, jittered and \
         multi-jittered 2, CCVT 3, Owen-Sobol′ 2d′), α (integrand seen by the pattern: Gaussian \
         ∞; indicator d′+1; disk or ball chord under lines d′+2; crossed straight edge d′+3), d′ \
         (pattern dimension: d for points and segments, d−1 for line offsets). The derivation is \
         in the repository's <code>docs/theory.md</code>.</li></ul>\n"
    );
    h.push_str(body);
    h.push_str("<h2 id=\"files\">Files</h2>\n<ul>");
    for f in [
        "rates.csv",
        "prediction.csv",
        "cost.csv",
        "curves.csv",
        "manifest.json",
    ] {
        let _ = write!(h, "<li><a href=\"{f}\">{f}</a></li>");
    }
    h.push_str("</ul>\n</body></html>\n");
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_and_dates() {
        assert_eq!(esc("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
        let d = utc_now();
        assert!(d.ends_with(" UTC") && d.len() == 20, "{d}");
        assert!(d.starts_with("20"), "{d}");
    }
}
