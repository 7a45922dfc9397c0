//! The scene's camera: which world point sits at the centre of the view and how many screen points a
//! metre spans, and how it moves — following the object, fitted to the whole push, or left where the
//! user put it. Plain maths on rectangles, unit-tested apart from any drawing.
//!
//! The *viewport* is the part of the scene the camera may use: the scene minus the open legend, so
//! that following or fitting never puts the object under it.

use eframe::egui::{Pos2, Rect, Vec2};
use nalgebra::Point2;

/// Fewest points per metre (a 45 m wide view in 900 points).
pub const MIN_SCALE: f32 = 20.0;
/// Most points per metre (a 5 mm wide view in 1000 points).
pub const MAX_SCALE: f32 = 200_000.0;

/// An axis-aligned box in the world, metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldBox {
    pub min: Point2<f64>,
    pub max: Point2<f64>,
}

impl WorldBox {
    /// The smallest box holding every point; `None` without a finite point.
    pub fn around(points: impl IntoIterator<Item = Point2<f64>>) -> Option<Self> {
        points
            .into_iter()
            .filter(|p| p.x.is_finite() && p.y.is_finite())
            .fold(None, |found: Option<WorldBox>, p| {
                Some(match found {
                    None => WorldBox { min: p, max: p },
                    Some(b) => WorldBox {
                        min: b.min.inf(&p),
                        max: b.max.sup(&p),
                    },
                })
            })
    }

    /// The box grown by `margin` metres on every side.
    pub fn grown(self, margin: f64) -> Self {
        WorldBox {
            min: self.min - nalgebra::Vector2::repeat(margin),
            max: self.max + nalgebra::Vector2::repeat(margin),
        }
    }

    /// The smallest box holding both.
    pub fn union(self, other: WorldBox) -> Self {
        WorldBox {
            min: self.min.inf(&other.min),
            max: self.max.sup(&other.max),
        }
    }

    pub fn centre(&self) -> Point2<f64> {
        nalgebra::center(&self.min, &self.max)
    }

    /// Width and height, metres.
    pub fn size(&self) -> [f64; 2] {
        [self.max.x - self.min.x, self.max.y - self.min.y]
    }
}

/// Where the camera looks and how close.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// The world point at the centre of the viewport, metres.
    pub centre: Point2<f64>,
    /// Screen points per metre.
    pub scale: f32,
}

impl Default for Camera {
    fn default() -> Self {
        Self {
            centre: Point2::origin(),
            scale: 2000.0,
        }
    }
}

impl Camera {
    /// The camera that shows all of `world` in `viewport`, centred.
    pub fn fitting(world: WorldBox, viewport: Rect) -> Self {
        let [w, h] = world.size();
        let scale = (f64::from(viewport.width()) / w.max(1e-3))
            .min(f64::from(viewport.height()) / h.max(1e-3));
        Self {
            centre: world.centre(),
            scale: clamp_scale(scale as f32),
        }
    }

    /// Keeps the zoom and centres `target` (what should be seen) in the viewport; when `target` is
    /// larger than the viewport at this zoom, centres `must_see` (the object itself) instead, so
    /// that it never leaves the view — zooming out only when the object alone does not fit.
    pub fn follow(&mut self, target: WorldBox, must_see: WorldBox, viewport: Rect) {
        let fits = |b: &WorldBox, scale: f32| {
            let [w, h] = b.size();
            w * f64::from(scale) <= f64::from(viewport.width())
                && h * f64::from(scale) <= f64::from(viewport.height())
        };
        if fits(&target, self.scale) {
            self.centre = target.centre();
        } else {
            self.centre = must_see.centre();
            if !fits(&must_see, self.scale) {
                self.scale = Self::fitting(must_see, viewport).scale;
            }
        }
    }

    /// Moves the view by a drag of `delta` screen points (the world follows the pointer).
    pub fn pan(&mut self, delta: Vec2) {
        self.centre.x -= f64::from(delta.x / self.scale);
        self.centre.y += f64::from(delta.y / self.scale);
    }

    /// Zooms by `factor` keeping the world point under `pointer` where it is on the screen.
    pub fn zoom_about(&mut self, viewport: Rect, pointer: Pos2, factor: f32) {
        let before = self.on(viewport).to_world(pointer);
        self.scale = clamp_scale(self.scale * factor);
        let after = self.on(viewport).to_world(pointer);
        self.centre += before - after;
    }

    /// The projection of this camera onto `viewport`.
    pub fn on(self, viewport: Rect) -> Projection {
        Projection {
            viewport,
            camera: self,
        }
    }
}

fn clamp_scale(scale: f32) -> f32 {
    if scale.is_finite() {
        scale.clamp(MIN_SCALE, MAX_SCALE)
    } else {
        MAX_SCALE
    }
}

/// Maps world metres to screen points and back (y up in the world, down on the screen).
#[derive(Clone, Copy, Debug)]
pub struct Projection {
    pub viewport: Rect,
    pub camera: Camera,
}

impl Projection {
    /// Screen points per metre.
    pub fn scale(&self) -> f32 {
        self.camera.scale
    }

