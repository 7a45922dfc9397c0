//! How `train` and `eval` show which recordings (and frames) they use. Loading and every rule of
//! which recording and sample is used lives in `pushlab_core::experiment`.

use pushlab_core::experiment::{Loaded, UsedRecording};

/// Prints the recordings used, one line per folder, and what was left out.
pub fn print_summary(role: &str, loaded: &Loaded, horizon: usize) {
    let samples: usize = loaded.samples(horizon).iter().map(Vec::len).sum();
    let bad: usize = loaded.used.iter().map(UsedRecording::skipped_frames).sum();
    println!(
        "{role}: {} recording(s), {samples} sample(s) at horizon {horizon}",
        loaded.used.len()
    );
    let mut by_folder: Vec<(String, Vec<String>)> = Vec::new();
    for u in &loaded.used {
        let folder = u
            .recording
            .source
            .parent()
            .map(|p| p.display().to_string())
            .unwrap_or_default();
        let name = u
            .recording
            .source
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| u.recording.name.clone());
        match by_folder.last_mut() {
            Some((f, names)) if *f == folder => names.push(name),
            _ => by_folder.push((folder, vec![name])),
        }
    }
    for (folder, names) in by_folder {
        println!("  {folder}/ ({}): {}", names.len(), names.join(" "));
    }
    if loaded.other_split > 0 {
        println!(
            "  ({} recording(s) with another split left out)",
            loaded.other_split
        );
    }
    if bad > 0 {
        println!("  ({bad} frame(s) labelled bad tracking left out)");
    }
    for s in &loaded.skipped {
        println!("  skipped: {}", s.message());
    }
}
