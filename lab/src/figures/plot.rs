//! Line plots: the log-log convergence plot and the radial spectrum plot.

use crate::{LabError, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Size of every line plot, in SVG pixels.
const SIZE: (u32, u32) = (800, 580);
pub(crate) const FONT: &str = "sans-serif";
const DATA: RGBColor = RGBColor(31, 78, 153);
const BAND: RGBColor = RGBColor(157, 183, 224);
const FIT: RGBColor = RGBColor(192, 57, 43);
const GREY: RGBColor = RGBColor(110, 110, 110);

/// [`LabError::Internal`] for a `plotters` drawing error.
pub(crate) fn plot_err<E: std::fmt::Debug>(e: E) -> LabError {
    LabError::Internal(format!("drawing a figure: {e:?}"))
}

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

/// A log-log plot of one measured series with error bars, a fitted power law
/// and dashed reference slopes through the first point.
#[derive(Clone, Debug)]
pub struct LogLog<'a> {
    pub title: &'a str,
    pub subtitle: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    pub points: &'a [Point],
    pub fit: Option<PowerLaw>,
    pub reference_slopes: &'a [f64],
}

/// A radial spectrum: ring means (rings `1..=k`, index = ring) with a ±1 SE
/// band on a log y axis and the white-noise level 1 dashed.
#[derive(Clone, Debug)]
pub struct Radial<'a> {
    pub title: &'a str,
    pub subtitle: &'a str,
    pub mean: &'a [f64],
    pub se: &'a [f64],
    pub k: usize,
}

fn drawable(x: f64, y: f64) -> bool {
    x > 0.0 && x.is_finite() && y > 0.0 && y.is_finite()
}

/// `[floor(min), ceil(max)]` of the finite values, at least one decade wide.
pub(crate) fn decades(values: impl Iterator<Item = f64>) -> (f64, f64) {
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

/// Tick label of a log axis: `1e-5` at decades, `{:e}` elsewhere.
pub(crate) fn log_label(v: &f64) -> String {
    let l = v.log10();
    if (l - l.round()).abs() < 1e-9 {
        format!("1e{}", l.round() as i32)
    } else {
        format!("{v:e}")
    }
}

/// The title block: a title and a grey subtitle, returning the area below.
pub(crate) fn titled<'a>(
    root: &DrawingArea<SVGBackend<'a>, Shift>,
    title: &str,
    subtitle: &str,
) -> Result<DrawingArea<SVGBackend<'a>, Shift>> {
    root.fill(&WHITE).map_err(plot_err)?;
    let (w, _) = root.dim_in_pixel();
    let (head, body) = root.split_vertically(56);
    let centre = Pos::new(HPos::Center, VPos::Center);
    head.draw(&Text::new(
        title.to_string(),
        (w as i32 / 2, 18),
        (FONT, 17).into_font().color(&BLACK).pos(centre),
    ))
    .map_err(plot_err)?;
    head.draw(&Text::new(
        subtitle.to_string(),
        (w as i32 / 2, 40),
        (FONT, 11).into_font().color(&GREY).pos(centre),
    ))
    .map_err(plot_err)?;
    Ok(body)
}

/// The shared chart frame: margins and label areas.
pub(crate) fn builder<'a, 'b>(
    area: &'a DrawingArea<SVGBackend<'b>, Shift>,
) -> ChartBuilder<'a, 'b, SVGBackend<'b>> {
    let mut b = ChartBuilder::on(area);
    b.margin(14).x_label_area_size(44).y_label_area_size(70);
    b
}

/// The shared legend style (upper right, framed, translucent background).
macro_rules! legend {
    ($chart:expr) => {
        $chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font((FONT, 12))
            .draw()
            .map_err(plot_err)
    };
}

