#!/usr/bin/env python3
"""Writes a real-size ROS 2 camera bag for pushlab's streaming-import experiment (issue 23): a
rosbag2 folder with one MCAP file holding a 30 Hz camera and two 100 Hz poses of a push.

    python3 generate.py OUT_FOLDER [--size-gb 4.0] [--chunks zstd|none] [--seed 1]

Written with `rosbags` (0.11.9, pinned in requirements.txt), independently of pushlab, the way
`ros2 bag record -s mcap` writes with its default storage settings as closely as rosbags can:

- rosbag2 folder, metadata.yaml version 9, MCAP storage, profile `ros2`, the message definitions
  in the schemas, one channel per topic with its QoS;
- chunked, each chunk followed by its message indexes, a summary with the chunk indexes and
  statistics: what lets a reader seek to the chunks of the topics it wants;
- zstd chunk compression (`Writer.set_compression(CompressionMode.STORAGE, ZSTD)`, rosbags' only
  chunk compression, at zstd's default level 3). ros2 bag's MCAP plugin without a preset opens
  `mcap::McapWriterOptions("ros2")`, whose defaults are zstd chunks at the default level, 768 KiB
  chunks and chunk CRCs. rosbags differs in two details it does not let us choose: it closes a
  chunk once it passes 1 MiB of uncompressed records (not 768 KiB) and writes no chunk CRC (0,
  "not computed", as the `zstd_fast` preset does). `--chunks none` writes uncompressed chunks
  instead, as `ros2 bag record` does with a storage config saying `compression: None`.

Topics, all stamped in their header (the log time is the stamp plus a receive delay of 1-3 ms):

- `/camera/image_raw/compressed`, `sensor_msgs/msg/CompressedImage`, 30 Hz, format `jpeg`. The
  frames are real 1280x720 JPEGs made with Pillow (quality 85, ~165 KB each, about the size of a
  colour camera's JPEG): 60 distinct images of a noisy table scene, cycled, each copy made a
  distinct file by a JPEG comment (COM segment) holding its frame number. The scene does not show
  the push. JPEG data barely compresses, so the chunks are about as large as the frames in them.
- `/pusher/pose` and `/object/pose`, `geometry_msgs/msg/PoseStamped`, 100 Hz each, frame `world`
  (the object's stamps 4 ms after the pusher's, as from two tracker clients): a 0.10 x 0.12 m box
  pushed quasi-statically around a circle of radius 0.3 m at 2.1 cm/s, its yaw swinging +/-0.15
  rad about the path's heading, by a 5 mm pusher touching its back face at an offset sweeping
  +/-2 cm; 0.2 mm and 5 mrad of Gaussian noise. A session of pushes: 50 s of pushing, then 5 s
  in which the poses are not published (the push script publishes them only while it pushes),
  then the next push from where the box stopped; the camera runs throughout. pushlab takes a push
  to be at most 600 s long, so the bag is imported with `--split-gap 1` (one push per 50 s).

Messages are written in log-time order, as a recorder receives them. The bag grows until its
messages hold `--size-gb` x 10^9 bytes (4.0: ~13.5 minutes, ~24,000 frames); `--size-gb 0.05`
makes a small one for trying the scripts.
"""

import argparse
import io
import math
import sys
import time
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw
from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin, Writer
from rosbags.typesys import Stores, get_typestore

TS = get_typestore(Stores.ROS2_HUMBLE)
T = TS.types
Time = T['builtin_interfaces/msg/Time']
Header = T['std_msgs/msg/Header']
Point = T['geometry_msgs/msg/Point']
Quaternion = T['geometry_msgs/msg/Quaternion']
Pose = T['geometry_msgs/msg/Pose']
PoseStamped = T['geometry_msgs/msg/PoseStamped']
CompressedImage = T['sensor_msgs/msg/CompressedImage']

