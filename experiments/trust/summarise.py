#!/usr/bin/env python3
"""The tables of experiments/trust/run from `pushlab eval --json --per-frame` reports.

Arguments: SOURCE:OPTIMIZER:REPORT.json ... where SOURCE is `mujoco` or `mit-SHAPE`, with `-carry`
appended for a report made with `--carry-theta` (each push going on from the one before it of the
same object): those make the tables of learning across pushes, not the rows and targets above them,
which are the issue's claims for one push learned from θ_online(0).
Per push it takes from the report: the final θ and its posterior (`com_offset_learned`,
`com_offset_cov`), θ at every frame (`frames[].theta`, from --per-frame) and the source file; the
truth is `com_offset_true` for MuJoCo (from its setting.json) and the geometric centre (0, 0) for MIT
(the dataset gives no COM for hex; its other shapes' COM is their centre). It computes itself, so
that nothing depends on what a pushlab version puts in `com_found`:
  - holds: the truth inside the final 95 % ellipse, d' C^-1 d <= 5.991 (chi-square, 2 dof), the
    rule of learn/uncertainty.rs; checked against `com_found.within_95` where the report has it;
  - sigma: sqrt((Cxx + Cyy) / 2), the RMS of the two principal standard deviations, mm;
  - COM out: pushes whose learned COM left the outline at any frame (and at the last);
  - h/R: h over R, the largest distance from the learned COM to the outline (the most h can be for
    any pressure under the object), at every frame; h > R counts the pushes where it exceeded 1;
  - NMSE: the reports' online / fixed / physics-only online, means weighted by online samples;
  - along the final posterior's axes: the error's component along the axis it knows best and the one
    it knows least (the eigenvectors of C), medians in mm: how much of the error is where one push
    cannot see;
  - the physics-only model's final COM on the same push (`physics_trajectories`, by source), its
    error against the same truth and whether its 95 % ellipse holds it: how much of finding the COM
    is Lynch's model's own and how much the network adds;
  - with -carry: the final error after the n-th push of an object (n counted from `continued`);
  - what the final σ is made of: the report's `com_sigma_parts` (the frames, the model's COM
    misfit, the estimate's path drift; they add in squares to sigma), medians in mm, where the
    report has them.
"""

import argparse
import json
import math
import os
import re
import statistics
import sys

CHI2_2DOF_95 = 5.991464547107979
TARGET_COVERAGE, TARGET_MEDIAN_MM = 0.80, 3.0


def centroid(vertices):
    a = cx = cy = 0.0
    for (x0, y0), (x1, y1) in zip(vertices, vertices[1:] + vertices[:1]):
        c = x0 * y1 - x1 * y0
        a, cx, cy = a + c, cx + (x0 + x1) * c, cy + (y0 + y1) * c
    return cx / (3 * a), cy / (3 * a)


def inside(vertices, p):
    """Crossing rule: any simple polygon."""
    x, y = p
    hit = False
    for (x0, y0), (x1, y1) in zip(vertices, vertices[1:] + vertices[:1]):
        if (y0 > y) != (y1 > y) and x < x0 + (y - y0) * (x1 - x0) / (y1 - y0):
            hit = not hit
    return hit


def on_boundary(vertices, p, tolerance=1e-9):
    """Within `tolerance` metres of an edge: where a COM kept physical lands when learning pushes it
    out (pushlab projects it onto the boundary), which the crossing rule leaves undecided."""
    x, y = p
    for (x0, y0), (x1, y1) in zip(vertices, vertices[1:] + vertices[:1]):
        ex, ey = x1 - x0, y1 - y0
        t = max(0.0, min(1.0, ((x - x0) * ex + (y - y0) * ey) / (ex * ex + ey * ey)))
        if math.hypot(x - x0 - t * ex, y - y0 - t * ey) <= tolerance:
            return True
    return False


def physical(vertices, p):
    return inside(vertices, p) or on_boundary(vertices, p)


