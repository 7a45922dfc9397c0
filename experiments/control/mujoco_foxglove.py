#!/usr/bin/env python3
"""The controller driving MuJoCo as it would drive a robot: a Foxglove server of our own (the
Python foxglove-sdk, pinned in requirements.txt) runs mujoco_control.py's box in real time,
publishes the pusher's and the object's poses (CDR geometry_msgs/msg/PoseStamped, every 20 ms)
and takes the pusher's target by the protocol's client publish; `pushlab control ws://... --arm`
connects to it, learns and plans from the poses as they arrive, and sends the targets through its
safety gate. The pusher follows the newest target kinematically at most 4 cm/s, one MuJoCo step
(1 ms) at a time, paced by the wall clock.

The pairs are mujoco_control.py's (the same seeds draw the same COM and goal), so the table can be
set beside the one `--pipe` made in lock-step: here the poses and the targets cross a socket
asynchronously, as with a robot.

`--serve PAIR` runs one pair's robot until Ctrl-C on ws://127.0.0.1:PORT for a person to drive
from the app (File → Connect to a live robot…, Drive): it writes the object's setting.json and
prints the goal to type in.

Usage: mujoco_foxglove.py OUT.csv [--pairs 20] [--first 31] [--theta online] [--jobs 2]
                          [--pushlab PATH] [--model MODEL.json]
       mujoco_foxglove.py --table OUT.csv
       mujoco_foxglove.py --serve PAIR [--port 8765] [--setting-out setting.json]
"""

import argparse
import concurrent.futures
import csv
import json
import math
import os
import signal
import struct
import subprocess
import sys
import tempfile
import threading
import time

import foxglove
import mujoco
import numpy as np
from foxglove.websocket import Capability, ServerListener

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from mujoco_control import FIELDS, LIMIT_S, SPEC, SPEED, world  # noqa: E402

sys.path.insert(0, os.path.join(HERE, "..", "mujoco-pushes"))
from generate import yaw_of  # noqa: E402

POSE_STAMPED = "geometry_msgs/msg/PoseStamped"
PUBLISH_EVERY_S = 0.02


def cdr_pose(stamp_ns, x, y, yaw, frame=b"table"):
    """A little-endian CDR PoseStamped, as rclcpp writes one."""
    body = struct.pack("<iI", stamp_ns // 1_000_000_000, stamp_ns % 1_000_000_000)
    body += struct.pack("<I", len(frame) + 1) + frame + b"\0"
    body += b"\0" * (-len(body) % 8)
    body += struct.pack("<7d", x, y, 0.0, 0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))
    return b"\0\1\0\0" + body


def target_of(data):
    """The position of a CDR PoseStamped: after the stamp and the frame id, aligned to 8."""
    (n,) = struct.unpack_from("<I", data, 12)
    at = 4 + ((8 + 4 + n + 7) // 8) * 8
    return struct.unpack_from("<2d", data, at)


class Commands(ServerListener):
    """The targets received on the command topic: the newest, and how many."""

    def __init__(self):
        self.lock = threading.Lock()
        self.target = None
        self.received = 0

    def on_message_data(self, client, client_channel_id, data):
        x, y = target_of(data)
        with self.lock:
            self.target = np.array([x, y])
            self.received += 1


def robot_server(port):
    """The robot's Foxglove server on `port` (0: any): the command listener, the server, and the
    pusher's and the object's pose channels (which hold the context they log in: a context
    dropped closes its channels)."""
    commands = Commands()
    context = foxglove.Context()
    server = foxglove.start_server(
        name="mujoco robot", port=port, capabilities=[Capability.ClientPublish],
        server_listener=commands, supported_encodings=["cdr"], context=context)
    schema = foxglove.Schema(name=POSE_STAMPED, encoding="ros2msg", data=b"")
    channels = [foxglove.Channel(t, schema=schema, message_encoding="cdr", context=context)
                for t in ("/pusher", "/object")]
    return commands, server, (context, channels)


def serve(pair, port, setting_out):
    """One pair's robot until Ctrl-C, for a person driving it from the app."""
    model, data, pusher, setting, goal, com = world(pair, "mujoco-foxglove")
    commands, server, (_context, channels) = robot_server(port)
    with open(setting_out, "w") as f:
        json.dump(setting, f)
    print(f"ws://127.0.0.1:{server.port}: pair {pair}, the setting in {setting_out}; "
          f"the goal x {goal[0]:.4f} m, y {goal[1]:.4f} m, yaw {math.degrees(goal[2]):.1f}°; "
          f"Ctrl-C ends", flush=True)
    # The SDK's server holds Python's own Ctrl-C handling off: a flag the loop looks at instead.
    stopped = threading.Event()
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, lambda *_: stopped.set())
    try:
        simulate(lambda: not stopped.is_set(), model, data, pusher, channels, commands)
    finally:
        server.stop()
    print(f"{commands.received} target(s) received", flush=True)


