"""pushlab.Labels: edits go through pushlab's labels document and come back unchanged everywhere."""

import json
import re

import numpy as np
import pytest

import pushlab
from conftest import run_cli


def test_edits_saved_from_python_reopen_unchanged(set_copy, cli):
    labels = pushlab.Labels(set_copy)
    assert len(labels.recordings) == 36 and not labels.dirty
    rec = pushlab.load(set_copy / "online_004.csv")[0]
    meta_before = labels.meta(rec)
    assert meta_before["split"] == "online"
    assert labels.paint(rec, "contact", 10, 60)
    assert labels.paint("online_004.csv", "sticking", 12, 40)
    assert labels.paint(rec, "slipping", 40, 58)
    assert labels.paint("online_004.csv", "bad tracking", 70, 74)
    assert labels.add_event(rec, "contact made", 10)
    assert not labels.set_meta(rec, "split", "online")  # already so: nothing changes
    assert labels.set_meta(rec, "com_offset", (0.01, -0.02))
    assert labels.set_meta(rec, "notes", "painted from Python")
    assert labels.dirty
    labels.save()
    assert not labels.dirty

    again = pushlab.Labels(set_copy / "pushlab-labels.json")
    assert again.recordings == labels.recordings
    assert again.segments(rec) == labels.segments(rec) == [
        ("contact", 10, 60),
        ("sticking", 12, 40),
        ("slipping", 40, 58),
        ("bad tracking", 70, 74),
    ]
    assert again.events(rec) == [("contact made", 10)]
    assert again.meta(rec) == {**meta_before, "com_offset": [0.01, -0.02], "notes": "painted from Python"}

    # The loader attaches them to the recording, as training and evaluation use them.
    loaded = pushlab.load(set_copy / "online_004.csv")[0]
    masks = loaded.labels
    assert sorted(masks) == ["bad tracking", "contact", "slipping", "sticking"]
    expected = np.zeros(len(loaded), bool)
    expected[12:40] = True
    np.testing.assert_array_equal(masks["sticking"], expected)
    np.testing.assert_array_equal(again.mask(loaded, "sticking"), expected)
    skip = np.zeros(len(loaded), bool)
    skip[70:74] = True
    np.testing.assert_array_equal(loaded.skip, skip)
    assert loaded.meta["split"] == "online"

    # The CLI reads the same file through the core and exports the same segments.
    out = set_copy.parent / "export.json"
    run_cli(cli, "labels", "export", str(set_copy), "--json", str(out))
    exported = json.loads(out.read_text())
    ranges = [
        (s["label"], s["first_frame"], s["last_frame"] + 1)
        for s in exported["segments"]
        if s["recording"] == "online_004.csv" and s["kind"] == "range"
    ]
    events = [
        (s["label"], s["first_frame"])
        for s in exported["segments"]
        if s["recording"] == "online_004.csv" and s["kind"] == "event"
    ]
    assert sorted(ranges) == sorted(again.segments(rec))
    assert events == again.events(rec)
    assert exported["recordings"]["online_004.csv"] == again.meta(rec)
    # Frame times come from the recording the CLI loaded: the same as Python's.
    sticking = next(s for s in exported["segments"] if s["label"] == "sticking")
    assert sticking["first_time"] == loaded.times[12] and sticking["last_time"] == loaded.times[39]


def test_painting_cuts_the_exclusive_group(set_copy):
    labels = pushlab.Labels(set_copy)
    labels.paint("offline_000.csv", "sticking", 0, 50)
    labels.paint("offline_000.csv", "slipping", 30, 80)
    assert labels.segments("offline_000.csv") == [("sticking", 0, 30), ("slipping", 30, 80)]