def reach(vertices, p):
    return max(math.hypot(vx - p[0], vy - p[1]) for vx, vy in vertices)


def holds(estimate, cov, truth):
    (a, b), (_, d) = cov
    det = a * d - b * b
    if not (det > 0 and math.isfinite(det)):
        return False
    dx, dy = truth[0] - estimate[0], truth[1] - estimate[1]
    return (d * dx * dx - 2 * b * dx * dy + a * dy * dy) / det <= CHI2_2DOF_95


class Outlines:
    def __init__(self, shapes_path):
        shapes = json.load(open(shapes_path))["shapes"]
        self.mit = {}
        for name, shape in shapes.items():
            v = [tuple(p) for p in shape["vertices"]]
            c = centroid(v)
            self.mit[name] = [(x - c[0], y - c[1]) for x, y in v]
        self.settings = {}

    def setting(self, source):
        folder = os.path.dirname(source)
        if folder not in self.settings:
            self.settings[folder] = json.load(open(os.path.join(folder, "setting.json")))
        return self.settings[folder]


def push_of(source_kind, traj, outlines):
    src = traj["source"]
    if source_kind == "mujoco":
        setting = outlines.setting(src)
        vertices = [tuple(v) for v in setting["object"]["vertices"]]
        truth = traj["com_offset_true"]
        g = setting["generator"]
        group = {"object": g["object"], "rate": f"{setting['sample_rate_hz']:g} Hz",
                 "noise": g["noise"]["name"], "com": "centred" if g["com_index"] == 0 else "moved"}
    else:
        shape = re.search(r"shape=([a-z0-9]+)_", src).group(1)
        vertices, truth, group = outlines.mit[shape], [0.0, 0.0], {"object": shape}
    est, cov = traj["com_offset_learned"], traj["com_offset_cov"]
    frames = traj.get("frames") or []
    thetas = [f["theta"] for f in frames] or [{"com_offset": est, "h": traj["h_learned"]}]
    ratios = [t["h"] / reach(vertices, t["com_offset"]) for t in thetas]
    within = holds(est, cov, truth)
    reported = (traj.get("com_found") or {}).get("within_95")
    if reported is not None and reported != within:
        print(f"warning: {src}: within_95 {reported} in the report, {within} here", file=sys.stderr)
    return {
        "source": src, "group": group,
        "error_mm": math.hypot(est[0] - truth[0], est[1] - truth[1]) * 1000,
        "estimate": est, "truth": truth, "cov": cov,
        "holds": within,
        "sigma_mm": math.sqrt(max(0.0, (cov[0][0] + cov[1][1]) / 2)) * 1000,
        "outside_any": any(not physical(vertices, t["com_offset"]) for t in thetas),
        "outside_final": not physical(vertices, est),
        "h_ratio_min": min(ratios), "h_ratio_max": max(ratios),
        "h_over_reach": any(r > 1 + 1e-9 for r in ratios),
        "h_mm": traj["h_learned"] * 1000,
        "h_true_mm": traj["h_true"] * 1000 if traj.get("h_true") is not None else None,
        "frames_per_theta": bool(frames),
        "along_axes_mm": along_axes(est, cov, truth),
        "continued": bool(traj.get("continued")),
        "sigma_parts_mm": {k.removesuffix("_m"): v * 1000 for k, v in traj["com_sigma_parts"].items()}
        if traj.get("com_sigma_parts") else None,
        **best_of(traj.get("best_fit"), truth, "best"),
    }


def best_of(fit, truth, prefix):
    """A push's best θ (`eval --best-fit`) against the truth: its COM error, NMSE and samples."""
    if not fit:
        return {}
    com = fit["theta"]["com_offset"]
    return {f"{prefix}_error_mm": math.hypot(com[0] - truth[0], com[1] - truth[1]) * 1000,
            f"{prefix}_nmse": fit["nmse"], f"{prefix}_samples": fit["samples"]}


