//! Section 9 of the report: direct light in the Cornell box with line
//! orientation, read from the files `direct::paper_runs` wrote under
//! `OUT/direct/`.

use std::fmt::Write as _;
use std::path::Path;

use serde_json::Value;

use super::esc;
use crate::experiments::direct::CORNELL_SCENE_NAME;
use crate::fit::fit_sci;

use crate::experiments::study::SLOPE_SLACK;

/// The expected slope of an estimator (jittered patterns) at a pixel, with
/// the reason; `None` where no single rate holds over `[n_min, n_max]`.
/// `turn` is `N*` of a parallel-edge pixel (P1, P2): the lines parallel to
/// the edge see a jump below it and a kink above.
fn expected(
    pixel: &str,
    estimator: &str,
    turn: Option<f64>,
    n_min: f64,
    n_max: f64,
) -> Option<(f64, String)> {
    let parallel = matches!(
        (pixel, estimator),
        ("P1", "lines-edge1") | ("P2", "lines-edge2")
    );
    if parallel {
        let t = turn?;
        return if t >= n_max {
            Some((
                -2.0,
                format!(
                    "lines parallel to a shadow edge: a jump while N < N* = {t:.0}, 1D jitter N^-2"
                ),
            ))
        } else if t <= n_min {
            Some((
                -3.0,
                format!("the near-parallel edge is resolved beyond N* = {t:.0}: a kink, N^-3"),
            ))
        } else {
            None
        };
    }
    match estimator {
        "points" => Some((-1.5, "2D jitter, shadow edges: N^-1.5".into())),
        "lines-edge1" | "lines-edge2" => Some((
            -3.0,
            "lines crossing every shadow edge: the line function has kinks, N^-3".into(),
        )),
        "lines-random-per-point" => Some((
            -3.0,
            "a random direction is almost surely not parallel to an edge: N^-3".into(),
        )),
        "lines-random-per-line" => Some((
            -1.0,
            "independent directions: the direction is not stratified, N^-1".into(),
        )),
        _ => None,
    }
}

/// The section's HTML, or a note saying how to produce it.
///
/// # Errors
/// A file that exists but does not parse.
pub(in crate::experiments::paper) fn section_direct(out_dir: &Path) -> crate::Result<String> {
    let dir = out_dir.join("direct");
    let mut h = String::new();
    h.push_str("<h2 id=\"direct\">9 A rendering problem: direct light and line orientation</h2>\n");
    let csv_path = dir.join("images.csv");
    if !csv_path.is_file() {
        let _ = writeln!(
            h,
            "<p>Not run: a sharded <code>paper</code> run leaves the scene out. Run \
             <code>linesample-lab scene {CORNELL_SCENE_NAME}</code> for these results.</p>"
        );
        return Ok(h);
    }
    let _ = writeln!(
        h,
        "<p>The Cornell box (<code>{CORNELL_SCENE_NAME}</code>) with the one effect it asks \
         for: direct light from the rectangular light under the ceiling onto the diffuse \
         surfaces, <code>E = ∫ G V dA</code> with <code>G = cos θ_x cos θ_y / r²</code>, no \
         indirect light (so the box faces turned away from the light are black). A camera ray \
         per pixel finds the surface point; the occluders' faces are projected from it onto the \
         light's plane (exact shadows as convex polygons). <b>Points</b> sample the light \
         uniformly by area. <b>Lines</b> cross the light with an orientation and an offset, and \
         each contributes the closed-form integral of G over its visible pieces (Billen &amp; \
         Dutré 2016): along the light's first edge (<i>edge1</i>), its second (<i>edge2</i>), \
         one random direction per estimate (<i>random-per-point</i>), one per line \
         (<i>random-per-line</i>), or direction and offset from one 2D pattern \
         (<i>stratified</i>). Jittered patterns are not shifted: a toroidal shift would move \
         the strata off the light's edges, where lines along an edge see a jump in the \
         periodised line function and drop to N<sup>-2</sup>.</p>"
    );
    let _ = writeln!(
        h,
        "<h3>Images</h3><figure><img src=\"direct/sheet.png\" style=\"width:100%;\
         image-rendering:pixelated\"><figcaption>Columns: the reference (lines along edge 1, \
         4 × 256 jittered offsets), then points, lines edge1, edge2, random-per-point, \
         random-per-line, stratified (jittered), and the edge1 lines through the kernel's \
         f32 SIMD batch. Row 1: N = 16 samples per pixel (equal \
         samples). Row 2: each estimator at the N whose measured time is closest to the edge1 \
         lines' at N = 16 (equal time). Row 3: per-pixel variance of E at N = 16 over 8 \
         realisations (log scale, 8 decades below the mean E², dark blue to yellow). Files: \
         <a href=\"direct/images.csv\">images.csv</a> and one PNG per image in \
         <code>direct/</code>.</figcaption></figure>\
         <figure><img src=\"direct/orientation-map.png\" style=\"width:40%;\
         image-rendering:pixelated\"><figcaption>Which fixed orientation has the smaller \
         variance at N = 16: red where lines along edge 1 win, blue where edge 2 wins, \
         brightness the log ratio (full at 100×); white crosses mark A and B.</figcaption>\
         </figure>"
    );
    let rows = super::scene_section::read_csv(&csv_path)?;
    super::scene_section::images_table(&mut h, &rows);
    h.push_str("</table>\n");
    pixel_studies(&mut h, &dir)?;
    Ok(h)
}

