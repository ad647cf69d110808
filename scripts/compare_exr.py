#!/usr/bin/env python3
"""Compares linear images (EXR) per pixel: each image's mean, the mean of
the per-pixel difference and the RMSE of each pair against the first
image (the reference) or pairwise. Used by scripts/bench_path.sh.

  compare_exr.py REF.exr A.exr [B.exr ...]"""
import sys
import numpy as np
import mitsuba as mi

mi.set_variant('scalar_rgb')


def load(path):
    return np.array(mi.Bitmap(path))[..., :3].astype(np.float64)


def main():
    ref = load(sys.argv[1])
    print(f'{sys.argv[1]}: mean {ref.mean():.5f}')
    for p in sys.argv[2:]:
        a = load(p)
        d = a - ref
        print(f'{p}: mean {a.mean():.5f} mean_diff {d.mean():+.5f} rmse {np.sqrt((d * d).mean()):.5f}')


if __name__ == '__main__':
    main()