def with_physics(pushes, physics_trajectories):
    """The physics-only model's final COM on the same push (the report's `physics_trajectories`, by
    source), against the same truth: its error and whether its 95 % ellipse holds the truth."""
    by_source = {t["source"]: t for t in physics_trajectories}
    for p in pushes:
        t = by_source.get(p["source"])
        if t is None:
            p["physics_error_mm"] = p["physics_holds"] = None
            continue
        est, truth = t["com_offset_learned"], p["truth"]
        p["physics_error_mm"] = math.hypot(est[0] - truth[0], est[1] - truth[1]) * 1000
        p["physics_holds"] = holds(est, t["com_offset_cov"], truth)
        p.update(best_of(t.get("best_fit"), truth, "physics_best"))


def with_object_fits(pushes, objects):
    """The best θ over all the pushes of each object (`eval --best-fit --carry-theta`), its COM
    error set on the object's last push, beside where carried learning ended there."""
    last = {p["source"]: p for p in pushes}
    for o in objects:
        fit, p = o.get("best_fit"), last.get(o["sources"][-1])
        if fit and p:
            com, truth = fit["theta"]["com_offset"], p["truth"]
            p["object_best_error_mm"] = math.hypot(com[0] - truth[0], com[1] - truth[1]) * 1000


def along_axes(estimate, cov, truth):
    """|error| along the best- and least-known axes of the 2 x 2 covariance `cov`, mm."""
    a, b, c = cov[0][0], cov[0][1], cov[1][1]
    mean, half = (a + c) / 2, math.hypot((a - c) / 2, b)
    # The eigenvector of the larger eigenvalue mean + half.
    angle = 0.5 * math.atan2(2 * b, a - c)
    worst = (math.cos(angle), math.sin(angle))
    d = (estimate[0] - truth[0], estimate[1] - truth[1])
    along_worst = abs(d[0] * worst[0] + d[1] * worst[1]) * 1000
    along_best = abs(-d[0] * worst[1] + d[1] * worst[0]) * 1000
    return [along_best, along_worst] if half >= 0 and mean >= 0 else [None, None]


def weighted(reports, key, sub=None):
    total = pos = rot = 0.0
    for r in reports:
        value = r[key] if sub is None else (r.get(key) or {}).get(sub)
        if value is None:
            return None
        n = r["config"]["online_samples"]
        total, pos, rot = total + n, pos + n * value["pos"], rot + n * value["rot"]
    return {"pos": pos / total, "rot": rot / total} if total else None


def summary(pushes, reports):
    errors = [p["error_mm"] for p in pushes]
    out = {
        "pushes": len(pushes),
        "holds": sum(p["holds"] for p in pushes),
        "coverage": sum(p["holds"] for p in pushes) / max(1, len(pushes)),
        "median_error_mm": statistics.median(errors) if errors else None,
        "max_error_mm": max(errors) if errors else None,
        "median_sigma_mm": statistics.median(p["sigma_mm"] for p in pushes) if pushes else None,
        "outside_any": sum(p["outside_any"] for p in pushes),
        "outside_final": sum(p["outside_final"] for p in pushes),
        "h_ratio_range": [min(p["h_ratio_min"] for p in pushes), max(p["h_ratio_max"] for p in pushes)]
        if pushes else None,
        "h_over_reach": sum(p["h_over_reach"] for p in pushes),
        "per_frame": all(p["frames_per_theta"] for p in pushes),
    }
    if reports is not None:
        out["online"] = weighted(reports, "online")
        out["fixed"] = weighted(reports, "fixed")
        out["physics_online"] = weighted(reports, "physics", "online")
        out["physics_fixed"] = weighted(reports, "physics", "fixed")
    h_err = [abs(p["h_mm"] - p["h_true_mm"]) for p in pushes if p["h_true_mm"] is not None]
    out["median_h_error_mm"] = statistics.median(h_err) if h_err else None
    axes = [p["along_axes_mm"] for p in pushes if p["along_axes_mm"][0] is not None]
    out["median_along_best_mm"] = statistics.median(a[0] for a in axes) if axes else None
    out["median_along_worst_mm"] = statistics.median(a[1] for a in axes) if axes else None
    physics = [p for p in pushes if p.get("physics_error_mm") is not None]
    out["physics_pushes"] = len(physics)
    out["physics_holds"] = sum(p["physics_holds"] for p in physics)
    out["median_physics_error_mm"] = statistics.median(p["physics_error_mm"] for p in physics) \
        if physics else None
    for prefix in ("best", "physics_best"):
        fitted = [p for p in pushes if f"{prefix}_error_mm" in p]
        out[f"{prefix}_pushes"] = len(fitted)
        out[f"median_{prefix}_error_mm"] = statistics.median(p[f"{prefix}_error_mm"] for p in fitted) \
            if fitted else None
        n = sum(p[f"{prefix}_samples"] for p in fitted)
        out[f"{prefix}_nmse"] = {k: sum(p[f"{prefix}_nmse"][k] * p[f"{prefix}_samples"] for p in fitted) / n
                                 for k in ("pos", "rot")} if n else None
    parts = [p["sigma_parts_mm"] for p in pushes if p.get("sigma_parts_mm")]
    out["median_sigma_parts_mm"] = {k: statistics.median(q[k] for q in parts) for k in parts[0]} \
        if parts else None
    return out


