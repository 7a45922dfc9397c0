#!/usr/bin/env python3
"""Summarises `pushlab suggest --measure-orders` reports (experiments/next-push/run).

Each report is one MuJoCo set (one object, one COM, one rate and noise; nine pushes): the COM error
after each push of the ranked order, the worst order and R random orders, θ carried on.

Per optimiser and group of sets (all; the COM moved, the sets whose name is not `com+0+0`), after n
pushes:
  ranked, worst  the median over sets of that order's error;
  random         for each random order index r, the median over sets of the r-th random order's
                 error (one random order per set); the median of those R medians and their 10-90 %
                 band: how far the median of one random draw of orders strays.
Targets (issue #51): Gauss-Newton, after 3 ranked pushes, the median at most what 9 random pushes
gave (2.5 mm over all sets, 4.1 mm with the COM moved; experiments/trust/README.md).

Usage:
  summarise.py choose --out choose.json CRITERION:RATE:OPTIMISER:FOLDER ...
  summarise.py measure --out next-push.json [--figure next-push.svg] CRITERION:RATE:OPTIMISER:FOLDER ...
Standard library only.
"""

import argparse
import json
import os
import statistics
import sys

AFTER = [1, 2, 3, 5, 9]
TARGETS_MM = {"all": 2.5, "COM moved": 4.1}


def load(specs):
    """Per (criterion, optimiser): the list of set reports."""
    runs = {}
    for spec in specs:
        criterion, rate, optimiser, folder = spec.split(":", 3)
        for name in sorted(os.listdir(folder)):
            if not name.endswith(".json"):
                continue
            with open(os.path.join(folder, name)) as f:
                report = json.load(f)
            report["rate"] = int(rate)
            runs.setdefault((criterion, optimiser), []).append(report)
    return runs


def error_after(order, n):
    if len(order) < n or order[n - 1]["com_error_m"] is None:
        return None
    return order[n - 1]["com_error_m"] * 1e3


def median(values):
    values = [v for v in values if v is not None]
    return statistics.median(values) if values else None


def quantile(values, p):
    values = sorted(v for v in values if v is not None)
    if not values:
        return None
    return values[round((len(values) - 1) * p)]


def groups(reports):
    moved = [r for r in reports if "com+0+0" not in r["object"]]
    return {"all": reports, "COM moved": moved}


def curve(reports, n):
    """The ranked, worst and random figures after n pushes, mm."""
    orders = min(len(r["random"]) for r in reports)
    medians = [median(error_after(r["random"][k], n) for r in reports) for k in range(orders)]
    return {
        "after": n,
        "sets": len(reports),
        "ranked_mm": median(error_after(r["ranked"], n) for r in reports),
        "worst_mm": median(error_after(r["worst"], n) for r in reports),
        "random_median_mm": median(medians),
        "random_p10_mm": quantile(medians, 0.1),
        "random_p90_mm": quantile(medians, 0.9),
        "random_orders": orders,
    }


def fmt(v):
    return "    -" if v is None else f"{v:5.1f}"


def choose(args):
    runs = load(args.specs)
    scores = {}
    print("Choosing the criterion (validation draw): median COM error after 3 ranked pushes, mm")
    for (criterion, optimiser), reports in sorted(runs.items()):
        by_rate = {}
        for r in reports:
            by_rate.setdefault(r["rate"], []).append(r)
        for rate, rs in sorted(by_rate.items()):
            c = curve(rs, 3)
            scores.setdefault(criterion, []).append(c["ranked_mm"])
            print(f"  {criterion:7} {optimiser:13} {rate:4} Hz  ranked {fmt(c['ranked_mm'])}"
                  f"  random {fmt(c['random_median_mm'])}  worst {fmt(c['worst_mm'])}")
    mean = {k: statistics.mean(v) for k, v in scores.items()}
    chosen = min(sorted(mean), key=lambda k: (mean[k], k != "spread"))
    print("  mean over rates and optimisers: "
          + ", ".join(f"{k} {v:.2f} mm" for k, v in sorted(mean.items())) + f"; chosen: {chosen}")
    with open(args.out, "w") as f:
        json.dump({"mean_ranked_after_3_mm": mean, "chosen": chosen}, f, indent=1)


def measure(args):
    runs = load(args.specs)
    out = {"rows": [], "targets": []}
    print("COM error after n pushes, θ carried (median over sets, mm); random: the median of "
          "one random order per set, median [10-90 %] over the draws of orders")
    print(f"{'optimiser':13} {'sets':10} {'n':>2} {'ranked':>7} {'worst':>7} {'random':>22}")
    for (criterion, optimiser), reports in sorted(runs.items(), key=lambda kv: kv[0][1]):
        for group, rs in groups(reports).items():
            for n in range(1, 10):
                c = curve(rs, n)
                c.update(optimiser=optimiser, group=group, criterion=criterion)
                out["rows"].append(c)
                if n in AFTER:
                    print(f"{optimiser:13} {group:10} {n:>2} {fmt(c['ranked_mm']):>7} "
                          f"{fmt(c['worst_mm']):>7} {fmt(c['random_median_mm']):>7} "
                          f"[{fmt(c['random_p10_mm'])}-{fmt(c['random_p90_mm'])}]")
            if optimiser == "gauss-newton":
                target = TARGETS_MM[group]
                ranked3 = curve(rs, 3)["ranked_mm"]
                met = ranked3 is not None and ranked3 <= target
                out["targets"].append({"group": group, "ranked_after_3_mm": ranked3,
                                       "target_mm": target, "met": met})
    print("Targets (Gauss-Newton, after 3 ranked pushes <= what 9 random pushes gave):")
    for t in out["targets"]:
        print(f"  {t['group']:10} {fmt(t['ranked_after_3_mm'])} mm <= {t['target_mm']} mm: "
              f"{'met' if t['met'] else 'NOT met'}")
    with open(args.out, "w") as f:
        json.dump(out, f, indent=1)
    if args.figure:
        with open(args.figure, "w") as f:
            f.write(figure(out["rows"]))


