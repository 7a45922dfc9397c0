#!/usr/bin/env python3
"""The controller measured in MuJoCo, an engine pushlab did not write: a box whose COM is hidden
(drawn within 5 cm of its centre) rests on a grid of small spheres with Coulomb friction (the model
of experiments/mujoco-pushes/generate.py, at the bundled model's size: a 0.3 x 0.4 m box, a 175 mm
pusher); a goal is drawn 20-40 cm away in any direction and turned up to 45 degrees. Each control
step (10 Hz) MuJoCo's poses go to pushlab's Python package (`pushlab.Controller`, built with
maturin and installed in the environment: see the README), and the pusher's target it answers is
followed kinematically at most 4 cm/s for the next 0.1 s (100 MuJoCo steps of 1 ms). With
`--pushlab PATH` they go on a line to `PATH control --pipe` instead, which gives the same targets
to the bit. Every controller (online, fixed, physics, truth, weighted; `--with` some) on every
pair; a CSV like the bench's.

Usage: mujoco_control.py OUT.csv [--pairs 100] [--first 31] [--jobs 2] [--pushlab PATH]
                         [--with online,weighted] [--optimizer gd|gauss-newton] [--lookahead]
                         [--planner-seed K] [--model MODEL.json] [--time-limit 120] [--only 34,39]
       mujoco_control.py --table OUT.csv     (the summary of a CSV written, whole or cut short)

Each run is written to OUT.csv as it ends, so a run cut short leaves the pairs it finished; the
summary counts only pairs every controller finished.

The true h (for `--theta truth`) is what generate.py calls h: the pressure-weighted mean distance
of the support from the COM, from MuJoCo's normal forces at rest.
"""

import argparse
import concurrent.futures
import csv
import json
import math
import os
import random
import subprocess
import sys
import tempfile

import mujoco
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "mujoco-pushes"))
from generate import model_xml, outline_of, support_points, yaw_of  # noqa: E402

SPEC = {
    "timestep_s": 0.001,
    "pusher_radius": 0.175,
    "pusher_friction": 0.45,
    "floor_friction": 0.35,
    "object_height": 0.02,
    "object_mass_kg": 0.6,
    "support_sphere_radius": 0.002,
    "support_grid": 11,
}
RATE_HZ, SPEED, LIMIT_S, HOLD_STEPS = 10.0, 0.04, 120.0, 5
WITH = ["online", "fixed", "physics", "truth", "weighted"]


def draw_pair(seed):
    rng = random.Random(seed)
    com = [rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05)]
    d, a = rng.uniform(0.2, 0.4), rng.uniform(0, 2 * math.pi)
    goal = [d * math.cos(a), d * math.sin(a), math.radians(rng.uniform(-45, 45))]
    return com, goal


def settle(model, data, pusher_at):
    """The box settled on its supports, the pusher parked; the true h from the normal forces."""
    jp, jv = model.joint("px").qposadr[0], model.joint("px").dofadr[0]
    data.qpos[0:7] = [0, 0, 0, 1, 0, 0, 0]
    for _ in range(300):
        data.qpos[jp:jp + 2] = pusher_at
        data.qvel[jv:jv + 2] = 0
        mujoco.mj_step(model, data)
    mujoco.mj_forward(model, data)
    body, floor = model.body("object").id, model.geom("floor").id
    f6, forces, points = np.zeros(6), [], []
    rot, origin = data.xmat[body].reshape(3, 3), data.xpos[body]
    for i in range(data.ncon):
        con = data.contact[i]
        if floor in (con.geom1, con.geom2):
            mujoco.mj_contactForce(model, data, i, f6)
            forces.append(f6[0])
            points.append((rot.T @ (con.pos - origin))[:2])
    return np.array(forces), np.array(points)


def world(pair, name):
    """The pair's MuJoCo box (its COM hidden), settled, the pusher parked before it; its setting
    (with the true COM and h, for --theta truth) and its goal."""
    com, goal = draw_pair(pair)
    vertices = outline_of({"name": "box", "box": [0.3, 0.4]})
    supports = support_points(vertices, SPEC["support_grid"], 0.01)
    model = mujoco.MjModel.from_xml_string(model_xml(SPEC, vertices, supports, com))
    data = mujoco.MjData(model)
    pusher = np.array([-0.15 - 0.175 - 0.05, 0.0])
    forces, points = settle(model, data, pusher)
    h = float((forces * np.linalg.norm(points - np.array(com), axis=1)).sum() / forces.sum())
    setting = {
        "name": f"{name}-{pair}",
        "object": {"shape": "box", "width": 0.3, "length": 0.4},
        "pusher_radius": SPEC["pusher_radius"],
        "com_offset": com,
        "h": h,
        "sample_rate_hz": RATE_HZ,
        "trajectories": [],
    }
    return model, data, pusher, setting, goal, com