def print_sigma_parts(rows):
    print("\nWhat the final COM σ is made of: medians of the frames', the COM misfit's and the path "
          "drift's σ, mm (they add in squares per push):")
    for r in rows:
        m = r["summary"].get("median_sigma_parts_mm")
        if m:
            print(f"  {r['source']:<19} {r['optimizer']:<12} frames {m['frames']:5.1f}  "
                  f"misfit {m['misfit']:5.1f}  drift {m['drift']:5.1f}  (σ {r['summary']['median_sigma_mm']:5.1f})")


def print_axes(rows):
    print("\nWhere one push's error lies: median |error| along the final posterior's best-known and "
          "least-known axes, mm:")
    for r in rows:
        s = r["summary"]
        if s["median_along_best_mm"] is not None:
            print(f"  {r['source']:<19} {r['optimizer']:<12} best {s['median_along_best_mm']:5.1f}  "
                  f"least {s['median_along_worst_mm']:5.1f}  (total {s['median_error_mm']:5.1f})")


def print_physics_com(rows):
    print("\nThe COM after one push, the combined model against the physics-only model (the outline's "
          "contact and Lynch, no network) learning online with the same optimiser on the same pushes: "
          "95 % holds, median error mm:")
    for r in rows:
        s = r["summary"]
        if s["physics_pushes"]:
            print(f"  {r['source']:<19} {r['optimizer']:<12} combined {s['holds']:>3}/{s['pushes']:<3} "
                  f"{s['median_error_mm']:5.1f}  physics-only {s['physics_holds']:>3}/{s['physics_pushes']:<3} "
                  f"{s['median_physics_error_mm']:5.1f}")


def print_best(rows):
    rows = [r for r in rows if r["summary"]["best_pushes"]]
    if not rows:
        return
    print("\nThe best θ for each whole push (eval --best-fit: the θ held fixed over the push that fits it "
          "best, found by a grid over the object and Levenberg-Marquardt; no online learner with the model "
          "beats it on that push), against where online learning ended: median COM error mm, NMSE pos/rot")
    for r in rows:
        s = r["summary"]
        line = (f"  {r['source']:<19} {r['optimizer']:<12} combined best {s['median_best_error_mm']:5.1f} "
                f"{nmse(s['best_nmse'])} online {s['median_error_mm']:5.1f} {nmse(s.get('online'))}")
        if s["physics_best_pushes"]:
            line += (f"   physics-only best {s['median_physics_best_error_mm']:5.1f} "
                     f"{nmse(s['physics_best_nmse'])} online {s['median_physics_error_mm']:5.1f} "
                     f"{nmse(s.get('physics_online'))}")
        print(line)


