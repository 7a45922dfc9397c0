//! A link that holds the lesson: what is shown, as a page address's query, and back.
//!
//! Why: a teacher shares one moment of a demo — this push, this frame, this θ — as TensorFlow
//! Playground shares its setup, by a link. [`Link::of`] reads it off the state (the page writes it
//! into the address bar as it changes); [`Link::parse`] reads an address's query and [`Steps`] turns
//! it back into the state's own commands, in the order that reproduces the same numbers: the demo
//! or recording first, then the settings, then (once loading and training are done) the seek with
//! learning on, then θ only if the link's differs from what learning gave.
//!
//! Query: `demo`, `rec` (folder/name), `frame`, `learned` (how many frames learning had passed,
//! when past the frame shown: the page seeks there first, then back), `theta` (x,y,h in metres), `opt` (gd or
//! gauss-newton), `lr`, `speed`, `learn` (0/1), `layers` (the layers that differ from the default,
//! `name` on or `-name` off), `present` (the presentation layout), `projector` (high contrast,
//! larger text), `light` (the light theme) and `hide` (controls hidden in a classroom: `browser`, `tools`, `timeline`, `menu`).
//! Push it yourself: `sandbox` (the mystery's seed), `object` (box, t or ellipse), `challenge`
//! (the model's estimate hidden until reveal) and `com` (a teacher's hidden COM offset, x,y in
//! metres, in place of the seed's): the whole class gets the same mystery; the pushes a student
//! makes are theirs and are not in the link.

use pushlab_core::learn::Optimizer;
use pushlab_core::model::OnlineParams;
use pushlab_core::sandbox::MysteryObject;

use super::state::demos::demo::DemoCommand;
use super::state::playback::layers::Layers;
use super::state::playback::timeline::TimelineCommand;
use super::state::sources::sandbox::SandboxCommand;
use super::state::{AppState, Command, OnlineCommand, SessionCommand};

/// Controls a classroom link may hide.
pub const HIDEABLE: [&str; 4] = ["browser", "tools", "timeline", "menu"];

/// What a link holds; `None` (or empty) is "as the app starts".
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Link {
    pub demo: Option<String>,
    pub recording: Option<String>,
    pub frame: Option<usize>,
    /// Frames learned, when more than `frame` (the run went past the frame shown and back).
    pub learned: Option<usize>,
    pub theta: Option<[f64; 3]>,
    pub optimizer: Option<Optimizer>,
    pub lr: Option<f64>,
    pub speed: Option<f64>,
    pub learn: Option<bool>,
    /// Layers that differ from the default: (name, on).
    pub layers: Vec<(String, bool)>,
    pub present: bool,
    pub projector: bool,
    pub light: bool,
    pub hide: Vec<String>,
    /// Push it yourself: the mystery's seed and object, challenge mode, a teacher's COM.
    pub sandbox: Option<u64>,
    pub object: Option<String>,
    pub challenge: bool,
    pub com: Option<[f64; 2]>,
}

/// The view's part of a link, which the state does not hold.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ViewPart {
    pub present: bool,
    pub projector: bool,
    pub light: bool,
    pub hide: Vec<String>,
}

fn layer_values(layers: &Layers) -> Vec<(String, bool)> {
    match serde_json::to_value(layers) {
        Ok(serde_json::Value::Object(map)) => map
            .into_iter()
            .filter_map(|(k, v)| Some((k, v.as_bool()?)))
            .collect(),
        _ => Vec::new(),
    }
}

