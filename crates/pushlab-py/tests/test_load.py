"""pushlab.load: the arrays are the files' values, the setting is setting.json, bad files raise."""

import csv
import json

import numpy as np
import pytest

import pushlab
from conftest import MIT, SET


def csv_columns(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {name: np.array([float(r[name]) for r in rows]) for name in rows[0]}


def test_a_set_loads_every_push_with_the_csv_values():
    recordings = pushlab.load(SET)
    setting = json.loads((SET / "setting.json").read_text())
    assert [r.name for r in recordings] == [t["file"][:-4] for t in setting["trajectories"]]
    for r in recordings:
        columns = csv_columns(SET / f"{r.name}.csv")
        n = len(columns["time"])
        assert len(r) == n
        assert r.times.shape == (n,) and r.robot.shape == (n, 2) and r.object.shape == (n, 3)
        np.testing.assert_array_equal(r.times, columns["time"])
        np.testing.assert_array_equal(r.robot[:, 0], columns["robot_x"])
        np.testing.assert_array_equal(r.robot[:, 1], columns["robot_y"])
        np.testing.assert_array_equal(r.object[:, 0], columns["object_x"])
        np.testing.assert_array_equal(r.object[:, 1], columns["object_y"])
        np.testing.assert_array_equal(r.object[:, 2], columns["object_theta"])


def test_the_setting_is_setting_json():
    r = pushlab.load(SET / "online_003.csv")[0]
    setting = json.loads((SET / "setting.json").read_text())
    assert r.setting["name"] == setting["name"]
    assert r.setting["com_offset"] == setting["com_offset"]
    assert r.setting["h"] == setting["h"]
    assert r.setting["pusher_radius"] == setting["pusher_radius"]
    # The sample sets' labels files hold each push's split and object, no segments.
    labelled = json.loads((SET / "pushlab-labels.json").read_text())["recordings"]["online_003.csv"]
    assert r.meta == labelled["meta"] and r.meta["split"] == "online"
    assert r.labels == {} and r.events == []
    assert not r.skip.any() and r.skip.shape == (len(r),)


def test_without_a_labels_file_there_are_no_labels(set_copy):
    (set_copy / "pushlab-labels.json").unlink()
    r = pushlab.load(set_copy / "online_003.csv")[0]
    assert r.labels is None and r.meta == {} and r.events == []


def test_several_paths_load_together():
    recordings = pushlab.load([SET / "online_000.csv", str(SET / "online_001.csv")])
    assert [r.name for r in recordings] == ["online_000", "online_001"]


def test_a_bad_number_raises_with_the_file_and_line(set_copy):
    path = set_copy / "online_002.csv"
    lines = path.read_text().splitlines()
    lines[5] = lines[5].replace(",", ",x", 1)
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(pushlab.PushlabError) as raised:
        pushlab.load(set_copy)
    assert str(path) in str(raised.value)
    assert "line 6" in str(raised.value)


def test_a_missing_path_raises_naming_it(tmp_path):
    missing = tmp_path / "nowhere"
    with pytest.raises(pushlab.PushlabError, match="nowhere"):
        pushlab.load(missing)


def test_a_broken_labels_file_raises_naming_it(set_copy):
    (set_copy / "pushlab-labels.json").write_text("{ not json")
    with pytest.raises(pushlab.PushlabError) as raised:
        pushlab.load(set_copy)
    assert "pushlab-labels.json" in str(raised.value)


@pytest.mark.skipif(not MIT.is_dir(), reason=f"{MIT} absent: the MIT Push Dataset files are not here")
def test_mit_files_load_through_the_same_loader():
    recordings = pushlab.load(MIT)
    assert len(recordings) == 4
    for r in recordings:
        assert len(r) > 10
        assert np.isfinite(r.object).all() and np.isfinite(r.robot).all()
        assert np.all(np.diff(r.times) > 0)
        assert r.setting["object"]
    # rect1 lost a pose row (a warning); its force sensor, which pushlab does not read, is frozen
    # (a note).
    rect1 = next(r for r in recordings if "shape=rect1" in r.name)
    assert rect1.warnings == [
        "object_pose: 1 timestamp(s) step backwards (worst -0.1 ms); 1 row(s) out of order dropped"
    ]
    assert len(rect1.notes) == 1 and rect1.notes[0].startswith("ft_wrench is frozen: 287 of 293 rows")
