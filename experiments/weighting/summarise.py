"""Tables of experiments/weighting/run from `pushlab eval --physics --json` reports.

  summarise.py choose --out choose.json  CONFIG:SOURCE:OPTIMISER:REPORT ...
  summarise.py measure --out weighting.json  SOURCE:OPTIMISER:REPORT ...

A source meets the target when weighted is at most physics-only online and at most online, in
position and in rotation, each within TOLERANCE (2 %, for noise).
"""

import argparse
import json
import sys

TOLERANCE = 1.02


def nmse(report):
    physics = report["physics"]
    pick = lambda n: (n["pos"], n["rot"])
    return {
        "online": pick(report["online"]),
        "physics": pick(physics["online"]),
        "weighted": pick(physics["weighted"]),
    }


def ratios(n):
    """Weighted over the better of online and physics-only online, position and rotation."""
    return [n["weighted"][i] / min(n["online"][i], n["physics"][i]) for i in range(2)]


def met(n):
    return all(
        n["weighted"][i] <= TOLERANCE * n[other][i] for other in ("online", "physics") for i in range(2)
    )


def fmt(pair):
    return f"{pair[0]:.3f} / {pair[1]:.3f}"


def choose(rows, out):
    configs = {}
    for row in rows:
        config, source, optimiser, path = row.split(":", 3)
        with open(path) as f:
            n = nmse(json.load(f))
        configs.setdefault(config, []).append((source, optimiser, n))
    summary = []
    for config, runs in configs.items():
        r = [x for _, _, n in runs for x in ratios(n)]
        summary.append(
            {
                "config": config,
                "worst_ratio": max(r),
                "mean_ratio": sum(r) / len(r),
                "met": sum(met(n) for _, _, n in runs),
                "runs": len(runs),
            }
        )
    summary.sort(key=lambda s: (s["worst_ratio"], s["mean_ratio"]))
    print("| weighting | worst weighted / best of both | mean | sources met |")
    print("|---|---|---|---|")
    for s in summary:
        print(f"| {s['config']} | {s['worst_ratio']:.3f} | {s['mean_ratio']:.3f} | {s['met']} of {s['runs']} |")
    print(f"\nchosen (lowest worst ratio): {summary[0]['config']}")
    with open(out, "w") as f:
        json.dump({"configs": summary, "chosen": summary[0]["config"]}, f, indent=1)


def measure(rows, out):
    table = []
    print("| online on | optimiser | online | physics-only online | weighted | weighted ≤ both (2 %) |")
    print("|---|---|---|---|---|---|")
    for row in rows:
        source, optimiser, path = row.split(":", 2)
        with open(path) as f:
            report = json.load(f)
        n = nmse(report)
        weights = [t.get("weight_end") for t in report.get("physics_trajectories", [])]
        weights = [w for w in weights if w is not None]
        ok = met(n)
        table.append({"source": source, "optimiser": optimiser, **n, "met": ok, "weight_end": weights})
        print(
            f"| {source} | {optimiser} | {fmt(n['online'])} | {fmt(n['physics'])} | "
            f"**{fmt(n['weighted'])}** | {'met' if ok else 'MISSED'} |"
        )
    missed = [t for t in table if not t["met"]]
    print(f"\n{len(table) - len(missed)} of {len(table)} met")
    with open(out, "w") as f:
        json.dump(table, f, indent=1)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("mode", choices=["choose", "measure"])
    parser.add_argument("--out", required=True)
    parser.add_argument("rows", nargs="+")
    args = parser.parse_args()
    (choose if args.mode == "choose" else measure)(args.rows, args.out)


if __name__ == "__main__":
    sys.exit(main())
