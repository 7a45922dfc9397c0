//! How `pushlab live`'s line of a second shows one followed stream: its latest pose and how late it
//! arrived, as text or JSON.

use pushlab_core::live::Followed;
use serde_json::json;

pub(super) fn text(followed: &Followed) -> String {
    match followed.latest() {
        Some(p) => {
            format!(
                "{} ({:.3}, {:.3}) m {:.1}°{}",
                followed.role(),
                p.x,
                p.y,
                p.yaw.to_degrees(),
                followed
                    .lag()
                    .map(|l| match l.wall_clock {
                        true => format!(" {:.0} ms late", l.seconds * 1e3),
                        false => format!(
                            " {:.0} ms later than its first (its stamps are not wall-clock time)",
                            l.seconds * 1e3
                        ),
                    })
                    .unwrap_or_default()
            ) + &dropped(followed)
        }
        None => format!("{} -{}", followed.role(), dropped(followed)),
    }
}

/// A TF chain's poses that could not be composed (a link not published at their time), if any.
fn dropped(followed: &Followed) -> String {
    match followed.dropped() {
        0 => String::new(),
        n => format!(" ({n} pose(s) dropped: a link of its TF chain not published then)"),
    }
}

pub(super) fn json(followed: &Followed) -> serde_json::Value {
    match followed.latest() {
        Some(p) => json!({"stamp_ns": p.stamp_ns, "x": p.x, "y": p.y, "yaw": p.yaw,
                          "lag_s": followed.lag().map(|l| l.seconds),
                          "stamps_wall_clock": followed.lag().map(|l| l.wall_clock),
                          "unreadable": followed.unreadable(),
                          "dropped": followed.dropped()}),
        None => serde_json::Value::Null,
    }
}
