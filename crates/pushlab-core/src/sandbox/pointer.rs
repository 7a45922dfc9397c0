//! Where a student's pointer went, and the one rule by which the pusher follows it: each frame the
//! pusher heads for the pointer's position at that frame's time, at most the pusher's speed × the
//! frame's interval away. The sandbox drags by it as the pointer moves, `pushlab simulate
//! --pointer-path` replays a path by it, so both make the same pusher path, frame for frame.
//!
//! A pointer path is a CSV of `t,x,y` rows (seconds from the push's start, world metres), times
//! increasing; between two rows the pointer moves in a straight line, before the first it is at
//! the first, after the last at the last.

use std::path::Path;

use nalgebra::{Point2, Vector2};

/// A pointer's path over a push (see the module documentation).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointerPath {
    /// `(t, position)`, times increasing.
    points: Vec<(f64, Point2<f64>)>,
}

/// Why a pointer path cannot be used, naming the row and what was expected.
#[derive(Debug, thiserror::Error)]
pub enum PointerPathError {
    #[error("{path}: {error}")]
    Read { path: String, error: String },
    #[error("{path}: the header is '{found}', expected 't,x,y'")]
    Header { path: String, found: String },
    #[error("{path} line {line}: {field} is '{value}', expected a finite number")]
    NotANumber {
        path: String,
        line: usize,
        field: &'static str,
        value: String,
    },
    #[error("{path} line {line}: t {t} is not after the row before's {before}")]
    NotIncreasing {
        path: String,
        line: usize,
        t: f64,
        before: f64,
    },
    #[error("{path}: no rows: a pointer path needs at least one point")]
    Empty { path: String },
}

impl PointerPath {
    /// A path through `points` (`[x, y, t]`, as the page's hook takes a drag), times increasing.
    pub fn from_points(points: &[[f64; 3]]) -> Result<Self, PointerPathError> {
        let mut path = Self::default();
        for (k, &[x, y, t]) in points.iter().enumerate() {
            path.add(t, Point2::new(x, y), "the drag", k + 1)?;
        }
        if path.points.is_empty() {
            return Err(PointerPathError::Empty {
                path: "the drag".into(),
            });
        }
        Ok(path)
    }

    fn add(
        &mut self,
        t: f64,
        at: Point2<f64>,
        source: &str,
        line: usize,
    ) -> Result<(), PointerPathError> {
        for (field, value) in [("t", t), ("x", at.x), ("y", at.y)] {
            if !value.is_finite() {
                return Err(PointerPathError::NotANumber {
                    path: source.to_owned(),
                    line,
                    field,
                    value: value.to_string(),
                });
            }
        }
        if let Some(&(before, _)) = self.points.last()
            && t <= before
        {
            return Err(PointerPathError::NotIncreasing {
                path: source.to_owned(),
                line,
                t,
                before,
            });
        }
        self.points.push((t, at));
        Ok(())
    }

    /// Reads a `t,x,y` CSV file.
    pub fn read(file: &Path) -> Result<Self, PointerPathError> {
        let name = file.display().to_string();
        let text = crate::files::read_to_string(file).map_err(|e| PointerPathError::Read {
            path: name.clone(),
            error: e.to_string(),
        })?;
        Self::parse(&text, &name)
    }

    /// Parses a `t,x,y` CSV text; `name` names it in errors.
    pub fn parse(text: &str, name: &str) -> Result<Self, PointerPathError> {
        let mut lines = text.lines().enumerate();
        let header = lines.next().map(|(_, l)| l.trim()).unwrap_or_default();
        if header.replace(' ', "") != "t,x,y" {
            return Err(PointerPathError::Header {
                path: name.to_owned(),
                found: header.to_owned(),
            });
        }
        let mut path = Self::default();
        for (index, line) in lines {
            if line.trim().is_empty() {
                continue;
            }
            let mut values = [0.0; 3];
            let mut fields = line.split(',');
            for (slot, field) in values.iter_mut().zip(["t", "x", "y"]) {
                let text = fields.next().unwrap_or("").trim();
                *slot = text
                    .parse::<f64>()
                    .map_err(|_| PointerPathError::NotANumber {
                        path: name.to_owned(),
                        line: index + 1,
                        field,
                        value: text.to_owned(),
                    })?;
            }
            path.add(
                values[0],
                Point2::new(values[1], values[2]),
                name,
                index + 1,
            )?;
        }
        if path.points.is_empty() {
            return Err(PointerPathError::Empty {
                path: name.to_owned(),
            });
        }
        Ok(path)
    }