def with_push_index(pushes):
    """Numbers each push within its object's chain: 1 for a push from θ_online(0), n + 1 after n."""
    n = 0
    for p in pushes:
        n = n + 1 if p["continued"] else 1
        p["push_index"] = n
    return pushes


def chain_ends(pushes):
    """The last push of each chain (the push before a push that starts afresh, and the very last)."""
    return [p for i, p in enumerate(pushes) if i + 1 == len(pushes) or pushes[i + 1]["push_index"] == 1]


def sources(groups):
    """The rows of a table, as (label, optimiser, pushes, reports): per source kind in the order of
    the arguments and per optimiser, MuJoCo also with the COM moved (no reports: its NMSE is per
    report), then all held-out MIT shapes together per optimiser."""
    out = []
    opts = [o for o in ("gd", "gauss-newton") if any(k[0] == o for k in groups)]
    for kind in dict.fromkeys(k for _, k in groups):
        for opt in opts:
            if (opt, kind) not in groups:
                continue
            pushes, reports = groups[(opt, kind)]
            if kind == "mujoco":
                out.append(("MuJoCo", opt, pushes, reports))
                out.append(("MuJoCo, COM moved", opt, [p for p in pushes if p["group"]["com"] == "moved"], None))
            else:
                out.append((f"MIT {kind[4:]} held out", opt, pushes, reports))
    for opt in opts:
        mit = [(ps, rs) for (o, k), (ps, rs) in groups.items() if o == opt and k.startswith("mit-")]
        if mit:
            out.append(("MIT held out, all", opt, [p for ps, _ in mit for p in ps],
                        [r for _, rs in mit for r in rs]))
    return out


def print_carried(carried):
    """Learning across pushes (--carry-theta): the final COM after the n-th push of an object."""
    if not carried:
        return []
    print("\nθ carried from push to push of one object (--carry-theta): the final COM after the n-th "
          "push and after each object's last push (95 % holds, median error mm), and the NMSE:")
    rows = []
    for label, opt, ps, reports in sources(carried):
        by_n = {n: summary([p for p in ps if p["push_index"] == n], None)
                for n in sorted({p["push_index"] for p in ps})}
        last = summary(chain_ends(ps), None)  # a subset keeps whole chains: the COM is per set
        cells = [f"n={n}: {by_n[n]['holds']:>3}/{by_n[n]['pushes']:<3} {by_n[n]['median_error_mm']:5.1f}"
                 for n in (1, 3, 5, 9) if n in by_n]
        cells.append(f"last: {last['holds']:>3}/{last['pushes']:<3} {last['median_error_mm']:5.1f}")
        fitted = [p["object_best_error_mm"] for p in chain_ends(ps) if "object_best_error_mm" in p]
        if fitted:
            last["median_object_best_error_mm"] = statistics.median(fitted)
            cells.append(f"best θ over the object's pushes {statistics.median(fitted):5.1f}")
        whole = summary(ps, reports)
        online = f"  online {nmse(whole.get('online'))} phys {nmse(whole.get('physics_online'))}" \
            if reports is not None else ""
        print(f"  {label:<19} {opt:<12} " + "  ".join(cells) + online)
        rows.append({"source": label, "optimizer": opt, "summary": whole, "last": last,
                     "by_push": by_n})
    return rows


def nmse(v):
    return f"{v['pos']:.3f}/{v['rot']:.3f}" if v else "-"


