#!/usr/bin/env python3
"""Pushes with a known COM and h from a second physics engine (MuJoCo), as native pushlab sets.

Nothing here comes from pushlab's own simulator: a flat object (an extruded polygon) rests on a
plane on a grid of small spheres with Coulomb friction, so MuJoCo's soft contacts carry more of its
weight near its COM; a vertical cylinder moved kinematically (its slide joints' position and
velocity set every step) pushes it along straight or slightly curved paths at 2.5-4 cm/s (0.4 s speed ramps). The COM is
moved by the body's inertial frame only: outline and support stay the same.

The true h is what pushlab's simulator calls h (docs/src/simulator.md, sim/pressure.rs `h_about`):
the pressure-weighted mean distance of the support from the COM, h = sum N_i |r_i - com| / sum N_i,
with N_i the normal forces MuJoCo computes at the support contacts r_i at rest before each push
(mean over the set's pushes). Recorded poses are the outline's area centroid (the body frame's
origin), not the COM; robot = the pusher's centre.

Usage: generate.py OUT_DIR [--spec sets.json] [--objects a,b] [--rates 10,30]
Writes OUT_DIR/<set>/setting.json + push_NNN.csv per set and OUT_DIR/sanity.json, and prints the
physical sanity checks. Same spec, same files (seeded).
"""

import argparse
import json
import math
import os
import sys

import mujoco
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def outline_of(obj):
    """Counter-clockwise vertices, moved so that the area centroid is the origin."""
    if "box" in obj:
        w, l = obj["box"]
        v = [[w / 2, -l / 2], [w / 2, l / 2], [-w / 2, l / 2], [-w / 2, -l / 2]]
    elif "regular" in obj:
        n, r = obj["regular"]
        v = [[r * math.cos(2 * math.pi * k / n), r * math.sin(2 * math.pi * k / n)] for k in range(n)]
    elif "ellipse" in obj:
        a, b, n = obj["ellipse"]
        v = [[a * math.cos(2 * math.pi * k / n), b * math.sin(2 * math.pi * k / n)] for k in range(n)]
    else:
        raise ValueError(f"object {obj['name']}: expected box, regular or ellipse")
    v = np.array(v, dtype=float)
    x, y = v[:, 0], v[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = cross.sum() / 2
    if area <= 0:
        raise ValueError(f"object {obj['name']}: outline is not counter-clockwise")
    centroid = np.array([((x + xn) * cross).sum(), ((y + yn) * cross).sum()]) / (6 * area)
    return v - centroid


def edge_distance(vertices, p):
    """Signed distance of p from the convex outline: > 0 inside."""
    d = math.inf
    for i in range(len(vertices)):
        a, b = vertices[i], vertices[(i + 1) % len(vertices)]
        t = (b - a) / np.linalg.norm(b - a)
        inward = np.array([-t[1], t[0]])
        d = min(d, float(np.dot(p - a, inward)))
    return d


def support_points(vertices, n, margin):
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    xs, ys = np.linspace(lo[0], hi[0], n), np.linspace(lo[1], hi[1], n)
    pts = [np.array([x, y]) for x in xs for y in ys]
    pts = [p for p in pts if edge_distance(vertices, p) >= margin]
    if len(pts) < 25:
        raise ValueError("fewer than 25 support points: make support_grid larger")
    return np.array(pts)


def model_xml(spec, vertices, supports, com):
    r_s, height, mass = spec["support_sphere_radius"], spec["object_height"], spec["object_mass_kg"]
    z0 = 2 * r_s
    mesh = " ".join(f"{x:.6f} {y:.6f} {z:.6f}" for z in (z0, z0 + height) for x, y in vertices)
    w, l = vertices.max(axis=0) - vertices.min(axis=0)
    inertia = [mass * (l * l + height * height) / 12, mass * (w * w + height * height) / 12,
               mass * (w * w + l * l) / 12]
    spheres = "\n".join(
        f'<geom type="sphere" size="{r_s}" pos="{x:.6f} {y:.6f} {r_s}" contype="1" conaffinity="0"'
        f' friction="{spec["floor_friction"]} 0 0" condim="3" rgba="0 0 1 1"/>'
        for x, y in supports)
    rp = spec["pusher_radius"]
    # Contact bits: floor (1/1) touches only the support spheres (1/0); the pusher (2/2) only the
    # object's prism (2/2). Frictions combine by their maximum: floor and pusher carry 0.
    return f"""<mujoco model="push">
  <option timestep="{spec['timestep_s']}" cone="elliptic" impratio="10" noslip_iterations="5"/>
  <asset><mesh name="prism" vertex="{mesh}"/></asset>
  <worldbody>
    <geom name="floor" type="plane" size="2 2 0.1" contype="1" conaffinity="1" friction="0 0 0"/>
    <body name="object">
      <freejoint/>
      <inertial pos="{com[0]:.6f} {com[1]:.6f} {z0 + height / 2:.6f}" mass="{mass}"
                diaginertia="{inertia[0]:.3e} {inertia[1]:.3e} {inertia[2]:.3e}"/>
      <geom name="prism" type="mesh" mesh="prism" contype="2" conaffinity="2" condim="3"
            friction="{spec['pusher_friction']} 0 0" mass="0"/>
      {spheres}
    </body>
    <body name="pusher">
      <joint name="px" type="slide" axis="1 0 0"/>
      <joint name="py" type="slide" axis="0 1 0"/>
      <geom name="pusher" type="cylinder" size="{rp} 0.02" pos="0 0 {z0 + 0.021}" mass="100"
            contype="2" conaffinity="2" condim="3" friction="0 0 0"/>
    </body>
  </worldbody>
</mujoco>"""


def plan_pushes(spec, vertices, rng, count):
    """Where each push starts and how it moves: an edge, a place on it, an angle, a curvature."""
    plans = []
    n = len(vertices)
    for _ in range(count):
        edge = int(rng.integers(n))
        a, b = vertices[edge], vertices[(edge + 1) % n]
        length = float(np.linalg.norm(b - a))
        frac = float(rng.uniform(0.15, 0.85))
        tangent = (b - a) / length
        outward = np.array([tangent[1], -tangent[0]])
        angle = float(rng.uniform(-1, 1) * spec["push_angle_max_deg"])
        curved = rng.uniform() < spec["curved_share"]
        plans.append({
            "edge": edge,
            "contact_offset": (frac - 0.5) * length,
            "point": a + frac * (b - a),
            "outward": outward,
            "angle_deg": angle,
            "curvature": float(rng.uniform(-1, 1) * spec["curvature_max"]) if curved else 0.0,
            "speed": float(rng.uniform(*spec["speed_range"])),
            "length": float(rng.uniform(*spec["push_length_range"])),
            "yaw0": float(rng.uniform(-math.pi, math.pi)),
        })
    return plans


def path_at(s, start, heading, curvature):
    """The pusher's centre after arc length s along a path of constant curvature."""
    if abs(curvature) < 1e-9:
        return start + s * np.array([math.cos(heading), math.sin(heading)])
    k = curvature
    return start + np.array([math.sin(heading + k * s) - math.sin(heading),
                             -math.cos(heading + k * s) + math.cos(heading)]) / k


def yaw_of(quat):
    w, x, y, z = quat
    return math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))