    /// The path as `t,x,y` CSV text, every number printed so that it reads back exactly.
    pub fn to_csv(&self) -> String {
        let mut text = String::from("t,x,y\n");
        for (t, p) in &self.points {
            text += &format!("{t},{},{}\n", p.x, p.y);
        }
        text
    }

    /// A path of one point per frame, at the frame times given: the pusher's own path, which
    /// replayed by [`follow`] moves the pusher exactly through it.
    pub fn of_frames(frames: impl IntoIterator<Item = (f64, Point2<f64>)>) -> Self {
        Self {
            points: frames.into_iter().collect(),
        }
    }

    /// The pointer at time `t`.
    pub fn at(&self, t: f64) -> Option<Point2<f64>> {
        let (first, last) = (self.points.first()?, self.points.last()?);
        if t <= first.0 {
            return Some(first.1);
        }
        if t >= last.0 {
            return Some(last.1);
        }
        let next = self.points.partition_point(|(time, _)| *time <= t);
        let ((t0, p0), (t1, p1)) = (self.points[next - 1], self.points[next]);
        if t == t0 {
            return Some(p0);
        }
        Some(p0 + (p1 - p0) * ((t - t0) / (t1 - t0)))
    }

    /// When the path ends, seconds.
    pub fn end(&self) -> f64 {
        self.points.last().map_or(0.0, |&(t, _)| t)
    }

    /// Its points, `(t, position)`.
    pub fn points(&self) -> &[(f64, Point2<f64>)] {
        &self.points
    }
}

/// Where the pusher at `pusher` goes over one frame of `dt` seconds toward `pointer`, at most
/// `speed` m/s: the pointer itself when that is near enough (exactly, so that a path already
/// within the speed is followed to the bit), else that far along the line to it.
pub fn follow(pusher: Point2<f64>, pointer: Point2<f64>, speed: f64, dt: f64) -> Point2<f64> {
    let reach = speed * dt;
    let to: Vector2<f64> = pointer - pusher;
    let distance = to.norm();
    if distance <= reach {
        pointer
    } else {
        pusher + to * (reach / distance)
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    #[test]
    fn the_pointer_moves_in_straight_lines_between_rows() {
        let path = PointerPath::from_points(&[[0.0, 0.0, 0.0], [1.0, 2.0, 2.0]]).unwrap();
        assert_eq!(path.at(-1.0), Some(Point2::new(0.0, 0.0)));
        assert_eq!(path.at(1.0), Some(Point2::new(0.5, 1.0)));
        assert_eq!(path.at(5.0), Some(Point2::new(1.0, 2.0)));
    }

    #[test]
    fn the_pusher_goes_no_faster_than_its_speed() {
        let to = follow(Point2::origin(), Point2::new(1.0, 0.0), 0.04, 0.1);
        assert!((to.x - 0.004).abs() < 1e-15 && to.y == 0.0);
        let near = Point2::new(0.001, 0.002);
        assert_eq!(follow(Point2::origin(), near, 0.04, 0.1), near);
    }

    #[test]
    fn a_bad_row_is_refused_by_line_and_field() {
        let e = PointerPath::parse("t,x,y\n0,0,0\n0.1,nope,0\n", "drag.csv").unwrap_err();
        assert_eq!(
            e.to_string(),
            "drag.csv line 3: x is 'nope', expected a finite number"
        );
        let e = PointerPath::parse("t,x,y\n0.2,0,0\n0.1,0,0\n", "drag.csv").unwrap_err();
        assert_eq!(
            e.to_string(),
            "drag.csv line 3: t 0.1 is not after the row before's 0.2"
        );
        let e = PointerPath::parse("time,x\n", "drag.csv").unwrap_err();
        assert_eq!(
            e.to_string(),
            "drag.csv: the header is 'time,x', expected 't,x,y'"
        );
    }

    #[test]
    fn a_path_written_reads_back_the_same() {
        let path = PointerPath::from_points(&[[0.1, -0.2, 0.0], [0.30000000000000004, 1e-7, 0.1]])
            .unwrap();
        assert_eq!(PointerPath::parse(&path.to_csv(), "x").unwrap(), path);
    }
}
