//! egui's tessellated output painted into pixels on the CPU, for rendered videos. The scene is
//! drawn by the app's own painting code (`panels::scene`) and tessellated by egui exactly as in the
//! window; only this last step — triangles into pixels — is done here instead of on the GPU, so that
//! `pushlab render` needs no graphics device and gives the same pixels on every machine.
//!
//! It follows egui's renderers: vertex colours and textures are premultiplied sRGB, multiplied
//! together and blended in gamma space (`out = src + dst·(1 − src.a)`), a linear-filtered texture
//! (the font atlas) sampled bilinearly, each mesh cut to its clip rectangle. Edges need no
//! anti-aliasing of their own: egui feathers them with a thin ring of transparent vertices.

use std::collections::HashMap;

use eframe::egui::{self, Color32, TextureId};
use eframe::epaint::textures::{TextureFilter, TexturesDelta};
use eframe::epaint::{ClippedPrimitive, ImageData, Primitive};

/// The textures egui asked for (the font atlas, images), kept as it updates them.
#[derive(Default)]
pub struct Textures {
    by_id: HashMap<TextureId, Texture>,
}

struct Texture {
    size: [usize; 2],
    pixels: Vec<Color32>,
    linear: bool,
}

impl Textures {
    /// Applies one frame's texture changes: new textures, patches of existing ones, frees.
    pub fn update(&mut self, delta: &TexturesDelta) {
        for (id, change) in delta
            .set
            .iter()
            .flat_map(|(id, changes)| changes.iter().map(move |c| (id, c)))
        {
            let ImageData::Color(image) = &change.image;
            let linear = change.options.magnification == TextureFilter::Linear;
            match change.pos {
                None => {
                    self.by_id.insert(
                        *id,
                        Texture {
                            size: image.size,
                            pixels: image.pixels.clone(),
                            linear,
                        },
                    );
                }
                Some([x0, y0]) => {
                    let Some(texture) = self.by_id.get_mut(id) else {
                        continue;
                    };
                    let [w, h] = image.size;
                    for y in 0..h {
                        for x in 0..w {
                            let (tx, ty) = (x0 + x, y0 + y);
                            if tx < texture.size[0] && ty < texture.size[1] {
                                texture.pixels[ty * texture.size[0] + tx] = image.pixels[y * w + x];
                            }
                        }
                    }
                }
            }
        }
        for id in &delta.free {
            self.by_id.remove(id);
        }
    }
}

impl Texture {
    /// The premultiplied colour at `uv`, components in 0 … 1.
    fn sample(&self, u: f32, v: f32) -> [f32; 4] {
        let [w, h] = self.size;
        if w == 0 || h == 0 {
            return [1.0; 4];
        }
        let texel = |x: usize, y: usize| {
            let c = self.pixels[y.min(h - 1) * w + x.min(w - 1)].to_array();
            c.map(|v| f32::from(v) / 255.0)
        };
        if !self.linear {
            let x = (u * w as f32).floor().clamp(0.0, (w - 1) as f32) as usize;
            let y = (v * h as f32).floor().clamp(0.0, (h - 1) as f32) as usize;
            return texel(x, y);
        }
        let x = (u * w as f32 - 0.5).clamp(0.0, (w - 1) as f32);
        let y = (v * h as f32 - 0.5).clamp(0.0, (h - 1) as f32);
        let (x0, y0) = (x.floor() as usize, y.floor() as usize);
        let (fx, fy) = (x - x0 as f32, y - y0 as f32);
        let (a, b) = (texel(x0, y0), texel(x0 + 1, y0));
        let (c, d) = (texel(x0, y0 + 1), texel(x0 + 1, y0 + 1));
        std::array::from_fn(|i| {
            let top = a[i] + (b[i] - a[i]) * fx;
            let bottom = c[i] + (d[i] - c[i]) * fx;
            top + (bottom - top) * fy
        })
    }
}

/// An RGBA picture being painted, components in 0 … 1 (premultiplied, opaque once filled).
pub struct Canvas {
    width: usize,
    height: usize,
    pixels: Vec<[f32; 4]>,
}