CAMERA = '/camera/image_raw/compressed'
PUSHER = '/pusher/pose'
OBJECT = '/object/pose'
BASE_NS = 1_700_000_000 * 1_000_000_000
POSE_PERIOD_NS = 10_000_000  # 100 Hz
CAMERA_PERIOD_NS = 1_000_000_000 // 30  # 30 Hz (33.333 ms; stamps rounded to the nanosecond)
OBJECT_LAG_NS = 4_000_000
WIDTH, HEIGHT, DISTINCT_FRAMES = 1280, 720, 60

BOX_LENGTH, PUSHER_RADIUS = 0.12, 0.005
CIRCLE_CENTRE, CIRCLE_RADIUS, LOOP_S = (0.5, 0.0), 0.3, 90.0
PUSH_TICKS, PAUSE_TICKS = 5_000, 500  # 50 s of pushing, 5 s of pause (100 Hz ticks)


def header(ns, frame):
    return Header(stamp=Time(sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000), frame_id=frame)


def pose_stamped(ns, x, y, yaw):
    return PoseStamped(
        header=header(ns, 'world'),
        pose=Pose(
            position=Point(x=x, y=y, z=0.02),
            orientation=Quaternion(x=0.0, y=0.0, z=math.sin(yaw / 2), w=math.cos(yaw / 2)),
        ),
    )


def object_pose(t):
    """The box's centre and yaw at `t` seconds: around the circle, yaw swinging about the heading."""
    phase = 2 * math.pi * t / LOOP_S
    x = CIRCLE_CENTRE[0] + CIRCLE_RADIUS * math.cos(phase)
    y = CIRCLE_CENTRE[1] + CIRCLE_RADIUS * math.sin(phase)
    heading = phase + math.pi / 2
    yaw = heading + 0.15 * math.sin(2 * math.pi * t / 23.0)
    return x, y, heading, yaw


def pusher_pose(t):
    """The pusher's centre at `t`: on the box's back face (seen along its heading), offset sideways."""
    x, y, heading, yaw = object_pose(t)
    back = -(BOX_LENGTH / 2 + PUSHER_RADIUS)
    side = 0.02 * math.sin(2 * math.pi * t / 37.0)
    c, s = math.cos(yaw), math.sin(yaw)
    return x + c * back - s * side, y + s * back + c * side, heading


def jpeg_frames(rng):
    """DISTINCT_FRAMES real JPEGs of a noisy table scene with a box and a pusher on it."""
    yy, xx = np.mgrid[0:HEIGHT, 0:WIDTH]
    table = np.stack([
        120 + 40 * np.sin(xx / 90.0 + yy / 300.0),
        90 + 30 * np.sin(xx / 140.0),
        60 + 20 * np.cos(yy / 70.0),
    ], -1)
    frames = []
    for i in range(DISTINCT_FRAMES):
        pixels = np.clip(table + rng.normal(0, 8, (HEIGHT, WIDTH, 3)), 0, 255).astype(np.uint8)
        image = Image.fromarray(pixels)
        draw = ImageDraw.Draw(image)
        dx = 4 * i
        draw.rectangle([500 + dx, 300, 700 + dx, 420], fill=(200, 60, 40))
        draw.ellipse([460 + dx, 340, 490 + dx, 370], fill=(30, 30, 30))
        out = io.BytesIO()
        image.save(out, 'JPEG', quality=85)
        frames.append(out.getvalue())
    return frames


