//! Where the pusher can push the object and how it gets there: contact sites on the faces of the
//! object's convex hull that are faces of the object itself (a T's notches and the hull's bridges
//! over them are left out: a disc cannot push there), and the way round the object at a clearance
//! for a pusher moving from one face to another. Everything in the object's frame, where it does
//! not change as the object moves.

use crate::math;
use nalgebra::{Point2, Vector2};

use crate::geometry::{Outline, cross, rotate};

/// How far off the object the pusher goes round it, beyond touching, metres.
pub const CLEARANCE_M: f64 = 0.025;
/// How far before touching a push starts, along its direction, metres.
pub const APPROACH_M: f64 = 0.02;
/// Sites are kept this far from a sharp corner (or a quarter of the face on a short one).
const CORNER_MARGIN_M: f64 = 0.02;
/// A bend sharper than this ends a face at a corner.
const SHARP_RAD: f64 = 20.0 * std::f64::consts::PI / 180.0;
/// The way round's arcs are drawn in pieces of at most this turn.
const ARC_PIECE_RAD: f64 = 15.0 * std::f64::consts::PI / 180.0;

/// A place on the object's boundary to push at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Site {
    /// The contact point, object frame.
    pub point: Point2<f64>,
    /// The outward normal there.
    pub normal: Vector2<f64>,
    /// Where along the pushable perimeter it lies, metres (see [`Sites::site_at`]).
    pub along: f64,
}

/// A hull face the pusher can push, with the stretch of it kept clear of corners.
#[derive(Clone, Debug)]
struct Face {
    a: Point2<f64>,
    direction: Vector2<f64>,
    normal: Vector2<f64>,
    /// The usable stretch, metres from `a`.
    usable: (f64, f64),
    /// Where its usable stretch starts along the pushable perimeter.
    starts_at: f64,
}

/// The object's pushable sites and the way round it (see the module documentation).
#[derive(Clone, Debug)]
pub struct Sites {
    outline: Outline,
    pusher_radius: f64,
    faces: Vec<Face>,
    perimeter: f64,
    /// The way round: a closed polygon about the hull at the pusher's radius and the clearance,
    /// counter-clockwise, with the distance along it at each vertex.
    ring: Vec<(Point2<f64>, f64)>,
    ring_length: f64,
}

impl Sites {
    /// The sites of `outline` for a disc pusher of `pusher_radius`.
    pub fn new(outline: &Outline, pusher_radius: f64) -> Self {
        let vertices = outline.vertices();
        let hull = convex_hull(vertices);
        let n = hull.len();
        let mut faces = Vec::new();
        let mut perimeter = 0.0;
        for k in 0..n {
            let (i, j) = (hull[k], hull[(k + 1) % n]);
            let (a, b) = (vertices[i], vertices[j]);
            if !is_outline_face(vertices, i, j) {
                continue;
            }
            let length = (b - a).norm();
            let direction = (b - a) / length;
            let before = vertices[hull[(k + n - 1) % n]];
            let after = vertices[hull[(k + 2) % n]];
            let margin = CORNER_MARGIN_M.min(0.25 * length);
            let bend_at_a = turn(a - before, b - a);
            let bend_at_b = turn(b - a, after - b);
            let usable = (
                if bend_at_a > SHARP_RAD { margin } else { 0.0 },
                length - if bend_at_b > SHARP_RAD { margin } else { 0.0 },
            );
            faces.push(Face {
                a,
                direction,
                normal: Vector2::new(direction.y, -direction.x),
                usable,
                starts_at: perimeter,
            });
            perimeter += usable.1 - usable.0;
        }
        let ring = ring_about(vertices, &hull, pusher_radius + CLEARANCE_M);
        let ring_length = ring.last().map_or(0.0, |(_, s)| *s);
        Self {
            outline: outline.clone(),
            pusher_radius,
            faces,
            perimeter,
            ring,
            ring_length,
        }
    }

    /// The length of the pushable perimeter, metres.
    pub fn perimeter(&self) -> f64 {
        self.perimeter
    }

