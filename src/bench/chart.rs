//! The bench charts: time per frame (x, log scale) against an error (y), one point per configuration,
//! coloured by sweep, with the Pareto front drawn as a line and labelled (placed by `labels`, clear of each
//! other). Written as SVG and as PNG.
//! [`Panel::Accuracy`] plots every configuration's FLIP against the reference; [`Panel::Visibility`] plots
//! the visibility configurations' own error (pixels differing from the z-buffer at the same settings);
//! [`Panel::Stability`] plots every configuration's shimmer RMS over the stability sequence.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::Row;
use super::labels;

/// Chart size in pixels.
pub const SIZE: (u32, u32) = (1200, 760);

const GROUPS: [(&str, RGBColor); 7] = [
    ("visibility", RGBColor(31, 119, 180)),
    ("texture", RGBColor(255, 127, 14)),
    ("lod", RGBColor(44, 160, 44)),
    ("resolution", RGBColor(148, 103, 189)),
    ("mip", RGBColor(214, 39, 40)),
    ("antialias", RGBColor(23, 190, 207)),
    ("quality", RGBColor(127, 127, 127)),
];

/// Which chart.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Panel {
    /// Every configuration: FLIP mean against the reference.
    Accuracy,
    /// The visibility sweep: share of pixels that differ from the z-buffer at the same settings.
    Visibility,
    /// Every configuration: shimmer RMS over consecutive frames against the reference's own change.
    Stability,
}

impl Panel {
    fn y(self, r: &Row) -> f64 {
        match self {
            Panel::Accuracy => r.flip_mean,
            Panel::Visibility => r.vis_wrong_pct,
            Panel::Stability => r.shimmer_rms,
        }
    }

    fn on_front(self, r: &Row) -> bool {
        match self {
            Panel::Accuracy => r.pareto,
            Panel::Visibility => r.vis_pareto,
            Panel::Stability => r.stability_pareto,
        }
    }

    fn shows(self, r: &Row) -> bool {
        self != Panel::Visibility || r.config.group == "visibility"
    }

    fn y_desc(self) -> &'static str {
        match self {
            Panel::Accuracy => "FLIP mean against the reference",
            Panel::Visibility => "% of pixels differing from the z-buffer",
            Panel::Stability => "shimmer RMS (0-255) over consecutive frames",
        }
    }
}

/// Why a chart could not be drawn.
#[derive(Debug, thiserror::Error)]
pub enum ChartError {
    /// No configuration has a finite time and error to place on the chart.
    #[error("no measured configuration to chart")]
    Empty,
    /// The bundled font for the chart's text did not load.
    #[error("the bundled chart font does not load")]
    Font,
    /// The SVG backend failed.
    #[error("drawing the chart: {0}")]
    Svg(#[source] SvgFailure),
    /// The bitmap backend failed.
    #[error("drawing the chart: {0}")]
    Bitmap(#[source] BitmapFailure),
}

/// What the SVG backend reports when drawing fails.
pub type SvgFailure = DrawingAreaErrorKind<<SVGBackend<'static> as DrawingBackend>::ErrorType>;
/// What the bitmap backend reports when drawing fails.
pub type BitmapFailure = DrawingAreaErrorKind<<BitMapBackend<'static> as DrawingBackend>::ErrorType>;

/// Draws the chart on `root`; `e` makes the backend's failure a [`ChartError`].
fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    rows: &[Row],
    title: &str,
    panel: Panel,
    e: fn(DrawingAreaErrorKind<DB::ErrorType>) -> ChartError,
) -> Result<(), ChartError> {
    root.fill(&WHITE).map_err(e)?;
    let finite: Vec<&Row> =
        rows.iter().filter(|r| panel.shows(r) && r.ms.is_finite() && r.ms > 0.0 && panel.y(r).is_finite()).collect();
    if finite.is_empty() {
        return Err(ChartError::Empty);
    }
    let (mut x0, mut x1) = (f64::INFINITY, 0.0f64);
    let mut y1 = 0.0f64;
    for r in &finite {
        x0 = x0.min(r.ms);
        x1 = x1.max(r.ms);
        y1 = y1.max(panel.y(r));
    }
    let (x0, x1) = (x0 / 1.3, x1 * 1.3);
    let y1 = (y1 * 1.1).max(1e-3);
    let mut chart = ChartBuilder::on(root)
        .caption(title, ("sans-serif", 22))
        .margin(18)
        .x_label_area_size(50)
        .y_label_area_size(70)
        .build_cartesian_2d((x0..x1).log_scale().with_key_points(ticks(x0, x1)), 0.0..y1)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc("milliseconds per frame (median over frames, log scale)")
        // Tick values are products like 7 x 0.1, which print as 0.7000000000000001 by default.
        .x_label_formatter(&|x| format!("{}", libm::round(x * 1e6) / 1e6))
        .y_desc(panel.y_desc())
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .draw()
        .map_err(e)?;
    for (group, colour) in GROUPS {
        let pts: Vec<(f64, f64)> =
            finite.iter().filter(|r| r.config.group == group).map(|r| (r.ms, panel.y(r))).collect();
        if pts.is_empty() {
            continue;
        }
        chart
            .draw_series(pts.iter().map(|&p| Circle::new(p, 5, colour.filled())))
            .map_err(e)?
            .label(group)
            .legend(move |(x, y)| Circle::new((x + 8, y), 5, colour.filled()));
    }
    let mut front: Vec<&&Row> = finite.iter().filter(|r| panel.on_front(r)).collect();
    front.sort_by(|a, b| a.ms.total_cmp(&b.ms));
    chart
        .draw_series(LineSeries::new(front.iter().map(|r| (r.ms, panel.y(r))), BLACK.stroke_width(2)))
        .map_err(e)?
        .label("Pareto front")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], BLACK.stroke_width(2)));
    chart
        .draw_series(
            front.iter().map(|r| EmptyElement::at((r.ms, panel.y(r))) + Circle::new((0, 0), 8, BLACK.stroke_width(1))),
        )
        .map_err(e)?;
    let points: Vec<(i32, i32)> = front.iter().map(|r| chart.backend_coord(&(r.ms, panel.y(r)))).collect();
    let (xs, ys) = chart.plotting_area().get_pixel_range();
    let names: Vec<&str> = front.iter().map(|r| r.config.label.as_str()).collect();
    front_labels(root, &names, &points, (xs.start, ys.start, xs.end, ys.end), e)?;
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .label_font(("sans-serif", 14))
        .border_style(BLACK)
        .background_style(WHITE.mix(0.9))
        .draw()
        .map_err(e)?;
    root.present().map_err(e)
}

