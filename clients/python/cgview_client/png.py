"""PNG images with zlib alone: decode 8-bit PNGs (grey, RGB, with or without
alpha, not interlaced), encode RGBA, and lay pictures side by side."""
import struct
import zlib

SIGNATURE = b"\x89PNG\r\n\x1a\n"
CHANNELS = {0: 1, 2: 3, 4: 2, 6: 4}  # colour type -> samples per pixel


class Image:
    """width x height RGBA pixels, row by row (4 bytes a pixel)."""

    def __init__(self, width, height, rgba=None):
        self.width, self.height = width, height
        self.rgba = bytearray(rgba) if rgba is not None else bytearray(4 * width * height)
        if len(self.rgba) != 4 * width * height:
            raise ValueError(f"{len(self.rgba)} bytes for {width}x{height} RGBA pixels")

    def pixel(self, x, y):
        i = 4 * (y * self.width + x)
        return tuple(self.rgba[i:i + 4])


def decode(data):
    """The Image of a PNG file's bytes; ValueError for what it does not read."""
    if data[:8] != SIGNATURE:
        raise ValueError("not a PNG file")
    pos, idat, header = 8, [], None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            break
    if header is None:
        raise ValueError("PNG without IHDR")
    width, height, depth, colour, _, _, interlace = header
    if depth != 8 or colour not in CHANNELS or interlace:
        raise ValueError(f"unsupported PNG: bit depth {depth}, colour type {colour}, interlace {interlace}")
    channels = CHANNELS[colour]
    raw = zlib.decompress(b"".join(idat))
    rows = unfilter(raw, width * channels, height, channels)
    return Image(width, height, to_rgba(rows, channels))


def unfilter(raw, stride, height, bpp):
    """The scanlines of raw with their filters (PNG spec 9) undone."""
    out = bytearray(stride * height)
    prev = bytearray(stride)
    for y in range(height):
        start = y * (stride + 1)
        kind, line = raw[start], bytearray(raw[start + 1:start + 1 + stride])
        if kind == 1:
            for i in range(bpp, stride):
                line[i] = (line[i] + line[i - bpp]) & 255
        elif kind == 2:
            line = bytearray((a + b) & 255 for a, b in zip(line, prev))
        elif kind == 3:
            for i in range(stride):
                left = line[i - bpp] if i >= bpp else 0
                line[i] = (line[i] + ((left + prev[i]) >> 1)) & 255
        elif kind == 4:
            for i in range(stride):
                a = line[i - bpp] if i >= bpp else 0
                b, c = prev[i], prev[i - bpp] if i >= bpp else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        elif kind != 0:
            raise ValueError(f"bad PNG filter type {kind} on row {y}")
        out[y * stride:(y + 1) * stride] = line
        prev = line
    return out


def to_rgba(pixels, channels):
    if channels == 4:
        return pixels
    rgba = bytearray(len(pixels) // channels * 4)
    grey = channels < 3
    rgba[0::4] = pixels[0::channels]
    rgba[1::4] = pixels[0::channels] if grey else pixels[1::channels]
    rgba[2::4] = pixels[0::channels] if grey else pixels[2::channels]
    rgba[3::4] = pixels[channels - 1::channels] if channels in (2, 4) else b"\xff" * (len(rgba) // 4)
    return rgba


def encode(image):
    """The PNG bytes of an Image (RGBA, 8 bits, each row filtered 'none')."""
    stride = 4 * image.width
    raw = b"".join(b"\x00" + image.rgba[y * stride:(y + 1) * stride] for y in range(image.height))

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    header = struct.pack(">IIBBBBB", image.width, image.height, 8, 6, 0, 0, 0)
    return SIGNATURE + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b"")


def side_by_side(images, gap=0, background=(255, 255, 255, 255)):
    """One Image of images left to right, gap pixels apart, each centred
    vertically on the background."""
    width = sum(im.width for im in images) + gap * (len(images) - 1)
    height = max(im.height for im in images)
    out = Image(width, height, bytes(background) * (width * height))
    x = 0
    for im in images:
        top = (height - im.height) // 2
        for y in range(im.height):
            at = 4 * ((top + y) * width + x)
            out.rgba[at:at + 4 * im.width] = im.rgba[4 * y * im.width:4 * (y + 1) * im.width]
        x += im.width + gap
    return out
