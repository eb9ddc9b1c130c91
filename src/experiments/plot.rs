//! Figures for the experiments: line charts (`plotters`, bitmap backend), labelled image
//! montages, false-colour error maps and CSV tables. Text is drawn with the DejaVu Sans
//! font embedded from `assets/`, so no system font is needed.

use crate::error::Error;
use crate::image_io::{self, Rgb32Image};
use crate::metrics;
use plotters::coord::ranged1d::{AsRangedCoord, Ranged, ValueFormatter};
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};
use std::fmt::Write as _;
use std::path::Path;
use std::sync::Once;

/// The font every figure's text is drawn with.
const FONT: &str = "sans-serif";
static FONT_BYTES: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");

/// Register the embedded font with plotters (once per process).
fn register() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        if register_font(FONT, FontStyle::Normal, FONT_BYTES).is_err() {
            panic!("assets/DejaVuSans.ttf is not a valid font");
        }
    });
}

/// Colours of successive series (Matplotlib's tab10).
const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
];

fn chart_error(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Setting(format!("{}: drawing the figure failed: {e}", path.display()))
}

/// Write an 8-bit RGB buffer (`width * height * 3` bytes, display values) as a PNG, through
/// [`image_io::write_png`] (atomic; it applies the sRGB curve, so the bytes are decoded from
/// sRGB first and come back unchanged).
pub fn write_rgb8_png(path: &Path, rgb: &[u8], width: u32, height: u32) -> Result<(), Error> {
    assert_eq!(rgb.len(), width as usize * height as usize * 3, "buffer size");
    let pixels = rgb.chunks_exact(3).map(|p| [0, 1, 2].map(|c| image_io::srgb_to_linear(p[c] as f32 / 255.0))).collect();
    image_io::write_png(path, &Rgb32Image { width, height, pixels })?;
    Ok(())
}

/// A linear-radiance image as 8-bit sRGB bytes (clamped), as PNG files store it.
pub fn srgb8(img: &Rgb32Image) -> Vec<u8> {
    img.pixels
        .iter()
        .flatten()
        .map(|&x| {
            let v = image_io::linear_to_srgb(x);
            if v.is_nan() {
                0
            } else {
                (v.clamp(0.0, 1.0) * 255.0).round() as u8
            }
        })
        .collect()
}

/// Display colours in [0, 1] (such as [`metrics::false_colour`]'s) as 8-bit bytes, without
/// any transfer curve.
pub fn display8(img: &Rgb32Image) -> Vec<u8> {
    img.pixels.iter().flatten().map(|&x| (x.clamp(0.0, 1.0) * 255.0).round() as u8).collect()
}

/// Nearest-neighbour enlargement by an integer factor.
pub fn enlarge(img: &Rgb32Image, factor: u32) -> Rgb32Image {
    Rgb32Image::from_fn(img.width * factor, img.height * factor, |x, y| img.get(x / factor, y / factor))
}

/// The false-colour map of the per-pixel relative error of `img` against `reference`
/// ([`metrics::false_colour`]), computed after box-downsampling both by `downsample` and
/// enlarged back to the full size, so that it shows the error the relMSE figures measure.
pub fn error_map(img: &Rgb32Image, reference: &Rgb32Image, downsample: u32) -> Result<Rgb32Image, Error> {
    let small = metrics::downsample_box(img, downsample).map_err(Error::Setting)?;
    let small_ref = metrics::downsample_box(reference, downsample).map_err(Error::Setting)?;
    let map = metrics::false_colour(&small, &small_ref).map_err(Error::Setting)?;
    Ok(enlarge(&map, downsample))
}

/// Write [`error_map`] to `path`: a PNG holds the map's colours as they are; an EXR holds
/// them as float values.
pub fn write_error_image(path: &Path, img: &Rgb32Image, reference: &Rgb32Image, downsample: u32) -> Result<(), Error> {
    let map = error_map(img, reference, downsample)?;
    let png = path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if png {
        write_rgb8_png(path, &display8(&map), map.width, map.height)
    } else {
        Ok(image_io::write_image(path, &map)?)
    }
}

