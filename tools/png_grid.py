#!/usr/bin/python3
"""Lays PNG frames of one size out in a grid, row by row, into one PNG (the standard
library alone: 8-bit RGB or RGBA frames, as rj animate writes them).

    /usr/bin/python3 tools/png_grid.py COLUMNS OUT.png FRAME.png ..."""
import struct
import sys
import zlib


def read_png(path):
    """Width, height, channels and rows (bytes, filters undone) of an 8-bit PNG."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise SystemExit("%s: not a PNG" % path)
    pos, idat, width = 8, b"", 0
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or colour not in (2, 6) or interlace:
                raise SystemExit("%s: only 8-bit RGB or RGBA, not interlaced" % path)
            channels = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride = width * channels
    rows, prev = [], bytearray(stride)
    for y in range(height):
        kind = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        # an unfiltered row (what rj's renderer writes) is its bytes
        for x in range(stride if kind else 0):
            a = line[x - channels] if x >= channels else 0
            b = prev[x]
            c = prev[x - channels] if x >= channels else 0
            if kind == 1:
                line[x] = (line[x] + a) & 255
            elif kind == 2:
                line[x] = (line[x] + b) & 255
            elif kind == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[x] = (line[x] + pred) & 255
        rows.append(bytes(line))
        prev = line
    return width, height, channels, rows


def write_png(path, width, height, channels, rows):
    """An 8-bit PNG, every row unfiltered."""
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    colour = 2 if channels == 3 else 6
    raw = b"".join(b"\x00" + r for r in rows)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, colour, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def main():
    if len(sys.argv) < 4:
        raise SystemExit(__doc__)
    columns, out, paths = int(sys.argv[1]), sys.argv[2], sys.argv[3:]
    frames = [read_png(p) for p in paths]
    width, height, channels = frames[0][:3]
    if any(f[:3] != (width, height, channels) for f in frames):
        raise SystemExit("the frames differ in size or channels")
    grid_rows = (len(frames) + columns - 1) // columns
    blank = bytes(width * channels)
    rows = []
    for gy in range(grid_rows):
        for y in range(height):
            rows.append(b"".join(frames[gy * columns + gx][3][y] if gy * columns + gx < len(frames) else blank
                                 for gx in range(columns)))
    write_png(out, width * columns, height * grid_rows, channels, rows)


if __name__ == "__main__":
    main()