def simulate(spec, model, plan, com):
    """One push: per-step states, the true h at rest, and the sanity measures."""
    data = mujoco.MjData(model)
    dt = spec["timestep_s"]
    rp, gap = spec["pusher_radius"], 0.005
    c, s = math.cos(plan["yaw0"]), math.sin(plan["yaw0"])
    rot = np.array([[c, -s], [s, c]])
    start = rot @ (plan["point"] + plan["outward"] * (rp + gap))
    inward = -(rot @ plan["outward"])
    heading = math.atan2(inward[1], inward[0]) + math.radians(plan["angle_deg"])
    quat = [math.cos(plan["yaw0"] / 2), 0, 0, math.sin(plan["yaw0"] / 2)]
    jp, jv = model.joint("px").qposadr[0], model.joint("px").dofadr[0]
    data.qpos[0:3] = [0, 0, 0]
    data.qpos[3:7] = quat
    obj_body, pusher_geom = model.body("object").id, model.geom("pusher").id
    floor_geom = model.geom("floor").id

    def set_pusher(p, v):
        data.qpos[jp:jp + 2] = p
        data.qvel[jv:jv + 2] = v

    # Settle on the floor with the pusher parked, then read the support's normal forces.
    for _ in range(int(0.3 / dt)):
        set_pusher(start, [0, 0])
        mujoco.mj_step(model, data)
    mujoco.mj_forward(model, data)
    forces, points = [], []
    f6 = np.zeros(6)
    world_from_body = data.xmat[obj_body].reshape(3, 3)
    origin = data.xpos[obj_body]
    for i in range(data.ncon):
        con = data.contact[i]
        if floor_geom not in (con.geom1, con.geom2):
            continue
        mujoco.mj_contactForce(model, data, i, f6)
        forces.append(f6[0])
        points.append((world_from_body.T @ (con.pos - origin))[:2])
    forces, points = np.array(forces), np.array(points)
    h_true = float((forces * np.linalg.norm(points - com, axis=1)).sum() / forces.sum())
    pressure_centre = (forces[:, None] * points).sum(axis=0) / forces.sum()

    # Speed ramps of 0.4 s: the pusher meets the object (5 mm away) while still speeding up, so the
    # first touch is gentle.
    ramp = 0.4
    v = plan["speed"]
    t_move = plan["length"] / v + ramp
    total = t_move + spec["hold_s"]
    steps = int(round(total / dt))
    rec = np.zeros((steps + 1, 8))  # t, robot xy, object xy, yaw, tilt, in contact

    def record(k):
        q = data.xquat[obj_body]
        tilt = math.degrees(math.acos(min(1.0, data.xmat[obj_body][8])))
        touching = bool((data.contact.geom[:data.ncon] == pusher_geom).any())
        rec[k] = [k * dt, *data.qpos[jp:jp + 2], *data.xpos[obj_body][:2], yaw_of(q), tilt, touching]

    def arc(t):  # trapezoidal speed
        if t <= 0:
            return 0.0, 0.0
        if t < ramp:
            return v * t * t / (2 * ramp), v * t / ramp
        if t < t_move - ramp:
            return v * (t - ramp / 2), v
        if t < t_move:
            r = t_move - t
            return plan["length"] - v * r * r / (2 * ramp), v * r / ramp
        return plan["length"], 0.0

    set_pusher(start, [0, 0])
    mujoco.mj_forward(model, data)
    record(0)
    for k in range(1, steps + 1):
        t = k * dt
        s_now, speed = arc(t)
        p = path_at(s_now, start, heading, plan["curvature"])
        direction = heading + plan["curvature"] * s_now
        set_pusher(p, speed * np.array([math.cos(direction), math.sin(direction)]))
        mujoco.mj_step(model, data)
        record(k)
    rec[:, 5] = np.unwrap(rec[:, 5])

    moving = rec[:, 0] <= t_move
    obj_v = np.linalg.norm(np.diff(rec[:, 3:5], axis=0), axis=1) / dt
    window = 10  # 10 ms mean speed: the soft contact's first touch rings for a few steps
    obj_v = np.convolve(obj_v, np.ones(window) / window, mode="valid")
    # Inertia against friction: the object's acceleration (20 ms differences) over mu g. Quasi-static
    # means far below 1.
    pos = rec[::20, 3:5]
    accel = np.linalg.norm(np.diff(pos, 2, axis=0), axis=1) / (20 * dt) ** 2
    accel_ratio = accel / (spec["floor_friction"] * 9.81)
    settle = int(round((t_move + 0.1) / dt))
    sanity = {
        "moved_m": float(np.linalg.norm(rec[int(t_move / dt), 3:5] - rec[0, 3:5])),
        "contact_share": float(rec[moving, 7].mean()),
        "max_speed_ratio": float(obj_v.max() / v),
        "creep_after_stop_mm": float(np.linalg.norm(rec[-1, 3:5] - rec[settle, 3:5]) * 1000),
        "yaw_after_stop_deg": float(abs(math.degrees(rec[-1, 5] - rec[settle, 5]))),
        "max_tilt_deg": float(rec[:, 6].max()),
        "max_inertia_ratio": float(accel_ratio.max()),
        "p95_inertia_ratio": float(np.percentile(accel_ratio, 95)),
        "h_true": h_true,
        "pressure_centre_error_mm": float(np.linalg.norm(pressure_centre - com) * 1000),
    }
    return rec, sanity