def run(pushlab, pair, with_, model_path=None):
    model, data, pusher, setting, goal, com = world(pair, "mujoco-foxglove")
    commands, server, (_context, channels) = robot_server(0)
    try:
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "setting.json")
            with open(path, "w") as f:
                json.dump(setting, f)
            proc = subprocess.Popen(
                [pushlab, "control", f"ws://127.0.0.1:{server.port}", "--pusher", "/pusher",
                 "--object", "/object", "--command", "/pusher_target", "--frame", "table",
                 "--setting", path, "--theta", with_, "--arm", "--json",
                 *(["--model", model_path] if model_path else []),
                 "--time-limit", str(LIMIT_S), "--goal", ",".join(f"{g:.6f}" for g in goal)],
                stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
            lines = []
            reader = threading.Thread(target=lambda: lines.extend(proc.stdout), daemon=True)
            reader.start()
            path_m = simulate(lambda: proc.poll() is None, model, data, pusher, channels,
                              commands)
            reader.join()
    finally:
        server.stop()
    parsed = [json.loads(line) for line in lines]
    outcome = next((p["outcome"] for p in parsed if "outcome" in p), {})
    steps = [p["step"] for p in parsed if "step" in p]
    body = model.body("object").id
    x, y, yaw = float(data.xpos[body][0]), float(data.xpos[body][1]), yaw_of(data.xquat[body])
    yaw_err = (goal[2] - yaw + math.pi) % (2 * math.pi) - math.pi
    return {"pair": pair, "plans_with": with_, "com_offset_m": math.hypot(*com),
            "reached": outcome.get("why") == "reached",
            "time_s": steps[-1]["time_s"] if steps else 0.0, "pusher_path_m": path_m,
            "final_position_m": math.hypot(goal[0] - x, goal[1] - y),
            "final_yaw_deg": math.degrees(yaw_err), "sent": outcome.get("commands_sent", 0),
            "received": commands.received}


def simulate(running, model, data, pusher, channels, commands):
    """MuJoCo in real time while `running()` (until pushlab ends): the pusher following the newest
    target, the poses published every 20 ms. The pusher's path, metres."""
    jp, jv = model.joint("px").qposadr[0], model.joint("px").dofadr[0]
    body = model.body("object").id
    dt = SPEC["timestep_s"]
    started, sim_t, next_publish, path = time.monotonic(), 0.0, 0.0, 0.0
    while running():
        wall = time.monotonic() - started
        while sim_t < wall:
            with commands.lock:
                target = commands.target
            move = np.zeros(2) if target is None else target - pusher
            dist = float(np.linalg.norm(move))
            if dist > SPEED * dt:
                move *= SPEED * dt / dist
            pusher = pusher + move
            path += float(np.linalg.norm(move))
            data.qpos[jp:jp + 2] = pusher
            data.qvel[jv:jv + 2] = move / dt
            mujoco.mj_step(model, data)
            sim_t += dt
            if sim_t >= next_publish:
                next_publish += PUBLISH_EVERY_S
                stamp = time.time_ns()
                x, y = float(data.xpos[body][0]), float(data.xpos[body][1])
                channels[0].log(cdr_pose(stamp, pusher[0], pusher[1], 0.0), log_time=stamp)
                channels[1].log(cdr_pose(stamp, x, y, yaw_of(data.xquat[body])), log_time=stamp)
        time.sleep(0.002)
    return path


def table(rows):
    print(f"{len(rows)} runs")
    print("| plans with | reached | median time (s) | median final error (mm, °) | targets sent = received |")
    print("|---|---|---|---|---|")
    med = lambda v: float(np.median(v)) if v else float("nan")  # noqa: E731
    for name in sorted({r["plans_with"] for r in rows}):
        mine = [r for r in rows if r["plans_with"] == name]
        ok = [r for r in mine if str(r["reached"]).lower() == "true"]
        same = sum(int(r["sent"]) == int(r["received"]) for r in mine)
        print(f"| {name} | {len(ok)}/{len(mine)} | {med([float(r['time_s']) for r in ok]):.1f} | "
              f"{1e3 * med([float(r['final_position_m']) for r in mine]):.1f}, "
              f"{med([abs(float(r['final_yaw_deg'])) for r in mine]):.2f} | {same}/{len(mine)} |")


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--table":
        table(list(csv.DictReader(open(sys.argv[2], newline=""))))
        return
    if len(sys.argv) >= 3 and sys.argv[1] == "--serve":
        parser = argparse.ArgumentParser(description="one pair's robot, for the app to drive")
        parser.add_argument("--serve", type=int, required=True, metavar="PAIR")
        parser.add_argument("--port", type=int, default=8765)
        parser.add_argument("--setting-out", default="setting.json")
        args = parser.parse_args()
        serve(args.serve, args.port, args.setting_out)
        return
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("out")
    parser.add_argument("--pairs", type=int, default=20)
    parser.add_argument("--first", type=int, default=31)
    parser.add_argument("--theta", default="online")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--pushlab", default=os.environ.get("PUSHLAB", "target/release/pushlab"))
    parser.add_argument("--model", help="the model file planned with (default: the CLI's, the app's)")
    args = parser.parse_args()
    pairs = list(range(args.first, args.first + args.pairs))
    rows = []
    with open(args.out, "w", newline="") as f, \
            concurrent.futures.ProcessPoolExecutor(args.jobs) as pool:
        out = csv.DictWriter(f, fieldnames=FIELDS + ["sent", "received"])
        out.writeheader()
        for row in pool.map(run, [args.pushlab] * len(pairs), pairs, [args.theta] * len(pairs),
                            [args.model] * len(pairs)):
            rows.append(row)
            out.writerow(row)
            f.flush()
            print(json.dumps(row), flush=True)
    table(rows)


if __name__ == "__main__":
    main()
