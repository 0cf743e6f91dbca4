#!/usr/bin/env python3
"""Regenerates the PNG fixtures of this folder (run here: python3 make_fixtures.py).

The OpenEXR fixtures were written once with OpenEXR 3's Imf::RgbaOutputFile (half floats):
  hdr.exr  2x2, WRITE_RGB: (0.5, 2, 4), (0.25, 0.125, 8) / (1.5, 3, 0.75), (16, 0, 1)
  lum.exr  2x1, WRITE_Y:   0.25, 6
"""
import struct
import zlib


def png(path, width, height, colour_type, rows, depth=8):
    def chunk(kind, data):
        return struct.pack('>I', len(data)) + kind + data + struct.pack('>I', zlib.crc32(kind + data) & 0xffffffff)
    raw = b''.join(b'\x00' + bytes(row) for row in rows)  # filter type 0 on every row
    header = struct.pack('>IIBBBBB', width, height, depth, colour_type, 0, 0, 0)
    with open(path, 'wb') as f:
        f.write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', header) + chunk(b'IDAT', zlib.compress(raw, 9)) + chunk(b'IEND', b''))


# 2x2 RGBA: red, green / blue, white with alpha 51
png('quad.png', 2, 2, 6, [[255, 0, 0, 255, 0, 255, 0, 255], [0, 0, 255, 255, 255, 255, 255, 51]])
# 4x1 grey: 0, 64, 128, 255
png('ramp.png', 4, 1, 0, [[0, 64, 128, 255]])
# 64x64 grey checkerboard of 8x8-texel cells, the top left cell white
png('checker.png', 64, 64, 0, [[255 if (x // 8 + y // 8) % 2 == 0 else 0 for x in range(64)] for y in range(64)])
# 3x1 RGB (a size that is not a power of two): white, black, white
png('odd.png', 3, 1, 2, [[255, 255, 255, 0, 0, 0, 255, 255, 255]])
with open('not_an_image.png', 'w') as f:
    f.write('this is not a PNG file\n')
with open('truncated.png', 'wb') as f:  # a PNG signature and a cut-off header
    f.write(b'\x89PNG\r\n\x1a\n\x00\x00\x00\x0dIHDR\x00\x00')
# Pseudo-random RGBA (a fixed LCG), for lookups from stored codes against decoded floats:
# noise.png 17x11 at 8 bits, deep.png 7x5 at 16 bits (big-endian samples).
state = [12345]


def lcg():
    state[0] = (state[0] * 1103515245 + 12345) % 2**31
    return state[0] >> 8


png('noise.png', 17, 11, 6, [[lcg() % 256 for _ in range(17 * 4)] for _ in range(11)])
png('deep.png', 7, 5, 6, [[b for _ in range(7 * 4) for b in struct.pack('>H', lcg() % 65536)] for _ in range(5)], depth=16)
