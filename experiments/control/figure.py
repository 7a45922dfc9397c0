#!/usr/bin/env python3
"""The controller's figure: the share of goals reached by each time, per controller, from the CSV
`cargo bench -p pushlab-core --bench control -- --csv OUT.csv` and mujoco_control.py write (one or
more, their rows together: controllers measured in separate runs on the same pairs; a later file's
row for a pair and controller replaces an earlier one's, as a miss run again with a longer limit
does). Standard library only, so it runs wherever the bench does.

    python3 experiments/control/figure.py experiments/control/box.csv docs/src/images/control-box.svg

With `--limit 240` (runs measured with a 240 s limit) the time axis runs to 240 s, and a dashed
line marks the tables' 120 s.
"""

import argparse
import csv

COLOURS = {
    "online": "#1f77b4",
    "fixed": "#d62728",
    "physics": "#2ca02c",
    "truth": "#7f7f7f",
    "weighted": "#9467bd",
}
LABELS = {
    "online": "learning online",
    "fixed": "θ fixed at θ(0)",
    "physics": "physics alone, learning",
    "truth": "the true θ",
    "weighted": "the weighted prediction",
}
W, H, LEFT, BOTTOM, TOP, RIGHT = 720, 380, 60, 50, 20, 250
TABLE_LIMIT_S = 120.0


def main(sources: list, out: str, limit_s: float = TABLE_LIMIT_S) -> None:
    runs = {}
    for source in sources:
        for r in csv.DictReader(open(source, newline="")):
            runs[(r["pair"], r["plans_with"])] = r
    rows = list(runs.values())
    plot_w, plot_h = W - LEFT - RIGHT, H - TOP - BOTTOM

    def x(t: float) -> float:
        return LEFT + plot_w * t / limit_s

    def y(share: float) -> float:
        return TOP + plot_h * (1.0 - share)

    parts = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" '
        f'font-family="sans-serif" font-size="12">',
        f'<rect width="{W}" height="{H}" fill="white"/>',
    ]
    for k in range(0, 11, 2):
        share = k / 10
        parts.append(f'<line x1="{LEFT}" x2="{LEFT + plot_w}" y1="{y(share):.1f}" '
                     f'y2="{y(share):.1f}" stroke="#ddd"/>')
        parts.append(f'<text x="{LEFT - 6}" y="{y(share) + 4:.1f}" text-anchor="end">'
                     f'{int(share * 100)} %</text>')
    for t in range(0, int(limit_s) + 1, 20 if limit_s <= 120 else 40):
        parts.append(f'<text x="{x(t):.1f}" y="{TOP + plot_h + 16}" text-anchor="middle">{t}</text>')
    parts.append(f'<text x="{LEFT + plot_w / 2}" y="{H - 10}" text-anchor="middle">'
                 f'seconds from the first step</text>')
    parts.append(f'<text x="14" y="{TOP + plot_h / 2}" text-anchor="middle" '
                 f'transform="rotate(-90 14 {TOP + plot_h / 2})">goals reached and held</text>')
    parts.append(f'<rect x="{LEFT}" y="{TOP}" width="{plot_w}" height="{plot_h}" '
                 f'fill="none" stroke="#333"/>')
    if limit_s > TABLE_LIMIT_S:
        at = x(TABLE_LIMIT_S)
        parts.append(f'<line x1="{at:.1f}" x2="{at:.1f}" y1="{TOP}" y2="{TOP + plot_h}" '
                     f'stroke="#333" stroke-dasharray="4 3"/>')
        parts.append(f'<text x="{at + 4:.1f}" y="{TOP + plot_h - 6}">the tables\' limit</text>')
    for n, (name, colour) in enumerate(COLOURS.items()):
        runs = [r for r in rows if r["plans_with"] == name]
        if not runs:
            continue
        times = sorted(float(r["time_s"]) for r in runs if r["reached"].lower() == "true")
        points = [(0.0, 0.0)]
        for k, t in enumerate(times, start=1):
            points.append((t, (k - 1) / len(runs)))
            points.append((t, k / len(runs)))
        points.append((limit_s, len(times) / len(runs)))
        path = " ".join(f"{x(t):.1f},{y(s):.1f}" for t, s in points)
        parts.append(f'<polyline points="{path}" fill="none" stroke="{colour}" stroke-width="2"/>')
        ly = TOP + 14 + 20 * n
        parts.append(f'<line x1="{LEFT + plot_w + 12}" x2="{LEFT + plot_w + 32}" y1="{ly - 4}" '
                     f'y2="{ly - 4}" stroke="{colour}" stroke-width="2"/>')
        parts.append(f'<text x="{LEFT + plot_w + 36}" y="{ly}">{LABELS[name]} '
                     f'({len(times)}/{len(runs)})</text>')
    parts.append("</svg>")
    with open(out, "w") as f:
        f.write("\n".join(parts) + "\n")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("files", nargs="+", metavar="RUNS.csv [MORE.csv ...] OUT.svg")
    parser.add_argument("--limit", type=float, default=TABLE_LIMIT_S,
                        help="the runs' time limit, seconds: the time axis's end (default 120)")
    args = parser.parse_args()
    if len(args.files) < 2:
        parser.error("expected one CSV or more, then the SVG to write")
    main(args.files[:-1], args.files[-1], args.limit)