    /// Where the `i`-th of `n` sites spread evenly round the pushable perimeter lies, metres
    /// along it: the middle of its `n`-th (the planner's grid).
    pub fn evenly(&self, i: usize, n: usize) -> f64 {
        (i as f64 + 0.5) * self.perimeter / n as f64
    }

    /// Which of `n` sites spread evenly ([`Sites::evenly`]) has `along` in its `n`-th of the
    /// perimeter (taken round it modulo its length).
    pub fn evenly_nearest(&self, along: f64, n: usize) -> usize {
        if n == 0 || self.perimeter <= 0.0 {
            return 0;
        }
        let i = (along.rem_euclid(self.perimeter) / self.perimeter * n as f64).floor() as usize;
        i.min(n - 1)
    }

    /// The pusher's radius.
    pub fn pusher_radius(&self) -> f64 {
        self.pusher_radius
    }

    /// The object's outline.
    pub fn outline(&self) -> &Outline {
        &self.outline
    }

    /// How far a pusher centred at `pusher_in_object` is from touching the object (negative: it
    /// overlaps it), metres.
    pub fn gap(&self, pusher_in_object: Point2<f64>) -> f64 {
        self.outline
            .closest_boundary_point(pusher_in_object)
            .signed_distance
            - self.pusher_radius
    }

    /// The site `along` metres round the pushable perimeter (taken round it modulo its length).
    pub fn site_at(&self, along: f64) -> Option<Site> {
        if !(self.perimeter > 0.0 && along.is_finite()) {
            return None;
        }
        let along = along.rem_euclid(self.perimeter);
        let face = self
            .faces
            .iter()
            .rev()
            .find(|f| f.starts_at <= along)
            .or(self.faces.first())?;
        let at = face.usable.0 + (along - face.starts_at);
        Some(Site {
            point: face.a + face.direction * at.min(face.usable.1),
            normal: face.normal,
            along,
        })
    }

    /// The site nearest to a pusher at `pusher_in_object` if it is within `reach` of touching a
    /// pushable face there (its contact point within the face's usable stretch).
    pub fn site_near(&self, pusher_in_object: Point2<f64>, reach: f64) -> Option<(Site, f64)> {
        self.faces.iter().find_map(|face| {
            let along_face = (pusher_in_object - face.a).dot(&face.direction);
            let gap = (pusher_in_object - face.a).dot(&face.normal) - self.pusher_radius;
            let inside = (face.usable.0..=face.usable.1).contains(&along_face);
            (inside && gap > -reach && gap < reach).then(|| {
                let site = Site {
                    point: face.a + face.direction * along_face,
                    normal: face.normal,
                    along: face.starts_at + along_face - face.usable.0,
                };
                (site, gap.max(0.0))
            })
        })
    }

    /// Where the pusher's centre is when it touches `site`.
    pub fn touching(&self, site: &Site) -> Point2<f64> {
        site.point + site.normal * self.pusher_radius
    }

    /// The pusher's direction for a push at `site` turned `angle` from the inward normal.
    pub fn push_direction(site: &Site, angle: f64) -> Vector2<f64> {
        rotate(-site.normal, angle)
    }

    /// Where a push at `site` in `direction` starts: before touching, along the direction.
    pub fn approach(&self, site: &Site, direction: Vector2<f64>) -> Point2<f64> {
        self.touching(site) - direction * APPROACH_M
    }

    /// The pusher's way from `from` to `to` clear of the object, written into `path` (cleared
    /// first): straight where a straight move does not touch the object, else out to the way
    /// round, along it the shorter way, and in. Its length, metres.
    pub fn way(&self, from: Point2<f64>, to: Point2<f64>, path: &mut Vec<Point2<f64>>) -> f64 {
        path.clear();
        path.push(from);
        let clear = self
            .outline
            .disc_first_touch(from, to - from, self.pusher_radius + 0.5 * CLEARANCE_M)
            .is_none();
        if !clear && self.ring.len() > 2 {
            let (s0, p0) = self.nearest_on_ring(from);
            let (s1, p1) = self.nearest_on_ring(to);
            path.push(p0);
            let forward = (s1 - s0).rem_euclid(self.ring_length);
            let ring = &self.ring[..self.ring.len() - 1];
            if forward <= self.ring_length - forward {
                let first = ring.partition_point(|(_, s)| *s <= s0);
                for k in 0..ring.len() {
                    let (p, s) = ring[(first + k) % ring.len()];
                    if (s - s0).rem_euclid(self.ring_length) >= forward {
                        break;
                    }
                    path.push(p);
                }
            } else {
                let last = ring.partition_point(|(_, s)| *s < s0);
                for k in 0..ring.len() {
                    let (p, s) = ring[(last + ring.len() - 1 - k) % ring.len()];
                    if (s0 - s).rem_euclid(self.ring_length) >= self.ring_length - forward {
                        break;
                    }
                    path.push(p);
                }
            }
            path.push(p1);
        }
        path.push(to);
        path.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
    }

