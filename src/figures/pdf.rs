//! Figures as PDF: a plotters backend that writes what the figure draws as PDF operators — lines,
//! polylines and polygons as paths, text as text in the bundled font, embedded (a CID font over the
//! TrueType file, compressed, with a ToUnicode map so that the words can be searched and copied).
//! plotters has no PDF backend, and converting the SVG would take a renderer's worth of crates.
//!
//! The text is placed as plotters' bitmap backend places it — the same size (the font scaled so that
//! its ascent to descent is the style's size), the same anchors, the same quarter turns — so that
//! the PDF looks like the PNG. One PDF point is one pixel of the PNG.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;

use ab_glyph::{Font, FontRef};
use plotters::prelude::DrawingBackend;
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind, FontTransform,
};

/// Why drawing failed: the bundled font did not read (it always does).
#[derive(Debug)]
pub struct PdfError;

impl std::fmt::Display for PdfError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("the bundled font assets/fonts/LiberationSans-Regular.ttf is unreadable")
    }
}

impl std::error::Error for PdfError {}

/// A page being drawn: plotters draws on `&mut PdfPage`, then [`PdfPage::file`] gives the bytes.
pub struct PdfPage {
    size: (u32, u32),
    font: FontRef<'static>,
    content: String,
    /// The transparencies used, as ExtGState names (`/A<alpha×255>`).
    alphas: BTreeSet<u8>,
    /// The glyphs used and the character each is.
    glyphs: BTreeMap<u16, char>,
    /// The TrueType file the text is set in, embedded.
    font_file: &'static [u8],
}

impl PdfPage {
    /// An empty page of `size` points (the figure's pixels), its text in the TrueType `font_file`.
    pub fn new(size: (u32, u32), font_file: &'static [u8]) -> Result<Self, PdfError> {
        Ok(Self {
            size,
            font: FontRef::try_from_slice(font_file).map_err(|_| PdfError)?,
            content: String::new(),
            alphas: BTreeSet::new(),
            glyphs: BTreeMap::new(),
            font_file,
        })
    }

    /// A point of the figure (pixels, y down) on the page (points, y up).
    fn at(&self, (x, y): BackendCoord) -> (f64, f64) {
        (f64::from(x), f64::from(self.size.1) - f64::from(y))
    }

    /// Sets the colour (and its transparency) for strokes or fills.
    fn colour(&mut self, color: BackendColor, fill: bool) {
        let (r, g, b) = color.rgb;
        let op = if fill { "rg" } else { "RG" };
        let _ = writeln!(
            self.content,
            "{:.4} {:.4} {:.4} {op}",
            f64::from(r) / 255.0,
            f64::from(g) / 255.0,
            f64::from(b) / 255.0
        );
        let alpha = (color.alpha.clamp(0.0, 1.0) * 255.0).round() as u8;
        self.alphas.insert(alpha);
        let _ = writeln!(self.content, "/A{alpha} gs");
    }

    fn path(&mut self, points: &[BackendCoord], close: bool) {
        for (i, &p) in points.iter().enumerate() {
            let (x, y) = self.at(p);
            let op = if i == 0 { "m" } else { "l" };
            let _ = writeln!(self.content, "{x:.2} {y:.2} {op}");
        }
        if close {
            self.content.push_str("h\n");
        }
    }

    /// The scale from the font's units to the em of text `size` pixels tall (ascent to descent, as
    /// the bitmap backend scales it), and the em.
    fn em(&self, size: f64) -> f64 {
        let height = f64::from(self.font.ascent_unscaled() - self.font.descent_unscaled());
        let units = f64::from(self.font.units_per_em().unwrap_or(1000.0));
        size * units / height.max(1.0)
    }

    fn width(&self, text: &str, size: f64) -> f64 {
        let units = f64::from(self.font.units_per_em().unwrap_or(1000.0));
        let scale = self.em(size) / units;
        text.chars()
            .map(|c| f64::from(self.font.h_advance_unscaled(self.font.glyph_id(c))) * scale)
            .sum()
    }