MODEL = os.path.join(HERE, "..", "..", "assets", "default-model.json")


def run(pushlab, pair, with_, optimizer="gd", limit_s=LIMIT_S, lookahead=False, planner_seed=0,
        model_path=MODEL):
    """One pair with one controller: through `pushlab.Controller`, or `pushlab control --pipe`
    where `pushlab` is the CLI's path; `model_path` the model file it plans with."""
    model, data, _, setting, goal, com = world(pair, "mujoco-control")
    if pushlab is None:
        import pushlab as package
        # The goal as the pipe's --goal gives it (six decimals): both ways plan for one goal.
        planned = tuple(float(f"{g:.6f}") for g in goal)
        controller = package.Controller(package.Model.load(model_path), setting, planned,
                                        theta=with_, rate=RATE_HZ, speed=SPEED,
                                        optimizer=optimizer, lookahead=lookahead,
                                        planner_seed=planner_seed)

        def step(line):
            answer = controller.step(line["t"], tuple(line["pusher"]), tuple(line["object"]))
            return answer, controller.done

        outcome = drive(step, model, data, goal, limit_s)
    else:
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "setting.json")
            with open(path, "w") as f:
                json.dump(setting, f)
            proc = subprocess.Popen(
                [pushlab, "control", "--pipe", "--setting", path, "--theta", with_, "--model", model_path,
                 "--optimizer", optimizer, "--goal", ",".join(f"{g:.6f}" for g in goal),
                 "--planner-seed", str(planner_seed), *(["--lookahead"] if lookahead else [])],
                stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, bufsize=1)

            def step(line):
                proc.stdin.write(json.dumps(line) + "\n")
                proc.stdin.flush()
                answer = json.loads(proc.stdout.readline())
                return answer["step"], answer["done"]

            outcome = drive(step, model, data, goal, limit_s)
            proc.stdin.close()
            proc.wait()
    theta = outcome.pop("theta")
    learned = {"theta_com_error_m": math.hypot(theta["com_offset"][0] - com[0],
                                               theta["com_offset"][1] - com[1]),
               "theta_h_m": theta["h"], "true_h_m": setting["h"]}
    return {"pair": pair, "plans_with": with_, "com_offset_m": math.hypot(*com), **outcome, **learned}


def drive(step, model, data, goal, limit_s=LIMIT_S):
    """Runs a pair to its goal or the limit; `step(line)` is one control step on the poses
    (`{"t", "pusher", "object"}`): the step's answer and whether the goal is reached and held."""
    jp, jv = model.joint("px").qposadr[0], model.joint("px").dofadr[0]
    body = model.body("object").id
    dt, sub = SPEC["timestep_s"], int(round(1 / RATE_HZ / SPEC["timestep_s"]))
    pusher = data.qpos[jp:jp + 2].copy()
    path, reached, steps, theta = 0.0, False, 0, None
    while steps < limit_s * RATE_HZ:
        obj = [float(data.xpos[body][0]), float(data.xpos[body][1]), yaw_of(data.xquat[body])]
        line = {"t": steps / RATE_HZ, "pusher": [float(pusher[0]), float(pusher[1])], "object": obj}
        answer, done = step(line)
        theta = answer["theta"]
        steps += 1
        if done:
            reached = True
            break
        target = np.array(answer["target"])
        move = target - pusher
        dist = float(np.linalg.norm(move))
        if dist > SPEED / RATE_HZ:
            move *= SPEED / RATE_HZ / dist
        velocity = move * RATE_HZ
        start = pusher.copy()
        for k in range(1, sub + 1):
            data.qpos[jp:jp + 2] = start + move * (k / sub)
            data.qvel[jv:jv + 2] = velocity
            mujoco.mj_step(model, data)
        path += float(np.linalg.norm(move))
        pusher = start + move
    x, y, yaw = float(data.xpos[body][0]), float(data.xpos[body][1]), yaw_of(data.xquat[body])
    yaw_err = (goal[2] - yaw + math.pi) % (2 * math.pi) - math.pi
    return {"reached": reached, "time_s": steps / RATE_HZ, "pusher_path_m": path,
            "final_position_m": math.hypot(goal[0] - x, goal[1] - y),
            "final_yaw_deg": math.degrees(yaw_err), "theta": theta}


