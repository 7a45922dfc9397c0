//! One colour per quantity, shared by the scene, its legend and the plots, so that "orange" means the
//! online-learned model everywhere — in both themes.
//!
//! Why two palettes: the dark one is tuned for a screen (light strokes on near-black), and on paper
//! or a projector's white its near-white truth and yellow pusher vanish. The light palette keeps
//! each quantity's hue and darkens it until it reads on white. Which one applies is egui's own
//! `Visuals::dark_mode`, so the theme is one switch (View → Theme, projector mode, or
//! `pushlab render --theme`), and every painter asks [`of`] rather than holding a colour.

use eframe::egui::{self, Color32};

/// The colours of one theme.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Palette {
    /// The scene's background.
    pub background: Color32,
    /// Measured (true) object poses and true parameter values.
    pub truth: Color32,
    /// The online-learned combined model and `θ_online`.
    pub online: Color32,
    /// The fixed model (`θ_online(0)`, never updated).
    pub fixed: Color32,
    /// The pure-network baseline.
    pub pure_nn: Color32,
    /// The physics-only model.
    pub physics: Color32,
    /// The robot's pusher disc and its path.
    pub robot: Color32,
    /// The contact point `c` and contact motion `u_c`.
    pub contact: Color32,
    /// The COM labelled in a recording's metadata.
    pub com_label: Color32,
    /// The pushes suggested next (the Steer tab's "next push that teaches the most"): arrows.
    pub suggestion: Color32,
    /// Grid lines.
    pub grid: Color32,
    /// Every tenth grid line.
    pub grid_major: Color32,
    /// The grid's labels (metres).
    pub grid_label: Color32,
    /// Text drawn on the scene when there is nothing to show.
    pub muted: Color32,
    /// The open legend's backing, which its labels are read against.
    pub legend_fill: Color32,
    /// The timeline's bands (labels, proposals, gaps) behind their pieces.
    pub band: Color32,
    /// The current frame's tick on a band and the plots' "now" line.
    pub cursor: Color32,
    /// The LIVE badge of a live session connected to its robot.
    pub live: Color32,
    /// Warnings a user should act on (a model that does not fit the recordings).
    pub warning: Color32,
    /// Contour lines over the loss landscape.
    pub contour: Color32,
}

/// The screen theme: light strokes on near-black.
pub const DARK: Palette = Palette {
    background: Color32::from_gray(22),
    truth: Color32::from_rgb(230, 230, 230),
    online: Color32::from_rgb(255, 150, 40),
    fixed: Color32::from_rgb(90, 160, 255),
    pure_nn: Color32::from_rgb(120, 210, 120),
    physics: Color32::from_rgb(200, 120, 230),
    robot: Color32::from_rgb(240, 210, 70),
    contact: Color32::from_rgb(255, 80, 80),
    com_label: Color32::from_rgb(240, 90, 220),
    suggestion: Color32::from_rgb(60, 210, 200),
    grid: Color32::from_gray(55),
    grid_major: Color32::from_gray(80),
    grid_label: Color32::from_gray(128),
    muted: Color32::GRAY,
    legend_fill: Color32::from_rgba_premultiplied(0, 0, 0, 200),
    band: Color32::from_gray(22),
    cursor: Color32::from_gray(200),
    live: Color32::from_rgb(235, 70, 70),
    warning: Color32::from_rgb(255, 200, 60),
    contour: Color32::from_rgba_premultiplied(200, 200, 200, 160),
};

/// The paper and projector theme: the same hues, dark enough to read on white (each at least 3:1
/// against the background, WCAG's contrast for graphics; tested).
pub const LIGHT: Palette = Palette {
    background: Color32::from_gray(250),
    truth: Color32::from_gray(35),
    online: Color32::from_rgb(214, 96, 0),
    fixed: Color32::from_rgb(25, 95, 210),
    pure_nn: Color32::from_rgb(30, 135, 50),
    physics: Color32::from_rgb(140, 50, 185),
    robot: Color32::from_rgb(150, 120, 0),
    contact: Color32::from_rgb(205, 30, 30),
    com_label: Color32::from_rgb(190, 30, 160),
    suggestion: Color32::from_rgb(0, 125, 125),
    grid: Color32::from_gray(228),
    grid_major: Color32::from_gray(200),
    grid_label: Color32::from_gray(110),
    muted: Color32::from_gray(100),
    legend_fill: Color32::from_rgba_premultiplied(225, 225, 225, 225),
    band: Color32::from_gray(225),
    cursor: Color32::from_gray(40),
    live: Color32::from_rgb(210, 35, 35),
    warning: Color32::from_rgb(170, 110, 0),
    contour: Color32::from_rgba_premultiplied(40, 40, 40, 160),
};