/// The colours of [`metrics::false_colour`] for relative errors from 1e-3 to 1, left to right
/// over `width` pixels (a colour bar for legends).
fn colour_bar(width: u32) -> Rgb32Image {
    // Against a black reference the per-pixel error is |x| / 0.1, so x = e / 10 shows error e.
    let errors = Rgb32Image::from_fn(width, 1, |x, _| {
        let e = 10f32.powf(-3.0 + 3.0 * (x as f32 + 0.5) / width as f32);
        [e / 10.0; 3]
    });
    metrics::false_colour(&errors, &Rgb32Image::new(width, 1)).expect("same size")
}

/// One image of a montage, with lines of caption above it.
pub struct Tile {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// 8-bit RGB, display values.
    pub rgb: Vec<u8>,
    /// Lines of text above the image.
    pub caption: Vec<String>,
}

impl Tile {
    /// A rendered (linear) image, shown as sRGB.
    pub fn render(img: &Rgb32Image, caption: Vec<String>) -> Self {
        Self { width: img.width, height: img.height, rgb: srgb8(img), caption }
    }

    /// A false-colour map (display values).
    pub fn colours(img: &Rgb32Image, caption: Vec<String>) -> Self {
        Self { width: img.width, height: img.height, rgb: display8(img), caption }
    }

    /// An empty (white) space of the given size.
    pub fn blank(width: u32, height: u32) -> Self {
        Self { width, height, rgb: vec![255; (width * height * 3) as usize], caption: Vec::new() }
    }
}

const PAD: u32 = 8;
const LINE: u32 = 17;
const TEXT_SIZE: u32 = 14;

/// Lay out rows of tiles on white, each under its caption, with an optional title line on
/// top and, when `error_legend`, a colour bar for the error maps at the bottom; write the
/// result as a PNG.
pub fn write_montage(path: &Path, title: &str, rows: &[Vec<Tile>], error_legend: Option<&str>) -> Result<(), Error> {
    register();
    let title_h = if title.is_empty() { 0 } else { LINE + 4 };
    let row_caption = |row: &Vec<Tile>| row.iter().map(|t| t.caption.len() as u32).max().unwrap_or(0) * LINE;
    let row_height = |row: &Vec<Tile>| row_caption(row) + row.iter().map(|t| t.height).max().unwrap_or(0) + PAD;
    let legend_h = if error_legend.is_some() { 2 * LINE + 14 + PAD } else { 0 };
    let width = rows
        .iter()
        .map(|r| r.iter().map(|t| t.width + PAD).sum::<u32>() + PAD)
        .max()
        .unwrap_or(0)
        .max(if error_legend.is_some() { 520 } else { 0 });
    let height = PAD + title_h + rows.iter().map(row_height).sum::<u32>() + legend_h;
    let mut buf = vec![255u8; (width * height * 3) as usize];

    // Images first, then text on top through plotters.
    let mut blit = |tile: &Tile, x0: u32, y0: u32| {
        for y in 0..tile.height {
            let src = &tile.rgb[(y * tile.width * 3) as usize..((y + 1) * tile.width * 3) as usize];
            let start = (((y0 + y) * width + x0) * 3) as usize;
            buf[start..start + src.len()].copy_from_slice(src);
        }
    };
    let mut texts: Vec<(String, i32, i32)> = Vec::new();
    if !title.is_empty() {
        texts.push((title.to_string(), PAD as i32, PAD as i32));
    }
    let mut y = PAD + title_h;
    for row in rows {
        let caption_h = row_caption(row);
        let mut x = PAD;
        for tile in row {
            for (i, line) in tile.caption.iter().enumerate() {
                texts.push((line.clone(), x as i32, (y + i as u32 * LINE) as i32));
            }
            blit(tile, x, y + caption_h);
            x += tile.width + PAD;
        }
        y += row_height(row);
    }
    let bar_w = 256;
    if let Some(legend) = error_legend {
        texts.push((legend.to_string(), PAD as i32, y as i32));
        let bar = colour_bar(bar_w);
        let bar_y = y + LINE + 2;
        for dy in 0..12 {
            let row = Tile::colours(&bar, Vec::new());
            blit(&row, PAD, bar_y + dy);
        }
        for (i, label) in ["0.001", "0.01", "0.1", "1"].iter().enumerate() {
            let x = PAD + (bar_w - 1) * i as u32 / 3;
            texts.push((label.to_string(), x as i32 - if i == 0 { 0 } else { 8 }, (bar_y + 14) as i32));
        }
    }
    {
        let root = BitMapBackend::with_buffer(&mut buf, (width, height)).into_drawing_area();
        let style = (FONT, TEXT_SIZE).into_font().color(&BLACK);
        for (text, x, y) in &texts {
            root.draw(&Text::new(text.as_str(), (*x, *y), style.clone())).map_err(|e| chart_error(path, e))?;
        }
        root.present().map_err(|e| chart_error(path, e))?;
    }
    write_rgb8_png(path, &buf, width, height)
}

