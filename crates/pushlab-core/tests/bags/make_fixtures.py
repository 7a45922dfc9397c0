#!/usr/bin/env python3
"""Writes the ROS 2 bag fixtures of pushlab's bag tests from push.csv, with writers independent of
pushlab: the `rosbags` library (rosbag2 folders with MCAP storage, uncompressed chunks) and
Foxglove's Python `mcap` library (zstd, lz4 and uncompressed chunks with CRCs).

Pinned versions (requirements.txt beside this file): rosbags 0.11.9, mcap 1.6.0, zstandard 0.25.0,
lz4 4.4.5, under Python 3.11. Run from this folder:

    python3 -m venv /tmp/venv && /tmp/venv/bin/pip install -r requirements.txt
    /tmp/venv/bin/python make_fixtures.py

push.csv is pushlab's native CSV (time,robot_x,robot_y,object_x,object_y,object_theta), 100 Hz.
Every bag stamps a row at BASE_S + time. The pusher is published at 100 Hz, the object at 50 Hz
(every other row), so the import resamples and interpolates. The object's yaw crosses ±π.
"""

import csv
import math
import shutil
from pathlib import Path

from mcap.writer import CompressionType, Writer as McapWriter
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
Vector3 = T['geometry_msgs/msg/Vector3']
Transform = T['geometry_msgs/msg/Transform']
TransformStamped = T['geometry_msgs/msg/TransformStamped']
TFMessage = T['tf2_msgs/msg/TFMessage']
Odometry = T['nav_msgs/msg/Odometry']
PoseWithCovariance = T['geometry_msgs/msg/PoseWithCovariance']
TwistWithCovariance = T['geometry_msgs/msg/TwistWithCovariance']
Twist = T['geometry_msgs/msg/Twist']
Pose2D = T['geometry_msgs/msg/Pose2D']
String = T['std_msgs/msg/String']

import numpy as np  # noqa: E402  (rosbags depends on numpy)


def rows():
    with open(HERE / 'push.csv', newline='') as f:
        return [[float(v) for v in r] for r in list(csv.reader(f))[1:]]


def ns(t):
    return BASE_S * 1_000_000_000 + round(t * 1e9)


