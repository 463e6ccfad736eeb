"""A small baseline JPEG encoder (8-bit, grayscale or YCbCr 4:4:4, Huffman tables fitted to the
image), for ``candela.mitsuba.Bitmap.write('x.jpg')``: Candela's native module writes PNG and
OpenEXR only. The output is plain JFIF that any decoder reads (Candela's own image reader
included, which the tests use to check it).
"""

from __future__ import annotations

import math
import struct

import numpy as np

# The example quantisation tables of the JPEG standard (ITU T.81, annex K.1), in natural order.
_LUMA = np.array([
    16, 11, 10, 16, 24, 40, 51, 61, 12, 12, 14, 19, 26, 58, 60, 55, 14, 13, 16, 24, 40, 57, 69, 56,
    14, 17, 22, 29, 51, 87, 80, 62, 18, 22, 37, 56, 68, 109, 103, 77, 24, 35, 55, 64, 81, 104, 113, 92,
    49, 64, 78, 87, 103, 121, 120, 101, 72, 92, 95, 98, 112, 100, 103, 99]).reshape(8, 8)
_CHROMA = np.full((8, 8), 99)
_CHROMA[:4, :4] = [[17, 18, 24, 47], [18, 21, 26, 66], [24, 26, 56, 99], [47, 66, 99, 99]]


def _zigzag() -> np.ndarray:
    """Indices (row * 8 + column) of the 64 coefficients in zig-zag order."""
    order = sorted(((r, c) for r in range(8) for c in range(8)),
                   key=lambda rc: (rc[0] + rc[1], rc[0] if (rc[0] + rc[1]) % 2 else rc[1]))
    return np.array([r * 8 + c for r, c in order])


_ZIGZAG = _zigzag()
_DCT = np.array([[(math.sqrt(0.5) if u == 0 else 1.0) * 0.5 * math.cos((2 * x + 1) * u * math.pi / 16) for x in range(8)]
                 for u in range(8)])


