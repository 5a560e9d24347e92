//! Multi-series plots of the paper report: log-log convergence curves with
//! fits, theory slopes and predictions; a labelled scatter of fitted slope
//! against intercept; and multi-series line plots (radial spectra, cost).

use plotters::prelude::*;

use super::plot::{builder, decades, log_label, plot_err, titled, FONT};
use crate::Result;

/// Size of every multi-series plot, in SVG pixels.
const SIZE: (u32, u32) = (900, 620);

/// A qualitative palette (Tableau 10), cycled by series index.
pub const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// The colour of series `i`.
#[must_use]
pub fn color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// One series of a [`Multi`] plot.
#[derive(Clone, Debug, Default)]
pub struct Series {
    pub label: String,
    /// `(x, y, SE of y)`; non-drawable points are skipped.
    pub points: Vec<(f64, f64, f64)>,
    /// Predicted `(x, y)` (hollow markers).
    pub predicted: Vec<(f64, f64)>,
    /// A fitted line `y = e^a·x^s·l(x)` drawn over `[x0, x1]`, where `l` is
    /// `(ln x)^log_power`.
    pub fit: Option<Line>,
    /// A dashed theory line of the same form.
    pub theory: Option<Line>,
    /// Join the points with a line (spectra, cost).
    pub joined: bool,
    /// Draw the joining line dashed.
    pub dashed: bool,
    /// Palette index (default: the series index).
    pub color: Option<usize>,
}

/// A power law `y = e^a·x^s·(ln x)^p` drawn between `x0` and `x1`.
#[derive(Clone, Copy, Debug)]
pub struct Line {
    pub a: f64,
    pub slope: f64,
    pub log_power: u32,
    pub x0: f64,
    pub x1: f64,
}

impl Line {
    fn at(&self, x: f64) -> f64 {
        (self.a + self.slope * x.ln()).exp() * x.ln().powi(self.log_power as i32)
    }

    fn polyline(&self) -> Vec<(f64, f64)> {
        let (l0, l1) = (self.x0.ln(), self.x1.ln());
        (0..=24)
            .map(|i| {
                let x = (l0 + (l1 - l0) * f64::from(i) / 24.0).exp();
                (x, self.at(x))
            })
            .collect()
    }
}

/// A multi-series plot.
#[derive(Clone, Debug)]
pub struct Multi<'a> {
    pub title: &'a str,
    pub subtitle: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    pub series: &'a [Series],
    /// Logarithmic x axis (else linear).
    pub log_x: bool,
}

fn drawable(x: f64, y: f64, log_x: bool) -> bool {
    (x > 0.0 || !log_x) && x.is_finite() && y > 0.0 && y.is_finite()
}

/// The plot as an SVG document: per series, measured points with ±1 SE
/// bars, hollow predicted markers, the fit (solid) and the theory (dashed),
/// all in the series' colour; the legend names each series once.
///
/// # Errors
/// Only on an internal drawing error.
pub fn multi(p: &Multi<'_>) -> Result<String> {
    let (x0, x1, ylo, yhi) = ranges(p);
    let clip = |v: f64| v.clamp(ylo, yhi);
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, SIZE).into_drawing_area();
        let body = titled(&root, p.title, p.subtitle)?;
        if p.log_x {
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
            draw_all(&mut chart, p, &clip)?;
        } else {
            let mut chart = builder(&body)
                .build_cartesian_2d(x0..x1, (ylo..yhi).log_scale())
                .map_err(plot_err)?;
            chart
                .configure_mesh()
                .x_desc(p.x_label)
                .y_desc(p.y_label)
                .y_label_formatter(&log_label)
                .label_style((FONT, 12))
                .axis_desc_style((FONT, 13))
                .draw()
                .map_err(plot_err)?;
            draw_all(&mut chart, p, &clip)?;
        }
        root.present().map_err(plot_err)?;
    }
    Ok(out)
}

