//! Figures as SVG and PNG with plotters, drawn with an embedded font (DejaVu Sans), so no
//! system font is needed.

use anyhow::{Result, anyhow};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

static FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

fn register_font() {
    REGISTER.call_once(|| {
        // The embedded font is a valid TTF; a failure here would be a build defect.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// One line in a panel.
pub struct Series {
    /// Legend label.
    pub label: String,
    /// (x, y) points.
    pub points: Vec<(f64, f64)>,
    /// Colour.
    pub color: RGBColor,
}

/// One stacked panel of a figure.
pub struct Panel {
    /// Y-axis label.
    pub y_label: String,
    /// Lines.
    pub series: Vec<Series>,
}

/// The palette: measurement, initial model, final model, extra.
pub const COLORS: [RGBColor; 4] =
    [RGBColor(30, 30, 30), RGBColor(200, 60, 40), RGBColor(30, 100, 200), RGBColor(40, 150, 60)];

const WIDTH: u32 = 960;
const PANEL_HEIGHT: u32 = 260;

/// A figure to draw: stacked panels of lines.
pub struct Figure {
    /// Title.
    pub title: String,
    /// X-axis label.
    pub x_label: String,
    /// Panels, top to bottom.
    pub panels: Vec<Panel>,
}

impl Figure {
    fn size(&self) -> (u32, u32) {
        (WIDTH, 60 + PANEL_HEIGHT * self.panels.len() as u32)
    }

    /// The figure as SVG text.
    pub fn svg(&self) -> Result<Vec<u8>> {
        register_font();
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, self.size()).into_drawing_area();
            draw(root, &self.title, &self.x_label, &self.panels)
                .map_err(|e| anyhow!("drawing {}: {e}", self.title))?;
        }
        Ok(svg.into_bytes())
    }

    /// Draws the figure as PNG into `path` (the encoder picks the format from its extension).
    pub fn png(&self, path: &Path) -> Result<()> {
        register_font();
        let root = BitMapBackend::new(path, self.size()).into_drawing_area();
        draw(root, &self.title, &self.x_label, &self.panels)
            .map_err(|e| anyhow!("drawing {}: {e}", path.display()))
    }
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    title: &str,
    x_label: &str,
    panels: &[Panel],
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    root.fill(&WHITE)?;
    let root = root.titled(title, ("sans-serif", 22))?;
    let areas = root.split_evenly((panels.len(), 1));
    for (area, panel) in areas.iter().zip(panels) {
        let (mut x_min, mut x_max, mut y_min, mut y_max) =
            (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
        for s in &panel.series {
            for (x, y) in s.points.iter().filter(|(x, y)| x.is_finite() && y.is_finite()) {
                x_min = x_min.min(*x);
                x_max = x_max.max(*x);
                y_min = y_min.min(*y);
                y_max = y_max.max(*y);
            }
        }
        // Degenerate or empty ranges (a constant signal, or no finite point) get a unit span.
        if !x_min.is_finite() {
            (x_min, x_max) = (0.0, 1.0);
        }
        if !y_min.is_finite() {
            (y_min, y_max) = (0.0, 1.0);
        }
        if x_min.partial_cmp(&x_max) != Some(std::cmp::Ordering::Less) {
            x_max = x_min + 1.0;
        }
        let pad = 0.05 * (y_max - y_min).abs().max(1e-12);
        let mut chart = ChartBuilder::on(area)
            .margin(8)
            .x_label_area_size(36)
            .y_label_area_size(70)
            .build_cartesian_2d(x_min..x_max, (y_min - pad)..(y_max + pad))?;
        chart
            .configure_mesh()
            .x_desc(x_label)
            .y_desc(panel.y_label.as_str())
            .label_style(("sans-serif", 14))
            .axis_desc_style(("sans-serif", 15))
            .light_line_style(RGBColor(235, 235, 235))
            .draw()?;
        for s in &panel.series {
            let color = s.color;
            chart
                .draw_series(LineSeries::new(
                    s.points.iter().copied().filter(|(x, y)| x.is_finite() && y.is_finite()),
                    color.stroke_width(2),
                ))?
                .label(s.label.as_str())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2)));
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(180, 180, 180))
            .label_font(("sans-serif", 14))
            .position(SeriesLabelPosition::UpperRight)
            .draw()?;
    }
    root.present()?;
    Ok(())
}
