//! Scatter plots of point sets in the unit interval, square or cube.

use plotters::prelude::*;

use super::plot::plot_err;
use crate::{LabError, Result};

/// At most this many points are drawn per panel (the first ones; the title
/// says so): larger SVGs are too big for a browser to show, and the text
/// point file holds every point.
pub const MAX_SCATTER_POINTS: usize = 1 << 16;

const PANEL: u32 = 420;
const FONT: &str = "sans-serif";
const DOT: RGBColor = RGBColor(31, 78, 153);

/// Circle radius in pixels for `n` points in a panel.
fn dot_radius(n: usize, panel: u32) -> i32 {
    let spacing = f64::from(panel) / (n.max(1) as f64).sqrt();
    (0.22 * spacing).clamp(1.0, 4.0).round() as i32
}

/// The scatter plot of `coords` (`dims` coordinates per point, row-major) as an
/// SVG document under `title`: 1D on the segment `[0, 1]`, 2D in the unit
/// square (`y` up), 3D as the projections `xy`, `xz`, `yz` side by side. Every
/// drawn point is one `<circle>` per panel.
///
/// # Errors
/// Only on an internal drawing error or `dims ∉ 1..=3`.
pub fn scatter(coords: &[f32], dims: usize, title: &str) -> Result<String> {
    if !(1..=3).contains(&dims) {
        return Err(LabError::Internal(format!("scatter of {dims}D points")));
    }
    let n = coords.len() / dims;
    let shown = n.min(MAX_SCATTER_POINTS);
    let title = if shown < n {
        format!("{title} (first {shown} of {n} points shown)")
    } else {
        title.to_string()
    };
    let pts = coords[..shown * dims].chunks_exact(dims);
    let r = dot_radius(shown, PANEL);
    let panels: &[(usize, usize, &str)] = match dims {
        1 => &[(0, 0, "x")],
        2 => &[(0, 1, "xy")],
        _ => &[(0, 1, "xy"), (0, 2, "xz"), (1, 2, "yz")],
    };
    // Square plotting areas of PANEL pixels: per panel 2 × 10 margin and 36
    // for the y labels; above, the title (about 32) and in 3D the panel
    // caption (about 22); below, 28 for the x labels.
    let width = (PANEL + 56) * panels.len() as u32;
    let height = if dims == 1 {
        170
    } else {
        PANEL + 20 + 28 + 32 + if dims == 3 { 22 } else { 0 }
    };
    let mut s = String::new();
    {
        let root = SVGBackend::with_string(&mut s, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let body = root.titled(&title, (FONT, 15)).map_err(plot_err)?;
        let areas = body.split_evenly((1, panels.len()));
        for (area, &(a, b, name)) in areas.iter().zip(panels) {
            let mut chart = ChartBuilder::on(area)
                .caption(if dims == 3 { name } else { "" }, (FONT, 13))
                .margin(10)
                .x_label_area_size(28)
                .y_label_area_size(if dims == 1 { 0 } else { 36 })
                .build_cartesian_2d(0f64..1f64, 0f64..1f64)
                .map_err(plot_err)?;
            chart
                .configure_mesh()
                .disable_mesh()
                .x_labels(3)
                .y_labels(if dims == 1 { 0 } else { 3 })
                .x_desc(&name[..1])
                .y_desc(if dims == 1 { "" } else { &name[1..] })
                .label_style((FONT, 11))
                .draw()
                .map_err(plot_err)?;
            chart
                .draw_series(pts.clone().map(|p| {
                    let y = if dims == 1 { 0.5 } else { f64::from(p[b]) };
                    Circle::new((f64::from(p[a]), y), r, DOT.mix(0.8).filled())
                }))
                .map_err(plot_err)?;
        }
        root.present().map_err(plot_err)?;
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_circle_per_point_and_panel() {
        let pts = [0.1f32, 0.2, 0.3, 0.4, 0.5, 0.6];
        assert_eq!(scatter(&pts, 1, "t").unwrap().matches("<circle").count(), 6);
        assert_eq!(scatter(&pts, 2, "t").unwrap().matches("<circle").count(), 3);
        assert_eq!(scatter(&pts, 3, "t").unwrap().matches("<circle").count(), 6);
        assert!(scatter(&pts, 4, "t").is_err());
    }

    #[test]
    fn large_sets_are_thinned_and_say_so() {
        let n = MAX_SCATTER_POINTS + 5;
        let pts = vec![0.5f32; n];
        let s = scatter(&pts, 1, "big").unwrap();
        assert_eq!(s.matches("<circle").count(), MAX_SCATTER_POINTS);
        assert!(s.contains(&format!("first {MAX_SCATTER_POINTS} of {n} points shown")));
    }
}
