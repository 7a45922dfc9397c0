//! One colour per quantity, shared by the scene, its legend and the plots, so that "orange" means the
//! online-learned model everywhere.

use eframe::egui::Color32;

/// Measured (true) object poses and true parameter values.
pub const TRUE: Color32 = Color32::from_rgb(230, 230, 230);
/// The online-learned combined model and `θ_online`.
pub const ONLINE: Color32 = Color32::from_rgb(255, 150, 40);
/// The fixed model (`θ_online(0)`, never updated).
pub const FIXED: Color32 = Color32::from_rgb(90, 160, 255);
/// The pure-network baseline.
pub const PURE_NN: Color32 = Color32::from_rgb(120, 210, 120);
/// The physics-only model.
pub const PHYSICS: Color32 = Color32::from_rgb(200, 120, 230);
/// The robot's pusher disc and its path.
pub const ROBOT: Color32 = Color32::from_rgb(240, 210, 70);
/// The contact point `c` and contact motion `u_c`.
pub const CONTACT: Color32 = Color32::from_rgb(255, 80, 80);
/// The COM labelled in a recording's metadata.
pub const COM_LABEL: Color32 = Color32::from_rgb(240, 90, 220);
/// Grid lines.
pub const GRID: Color32 = Color32::from_gray(55);
/// Every tenth grid line.
pub const GRID_MAJOR: Color32 = Color32::from_gray(80);

/// The LIVE badge of a live session connected to its robot.
pub const LIVE: Color32 = Color32::from_rgb(235, 70, 70);

/// Warnings a user should act on (a model that does not fit the recordings).
pub const WARNING: Color32 = Color32::from_rgb(255, 200, 60);

/// The loss landscape's colour scale, lowest loss first (viridis: ordered in lightness, readable
/// by colour-blind viewers and in greyscale).
pub const LANDSCAPE_PALETTE: [Color32; 5] = [
    Color32::from_rgb(68, 1, 84),
    Color32::from_rgb(59, 82, 139),
    Color32::from_rgb(33, 145, 140),
    Color32::from_rgb(94, 201, 98),
    Color32::from_rgb(253, 231, 37),
];
/// Contour lines over the landscape.
pub const CONTOUR: Color32 = Color32::from_rgba_premultiplied(200, 200, 200, 160);
