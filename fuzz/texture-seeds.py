#!/usr/bin/env python3
"""Writes the seeds of the `texture` fuzz target: tiny images of every format Prism reads
as a texture, each written here from its specification so that none is copied from
elsewhere. Every seed starts with the target's selector byte: bits 0-2 pick the file
name's extension (png jpg bmp tga ppm hdr exr, 7: an unknown one), bits 3-4 the encoding.

    python3 fuzz/texture-seeds.py     # rewrites fuzz/seeds/texture/
"""
import math
import os
import struct
import zlib

PNG, JPG, BMP, TGA, PPM, HDR, EXR = range(7)
SRGB, LINEAR, MASK = (0 << 3, 1 << 3, 2 << 3)

# 2x2 RGB, row by row.
PIXELS = [(192, 64, 32), (32, 160, 64), (16, 48, 200), (250, 250, 250)]


def png_chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def png(ihdr, raw, extra=()):
    out = b"\x89PNG\r\n\x1a\n" + png_chunk(b"IHDR", struct.pack(">IIBBBBB", *ihdr))
    for kind, data in extra:
        out += png_chunk(kind, data)
    return out + png_chunk(b"IDAT", zlib.compress(raw, 9)) + png_chunk(b"IEND", b"")


def png_rgb():
    rows = [b"\0" + bytes(sum(PIXELS[2 * y : 2 * y + 2], ())) for y in range(2)]
    return png((2, 2, 8, 2, 0, 0, 0), b"".join(rows), [(b"sRGB", b"\0")])


def png_palette():
    # 2-bit indices 0 1 / 2 3; index 0 transparent.
    palette = bytes(sum(PIXELS, ()))
    raw = b"\0" + bytes([0b0001_0000]) + b"\0" + bytes([0b1011_0000])
    return png((2, 2, 2, 3, 0, 0, 0), raw, [(b"PLTE", palette), (b"tRNS", b"\0\x80")])


def png_grey_alpha_16_interlaced():
    # Adam7 on 2x2: pass 1 holds (0,0), pass 6 (1,0), pass 7 the second row.
    px = [struct.pack(">HH", 1000 * (i + 1), 65535 - 9000 * i) for i in range(4)]
    raw = b"\0" + px[0] + b"\0" + px[1] + b"\0" + px[2] + px[3]
    return png((2, 2, 16, 4, 0, 0, 1), raw, [(b"gAMA", struct.pack(">I", 45455))])


ZIGZAG = [
    0, 1, 8, 16, 9, 2, 3, 10, 17, 24, 32, 25, 18, 11, 4, 5, 12, 19, 26, 33, 40, 48, 41, 34,
    27, 20, 13, 6, 7, 14, 21, 28, 35, 42, 49, 56, 57, 50, 43, 36, 29, 22, 15, 23, 30, 37,
    44, 51, 58, 59, 52, 45, 38, 31, 39, 46, 53, 60, 61, 54, 47, 55, 62, 63,
]


def huffman_codes(bits, values):
    """Canonical codes of a JPEG Huffman table: symbol -> (code, length)."""
    codes, code, k = {}, 0, 0
    for length in range(1, 17):
        for _ in range(bits[length - 1]):
            codes[values[k]] = (code, length)
            code += 1
            k += 1
        code <<= 1
    return codes


