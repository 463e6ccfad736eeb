"""Images as NumPy arrays: ``candela.Image`` is an ``ndarray`` (height x width x channels,
float32) viewing the pixels Candela rendered or read, without a copy, with the channel names and
the file's metadata beside them. Jupyter shows one as a tonemapped sRGB picture (bands of a
specfilm side by side in grey).
"""

from __future__ import annotations

import os

import numpy as np

from . import _candela


class Image(np.ndarray):
    """H x W x C float32 pixels with ``channels`` (names, e.g. ["R", "G", "B"]) and ``metadata``.

    ``np.asarray(image)`` is a view of the same memory; so is the array a render returns: its
    base chain ends at the native buffer Candela wrote."""

    def __new__(cls, array, channels=None, metadata=None):
        if isinstance(array, _candela.ImageBuffer):
            # The native pixels themselves: view.base is the buffer, np.asarray(view).base is view.
            layout = np.asarray(array)
            view = np.ndarray.__new__(cls, layout.shape, dtype=np.float32, buffer=array, strides=layout.strides)
            view.channels = list(array.channels)
            view.metadata = dict(array.metadata)
            return view
        a = np.asarray(array, dtype=np.float32)
        if a.ndim == 2:
            a = a[:, :, None]
        if a.ndim != 3:
            raise ValueError(f"an image is height x width x channels, got an array of shape {a.shape}")
        view = a.view(cls)
        view.channels = list(channels) if channels is not None else default_channels(a.shape[2])
        if len(view.channels) != a.shape[2]:
            raise ValueError(f"{len(view.channels)} channel names for {a.shape[2]} channels")
        view.metadata = dict(metadata or {})
        return view

    def __array_finalize__(self, obj):
        self.channels = list(getattr(obj, "channels", []) or [])
        self.metadata = dict(getattr(obj, "metadata", {}) or {})

    def __array_wrap__(self, out, context=None, return_scalar=False):
        # Arithmetic (image * 2, image ** (1 / 2.2)) gives an Image of the same channels; reductions
        # and reshapes that lose the layout give plain arrays.
        if out.ndim == 3 and self.ndim == 3 and out.shape[2] == len(self.channels):
            return np.ndarray.__array_wrap__(self, out, context)
        return np.asarray(out)

    @property
    def width(self) -> int:
        return self.shape[1]

    @property
    def height(self) -> int:
        return self.shape[0]

    def layer(self, name: str) -> np.ndarray:
        """The channels of a layer by its name prefix ("albedo" -> albedo.R, albedo.G, albedo.B)
        or one channel by its full name."""
        names = [i for i, c in enumerate(self.channels) if c == name or c.startswith(name + ".")]
        if not names:
            raise KeyError(f"no channel or layer {name!r} (channels: {', '.join(self.channels)})")
        return np.asarray(self)[:, :, names]

    def rgb(self) -> np.ndarray:
        """The R, G, B channels (the first three when unnamed; a grey image's one channel three
        times)."""
        try:
            return np.asarray(self)[:, :, [self.channels.index(c) for c in ("R", "G", "B")]]
        except ValueError:
            if self.shape[2] < 3:
                return np.repeat(np.asarray(self)[:, :, :1], 3, axis=2)
            return np.asarray(self)[:, :, :3]

    def numpy(self) -> np.ndarray:
        """The pixels as a plain NumPy array (a copy, H x W x C float32), as Mitsuba's
        ``TensorXf.numpy()`` gives them."""
        return np.array(self, dtype=np.float32)

    def to_srgb8(self) -> np.ndarray:
        """The colour as 8-bit sRGB (clamped to [0, 1], then the sRGB curve): H x W x 3 uint8."""
        return srgb8(self.rgb())

    def write(self, path: str, float32: bool = True):
        """Writes the image: OpenEXR (all channels, float32 or float16) or PNG (8-bit sRGB)."""
        write_image(path, self, float32=float32)

    def _repr_png_(self) -> bytes:
        return _candela.encode_png(np.ascontiguousarray(self._preview_srgb8()))

    def _preview_srgb8(self) -> np.ndarray:
        """What Jupyter shows: the colour, or for an image of named channels that are not a
        colour (a specfilm's bands) each channel in grey side by side, left to right in the
        channels' order, under one scale (the largest finite value is white): to_srgb8 would
        show the first channels as if they were R, G and B."""
        names = set(self.channels)
        if {"R", "G", "B"} <= names or "Y" in names or self.channels == default_channels(self.shape[2]):
            return self.to_srgb8()
        x = np.nan_to_num(np.asarray(self, dtype=np.float64), nan=0.0, posinf=0.0, neginf=0.0)
        top = x.max() if x.size else 0.0
        tiles = np.concatenate([x[:, :, c] for c in range(x.shape[2])], axis=1) / (top if top > 0.0 else 1.0)
        return srgb8(np.repeat(tiles[:, :, None], 3, axis=2))

    def __repr__(self):
        return f"candela.Image({self.width} x {self.height}, channels {','.join(self.channels)})"


