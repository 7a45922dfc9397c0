#!/usr/bin/env bash
# Trains the network `mujoco_control.py --model` plans with in MuJoCo, as the paper trains its network
# on the system it will push (offline, on nominal objects) and adapts θ online to the object at hand:
# 243 pushes of the controller's box in MuJoCo with its COM at the centre (never a measured pair's:
# theirs are hidden and drawn within 5 cm of it), from experiments/control/mujoco-train-spec.json,
# trained as assets/default-model.json is (horizon 10, the pure-network baseline too, seed 0).
#
# Usage: experiments/control/train_mujoco_model.sh PYTHON PUSHLAB OUT.json
#   PYTHON   a Python with experiments/control/requirements.txt (MuJoCo)
#   PUSHLAB  the CLI (target/debug/pushlab)
# The pushes go to target/mujoco-train-pushes/ (made again each time). Same spec, same pushes
# (seeded), same model (seed 0) to the byte: about 4 minutes on one core.
set -euo pipefail
if [ $# -ne 3 ]; then
    sed -n 2,12p "$0" | sed 's/^# \{0,1\}//'
    exit 2
fi
# Absolute, not resolved: a venv's python is a symlink whose target is not the venv.
absolute() { echo "$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"; }
python=$(absolute "$1") pushlab=$(absolute "$2") out=$(absolute "$3")
cd "$(dirname "$0")/../.."
data=target/mujoco-train-pushes
rm -rf "$data"
mkdir -p target
"$python" experiments/mujoco-pushes/generate.py "$data" --spec experiments/control/mujoco-train-spec.json
# Relative paths, so that the model file's sources are the same on every machine.
"$pushlab" train --data "$data" --split-from-labels --baseline --horizon 10 --out "$out"
