"""Replays a recording as a live robot: a Foxglove WebSocket server (the Python foxglove-sdk) that
sends a push's poses at their real rate, for a demo of learning while the robot pushes and for the
guide. Connect with `pushlab live ws://127.0.0.1:8765 --pusher /pusher --object /object --setting
SET/setting.json`, or the app's File → Connect to a live robot….

    live-demo.py SET_FOLDER_OR_CSV [--port 8765] [--speed 1.0] [--loop]
        a native pushlab set (its first CSV, or the CSV given): /pusher and /object as JSON
        PoseStamped messages (the shape rosbridge writes, which pushlab reads), stamped now.
    live-demo.py BAG.mcap|ROSBAG2_FOLDER [--port 8765] [--speed 1.0] [--loop]
        a ROS 2 bag (rosbags reads it): every topic re-sent as the CDR it holds, with its schema,
        at the pace of its log times.

Run it with scripts/live-demo/run, which makes a virtual environment from the pinned requirements.
"""

import argparse
import json
import math
import sys
import time
from pathlib import Path

import foxglove
from foxglove import Channel, Schema


def stamp_of(ns):
    return {"sec": ns // 1_000_000_000, "nanosec": ns % 1_000_000_000}


def pose_json(ns, x, y, yaw):
    return json.dumps({
        "header": {"stamp": stamp_of(ns), "frame_id": "table"},
        "pose": {
            "position": {"x": x, "y": y, "z": 0.0},
            "orientation": {"x": 0.0, "y": 0.0, "z": math.sin(yaw / 2), "w": math.cos(yaw / 2)},
        },
    })


def native_rows(path):
    csv = path if path.is_file() else sorted(path.glob("*.csv"))[0]
    lines = csv.read_text().splitlines()
    header = lines[0].split(",")
    want = ["time", "robot_x", "robot_y", "object_x", "object_y", "object_theta"]
    if header[:6] != want:
        sys.exit(f"{csv}: line 1: expected the columns {','.join(want)}, found {lines[0]}")
    rows = []
    for number, line in enumerate(lines[1:], start=2):
        try:
            rows.append([float(v) for v in line.split(",")[:6]])
        except ValueError:
            sys.exit(f"{csv}: line {number}: not six numbers: {line}")
    return csv, rows


def replay_native(path, context, speed, loop):
    csv, rows = native_rows(path)
    schema = Schema(name="pushlab.PoseStamped", encoding="jsonschema", data=b"{}")
    pusher = Channel("/pusher", schema=schema, message_encoding="json", context=context)
    obj = Channel("/object", schema=schema, message_encoding="json", context=context)
    print(f"sending {csv} ({len(rows)} rows) on /pusher and /object", flush=True)
    while True:
        start_wall, start_t = time.time_ns(), rows[0][0]
        for t, rx, ry, ox, oy, oyaw in rows:
            due = start_wall + int((t - start_t) / speed * 1e9)
            time.sleep(max(0.0, (due - time.time_ns()) * 1e-9))
            now = time.time_ns()
            pusher.log(pose_json(now, rx, ry, 0.0), log_time=now)
            obj.log(pose_json(now, ox, oy, oyaw), log_time=now)
        if not loop:
            return


def replay_bag(path, context, speed, loop):
    from rosbags.highlevel import AnyReader

    with AnyReader([path]) as reader:
        channels = {}
        for c in reader.connections:
            schema = Schema(name=c.msgtype, encoding="ros2msg", data=c.msgdef.data.encode())
            channels[c.id] = Channel(c.topic, schema=schema, message_encoding="cdr", context=context)
        print(f"sending {path}: {', '.join(sorted({c.topic for c in reader.connections}))}", flush=True)
        while True:
            start_wall, first = time.time_ns(), None
            for connection, log_time, raw in reader.messages():
                first = log_time if first is None else first
                due = start_wall + int((log_time - first) / speed)
                time.sleep(max(0.0, (due - time.time_ns()) * 1e-9))
                channels[connection.id].log(bytes(raw), log_time=time.time_ns())
            if not loop:
                return


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("recording", type=Path)
    parser.add_argument("--port", type=int, default=8765)
    parser.add_argument("--speed", type=float, default=1.0)
    parser.add_argument("--loop", action="store_true")
    parser.add_argument("--wait", type=float, default=0.0,
                        help="seconds to wait after starting the server, for a client to connect")
    args = parser.parse_args()
    if not args.recording.exists():
        sys.exit(f"{args.recording}: no such file or folder")
    context = foxglove.Context()
    server = foxglove.start_server(name="pushlab live-demo", port=args.port, context=context)
    print(f"serving on ws://127.0.0.1:{server.port}", flush=True)
    time.sleep(args.wait)
    bag = args.recording.suffix == ".mcap" or (args.recording / "metadata.yaml").exists()
    try:
        (replay_bag if bag else replay_native)(args.recording, context, args.speed, args.loop)
    except KeyboardInterrupt:
        pass
    server.stop()


if __name__ == "__main__":
    main()
