#!/usr/bin/env python3
"""Fails when a frame of the sample game has pixels that nothing was drawn on.

Usage: check_sky_covered.py DIR
Reads DIR/frame_*.png (matplotlib) and counts the pixels that are exactly black (0, 0, 0): the
clear colour, which the terrain, the sky and its skirt cover everywhere. Prints the count per
frame; exit 1 when any frame has one, 2 when there are no frames.
"""
import glob
import os
import sys

import matplotlib.image as image
import numpy as np


def main():
    if len(sys.argv) != 2:
        print("usage: check_sky_covered.py DIR", file=sys.stderr)
        return 2
    frames = sorted(glob.glob(os.path.join(sys.argv[1], "frame_*.png")))
    if not frames:
        print("check_sky_covered.py: no frame_*.png in %s" % sys.argv[1], file=sys.stderr)
        return 2
    uncovered = 0
    for path in frames:
        rgb = image.imread(path)[:, :, :3]
        black = int(np.all(rgb == 0, axis=2).sum())
        print("%s: %d black pixels" % (os.path.basename(path), black))
        uncovered += black
    print("uncovered=%d in %d frames" % (uncovered, len(frames)))
    return 1 if uncovered else 0


if __name__ == "__main__":
    sys.exit(main())