def figure(rows):
    """Two panels (gradient descent, Gauss-Newton) of the all-sets curves: ranked, worst and random
    median with its 10-90 % band, and the 9-random-push figure the target names. Plain SVG."""
    w, h, pad_l, pad_b, pad_t, gap = 380, 300, 52, 44, 34, 30
    top = max(r[k] for r in rows if r["group"] == "all"
              for k in ("worst_mm", "random_p90_mm", "ranked_mm") if r[k] is not None)
    top = 5 * (int(top / 5) + 1)
    parts = []
    total_w = 2 * w + gap
    total_h = h + 30
    parts.append(f'<svg xmlns="http://www.w3.org/2000/svg" width="{total_w}" height="{total_h}" '
                 f'font-family="sans-serif" font-size="12">')
    parts.append(f'<rect width="{total_w}" height="{total_h}" fill="white"/>')
    for p, optimiser in enumerate(["gd", "gauss-newton"]):
        x0 = p * (w + gap)
        rs = sorted((r for r in rows if r["optimiser"] == optimiser and r["group"] == "all"),
                    key=lambda r: r["after"])
        if not rs:
            continue
        pw, ph = w - pad_l - 10, h - pad_b - pad_t

        def X(n):
            return x0 + pad_l + (n - 1) / 8 * pw

        def Y(v):
            return pad_t + ph - v / top * ph

        title = "gradient descent" if optimiser == "gd" else "Gauss-Newton"
        parts.append(f'<text x="{x0 + pad_l}" y="20" font-weight="bold">{title}, '
                     f'{rs[0]["sets"]} MuJoCo sets</text>')
        for v in range(0, top + 1, 5):
            parts.append(f'<line x1="{X(1)}" x2="{X(9)}" y1="{Y(v)}" y2="{Y(v)}" stroke="#ddd"/>')
            parts.append(f'<text x="{x0 + pad_l - 6}" y="{Y(v) + 4}" text-anchor="end">{v}</text>')
        for n in range(1, 10):
            parts.append(f'<text x="{X(n)}" y="{pad_t + ph + 16}" text-anchor="middle">{n}</text>')
        parts.append(f'<text x="{x0 + pad_l + pw / 2}" y="{pad_t + ph + 34}" '
                     f'text-anchor="middle">pushes learned</text>')
        parts.append(f'<text transform="translate({x0 + 14},{pad_t + ph / 2}) rotate(-90)" '
                     f'text-anchor="middle">median COM error, mm</text>')
        band = [(X(r["after"]), Y(r["random_p90_mm"])) for r in rs] + \
               [(X(r["after"]), Y(r["random_p10_mm"])) for r in reversed(rs)]
        parts.append('<polygon fill="#9ecae1" fill-opacity="0.5" points="'
                     + " ".join(f"{x:.1f},{y:.1f}" for x, y in band) + '"/>')

        def line(key, colour, dash=""):
            pts = " ".join(f"{X(r['after']):.1f},{Y(r[key]):.1f}" for r in rs if r[key] is not None)
            extra = f' stroke-dasharray="{dash}"' if dash else ""
            parts.append(f'<polyline fill="none" stroke="{colour}" stroke-width="2"{extra} '
                         f'points="{pts}"/>')

        line("random_median_mm", "#2171b5")
        line("worst_mm", "#636363", "5,4")
        line("ranked_mm", "#e6550d")
        if optimiser == "gauss-newton":
            target = TARGETS_MM["all"]
            parts.append(f'<line x1="{X(1)}" x2="{X(9)}" y1="{Y(target)}" y2="{Y(target)}" '
                         f'stroke="black" stroke-dasharray="2,3"/>')
    # One legend for both panels, below them.
    legend = [("#e6550d", "", "ranked (suggest)"),
              ("#2171b5", "", "random: median, 10-90 % band"),
              ("#636363", "5,4", "worst ranked"),
              ("black", "2,3", f"{TARGETS_MM['all']} mm: 9 pushes (target)")]
    x, y = pad_l, h + 12
    for colour, dash, text in legend:
        extra = f' stroke-dasharray="{dash}"' if dash else ""
        parts.append(f'<line x1="{x}" x2="{x + 24}" y1="{y}" y2="{y}" stroke="{colour}" '
                     f'stroke-width="2"{extra}/>')
        parts.append(f'<text x="{x + 30}" y="{y + 4}">{text}</text>')
        x += 40 + 6.8 * len(text)
    parts.append("</svg>\n")
    return "\n".join(parts)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("mode", choices=["choose", "measure"])
    ap.add_argument("--out", required=True)
    ap.add_argument("--figure")
    ap.add_argument("specs", nargs="+")
    args = ap.parse_args()
    (choose if args.mode == "choose" else measure)(args)


if __name__ == "__main__":
    sys.exit(main())