    pub fn to_screen(&self, world: Point2<f64>) -> Pos2 {
        let c = self.viewport.center();
        let d = world - self.camera.centre;
        Pos2::new(
            c.x + (d.x as f32) * self.camera.scale,
            c.y - (d.y as f32) * self.camera.scale,
        )
    }

    pub fn to_world(&self, screen: Pos2) -> Point2<f64> {
        let c = self.viewport.center();
        Point2::new(
            self.camera.centre.x + f64::from((screen.x - c.x) / self.camera.scale),
            self.camera.centre.y - f64::from((screen.y - c.y) / self.camera.scale),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn viewport() -> Rect {
        Rect::from_min_size(Pos2::new(250.0, 30.0), Vec2::new(800.0, 500.0))
    }

    fn close(a: Point2<f64>, b: Point2<f64>, tolerance: f64) -> bool {
        (a - b).norm() <= tolerance
    }

    #[test]
    fn screen_and_world_round_trip_with_y_up() {
        let camera = Camera {
            centre: Point2::new(1.25, -0.5),
            scale: 1234.0,
        };
        let p = camera.on(viewport());
        assert_eq!(p.to_screen(camera.centre), viewport().center());
        for world in [
            Point2::new(1.3, -0.45),
            Point2::new(0.9, -0.7),
            Point2::new(1.25, -0.5),
        ] {
            assert!(close(p.to_world(p.to_screen(world)), world, 1e-6));
        }
        // Up in the world is up on the screen (smaller y).
        assert!(p.to_screen(Point2::new(1.25, -0.4)).y < viewport().center().y);
    }

    #[test]
    fn zooming_keeps_the_point_under_the_pointer() {
        let mut camera = Camera::default();
        let pointer = Pos2::new(900.0, 100.0);
        let under = camera.on(viewport()).to_world(pointer);
        camera.zoom_about(viewport(), pointer, 3.0);
        assert_eq!(camera.scale, 6000.0);
        assert!(close(camera.on(viewport()).to_world(pointer), under, 1e-6));
        camera.zoom_about(viewport(), pointer, 1e9);
        assert_eq!(camera.scale, MAX_SCALE, "clamped");
        assert!(close(camera.on(viewport()).to_world(pointer), under, 1e-6));
    }

    #[test]
    fn fitting_shows_the_whole_box_centred() {
        let world =
            WorldBox::around([Point2::new(-0.2, 0.0), Point2::new(0.6, 0.1)]).expect("points");
        let camera = Camera::fitting(world, viewport());
        let p = camera.on(viewport());
        // 0.8 m across 800 points is the tighter fit: 1000 points per metre.
        assert_eq!(camera.scale, 1000.0);
        for corner in [world.min, world.max] {
            assert!(viewport().expand(0.01).contains(p.to_screen(corner)));
        }
        assert_eq!(p.to_screen(world.centre()), viewport().center());
        // A single point gets the closest zoom that still shows a millimetre.
        let point = WorldBox::around([Point2::new(3.0, 4.0)]).expect("a point");
        assert!(Camera::fitting(point, viewport()).scale <= MAX_SCALE);
        assert!(WorldBox::around([Point2::new(f64::NAN, 0.0)]).is_none());
    }

    #[test]
    fn following_keeps_the_zoom_and_centres_the_target_or_else_the_object() {
        let mut camera = Camera {
            centre: Point2::origin(),
            scale: 1000.0,
        };
        let object = WorldBox::around([Point2::new(2.0, 2.0), Point2::new(2.1, 2.1)]).expect("box");
        let target = object
            .union(WorldBox::around([Point2::new(2.4, 2.2), Point2::new(2.5, 2.3)]).expect("box"));
        camera.follow(target, object, viewport());
        assert_eq!(camera.scale, 1000.0, "the user's zoom is kept");
        assert!(close(camera.centre, target.centre(), 1e-12));
        // Zoomed in so far that the target does not fit: the object stays centred.
        camera.scale = 5000.0;
        camera.follow(target, object, viewport());
        assert!(close(camera.centre, object.centre(), 1e-12));
        let p = camera.on(viewport());
        assert!(viewport().contains(p.to_screen(object.min)));
        assert!(viewport().contains(p.to_screen(object.max)));
        // So far in that the object alone does not fit (a narrow viewport): zoomed out to fit it.
        camera.scale = 50_000.0;
        camera.follow(target, object, viewport());
        assert_eq!(
            camera.scale,
            500.0 / 0.1,
            "the object's 0.1 m in 500 points"
        );
        let p = camera.on(viewport());
        assert!(viewport().expand(0.01).contains(p.to_screen(object.min)));
        assert!(viewport().expand(0.01).contains(p.to_screen(object.max)));
    }

    #[test]
    fn panning_moves_the_world_with_the_pointer() {
        let mut camera = Camera::default();
        let grabbed = Pos2::new(400.0, 200.0);
        let world = camera.on(viewport()).to_world(grabbed);
        camera.pan(Vec2::new(30.0, -12.0));
        let p = camera.on(viewport()).to_screen(world);
        assert!((p - (grabbed + Vec2::new(30.0, -12.0))).length() < 1e-3);
    }
}