def test_refused_edits_raise_the_documents_message(set_copy):
    labels = pushlab.Labels(set_copy)
    with pytest.raises(pushlab.PushlabError, match="unknown label \"wobbling\""):
        labels.paint("offline_000.csv", "wobbling", 0, 5)
    with pytest.raises(pushlab.PushlabError, match="point event"):
        labels.paint("offline_000.csv", "contact made", 0, 5)
    with pytest.raises(pushlab.PushlabError, match="not a split"):
        labels.set_meta("offline_000.csv", "split", "training")
    with pytest.raises(ValueError, match=r"frames 10\.\.0: start is after end"):
        labels.paint("offline_000.csv", "sticking", 10, 0)
    with pytest.raises(ValueError, match=r"frames 10\.\.0: start is after end"):
        labels.erase("offline_000.csv", 10, 0)
    with pytest.raises(pushlab.PushlabError, match="no such set folder"):
        pushlab.Labels(set_copy / "typo")
    # The field that does not fit, not a position in JSON the user never wrote.
    with pytest.raises(pushlab.PushlabError, match=r'^label "wobbling": colour: expected a colour like "#1f77b4", found "blue"$'):
        labels.add_label("wobbling", colour="blue")
    with pytest.raises(pushlab.PushlabError, match=r'^label "wobbling": kind: unknown variant `blob`, expected `range` or `event`$'):
        labels.add_label("wobbling", kind="blob")
    assert not labels.dirty
    assert labels.add_label("wobbling", colour="#112233", group="contact mode")
    assert labels.paint("offline_000.csv", "wobbling", 0, 5)
    labels.rename_label("wobbling", "rocking")
    assert labels.segments("offline_000.csv") == [("rocking", 0, 5)]
    with pytest.raises(pushlab.PushlabError, match="is used 1 times"):
        labels.remove_label("rocking")


def test_a_file_changed_by_another_program_is_not_overwritten(set_copy):
    labels = pushlab.Labels(set_copy)
    labels.paint("offline_000.csv", "contact", 0, 5)
    labels.save()
    other = pushlab.Labels(set_copy)
    other.paint("offline_000.csv", "contact", 20, 25)
    other.save()
    labels.paint("offline_000.csv", "contact", 40, 45)
    with pytest.raises(pushlab.PushlabError, match="changed"):
        labels.save()
    labels.save(overwrite=True)
    assert pushlab.Labels(set_copy).segments("offline_000.csv") == [("contact", 0, 5), ("contact", 40, 45)]


def test_a_broken_labels_file_raises_naming_it(set_copy):
    path = set_copy / "pushlab-labels.json"
    path.write_text('{"format": "pushlab-labels", "version": 1, "recordings": {"offline_000.csv": {"segments": 3}}}')
    with pytest.raises(pushlab.PushlabError) as raised:
        pushlab.Labels(set_copy)
    assert str(path) in str(raised.value)


def test_edits_past_the_end_of_a_recording_are_refused(set_copy):
    labels = pushlab.Labels(set_copy)
    rec = pushlab.load(set_copy / "online_004.csv")[0]
    n = len(rec)
    past = rf"^frames 10\.\.{n + 1}: online_004\.csv has {n} frames, 0\.\.{n} \(end exclusive\)$"
    with pytest.raises(ValueError, match=past):
        labels.paint(rec, "contact", 10, n + 1)
    with pytest.raises(ValueError, match=past):
        labels.erase(rec, 10, n + 1)
    with pytest.raises(ValueError, match=rf"^frame {n}: online_004\.csv has {n} frames, 0 to {n - 1}$"):
        labels.add_event(rec, "contact made", n)
    assert not labels.dirty
    # Up to the last frame is inside.
    assert labels.paint(rec, "contact", n - 5, n)
    assert labels.add_event(rec, "contact made", n - 1)
    assert labels.segments(rec) == [("contact", n - 5, n)]


def test_a_name_that_is_no_recording_of_the_folder_is_refused(set_copy):
    labels = pushlab.Labels(set_copy)
    typo = '^' + re.escape(f'"offline_00.csv": no recording of that name in {set_copy} and none labelled so')
    with pytest.raises(ValueError, match=typo):
        labels.paint("offline_00.csv", "contact", 0, 5)
    with pytest.raises(ValueError, match=typo):
        labels.segments("offline_00.csv")
    # A file of the folder that is not a recording: the setting, the labels, a bag without its push.
    (set_copy / "run1.mcap").write_bytes(b"")
    for name in ["setting.json", "pushlab-labels.json", "run1.mcap"]:
        with pytest.raises(ValueError, match=re.escape(f'"{name}": no recording of that name')):
            labels.paint(name, "contact", 0, 5)
    assert not labels.dirty
    # A push of a bag or dataset in the folder is named after it, '#' and its number.
    assert labels.paint("run1.mcap#002", "contact", 0, 5)
    assert labels.segments("run1.mcap#002") == [("contact", 0, 5)]
