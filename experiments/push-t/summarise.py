"""Prints experiments/push-t/run's table from its `pushlab eval --json` reports (RESULTS/NAME-OPT.json)."""

import glob
import json
import os
import statistics
import sys


def pair(d):
    return f"{d['pos']:.3f} / {d['rot']:.3f}"


def main(results):
    print("| test set | optimiser | offline | fixed | online | physics-only online "
          "| COM true (mm) | COM learned, mean (mm) | mean error (mm) | 95 % ellipse holds it | h learned, median (mm) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name in ["same", "com-bar", "com-stem"]:
        for optimizer in ["gd", "gd-lr0.05", "gauss-newton"]:
            path = os.path.join(results, f"{name}-{optimizer}.json")
            if not os.path.exists(path):
                continue
            r = json.load(open(path))
            pushes = r["trajectories"]
            true = pushes[0]["com_offset_true"]
            learned = [p["com_offset_learned"] for p in pushes]
            mean = [statistics.fmean(c[i] for c in learned) * 1000 for i in range(2)]
            h = statistics.median(p["h_learned"] for p in pushes) * 1000
            found = r["com_found"]
            print(f"| {name} | {optimizer} | {pair(r['offline'])} | {pair(r['fixed'])} "
                  f"| {pair(r['online'])} | {pair(r['physics']['online'])} "
                  f"| ({true[0]*1000:.1f}, {true[1]*1000:.1f}) | ({mean[0]:.1f}, {mean[1]:.1f}) "
                  f"| {found['mean_error_m']*1000:.1f} | {found['within_95']} of {found['pushes']} "
                  f"| {h:.1f} |")
    print()
    print("NMSE as position / rotation; offline on the training episodes, the rest on the test set.")


if __name__ == "__main__":
    main(sys.argv[1])
