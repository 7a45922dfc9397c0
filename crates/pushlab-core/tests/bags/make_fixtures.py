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


def quat_matrix(x, y, z, w):
    """The rotation matrix of a unit quaternion."""
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def matrix_quat(r):
    """A unit quaternion (x, y, z, w) of a rotation matrix (Shepperd's method)."""
    trace = r[0, 0] + r[1, 1] + r[2, 2]
    if trace > 0:
        s = 2 * math.sqrt(trace + 1)
        return ((r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s, s / 4)
    i = int(np.argmax([r[0, 0], r[1, 1], r[2, 2]]))
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2 * math.sqrt(1 + r[i, i] - r[j, j] - r[k, k])
    q = [0.0, 0.0, 0.0]
    q[i] = s / 4
    q[j] = (r[j, i] + r[i, j]) / s
    q[k] = (r[k, i] + r[i, k]) / s
    return (*q, (r[k, j] - r[j, k]) / s)


def axis_angle(axis, angle):
    n = np.array(axis, dtype=float) / np.linalg.norm(axis)
    return (*(n * math.sin(angle / 2)), math.cos(angle / 2))


def iso(translation, q):
    """A 4x4 homogeneous `parent_from_child` from a translation and a quaternion (x, y, z, w)."""
    m = np.eye(4)
    m[:3, :3] = quat_matrix(*q)
    m[:3, 3] = translation
    return m


def planar(x, y, z, yaw):
    return iso((x, y, z), (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2)))


def transform3(t, parent, child, m):
    """A TransformStamped of a 4x4 `parent_from_child`."""
    x, y, z, w = matrix_quat(m[:3, :3])
    return TransformStamped(
        header=header(t, parent),
        child_frame_id=child,
        transform=Transform(
            translation=Vector3(x=m[0, 3], y=m[1, 3], z=m[2, 3]),
            rotation=Quaternion(x=x, y=y, z=z, w=w),
        ),
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


def tf_tree_bag(w):
    """A transform tree, as a robot arm and mocap publish it. /tf_static: world -> base_link (moved
    and turned) and tool0 -> tip (an offset along a tool0 that points down and is tilted, so tool0
    itself is not planar but the tip is). /tf: base_link -> tool0 at 100 Hz, computed from the CSV's
    pusher so that world -> base_link -> tool0 -> tip gives it back; world -> object at 50 Hz (the
    CSV's object); world -> table, a tilted table that moves and turns about a fixed axis at constant
    speed, published 5 ms after each row, with table -> object_on_table at 50 Hz such that the
    object on the table is again the CSV's object (an import interpolates the table at the object's
    stamps, exactly, as lerp and slerp are exact for this motion; its first object pose falls before
    the table's first transform); odom -> stray, a frame of another root."""
    tf = w.add_connection('/tf', TFMessage.__msgtype__, typestore=TS)
    tf_static = w.add_connection('/tf_static', TFMessage.__msgtype__, typestore=TS)
    world_from_base = planar(0.4, -0.3, 0.0, 0.6)
    tool0_from_tip = iso((0.01, -0.02, 0.15), matrix_quat(
        quat_matrix(*axis_angle((1, 0, 0), math.pi)) @ quat_matrix(*axis_angle((0, 1, 0), 0.2))))
    static = TFMessage(transforms=[
        transform3(0.0, 'world', 'base_link', world_from_base),
        transform3(0.0, 'tool0', 'tip', tool0_from_tip),
    ])
    w.write(tf_static, ns(0.0), ser(static, TFMessage.__msgtype__))

    def world_from_table(t):
        return iso((0.3 + 0.05 * t, -0.1 + 0.02 * t, 0.01), axis_angle((0.1, 0.2, 1.0), 0.2 + 0.5 * t))

    for i, (t, rx, ry, ox, oy, th) in enumerate(rows()):
        world_from_tip = planar(rx, ry, 0.02, 0.0)
        base_from_tool0 = np.linalg.inv(world_from_base) @ world_from_tip @ np.linalg.inv(tool0_from_tip)
        transforms = [
            transform3(t, 'base_link', 'tool0', base_from_tool0),
            transform3(t, 'odom', 'stray', planar(0.1, 0.0, 0.0, 0.0)),
        ]
        if i % 2 == 0:
            world_from_object = planar(ox, oy, 0.0, th)
            transforms.append(transform3(t, 'world', 'object', world_from_object))
            table_from_object = np.linalg.inv(world_from_table(t)) @ world_from_object
            transforms.append(transform3(t, 'table', 'object_on_table', table_from_object))
        w.write(tf, ns(t), ser(TFMessage(transforms=transforms), TFMessage.__msgtype__))
        table = TFMessage(transforms=[transform3(t + 0.005, 'world', 'table', world_from_table(t + 0.005))])
        w.write(tf, ns(t + 0.005), ser(table, TFMessage.__msgtype__))


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
    rosbag('tf_tree', tf_tree_bag)
    rosbag('odometry', odometry_bag)
    mcap_file('zstd.mcap', CompressionType.ZSTD)
    mcap_file('lz4.mcap', CompressionType.LZ4)
    # Uncompressed chunks with their CRC (rosbags writes none), for the bad-CRC test.
    mcap_file('crc.mcap', CompressionType.NONE)
    # Two pushes, the second starting 2.5 s after the first (a 1.3 s pause), for --split-gap.
    mcap_file('gap.mcap', CompressionType.ZSTD, repeats=(0.0, 2.5))


if __name__ == '__main__':
    main()
