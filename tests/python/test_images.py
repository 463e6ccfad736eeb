"""Images: reading and writing OpenEXR and PNG, the Image type (an ndarray with channel names and
metadata), and the PNG Jupyter shows (_repr_png_), decoded here by a small PNG reader."""

import struct
import zlib

import numpy as np
import pytest

from conftest import SCENES, candela


def decode_png(data: bytes) -> np.ndarray:
    """The pixels of an 8-bit, non-interlaced PNG (grey, grey+alpha, RGB or RGBA): H x W x C uint8.
    Checks the signature and every chunk's CRC."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG signature"
    pos, chunks = 8, []
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind, payload = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + length]
        (crc,) = struct.unpack(">I", data[pos + 8 + length:pos + 12 + length])
        assert zlib.crc32(kind + payload) & 0xFFFFFFFF == crc, f"bad CRC in {kind!r}"
        chunks.append((kind, payload))
        pos += 12 + length
    assert chunks[0][0] == b"IHDR" and chunks[-1][0] == b"IEND"
    width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", chunks[0][1])
    assert depth == 8 and interlace == 0
    channels = {0: 1, 2: 3, 4: 2, 6: 4}[colour]
    raw = zlib.decompress(b"".join(p for k, p in chunks if k == b"IDAT"))
    stride = width * channels
    assert len(raw) == height * (stride + 1)
    out = np.zeros((height, stride), dtype=np.int64)
    previous = np.zeros(stride, dtype=np.int64)
    for y in range(height):
        kind = raw[y * (stride + 1)]
        line = np.frombuffer(raw, dtype=np.uint8, count=stride, offset=y * (stride + 1) + 1).astype(np.int64)
        row = np.zeros(stride, dtype=np.int64)
        for x in range(stride):
            a = row[x - channels] if x >= channels else 0
            b = previous[x]
            c = previous[x - channels] if x >= channels else 0
            if kind == 0:
                predictor = 0
            elif kind == 1:
                predictor = a
            elif kind == 2:
                predictor = b
            elif kind == 3:
                predictor = (a + b) // 2
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                predictor = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
            else:
                raise AssertionError(f"unknown PNG filter {kind}")
            row[x] = (line[x] + predictor) & 0xFF
        out[y] = row
        previous = row
    return out.astype(np.uint8).reshape(height, width, channels)


@pytest.fixture(scope="module")
def render():
    return candela.render(candela.load_file(SCENES / "validation" / "cbox.xml", res=24), spp=4, seed=8,
                          aovs=["albedo", "depth"])


def test_exr_round_trip_float32(tmp_path, render):
    path = tmp_path / "r.exr"
    candela.write_image(path, render)
    back = candela.read_image(path)
    assert back.channels == render.channels
    assert np.array_equal(np.asarray(back), np.asarray(render))
    # The render's metadata goes with it.
    assert back.metadata["candela.spp"] == "4" and back.metadata["candela.seed"] == "8"
    assert back.layer("albedo").shape == (24, 24, 3) and back.layer("depth.Z").shape == (24, 24, 1)
    render.write(tmp_path / "method.exr")
    assert np.array_equal(np.asarray(candela.read_image(tmp_path / "method.exr")), np.asarray(render))


def test_exr_half_precision(tmp_path, render):
    path = tmp_path / "h.exr"
    candela.write_image(path, render, float32=False)
    back = np.asarray(candela.read_image(path))
    assert np.array_equal(back, np.asarray(render).astype(np.float16).astype(np.float32))


def test_exr_from_plain_arrays(tmp_path):
    rng = np.random.default_rng(4)
    for channels in (1, 3, 4):
        a = rng.random((5, 7, channels), dtype=np.float32) * 10
        path = tmp_path / f"c{channels}.exr"
        candela.write_image(path, a)
        back = candela.read_image(path)
        assert back.channels == {1: ["Y"], 3: ["R", "G", "B"], 4: ["R", "G", "B", "A"]}[channels]
        assert np.array_equal(np.asarray(back), a)
    grey = rng.random((4, 6)).astype(np.float32)
    candela.write_image(tmp_path / "grey.exr", grey)
    assert candela.read_image(tmp_path / "grey.exr").shape == (4, 6, 1)
    named = candela.Image(rng.random((2, 3, 2), dtype=np.float32), channels=["u", "v"], metadata={"note": "hello"})
    candela.write_image(tmp_path / "named.exr", named)
    back = candela.read_image(tmp_path / "named.exr")
    assert back.channels == ["u", "v"] and back.metadata["note"] == "hello"


def test_png_write_and_read(tmp_path, render):
    path = tmp_path / "r.png"
    candela.write_image(path, render)
    expected = render.to_srgb8()
    assert expected.shape == (24, 24, 3) and expected.dtype == np.uint8
    assert np.array_equal(decode_png(path.read_bytes()), expected)
    # read_image gives linear values (decoded from sRGB); raw=True the stored 8-bit values.
    raw = candela.read_image(path, raw=True)
    assert np.array_equal(np.round(np.asarray(raw) * 255).astype(np.uint8), expected)
    linear = candela.read_image(path)
    assert np.array_equal(candela.image.srgb8(np.asarray(linear)), expected)
    assert np.allclose(np.asarray(linear), np.clip(np.asarray(render.rgb()), 0, 1), atol=0.02)


def test_png_matches_the_command_line(tmp_path):
    # candela render --png writes the same 8-bit picture as write_image.
    from conftest import run_cli

    run_cli("render", SCENES / "validation" / "cbox.xml", "-o", tmp_path / "c.exr", "--png", "--spp", 2, "-D", "res=16", "-q")
    image = candela.read_image(tmp_path / "c.exr")
    assert np.array_equal(decode_png((tmp_path / "c.png").read_bytes()), image.to_srgb8())


def test_repr_png_is_the_srgb_picture(render):
    data = render._repr_png_()
    assert isinstance(data, bytes)
    pixels = decode_png(data)
    assert np.array_equal(pixels, render.to_srgb8())
    # Plain Images and single-channel ones show too.
    grey = candela.Image(np.linspace(0, 1, 12, dtype=np.float32).reshape(3, 4))
    shown = decode_png(grey._repr_png_())
    assert shown.shape == (3, 4, 3)
    assert np.array_equal(shown[:, :, 0], shown[:, :, 2]) and np.array_equal(shown[:, :, 0], candela.image.srgb8(np.asarray(grey)[:, :, 0]))


def test_srgb8_encoding():
    x = np.array([-1.0, 0.0, 0.0031308, 0.5, 1.0, 2.0, np.nan, np.inf], dtype=np.float32)
    got = candela.image.srgb8(x)
    assert got.tolist() == [0, 0, 10, 188, 255, 255, 0, 255]


def test_image_type():
    a = candela.Image(np.zeros((2, 3, 3), dtype=np.float32))
    assert (a.width, a.height) == (3, 2)
    assert a.channels == ["R", "G", "B"]
    assert repr(a) == "candela.Image(3 x 2, channels R,G,B)"
    assert isinstance(a + 1, candela.Image) and (a + 1).channels == ["R", "G", "B"]
    assert not isinstance(a.mean(axis=2), candela.Image)
    b = candela.Image(np.arange(24, dtype=np.float32).reshape(2, 3, 4), channels=["B", "G", "R", "X"])
    assert np.array_equal(b.rgb(), np.asarray(b)[:, :, [2, 1, 0]])
    with pytest.raises(KeyError, match="no channel or layer"):
        b.layer("albedo")
    with pytest.raises(ValueError, match="channel names"):
        candela.Image(np.zeros((2, 2, 3)), channels=["R", "G"])
