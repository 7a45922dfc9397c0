"""pushlab.Controller is `pushlab control --pipe`: the same poses give the same targets, to the bit;
bad arguments are refused with their name."""

import json
import subprocess
from pathlib import Path

import pytest

import pushlab

from conftest import REPO

SETTING = {
    "name": "pipe",
    "object": {"shape": "box", "width": 0.3, "length": 0.4},
    "pusher_radius": 0.175,
    "sample_rate_hz": 10.0,
    "trajectories": [],
}
GOAL = (0.25, 0.1, 0.4)


def poses(steps):
    """The pusher walking in to the object's back face and on, the object moving a little: each
    step's time, pusher and object."""
    for k in range(steps):
        pusher = (-0.40 + 0.004 * k, 0.01)
        shift = max(0.0, 0.004 * k - 0.03)
        yield k / 10.0, pusher, (shift, 0.0, 0.02 * shift)


def test_the_controller_gives_the_clis_targets(cli: Path, tmp_path: Path):
    setting = tmp_path / "setting.json"
    setting.write_text(json.dumps(SETTING))
    model = pushlab.Model.load(REPO / "assets" / "default-model.json")
    controller = pushlab.Controller(model, setting, GOAL)
    lines = [json.dumps({"t": t, "pusher": list(p), "object": list(o)}) for t, p, o in poses(30)]
    done = subprocess.run(
        [str(cli), "control", "--pipe", "--setting", str(setting), "--goal", "0.25,0.1,0.4"],
        input="\n".join(lines) + "\n", capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    cli_steps = [json.loads(line)["step"] for line in done.stdout.splitlines()]
    assert len(cli_steps) == 30
    for (t, p, o), expected in zip(poses(30), cli_steps):
        step = controller.step(t, p, o)
        assert step["target"] == expected["target"]
        assert step["phase"] == expected["phase"]
        assert step["theta"] == expected["theta"]
    assert not controller.done
    # A setting given as a dict is the same setting.
    again = pushlab.Controller(model, SETTING, GOAL)
    t, p, o = next(poses(1))
    assert again.step(t, p, o)["target"] == cli_steps[0]["target"]
    assert len(controller.theta) == 3


def noisy_poses(steps):
    """poses() with a few millimetres of tracking noise, fixed, so a filter has something to do."""
    for k, (t, pusher, (x, y, yaw)) in enumerate(poses(steps)):
        wobble = 0.003 * ((k * 7) % 5 - 2) / 2
        yield t, (pusher[0] - wobble, pusher[1] + wobble), (x + wobble, y - wobble, yaw + wobble)


def test_a_filtered_controller_gives_the_clis_filtered_targets(cli: Path, tmp_path: Path):
    setting = tmp_path / "setting.json"
    setting.write_text(json.dumps(SETTING))
    model = pushlab.Model.load(REPO / "assets" / "default-model.json")
    lines = [json.dumps({"t": t, "pusher": list(p), "object": list(o)}) for t, p, o in noisy_poses(30)]

    def cli_targets(*extra):
        done = subprocess.run(
            [str(cli), "control", "--pipe", "--setting", str(setting), "--goal", "0.25,0.1,0.4",
             *extra], input="\n".join(lines) + "\n", capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
        return [json.loads(line)["step"]["target"] for line in done.stdout.splitlines()]

    filtered, raw = cli_targets("--track", "0.5,0.1"), cli_targets()
    assert filtered != raw, "the filter changed no target: the test would not see it ignored"
    controller = pushlab.Controller(model, setting, GOAL, track=(0.5, 0.1))
    ours = [controller.step(t, p, o)["target"] for t, p, o in noisy_poses(30)]
    assert ours == filtered


def sandbox_poses(cli: Path):
    """Poses of a real push: the sandbox's mystery 3 pushed for 8 s by the CLI's controller, each
    step's time, pusher and object (poses() pass through the object, so nothing is learned)."""
    done = subprocess.run([str(cli), "control", "--sandbox", "3", "--goal", "0.25,0.1,0.4",
                           "--json", "--time-limit", "8"], capture_output=True, text=True)
    assert "not reached within 8 s" in done.stderr, done.stderr
    steps = [json.loads(line).get("step", {}) for line in done.stdout.splitlines()]
    return [(s["time_s"], tuple(s["pusher"]), (*s["object"]["position"], s["object"]["yaw"]))
            for s in steps if "pusher" in s]


def test_the_learners_options_the_lookahead_and_the_planner_stream_give_the_clis_targets(cli: Path, tmp_path: Path):
    poses = sandbox_poses(cli)
    assert len(poses) == 80
    setting = tmp_path / "setting.json"
    setting.write_text(json.dumps(SETTING))
    model = pushlab.Model.load(REPO / "assets" / "default-model.json")
    lines = [json.dumps({"t": t, "pusher": list(p), "object": list(o)}) for t, p, o in poses]

    def cli_steps(*extra):
        done = subprocess.run(
            [str(cli), "control", "--pipe", "--setting", str(setting), "--goal", "0.25,0.1,0.4",
             *extra], input="\n".join(lines) + "\n", capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
        return [json.loads(line)["step"] for line in done.stdout.splitlines()]

    def ours(**options):
        controller = pushlab.Controller(model, setting, GOAL, **options)
        return [controller.step(t, p, o) for t, p, o in poses]

    plain = cli_steps()
    learner = cli_steps("--optimizer", "gauss-newton", "--steps", "3", "--lr", "0.01")
    lookahead = cli_steps("--lookahead")
    stream = cli_steps("--planner-seed", "1")
    # Each option changes what the CLI does, so a keyword the package ignored would show.
    assert [s["theta"] for s in learner] != [s["theta"] for s in plain]
    assert [s["target"] for s in lookahead] != [s["target"] for s in plain]
    assert [s["target"] for s in stream] != [s["target"] for s in plain]
    mine = ours(optimizer="gauss-newton", steps=3, lr=0.01)
    assert [(s["target"], s["theta"]) for s in mine] == [(s["target"], s["theta"]) for s in learner]
    mine = ours(lookahead=True)
    assert [s["target"] for s in mine] == [s["target"] for s in lookahead]
    mine = ours(planner_seed=1)
    assert [s["target"] for s in mine] == [s["target"] for s in stream]


def test_bad_arguments_are_refused_by_name():
    model = pushlab.Model.load(REPO / "assets" / "default-model.json")
    with pytest.raises(ValueError, match="theta 'learned': expected online, fixed, physics, truth or weighted"):
        pushlab.Controller(model, SETTING, GOAL, theta="learned")
    with pytest.raises(ValueError, match='optimizer: expected "gd" or "gauss-newton", got "adam"'):
        pushlab.Controller(model, SETTING, GOAL, optimizer="adam")
    with pytest.raises(ValueError, match="speed -1: expected a positive number"):
        pushlab.Controller(model, SETTING, GOAL, speed=-1)
    with pytest.raises(ValueError, match=r"track \(1.5, 0.1\): expected 0 < ALPHA ≤ 1 and 0 ≤ BETA < 1"):
        pushlab.Controller(model, SETTING, GOAL, track=(1.5, 0.1))
    with pytest.raises(ValueError, match="com_offset and h"):
        pushlab.Controller(model, SETTING, GOAL, theta="truth")
    with pytest.raises(Exception, match="setting"):
        pushlab.Controller(model, {"name": "no object"}, GOAL)
