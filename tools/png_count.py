#!/usr/bin/python3
"""Counts a PNG's pixels: those not white, then those of each colour named (hex RRGGBB),
on one line (the standard library alone; tools/png_grid.py reads the file).

    /usr/bin/python3 tools/png_count.py IMAGE.png [RRGGBB ...]"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from png_grid import read_png  # noqa: E402


def main():
    width, height, channels, rows = read_png(sys.argv[1])
    counts = {}
    for row in rows:
        for x in range(0, width * channels, channels):
            px = row[x:x + 3]
            counts[px] = counts.get(px, 0) + 1
    wanted = [counts.get(bytes.fromhex(c), 0) for c in sys.argv[2:]]
    not_white = width * height - counts.get(b"\xff\xff\xff", 0)
    print(not_white, *wanted)


main()
