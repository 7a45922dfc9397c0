"""Push-T fixtures from the real gym-pusht environment, for the zarr and LeRobot importers' tests.

A scripted pusher drives gym-pusht's `PushTEnv` (its action is a target position the agent is
PD-controlled to, 10 actions per second): each episode places the T somewhere in the arena, puts
the agent beside one face of the T and moves the target straight through that face, so that the
pushes together hit every face (the eight edges of the outline, the notches' faces included).
Each step records the environment's true state read from the pymunk bodies (agent position, the
block's `Body.position` — the T's local origin, the middle of the bar's outer edge — and its angle,
unwrapped), the T's eight corner keypoints (`PushTEnv.get_keypoints`) and the action, and writes:

- `replay.zarr`: a zarr v2 replay buffer in Diffusion Policy's `ReplayBuffer` layout: `data/state`
  (agent x, y, block x, y, angle; float32), `data/action`, `data/keypoint` (here the T's 8 corners;
  Diffusion Policy's own files hold 9 keypoints of its keypoint manager), `data/img` (96 × 96 RGB,
  as Diffusion Policy renders them) and `meta/episode_ends` (int64, uncompressed). Compressors as
  Diffusion Policy uses them: blosc zstd with bit-shuffle (its 'disk' setting) for the numbers,
  blosc lz4 without shuffle (its default) for the images, several chunks along time.
- `lerobot-v2.1/` and `lerobot-v3.0/`: the same episodes as LeRobot datasets in the layout of
  `lerobot/pusht_keypoints` (`observation.state` = agent position, `observation.environment_state`
  = the 8 corners, x0, y0, x1, y1 …; `action`, timestamps, indexes), parquet written by pyarrow
  (snappy, as LeRobot's writers leave it), and the same 96 × 96 renders as `data/img` as the
  `observation.image` video feature: v3.0 as LeRobot writes it (AV1 by SVT-AV1, key frame every 2
  frames, crf 30, yuv420p; one file holding every episode, each episode's `from_timestamp` in the
  episodes table), v2.1 in H.264 (libx264, crf 23), one file per episode — two codecs a reader
  meets. Encoded by the ffmpeg binary pinned in `imageio-ffmpeg`, single-threaded and bit-exact
  so that the files regenerate identically.
- `lerobot-v2.1-images/` and `lerobot-v3.0-images/`: the first two episodes as
  `lerobot/pusht_image` keeps its renders: the `observation.image` feature of dtype `image`, each
  frame a PNG inside the parquet file (the struct of `bytes` and `path` Hugging Face `datasets`
  writes), no videos; v3.0 both episodes in one file. PNG by OpenCV.
- `truth.json`: per episode and frame, the state in float64 straight from pymunk, the local
  keypoints in `get_keypoints`' order, and the body's COM, mass and moment.

    python3 -m venv /tmp/pusht-venv && /tmp/pusht-venv/bin/pip install -r requirements.txt
    /tmp/pusht-venv/bin/python make_fixtures.py                       # the committed fixtures
    /tmp/pusht-venv/bin/python make_fixtures.py --out DIR --episodes 80 --steps 40 --seed 1 --no-img
    /tmp/pusht-venv/bin/python make_fixtures.py --out DIR ... --com-px 30,15   # the COM moved

Same arguments, same files (the pushes are drawn from a seeded generator; pymunk is deterministic).
"""

import argparse
import json
import math
import os
import shutil

import subprocess

import cv2
import imageio_ffmpeg
import numcodecs
import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import zarr
from gym_pusht.envs.pusht import PushTEnv

FPS = 10
AGENT_RADIUS = 15.0
# The T's outline in pymunk's local frame, counter-clockwise; edge i runs from vertex i to i + 1.
OUTLINE = [(-60, 0), (60, 0), (60, 30), (15, 30), (15, 120), (-15, 120), (-15, 30), (-60, 30)]
# Where along each edge a contact may be, as fractions, so that the agent's disc fits beside it
# (the notches' faces: clear of the stem and of the bar).
EDGE_RANGES = {
    0: (0.15, 0.85),
    1: (0.25, 0.75),
    2: (0.0, 0.6),
    3: (0.2, 0.8),
    4: (0.2, 0.8),
    5: (0.2, 0.8),
    6: (0.4, 1.0),
    7: (0.25, 0.75),
}