FIELDS = ["pair", "plans_with", "com_offset_m", "reached", "time_s", "pusher_path_m",
          "final_position_m", "final_yaw_deg"]
# Where θ ended (the last step's): its COM's distance from the hidden one, its h and the true h.
# Not in the older CSVs.
THETA_FIELDS = ["theta_com_error_m", "theta_h_m", "true_h_m"]


def table(rows):
    """The summary over the pairs every controller in the rows finished."""
    ran = [w for w in WITH if any(r["plans_with"] == w for r in rows)]
    done = {p for p in {r["pair"] for r in rows}
            if {r["plans_with"] for r in rows if r["pair"] == p} == set(ran)}
    rows = [r for r in rows if r["pair"] in done]
    print(f"{len(done)} pairs")
    # Where θ ended, when the rows say (CSVs written before THETA_FIELDS do not).
    theta = all(r.get("theta_com_error_m") not in (None, "") for r in rows)
    print("| plans with | reached | median time (s) | median pusher path (m) | "
          "median final error (mm, °) |" + (" median θ's COM from the truth (mm) |" if theta else ""))
    print("|---|---|---|---|---|" + ("---|" if theta else ""))
    med = lambda v: float(np.median(v)) if v else float("nan")  # noqa: E731
    for name in ran:
        mine = [r for r in rows if r["plans_with"] == name]
        ok = [r for r in mine if str(r["reached"]).lower() == "true"]
        com = f" {1e3 * med([float(r['theta_com_error_m']) for r in mine]):.1f} |" if theta else ""
        print(f"| {name} | {len(ok)}/{len(mine)} | {med([float(r['time_s']) for r in ok]):.1f} | "
              f"{med([float(r['pusher_path_m']) for r in ok]):.2f} | "
              f"{1e3 * med([float(r['final_position_m']) for r in mine]):.1f}, "
              f"{med([abs(float(r['final_yaw_deg'])) for r in mine]):.2f} |{com}")


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--table":
        table(list(csv.DictReader(open(sys.argv[2], newline=""))))
        return
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("out")
    parser.add_argument("--pairs", type=int, default=100)
    parser.add_argument("--first", type=int, default=31)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--pushlab", default=os.environ.get("PUSHLAB"),
                        help="drive this CLI's `control --pipe` instead of pushlab.Controller")
    parser.add_argument("--with", dest="plans_with", default=",".join(WITH),
                        help="the controllers run, comma-separated (default: all)")
    parser.add_argument("--optimizer", choices=["gd", "gauss-newton"], default="gd",
                        help="how θ learns as it pushes (pushlab control --optimizer)")
    parser.add_argument("--lookahead", action="store_true",
                        help="weigh the best pushes as the first of two (pushlab control --lookahead)")
    parser.add_argument("--planner-seed", type=int, default=0,
                        help="the planner's samples from stream K; the box and goal stay the pair's "
                             "(pushlab control --planner-seed)")
    parser.add_argument("--model", default=MODEL,
                        help="the model file planned with (default: the app's, assets/default-model.json)")
    parser.add_argument("--time-limit", type=float, default=LIMIT_S,
                        help="seconds before a run is called failed (default: 120)")
    parser.add_argument("--only", help="only these pairs, comma-separated (instead of --first and --pairs)")
    args = parser.parse_args()
    chosen = args.plans_with.split(",")
    unknown = [w for w in chosen if w not in WITH]
    if unknown:
        parser.error(f"--with {','.join(unknown)}: expected some of {', '.join(WITH)}")
    pairs = range(args.first, args.first + args.pairs)
    if args.only:
        pairs = [int(p) for p in args.only.split(",")]
    if args.pushlab is None:
        try:
            import pushlab  # noqa: F401
        except ImportError:
            parser.error("no pushlab package in this environment: build and install it (see "
                         "experiments/control/README.md), or give --pushlab target/debug/pushlab")
    jobs = [(p, w) for p in pairs for w in chosen]
    rows = []
    with open(args.out, "w", newline="") as f, \
            concurrent.futures.ProcessPoolExecutor(args.jobs) as pool:
        out = csv.DictWriter(f, fieldnames=FIELDS + THETA_FIELDS)
        out.writeheader()
        for row in pool.map(run, [args.pushlab] * len(jobs), *zip(*jobs),
                                [args.optimizer] * len(jobs), [args.time_limit] * len(jobs),
                                [args.lookahead] * len(jobs), [args.planner_seed] * len(jobs),
                                [args.model] * len(jobs)):
            rows.append(row)
            out.writerow(row)
            f.flush()
            print(json.dumps(row), flush=True)
    table(rows)


if __name__ == "__main__":
    main()
