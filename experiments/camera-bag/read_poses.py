#!/usr/bin/env python3
"""Reads the two pose topics of a bag with `rosbags` as a user would: AnyReader, the connections
of the wanted topics, every message deserialised, each pose's stamp, x, y and yaw kept.

    python3 read_poses.py BAG [--pusher /pusher/pose] [--object /object/pose]

rosbags reads the MCAP summary and reads and decompresses only the chunks whose chunk index lists
a wanted channel (in the camera bag every chunk holds poses). The poses are kept in `array('d')`
columns (8 bytes a value), so the resident size is the reader's, not a list of Python objects'.
Prints the count per topic, the time span and the wall time of the read.
"""

import argparse
import math
import time
from array import array
from pathlib import Path

from rosbags.highlevel import AnyReader
from rosbags.typesys import Stores, get_typestore


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('bag', type=Path)
    parser.add_argument('--pusher', default='/pusher/pose')
    parser.add_argument('--object', default='/object/pose')
    args = parser.parse_args()

    started = time.perf_counter()
    columns = {topic: tuple(array('d') for _ in range(4)) for topic in (args.pusher, args.object)}
    with AnyReader([args.bag], default_typestore=get_typestore(Stores.ROS2_HUMBLE)) as reader:
        wanted = [c for c in reader.connections if c.topic in columns]
        missing = set(columns) - {c.topic for c in wanted}
        if missing:
            raise SystemExit(f'{args.bag}: no topic {", ".join(sorted(missing))}')
        for connection, _, raw in reader.messages(connections=wanted):
            msg = reader.deserialize(raw, connection.msgtype)
            stamp, position, q = msg.header.stamp, msg.pose.position, msg.pose.orientation
            t, x, y, yaw = columns[connection.topic]
            t.append(stamp.sec + stamp.nanosec * 1e-9)
            x.append(position.x)
            y.append(position.y)
            yaw.append(2 * math.atan2(q.z, q.w))
    elapsed = time.perf_counter() - started
    for topic, (t, *_) in columns.items():
        print(f'{topic}: {len(t)} poses, {t[-1] - t[0]:.2f} s' if t else f'{topic}: 0 poses')
    print(f'read in {elapsed:.2f} s')


if __name__ == '__main__':
    main()
