//! How fast the window draws, shown at the right of the menu bar: frames per second while something
//! moves, and the CPU time the app and egui take per frame. A user playing a long recording can see
//! whether the machine keeps up, and the guide's figures (`docs/src/performance.md`) can be checked
//! in the real window.

/// Weight of the newest frame in the smoothed figures.
const SMOOTHING: f32 = 0.05;

/// Smoothed frame interval and CPU time (view state).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameRate {
    /// Seconds between frames drawn one after the other; `None` until the window animates.
    interval_s: Option<f32>,
    /// CPU seconds per frame (eframe's measure, without the GPU's work); `None` where unknown.
    cpu_s: Option<f32>,
}

impl FrameRate {
    /// Takes one frame in: `interval_s` since the previous frame when the window is animating
    /// (`None` when it idles, where the gap is the user's pause, not the machine's speed), and the
    /// frame's CPU time when known.
    pub fn record(&mut self, interval_s: Option<f32>, cpu_s: Option<f32>) {
        let smooth =
            |old: Option<f32>, new: f32| Some(old.map_or(new, |old| old + SMOOTHING * (new - old)));
        if let Some(interval) = interval_s.filter(|i| i.is_finite() && *i > 0.0) {
            self.interval_s = smooth(self.interval_s, interval);
        }
        if let Some(cpu) = cpu_s.filter(|c| c.is_finite() && *c >= 0.0) {
            self.cpu_s = smooth(self.cpu_s, cpu);
        }
    }

    /// What the menu bar says, e.g. "60 fps · 2.1 ms CPU per frame".
    pub fn text(&self) -> Option<String> {
        let fps = self.interval_s.map(|i| format!("{:.0} fps", 1.0 / i));
        let cpu = self
            .cpu_s
            .map(|c| format!("{:.1} ms CPU per frame", c * 1e3));
        match (fps, cpu) {
            (Some(fps), Some(cpu)) => Some(format!("{fps} · {cpu}")),
            (Some(one), None) | (None, Some(one)) => Some(one),
            (None, None) => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steady_frames_read_as_their_rate_and_idle_gaps_do_not_count() {
        let mut rate = FrameRate::default();
        assert_eq!(rate.text(), None);
        for _ in 0..200 {
            rate.record(Some(1.0 / 60.0), Some(0.002));
        }
        // A five-second pause while idle is not a slow frame.
        rate.record(None, Some(0.002));
        assert_eq!(
            rate.text().as_deref(),
            Some("60 fps · 2.0 ms CPU per frame")
        );
        for _ in 0..200 {
            rate.record(Some(1.0 / 30.0), None);
        }
        assert_eq!(
            rate.text().as_deref(),
            Some("30 fps · 2.0 ms CPU per frame")
        );
    }
}
