"""pushlab.simulate: sets with a known COM and h, in memory or written and read back."""

import numpy as np
import pytest

import pushlab

SPEC = {
    "name": "py-box",
    "object": {"shape": "box", "width": 0.3, "length": 0.4},
    "com_offset": [0.03, -0.02],
    "pressure": "uniform",
    "pusher_friction": 0.3,
    "pusher_radius": 0.05,
    "push_side": "front",
    "sample_rate_hz": 10.0,
    "duration_s": 4.0,
    "speed": 0.05,
    "approach": 0.01,
    "noise": {"position_m": 0.0, "yaw_deg": 0.0},
    "seed": 7,
    "pushes": [
        {"contact_offset": 0.0, "push_angle_deg": 0.0},
        {"contact_offset": 0.05, "push_angle_deg": 10.0},
    ],
}


def test_a_simulated_set_knows_its_truth():
    recordings = pushlab.simulate(SPEC)
    assert len(recordings) == 2
    for r in recordings:
        assert r.setting["com_offset"] == [0.03, -0.02]
        assert r.setting["h"] > 0
        assert len(r) == 41
        # The pusher moves at the commanded speed, and pushes the box along +x (the front face).
        assert r.object[-1, 0] > r.object[0, 0]


def test_written_sets_load_back_equal(tmp_path):
    in_memory = pushlab.simulate(SPEC)
    written = pushlab.simulate(SPEC, out=tmp_path / "py-box", truth_labels=True)
    assert (tmp_path / "py-box" / "setting.json").is_file()
    assert (tmp_path / "py-box" / "truth-labels.json").is_file()
    for a, b in zip(in_memory, written):
        assert a.name == b.name
        np.testing.assert_array_equal(a.times, b.times)
        np.testing.assert_array_equal(a.robot, b.robot)
        np.testing.assert_array_equal(a.object, b.object)
    reloaded = pushlab.load(tmp_path / "py-box")
    np.testing.assert_array_equal(reloaded[1].object, written[1].object)
    with pytest.raises(pushlab.PushlabError, match="already holds a recording set"):
        pushlab.simulate(SPEC, out=tmp_path / "py-box")


def test_a_bad_spec_names_the_field():
    with pytest.raises(pushlab.PushlabError, match="spec: missing field `seed`"):
        pushlab.simulate({k: v for k, v in SPEC.items() if k != "seed"})
