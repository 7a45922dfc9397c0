//! Figures drawn with plotters for files — PNG, SVG or PDF (`pdf`) by the file's extension, text in the font
//! shipped in `assets/fonts` so that rendering never depends on the fonts installed on the machine:
//! `pushlab eval --plot`'s ([`eval`]) and the app's Export plots ([`run`], one run's losses and θ as
//! its plots panel shows them). What both share is here: the formats, the font, the SVG with the
//! font embedded, an atomic write.

pub mod eval;
mod pdf;
pub mod run;

use std::path::Path;
use std::sync::OnceLock;

use anyhow::{Context, anyhow};
use image::codecs::png::PngEncoder;
use image::{ExtendedColorType, ImageEncoder};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};
use pushlab_core::atomic_file::write_atomically;

const FONT: &str = "sans-serif";
const FONT_BYTES: &[u8] = include_bytes!("../../assets/fonts/LiberationSans-Regular.ttf");
/// matplotlib's first two colours, the paper's blue (fixed) and orange (online).
const FIXED: RGBColor = RGBColor(31, 119, 180);
const ONLINE: RGBColor = RGBColor(255, 127, 14);

type Chart<'a, DB> = ChartContext<
    'a,
    DB,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// A figure: its size in pixels, and how it draws on either backend.
pub trait Drawing {
    fn size(&self) -> (u32, u32);

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static;
}

/// The figure's file formats, by the name's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Png,
    /// Vector: lines as polylines, text as text in the bundled font, embedded.
    Svg,
    /// Vector for print: the same, as PDF (`pdf`).
    Pdf,
}

impl Format {
    /// The format of a file name, or why not (for the argument's parser).
    pub fn of(path: &Path) -> Result<Self, String> {
        let extension = path.extension().map(|e| e.to_string_lossy().to_lowercase());
        match extension.as_deref() {
            Some("png") => Ok(Self::Png),
            Some("svg") => Ok(Self::Svg),
            Some("pdf") => Ok(Self::Pdf),
            other => Err(format!(
                "{}: expected a .png, .svg or .pdf file name, got {}",
                path.display(),
                other.map_or_else(|| "no extension".to_owned(), |e| format!(".{e}"))
            )),
        }
    }
}

/// Renders `figure` and writes it as its name's extension says (PNG, SVG or PDF), atomically: a figure
/// half written is never left where a paper's build reads it.
pub fn write(path: &Path, figure: &impl Drawing) -> anyhow::Result<()> {
    let bytes = match Format::of(path).map_err(|e| anyhow!(e))? {
        Format::Png => {
            let (width, height) = figure.size();
            let pixels = render(figure)?;
            let mut png = Vec::new();
            PngEncoder::new(&mut png)
                .write_image(&pixels, width, height, ExtendedColorType::Rgb8)
                .context("cannot encode the figure as PNG")?;
            png
        }
        Format::Svg => render_svg(figure)?.into_bytes(),
        Format::Pdf => {
            let mut page = pdf::PdfPage::new(figure.size(), FONT_BYTES)?;
            figure.draw(&(&mut page).into_drawing_area())?;
            page.file()?
        }
    };
    write_atomically(path, &bytes).with_context(|| format!("cannot write {}", path.display()))
}

/// The figure as RGB pixels, row by row.
pub fn render(figure: &impl Drawing) -> anyhow::Result<Vec<u8>> {
    let (width, height) = figure.size();
    let mut pixels = vec![255u8; (width * height * 3) as usize];
    figure.draw(&BitMapBackend::with_buffer(&mut pixels, (width, height)).into_drawing_area())?;
    Ok(pixels)
}

/// The same figure as SVG, drawn by the same code: lines and bands as polylines and polygons, text
/// as `<text>` in the bundled font, which the file carries (an `@font-face` of the TTF, about
/// 550 kB), so that it renders with the PNG's letters in a browser or a vector editor that has never
/// seen the font; Arial and Helvetica, of the same widths, are named after it.
pub fn render_svg(figure: &impl Drawing) -> anyhow::Result<String> {
    let mut svg = String::new();
    figure.draw(&SVGBackend::with_string(&mut svg, figure.size()).into_drawing_area())?;
    Ok(svg_with_font(&svg))
}

/// The family the SVG's text names: the embedded font first, then fonts of the same metrics.
const SVG_FAMILY: &str = "pushlab-figure, 'Liberation Sans', Arial, Helvetica, sans-serif";

/// `svg` with the bundled font embedded and its text set in it.
fn svg_with_font(svg: &str) -> String {
    let style = format!(
        "<defs><style>@font-face{{font-family:pushlab-figure;src:url(data:font/ttf;base64,{})format('truetype');}}</style></defs>",
        base64(FONT_BYTES)
    );
    let svg = svg.replace(
        &format!("font-family=\"{FONT}\""),
        &format!("font-family=\"{SVG_FAMILY}\""),
    );
    // After the opening <svg …> tag.
    match svg
        .find("<svg")
        .and_then(|at| svg[at..].find('>').map(|end| at + end + 1))
    {
        Some(at) => format!("{}{style}{}", &svg[..at], &svg[at..]),
        None => svg,
    }
}

/// Standard base64 with padding (RFC 4648).
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for i in 0..4 {
            if i <= chunk.len() {
                out.push(char::from(ALPHABET[((n >> (18 - 6 * i)) & 63) as usize]));
            } else {
                out.push('=');
            }
        }
    }
    out
}

fn register() -> anyhow::Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| register_font(FONT, FontStyle::Normal, FONT_BYTES).is_ok());
    if ok {
        Ok(())
    } else {
        Err(anyhow!(
            "the bundled font assets/fonts/LiberationSans-Regular.ttf is unreadable"
        ))
    }
}

/// The legend in the upper right corner, its text `size` points.
fn legend<'a, DB: DrawingBackend + 'a>(chart: &mut Chart<'a, DB>, size: u32) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.4))
        .label_font((FONT, size))
        .draw()
        .map_err(plot_error)
}

fn plot_error(e: impl std::fmt::Display) -> anyhow::Error {
    anyhow!("cannot draw the figure: {e}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_is_rfc_4648() {
        assert_eq!(base64(b""), "");
        assert_eq!(base64(b"f"), "Zg==");
        assert_eq!(base64(b"fo"), "Zm8=");
        assert_eq!(base64(b"foobar"), "Zm9vYmFy");
    }

    #[test]
    fn a_figure_file_is_named_png_or_svg() {
        assert_eq!(Format::of(Path::new("a/fig.SVG")), Ok(Format::Svg));
        assert_eq!(Format::of(Path::new("fig.pdf")), Ok(Format::Pdf));
        assert_eq!(
            Format::of(Path::new("fig.eps")).expect_err("an EPS"),
            "fig.eps: expected a .png, .svg or .pdf file name, got .eps"
        );
    }
}