def with_comment(jpeg, text):
    """The JPEG with a COM segment right after its SOI marker: a distinct but equally valid file."""
    body = text.encode()
    return jpeg[:2] + b'\xff\xfe' + (len(body) + 2).to_bytes(2, 'big') + body + jpeg[2:]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('out', type=Path, help='the rosbag2 folder to write (must not exist)')
    parser.add_argument('--size-gb', type=float, default=4.0,
                        help='stop once the messages hold this many 10^9 bytes (default 4.0)')
    parser.add_argument('--chunks', choices=['zstd', 'none'], default='zstd',
                        help='chunk compression (default zstd)')
    parser.add_argument('--seed', type=int, default=1)
    args = parser.parse_args()
    if args.out.exists():
        sys.exit(f'{args.out}: already exists; remove it first')

    rng = np.random.default_rng(args.seed)
    started = time.perf_counter()
    frames = jpeg_frames(rng)
    target = args.size_gb * 1e9
    written = 0
    counts = {CAMERA: 0, PUSHER: 0, OBJECT: 0}

    def delay():
        return int(rng.integers(1_000_000, 3_000_000))

    writer = Writer(args.out, version=9, storage_plugin=StoragePlugin.MCAP)
    if args.chunks == 'zstd':
        writer.set_compression(CompressionMode.STORAGE, CompressionFormat.ZSTD)
    with writer:
        camera = writer.add_connection(CAMERA, CompressedImage.__msgtype__, typestore=TS)
        pusher = writer.add_connection(PUSHER, PoseStamped.__msgtype__, typestore=TS)
        obj = writer.add_connection(OBJECT, PoseStamped.__msgtype__, typestore=TS)
        tick, frame = 0, 0
        pending = []  # received, not yet written: (log time, connection, data)

        def flush(before_ns):
            """Writes, in log-time order, what was received before `before_ns`."""
            nonlocal pending, written
            pending.sort(key=lambda m: m[0])
            ready = [m for m in pending if m[0] < before_ns]
            pending = pending[len(ready):]
            for log_ns, connection, data in ready:
                writer.write(connection, log_ns, data)
                written += len(data)
                counts[connection.topic] += 1

        while written < target:
            # Everything stamped in this 10 ms tick; written once nothing later can be received first.
            ns = BASE_NS + tick * POSE_PERIOD_NS
            push, in_push = divmod(tick, PUSH_TICKS + PAUSE_TICKS)
            if in_push < PUSH_TICKS:
                # Time spent pushing so far: the box moves only while pushed.
                t = (push * PUSH_TICKS + in_push) * POSE_PERIOD_NS / 1e9
                px, py, pyaw = pusher_pose(t)
                msg = pose_stamped(ns, px + rng.normal(0, 2e-4), py + rng.normal(0, 2e-4),
                                   pyaw + rng.normal(0, 5e-3))
                pending.append((ns + delay(), pusher,
                                TS.serialize_cdr(msg, PoseStamped.__msgtype__)))
                ons = ns + OBJECT_LAG_NS
                ox, oy, _, oyaw = object_pose(t + OBJECT_LAG_NS / 1e9)
                msg = pose_stamped(ons, ox + rng.normal(0, 2e-4), oy + rng.normal(0, 2e-4),
                                   oyaw + rng.normal(0, 5e-3))
                pending.append((ons + delay(), obj,
                                TS.serialize_cdr(msg, PoseStamped.__msgtype__)))
            while frame * CAMERA_PERIOD_NS < (tick + 1) * POSE_PERIOD_NS:
                fns = BASE_NS + frame * CAMERA_PERIOD_NS
                jpeg = with_comment(frames[frame % DISTINCT_FRAMES], f'pushlab camera-bag frame {frame}')
                msg = CompressedImage(header=header(fns, 'camera'), format='jpeg',
                                      data=np.frombuffer(jpeg, dtype=np.uint8))
                pending.append((fns + delay(), camera,
                                TS.serialize_cdr(msg, CompressedImage.__msgtype__)))
                frame += 1
            tick += 1
            flush(BASE_NS + tick * POSE_PERIOD_NS + 1_000_000)
        flush(2**63)

    minutes = tick * POSE_PERIOD_NS / 60e9
    size = sum(f.stat().st_size for f in args.out.iterdir())
    print(f'{args.out}: {size / 1e9:.2f} GB on disk, {minutes:.1f} min, '
          + ', '.join(f'{topic} {n}' for topic, n in counts.items())
          + f', written in {time.perf_counter() - started:.0f} s')


if __name__ == '__main__':
    main()