def header(t, frame='world', zero=False):
    n = 0 if zero else ns(t)
    return Header(stamp=Time(sec=n // 1_000_000_000, nanosec=n % 1_000_000_000), frame_id=frame)


def quat(yaw):
    return Quaternion(x=0.0, y=0.0, z=math.sin(yaw / 2), w=math.cos(yaw / 2))


def pose(x, y, yaw):
    return Pose(position=Point(x=x, y=y, z=0.02), orientation=quat(yaw))


def pose_stamped(t, x, y, yaw, zero=False):
    return PoseStamped(header=header(t, zero=zero), pose=pose(x, y, yaw))


def transform(t, child, x, y, yaw):
    return TransformStamped(
        header=header(t),
        child_frame_id=child,
        transform=Transform(translation=Vector3(x=x, y=y, z=0.0), rotation=quat(yaw)),
    )


def fresh(name):
    path = HERE / name
    if path.exists():
        shutil.rmtree(path) if path.is_dir() else path.unlink()
    return path


def rosbag(name, write):
    with Writer(fresh(name), version=9, storage_plugin=StoragePlugin.MCAP) as w:
        write(w)


def ser(msg, typename):
    return TS.serialize_cdr(msg, typename)


def pose_stamped_bag(w):
    """PoseStamped for both; one pusher stamp left zero (log time used); an unreadable topic."""
    pusher = w.add_connection('/pusher/pose', PoseStamped.__msgtype__, typestore=TS)
    obj = w.add_connection('/object/pose', PoseStamped.__msgtype__, typestore=TS)
    note = w.add_connection('/note', String.__msgtype__, typestore=TS)
    for i, (t, rx, ry, ox, oy, th) in enumerate(rows()):
        msg = pose_stamped(t, rx, ry, 0.0, zero=(i == 7))
        w.write(pusher, ns(t), ser(msg, PoseStamped.__msgtype__))
        if i % 2 == 0:
            w.write(obj, ns(t), ser(pose_stamped(t, ox, oy, th), PoseStamped.__msgtype__))
        if i % 20 == 0:
            w.write(note, ns(t), ser(String(data=f'row {i}'), String.__msgtype__))


def tf_bag(w):
    """/tf with the pusher tip every row and the object every other row, among another frame."""
    tf = w.add_connection('/tf', TFMessage.__msgtype__, typestore=TS)
    for i, (t, rx, ry, ox, oy, th) in enumerate(rows()):
        transforms = [transform(t, 'base_link', 0.0, 0.0, 0.0), transform(t, 'pusher_tip', rx, ry, 0.0)]
        if i % 2 == 0:
            transforms.append(transform(t, 'box', ox, oy, th))
        w.write(tf, ns(t), ser(TFMessage(transforms=transforms), TFMessage.__msgtype__))


def odometry_bag(w):
    """The object as nav_msgs/Odometry, the pusher as Pose2D (no header: log time is the time)."""
    pusher = w.add_connection('/pusher/pose2d', Pose2D.__msgtype__, typestore=TS)
    obj = w.add_connection('/object/odom', Odometry.__msgtype__, typestore=TS)
    zero_twist = TwistWithCovariance(
        twist=Twist(linear=Vector3(x=0.0, y=0.0, z=0.0), angular=Vector3(x=0.0, y=0.0, z=0.0)),
        covariance=np.zeros(36),
    )
    for i, (t, rx, ry, ox, oy, th) in enumerate(rows()):
        w.write(pusher, ns(t), ser(Pose2D(x=rx, y=ry, theta=0.0), Pose2D.__msgtype__))
        if i % 2 == 0:
            odom = Odometry(
                header=header(t, 'odom'),
                child_frame_id='box',
                pose=PoseWithCovariance(pose=pose(ox, oy, th), covariance=np.zeros(36)),
                twist=zero_twist,
            )
            w.write(obj, ns(t), ser(odom, Odometry.__msgtype__))


def shifted(shift):
    return [[r[0] + shift, *r[1:]] for r in rows()]


def mcap_file(name, compression, repeats=(0.0,)):
    """PoseStamped for both, in small chunks, with Foxglove's Python writer; the CSV's rows once per
    entry of `repeats`, shifted by it in seconds (two entries: two pushes with a pause between)."""
    typename = PoseStamped.__msgtype__
    msgdef, _ = TS.generate_msgdef(typename)
    with open(fresh(name), 'wb') as f:
        w = McapWriter(f, compression=compression, chunk_size=4096)
        w.start(profile='ros2', library='make_fixtures.py')
        schema = w.register_schema(name=typename, encoding='ros2msg', data=msgdef.encode())
        pusher = w.register_channel(topic='/pusher/pose', message_encoding='cdr', schema_id=schema)
        obj = w.register_channel(topic='/object/pose', message_encoding='cdr', schema_id=schema)
        for i, (t, rx, ry, ox, oy, th) in ((i, r) for shift in repeats for i, r in enumerate(shifted(shift))):
            w.add_message(pusher, log_time=ns(t), publish_time=ns(t), data=ser(pose_stamped(t, rx, ry, 0.0), typename))
            if i % 2 == 0:
                w.add_message(obj, log_time=ns(t), publish_time=ns(t), data=ser(pose_stamped(t, ox, oy, th), typename))
        w.finish()


def main():
    rosbag('pose_stamped', pose_stamped_bag)
    rosbag('tf', tf_bag)
    rosbag('odometry', odometry_bag)
    mcap_file('zstd.mcap', CompressionType.ZSTD)
    mcap_file('lz4.mcap', CompressionType.LZ4)
    # Uncompressed chunks with their CRC (rosbags writes none), for the bad-CRC test.
    mcap_file('crc.mcap', CompressionType.NONE)
    # Two pushes, the second starting 2.5 s after the first (a 1.3 s pause), for --split-gap.
    mcap_file('gap.mcap', CompressionType.ZSTD, repeats=(0.0, 2.5))


if __name__ == '__main__':
    main()