/// The log-log plot as an SVG document.
///
/// # Errors
/// Only on an internal drawing error.
pub fn loglog(p: &LogLog<'_>) -> Result<String> {
    let pts: Vec<Point> = p
        .points
        .iter()
        .copied()
        .filter(|q| drawable(q.x, q.y))
        .collect();
    let (x0, x1) = decades(pts.iter().map(|q| q.x.log10()));
    let (xmin, xmax) = pts.iter().fold((f64::INFINITY, 0.0f64), |(a, b), q| {
        (a.min(q.x), b.max(q.x))
    });
    let fit_at = |f: &PowerLaw, x: f64| (f.intercept + f.slope * x.ln()).exp();
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
            ys.push(fit_at(f, xmin).log10());
            ys.push(fit_at(f, xmax).log10());
        }
    }
    let (y0, y1) = decades(ys.iter().flat_map(|&y| [y - 0.05, y + 0.05]));
    let (ylo, yhi) = (10f64.powf(y0), 10f64.powf(y1));
    let mut s = String::new();
    {
        let root = SVGBackend::with_string(&mut s, SIZE).into_drawing_area();
        let body = titled(&root, p.title, p.subtitle)?;
        let mut chart = builder(&body)
            .build_cartesian_2d(
                (10f64.powf(x0)..10f64.powf(x1)).log_scale(),
                (ylo..yhi).log_scale(),
            )
            .map_err(plot_err)?;
        chart
            .configure_mesh()
            .x_desc(p.x_label)
            .y_desc(p.y_label)
            .x_label_formatter(&log_label)
            .y_label_formatter(&log_label)
            .label_style((FONT, 12))
            .axis_desc_style((FONT, 13))
            .draw()
            .map_err(plot_err)?;
        if let Some(first) = pts.first() {
            for (i, &slope) in p.reference_slopes.iter().enumerate() {
                // y = y_a (x/x_a)^s, clipped where it leaves the y range.
                let at = |x: f64| first.y * (x / first.x).powf(slope);
                let mut end = xmax.max(first.x * 10.0).min(10f64.powf(x1));
                if slope < 0.0 && at(end) < ylo {
                    end = first.x * (ylo / first.y).powf(1.0 / slope);
                }
                let shade = 60 + 30 * i as u8;
                let style = RGBColor(shade, shade, shade).stroke_width(1);
                chart
                    .draw_series(DashedLineSeries::new(
                        [(first.x, first.y), (end, at(end))],
                        6,
                        4,
                        style,
                    ))
                    .map_err(plot_err)?
                    .label(format!("slope {slope}"))
                    .legend(move |(x, y)| PathElement::new([(x, y), (x + 8, y)], style));
            }
        }
        if let (Some(f), false) = (&p.fit, pts.is_empty()) {
            chart
                .draw_series(LineSeries::new(
                    [(xmin, fit_at(f, xmin)), (xmax, fit_at(f, xmax))],
                    FIT.stroke_width(2),
                ))
                .map_err(plot_err)?
                .label(f.label.clone())
                .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], FIT.stroke_width(2)));
        }
        // An error bar draws its own centre marker; points without a finite
        // error get a plain marker.
        chart
            .draw_series(pts.iter().filter(|q| q.err.is_finite()).map(|q| {
                let lo = (q.y - q.err).max(ylo);
                let hi = (q.y + q.err).min(yhi);
                ErrorBar::new_vertical(q.x, lo, q.y, hi, DATA.filled().stroke_width(1), 8)
            }))
            .map_err(plot_err)?;
        chart
            .draw_series(
                pts.iter()
                    .filter(|q| !q.err.is_finite())
                    .map(|q| Circle::new((q.x, q.y), 4, DATA.filled())),
            )
            .map_err(plot_err)?
            .label("measured (± 1 SE)")
            .legend(|(x, y)| Circle::new((x + 8, y), 4, DATA.filled()));
        legend!(chart)?;
        root.present().map_err(plot_err)?;
    }
    Ok(s)
}

