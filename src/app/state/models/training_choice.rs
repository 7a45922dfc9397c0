//! Which recordings the app trains on: those chosen in the Train tab, those its labels put in the
//! offline split (the core's `split_of`, as `pushlab train --split-from-labels`), each with the
//! frames its labels say to skip.

use pushlab_core::experiment::{UsedRecording, split_of};
use pushlab_core::labels::Split;

use crate::app::state::AppState;
use crate::app::state::labels::labeling::LabelTarget;
use crate::app::state::models::training::TrainingChoice;
use crate::app::state::recordings::session::RecordingId;

impl AppState {
    /// The recordings chosen for training that have a sample at the training horizon, with the
    /// frames labelled "skip in training" (bad tracking) from the open labels files:
    /// `pushlab_core::experiment` leaves out every sample touching them, exactly as `pushlab train`
    /// does.
    pub fn training_recordings(&self) -> Vec<UsedRecording> {
        let horizon = self.training.config.horizon;
        self.training
            .chosen
            .iter()
            .filter_map(|&id| self.session.get(id))
            .map(|r| {
                let skip = LabelTarget::of(r)
                    .map(|t| self.labels.frames_to_skip(&t))
                    .unwrap_or_default();
                UsedRecording::new(r.clone(), None, skip)
            })
            .filter(|u| !u.samples(horizon).is_empty())
            .collect()
    }

    pub(in crate::app::state) fn start_training(&mut self) {
        if self.training.is_running() {
            return;
        }
        let recordings = self.training_recordings();
        if recordings.is_empty() {
            self.status = Some("choose at least one recording to train on".to_owned());
            return;
        }
        self.training.start(recordings, Vec::new());
        self.status = Some(format!("training the {} model…", self.training.kind));
    }

    /// The open recordings in the offline split: by their labels file (as open in the app), else by
    /// the `split` their `setting.json` entry names — the core's rule (`split_of`), as in
    /// `pushlab train --split-from-labels`.
    pub(in crate::app::state) fn offline_labelled(&self) -> Vec<RecordingId> {
        self.session
            .recordings()
            .filter(|(_, r)| {
                let labels = LabelTarget::of(r)
                    .and_then(|t| self.labels.document(&t.document))
                    .map(|d| d.set());
                split_of(r, labels) == Some(Split::Offline)
            })
            .map(|(id, _)| id)
            .collect()
    }

    pub(in crate::app::state) fn choose_for_training(&mut self, choice: TrainingChoice) {
        let chosen = &mut self.training.chosen;
        match choice {
            TrainingChoice::All => chosen.extend(self.session.recordings().map(|(id, _)| id)),
            TrainingChoice::None => chosen.clear(),
            TrainingChoice::ShownInBrowser => self.choose_shown_in_browser(),
            TrainingChoice::Set(id, true) if self.session.get(id).is_some() => {
                chosen.insert(id);
            }
            TrainingChoice::Set(id, _) => {
                chosen.remove(&id);
            }
        }
    }

    /// Chooses for training the recordings the browser's filter shows ("hex", "ellip1 online"):
    /// one shape of a dataset, one setting, one split, without ticking each.
    fn choose_shown_in_browser(&mut self) {
        let shown: Vec<RecordingId> = self.browser_rows().iter().map(|row| row.id).collect();
        let filter = self.settings.browser.filter.trim();
        self.status = Some(match (shown.len(), filter.is_empty()) {
            (0, _) => format!("the browser shows no recording under the filter \"{filter}\""),
            (n, true) => format!("chose all {n} recordings (the browser has no filter)"),
            (n, false) => format!("chose the {n} recordings the filter \"{filter}\" shows"),
        });
        self.training.chosen = shown.into_iter().collect();
    }

    /// Chooses for training the recordings in the offline split.
    pub(in crate::app::state) fn choose_offline_labelled(&mut self) {
        let offline = self.offline_labelled();
        self.status = Some(if offline.is_empty() {
            "no open recording is labelled offline; set splits in the Labels tab".to_owned()
        } else {
            format!("chose the {} recordings labelled offline", offline.len())
        });
        self.training.chosen = offline.into_iter().collect();
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::app::state::models::Models;
    use crate::app::state::recordings::browser::BrowserCommand;
    use crate::app::state::{AppState, Command, Persisted, TrainingCommand};

    use super::TrainingChoice;

    fn filter_and_choose(state: &mut AppState, filter: &str) -> Vec<(String, String)> {
        state.apply(Command::Browser(BrowserCommand::SetFilter(filter.into())));
        state.apply(Command::Training(TrainingCommand::Choose(
            TrainingChoice::ShownInBrowser,
        )));
        let mut chosen: Vec<(String, String)> = (state.training.chosen.iter())
            .map(|&id| {
                let set = &state.session.sets[id.set].setting.name;
                (
                    set.clone(),
                    state.session.get(id).expect("open").name.clone(),
                )
            })
            .collect();
        chosen.sort();
        chosen
    }

    #[test]
    fn the_browser_filter_chooses_what_it_shows_in_place_of_the_choice() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("sample-data");
        let mut state = AppState::new(Persisted::default(), Models::default());
        state.open_blocking(&[dir]);
        state.apply(Command::Training(TrainingCommand::Choose(
            TrainingChoice::All,
        )));

        let chosen = filter_and_choose(&mut state, "online box2");
        // Three box2 settings with nine online pushes each, and nothing else.
        assert_eq!(chosen.len(), 27, "{chosen:?}");
        assert!(
            (chosen.iter())
                .all(|(set, name)| set.starts_with("box2") && name.starts_with("online_"))
        );
        assert_eq!(
            state.status.as_deref(),
            Some("chose the 27 recordings the filter \"online box2\" shows")
        );

        assert!(filter_and_choose(&mut state, "no-such-push").is_empty());
        assert_eq!(
            state.status.as_deref(),
            Some("the browser shows no recording under the filter \"no-such-push\"")
        );

        assert_eq!(filter_and_choose(&mut state, " ").len(), 324);
        assert_eq!(
            state.status.as_deref(),
            Some("chose all 324 recordings (the browser has no filter)")
        );
    }
}
