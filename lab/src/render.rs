//! Text and SVG output of a point set. Formatting only.

use std::fmt::Write as _;

use crate::sampler::Points;

/// One point per line, coordinates separated by single spaces, each written with
/// Rust's shortest round-trip formatting of the `f32` (`{}`), `\n` line ends.
/// This is the plain point-file format the UTK toolkit reads.
pub fn txt(points: &Points) -> String {
    let mut s = String::with_capacity(points.coords.len() * 12);
    for p in points.iter() {
        for (j, x) in p.iter().enumerate() {
            if j > 0 {
                s.push(' ');
            }
            // Writing to a String cannot fail.
            let _ = write!(s, "{x}");
        }
        s.push('\n');
    }
    s
}

/// Side of one square panel, in SVG user units (pixels).
const PANEL: f64 = 400.0;
/// Space around and between panels.
const PAD: f64 = 40.0;
/// Top of the panels (below the title and the panel labels).
const TOP: f64 = 64.0;

/// The SVG scatter plot: the unit square framed, with a title line.
///
/// 1D: the points on a line segment `[0, 1]`. 2D: the unit square, `y` up.
/// 3D: the three axis-aligned projections `xy`, `xz`, `yz` side by side. Every
/// point is one `<circle>` per panel (so `N` circles, or `3N` in 3D).
pub fn svg(points: &Points, title: &str) -> String {
    let n = points.len();
    let mut s = String::with_capacity(n * 48 * points.dims.max(1) + 2048);
    match points.dims {
        1 => {
            let width = 2.0 * PANEL + 2.0 * PAD;
            let height = TOP + 80.0;
            header(&mut s, width, height, title);
            let (x0, y) = (PAD, TOP + 24.0);
            let _ = writeln!(
                s,
                r##"<rect x="{x0}" y="{:.1}" width="{:.1}" height="48" fill="none" stroke="#888"/>"##,
                y - 24.0,
                2.0 * PANEL
            );
            let _ = writeln!(
                s,
                r##"<line x1="{x0}" y1="{y}" x2="{:.1}" y2="{y}" stroke="#000"/>"##,
                x0 + 2.0 * PANEL
            );
            tick_label(&mut s, x0, y + 40.0, "0");
            tick_label(&mut s, x0 + 2.0 * PANEL, y + 40.0, "1");
            tick_label(&mut s, x0 + PANEL, y + 40.0, "x");
            let r = radius(2.0 * PANEL / n.max(1) as f64);
            points_open(&mut s);
            for p in points.iter() {
                circle(&mut s, x0 + f64::from(p[0]) * 2.0 * PANEL, y, r);
            }
            s.push_str("</g>\n");
        }
        2 => {
            let width = PANEL + 2.0 * PAD;
            let height = TOP + PANEL + PAD;
            header(&mut s, width, height, title);
            panel(&mut s, points, PAD, (0, 1), None);
        }
        _ => {
            let width = 3.0 * PANEL + 4.0 * PAD;
            let height = TOP + PANEL + PAD;
            header(&mut s, width, height, title);
            for (k, (axes, label)) in [((0, 1), "xy"), ((0, 2), "xz"), ((1, 2), "yz")]
                .into_iter()
                .enumerate()
            {
                let x0 = PAD + k as f64 * (PANEL + PAD);
                panel(&mut s, points, x0, axes, Some(label));
            }
        }
    }
    s.push_str("</svg>\n");
    s
}

const AXES: [&str; 3] = ["x", "y", "z"];

/// One framed unit-square panel at `x0` showing coordinates `axes` of each point.
fn panel(s: &mut String, points: &Points, x0: f64, axes: (usize, usize), label: Option<&str>) {
    let (a, b) = axes;
    if let Some(label) = label {
        let _ = writeln!(
            s,
            r#"<text x="{:.1}" y="{:.1}" font-size="14" text-anchor="middle" font-weight="bold">{label}</text>"#,
            x0 + PANEL / 2.0,
            TOP - 10.0
        );
    }
    let _ = writeln!(
        s,
        r##"<rect x="{x0}" y="{TOP}" width="{PANEL}" height="{PANEL}" fill="none" stroke="#000"/>"##
    );
    tick_label(s, x0, TOP + PANEL + 16.0, "0");
    tick_label(s, x0 + PANEL, TOP + PANEL + 16.0, "1");
    tick_label(s, x0 + PANEL / 2.0, TOP + PANEL + 16.0, AXES[a]);
    tick_label(s, x0 - 10.0, TOP + 5.0, "1");
    tick_label(s, x0 - 10.0, TOP + PANEL / 2.0 + 5.0, AXES[b]);
    let r = radius(PANEL / (points.len().max(1) as f64).sqrt());
    points_open(s);
    for p in points.iter() {
        circle(
            s,
            x0 + f64::from(p[a]) * PANEL,
            TOP + (1.0 - f64::from(p[b])) * PANEL,
            r,
        );
    }
    s.push_str("</g>\n");
}

/// Dot radius for a typical point spacing of `spacing` pixels.
fn radius(spacing: f64) -> f64 {
    (spacing * 0.2).clamp(0.6, 4.0)
}

fn header(s: &mut String, width: f64, height: f64, title: &str) {
    let _ = writeln!(
        s,
        r#"<?xml version="1.0" encoding="UTF-8"?>
<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="sans-serif">
<rect width="100%" height="100%" fill="white"/>
<text x="{:.1}" y="26" font-size="{:.1}" text-anchor="middle">{}</text>"#,
        width / 2.0,
        // Shrink long titles to fit (a sans-serif glyph is about 0.55 em wide).
        (0.95 * width / (0.55 * title.chars().count().max(1) as f64)).min(16.0),
        escape(title)
    );
}

fn tick_label(s: &mut String, x: f64, y: f64, text: &str) {
    let _ = writeln!(
        s,
        r##"<text x="{x:.1}" y="{y:.1}" font-size="12" text-anchor="middle" fill="#444">{}</text>"##,
        escape(text)
    );
}

fn points_open(s: &mut String) {
    s.push_str("<g fill=\"#1f4e9c\" fill-opacity=\"0.85\" stroke=\"none\">\n");
}

fn circle(s: &mut String, cx: f64, cy: f64, r: f64) {
    let _ = writeln!(s, r#"<circle cx="{cx:.2}" cy="{cy:.2}" r="{r:.2}"/>"#);
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}