/// The radial spectrum plot as an SVG document.
///
/// # Errors
/// Only on an internal drawing error.
pub fn radial(p: &Radial<'_>) -> Result<String> {
    let k = p.k.max(1);
    let rings = 1..=p.k;
    let (mut lo, mut hi) = (0.0f64, 0.0f64); // log10, including the level 1
    for r in rings.clone() {
        for v in [p.mean[r], p.mean[r] + p.se[r], p.mean[r] - p.se[r]] {
            if v > 0.0 && v.is_finite() {
                lo = lo.min(v.log10());
                hi = hi.max(v.log10());
            }
        }
    }
    let y1 = hi.ceil().max(1.0);
    let y0 = lo.floor().max(y1 - 8.0).min(-1.0);
    let (ylo, yhi) = (10f64.powf(y0), 10f64.powf(y1));
    let clamp = |v: f64| {
        if v > 0.0 {
            v.clamp(ylo, yhi)
        } else {
            ylo
        }
    };
    let mut s = String::new();
    {
        let root = SVGBackend::with_string(&mut s, SIZE).into_drawing_area();
        let body = titled(&root, p.title, p.subtitle)?;
        let mut chart = builder(&body)
            .build_cartesian_2d(0f64..k as f64, (ylo..yhi).log_scale())
            .map_err(plot_err)?;
        chart
            .configure_mesh()
            .x_desc("radius |ν| (ring r: round(|ν|) = r)")
            .y_desc("ring mean of ⟨N·P(ν)⟩")
            .y_label_formatter(&log_label)
            .x_label_formatter(&|v| format!("{v}"))
            .label_style((FONT, 12))
            .axis_desc_style((FONT, 13))
            .draw()
            .map_err(plot_err)?;
        let finite: Vec<usize> = rings
            .clone()
            .filter(|&r| p.se[r].is_finite() && p.mean[r].is_finite())
            .collect();
        if !finite.is_empty() {
            let mut band: Vec<(f64, f64)> = finite
                .iter()
                .map(|&r| (r as f64, clamp(p.mean[r] + p.se[r])))
                .collect();
            band.extend(
                finite
                    .iter()
                    .rev()
                    .map(|&r| (r as f64, clamp(p.mean[r] - p.se[r]))),
            );
            chart
                .draw_series(std::iter::once(Polygon::new(band, BAND.mix(0.6).filled())))
                .map_err(plot_err)?
                .label("± 1 SE")
                .legend(|(x, y)| Rectangle::new([(x, y - 5), (x + 16, y + 5)], BAND.filled()));
        }
        chart
            .draw_series(DashedLineSeries::new(
                [(0.0, 1.0), (k as f64, 1.0)],
                6,
                4,
                FIT.stroke_width(1),
            ))
            .map_err(plot_err)?
            .label("white noise (1)")
            .legend(|(x, y)| PathElement::new([(x, y), (x + 8, y)], FIT.stroke_width(1)));
        // One polyline per run of drawable ring means.
        let mut runs: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
        for r in rings {
            if p.mean[r] > 0.0 && p.mean[r].is_finite() {
                if let Some(v) = runs.last_mut() {
                    v.push((r as f64, p.mean[r].min(yhi)));
                }
            } else if runs.last().is_some_and(|v| !v.is_empty()) {
                runs.push(Vec::new());
            }
        }
        let mut labelled = false;
        for run in runs.into_iter().filter(|v| !v.is_empty()) {
            let series = chart
                .draw_series(LineSeries::new(run, DATA.stroke_width(2)))
                .map_err(plot_err)?;
            if !labelled {
                series
                    .label("ring mean")
                    .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], DATA.stroke_width(2)));
                labelled = true;
            }
        }
        legend!(chart)?;
        root.present().map_err(plot_err)?;
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_and_ranges() {
        assert_eq!(log_label(&1e-5), "1e-5");
        assert_eq!(log_label(&100.0), "1e2");
        assert_eq!(log_label(&0.2), "2e-1");
        assert_eq!(decades([-2.3, 0.4].into_iter()), (-3.0, 1.0));
        assert_eq!(decades(std::iter::empty()), (0.0, 1.0));
    }

    #[test]
    fn loglog_draws_points_bars_fit_and_references() {
        let points = [
            Point {
                x: 16.0,
                y: 1e-3,
                err: 1e-4,
            },
            Point {
                x: 64.0,
                y: 1e-4,
                err: 1e-5,
            },
            Point {
                x: 256.0,
                y: 0.0,
                err: 1.0,
            }, // not drawable
        ];
        let s = loglog(&LogLog {
            title: "a < b",
            subtitle: "sub",
            x_label: "N",
            y_label: "Var",
            points: &points,
            fit: Some(PowerLaw {
                slope: -1.66,
                intercept: 1.0,
                label: "fit".into(),
            }),
            reference_slopes: &[-1.0, -2.0],
        })
        .unwrap();
        assert!(s.starts_with("<svg") && s.trim_end().ends_with("</svg>"));
        assert!(s.contains("a &lt; b"), "title escaped");
        // Two data points and one legend marker.
        assert_eq!(s.matches("<circle").count(), 3);
        for label in ["slope -1", "slope -2", "fit", "measured"] {
            assert!(s.contains(label), "{label}");
        }
    }

    #[test]
    fn radial_plot_skips_zero_rings() {
        let mean = [1.0, 0.0, 0.5, 1.2, 1.0];
        let se = [0.0, 0.1, 0.1, f64::INFINITY, 0.05];
        let s = radial(&Radial {
            title: "t",
            subtitle: "s",
            mean: &mean,
            se: &se,
            k: 4,
        })
        .unwrap();
        assert!(s.contains("ring mean") && s.contains("white noise (1)"));
        // Ring 1 is 0: the data line starts at ring 2 (one polyline + legend).
        let data = s
            .lines()
            .filter(|l| l.starts_with("<polyline") && l.contains("#1F4E99"))
            .count();
        assert_eq!(data, 2, "{s}");
    }
}
