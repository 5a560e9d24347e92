//! A log-log SVG plot of positive data with error bars, a fitted power law and
//! dashed reference slopes. Formatting only.

use std::fmt::Write as _;

/// One data point: `x > 0`, `y`, and the standard error of `y` (error bar
/// `y ± err`). Points with `y ≤ 0` or non-finite values cannot be drawn on a
/// log axis and are skipped.
#[derive(Clone, Copy, Debug)]
pub struct Point {
    pub x: f64,
    pub y: f64,
    pub err: f64,
}

/// A power law `y = exp(intercept) · x^slope` (natural logarithms) drawn over
/// the x range of the data, with its legend label.
#[derive(Clone, Debug)]
pub struct PowerLaw {
    pub slope: f64,
    pub intercept: f64,
    pub label: String,
}

/// What to draw.
#[derive(Clone, Debug)]
pub struct LogLog<'a> {
    pub title: &'a str,
    pub subtitle: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    pub points: &'a [Point],
    pub fit: Option<PowerLaw>,
    /// Slopes of the thin dashed reference lines, drawn through the first
    /// drawable data point and clipped to the plot area.
    pub reference_slopes: &'a [f64],
}

const WIDTH: f64 = 760.0;
const HEIGHT: f64 = 560.0;
const LEFT: f64 = 90.0;
const RIGHT: f64 = 210.0;
const TOP: f64 = 76.0;
const BOTTOM: f64 = 64.0;

/// Escapes the XML special characters of `s`.
pub fn xml_escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
    out
}

/// `−1.5` with a typographic minus sign.
fn signed(v: f64) -> String {
    let s = format!("{v}");
    s.replace('-', "\u{2212}")
}

fn drawable(p: &Point) -> bool {
    p.x > 0.0 && p.x.is_finite() && p.y > 0.0 && p.y.is_finite()
}

/// The decade range `[floor(min), ceil(max)]` of `log10` values, at least one
/// decade wide.
fn decades(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let (lo, mut hi) = (lo.floor(), hi.ceil());
    if hi <= lo {
        hi = lo + 1.0;
    }
    (lo, hi)
}

