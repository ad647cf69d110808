#!/usr/bin/env python3
"""Converts the scans of ../shared/anchors/octomap_scans.py (`make`) from
.npz into a little-endian binary file that benches/memory.rs reads
without numpy:

    octomap_scans_export.py SCANS.npz OUT.bin

Layout (all little-endian):
    magic   8 bytes  b"LMSCANS1"
    views   u32      number of scans V
    edge    u32      window edge in pixels (64); counts[v] = edge*edge
                     when no ray of the view missed
    fov     f64      field of view in degrees (60, square window)
    then per view v = 0 .. V-1:
        origin  3 x f64   the eye
        look_at 3 x f64   eye + forward, forward = (cos a, 0, sin a),
                          a = 2 pi v / V (as octomap_scans.py's make)
        count   u32       points of the view
        points  count x 3 x f64, row-major pixel order (misses dropped)
"""
import struct
import sys

import numpy as np


def main(src, dst):
    data = np.load(src)
    origins, counts, points = data['origins'], data['counts'], data['points']
    views = len(origins)
    edge = int(round(np.sqrt(counts.max())))
    out = [b'LMSCANS1', struct.pack('<IId', views, edge, 60.0)]
    start = 0
    for v in range(views):
        a = 2 * np.pi * v / views
        eye = origins[v].astype('<f8')
        look = eye + np.array([np.cos(a), 0.0, np.sin(a)])
        n = int(counts[v])
        out.append(eye.tobytes())
        out.append(look.astype('<f8').tobytes())
        out.append(struct.pack('<I', n))
        out.append(points[start:start + n].astype('<f8').tobytes())
        start += n
    with open(dst, 'wb') as f:
        f.write(b''.join(out))
    print(f'views {views} edge {edge} points {start} -> {dst}')


if __name__ == '__main__':
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