def jpeg():
    """A baseline JPEG of the 2x2 image: YCbCr 4:4:4, one quantisation table of 4s, one
    DC and one AC Huffman table of its own (any valid table will do)."""
    dc_values = list(range(12))
    dc_bits = [0, 1, 0, 11] + [0] * 12
    ac_values = [0x00, 0x01] + [r << 4 | s for r in range(16) for s in range(1, 11) if (r, s) != (0, 1)] + [0xF0]
    ac_bits = [0, 2, 0, 0, 0, 0, 0, 0, 160] + [0] * 7
    dc, ac = huffman_codes(dc_bits, dc_values), huffman_codes(ac_bits, ac_values)
    q = 4

    def at(x, y):
        return PIXELS[2 * min(y, 1) + min(x, 1)]

    def ycbcr(r, g, b):
        return (
            0.299 * r + 0.587 * g + 0.114 * b,
            128 - 0.168736 * r - 0.331264 * g + 0.5 * b,
            128 + 0.5 * r - 0.418688 * g - 0.081312 * b,
        )

    bits = []

    def put(value, length):
        bits.extend((value >> (length - 1 - i)) & 1 for i in range(length))

    def magnitude(v):
        size = abs(v).bit_length()
        return size, (v if v >= 0 else v + (1 << size) - 1)

    previous = [0, 0, 0]
    for c in range(3):
        block = [ycbcr(*at(x, y))[c] - 128 for y in range(8) for x in range(8)]
        coeffs = []
        for v in range(8):
            for u in range(8):
                s = sum(
                    block[y * 8 + x]
                    * math.cos((2 * x + 1) * u * math.pi / 16)
                    * math.cos((2 * y + 1) * v * math.pi / 16)
                    for y in range(8)
                    for x in range(8)
                )
                cu = 1 / math.sqrt(2) if u == 0 else 1
                cv = 1 / math.sqrt(2) if v == 0 else 1
                coeffs.append(round(0.25 * cu * cv * s / q))
        zz = [coeffs[i] for i in ZIGZAG]
        size, bits_of = magnitude(zz[0] - previous[c])
        previous[c] = zz[0]
        put(*dc[size])
        put(bits_of, size)
        run = 0
        for v in zz[1:]:
            if v == 0:
                run += 1
                continue
            while run > 15:
                put(*ac[0xF0])
                run -= 16
            size, bits_of = magnitude(v)
            put(*ac[run << 4 | size])
            put(bits_of, size)
            run = 0
        if run:
            put(*ac[0x00])
    bits.extend([1] * (-len(bits) % 8))
    scan = bytearray()
    for i in range(0, len(bits), 8):
        byte = int("".join(map(str, bits[i : i + 8])), 2)
        scan.append(byte)
        if byte == 0xFF:
            scan.append(0)

    def segment(marker, data):
        return bytes([0xFF, marker]) + struct.pack(">H", len(data) + 2) + data

    out = b"\xff\xd8"
    out += segment(0xE0, b"JFIF\0\x01\x01\0\0\x01\0\x01\0\0")
    out += segment(0xDB, b"\0" + bytes([q] * 64))
    out += segment(0xC0, struct.pack(">BHHB", 8, 2, 2, 3) + b"\x01\x11\0\x02\x11\0\x03\x11\0")
    out += segment(0xC4, b"\x00" + bytes(dc_bits) + bytes(dc_values) + b"\x10" + bytes(ac_bits) + bytes(ac_values))
    out += segment(0xDA, b"\x03\x01\x00\x02\x00\x03\x00\x00\x3f\x00")
    return out + bytes(scan) + b"\xff\xd9"


def bmp_24():
    rows = b""
    for y in (1, 0):  # bottom-up
        row = b"".join(bytes((b, g, r)) for r, g, b in PIXELS[2 * y : 2 * y + 2])
        rows += row + b"\0" * (-len(row) % 4)
    info = struct.pack("<IiiHHIIiiII", 40, 2, 2, 1, 24, 0, len(rows), 2835, 2835, 0, 0)
    return b"BM" + struct.pack("<IHHI", 14 + len(info) + len(rows), 0, 0, 14 + 40) + info + rows


def bmp_rle8():
    palette = b"".join(bytes((b, g, r, 0)) for r, g, b in PIXELS[:2])
    rle = b"\x01\x00\x01\x01\x00\x00" + b"\x02\x01\x00\x01"  # bottom row, end of line; top row, end
    info = struct.pack("<IiiHHIIiiII", 40, 2, 2, 1, 8, 1, len(rle), 2835, 2835, 2, 0)
    offset = 14 + len(info) + len(palette)
    return b"BM" + struct.pack("<IHHI", offset + len(rle), 0, 0, offset) + info + palette + rle


def tga(kind, body):
    return struct.pack("<BBBHHBHHHHBB", 0, 0, kind, 0, 0, 0, 0, 0, 2, 2, 24, 0x20) + body


def tga_plain():
    return tga(2, b"".join(bytes((b, g, r)) for r, g, b in PIXELS))


def tga_rle():
    r, g, b = PIXELS[0]
    r2, g2, b2 = PIXELS[3]
    # A run of 3, then one raw pixel; and the TGA 2.0 footer.
    footer = struct.pack("<II", 0, 0) + b"TRUEVISION-XFILE.\0"
    return tga(10, bytes((0x82, b, g, r, 0x00, b2, g2, r2))) + footer