/// The axes' ranges of `p`: `(x0, x1)` (in decades for a log axis) and the y
/// range `(ylo, yhi)`, whole decades around every drawable point and its
/// lower error bar.
fn ranges(p: &Multi<'_>) -> (f64, f64, f64, f64) {
    let lx = |x: f64| if p.log_x { x.log10() } else { x };
    let (mut xs, mut ys) = (Vec::new(), Vec::new());
    for s in p.series {
        for &(x, y, e) in &s.points {
            if drawable(x, y, p.log_x) {
                xs.push(lx(x));
                ys.push(y.log10());
                if e.is_finite() && y - e > 0.0 {
                    ys.push((y - e).log10());
                }
            }
        }
        for &(x, y) in &s.predicted {
            if drawable(x, y, p.log_x) {
                xs.push(lx(x));
                ys.push(y.log10());
            }
        }
    }
    let (x0, x1) = if p.log_x {
        decades(xs.iter().copied())
    } else {
        let lo = xs.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        if lo.is_finite() && hi > lo {
            (lo, hi)
        } else {
            (0.0, 1.0)
        }
    };
    let (y0, y1) = decades(ys.iter().flat_map(|&y| [y - 0.05, y + 0.05]));
    (x0, x1, 10f64.powf(y0), 10f64.powf(y1))
}

/// A [`multi`] chart: a log or linear x axis, a log y axis.
type MultiChart<'a, 'b, X> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<X, LogCoord<f64>>>;

/// Every series of `p` on `chart` (y values clipped by `clip`), then the
/// legend.
fn draw_all<'a, 'b: 'a, X: Ranged<ValueType = f64>>(
    chart: &mut MultiChart<'a, 'b, X>,
    p: &Multi<'_>,
    clip: &impl Fn(f64) -> f64,
) -> Result<()> {
    for (i, s) in p.series.iter().enumerate() {
        draw_one(chart, s, color(s.color.unwrap_or(i)), p.log_x, clip)?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font((FONT, 12))
        .draw()
        .map_err(plot_err)?;
    Ok(())
}

/// One series in colour `c`: its theory line (dashed), fit, joining line,
/// error bars, points (named in the legend) and predicted markers.
fn draw_one<'a, 'b: 'a, X: Ranged<ValueType = f64>>(
    chart: &mut MultiChart<'a, 'b, X>,
    s: &Series,
    c: RGBColor,
    log_x: bool,
    clip: &impl Fn(f64) -> f64,
) -> Result<()> {
    let pts: Vec<(f64, f64, f64)> = s
        .points
        .iter()
        .copied()
        .filter(|&(x, y, _)| drawable(x, y, log_x))
        .collect();
    if let Some(t) = s.theory {
        chart
            .draw_series(DashedLineSeries::new(
                t.polyline().into_iter().map(|(x, y)| (x, clip(y))),
                6,
                4,
                c.stroke_width(1),
            ))
            .map_err(plot_err)?;
    }
    if let Some(f) = s.fit {
        chart
            .draw_series(LineSeries::new(
                f.polyline().into_iter().map(|(x, y)| (x, clip(y))),
                c.stroke_width(2),
            ))
            .map_err(plot_err)?;
    }
    if s.joined && s.dashed {
        chart
            .draw_series(DashedLineSeries::new(
                pts.iter().map(|&(x, y, _)| (x, clip(y))),
                8,
                4,
                c.stroke_width(2),
            ))
            .map_err(plot_err)?;
    } else if s.joined {
        chart
            .draw_series(LineSeries::new(
                pts.iter().map(|&(x, y, _)| (x, clip(y))),
                c.stroke_width(2),
            ))
            .map_err(plot_err)?;
    }
    chart
        .draw_series(
            pts.iter()
                .filter(|q| q.2.is_finite() && q.2 > 0.0)
                .map(|&(x, y, e)| {
                    ErrorBar::new_vertical(
                        x,
                        clip(y - e),
                        y,
                        clip(y + e),
                        c.filled().stroke_width(1),
                        6,
                    )
                }),
        )
        .map_err(plot_err)?;
    chart
        .draw_series(
            pts.iter()
                .map(|&(x, y, _)| Circle::new((x, y), 3, c.filled())),
        )
        .map_err(plot_err)?
        .label(s.label.clone())
        .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], c.stroke_width(2)));
    chart
        .draw_series(
            s.predicted
                .iter()
                .filter(|&&(x, y)| drawable(x, y, log_x))
                .map(|&(x, y)| Circle::new((x, y), 6, c.stroke_width(1))),
        )
        .map_err(plot_err)?;
    Ok(())
}