/// The theme `ctx` draws with: its visuals' own (projector mode sets light visuals without
/// changing egui's theme preference).
pub fn theme_of(ctx: &egui::Context) -> egui::Theme {
    if ctx.global_style().visuals.dark_mode {
        egui::Theme::Dark
    } else {
        egui::Theme::Light
    }
}

/// The palette of the theme `ctx` draws with.
pub fn of(ctx: &egui::Context) -> &'static Palette {
    of_theme(theme_of(ctx))
}

/// The palette of `theme`.
pub fn of_theme(theme: egui::Theme) -> &'static Palette {
    match theme {
        egui::Theme::Dark => &DARK,
        egui::Theme::Light => &LIGHT,
    }
}

/// The loss landscape's colour scale, lowest loss first (viridis: ordered in lightness, readable
/// by colour-blind viewers and in greyscale, on either background).
pub const LANDSCAPE_PALETTE: [Color32; 5] = [
    Color32::from_rgb(68, 1, 84),
    Color32::from_rgb(59, 82, 139),
    Color32::from_rgb(33, 145, 140),
    Color32::from_rgb(94, 201, 98),
    Color32::from_rgb(253, 231, 37),
];

#[cfg(test)]
mod tests {
    use super::*;

    /// WCAG's relative luminance of an sRGB colour.
    fn luminance(c: Color32) -> f64 {
        let channel = |v: u8| {
            let v = f64::from(v) / 255.0;
            if v <= 0.039_28 {
                v / 12.92
            } else {
                ((v + 0.055) / 1.055).powf(2.4)
            }
        };
        0.2126 * channel(c.r()) + 0.7152 * channel(c.g()) + 0.0722 * channel(c.b())
    }

    fn contrast(a: Color32, b: Color32) -> f64 {
        let (la, lb) = (luminance(a), luminance(b));
        (la.max(lb) + 0.05) / (la.min(lb) + 0.05)
    }

    #[test]
    fn every_quantity_reads_against_its_themes_background() {
        for (name, palette) in [("dark", DARK), ("light", LIGHT)] {
            let drawn = [
                ("truth", palette.truth),
                ("online", palette.online),
                ("fixed", palette.fixed),
                ("pure_nn", palette.pure_nn),
                ("physics", palette.physics),
                ("robot", palette.robot),
                ("contact", palette.contact),
                ("com_label", palette.com_label),
                ("suggestion", palette.suggestion),
                ("grid_label", palette.grid_label),
                ("cursor", palette.cursor),
            ];
            for (quantity, colour) in drawn {
                let ratio = contrast(colour, palette.background);
                assert!(
                    ratio >= 3.0,
                    "{name} theme: {quantity} has contrast {ratio:.2} against the background"
                );
            }
        }
        // The old light-on-dark colours on white would not: the pusher's yellow is 1.5:1.
        assert!(contrast(DARK.robot, LIGHT.background) < 2.0);
    }

    #[test]
    fn the_orange_and_the_pushers_yellow_stay_apart_in_both_themes() {
        for palette in [DARK, LIGHT] {
            let [r1, g1, b1, _] = palette.online.to_array();
            let [r2, g2, b2, _] = palette.robot.to_array();
            let distance = (f64::from(r1) - f64::from(r2)).abs()
                + (f64::from(g1) - f64::from(g2)).abs()
                + (f64::from(b1) - f64::from(b2)).abs();
            assert!(distance >= 60.0, "online and robot only {distance} apart");
        }
    }
}