impl Canvas {
    /// A canvas of `width` × `height` pixels filled with `background`.
    pub fn new(width: usize, height: usize, background: Color32) -> Self {
        let fill = background.to_array().map(|v| f32::from(v) / 255.0);
        Self {
            width,
            height,
            pixels: vec![fill; width * height],
        }
    }

    /// Paints egui's primitives, their positions in points at `pixels_per_point`.
    pub fn paint(
        &mut self,
        primitives: &[ClippedPrimitive],
        textures: &Textures,
        pixels_per_point: f32,
    ) {
        for primitive in primitives {
            let Primitive::Mesh(mesh) = &primitive.primitive else {
                continue;
            };
            let texture = textures.by_id.get(&mesh.texture_id);
            let clip = primitive.clip_rect * pixels_per_point;
            let clip = [
                clip.min.x.round().max(0.0) as usize,
                clip.min.y.round().max(0.0) as usize,
                (clip.max.x.round().max(0.0) as usize).min(self.width),
                (clip.max.y.round().max(0.0) as usize).min(self.height),
            ];
            for triangle in mesh.indices.chunks_exact(3) {
                let vertex = |k: usize| mesh.vertices.get(triangle[k] as usize);
                if let (Some(a), Some(b), Some(c)) = (vertex(0), vertex(1), vertex(2)) {
                    self.triangle([a, b, c], texture, pixels_per_point, clip);
                }
            }
        }
    }

    fn triangle(
        &mut self,
        v: [&egui::epaint::Vertex; 3],
        texture: Option<&Texture>,
        pixels_per_point: f32,
        clip: [usize; 4],
    ) {
        let p = v.map(|v| (v.pos.x * pixels_per_point, v.pos.y * pixels_per_point));
        let edge = |a: (f32, f32), b: (f32, f32), x: f32, y: f32| {
            (b.0 - a.0) * (y - a.1) - (b.1 - a.1) * (x - a.0)
        };
        let area = edge(p[0], p[1], p[2].0, p[2].1);
        if area.abs() < 1e-9 {
            return;
        }
        let inverse = 1.0 / area;
        let lowest = |i: usize| {
            p.iter()
                .map(|q| if i == 0 { q.0 } else { q.1 })
                .fold(f32::MAX, f32::min)
        };
        let highest = |i: usize| {
            p.iter()
                .map(|q| if i == 0 { q.0 } else { q.1 })
                .fold(f32::MIN, f32::max)
        };
        let x0 = (lowest(0).floor().max(clip[0] as f32)) as usize;
        let y0 = (lowest(1).floor().max(clip[1] as f32)) as usize;
        let x1 = (highest(0).ceil() as usize).min(clip[2]);
        let y1 = (highest(1).ceil() as usize).min(clip[3]);
        let colors = v.map(|v| v.color.to_array().map(|c| f32::from(c) / 255.0));
        for y in y0..y1 {
            let py = y as f32 + 0.5;
            for x in x0..x1 {
                let px = x as f32 + 0.5;
                let w0 = edge(p[1], p[2], px, py) * inverse;
                let w1 = edge(p[2], p[0], px, py) * inverse;
                let w2 = 1.0 - w0 - w1;
                if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                    continue;
                }
                let w = [w0, w1, w2];
                let mut src: [f32; 4] = std::array::from_fn(|i| {
                    w[0] * colors[0][i] + w[1] * colors[1][i] + w[2] * colors[2][i]
                });
                if let Some(texture) = texture {
                    let u = w[0] * v[0].uv.x + w[1] * v[1].uv.x + w[2] * v[2].uv.x;
                    let t = w[0] * v[0].uv.y + w[1] * v[1].uv.y + w[2] * v[2].uv.y;
                    let texel = texture.sample(u, t);
                    for i in 0..4 {
                        src[i] *= texel[i];
                    }
                }
                let dst = &mut self.pixels[y * self.width + x];
                let keep = 1.0 - src[3];
                for i in 0..4 {
                    dst[i] = src[i] + dst[i] * keep;
                }
            }
        }
    }

    /// The picture as RGBA bytes, row by row.
    pub fn rgba(&self) -> Vec<u8> {
        (self.pixels.iter())
            .flat_map(|p| p.map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8))
            .collect()
    }
}