    /// The whole file: the page, its content, the font and the cross-reference table.
    pub fn file(self) -> Vec<u8> {
        let (w, h) = self.size;
        let units = f64::from(self.font.units_per_em().unwrap_or(1000.0));
        let per_mille = |v: f32| (f64::from(v) * 1000.0 / units).round() as i64;
        let mut alphas = String::new();
        for alpha in &self.alphas {
            let a = f64::from(*alpha) / 255.0;
            let _ = write!(alphas, "/A{alpha} << /CA {a:.4} /ca {a:.4} >> ");
        }
        let mut widths = String::new();
        let mut unicode = String::new();
        for (&glyph, &c) in &self.glyphs {
            let advance = self.font.h_advance_unscaled(ab_glyph::GlyphId(glyph));
            let _ = write!(widths, "{glyph} [{}] ", per_mille(advance));
            let mut utf16 = [0u16; 2];
            let units: String = (c.encode_utf16(&mut utf16).iter())
                .map(|u| format!("{u:04X}"))
                .collect();
            let _ = writeln!(unicode, "<{glyph:04X}> <{units}>");
        }
        let to_unicode = format!(
            "/CIDInit /ProcSet findresource begin 12 dict begin begincmap\n\
             /CIDSystemInfo << /Registry (Adobe) /Ordering (UCS) /Supplement 0 >> def\n\
             /CMapName /Adobe-Identity-UCS def /CMapType 2 def\n\
             1 begincodespacerange <0000> <FFFF> endcodespacerange\n\
             {} beginbfchar\n{unicode}endbfchar\n\
             endcmap CMapName currentdict /CMap defineresource pop end end\n",
            self.glyphs.len()
        );
        let (ascent, descent) = (self.font.ascent_unscaled(), self.font.descent_unscaled());
        let mut objects: Vec<Vec<u8>> = vec![
            b"<< /Type /Catalog /Pages 2 0 R >>".to_vec(),
            b"<< /Type /Pages /Kids [3 0 R] /Count 1 >>".to_vec(),
            format!(
                "<< /Type /Page /Parent 2 0 R /MediaBox [0 0 {w} {h}] /Contents 4 0 R \
                 /Resources << /Font << /F1 5 0 R >> /ExtGState << {alphas}>> >> >>"
            )
            .into_bytes(),
            stream("", self.content.as_bytes()),
            b"<< /Type /Font /Subtype /Type0 /BaseFont /LiberationSans /Encoding /Identity-H \
               /DescendantFonts [6 0 R] /ToUnicode 9 0 R >>"
                .to_vec(),
            format!(
                "<< /Type /Font /Subtype /CIDFontType2 /BaseFont /LiberationSans \
                 /CIDSystemInfo << /Registry (Adobe) /Ordering (Identity) /Supplement 0 >> \
                 /FontDescriptor 7 0 R /CIDToGIDMap /Identity /DW 1000 /W [{widths}] >>"
            )
            .into_bytes(),
            format!(
                "<< /Type /FontDescriptor /FontName /LiberationSans /Flags 32 \
                 /FontBBox [-544 -303 1302 980] /ItalicAngle 0 /Ascent {} /Descent {} \
                 /CapHeight 729 /StemV 80 /FontFile2 8 0 R >>",
                per_mille(ascent),
                per_mille(descent)
            )
            .into_bytes(),
            stream(
                &format!("/Length1 {}", self.font_file.len()),
                self.font_file,
            ),
            stream("", to_unicode.as_bytes()),
        ];
        let mut file = b"%PDF-1.7\n%\xE2\xE3\xCF\xD3\n".to_vec();
        let mut offsets = Vec::with_capacity(objects.len());
        for (i, object) in objects.iter_mut().enumerate() {
            offsets.push(file.len());
            file.extend(format!("{} 0 obj\n", i + 1).as_bytes());
            file.append(object);
            file.extend(b"\nendobj\n");
        }
        let xref = file.len();
        file.extend(format!("xref\n0 {}\n0000000000 65535 f \n", offsets.len() + 1).as_bytes());
        for offset in offsets {
            file.extend(format!("{offset:010} 00000 n \n").as_bytes());
        }
        file.extend(
            format!(
                "trailer\n<< /Size {} /Root 1 0 R >>\nstartxref\n{xref}\n%%EOF\n",
                objects.len() + 1
            )
            .as_bytes(),
        );
        file
    }
}

/// A stream object, its bytes compressed (zlib, FlateDecode).
fn stream(extra: &str, bytes: &[u8]) -> Vec<u8> {
    let compressed = miniz_oxide::deflate::compress_to_vec_zlib(bytes, 6);
    let mut object = format!(
        "<< /Length {} /Filter /FlateDecode {extra} >>\nstream\n",
        compressed.len()
    )
    .into_bytes();
    object.extend(compressed);
    object.extend(b"\nendstream");
    object
}

impl DrawingBackend for &mut PdfPage {
    type ErrorType = PdfError;

    fn get_size(&self) -> (u32, u32) {
        self.size
    }

    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<PdfError>> {
        Ok(())
    }