/// One line of a chart.
pub struct Series {
    /// Its name in the legend.
    pub name: String,
    /// (x, y) points, joined in order.
    pub points: Vec<(f64, f64)>,
}

/// Axes and labels of a line chart.
pub struct Chart<'a> {
    /// The caption above the chart.
    pub title: &'a str,
    /// The x axis's label.
    pub x_desc: &'a str,
    /// The y axis's label.
    pub y_desc: &'a str,
    /// A logarithmic x axis.
    pub log_x: bool,
    /// A logarithmic y axis.
    pub log_y: bool,
    /// A line in small grey type under the chart (the device, say); may be empty.
    pub note: &'a str,
}

/// Short tick labels: plain for ordinary magnitudes, scientific otherwise.
pub fn tick_label(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 {
        "0".into()
    } else if !(1e-2..1e5).contains(&a) {
        let s = format!("{v:.0e}");
        if s.parse::<f64>().is_ok_and(|p| ((p - v) / v).abs() < 1e-6) {
            s
        } else {
            format!("{v:.1e}")
        }
    } else {
        let mut s = format!("{v:.3}");
        while s.contains('.') && (s.ends_with('0') || s.ends_with('.')) {
            s.pop();
        }
        s
    }
}

/// The axis range over `values`: padded by a factor on a log axis (only positive values
/// count), by a fraction of the span on a linear one.
fn axis_range(values: impl Iterator<Item = f64>, log: bool) -> std::ops::Range<f64> {
    let vals: Vec<f64> = values.filter(|v| v.is_finite() && (!log || *v > 0.0)).collect();
    let (mut lo, mut hi) = vals.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| (l.min(v), h.max(v)));
    if vals.is_empty() {
        (lo, hi) = (1.0, 10.0);
    }
    if log {
        if hi <= lo * 1.0001 {
            (lo, hi) = (lo / 2.0, hi * 2.0);
        }
        lo / 1.25..hi * 1.25
    } else {
        if hi <= lo {
            (lo, hi) = (lo - 1.0, hi + 1.0);
        }
        let pad = 0.05 * (hi - lo);
        lo - pad..hi + pad
    }
}

/// Tick values for a log axis over `range`: the densest of decades, 1-2-5 or 1-to-9 steps
/// that gives at most `max` ticks (decades whatever their number).
pub fn log_ticks(range: &std::ops::Range<f64>, max: usize) -> Vec<f64> {
    let steps: [&[f64]; 3] = [&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0], &[1.0, 2.0, 5.0], &[1.0]];
    let (lo, hi) = (range.start, range.end);
    let ticks = |mults: &[f64]| -> Vec<f64> {
        let mut out = Vec::new();
        let mut decade = 10f64.powi(lo.log10().floor() as i32);
        while decade <= hi {
            for m in mults {
                // Round to the decimal it names (avoids 0.30000000000000004).
                let v: f64 = format!("{:e}", m * decade).parse().unwrap_or(m * decade);
                if v >= lo && v <= hi {
                    out.push(v);
                }
            }
            decade *= 10.0;
        }
        out
    };
    steps.iter().map(|m| ticks(m)).find(|t| t.len() <= max).unwrap_or_else(|| ticks(&[1.0]))
}

/// Draw a line chart (one line with markers per series, and a legend to the right of the
/// plot) to a PNG.
pub fn write_chart(path: &Path, chart: &Chart, series: &[Series]) -> Result<(), Error> {
    let xs = axis_range(series.iter().flat_map(|s| s.points.iter().map(|p| p.0)), chart.log_x);
    let mut ys = axis_range(series.iter().flat_map(|s| s.points.iter().map(|p| p.1)), chart.log_y);
    if !chart.log_y && ys.start > 0.0 {
        // A linear axis of positive values starts at zero, so that heights compare honestly.
        ys.start = 0.0;
    }
    let log = |r: std::ops::Range<f64>, max| {
        let light = log_ticks(&r, 100);
        let bold = log_ticks(&r, max);
        r.log_scale().with_key_points(bold).with_light_points(light)
    };
    match (chart.log_x, chart.log_y) {
        (true, true) => draw_chart(path, chart, series, log(xs, 10), log(ys, 9)),
        (true, false) => draw_chart(path, chart, series, log(xs, 10), ys),
        (false, true) => draw_chart(path, chart, series, xs, log(ys, 9)),
        (false, false) => draw_chart(path, chart, series, xs, ys),
    }
}