/// Pixels A, B, P1 and P2: why each was chosen, their slopes against the
/// expectation, and their curves.
///
/// # Errors
/// A file that exists but does not parse.
fn pixel_studies(h: &mut String, dir: &Path) -> crate::Result<()> {
    let chosen: Value = match std::fs::read(dir.join("pixels.json")) {
        Ok(b) => serde_json::from_slice(&b).map_err(|e| format!("pixels.json: {e}"))?,
        Err(_) => Value::Null,
    };
    if chosen.is_null() {
        h.push_str("<p>No penumbra pixel was found: no pixel study.</p>\n");
        return Ok(());
    }
    let xy = |v: &Value| format!("({}, {})", v[0], v[1]);
    let mut pixel_text = format!(
        "<p><b>A</b> {} (largest var(edge2)/var(edge1) at N = 16 among penumbra pixels: \
         {:.3e}) and <b>B</b> {} (smallest: {:.3e}) follow the scan the question asks for. \
         A ratio that large can come from the constants alone: both fixed orientations \
         usually cross every shadow edge (the boxes are rotated by 17°, and vertical box edges \
         project onto the light along the line from the pixel's foot point to the edge), so \
         both converge as N<sup>-3</sup>. ",
        xy(&chosen["a"]),
        chosen["ratio_a"].as_f64().unwrap_or(f64::NAN),
        xy(&chosen["b"]),
        chosen["ratio_b"].as_f64().unwrap_or(f64::NAN),
    );
    for (name, key, k) in [("P1", "parallel1", 1), ("P2", "parallel2", 2)] {
        let p = &chosen[key];
        if p.is_null() {
            let _ = write!(
                pixel_text,
                "No penumbra pixel has a shadow edge within 2° of the light's edge {k} at this \
                 resolution (no {name}). "
            );
        } else {
            let _ = write!(
                pixel_text,
                "<b>{name}</b> {} is the penumbra pixel whose shadow has an edge closest to \
                 parallel to the light's edge {k} ({:.3}°, {:.3} long on the light): lines along \
                 edge {k} see it as a jump while their strata are wider than its ramp, i.e. for \
                 N below N* = W/(ℓ sin α) ≈ {:.0}, and as a kink beyond. ",
                xy(&p["pixel"]),
                p["angle_deg"].as_f64().unwrap_or(f64::NAN),
                p["length"].as_f64().unwrap_or(f64::NAN),
                p["turn_n"].as_f64().unwrap_or(f64::NAN)
            );
        }
    }
    pixel_text.push_str("</p>\n");
    h.push_str(&pixel_text);
    let slopes_path = dir.join("pixels").join("slopes.csv");
    let Ok(mut rdr) = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_path(&slopes_path)
    else {
        h.push_str("<p>The pixel studies did not run.</p>\n");
        return Ok(());
    };
    let rows: Vec<csv::StringRecord> = rdr
        .records()
        .collect::<Result<_, _>>()
        .map_err(|e| format!("{}: {e}", slopes_path.display()))?;
    h.push_str(
        "<table><tr><th>pixel</th><th>estimator</th><th>sampler</th><th>slope [95 %]</th>\
         <th>last two N</th><th>expected</th><th>verdict</th><th>time to 1 % (s)</th></tr>",
    );
    // The N range of the studies (rows.csv: pixel, x, y, estimator, sampler, n, …).
    let ns: Vec<f64> = std::fs::read_to_string(dir.join("pixels").join("rows.csv"))
        .unwrap_or_default()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .filter_map(|l| l.split(',').nth(5)?.parse().ok())
        .collect();
    let n_min = ns.iter().copied().fold(f64::INFINITY, f64::min);
    let n_max = ns.iter().copied().fold(0.0, f64::max);
    for r in &rows {
        let (pixel, est, sampler) = (&r[0], &r[1], &r[2]);
        let f = |i: usize| r[i].parse::<f64>().unwrap_or(f64::NAN);
        let (slope, lo, hi, last, t1) = (f(3), f(4), f(5), f(6), f(7));
        let turn = match pixel {
            "P1" => chosen["parallel1"]["turn_n"].as_f64(),
            "P2" => chosen["parallel2"]["turn_n"].as_f64(),
            _ => None,
        };
        let exp = if sampler == "random" {
            Some((-1.0, "random patterns: N^-1".to_string()))
        } else {
            expected(pixel, est, turn, n_min, n_max)
        };
        let (exp_text, verdict) = match exp {
            Some((e, why)) => {
                let ok = e >= lo - SLOPE_SLACK && e <= hi + SLOPE_SLACK;
                (
                    format!("<span title=\"{}\">{e:+.1}</span>", esc(&why)),
                    if ok { "consistent" } else { "differs" },
                )
            }
            None => ("—".to_string(), ""),
        };
        let _ = write!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{slope:+.2} [{lo:+.2}, {hi:+.2}]</td>\
             <td>{last:+.2}</td><td>{exp_text}</td><td>{verdict}</td><td>{}</td></tr>",
            esc(pixel),
            esc(est),
            esc(sampler),
            fit_sci(t1, 2)
        );
    }
    h.push_str(
        "</table><p>Hover an expectation for its reason. <i>Stratified</i> has no single \
         expectation here: its 2D pattern stratifies the direction and the offset together, and \
         the line function of (direction, offset) has point singularities wherever the \
         direction is parallel to a shadow edge (and at the light's corners), which is \
         pre-asymptotic over this range of N. At a pixel where a shadow edge is only nearly \
         parallel to the lines (angle α), the jump is a ramp of width ≈ ℓ sin α in offset: \
         the lines see a jump (N<sup>-2</sup>) while the strata are wider than the ramp and a \
         kink (N<sup>-3</sup>) beyond; the last-two-N column shows that turn. Files: \
         <a href=\"direct/orientation.csv\">orientation.csv</a>, \
         <a href=\"direct/pixels/slopes.csv\">slopes.csv</a>, \
         <a href=\"direct/pixels/rows.csv\">rows.csv</a>.</p>\n<div class=\"figs\">",
    );
    let mut labels: Vec<String> = rows.iter().map(|r| r[0].to_string()).collect();
    labels.dedup();
    for l in labels {
        let _ = write!(
            h,
            "<figure><img src=\"direct/pixels/convergence-{l}.svg\"><figcaption>Pixel {l}: \
             variance of E against N.</figcaption></figure><figure>\
             <img src=\"direct/pixels/time-to-error-{l}.svg\"><figcaption>Pixel {l}: relative \
             RMSE against time per estimate.</figcaption></figure>",
            l = esc(&l)
        );
    }
    h.push_str("</div>\n");
    Ok(())
}
