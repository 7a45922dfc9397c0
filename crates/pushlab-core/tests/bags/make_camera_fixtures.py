#!/usr/bin/env python3
"""Writes the camera bag fixtures of pushlab's camera tests with writers independent of pushlab:
the `rosbags` library (rosbag2 folders, MCAP storage) and Pillow's JPEG and PNG encoders.

Each image is drawn from a known pose: a white disc of radius 6 px on a dark table at the pixel
where the pusher was at the image's header stamp (push.csv interpolated linearly), so a test can
check that the image shown at a time was taken at that time. The mapping, metres to pixels, for
images of 160 x 120:

    u = 80 + 1000 * (x + 0.05)        v = 60 - 1000 * y

Pinned versions: requirements.txt beside this file (rosbags, numpy, pillow), under Python 3.11.
Run from this folder:

    python3 -m venv /tmp/venv-cam && /tmp/venv-cam/bin/pip install -r requirements.txt
    /tmp/venv-cam/bin/python make_camera_fixtures.py

camera/: /pusher/pose (100 Hz) and /object/pose (50 Hz) PoseStamped as in pose_stamped/, and
  /camera/image/compressed  sensor_msgs/msg/CompressedImage, format "jpeg", 25 Hz, stamps at
                            0.013 + k / 25 s (off the pose grid), logged 5 ms after their stamp
  /camera/image_raw         sensor_msgs/msg/Image rgb8, 10 Hz, stamps at 0.007 + k / 10 s
  /depth/image_mono16       sensor_msgs/msg/Image mono16 (big-endian false), 10 Hz, same stamps,
                            the disc 60000 on 1000
camera_bad/: the same poses, and
  /camera/image/compressed  5 JPEG frames at 0.1 + k / 5 s; frame 2 is a JPEG header followed by
                            garbage
  /camera/image_raw         5 rgb8 frames at the same stamps; frame 3 holds half its rows' bytes
  /camera/yuv               3 frames of encoding "yuv422", which pushlab does not read
"""

import csv
import io
import math
import shutil
from pathlib import Path

import numpy as np
from PIL import Image as PilImage
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import Stores, get_typestore

HERE = Path(__file__).resolve().parent
BASE_S = 1_700_000_000
TS = get_typestore(Stores.ROS2_HUMBLE)
T = TS.types
Time = T['builtin_interfaces/msg/Time']
Header = T['std_msgs/msg/Header']
Point = T['geometry_msgs/msg/Point']
Quaternion = T['geometry_msgs/msg/Quaternion']
Pose = T['geometry_msgs/msg/Pose']
PoseStamped = T['geometry_msgs/msg/PoseStamped']
CompressedImage = T['sensor_msgs/msg/CompressedImage']
Image = T['sensor_msgs/msg/Image']

WIDTH, HEIGHT, RADIUS = 160, 120, 6.0


def rows():
    with open(HERE / 'push.csv', newline='') as f:
        return [[float(v) for v in r] for r in list(csv.reader(f))[1:]]


ROWS = rows()


def ns(t):
    return BASE_S * 1_000_000_000 + round(t * 1e9)


