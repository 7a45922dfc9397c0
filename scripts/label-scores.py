#!/usr/bin/env python3
"""Table cells from a `pushlab labels compare --json` report, for scripts/measure-label-proposals.

Usage: label-scores.py REPORT f1 LABEL…   -> "F1 (frames in truth)" per label, joined by " | "
       label-scores.py REPORT prf LABEL    -> "precision | recall | F1" of one label
       label-scores.py REPORT other LABEL  -> frames the other file gives the label
"""
import json
import sys

report, mode, names = sys.argv[1], sys.argv[2], sys.argv[3:]
labels = {l["label"]: l for l in json.load(open(report))["labels"]}
fmt = lambda v: "–" if v is None else f"{v:.2f}"
if mode == "f1":
    print(" | ".join(f"{fmt(labels[n]['f1'])} ({labels[n]['frames_truth']})" for n in names))
elif mode == "prf":
    l = labels[names[0]]
    print(" | ".join(fmt(l[k]) for k in ("precision", "recall", "f1")))
else:
    print(labels[names[0]]["frames_other"])