    /// The point of the way round nearest to `p` and how far along the way round it lies.
    fn nearest_on_ring(&self, p: Point2<f64>) -> (f64, Point2<f64>) {
        let mut best = (f64::INFINITY, 0.0, p);
        for w in self.ring.windows(2) {
            let ((a, sa), (b, _)) = (w[0], w[1]);
            let ab = b - a;
            let t = ((p - a).dot(&ab) / ab.norm_squared().max(1e-18)).clamp(0.0, 1.0);
            let q = a + ab * t;
            let d = (p - q).norm();
            if d < best.0 {
                best = (d, sa + t * ab.norm(), q);
            }
        }
        (best.1 % self.ring_length.max(1e-12), best.2)
    }
}

/// The point `step` metres along `path` (its end if shorter).
pub fn along_path(path: &[Point2<f64>], step: f64) -> Option<Point2<f64>> {
    let mut left = step;
    for w in path.windows(2) {
        let d = (w[1] - w[0]).norm();
        if d >= left && d > 0.0 {
            return Some(w[0] + (w[1] - w[0]) * (left / d));
        }
        left -= d;
    }
    path.last().copied()
}

/// The angle turned from `u` to `v`, counter-clockwise positive.
fn turn(u: Vector2<f64>, v: Vector2<f64>) -> f64 {
    math::atan2(cross(u, v), u.dot(&v))
}

/// Whether the hull edge from vertex `i` to vertex `j` runs along the outline: the outline goes
/// from `i` to `j` counter-clockwise with every vertex between on the edge's line.
fn is_outline_face(vertices: &[Point2<f64>], i: usize, j: usize) -> bool {
    let n = vertices.len();
    let (a, b) = (vertices[i], vertices[j]);
    let length = (b - a).norm();
    let mut k = (i + 1) % n;
    while k != j {
        if (cross(b - a, vertices[k] - a) / length).abs() > 1e-9 {
            return false;
        }
        k = (k + 1) % n;
    }
    true
}