fn draw_chart<X, Y>(path: &Path, chart: &Chart, series: &[Series], xs: X, ys: Y) -> Result<(), Error>
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    register();
    let legend_w = 170u32;
    let (width, height) = (860u32, 540u32);
    let mut buf = vec![255u8; (width * height * 3) as usize];
    let err = |e: &dyn std::fmt::Display| chart_error(path, e);
    {
        let root = BitMapBackend::with_buffer(&mut buf, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(&e))?;
        let (upper, note_area) = root.split_vertically(height - 22);
        let (plot_area, legend_area) = upper.split_horizontally(width - legend_w);
        note_area
            .draw(&Text::new(chart.note, (14, 2), (FONT, 12).into_font().color(&RGBColor(110, 110, 110))))
            .map_err(|e| err(&e))?;
        let mut ctx = ChartBuilder::on(&plot_area)
            .caption(chart.title, (FONT, 17))
            .margin(14)
            .x_label_area_size(44)
            .y_label_area_size(70)
            .build_cartesian_2d(xs, ys)
            .map_err(|e| err(&e))?;
        ctx.configure_mesh()
            .x_desc(chart.x_desc)
            .y_desc(chart.y_desc)
            .x_label_formatter(&|v| tick_label(*v))
            .y_label_formatter(&|v| tick_label(*v))
            .label_style((FONT, 13))
            .axis_desc_style((FONT, 15))
            .light_line_style(RGBColor(238, 238, 238))
            .bold_line_style(RGBColor(200, 200, 200))
            .draw()
            .map_err(|e| err(&e))?;
        for (i, s) in series.iter().enumerate() {
            let colour = PALETTE[i % PALETTE.len()];
            let points: Vec<(f64, f64)> = s
                .points
                .iter()
                .copied()
                .filter(|&(x, y)| x.is_finite() && y.is_finite() && (!chart.log_x || x > 0.0) && (!chart.log_y || y > 0.0))
                .collect();
            ctx.draw_series(LineSeries::new(points.clone(), colour.stroke_width(2))).map_err(|e| err(&e))?;
            ctx.draw_series(points.iter().map(|&p| Circle::new(p, 3, colour.filled()))).map_err(|e| err(&e))?;
            // The legend, beside the plot so that it never hides a line.
            let y = 50 + 22 * i as i32;
            legend_area.draw(&PathElement::new(vec![(4, y), (30, y)], colour.stroke_width(3))).map_err(|e| err(&e))?;
            legend_area.draw(&Circle::new((17, y), 3, colour.filled())).map_err(|e| err(&e))?;
            legend_area
                .draw(&Text::new(s.name.as_str(), (38, y - 7), (FONT, 14).into_font().color(&BLACK)))
                .map_err(|e| err(&e))?;
        }
        root.present().map_err(|e| err(&e))?;
    }
    write_rgb8_png(path, &buf, width, height)
}

/// A CSV field: quoted when it holds a comma, quote or line break.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Write a CSV table (a header and rows of fields), via a temporary file renamed over `path`.
pub fn write_csv(path: &Path, header: &[&str], rows: &[Vec<String>]) -> Result<(), Error> {
    let mut text = String::new();
    for row in std::iter::once(header.iter().map(|s| s.to_string()).collect::<Vec<_>>()).chain(rows.iter().cloned()) {
        let fields: Vec<String> = row.iter().map(|f| csv_field(f)).collect();
        let _ = writeln!(text, "{}", fields.join(","));
    }
    let tmp = path.with_extension("csv.tmp");
    std::fs::write(&tmp, text).and_then(|()| std::fs::rename(&tmp, path)).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        Error::Setting(format!("{}: cannot write: {e}", path.display()))
    })
}