    fn present(&mut self) -> Result<(), DrawingErrorKind<PdfError>> {
        Ok(())
    }

    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<PdfError>> {
        if color.alpha > 0.0 {
            self.colour(color, true);
            let (x, y) = self.at(point);
            let _ = writeln!(self.content, "{x:.2} {:.2} 1 1 re f", y - 1.0);
        }
        Ok(())
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<PdfError>> {
        self.draw_path([from, to], style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<PdfError>> {
        let (l, t) = upper_left;
        let (r, b) = bottom_right;
        let corners = [(l, t), (r, t), (r, b), (l, b)];
        if fill {
            self.fill_polygon(corners, style)
        } else {
            if style.color().alpha == 0.0 {
                return Ok(());
            }
            self.colour(style.color(), false);
            let _ = writeln!(self.content, "{} w", style.stroke_width());
            self.path(&corners, true);
            self.content.push_str("S\n");
            Ok(())
        }
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<PdfError>> {
        if style.color().alpha == 0.0 {
            return Ok(());
        }
        let points: Vec<BackendCoord> = path.into_iter().collect();
        self.colour(style.color(), false);
        let _ = writeln!(self.content, "{} w 1 J 1 j", style.stroke_width());
        self.path(&points, false);
        self.content.push_str("S\n");
        Ok(())
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<PdfError>> {
        if style.color().alpha == 0.0 {
            return Ok(());
        }
        self.colour(style.color(), fill);
        let (x, y) = self.at(center);
        let r = f64::from(radius);
        let k = 0.552_284_75 * r;
        let _ = writeln!(
            self.content,
            "{} w {:.2} {y:.2} m {:.2} {:.2} {:.2} {:.2} {x:.2} {:.2} c \
             {:.2} {:.2} {:.2} {:.2} {:.2} {y:.2} c \
             {:.2} {:.2} {:.2} {:.2} {x:.2} {:.2} c \
             {:.2} {:.2} {:.2} {:.2} {:.2} {y:.2} c {}",
            style.stroke_width(),
            x + r,
            x + r,
            y + k,
            x + k,
            y + r,
            y + r,
            x - k,
            y + r,
            x - r,
            y + k,
            x - r,
            x - r,
            y - k,
            x - k,
            y - r,
            y - r,
            x + k,
            y - r,
            x + r,
            y - k,
            x + r,
            if fill { "f" } else { "S" }
        );
        Ok(())
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<PdfError>> {
        if style.color().alpha == 0.0 {
            return Ok(());
        }
        let points: Vec<BackendCoord> = vert.into_iter().collect();
        self.colour(style.color(), true);
        self.path(&points, true);
        self.content.push_str("f\n");
        Ok(())
    }

    fn draw_text<TStyle: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &TStyle,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<PdfError>> {
        let color = style.color();
        if color.alpha == 0.0 || text.is_empty() {
            return Ok(());
        }
        // As the bitmap backend: the box is the advances wide and size / 1.24 tall, its top left at
        // the anchor's offset, the baseline size / 2 below its top.
        let size = style.size();
        let (width, height) = (self.width(text, size), size / 1.24);
        let dx = match style.anchor().h_pos {
            HPos::Left => 0.0,
            HPos::Center => -(width as i64 / 2) as f64,
            HPos::Right => -(width as i64) as f64,
        };
        let dy = match style.anchor().v_pos {
            VPos::Top => 0.0,
            VPos::Center => -(height as i64 / 2) as f64,
            VPos::Bottom => -(height as i64) as f64,
        };
        // The text's x axis and its glyphs' up, on the screen (y down), by the quarter turn.
        let turn = |(x, y): (f64, f64)| match style.transform() {
            FontTransform::Rotate90 => (-y, x),
            FontTransform::Rotate180 => (-x, -y),
            FontTransform::Rotate270 => (y, -x),
            _ => (x, y),
        };
        let origin = turn((dx, dy + size / 2.0));
        let (ox, oy) = (f64::from(pos.0) + origin.0, f64::from(pos.1) + origin.1);
        let (ax, ay) = turn((1.0, 0.0));
        let (ux, uy) = turn((0.0, -1.0));
        let glyphs: String = text
            .chars()
            .map(|c| {
                let id = self.font.glyph_id(c).0;
                self.glyphs.entry(id).or_insert(c);
                format!("{id:04X}")
            })
            .collect();
        self.colour(color, true);
        let em = self.em(size);
        let page_height = f64::from(self.size.1);
        let _ = writeln!(
            self.content,
            "BT /F1 {em:.3} Tf {ax:.4} {:.4} {ux:.4} {:.4} {ox:.2} {:.2} Tm <{glyphs}> Tj ET",
            -ay,
            -uy,
            page_height - oy
        );
        Ok(())
    }

    fn estimate_text_size<TStyle: BackendTextStyle>(
        &self,
        text: &str,
        style: &TStyle,
    ) -> Result<(u32, u32), DrawingErrorKind<PdfError>> {
        let size = style.size();
        Ok((self.width(text, size) as u32, (size / 1.24) as u32))
    }
}