/// The indices of the convex hull's vertices, counter-clockwise (Andrew's monotone chain), in the
/// outline's own order so that a face's outline vertices lie between its ends.
fn convex_hull(vertices: &[Point2<f64>]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..vertices.len()).collect();
    order.sort_by(|&a, &b| {
        (vertices[a].x, vertices[a].y)
            .partial_cmp(&(vertices[b].x, vertices[b].y))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    let mut hull: Vec<usize> = Vec::with_capacity(2 * order.len());
    for pass in 0..2 {
        let floor = hull.len();
        let points: Box<dyn Iterator<Item = &usize>> = if pass == 0 {
            Box::new(order.iter())
        } else {
            Box::new(order.iter().rev())
        };
        for &k in points {
            while hull.len() >= floor + 2 {
                let (o, a) = (
                    vertices[hull[hull.len() - 2]],
                    vertices[hull[hull.len() - 1]],
                );
                if cross(a - o, vertices[k] - o) > 1e-12 {
                    break;
                }
                hull.pop();
            }
            hull.push(k);
        }
        hull.pop();
    }
    // Start where the outline's own order starts, so the hull runs in the outline's direction.
    if let Some(first) = hull
        .iter()
        .enumerate()
        .min_by_key(|(_, k)| **k)
        .map(|(i, _)| i)
    {
        hull.rotate_left(first);
    }
    hull
}

/// A closed polygon about the hull at `radius`: each hull edge moved out along its normal, joined
/// round each corner by an arc in pieces; with the distance along it at each vertex, the first
/// repeated at the end.
fn ring_about(vertices: &[Point2<f64>], hull: &[usize], radius: f64) -> Vec<(Point2<f64>, f64)> {
    let n = hull.len();
    let normal = |k: usize| {
        let (a, b) = (vertices[hull[k % n]], vertices[hull[(k + 1) % n]]);
        let d = (b - a).normalize();
        Vector2::new(d.y, -d.x)
    };
    let mut points = Vec::new();
    for k in 0..n {
        let corner = vertices[hull[k]];
        let (before, after) = (normal(k + n - 1), normal(k));
        let bend = turn(before, after).max(0.0);
        let pieces = (bend / ARC_PIECE_RAD).ceil().max(1.0) as usize;
        for p in 0..=pieces {
            let dir = rotate(before, bend * p as f64 / pieces as f64);
            points.push(corner + dir * radius);
        }
    }
    let mut ring = Vec::with_capacity(points.len() + 1);
    let mut s = 0.0;
    for (k, p) in points.iter().enumerate() {
        if k > 0 {
            s += (p - points[k - 1]).norm();
        }
        ring.push((*p, s));
    }
    if let Some(&first) = points.first() {
        s += (first - points[points.len() - 1]).norm();
        ring.push((first, s));
    }
    ring
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;
    use crate::geometry::PushT;

    #[test]
    fn a_box_has_four_faces_kept_clear_of_its_corners() {
        let outline = Outline::rectangle(0.3, 0.4).unwrap();
        let sites = Sites::new(&outline, 0.05);
        // 2·(0.3 + 0.4) less 2 cm at each end of each face.
        assert!((sites.perimeter() - (1.4 - 8.0 * 0.02)).abs() < 1e-12);
        for k in 0..50 {
            let site = sites.site_at(k as f64 * 0.03).unwrap();
            let b = outline.closest_boundary_point(site.point);
            assert!(b.signed_distance.abs() < 1e-12, "{site:?}");
            assert!((b.normal - site.normal).norm() < 1e-12, "{site:?}");
            let corner_distance = outline
                .vertices()
                .iter()
                .map(|v| (v - site.point).norm())
                .fold(f64::INFINITY, f64::min);
            assert!(corner_distance >= 0.02 - 1e-12, "{site:?}");
        }
    }

    #[test]
    fn the_t_is_pushed_on_its_hull_faces_only() {
        let t = PushT::outline(0.4 / 120.0).unwrap();
        let sites = Sites::new(&t, 0.05);
        for k in 0..40 {
            let site = sites.site_at(k as f64 * sites.perimeter() / 40.0).unwrap();
            // A disc touching there touches nothing else first: the site is on the hull.
            let centre = sites.touching(&site) + site.normal * 1e-6;
            let b = t.closest_boundary_point(centre);
            assert!((b.signed_distance - 0.05).abs() < 1e-5, "{site:?} {b:?}");
        }
    }

    #[test]
    fn the_way_round_does_not_touch_the_object() {
        let outline = Outline::rectangle(0.3, 0.4).unwrap();
        let sites = Sites::new(&outline, 0.1);
        let front = sites.site_at(0.1).unwrap();
        let back = sites.site_at(0.1 + sites.perimeter() / 2.0).unwrap();
        let from = sites.touching(&front);
        let to = sites.approach(&back, -back.normal);
        let mut path = Vec::new();
        let length = sites.way(from, to, &mut path);
        assert!(path.len() > 3, "{path:?}");
        // Walk it in millimetres: never closer than the pusher's radius, but at its start.
        let mut s = 0.005;
        while s < length {
            let p = along_path(&path, s).unwrap();
            let b = outline.closest_boundary_point(p);
            assert!(b.signed_distance >= 0.1 - 1e-9, "at {s} m: {p:?} {b:?}");
            s += 0.001;
        }
        assert!((along_path(&path, length + 1.0).unwrap() - to).norm() < 1e-12);
        // Round the short way: less than half the ring plus the way in and out.
        assert!(length < 0.5 * sites.ring_length + 0.1, "{length}");
    }
}
