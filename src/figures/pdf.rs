//! Figures as PDF: a plotters backend that writes what the figure draws as PDF operators — lines,
//! polylines and polygons as paths, text as text in the given font, embedded as a subset of the
//! glyphs used (a CID font over the TrueType subset, compressed, with a ToUnicode map so that the
//! words can be searched and copied). The file's objects are written by `pdf-writer`, the subset by
//! `subsetter`. plotters has no PDF backend, and converting the SVG would take a renderer's worth of
//! crates.
//!
//! The text is placed as plotters' bitmap backend places it — the same size (the font scaled so that
//! its ascent to descent is the style's size), the same anchors, the same quarter turns — so that
//! the PDF looks like the PNG. One PDF point is one pixel of the PNG.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;

use ab_glyph::{Font, FontRef};
use pdf_writer::types::{CidFontType, FontFlags, SystemInfo, UnicodeCmap};
use pdf_writer::{Filter, Name, Pdf, Rect, Ref, Str};
use plotters::prelude::DrawingBackend;
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind, FontTransform,
};
use subsetter::GlyphRemapper;

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

    /// The whole file, written by `pdf-writer`: the page, its content, and the font subset to
    /// the glyphs the text uses (`subsetter`), with its widths, its metrics read from the font
    /// file, and a ToUnicode map so that the words can be searched and copied. The content names
    /// glyphs by their ids in the whole font; a CIDToGIDMap takes each to its id in the subset.
    pub fn file(self) -> Result<Vec<u8>, PdfError> {
        let (w, h) = self.size;
        let units = self.font.units_per_em().unwrap_or(1000.0);
        let per_mille = |v: f32| v * 1000.0 / units;
        let mut remapper = GlyphRemapper::new();
        for &glyph in self.glyphs.keys() {
            remapper.remap(glyph);
        }
        let subset = subsetter::subset(self.font_file, 0, &remapper).map_err(|_| PdfError)?;
        let metrics = skrifa::FontRef::new(self.font_file)
            .map(|f| {
                skrifa::MetadataProvider::metrics(
                    &f,
                    skrifa::instance::Size::unscaled(),
                    skrifa::instance::LocationRef::default(),
                )
            })
            .map_err(|_| PdfError)?;

        let [
            catalog,
            pages,
            page,
            content,
            type0,
            cid,
            descriptor,
            font_file,
            to_unicode,
            gid_map,
        ] = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10].map(Ref::new);
        let mut pdf = Pdf::new();
        pdf.catalog(catalog).pages(pages);
        pdf.pages(pages).kids([page]).count(1);
        let mut alpha_ids = Vec::new();
        for (k, alpha) in self.alphas.iter().enumerate() {
            alpha_ids.push((*alpha, Ref::new(11 + k as i32)));
        }
        {
            let mut p = pdf.page(page);
            p.parent(pages)
                .media_box(Rect::new(0.0, 0.0, w as f32, h as f32))
                .contents(content);
            let mut resources = p.resources();
            resources.fonts().pair(Name(b"F1"), type0);
            let mut states = resources.ext_g_states();
            for (alpha, id) in &alpha_ids {
                states.pair(Name(format!("A{alpha}").as_bytes()), *id);
            }
        }
        for (alpha, id) in &alpha_ids {
            let a = f32::from(*alpha) / 255.0;
            pdf.ext_graphics(*id)
                .stroking_alpha(a)
                .non_stroking_alpha(a);
        }
        let deflate = |bytes: &[u8]| miniz_oxide::deflate::compress_to_vec_zlib(bytes, 6);
        pdf.stream(content, &deflate(self.content.as_bytes()))
            .filter(Filter::FlateDecode);

        pdf.type0_font(type0)
            .base_font(Name(FONT_NAME))
            .encoding_predefined(Name(b"Identity-H"))
            .descendant_font(cid)
            .to_unicode(to_unicode);
        {
            let mut font = pdf.cid_font(cid);
            font.subtype(CidFontType::Type2)
                .base_font(Name(FONT_NAME))
                .system_info(SystemInfo {
                    registry: Str(b"Adobe"),
                    ordering: Str(b"Identity"),
                    supplement: 0,
                })
                .font_descriptor(descriptor)
                .default_width(1000.0)
                .cid_to_gid_map_stream(gid_map);
            let mut widths = font.widths();
            for &glyph in self.glyphs.keys() {
                let advance = self.font.h_advance_unscaled(ab_glyph::GlyphId(glyph));
                widths.consecutive(glyph, [per_mille(advance)]);
            }
        }
        let bbox = metrics
            .bounds
            .map_or(Rect::new(0.0, 0.0, 1000.0, 1000.0), |b| {
                Rect::new(
                    per_mille(b.x_min),
                    per_mille(b.y_min),
                    per_mille(b.x_max),
                    per_mille(b.y_max),
                )
            });
        pdf.font_descriptor(descriptor)
            .name(Name(FONT_NAME))
            .flags(FontFlags::NON_SYMBOLIC)
            .bbox(bbox)
            .italic_angle(0.0)
            .ascent(per_mille(metrics.ascent))
            .descent(per_mille(metrics.descent))
            .cap_height(per_mille(metrics.cap_height.unwrap_or(metrics.ascent)))
            .stem_v(80.0)
            .font_file2(font_file);
        pdf.stream(font_file, &deflate(&subset))
            .filter(Filter::FlateDecode)
            .pair(Name(b"Length1"), subset.len() as i32);

        // The CIDToGIDMap: for each glyph id of the whole font up to the largest used, two bytes
        // of its id in the subset (0, the missing glyph, for those not used).
        let last = self.glyphs.keys().next_back().copied().unwrap_or(0);
        let mut map = vec![0u8; 2 * (usize::from(last) + 1)];
        for &glyph in self.glyphs.keys() {
            let new = remapper.get(glyph).unwrap_or(0);
            map[2 * usize::from(glyph)..2 * usize::from(glyph) + 2]
                .copy_from_slice(&new.to_be_bytes());
        }
        pdf.stream(gid_map, &deflate(&map))
            .filter(Filter::FlateDecode);

        let mut cmap = UnicodeCmap::new(
            Name(b"Adobe-Identity-UCS"),
            SystemInfo {
                registry: Str(b"Adobe"),
                ordering: Str(b"UCS"),
                supplement: 0,
            },
        );
        for (&glyph, &c) in &self.glyphs {
            cmap.pair(glyph, c);
        }
        pdf.cmap(to_unicode, &deflate(cmap.finish().as_slice()))
            .filter(Filter::FlateDecode);
        Ok(pdf.finish())
    }
}

/// The embedded font's PDF name: a subset is marked by six capitals and a plus before its name.
const FONT_NAME: &[u8] = b"PUSHLB+LiberationSans";

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
