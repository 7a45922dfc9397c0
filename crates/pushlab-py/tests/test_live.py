"""`pushlab live` against the Foxglove Python SDK (foxglove-sdk from PyPI, pinned in
requirements-test.txt): a robot written as a Python user writes one, its pusher a JSON channel of
dicts and its object the SDK's typed `PoseInFrameChannel` (protobuf). The CLI must learn θ as the
push arrives, record every message, and the recording imported at the same rate must give `pushlab
eval` the θ the session ended with, to the bit."""

import json
import math
import subprocess
import time

import foxglove
from foxglove.channels import PoseInFrameChannel
from foxglove.messages import Pose, PoseInFrame, Quaternion, Timestamp, Vector3

from conftest import REPO, SAMPLE, run_cli

PUSH = SAMPLE / "box1-paper-ur-front" / "online_000.csv"
SETTING = SAMPLE / "box1-paper-ur-front" / "setting.json"
BASE_NS = 1_700_000_000_000_000_000


def rows():
    lines = PUSH.read_text().splitlines()[1:]
    return [[float(v) for v in line.split(",")] for line in lines]


def stamp(ns):
    return {"sec": ns // 1_000_000_000, "nanosec": ns % 1_000_000_000}


def test_live_learns_from_the_python_sdks_server_as_eval_learns_its_recording(cli, tmp_path):
    context = foxglove.Context()
    server = foxglove.start_server(name="python robot", host="127.0.0.1", port=0, context=context)
    pusher = foxglove.Channel("/pusher", context=context)
    obj = PoseInFrameChannel("/object", context=context)
    url = f"ws://127.0.0.1:{server.port}"
    out = tmp_path / "push.mcap"
    live = subprocess.Popen(
        [str(cli), "live", url, "--pusher", "/pusher", "--object", "/object",
         "--setting", str(SETTING), "--record", str(out), "--duration", "4", "--json"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )
    try:
        deadline = time.monotonic() + 15
        while not (pusher.has_sinks() and obj.has_sinks()):
            assert time.monotonic() < deadline and live.poll() is None, live.communicate()
            time.sleep(0.01)
        for t, rx, ry, ox, oy, yaw in rows():
            ns = BASE_NS + round(t * 1e9)
            pusher.log(
                {"header": {"stamp": stamp(ns)},
                 "pose": {"position": {"x": rx, "y": ry, "z": 0},
                          "orientation": {"x": 0, "y": 0, "z": 0, "w": 1}}},
                log_time=ns,
            )
            late = ns + 3_000_000
            obj.log(
                PoseInFrame(
                    timestamp=Timestamp(sec=late // 1_000_000_000, nsec=late % 1_000_000_000),
                    frame_id="table",
                    pose=Pose(position=Vector3(x=ox, y=oy, z=0),
                              orientation=Quaternion(x=0, y=0, z=math.sin(yaw / 2),
                                                     w=math.cos(yaw / 2))),
                ),
                log_time=late,
            )
            time.sleep(0.002)
        stdout, stderr = live.communicate(timeout=30)
    finally:
        if live.poll() is None:
            live.kill()
        server.stop()
    assert live.returncode == 0, f"{stdout}\n{stderr}"
    assert f"connected to {url} (python robot, foxglove.sdk.v1): 2 channel(s)" in stdout, stdout
    last = json.loads([line for line in stdout.splitlines() if line.startswith("{")][-1])
    learning = last["learning"]
    frontier = learning["frontier"]
    assert frontier > 80, learning
    assert learning["refused"] == {"out_of_order": [0, 0], "bad_value": [0, 0]}
    assert last["object"]["stamp_ns"] == BASE_NS + round(rows()[-1][0] * 1e9) + 3_000_000

    # The recording: both topics readable, the protobuf one by its schema name.
    listing = run_cli(cli, "validate", str(out)).stdout
    assert "/object foxglove.PoseInFrame, " in listing, listing

    # Imported at the grid's rate and evaluated with the same (default) model: the same θ.
    imported = tmp_path / "set"
    run_cli(cli, "import", str(out), "--pusher", "/pusher", "--object", "/object",
            "--setting", str(SETTING), "--rate", "10", "--out", str(imported))
    report = tmp_path / "eval.json"
    run_cli(cli, "eval", "--model", str(REPO / "assets" / "default-model.json"),
            "--online", str(imported), "--per-frame", "--json", str(report))
    push = json.loads(report.read_text())["trajectories"][0]
    frames = push["frames"]
    assert frontier <= len(frames)
    if frontier < len(frames):
        theta = frames[frontier]["theta"]
    else:
        theta = {"com_offset": push["com_offset_learned"], "h": push["h_learned"]}
    assert learning["theta"] == theta
    assert learning["theta"]["com_offset"] != frames[0]["theta"]["com_offset"], "θ was learned"