impl Link {
    /// What `state` shows, with the view's part.
    pub fn of(state: &AppState, view: &ViewPart) -> Self {
        let defaults = layer_values(&Layers::default());
        let layers = layer_values(&state.settings().layers)
            .into_iter()
            .filter(|l| !defaults.contains(l))
            .collect();
        let config = state.settings().online;
        // The view's part and the layers: in every link.
        let view_part = Self {
            layers,
            present: view.present,
            projector: view.projector,
            light: view.light,
            hide: view.hide.clone(),
            ..Self::default()
        };
        // A sandbox's link is its mystery: its pushes are the student's, not the link's. (A
        // recording's outline has no name a link can give, so it links as a recording would.)
        let mystery = (state.sandbox())
            .filter(|_| state.sandbox_shown())
            .filter(|s| !matches!(s.sandbox().mystery().object, MysteryObject::Outline { .. }));
        if let Some(session) = mystery {
            let m = session.sandbox().mystery();
            return Self {
                sandbox: Some(m.seed),
                object: Some(m.object.name().to_owned()),
                challenge: session.challenge(),
                // A teacher's COM is in the link; the seed's own is not (the seed gives it).
                com: session.teachers_com(),
                ..view_part
            };
        }
        Self {
            demo: state.demos().active.as_ref().map(|d| d.name.clone()),
            recording: state.recording().map(super::hook::display_name),
            frame: state.recording().map(|_| state.frame()),
            learned: state
                .run()
                .map(|r| r.frontier())
                .filter(|&f| f > state.frame()),
            theta: state.theta().map(super::hook::theta_array),
            optimizer: Some(config.optimizer),
            lr: Some(config.lr),
            speed: Some(state.timeline().speed),
            learn: Some(state.settings().learn_while_playing),
            ..view_part
        }
    }

    /// The query, without `?`.
    pub fn to_query(&self) -> String {
        let mut parts: Vec<(&str, String)> = Vec::new();
        if let Some(demo) = &self.demo {
            parts.push(("demo", demo.clone()));
        }
        if let Some(recording) = &self.recording {
            parts.push(("rec", recording.clone()));
        }
        if let Some(frame) = self.frame {
            parts.push(("frame", frame.to_string()));
        }
        if let Some(learned) = self.learned {
            parts.push(("learned", learned.to_string()));
        }
        if let Some([x, y, h]) = self.theta {
            // Rust prints the shortest text that reads back as the same f64.
            parts.push(("theta", format!("{x},{y},{h}")));
        }
        if let Some(optimizer) = self.optimizer {
            parts.push(("opt", optimizer.name().to_owned()));
        }
        if let Some(lr) = self.lr {
            parts.push(("lr", lr.to_string()));
        }
        if let Some(speed) = self.speed {
            parts.push(("speed", speed.to_string()));
        }
        if let Some(learn) = self.learn {
            parts.push(("learn", u8::from(learn).to_string()));
        }
        if !self.layers.is_empty() {
            let layers: Vec<String> = (self.layers.iter())
                .map(|(name, on)| {
                    if *on {
                        name.clone()
                    } else {
                        format!("-{name}")
                    }
                })
                .collect();
            parts.push(("layers", layers.join(",")));
        }
        if self.present {
            parts.push(("present", "1".to_owned()));
        }
        if self.projector {
            parts.push(("projector", "1".to_owned()));
        }
        if self.light {
            parts.push(("light", "1".to_owned()));
        }
        if !self.hide.is_empty() {
            parts.push(("hide", self.hide.join(",")));
        }
        if let Some(seed) = self.sandbox {
            parts.push(("sandbox", seed.to_string()));
        }
        if let Some(object) = &self.object {
            parts.push(("object", object.clone()));
        }
        if self.challenge {
            parts.push(("challenge", "1".to_owned()));
        }
        if let Some([x, y]) = self.com {
            parts.push(("com", format!("{x},{y}")));
        }
        parts
            .into_iter()
            .map(|(k, v)| format!("{k}={}", encode(&v)))
            .collect::<Vec<_>>()
            .join("&")
    }

