#!/usr/bin/env python3
"""Copies a simulated set and spoils single frames of its object pose, to measure bad-tracking proposals.

Usage: glitch-set.py SET OUT --per-push N --jump METRES --turn DEGREES [--seed S]

Each push gets N glitches at random frames (10 .. last-10, at least 5 frames apart): the object's
recorded position moves by JUMP metres in a random direction and its yaw by ±TURN degrees, for that
frame only. OUT/truth-labels.json is the set's truth-labels.json with a `bad tracking` segment on each
spoiled frame, so that `pushlab labels compare` scores bad tracking as well.
"""
import argparse, csv, json, math, random, shutil
from pathlib import Path

p = argparse.ArgumentParser()
p.add_argument("set"); p.add_argument("out")
p.add_argument("--per-push", type=int, default=3)
p.add_argument("--jump", type=float, required=True)
p.add_argument("--turn", type=float, required=True)
p.add_argument("--seed", type=int, default=1)
a = p.parse_args()
src, out = Path(a.set), Path(a.out)
if out.exists():
    shutil.rmtree(out)
shutil.copytree(src, out)
rng = random.Random(a.seed)
truth = json.loads((src / "truth-labels.json").read_text())
for name, labels in truth["recordings"].items():
    path = out / name
    rows = list(csv.reader(path.open()))
    header, data = rows[0], rows[1:]
    ix, iy, it = header.index("object_x"), header.index("object_y"), header.index("object_theta")
    frames = []
    while len(frames) < a.per_push:
        k = rng.randrange(10, len(data) - 10)
        if all(abs(k - f) >= 5 for f in frames):
            frames.append(k)
    for k in sorted(frames):
        angle = rng.uniform(0, 2 * math.pi)
        data[k][ix] = f"{float(data[k][ix]) + a.jump * math.cos(angle):.6f}"
        data[k][iy] = f"{float(data[k][iy]) + a.jump * math.sin(angle):.6f}"
        data[k][it] = f"{float(data[k][it]) + rng.choice([-1, 1]) * math.radians(a.turn):.6f}"
        labels.setdefault("segments", []).append({"label": "bad tracking", "start": k, "end": k + 1})
    labels["segments"].sort(key=lambda s: (s["start"], s["label"], s["end"]))
    with path.open("w", newline="") as f:
        csv.writer(f, lineterminator="\n").writerows([header] + data)
(out / "truth-labels.json").write_text(json.dumps(truth, indent=2) + "\n")