def write_set(folder, setting, pushes, rate, noise, rng):
    os.makedirs(folder, exist_ok=True)
    for name in os.listdir(folder):
        if name.endswith(".csv"):
            os.remove(os.path.join(folder, name))
    entries = []
    for i, (rec, plan, split) in enumerate(pushes):
        step = 1.0 / rate
        times = np.arange(0.0, rec[-1, 0] + 1e-9, step)
        idx = np.clip(np.round(times / (rec[1, 0] - rec[0, 0])).astype(int), 0, len(rec) - 1)
        rows = rec[idx].copy()
        pos_sigma, yaw_sigma = noise["position_m"], math.radians(noise["yaw_deg"])
        rows[:, 1:5] += rng.normal(0.0, 1.0, (len(rows), 4)) * pos_sigma
        rows[:, 5] += rng.normal(0.0, 1.0, len(rows)) * yaw_sigma
        file = f"push_{i:03d}.csv"
        with open(os.path.join(folder, file), "w") as out:
            out.write("time,robot_x,robot_y,object_x,object_y,object_theta\n")
            for r in rows:
                out.write(f"{r[0]:.6g},{r[1]:.6f},{r[2]:.6f},{r[3]:.6f},{r[4]:.6f},{r[5]:.6f}\n")
        entries.append({"file": file, "contact_offset": round(plan["contact_offset"], 6),
                        "push_angle_deg": round(plan["angle_deg"], 3), "split": split,
                        "edge": plan["edge"], "curvature": round(plan["curvature"], 4),
                        "speed": round(plan["speed"], 4)})
    setting["sample_rate_hz"] = float(rate)
    setting["trajectories"] = entries
    with open(os.path.join(folder, "setting.json"), "w") as out:
        json.dump(setting, out, indent=1)