    /// Reads a query (with or without `?`); `url` (recordings by address) is the page's and is
    /// skipped here. A value that does not parse is refused naming the field and what was expected.
    pub fn parse(query: &str) -> Result<Self, String> {
        let mut link = Self::default();
        let query = query.strip_prefix('?').unwrap_or(query);
        for pair in query.split('&').filter(|p| !p.is_empty()) {
            let (key, value) = pair.split_once('=').unwrap_or((pair, ""));
            let value = decode(value);
            let bad = |expected: &str| format!("link: {key}={value:?}: expected {expected}");
            let flag = |v: &str| match v {
                "1" | "true" => Ok(true),
                "0" | "false" => Ok(false),
                _ => Err(bad("1 or 0")),
            };
            match key {
                "demo" => link.demo = Some(value.clone()),
                "rec" => link.recording = Some(value.clone()),
                "frame" => link.frame = Some(value.parse().map_err(|_| bad("a frame number"))?),
                "learned" => {
                    link.learned = Some(value.parse().map_err(|_| bad("a frame count"))?);
                }
                "theta" => {
                    let numbers: Result<Vec<f64>, _> =
                        value.split(',').map(|v| v.trim().parse::<f64>()).collect();
                    match numbers.as_deref() {
                        Ok(&[x, y, h]) if [x, y, h].iter().all(|v| v.is_finite()) && h > 0.0 => {
                            link.theta = Some([x, y, h]);
                        }
                        _ => return Err(bad("x,y,h in metres, finite, h > 0")),
                    }
                }
                "opt" => {
                    link.optimizer = Some(
                        Optimizer::from_name(&value).ok_or_else(|| bad("gd or gauss-newton"))?,
                    );
                }
                "lr" => link.lr = Some(positive(&value).ok_or_else(|| bad("a rate > 0"))?),
                "speed" => link.speed = Some(positive(&value).ok_or_else(|| bad("a speed > 0"))?),
                "learn" => link.learn = Some(flag(&value)?),
                "layers" => {
                    let known = layer_values(&Layers::default());
                    for name in value.split(',').filter(|n| !n.is_empty()) {
                        let (name, on) = match name.strip_prefix('-') {
                            Some(off) => (off, false),
                            None => (name, true),
                        };
                        if !known.iter().any(|(k, _)| k == name) {
                            let names: Vec<&str> = known.iter().map(|(k, _)| k.as_str()).collect();
                            return Err(bad(&format!("layer names among {}", names.join(", "))));
                        }
                        link.layers.push((name.to_owned(), on));
                    }
                }
                "present" => link.present = flag(&value)?,
                "projector" => link.projector = flag(&value)?,
                "light" => link.light = flag(&value)?,
                "hide" => {
                    for name in value.split(',').filter(|n| !n.is_empty()) {
                        if !HIDEABLE.contains(&name) {
                            return Err(bad(&format!("controls among {}", HIDEABLE.join(", "))));
                        }
                        link.hide.push(name.to_owned());
                    }
                }
                "sandbox" => {
                    link.sandbox = Some(value.parse().map_err(|_| bad("a seed, 0 or more"))?)
                }
                "object" => {
                    value
                        .parse::<MysteryObject>()
                        .map_err(|_| bad("box, t or ellipse"))?;
                    link.object = Some(value.clone());
                }
                "challenge" => link.challenge = flag(&value)?,
                "com" => {
                    let numbers: Result<Vec<f64>, _> =
                        value.split(',').map(|v| v.trim().parse::<f64>()).collect();
                    match numbers.as_deref() {
                        Ok(&[x, y]) if x.is_finite() && y.is_finite() => link.com = Some([x, y]),
                        _ => return Err(bad("x,y in metres")),
                    }
                }
                "url" => {}
                _ => return Err(format!("link: unknown field {key:?}")),
            }
        }
        Ok(link)
    }

    /// The view's part.
    pub fn view(&self) -> ViewPart {
        ViewPart {
            present: self.present,
            projector: self.projector,
            light: self.light,
            hide: self.hide.clone(),
        }
    }

    /// The steps that reproduce it, in order.
    pub fn steps(&self) -> Steps {
        Steps {
            link: self.clone(),
            stage: 0,
        }
    }
}

fn positive(text: &str) -> Option<f64> {
    text.parse::<f64>()
        .ok()
        .filter(|v| v.is_finite() && *v > 0.0)
}

/// A link being applied: [`Steps::next`] gives each stage's commands once the state is ready
/// for it (nothing running off the UI thread), so a demo's training ends before the seek learns.
#[derive(Clone, Debug)]
pub struct Steps {
    link: Link,
    stage: u8,
}