def default_channels(count: int) -> list[str]:
    return {1: ["Y"], 3: ["R", "G", "B"], 4: ["R", "G", "B", "A"]}.get(count, [f"C{i}" for i in range(count)])


def srgb8(rgb) -> np.ndarray:
    """Linear RGB (any shape ... x 3) as 8-bit sRGB, clamped."""
    x = np.clip(np.nan_to_num(np.asarray(rgb, dtype=np.float64), nan=0.0, posinf=1.0, neginf=0.0), 0.0, 1.0)
    encoded = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1.0 / 2.4) - 0.055)
    return np.round(encoded * 255.0).astype(np.uint8)


def _integer_file(path: str) -> bool:
    """Whether the image file holds 8- or 16-bit integers (PNG, JPEG, PPM, TGA, BMP), not floats
    (OpenEXR, RGBE, PFM), told by its first bytes."""
    with open(path, "rb") as f:
        head = f.read(16)
    return not (head.startswith(b"\x76\x2f\x31\x01") or head.startswith(b"#?") or head[:3] in (b"PF\n", b"Pf\n")
                or head[:3] in (b"PF\r", b"Pf\r"))


def read_image(path: str, raw: bool = False) -> Image:
    """An image file: OpenEXR with every channel and the metadata; PNG, JPEG, HDR, PFM, ... as
    Candela's textures read them: linear values (8- and 16-bit files decoded from sRGB, their
    alpha left as it is). ``raw=True`` keeps an 8- or 16-bit file's values as stored (in [0, 1])."""
    path = os.fspath(path)
    image = Image(_candela.read_image(path))
    if not raw and _integer_file(path):
        colour = [i for i, c in enumerate(image.channels) if c not in ("A", "a") and not c.endswith(".A")]
        x = np.asarray(image)
        v = x[:, :, colour]
        x[:, :, colour] = np.where(v <= 0.04045, v * np.float32(1.0 / 12.92),
                                   np.power((np.maximum(v, 0.04045) + 0.055) / 1.055, 2.4)).astype(np.float32)
    return image


def write_image(path: str, image, float32: bool = True, channels=None):
    """Writes an array or an Image: .exr keeps every channel (float32, or float16 with
    float32=False) and the metadata; .png writes 8-bit sRGB of the colour (tonemapped by
    clamping, as `candela render --png`). Written whole or not at all."""
    path = os.fspath(path)
    if not isinstance(image, Image):
        image = Image(image, channels=channels)
    extension = os.path.splitext(path)[1].lower()
    if extension == ".png":
        _candela.write_png(np.ascontiguousarray(image.to_srgb8()), path)
    elif extension == ".exr":
        buffer = _candela.ImageBuffer(np.ascontiguousarray(image, dtype=np.float32), list(image.channels), dict(image.metadata))
        _candela.write_exr(buffer, path, float32)
    else:
        raise ValueError(f"{path}: write_image writes .exr or .png")