def print_main(rows):
    head = (f"{'source':<19} {'optimiser':<12} {'95 % holds':>12} {'COM err med/max':>16} "
            f"{'σ med':>6} {'COM out':>7} {'h/R range':>11} {'h>R':>4} "
            f"{'online':>12} {'fixed':>12} {'phys online':>12}")
    print(head)
    print("-" * len(head))
    for r in rows:
        s = r["summary"]
        print(f"{r['source']:<19} {r['optimizer']:<12} "
              f"{s['holds']:>4}/{s['pushes']:<3} {s['coverage']:4.0%} "
              f"{s['median_error_mm']:6.1f}/{s['max_error_mm']:<6.1f} mm"
              f" {s['median_sigma_mm']:5.1f} {s['outside_any']:>3}/{s['outside_final']:<3} "
              f"{s['h_ratio_range'][0]:5.2f}-{s['h_ratio_range'][1]:<5.2f} {s['h_over_reach']:>4} "
              f"{nmse(s.get('online')):>12} {nmse(s.get('fixed')):>12} {nmse(s.get('physics_online')):>12}")


def print_breakdown(mujoco):
    print("\nMuJoCo pushes by group (95 % holds, median final COM error mm, median h error mm):")
    keys = ["object", "rate", "noise", "com"]
    opts = [o for o in ("gd", "gauss-newton") if (o, "mujoco") in mujoco]
    print(f"{'group':<22}" + "".join(f" {o:>30}" for o in opts))
    for key in keys:
        values = sorted({p["group"][key] for ps in mujoco.values() for p in ps[0]},
                        key=lambda v: (len(v), v))
        for value in values:
            line = f"{key + ' ' + value:<22}"
            for o in opts:
                ps = [p for p in mujoco[(o, "mujoco")][0] if p["group"][key] == value]
                s = summary(ps, None)
                line += (f"  {s['holds']:>3}/{s['pushes']:<3} {s['coverage']:4.0%} "
                         f"{s['median_error_mm']:6.1f} mm h {s['median_h_error_mm']:5.1f}")
            print(line)


def best_context(by, source, key):
    """What the best θ for each whole push reaches on `source` (from its gradient-descent row, where
    the trust run finds it), to set beside a claim: what no online learner with the model beats."""
    value = (by.get((source, "gd")) or {}).get(key)
    if value is None:
        return ""
    shown = f"{value:.1f} mm" if key == "median_best_error_mm" else f"{nmse(value)}"
    return f" (the best θ for each whole push: {shown})"


def targets(rows):
    """The issue's claims, met or missed, from the rows."""
    lines = []
    by = {(r["source"], r["optimizer"]): r["summary"] for r in rows}
    for (source, opt), s in by.items():
        if source == "MIT held out, all":
            continue
        ok = s["coverage"] >= TARGET_COVERAGE
        lines.append((ok, f"95 % ellipse holds the truth in >= 80 % of pushes: {source}, {opt}: "
                          f"{s['coverage']:.0%}"))
    for (source, opt), s in by.items():
        ok = s["outside_any"] == 0 and s["h_over_reach"] == 0
        lines.append((ok, f"θ physical (COM inside the outline at every frame, h <= R): {source}, "
                          f"{opt}: COM left it in {s['outside_any']}, h > R in {s['h_over_reach']}"
                          f" of {s['pushes']}"))
    for (source, opt), s in by.items():
        if not source.startswith("MIT") or s.get("physics_online") is None or source == "MIT held out, all":
            continue
        on, ph = s["online"], s["physics_online"]
        ok = on["pos"] < ph["pos"] and on["rot"] < ph["rot"]
        lines.append((ok, f"online below physics-only online (pos and rot): {source}, {opt}: "
                          f"{nmse(on)} against {nmse(ph)}{best_context(by, source, 'best_nmse')}"))
    for source in ("MuJoCo", "MuJoCo, COM moved"):
        for opt in ("gd", "gauss-newton"):
            s = by.get((source, opt))
            if s:
                ok = s["median_error_mm"] <= TARGET_MEDIAN_MM
                lines.append((ok, f"median final COM error <= 3 mm: {source}, {opt}: "
                                  f"{s['median_error_mm']:.1f} mm{best_context(by, source, 'median_best_error_mm')}"))
        gd, gn = by.get((source, "gd")), by.get((source, "gauss-newton"))
        if gd and gn:
            ok = gn["median_error_mm"] <= gd["median_error_mm"]
            lines.append((ok, f"Gauss–Newton's median COM error no worse than gradient descent's: {source}: "
                              f"{gn['median_error_mm']:.1f} against {gd['median_error_mm']:.1f} mm"))
    print("\nTargets of issue #25:")
    for ok, text in lines:
        print(f"  {'met   ' if ok else 'MISSED'} {text}")
    met = sum(ok for ok, _ in lines)
    print(f"  {met} of {len(lines)} met")
    return [{"met": ok, "claim": text} for ok, text in lines]