impl Steps {
    /// The next stage's commands, `Some(vec![])` while waiting, `None` when done; an error names
    /// what the link asked for that is not there.
    pub fn next(&mut self, state: &AppState) -> Option<Result<Vec<Command>, String>> {
        if state.is_busy() {
            // Waiting, while a stage is left (the seek's learning ahead may still run before θ).
            return (self.stage <= 3).then(|| Ok(Vec::new()));
        }
        let link = &self.link;
        let stage = self.stage;
        self.stage += 1;
        match stage {
            0 => Some(self.select(state)),
            1 => {
                let mut commands = Vec::new();
                let mut config = state.settings().online;
                config.optimizer = link.optimizer.unwrap_or(config.optimizer);
                config.lr = link.lr.unwrap_or(config.lr);
                if config != state.settings().online {
                    commands.push(Command::Online(OnlineCommand::SetConfig(config)));
                }
                if let Some(speed) = link.speed {
                    commands.push(Command::Timeline(TimelineCommand::SetSpeed(speed)));
                }
                if let Some(learn) = link.learn {
                    commands.push(Command::Online(OnlineCommand::SetLearnWhilePlaying(learn)));
                }
                if !link.layers.is_empty() {
                    commands.push(Command::SetLayers(with_layers(
                        &state.settings().layers,
                        &link.layers,
                    )));
                }
                Some(Ok(commands))
            }
            2 => Some(Ok(link
                .learned
                .into_iter()
                .chain(link.frame)
                .map(|f| Command::Timeline(TimelineCommand::SeekTo(f)))
                .collect())),
            3 => {
                let now = state.theta().map(super::hook::theta_array);
                Some(Ok(match link.theta {
                    Some([x, y, h]) if now != Some([x, y, h]) => {
                        vec![Command::Online(OnlineCommand::SetTheta(OnlineParams {
                            com_offset: [x, y],
                            h,
                        }))]
                    }
                    _ => Vec::new(),
                }))
            }
            _ => None,
        }
    }

    fn select(&self, state: &AppState) -> Result<Vec<Command>, String> {
        let mut commands = Vec::new();
        if self.link.sandbox.is_some() || self.link.object.is_some() {
            let object = match &self.link.object {
                Some(name) => name.parse::<MysteryObject>()?,
                None => MysteryObject::Box,
            };
            commands.push(Command::Sandbox(SandboxCommand::Start {
                seed: self.link.sandbox.unwrap_or(0),
                object: Some(object),
                noise: false,
                challenge: self.link.challenge,
                com: self.link.com,
            }));
        }
        if let Some(name) = &self.link.demo {
            let names = state.demos().names();
            let index = (names.iter().position(|n| n == name))
                .ok_or_else(|| format!("link: no demo named {name:?}"))?;
            commands.push(Command::Demo(DemoCommand::Start(index)));
        }
        if let Some(wanted) = &self.link.recording {
            let id = (state.session().recordings())
                .find(|(_, r)| super::hook::display_name(r) == *wanted)
                .map(|(id, _)| id)
                .ok_or_else(|| format!("link: no open recording {wanted:?}"))?;
            let shown = state.recording().map(super::hook::display_name);
            if shown.as_deref() != Some(wanted.as_str()) {
                commands.push(Command::Session(SessionCommand::Select(id)));
            }
        }
        Ok(commands)
    }
}

fn with_layers(layers: &Layers, changes: &[(String, bool)]) -> Layers {
    let Ok(serde_json::Value::Object(mut map)) = serde_json::to_value(layers) else {
        return layers.clone();
    };
    for (name, on) in changes {
        map.insert(name.clone(), serde_json::Value::Bool(*on));
    }
    serde_json::from_value(serde_json::Value::Object(map)).unwrap_or_else(|_| layers.clone())
}

/// Percent-encodes all but unreserved characters and `,` `/` (kept readable).
fn encode(text: &str) -> String {
    let mut out = String::new();
    for byte in text.bytes() {
        match byte {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'-' | b'_' | b'.' | b'~' | b',' | b'/' => {
                out.push(byte as char);
            }
            _ => out.push_str(&format!("%{byte:02X}")),
        }
    }
    out
}

/// Reads `%XX` and `+` (a space), as a query writes them.
fn decode(text: &str) -> String {
    percent_decode(text, true)
}

/// Reads `%XX` (and `+` as a space when `plus_is_space`: a query's, not a path's).
pub fn percent_decode(text: &str, plus_is_space: bool) -> String {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'%' if i + 2 < bytes.len() => {
                let hex = std::str::from_utf8(&bytes[i + 1..i + 3]).unwrap_or("");
                match u8::from_str_radix(hex, 16) {
                    Ok(b) => {
                        out.push(b);
                        i += 3;
                        continue;
                    }
                    Err(_) => out.push(b'%'),
                }
            }
            b'+' if plus_is_space => out.push(b' '),
            b => out.push(b),
        }
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

#[cfg(test)]
mod tests;