def header(t, frame='camera'):
    n = ns(t)
    return Header(stamp=Time(sec=n // 1_000_000_000, nanosec=n % 1_000_000_000), frame_id=frame)


def pusher_at(t):
    """The pusher's (x, y) at t, push.csv interpolated linearly."""
    for a, b in zip(ROWS, ROWS[1:]):
        if a[0] <= t <= b[0]:
            s = (t - a[0]) / (b[0] - a[0])
            return a[1] + s * (b[1] - a[1]), a[2] + s * (b[2] - a[2])
    raise ValueError(f'{t} is outside push.csv')


def pixel_of(x, y):
    return 80 + 1000 * (x + 0.05), 60 - 1000 * y


def disc(t, on=255, off=24):
    """A HEIGHT x WIDTH array: `on` within RADIUS of the pusher's pixel at t, else `off`."""
    u, v = pixel_of(*pusher_at(t))
    ys, xs = np.mgrid[0:HEIGHT, 0:WIDTH]
    inside = (xs + 0.5 - u) ** 2 + (ys + 0.5 - v) ** 2 <= RADIUS ** 2
    return np.where(inside, on, off)


def jpeg(t):
    gray = disc(t).astype(np.uint8)
    rgb = np.stack([gray, gray, gray], axis=-1)
    out = io.BytesIO()
    PilImage.fromarray(rgb).save(out, 'JPEG', quality=95)
    return out.getvalue()


def ser(msg, typename):
    return TS.serialize_cdr(msg, typename)


def compressed(t, data):
    return CompressedImage(header=header(t), format='jpeg', data=np.frombuffer(data, np.uint8))


def raw(t, encoding, pixels, step, height=HEIGHT, width=WIDTH):
    return Image(header=header(t), height=height, width=width, encoding=encoding, is_bigendian=0,
                 step=step, data=np.frombuffer(pixels, np.uint8))


def rgb8(t):
    gray = disc(t).astype(np.uint8)
    return np.stack([gray, gray // 2, gray], axis=-1).tobytes()


def write_poses(w):
    pusher = w.add_connection('/pusher/pose', PoseStamped.__msgtype__, typestore=TS)
    obj = w.add_connection('/object/pose', PoseStamped.__msgtype__, typestore=TS)
    for i, (t, rx, ry, ox, oy, th) in enumerate(ROWS):
        def pose(x, y, yaw):
            return PoseStamped(header=header(t, 'world'), pose=Pose(
                position=Point(x=x, y=y, z=0.0),
                orientation=Quaternion(x=0.0, y=0.0, z=math.sin(yaw / 2), w=math.cos(yaw / 2))))
        w.write(pusher, ns(t), ser(pose(rx, ry, 0.0), PoseStamped.__msgtype__))
        if i % 2 == 0:
            w.write(obj, ns(t), ser(pose(ox, oy, th), PoseStamped.__msgtype__))


def fresh(name):
    path = HERE / name
    if path.exists():
        shutil.rmtree(path)
    return path


def camera_bag(w):
    write_poses(w)
    jpg = w.add_connection('/camera/image/compressed', CompressedImage.__msgtype__, typestore=TS)
    rgb = w.add_connection('/camera/image_raw', Image.__msgtype__, typestore=TS)
    depth = w.add_connection('/depth/image_mono16', Image.__msgtype__, typestore=TS)
    last = ROWS[-1][0]
    k = 0
    while 0.013 + k / 25 <= last:
        t = 0.013 + k / 25
        w.write(jpg, ns(t + 0.005), ser(compressed(t, jpeg(t)), CompressedImage.__msgtype__))
        k += 1
    k = 0
    while 0.007 + k / 10 <= last:
        t = 0.007 + k / 10
        w.write(rgb, ns(t), ser(raw(t, 'rgb8', rgb8(t), 3 * WIDTH), Image.__msgtype__))
        mono16 = disc(t, on=60000, off=1000).astype('<u2').tobytes()
        w.write(depth, ns(t), ser(raw(t, 'mono16', mono16, 2 * WIDTH), Image.__msgtype__))
        k += 1


def camera_bad_bag(w):
    write_poses(w)
    jpg = w.add_connection('/camera/image/compressed', CompressedImage.__msgtype__, typestore=TS)
    rgb = w.add_connection('/camera/image_raw', Image.__msgtype__, typestore=TS)
    yuv = w.add_connection('/camera/yuv', Image.__msgtype__, typestore=TS)
    for k in range(5):
        t = 0.1 + k / 5
        data = jpeg(t)
        if k == 2:
            data = data[:20] + bytes((i * 37) % 251 for i in range(400))
        w.write(jpg, ns(t), ser(compressed(t, data), CompressedImage.__msgtype__))
        pixels = rgb8(t)
        if k == 3:
            pixels = pixels[: len(pixels) // 2]
        w.write(rgb, ns(t), ser(raw(t, 'rgb8', pixels, 3 * WIDTH), Image.__msgtype__))
        if k < 3:
            w.write(yuv, ns(t), ser(raw(t, 'yuv422', bytes(2 * WIDTH * HEIGHT), 2 * WIDTH),
                                    Image.__msgtype__))


def fuzz_seeds():
    """Seeds of the `image_message` fuzz target: CDR payloads of each kind, good and bad."""
    seeds = HERE.parent.parent.parent.parent / 'fuzz' / 'seeds' / 'image_message'
    seeds.mkdir(parents=True, exist_ok=True)
    t = 0.4
    payloads = {
        'compressed-jpeg': ser(compressed(t, jpeg(t)), CompressedImage.__msgtype__),
        'raw-rgb8': ser(raw(t, 'rgb8', rgb8(t), 3 * WIDTH), Image.__msgtype__),
        'raw-mono16': ser(raw(t, 'mono16', disc(t, 60000, 1000).astype('<u2').tobytes(), 2 * WIDTH),
                          Image.__msgtype__),
        'raw-rgb8-truncated': ser(raw(t, 'rgb8', rgb8(t)[:5000], 3 * WIDTH), Image.__msgtype__),
        'raw-yuv422': ser(raw(t, 'yuv422', bytes(64), 2 * WIDTH, height=2, width=16), Image.__msgtype__),
    }
    for name, payload in payloads.items():
        (seeds / name).write_bytes(bytes(payload))


fuzz_seeds()
for name, write in [('camera', camera_bag), ('camera_bad', camera_bad_bag)]:
    with Writer(fresh(name), version=9, storage_plugin=StoragePlugin.MCAP) as w:
        write(w)
    print(name, sum(p.stat().st_size for p in (HERE / name).iterdir()), 'bytes')
