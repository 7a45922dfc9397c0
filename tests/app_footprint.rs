//! The scene draws a non-convex footprint as it is: the Push-T T rendered (wgpu on the CPU, as the
//! snapshot test) is filled in its bar and stem and left empty in the notches beside the stem, which
//! a convex-polygon fill would paint over.

use egui_kittest::Harness;
use nalgebra::Point2;
use pushlab::app::panels::scene::camera::{Camera, Projection};
use pushlab::app::panels::scene::draw::{FootprintStyle, footprint};
use pushlab_core::geometry::{Pose2, PushT};

#[test]
fn the_t_is_filled_in_its_bar_and_stem_and_not_in_its_notches() {
    let outline = PushT::outline(0.001).expect("the T");
    let camera = Camera {
        centre: Point2::origin(),
        scale: 2000.0,
    };
    let mut harness = Harness::builder()
        .with_size([400.0, 400.0])
        .with_render_cursor(false)
        .build_ui(move |ui| {
            let projection = Projection {
                viewport: ui.max_rect(),
                camera,
            };
            footprint(
                ui.painter(),
                &projection,
                &outline,
                &Pose2::new(0.0, 0.0, 0.0),
                FootprintStyle::measured_now(&pushlab::app::colors::DARK),
            );
        });
    harness.run();
    let image = harness.render().expect("renders");
    // Where a point of the T's local frame (pixels of gym-pusht) lands in the image: the viewport
    // is the window, 400 × 400 points at the default 1 pixel per point.
    let pixel = |x: f64, y: f64| {
        let p = PushT::object_from_local(Point2::new(x, y), 0.001);
        let (px, py) = (200.0 + p.x * 2000.0, 200.0 - p.y * 2000.0);
        let scale = image.width() as f64 / 400.0;
        *image.get_pixel((px * scale) as u32, (py * scale) as u32)
    };
    let background = pixel(37.5, 110.0); // Far up the right notch.
    // A convex fill fans out from the first vertex (the bar's left end) and paints the left notch
    // beside the stem: (−20, 60) and (−22, 100) px are where it did.
    for (x, y) in [
        (37.5, 75.0),
        (-37.5, 75.0),
        (45.0, 40.0),
        (-20.0, 60.0),
        (-22.0, 100.0),
    ] {
        assert_eq!(
            pixel(x, y),
            background,
            "the notch at ({x}, {y}) px is filled"
        );
    }
    for (x, y) in [(0.0, 80.0), (-45.0, 15.0), (45.0, 15.0), (0.0, 15.0)] {
        assert_ne!(
            pixel(x, y),
            background,
            "the T at ({x}, {y}) px is not filled"
        );
    }
}
