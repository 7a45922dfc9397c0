//! The GIF's one palette, made for the scene rather than learned from each frame: each of the
//! app's colours (`app::colors`) exactly and blended over the scene's background at the
//! transparencies the scene draws with (a footprint's fill, the pusher's disc, anti-aliased
//! edges), greys for the text and the grid, and a colour cube for the rest. A per-frame quantizer
//! (NeuQuant) merged the COM's orange and the pusher's yellow into one entry on small frames; here
//! the orange stays orange and the blue blue in every frame. Pixels are mapped to the nearest
//! entry, remembered per colour, so a frame costs a lookup a pixel.

use std::collections::HashMap;

use crate::app::colors::Palette;

/// The index left transparent (a pixel like the frame before's).
pub const TRANSPARENT: u8 = 255;

/// The palette and the entry each colour seen maps to.
pub struct GifPalette {
    entries: Vec<[u8; 3]>,
    nearest: HashMap<[u8; 3], u8>,
}

impl GifPalette {
    /// The palette for frames drawn in `colours`: each exactly, and blended over its background.
    pub fn for_theme(colours: &Palette) -> Self {
        let themed = [
            colours.truth,
            colours.online,
            colours.fixed,
            colours.pure_nn,
            colours.physics,
            colours.robot,
            colours.contact,
            colours.com_label,
            colours.live,
            colours.warning,
        ];
        let [bg_r, bg_g, bg_b, _] = colours.background.to_array();
        let background = [bg_r, bg_g, bg_b];
        let mut entries: Vec<[u8; 3]> = Vec::with_capacity(255);
        let add = |c: [u8; 3], entries: &mut Vec<[u8; 3]>| {
            if !entries.contains(&c) && entries.len() < 255 {
                entries.push(c);
            }
        };
        add(background, &mut entries);
        for exact in [
            colours.grid,
            colours.grid_major,
            colours.grid_label,
            colours.muted,
        ] {
            let [r, g, b, _] = exact.to_array();
            add([r, g, b], &mut entries);
        }
        for grey in [
            0u8, 22, 27, 40, 55, 60, 80, 100, 120, 140, 160, 180, 200, 220, 230, 240, 248, 255,
        ] {
            add([grey; 3], &mut entries);
        }
        for colour in themed {
            let [r, g, b, _] = colour.to_array();
            for alpha in [1.0, 0.8, 0.6, 0.45, 0.35, 0.25, 0.15] {
                let mix = |c: u8, bg: u8| {
                    (alpha * f32::from(c) + (1.0 - alpha) * f32::from(bg)).round() as u8
                };
                add(
                    [
                        mix(r, background[0]),
                        mix(g, background[1]),
                        mix(b, background[2]),
                    ],
                    &mut entries,
                );
            }
        }
        let levels = [0u8, 64, 128, 192, 255];
        for r in levels {
            for g in [0u8, 51, 102, 153, 204, 255] {
                for b in levels {
                    add([r, g, b], &mut entries);
                }
            }
        }
        Self {
            entries,
            nearest: HashMap::new(),
        }
    }

    /// The palette as GIF wants it: RGB triples, the transparent entry last.
    pub fn bytes(&self) -> Vec<u8> {
        let mut bytes: Vec<u8> = self.entries.iter().flatten().copied().collect();
        bytes.resize(256 * 3, 0);
        bytes
    }

    /// The entry nearest `rgb` (squared distance, green weighted as the eye weighs it).
    pub fn index_of(&mut self, rgb: [u8; 3]) -> u8 {
        if let Some(&index) = self.nearest.get(&rgb) {
            return index;
        }
        let distance = |e: &[u8; 3]| {
            let d = |i: usize| i32::from(e[i]) - i32::from(rgb[i]);
            2 * d(0).pow(2) + 4 * d(1).pow(2) + 3 * d(2).pow(2)
        };
        let index = (self.entries.iter().enumerate())
            .min_by_key(|(_, e)| distance(e))
            .map_or(0, |(i, _)| i as u8);
        self.nearest.insert(rgb, index);
        index
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::colors::{DARK, LIGHT};

    #[test]
    fn the_scenes_colours_keep_entries_of_their_own() {
        for colours in [DARK, LIGHT] {
            let mut palette = GifPalette::for_theme(&colours);
            assert!(palette.entries.len() <= 255, "one index stays transparent");
            let rgb = |c: eframe::egui::Color32| {
                let [r, g, b, _] = c.to_array();
                [r, g, b]
            };
            for colour in [
                colours.background,
                colours.online,
                colours.fixed,
                colours.robot,
                colours.truth,
            ] {
                let index = palette.index_of(rgb(colour));
                assert_eq!(
                    palette.entries[usize::from(index)],
                    rgb(colour),
                    "{colour:?} exactly"
                );
            }
            assert_ne!(
                palette.index_of(rgb(colours.online)),
                palette.index_of(rgb(colours.robot)),
                "orange is not yellow"
            );
            assert_eq!(palette.bytes().len(), 768);
        }
    }
}