/// One labelled point of a [`labelled_scatter`].
#[derive(Clone, Debug)]
pub struct Labelled {
    pub x: f64,
    pub y: f64,
    /// Horizontal 95 % interval of `x`, drawn as a bar.
    pub x_err: f64,
    pub label: String,
    /// Colour index (e.g. the sampler).
    pub color: usize,
    /// Filled (true) or hollow marker (e.g. the integrand).
    pub filled: bool,
}

/// A scatter of labelled points on linear axes (fitted slope against the
/// fitted intercept, as the variance-analysis course tools draw it), with
/// optional vertical reference lines (theory slopes).
///
/// # Errors
/// Only on an internal drawing error.
pub fn labelled_scatter(
    title: &str,
    subtitle: &str,
    x_label: &str,
    y_label: &str,
    points: &[Labelled],
) -> Result<String> {
    let fin: Vec<&Labelled> = points
        .iter()
        .filter(|p| p.x.is_finite() && p.y.is_finite())
        .collect();
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for p in &fin {
        let e = if p.x_err.is_finite() { p.x_err } else { 0.0 };
        x0 = x0.min(p.x - e);
        x1 = x1.max(p.x + e);
        y0 = y0.min(p.y);
        y1 = y1.max(p.y);
    }
    if !x0.is_finite() {
        (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
    }
    let px = ((x1 - x0) * 0.08).max(0.1);
    let py = ((y1 - y0) * 0.08).max(0.1);
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, SIZE).into_drawing_area();
        let body = titled(&root, title, subtitle)?;
        let mut chart = builder(&body)
            .build_cartesian_2d((x0 - px)..(x1 + px), (y0 - py)..(y1 + py))
            .map_err(plot_err)?;
        chart
            .configure_mesh()
            .x_desc(x_label)
            .y_desc(y_label)
            .label_style((FONT, 12))
            .axis_desc_style((FONT, 13))
            .draw()
            .map_err(plot_err)?;
        for p in &fin {
            let c = color(p.color);
            if p.x_err.is_finite() && p.x_err > 0.0 {
                chart
                    .draw_series(std::iter::once(PathElement::new(
                        [(p.x - p.x_err, p.y), (p.x + p.x_err, p.y)],
                        c.stroke_width(1),
                    )))
                    .map_err(plot_err)?;
            }
            let style = if p.filled {
                c.filled()
            } else {
                c.stroke_width(2)
            };
            chart
                .draw_series(std::iter::once(Circle::new((p.x, p.y), 5, style)))
                .map_err(plot_err)?;
            chart
                .draw_series(std::iter::once(Text::new(
                    p.label.clone(),
                    (p.x, p.y),
                    (FONT, 11).into_font().color(&BLACK),
                )))
                .map_err(plot_err)?;
        }
        root.present().map_err(plot_err)?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn multi_draws_every_series() {
        let s = Series {
            label: "jittered".into(),
            points: vec![(16.0, 1e-3, 1e-4), (64.0, 1e-4, 1e-5), (256.0, 0.0, 1.0)],
            predicted: vec![(16.0, 1.1e-3)],
            fit: Some(Line {
                a: 0.0,
                slope: -1.5,
                log_power: 0,
                x0: 16.0,
                x1: 64.0,
            }),
            theory: None,
            joined: false,
            dashed: false,
            color: None,
        };
        let t = Series {
            label: "random & co".into(),
            points: vec![(16.0, 1e-2, f64::NAN)],
            ..Series::default()
        };
        let svg = multi(&Multi {
            title: "t",
            subtitle: "s",
            x_label: "N",
            y_label: "Var",
            series: &[s, t],
            log_x: true,
        })
        .unwrap();
        assert!(svg.contains("jittered") && svg.contains("random &amp; co"));
        // 3 drawable points + 1 hollow prediction marker.
        assert!(svg.matches("<circle").count() >= 4, "{svg}");
    }

    #[test]
    fn scatter_labels_points() {
        let svg = labelled_scatter(
            "t",
            "s",
            "slope",
            "intercept",
            &[Labelled {
                x: -1.5,
                y: -2.0,
                x_err: 0.05,
                label: "jittered disk".into(),
                color: 1,
                filled: true,
            }],
        )
        .unwrap();
        assert!(svg.contains("jittered disk"));
    }
}