/// The plot as a standalone SVG document.
pub fn svg(p: &LogLog<'_>) -> String {
    let pts: Vec<Point> = p.points.iter().copied().filter(drawable).collect();
    let (pw, ph) = (WIDTH - LEFT - RIGHT, HEIGHT - TOP - BOTTOM);
    let (x0, x1) = decades(pts.iter().map(|q| q.x.log10()));
    let fit_at = |f: &PowerLaw, x: f64| (f.intercept + f.slope * x.ln()) / std::f64::consts::LN_10;
    let (xmin, xmax) = pts.iter().fold((f64::INFINITY, 0.0f64), |(a, b), q| {
        (a.min(q.x), b.max(q.x))
    });
    let mut ys: Vec<f64> = Vec::new();
    for q in &pts {
        ys.push(q.y.log10());
        if q.err.is_finite() {
            ys.push((q.y + q.err).log10());
            if q.y - q.err > 0.0 {
                ys.push((q.y - q.err).log10());
            }
        }
    }
    if let Some(f) = &p.fit {
        if !pts.is_empty() {
            ys.push(fit_at(f, xmin));
            ys.push(fit_at(f, xmax));
        }
    }
    // A little headroom so no point or bar end sits on the frame.
    let (y0, y1) = decades(
        ys.iter()
            .map(|&y| y - 0.05)
            .chain(ys.iter().map(|&y| y + 0.05)),
    );
    let sx = |lx: f64| LEFT + (lx - x0) / (x1 - x0) * pw;
    let sy = |ly: f64| TOP + ph - (ly - y0) / (y1 - y0) * ph;

    let mut s = String::with_capacity(8192);
    let _ = writeln!(s, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{HEIGHT}" viewBox="0 0 {WIDTH} {HEIGHT}" font-family="sans-serif" font-size="13">"#
    );
    let _ = writeln!(s, r##"<rect width="100%" height="100%" fill="#fff"/>"##);
    let _ = writeln!(
        s,
        r#"<text x="{:.1}" y="26" text-anchor="middle" font-size="16">{}</text>"#,
        WIDTH / 2.0,
        xml_escape(p.title)
    );
    let _ = writeln!(
        s,
        r##"<text x="{:.1}" y="48" text-anchor="middle" fill="#444">{}</text>"##,
        WIDTH / 2.0,
        xml_escape(p.subtitle)
    );
    let _ = writeln!(
        s,
        r#"<defs><clipPath id="area"><rect x="{LEFT}" y="{TOP}" width="{pw}" height="{ph}"/></clipPath></defs>"#
    );

    // Grid, ticks and decade labels.
    let mut k = x0;
    while k <= x1 + 0.5 {
        let x = sx(k);
        let _ = writeln!(
            s,
            r##"<line x1="{x:.1}" y1="{TOP}" x2="{x:.1}" y2="{:.1}" stroke="#ddd"/>"##,
            TOP + ph
        );
        let _ = writeln!(
            s,
            r#"<text x="{x:.1}" y="{:.1}" text-anchor="middle">10<tspan dy="-6" font-size="10">{}</tspan></text>"#,
            TOP + ph + 20.0,
            signed(k)
        );
        if k < x1 {
            for m in 2..10 {
                let xm = sx(k + f64::from(m).log10());
                let _ = writeln!(
                    s,
                    r##"<line x1="{xm:.1}" y1="{:.1}" x2="{xm:.1}" y2="{:.1}" stroke="#000"/>"##,
                    TOP + ph,
                    TOP + ph - 4.0
                );
            }
        }
        k += 1.0;
    }
    let mut k = y0;
    while k <= y1 + 0.5 {
        let y = sy(k);
        let _ = writeln!(
            s,
            r##"<line x1="{LEFT}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#ddd"/>"##,
            LEFT + pw
        );
        let _ = writeln!(
            s,
            r#"<text x="{:.1}" y="{:.1}" text-anchor="end">10<tspan dy="-6" font-size="10">{}</tspan></text>"#,
            LEFT - 8.0,
            y + 4.0,
            signed(k)
        );
        if k < y1 && y1 - y0 <= 12.0 {
            for m in 2..10 {
                let ym = sy(k + f64::from(m).log10());
                let _ = writeln!(
                    s,
                    r##"<line x1="{LEFT}" y1="{ym:.1}" x2="{:.1}" y2="{ym:.1}" stroke="#000"/>"##,
                    LEFT + 4.0
                );
            }
        }
        k += 1.0;
    }
    let _ = writeln!(
        s,
        r##"<rect x="{LEFT}" y="{TOP}" width="{pw}" height="{ph}" fill="none" stroke="#000"/>"##
    );
    let _ = writeln!(
        s,
        r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
        LEFT + pw / 2.0,
        HEIGHT - 14.0,
        xml_escape(p.x_label)
    );
    let _ = writeln!(
        s,
        r#"<text transform="translate(22 {:.1}) rotate(-90)" text-anchor="middle">{}</text>"#,
        TOP + ph / 2.0,
        xml_escape(p.y_label)
    );

    if pts.is_empty() {
        let _ = writeln!(
            s,
            r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">no positive values to plot</text>"#,
            LEFT + pw / 2.0,
            TOP + ph / 2.0
        );
        s.push_str("</svg>\n");
        return s;
    }

    // Reference slopes through the first point, labelled where they leave the area.
    let (ax, ay) = (pts[0].x.log10(), pts[0].y.log10());
    let mut refs = String::new();
    for &slope in p.reference_slopes {
        let at = |lx: f64| ay + slope * (lx - ax);
        let _ = writeln!(
            refs,
            r##"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="#888" stroke-width="0.8" stroke-dasharray="5 4" clip-path="url(#area)"/>"##,
            sx(x0),
            sy(at(x0)),
            sx(x1),
            sy(at(x1))
        );
        let label = format!(
            "N<tspan dy=\"-5\" font-size=\"9\">{}</tspan>",
            signed(slope)
        );
        let y_end = at(x1);
        let (lx, ly, anchor) = if (y0..=y1).contains(&y_end) {
            (sx(x1) + 4.0, sy(y_end) + 4.0, "start")
        } else if slope != 0.0 {
            let bound = if y_end < y0 { y0 } else { y1 };
            let xe = ax + (bound - ay) / slope;
            let dy = if y_end < y0 { -6.0 } else { 14.0 };
            (sx(xe), sy(bound) + dy, "middle")
        } else {
            continue;
        };
        let _ = writeln!(
            refs,
            r##"<text x="{lx:.1}" y="{ly:.1}" text-anchor="{anchor}" font-size="11" fill="#666">{label}</text>"##
        );
    }
    s.push_str(&refs);

    if let Some(f) = &p.fit {
        let _ = writeln!(
            s,
            r##"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="#c0392b" stroke-width="1.8" clip-path="url(#area)"/>"##,
            sx(xmin.log10()),
            sy(fit_at(f, xmin)),
            sx(xmax.log10()),
            sy(fit_at(f, xmax))
        );
    }

    // Data with error bars (a lower end at or below zero runs off the bottom).
    for q in &pts {
        let (x, y) = (sx(q.x.log10()), sy(q.y.log10()));
        if q.err.is_finite() && q.err > 0.0 {
            let top = sy((q.y + q.err).log10());
            let bottom = if q.y - q.err > 0.0 {
                sy((q.y - q.err).log10())
            } else {
                TOP + ph
            };
            let _ = writeln!(
                s,
                r##"<g stroke="#1f4e99" clip-path="url(#area)"><line x1="{x:.1}" y1="{top:.1}" x2="{x:.1}" y2="{bottom:.1}"/><line x1="{:.1}" y1="{top:.1}" x2="{:.1}" y2="{top:.1}"/><line x1="{:.1}" y1="{bottom:.1}" x2="{:.1}" y2="{bottom:.1}"/></g>"##,
                x - 4.0,
                x + 4.0,
                x - 4.0,
                x + 4.0
            );
        }
        let _ = writeln!(
            s,
            r##"<circle cx="{x:.1}" cy="{y:.1}" r="3.5" fill="#1f4e99"/>"##
        );
    }

    // Legend in the right margin.
    let lx = LEFT + pw + 16.0;
    let mut ly = TOP + 10.0;
    let _ = writeln!(
        s,
        r##"<circle cx="{:.1}" cy="{:.1}" r="3.5" fill="#1f4e99"/><text x="{:.1}" y="{:.1}">data ± 1 SE</text>"##,
        lx + 10.0,
        ly - 4.0,
        lx + 26.0,
        ly
    );
    if let Some(f) = &p.fit {
        ly += 22.0;
        let _ = writeln!(
            s,
            r##"<line x1="{lx:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="#c0392b" stroke-width="1.8"/><text x="{:.1}" y="{ly:.1}">{}</text>"##,
            ly - 4.0,
            lx + 20.0,
            ly - 4.0,
            lx + 26.0,
            xml_escape(&f.label)
        );
    }
    if !p.reference_slopes.is_empty() {
        ly += 22.0;
        let _ = writeln!(
            s,
            r##"<line x1="{lx:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="#888" stroke-dasharray="5 4"/><text x="{:.1}" y="{ly:.1}">reference slopes</text>"##,
            ly - 4.0,
            lx + 20.0,
            ly - 4.0,
            lx + 26.0
        );
    }
    s.push_str("</svg>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decade_ranges() {
        assert_eq!(decades([1.2, 3.6].into_iter()), (1.0, 4.0));
        assert_eq!(decades([2.0].into_iter()), (2.0, 3.0));
        assert_eq!(decades(std::iter::empty()), (0.0, 1.0));
    }

    #[test]
    fn plot_has_points_fit_and_references() {
        let pts = [
            Point {
                x: 16.0,
                y: 1e-3,
                err: 1e-4,
            },
            Point {
                x: 256.0,
                y: 1e-5,
                err: 2e-5,
            },
            Point {
                x: 4096.0,
                y: 0.0,
                err: 1.0,
            },
        ];
        let s = svg(&LogLog {
            title: "a < b",
            subtitle: "s",
            x_label: "N",
            y_label: "Var",
            points: &pts,
            fit: Some(PowerLaw {
                slope: -1.5,
                intercept: 0.0,
                label: "fit".into(),
            }),
            reference_slopes: &[-1.0, -2.0],
        });
        assert!(s.starts_with("<?xml") && s.ends_with("</svg>\n"));
        assert!(s.contains("a &lt; b"));
        assert_eq!(s.matches("<circle ").count(), 3); // 2 points + legend
        assert_eq!(s.matches("stroke-dasharray").count(), 3); // 2 refs + legend
    }
}
