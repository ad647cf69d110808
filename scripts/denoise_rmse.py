#!/usr/bin/env python3
"""RMSE of linear EXR images against a reference: the R, G, B channels of
each (the colour a frame shows, denoised or not), over every pixel.

  denoise_rmse.py REF.exr IMG.exr [IMG.exr ...]

Needs OpenEXR and numpy (the OIDN environment of scripts/bench_denoise.sh
has both)."""
import sys

import numpy as np
import OpenEXR


def rgb(path):
    with OpenEXR.File(path, separate_channels=True) as f:
        ch = f.parts[0].channels
        return np.stack([ch[c].pixels for c in 'RGB'], -1).astype(np.float64)


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    ref = rgb(sys.argv[1])
    for path in sys.argv[2:]:
        x = rgb(path)
        if x.shape != ref.shape:
            sys.exit(f'{path}: {x.shape[1]}x{x.shape[0]}, the reference {ref.shape[1]}x{ref.shape[0]}')
        rmse = np.sqrt(np.mean((x - ref) ** 2))
        print(f'{path}: rmse {rmse:.5f} mean {x.mean():.5f} (reference {ref.mean():.5f})')


if __name__ == '__main__':
    main()
