"""Prints experiments/push-t/run's tables from its `pushlab eval --json` reports (RESULTS/NAME-OPT.json).

    summarise.py RESULTS RATE...            the validation table and the test table
    summarise.py --choose RESULTS RATE...   the rate with the lowest mean online NMSE on val-*
"""

import glob
import json
import os
import statistics
import sys


def pair(d):
    return f"{d['pos']:.3f} / {d['rot']:.3f}"


VALIDATION = ["val-bar", "val-stem"]


def validation_score(results, rate):
    """Mean over the validation sets of the online NMSE's mean of position and rotation."""
    scores = []
    for name in VALIDATION:
        online = json.load(open(os.path.join(results, f"{name}-lr{rate}.json")))["online"]
        scores.append((online["pos"] + online["rot"]) / 2)
    return statistics.fmean(scores)


def choose(results, rates):
    return min(rates, key=lambda rate: validation_score(results, rate))


def main(results, rates):
    chosen = choose(results, rates)
    print("| rate | " + " | ".join(f"{name} online" for name in VALIDATION) + " | score |")
    print("|---|" + "---|" * (len(VALIDATION) + 1))
    for rate in rates:
        cells = [pair(json.load(open(os.path.join(results, f"{n}-lr{rate}.json")))["online"])
                 for n in VALIDATION]
        mark = " (chosen)" if rate == chosen else ""
        print(f"| {rate}{mark} | " + " | ".join(cells) + f" | {validation_score(results, rate):.3f} |")
    print()
    print("| test set | optimiser | offline | fixed | online | physics-only online "
          "| COM true (mm) | COM learned, mean (mm) | mean error (mm) | 95 % ellipse holds it | h learned, median (mm) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name in ["same", "com-bar", "com-stem"]:
        for optimizer in ["gd", "gd-chosen", "gauss-newton"]:
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
            label = f"gd at {chosen}" if optimizer == "gd-chosen" else optimizer
            print(f"| {name} | {label} | {pair(r['offline'])} | {pair(r['fixed'])} "
                  f"| {pair(r['online'])} | {pair(r['physics']['online'])} "
                  f"| ({true[0]*1000:.1f}, {true[1]*1000:.1f}) | ({mean[0]:.1f}, {mean[1]:.1f}) "
                  f"| {found['mean_error_m']*1000:.1f} | {found['within_95']} of {found['pushes']} "
                  f"| {h:.1f} |")
    print()
    print("NMSE as position / rotation; offline on the training episodes, the rest on the test set.")


if __name__ == "__main__":
    if sys.argv[1] == "--choose":
        print(choose(sys.argv[2], sys.argv[3:]))
    else:
        main(sys.argv[1], sys.argv[2:])