/// Writes each front point's label (`names`, the points at `points` in backend pixels) where [`labels::place`]
/// finds room inside `area`, with a leader line when it is not beside its point.
fn front_labels<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    names: &[&str],
    points: &[(i32, i32)],
    area: labels::Box2,
    e: fn(DrawingAreaErrorKind<DB::ErrorType>) -> ChartError,
) -> Result<(), ChartError> {
    let font: TextStyle = ("sans-serif", 13).into();
    let sizes = names.iter().map(|n| root.estimate_text_size(n, &font).map_err(e)).collect::<Result<Vec<_>, _>>()?;
    for ((name, &(x, y)), b) in names.iter().zip(points).zip(labels::place(points, &sizes, area)) {
        let Some((l, t, r, bottom)) = b else { continue };
        root.draw(&Text::new(name.to_string(), (l, t), font.clone())).map_err(e)?;
        // A label moved away from its point gets a leader line to the nearest point of its box.
        let near = (x.clamp(l, r), y.clamp(t, bottom));
        if (near.0 - x).pow(2) + (near.1 - y).pow(2) > 14 * 14 {
            root.draw(&PathElement::new(vec![(x, y), near], RGBColor(120, 120, 120).stroke_width(1))).map_err(e)?;
        }
    }
    Ok(())
}

/// The chart as an SVG document.
pub fn svg(rows: &[Row], title: &str, panel: Panel) -> Result<String, ChartError> {
    fonts()?;
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, SIZE).into_drawing_area();
        draw(&root, rows, title, panel, ChartError::Svg)?;
    }
    Ok(out)
}

/// Tick values for a log axis from `lo` to `hi`: 1, 1.5, 2, 3, 5, 7 times powers of ten, thinned to at
/// most about a dozen.
fn ticks(lo: f64, hi: f64) -> Vec<f64> {
    let mut v = vec![];
    let mut p = libm::pow(10f64, libm::log10(lo.max(1e-9)).floor());
    while p <= hi && v.len() < 200 {
        for m in [1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0] {
            let t = m * p;
            if t >= lo && t <= hi {
                v.push(t);
            }
        }
        p *= 10.0;
    }
    let step = v.len().div_ceil(12).max(1);
    v.into_iter().step_by(step).collect()
}

/// Registers the bundled font for chart text once (both backends measure text with it).
fn fonts() -> Result<(), ChartError> {
    static FONT: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    let ok = *FONT.get_or_init(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT).is_ok()
    });
    if ok { Ok(()) } else { Err(ChartError::Font) }
}

/// The chart as `0x00RRGGBB` pixels of [`SIZE`].
pub fn pixels(rows: &[Row], title: &str, panel: Panel) -> Result<Vec<u32>, ChartError> {
    fonts()?;
    let mut rgb = vec![0u8; SIZE.0 as usize * SIZE.1 as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
        draw(&root, rows, title, panel, ChartError::Bitmap)?;
    }
    Ok(rgb.chunks_exact(3).map(|c| (u32::from(c[0]) << 16) | (u32::from(c[1]) << 8) | u32::from(c[2])).collect())
}