def print_sanity(path):
    if not path or not os.path.exists(path):
        return
    pushes = json.load(open(path))["pushes"]
    worst = lambda k, f=max: f(p[k] for p in pushes)  # noqa: E731
    print(f"\nMuJoCo pushes' physical sanity ({len(pushes)} pushes): moved >= {worst('moved_m', min) * 1000:.0f} mm, "
          f"pusher touching >= {worst('contact_share', min):.0%} of the motion, object speed / pusher "
          f"speed <= {worst('max_speed_ratio'):.2f}, after the stop creep <= {worst('creep_after_stop_mm'):.3f} mm "
          f"and {worst('yaw_after_stop_deg'):.3f}°, tilt <= {worst('max_tilt_deg'):.2f}°, inertia / friction "
          f"<= {worst('max_inertia_ratio'):.2f} (95th percentile <= {worst('p95_inertia_ratio'):.2f})")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--shapes", required=True)
    parser.add_argument("--sanity")
    parser.add_argument("--out")
    parser.add_argument("reports", nargs="+")
    args = parser.parse_args()
    outlines = Outlines(args.shapes)
    groups = {}  # (optimizer, source kind) -> (pushes, reports)
    carried = {}  # the same for --carry-theta reports
    for item in args.reports:
        kind, opt, path = item.split(":", 2)
        report = json.load(open(path))
        target = groups
        if kind.endswith("-carry"):
            kind, target = kind[: -len("-carry")], carried
        source_kind = "mujoco" if kind == "mujoco" else "mit"
        pushes = with_push_index([push_of(source_kind, t, outlines) for t in report["trajectories"]])
        with_physics(pushes, report.pop("physics_trajectories", []))
        with_object_fits(pushes, report.pop("object_best_fits", []))
        del report["trajectories"]
        entry = target.setdefault((opt, kind), ([], []))
        entry[0].extend(pushes)
        entry[1].append(report)
    rows = [{"source": label, "optimizer": opt, "summary": summary(pushes, reports)}
            for label, opt, pushes, reports in sources(groups)]
    print_main(rows)
    print("(95 % holds: final ellipse holds the true COM; COM err: final, mm; σ: RMS of the final COM "
          "posterior's principal σ, mm; COM out: pushes whose learned COM left the outline at any frame / "
          "at the last; h/R: learned h over the largest distance from the learned COM to the outline, "
          "every frame; NMSE pos/rot weighted by online samples)")
    mujoco = {(o, k): v for (o, k), v in groups.items() if k == "mujoco"}
    if mujoco:
        print_breakdown(mujoco)
    print_axes(rows)
    print_physics_com(rows)
    print_sigma_parts(rows)
    print_best(rows)
    carried_rows = print_carried(carried)
    claims = targets(rows)
    print_sanity(args.sanity)
    if args.out:
        every = [dict(p, optimizer=o, kind=k) for (o, k), (ps, _) in groups.items() for p in ps]
        every += [dict(p, optimizer=o, kind=k + "-carry") for (o, k), (ps, _) in carried.items() for p in ps]
        json.dump({"rows": rows, "carried": carried_rows, "targets": claims, "pushes": every},
                  open(args.out, "w"), indent=1)


if __name__ == "__main__":
    main()
