"""Derives mit_shapes.json (shipped with pushlab) from the facts in the MIT Push Dataset's shape
database (`shapes.json`, produced by the dataset authors' pnpush_config/src/config/shape_db.py).

Run once: python3 derive_mit_shapes.py ../../../../shared/mit-push/shapes.json > mit_shapes.json

- Polygons (rect1-3, tri1-3, hex) are copied as they are: convex, counter-clockwise, MIT object frame.
- Ellipses (ellip1-3) become 64-gons inscribed in the ellipse (vertex k at angle 2*pi*k/64).
- butter's outline is not convex (it has a waist); pushlab's outlines must be, so it becomes the convex
  hull of the approximate outline with collinear points removed.
"""
import json
import math
import sys

ELLIPSE_SEGMENTS = 64


def cross(o, a, b):
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def convex_hull(points):
    pts = sorted(set(map(tuple, points)))
    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 1e-12:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 1e-12:
            upper.pop()
        upper.append(p)
    return [list(p) for p in lower[:-1] + upper[:-1]]


def main(path):
    facts = json.load(open(path))
    shapes = {}
    for name, s in facts.items():
        if s["shape_type"] == "ellip":
            a, b = s["semi_axes_m"]
            vertices = [
                [round(a * math.cos(2 * math.pi * k / ELLIPSE_SEGMENTS), 9),
                 round(b * math.sin(2 * math.pi * k / ELLIPSE_SEGMENTS), 9)]
                for k in range(ELLIPSE_SEGMENTS)
            ]
            how = f"ellipse with semi-axes {a} x {b} m as an inscribed {ELLIPSE_SEGMENTS}-gon"
        elif s["shape_type"] == "polyapprox":
            vertices = convex_hull(s["vertices_m_ccw"])
            how = "convex hull of the dataset's approximate (non-convex) outline"
        else:
            vertices = s["vertices_m_ccw"]
            how = "polygon as given by the dataset"
        shapes[name] = {
            "vertices": vertices,
            "com": s["centroid_m"],
            "mass_kg": s["mass_kg"],
            "thickness_m": s["thickness_m"],
            "outline": how,
        }
    out = {
        "_about": "Outlines of the MIT Push Dataset's eleven objects in the dataset's object frame "
                  "(metres, counter-clockwise, convex), with the centre of mass ('com', null when "
                  "the dataset gives none). Derived by derive_mit_shapes.py from the dataset "
                  "authors' shape database.",
        "shapes": shapes,
    }
    json.dump(out, sys.stdout, indent=1)
    sys.stdout.write("\n")


main(sys.argv[1])