def _quant_table(base: np.ndarray, quality: int) -> np.ndarray:
    scale = 5000 // quality if quality < 50 else 200 - 2 * quality
    return np.clip((base * scale + 50) // 100, 1, 255).astype(np.int64)


def _category(v: int) -> int:
    return abs(v).bit_length()


def _amplitude(v: int, size: int) -> int:
    return v if v >= 0 else v + (1 << size) - 1


def _huffman_table(freq: dict[int, int]) -> tuple[list[int], list[int]]:
    """BITS (counts of codes of length 1..16) and HUFFVAL for the symbol counts, as T.81 annex K.2
    builds an optimal table: a reserved symbol keeps any code from being all ones, and code
    lengths over 16 are folded back."""
    f = [0] * 257
    for symbol, count in freq.items():
        f[symbol] = count
    f[256] = 1
    codesize = [0] * 257
    others = [-1] * 257
    while True:
        live = [i for i in range(257) if f[i] > 0]
        if len(live) < 2:
            break
        # The least frequent two; among equals the larger symbol value first (as the standard's figure).
        live.sort(key=lambda i: (f[i], -i))
        v1, v2 = live[0], live[1]
        if v1 > v2:
            v1, v2 = v2, v1
        f[v1] += f[v2]
        f[v2] = 0
        codesize[v1] += 1
        while others[v1] != -1:
            v1 = others[v1]
            codesize[v1] += 1
        others[v1] = v2
        codesize[v2] += 1
        while others[v2] != -1:
            v2 = others[v2]
            codesize[v2] += 1
    bits = [0] * 33
    for size in codesize:
        if size:
            bits[size] += 1
    for i in range(32, 16, -1):
        while bits[i] > 0:
            j = i - 2
            while bits[j] == 0:
                j -= 1
            bits[i] -= 2
            bits[i - 1] += 1
            bits[j + 1] += 2
            bits[j] -= 1
    i = 16
    while bits[i] == 0:
        i -= 1
    bits[i] -= 1  # the reserved symbol's code
    values = [s for s in sorted(range(256), key=lambda s: (codesize[s], s)) if codesize[s] > 0]
    return bits[1:17], values


def _codes(bits: list[int], values: list[int]) -> dict[int, tuple[int, int]]:
    codes, code, k = {}, 0, 0
    for length in range(1, 17):
        for _ in range(bits[length - 1]):
            codes[values[k]] = (code, length)
            code += 1
            k += 1
        code <<= 1
    return codes


class _BitWriter:
    def __init__(self):
        self.out = bytearray()
        self.acc = 0
        self.count = 0

    def put(self, value: int, length: int):
        self.acc = (self.acc << length) | (value & ((1 << length) - 1))
        self.count += length
        while self.count >= 8:
            self.count -= 8
            byte = (self.acc >> self.count) & 0xFF
            self.out.append(byte)
            if byte == 0xFF:
                self.out.append(0)
        self.acc &= (1 << self.count) - 1

    def flush(self) -> bytes:
        if self.count:
            self.put((1 << (8 - self.count)) - 1, 8 - self.count)
        return bytes(self.out)


def _blocks(plane: np.ndarray, table: np.ndarray) -> np.ndarray:
    """The quantised DCT coefficients of a plane's 8 x 8 blocks, in zig-zag order: N x 64 ints."""
    h, w = plane.shape
    b = (plane - 128.0).reshape(h // 8, 8, w // 8, 8).transpose(0, 2, 1, 3).reshape(-1, 8, 8)
    coefficients = np.einsum("ux,bxy,vy->buv", _DCT, b, _DCT)
    q = np.round(coefficients / table).astype(np.int64).reshape(-1, 64)[:, _ZIGZAG]
    q[:, 0] = np.clip(q[:, 0], -2047, 2047)
    q[:, 1:] = np.clip(q[:, 1:], -1023, 1023)
    return q


def _symbols(blocks: np.ndarray):
    """Per block: the DC (category, amplitude) and the AC (run/size symbol, amplitude, size) list."""
    out = []
    previous = 0
    for block in blocks.tolist():
        diff = block[0] - previous
        previous = block[0]
        ac, run = [], 0
        last = 63
        while last > 0 and block[last] == 0:
            last -= 1
        for k in range(1, last + 1):
            v = block[k]
            if v == 0:
                run += 1
                continue
            while run > 15:
                ac.append((0xF0, 0, 0))
                run -= 16
            size = _category(v)
            ac.append(((run << 4) | size, _amplitude(v, size), size))
            run = 0
        if last < 63:
            ac.append((0x00, 0, 0))
        size = _category(diff)
        out.append(((size, _amplitude(diff, size)), ac))
    return out


def encode_jpeg(pixels: np.ndarray, quality: int = 95) -> bytes:
    """JPEG bytes of H x W (grayscale) or H x W x 3 (RGB) 8-bit pixels; quality 1-100."""
    a = np.asarray(pixels)
    if a.dtype != np.uint8:
        raise ValueError("encode_jpeg expects 8-bit pixels")
    if a.ndim == 3 and a.shape[2] == 1:
        a = a[:, :, 0]
    if not (a.ndim == 2 or (a.ndim == 3 and a.shape[2] == 3)):
        raise ValueError(f"encode_jpeg expects H x W or H x W x 3 pixels, got {a.shape}")
    height, width = a.shape[:2]
    if not (0 < height < 65536 and 0 < width < 65536):
        raise ValueError(f"a JPEG is 1 to 65535 pixels on a side, got {width} x {height}")
    quality = int(min(max(quality, 1), 100))
    x = a.astype(np.float64)
    if x.ndim == 2:
        planes = [x]
    else:
        r, g, b = x[:, :, 0], x[:, :, 1], x[:, :, 2]
        planes = [0.299 * r + 0.587 * g + 0.114 * b,
                  -0.168735892 * r - 0.331264108 * g + 0.5 * b + 128.0,
                  0.5 * r - 0.418687589 * g - 0.081312411 * b + 128.0]
    ph, pw = -(-height // 8) * 8, -(-width // 8) * 8
    planes = [np.pad(p, ((0, ph - height), (0, pw - width)), mode="edge") for p in planes]
    tables = [_quant_table(_LUMA, quality), _quant_table(_CHROMA, quality)]
    which = [0, 1, 1][:len(planes)]
    coded = [_symbols(_blocks(p, tables[t])) for p, t in zip(planes, which)]

    # Huffman tables fitted to this image: one DC and one AC table per table class (luma, chroma).
    huff = {}
    for t in sorted(set(which)):
        dc, ac = {}, {}
        for c, comp in enumerate(coded):
            if which[c] != t:
                continue
            for (size, _), acs in comp:
                dc[size] = dc.get(size, 0) + 1
                for symbol, _, _ in acs:
                    ac[symbol] = ac.get(symbol, 0) + 1
        huff[t] = (_huffman_table(dc), _huffman_table(ac))

    w = _BitWriter()
    codes = {t: (_codes(*huff[t][0]), _codes(*huff[t][1])) for t in huff}
    for i in range(len(coded[0])):
        for c, comp in enumerate(coded):
            dc_codes, ac_codes = codes[which[c]]
            (size, amplitude), acs = comp[i]
            w.put(*dc_codes[size])
            if size:
                w.put(amplitude, size)
            for symbol, amp, s in acs:
                w.put(*ac_codes[symbol])
                if s:
                    w.put(amp, s)
    data = w.flush()

    def segment(marker: int, payload: bytes) -> bytes:
        return struct.pack(">HH", marker, len(payload) + 2) + payload

    out = bytearray(b"\xff\xd8")
    out += segment(0xFFE0, b"JFIF\x00\x01\x01\x00\x00\x01\x00\x01\x00\x00")
    for t in sorted(set(which)):
        out += segment(0xFFDB, bytes([t]) + bytes(tables[t].reshape(64)[_ZIGZAG].tolist()))
    components = b"".join(bytes([c + 1, 0x11, which[c]]) for c in range(len(planes)))
    out += segment(0xFFC0, struct.pack(">BHHB", 8, height, width, len(planes)) + components)
    for t in sorted(huff):
        for cls, (bits, values) in enumerate(huff[t]):
            out += segment(0xFFC4, bytes([(cls << 4) | t]) + bytes(bits) + bytes(values))
    selectors = b"".join(bytes([c + 1, (which[c] << 4) | which[c]]) for c in range(len(planes)))
    out += segment(0xFFDA, bytes([len(planes)]) + selectors + b"\x00\x3f\x00")
    out += data
    out += b"\xff\xd9"
    return bytes(out)