def com_tag(com):
    return f"com{com[0] * 1000:+.0f}{com[1] * 1000:+.0f}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("out")
    parser.add_argument("--spec", default=os.path.join(HERE, "sets.json"))
    parser.add_argument("--objects", help="comma-separated object names (default: all)")
    parser.add_argument("--rates", help="comma-separated rates in Hz (default: the spec's)")
    args = parser.parse_args()
    spec = json.load(open(args.spec))
    rates = [float(r) for r in args.rates.split(",")] if args.rates else spec["rates_hz"]
    wanted = set(args.objects.split(",")) if args.objects else None
    sanity = {"mujoco_version": mujoco.__version__, "sets": [], "pushes": []}
    for oi, obj in enumerate(spec["objects"]):
        if wanted and obj["name"] not in wanted:
            continue
        vertices = outline_of(obj)
        supports = support_points(vertices, spec["support_grid"], spec["support_sphere_radius"] + 0.002)
        size = {"shape": "polygon", "vertices": [[round(x, 9), round(y, 9)] for x, y in vertices]}
        roles = [("online", ci, com) for ci, com in enumerate(obj["com_offsets"])]
        roles.insert(0, ("offline", 0, [0.0, 0.0]))
        for role, ci, com in roles:
            com = np.array(com, dtype=float)
            model = mujoco.MjModel.from_xml_string(model_xml(spec, vertices, supports, com))
            rng = np.random.default_rng([spec["seed"], oi, ci, role == "offline"])
            plans = plan_pushes(spec, vertices, rng, spec["pushes_per_set"])
            runs = [simulate(spec, model, plan, com) for plan in plans]
            h_true = float(np.mean([s["h_true"] for _, s in runs]))
            for plan, (_, s) in zip(plans, runs):
                sanity["pushes"].append({"object": obj["name"], "com": com.tolist(), "role": role, **s})
            pushes = [(rec, plan, role) for plan, (rec, _) in zip(plans, runs)]
            noises = [n for n in spec["noise"] if role == "online" or n["name"] == spec["offline_noise"]]
            for ri, rate in enumerate(rates):
                for ni, noise in enumerate(noises):
                    tag = "offline" if role == "offline" else f"{com_tag(com)}-{noise['name']}"
                    name = f"{obj['name']}-{tag}-{rate:g}hz"
                    setting = {
                        "name": name, "object": size, "pusher_radius": spec["pusher_radius"],
                        "material": "mujoco", "floor_friction": spec["floor_friction"],
                        "pusher_friction": spec["pusher_friction"], "com_offset": com.tolist(),
                        "h": h_true,
                        "generator": {"engine": f"mujoco {mujoco.__version__}", "object": obj["name"],
                                      "role": role, "com_index": ci, "noise": noise,
                                      "support_points": len(supports)},
                    }
                    noise_rng = np.random.default_rng([spec["seed"], oi, ci, ri, ni, role == "offline", 7])
                    write_set(os.path.join(args.out, name), setting, pushes, rate, noise, noise_rng)
                    sanity["sets"].append(name)
            print(f"{obj['name']:<11} {role:<7} COM ({com[0] * 1000:+5.1f},{com[1] * 1000:+5.1f}) mm  "
                  f"h {h_true * 1000:5.1f} mm  support {len(supports)} spheres", file=sys.stderr)
    with open(os.path.join(args.out, "sanity.json"), "w") as out:
        json.dump(sanity, out, indent=1)
    summarise(sanity["pushes"])


def summarise(pushes):
    def worst(key, fn=max):
        return fn(p[key] for p in pushes)
    print(f"{len(pushes)} pushes simulated")
    print(f"  moved by the push: min {worst('moved_m', min) * 1000:.0f} mm; "
          f"pusher touching the object: min {worst('contact_share', min):.0%} of the motion")
    print(f"  object speed / pusher speed (10 ms means): max {worst('max_speed_ratio'):.2f}, "
          f"median {np.median([p['max_speed_ratio'] for p in pushes]):.2f}")
    print(f"  inertia / friction (m|a| / mu m g, 20 ms): max {worst('max_inertia_ratio'):.3f}, "
          f"95th percentile max {worst('p95_inertia_ratio'):.3f}")
    print(f"  after the pusher stops: creep max {worst('creep_after_stop_mm'):.3f} mm, "
          f"turn max {worst('yaw_after_stop_deg'):.3f} deg; tilt max {worst('max_tilt_deg'):.2f} deg")
    print(f"  pressure centre from the COM at rest: max {worst('pressure_centre_error_mm'):.2f} mm")


if __name__ == "__main__":
    main()