def rotate(v, angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def push_plan(rng, edge, steps):
    """The block's pose and the agent's targets of one push into `edge`."""
    a, b = np.array(OUTLINE[edge], float), np.array(OUTLINE[(edge + 1) % 8], float)
    lo, hi = EDGE_RANGES[edge]
    contact = a + (b - a) * rng.uniform(lo, hi)
    tangent = (b - a) / np.linalg.norm(b - a)
    normal = np.array([tangent[1], -tangent[0]])  # outward: the outline is counter-clockwise
    angle = rng.uniform(-np.radians(20), np.radians(20))
    direction = -rotate(normal, angle)
    start_local = contact + normal * (AGENT_RADIUS + 6.0)
    block_angle = rng.uniform(-math.pi, math.pi)
    block_pos = np.array([256.0, 256.0]) + rng.uniform(-40, 40, size=2)
    start = block_pos + rotate(start_local, block_angle)
    speed = rng.uniform(30.0, 60.0) / FPS  # px per step
    targets = [start + rotate(direction, block_angle) * speed * (k + 1) for k in range(steps)]
    return block_pos, block_angle, start, targets


def run_episode(env, rng, edge, steps, with_img, com_px=None):
    env.reset(seed=0)
    if com_px is not None:
        # A block whose mass sits elsewhere in the same outline (its moment about the COM kept):
        # what online learning of the COM offset is for.
        env.block.center_of_gravity = com_px
    block_pos, block_angle, start, targets = push_plan(rng, edge, steps)
    # Angle before position: pymunk turns a body about its COM, so this order puts the local
    # origin exactly where asked.
    env.block.angle = block_angle
    env.block.position = tuple(block_pos)
    env.agent.position = tuple(start)
    env.agent.velocity = (0, 0)
    env.space.step(env.dt)
    frames = []
    for target in targets:
        frame = {
            "agent": list(env.agent.position),
            "block": list(env.block.position),
            "angle": float(env.block.angle),
            "keypoints": PushTEnv.get_keypoints(env._block_shapes).tolist(),
            "action": [float(target[0]), float(target[1])],
        }
        if with_img:
            frame["img"] = env._render(visualize=False)
        frames.append(frame)
        env.step(np.array(target))
    return {"edge": edge, "frames": frames}


def write_zarr(path, episodes, with_img):
    state = np.array(
        [f["agent"] + f["block"] + [f["angle"]] for e in episodes for f in e["frames"]], np.float32
    )
    action = np.array([f["action"] for e in episodes for f in e["frames"]], np.float32)
    keypoint = np.array([f["keypoints"] for e in episodes for f in e["frames"]], np.float32)
    ends = np.cumsum([len(e["frames"]) for e in episodes]).astype(np.int64)
    disk = numcodecs.Blosc(cname="zstd", clevel=5, shuffle=numcodecs.Blosc.BITSHUFFLE)
    default = numcodecs.Blosc(cname="lz4", clevel=5, shuffle=numcodecs.Blosc.NOSHUFFLE)
    root = zarr.open_group(zarr.DirectoryStore(path), mode="w")
    data, meta = root.create_group("data"), root.create_group("meta")
    data.array("state", state, chunks=(64, 5), compressor=disk)
    data.array("action", action, chunks=(64, 2), compressor=disk)
    data.array("keypoint", keypoint, chunks=(64, 8, 2), compressor=disk)
    if with_img:
        img = np.stack([f["img"] for e in episodes for f in e["frames"]]).astype(np.uint8)
        data.array("img", img, chunks=(32, 96, 96, 3), compressor=default)
    meta.array("episode_ends", ends, chunks=ends.shape, compressor=None)


FEATURES = {
    "observation.state": {"dtype": "float32", "shape": [2], "names": {"motors": ["x", "y"]}},
    "observation.environment_state": {"dtype": "float32", "shape": [16], "names": None},
    "action": {"dtype": "float32", "shape": [2], "names": {"motors": ["x", "y"]}},
    "episode_index": {"dtype": "int64", "shape": [1], "names": None},
    "frame_index": {"dtype": "int64", "shape": [1], "names": None},
    "timestamp": {"dtype": "float32", "shape": [1], "names": None},
    "next.reward": {"dtype": "float32", "shape": [1], "names": None},
    "next.done": {"dtype": "bool", "shape": [1], "names": None},
    "next.success": {"dtype": "bool", "shape": [1], "names": None},
    "index": {"dtype": "int64", "shape": [1], "names": None},
    "task_index": {"dtype": "int64", "shape": [1], "names": None},
}
TASK = "Push the T-shaped block onto the T-shaped target."
VIDEO = "observation.image"
# How each layout's videos are encoded: LeRobot's own settings for v3.0, H.264 for v2.1.
CODECS = {
    "v2.1": ("h264", ["-c:v", "libx264", "-g", "2", "-crf", "23", "-threads", "1"]),
    "v3.0": ("av1", ["-c:v", "libsvtav1", "-g", "2", "-crf", "30", "-svtav1-params", "lp=1"]),
}


def video_feature(version):
    return {
        "dtype": "video",
        "shape": [96, 96, 3],
        "names": ["height", "width", "channel"],
        "info": {
            "video.fps": float(FPS),
            "video.height": 96,
            "video.width": 96,
            "video.channels": 3,
            "video.codec": CODECS[version][0],
            "video.pix_fmt": "yuv420p",
            "video.is_depth_map": False,
            "has_audio": False,
        },
    }


def write_video(path, frames, version):
    """The frames' renders as one MP4 at FPS, encoded as the layout's CODECS say."""
    os.makedirs(os.path.dirname(path), exist_ok=True)
    command = [imageio_ffmpeg.get_ffmpeg_exe(), "-y", "-loglevel", "error", "-f", "rawvideo"]
    command += ["-pix_fmt", "rgb24", "-s", "96x96", "-r", str(FPS), "-i", "-"]
    command += CODECS[version][1] + ["-pix_fmt", "yuv420p", "-fflags", "+bitexact"]
    command += ["-map_metadata", "-1", "-flags:v", "+bitexact", path]
    pixels = np.stack([f["img"] for f in frames]).astype(np.uint8).tobytes()
    quiet = dict(os.environ, SVT_LOG="1")  # SVT-AV1 prints its settings otherwise
    subprocess.run(command, input=pixels, check=True, env=quiet)


def episode_table(episode, episode_index, first_index):
    frames = episode["frames"]
    n = len(frames)

    def vectors(rows, width):
        flat = pa.array(np.array(rows, np.float32).reshape(-1))
        return pa.FixedSizeListArray.from_arrays(flat, width)

    return pa.table(
        {
            "observation.state": vectors([f["agent"] for f in frames], 2),
            "observation.environment_state": vectors(
                [np.array(f["keypoints"]).reshape(-1) for f in frames], 16
            ),
            "action": vectors([f["action"] for f in frames], 2),
            "episode_index": pa.array([episode_index] * n, pa.int64()),
            "frame_index": pa.array(range(n), pa.int64()),
            "timestamp": pa.array([k / FPS for k in range(n)], pa.float32()),
            "next.reward": pa.array([0.0] * n, pa.float32()),
            "next.done": pa.array([k == n - 1 for k in range(n)]),
            "next.success": pa.array([False] * n),
            "index": pa.array(range(first_index, first_index + n), pa.int64()),
            "task_index": pa.array([0] * n, pa.int64()),
        }
    )


def info(version, episodes, data_path, video_path):
    total = sum(len(e["frames"]) for e in episodes)
    features = dict(FEATURES)
    if video_path is not None:
        features[VIDEO] = video_feature(version)
    return {
        "codebase_version": version,
        "robot_type": "2d pointer",
        "total_episodes": len(episodes),
        "total_frames": total,
        "total_tasks": 1,
        "total_videos": len(episodes) if video_path is not None else 0,
        "total_chunks": 1,
        "chunks_size": 1000,
        "fps": FPS,
        "splits": {"train": f"0:{len(episodes)}"},
        "data_path": data_path,
        "video_path": video_path,
        "features": features,
    }


def write_lerobot_v21(path, episodes, with_img):
    os.makedirs(f"{path}/meta")
    os.makedirs(f"{path}/data/chunk-000")
    first = 0
    with open(f"{path}/meta/episodes.jsonl", "w") as out:
        for i, episode in enumerate(episodes):
            table = episode_table(episode, i, first)
            pq.write_table(table, f"{path}/data/chunk-000/episode_{i:06d}.parquet")
            if with_img:
                video = f"{path}/videos/chunk-000/{VIDEO}/episode_{i:06d}.mp4"
                write_video(video, episode["frames"], "v2.1")
            first += table.num_rows
            out.write(json.dumps({"episode_index": i, "tasks": [TASK], "length": table.num_rows}))
            out.write("\n")
    with open(f"{path}/meta/tasks.jsonl", "w") as out:
        out.write(json.dumps({"task_index": 0, "task": TASK}) + "\n")
    data_path = "data/chunk-{episode_chunk:03d}/episode_{episode_index:06d}.parquet"
    video_path = "videos/chunk-{episode_chunk:03d}/{video_key}/episode_{episode_index:06d}.mp4"
    with open(f"{path}/meta/info.json", "w") as out:
        json.dump(info("v2.1", episodes, data_path, video_path if with_img else None), out, indent=4)


IMAGE_EPISODES = 2
IMAGE_TYPE = pa.struct([("bytes", pa.binary()), ("path", pa.string())])


def with_pngs(table, episode):
    """`table` with the episode's renders as PNG cells of an `image` column, as `datasets` writes."""
    pngs = []
    for f in episode["frames"]:
        bgr = cv2.cvtColor(np.asarray(f["img"], np.uint8), cv2.COLOR_RGB2BGR)
        ok, png = cv2.imencode(".png", bgr)
        assert ok
        pngs.append({"bytes": png.tobytes(), "path": None})
    return table.append_column(VIDEO, pa.array(pngs, IMAGE_TYPE))


def image_feature(meta):
    meta["features"][VIDEO] = {
        "dtype": "image",
        "shape": [96, 96, 3],
        "names": ["height", "width", "channel"],
    }
    return meta


def write_lerobot_v21_images(path, episodes):
    """The first IMAGE_EPISODES episodes with their renders as PNG in their parquet files."""
    os.makedirs(f"{path}/meta")
    os.makedirs(f"{path}/data/chunk-000")
    episodes = episodes[:IMAGE_EPISODES]
    first = 0
    with open(f"{path}/meta/episodes.jsonl", "w") as out:
        for i, episode in enumerate(episodes):
            table = with_pngs(episode_table(episode, i, first), episode)
            pq.write_table(table, f"{path}/data/chunk-000/episode_{i:06d}.parquet")
            first += table.num_rows
            out.write(json.dumps({"episode_index": i, "tasks": [TASK], "length": table.num_rows}))
            out.write("\n")
    with open(f"{path}/meta/tasks.jsonl", "w") as out:
        out.write(json.dumps({"task_index": 0, "task": TASK}) + "\n")
    data_path = "data/chunk-{episode_chunk:03d}/episode_{episode_index:06d}.parquet"
    meta = image_feature(info("v2.1", episodes, data_path, None))
    with open(f"{path}/meta/info.json", "w") as out:
        json.dump(meta, out, indent=4)


def write_lerobot_v30(path, episodes, with_img, images_in_parquet=False):
    os.makedirs(f"{path}/meta/episodes/chunk-000")
    os.makedirs(f"{path}/data/chunk-000")
    tables, rows, first = [], [], 0
    for i, episode in enumerate(episodes):
        table = episode_table(episode, i, first)
        if images_in_parquet:
            table = with_pngs(table, episode)
        tables.append(table)
        rows.append(
            {
                "episode_index": i,
                "tasks": [TASK],
                "length": table.num_rows,
                "data/chunk_index": 0,
                "data/file_index": 0,
                "dataset_from_index": first,
                "dataset_to_index": first + table.num_rows,
                "meta/episodes/chunk_index": 0,
                "meta/episodes/file_index": 0,
            }
        )
        if with_img:
            rows[-1].update(
                {
                    f"videos/{VIDEO}/chunk_index": 0,
                    f"videos/{VIDEO}/file_index": 0,
                    f"videos/{VIDEO}/from_timestamp": first / FPS,
                    f"videos/{VIDEO}/to_timestamp": (first + table.num_rows) / FPS,
                }
            )
        first += table.num_rows
    pq.write_table(pa.concat_tables(tables), f"{path}/data/chunk-000/file-000.parquet")
    if with_img:
        frames = [f for e in episodes for f in e["frames"]]
        write_video(f"{path}/videos/{VIDEO}/chunk-000/file-000.mp4", frames, "v3.0")
    pq.write_table(pa.Table.from_pylist(rows), f"{path}/meta/episodes/chunk-000/file-000.parquet")
    pq.write_table(
        pa.table({"task_index": pa.array([0], pa.int64()), "__index_level_0__": [TASK]}),
        f"{path}/meta/tasks.parquet",
    )
    data_path = "data/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet"
    video_path = "videos/{video_key}/chunk-{chunk_index:03d}/file-{file_index:03d}.mp4"
    meta = info("v3.0", episodes, data_path, video_path if with_img else None)
    if images_in_parquet:
        image_feature(meta)
    meta.update({"data_files_size_in_mb": 100, "video_files_size_in_mb": 500})
    del meta["total_chunks"], meta["total_videos"]
    with open(f"{path}/meta/info.json", "w") as out:
        json.dump(meta, out, indent=4)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", default=os.path.dirname(os.path.abspath(__file__)))
    parser.add_argument("--episodes", type=int, default=8, help="pushes; faces taken in turn")
    parser.add_argument("--steps", type=int, default=24, help="frames per episode (10 per s)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--no-img", action="store_true", help="leave data/img out of the zarr")
    parser.add_argument(
        "--com-px",
        type=lambda s: tuple(float(v) for v in s.split(",")),
        help="move the block's centre of gravity to local X,Y px (gym-pusht's: 0,45)",
    )
    args = parser.parse_args()

    rng = np.random.default_rng(args.seed)
    env = PushTEnv(obs_type="state", render_mode="rgb_array")
    with_img = not args.no_img
    episodes = [
        run_episode(env, rng, i % 8, args.steps, with_img, args.com_px) for i in range(args.episodes)
    ]

    images = ["lerobot-v2.1-images", "lerobot-v3.0-images"]
    for name in ["replay.zarr", "lerobot-v2.1", "lerobot-v3.0"] + images:
        shutil.rmtree(os.path.join(args.out, name), ignore_errors=True)
    write_zarr(os.path.join(args.out, "replay.zarr"), episodes, with_img)
    write_lerobot_v21(os.path.join(args.out, "lerobot-v2.1"), episodes, with_img)
    write_lerobot_v30(os.path.join(args.out, "lerobot-v3.0"), episodes, with_img)
    if with_img:
        write_lerobot_v21_images(os.path.join(args.out, images[0]), episodes)
        first = episodes[:IMAGE_EPISODES]
        write_lerobot_v30(os.path.join(args.out, images[1]), first, False, images_in_parquet=True)

    env.reset(seed=0)
    if args.com_px is not None:
        env.block.center_of_gravity = args.com_px
    env.block.angle, env.block.position = 0.0, (0.0, 0.0)
    truth = {
        "fps": FPS,
        "agent_radius_px": AGENT_RADIUS,
        "block_center_of_gravity_px": list(env.block.center_of_gravity),
        "block_mass": env.block.mass,
        "block_moment_px2": env.block.moment,
        "local_keypoints_px": PushTEnv.get_keypoints(env._block_shapes).tolist(),
        "episodes": [
            {
                "edge": e["edge"],
                "agent": [f["agent"] for f in e["frames"]],
                "block": [f["block"] for f in e["frames"]],
                "angle": [f["angle"] for f in e["frames"]],
            }
            for e in episodes
        ],
    }
    with open(os.path.join(args.out, "truth.json"), "w") as out:
        json.dump(truth, out)


if __name__ == "__main__":
    main()