def ppm():
    return b"P6\n# 2x2\n2 2\n255\n" + bytes(sum(PIXELS, ()))


def pgm_ascii():
    return b"P2\n2 2\n65535\n0 1000\n40000 65535\n"


def rgbe(r, g, b):
    m = max(r, g, b)
    if m < 1e-32:
        return b"\0\0\0\0"
    f, e = math.frexp(m)
    s = f * 256 / m
    return bytes((int(r * s), int(g * s), int(b * s), e + 128))


def hdr_flat():
    head = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=1.0\n\n-Y 2 +X 2\n"
    return head + b"".join(rgbe(*(c / 64 for c in p)) for p in PIXELS)


def hdr_rle():
    # New-style run-length scan lines need a width of 8 to 32767: 8x1, each channel
    # one run of 8.
    r, g, b, e = rgbe(3.5, 0.25, 1.0)
    line = b"\x02\x02\x00\x08" + b"".join(bytes((128 + 8, v)) for v in (r, g, b, e))
    return b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 8\n" + line


def half(v):
    return struct.pack("<e", v)


def exr():
    """A single-part scan-line OpenEXR file, 2x2, half B G R, no compression."""

    def attribute(name, kind, value):
        return name + b"\0" + kind + b"\0" + struct.pack("<i", len(value)) + value

    channels = b"".join(c + b"\0" + struct.pack("<iB3xii", 1, 0, 1, 1) for c in (b"B", b"G", b"R")) + b"\0"
    window = struct.pack("<iiii", 0, 0, 1, 1)
    header = b"\x76\x2f\x31\x01" + struct.pack("<I", 2)
    header += attribute(b"channels", b"chlist", channels)
    header += attribute(b"compression", b"compression", b"\0")
    header += attribute(b"dataWindow", b"box2i", window)
    header += attribute(b"displayWindow", b"box2i", window)
    header += attribute(b"lineOrder", b"lineOrder", b"\0")
    header += attribute(b"pixelAspectRatio", b"float", struct.pack("<f", 1))
    header += attribute(b"screenWindowCenter", b"v2f", struct.pack("<ff", 0, 0))
    header += attribute(b"screenWindowWidth", b"float", struct.pack("<f", 1))
    header += b"\0"
    chunks = []
    for y in range(2):
        row = PIXELS[2 * y : 2 * y + 2]
        data = b"".join(half(p[c] / 64) for c in (2, 1, 0) for p in row)
        chunks.append(struct.pack("<ii", y, len(data)) + data)
    offset = len(header) + 8 * len(chunks)
    table = b""
    for chunk in chunks:
        table += struct.pack("<Q", offset)
        offset += len(chunk)
    return header + table + b"".join(chunks)


SEEDS = {
    "rgb.png": (PNG | SRGB, png_rgb),
    "palette-trns.png": (PNG | MASK, png_palette),
    "grey-alpha-16-adam7.png": (PNG | LINEAR, png_grey_alpha_16_interlaced),
    "baseline.jpg": (JPG | SRGB, jpeg),
    "rgb24.bmp": (BMP | SRGB, bmp_24),
    "rle8.bmp": (BMP | MASK, bmp_rle8),
    "plain.tga": (TGA | SRGB, tga_plain),
    "rle.tga": (TGA | LINEAR, tga_rle),
    "rgb.ppm": (PPM | SRGB, ppm),
    "grey16-ascii.pgm": (PPM | MASK, pgm_ascii),
    "flat.hdr": (HDR | LINEAR, hdr_flat),
    "rle.hdr": (HDR | SRGB, hdr_rle),
    "half.exr": (EXR | LINEAR, exr),
    # Radiance content under an 8-bit name: the 8-bit decoders take it by content.
    "flat-hdr-as.png": (PNG | SRGB, hdr_flat),
}

if __name__ == "__main__":
    folder = os.path.join(os.path.dirname(os.path.abspath(__file__)), "seeds", "texture")
    os.makedirs(folder, exist_ok=True)
    for name, (select, make) in SEEDS.items():
        with open(os.path.join(folder, name), "wb") as f:
            f.write(bytes([select]) + make())
