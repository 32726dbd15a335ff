"""cgview_client.png: decoding every filter and colour type, encoding, composition."""
import random
import struct
import unittest
import zlib

from cgview_client import png


def paeth(a, b, c):
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    return a if pa <= pb and pa <= pc else b if pb <= pc else c


def filtered(kind, line, prev, bpp):
    """A scanline filtered as an encoder does (PNG spec 9.2)."""
    def left(i):
        return line[i - bpp] if i >= bpp else 0

    def up_left(i):
        return prev[i - bpp] if i >= bpp else 0

    predict = [lambda i: 0, left, lambda i: prev[i], lambda i: (left(i) + prev[i]) // 2,
               lambda i: paeth(left(i), prev[i], up_left(i))][kind]
    return bytes([kind]) + bytes((line[i] - predict(i)) & 255 for i in range(len(line)))


def make_png(width, height, colour, samples, kinds):
    """A PNG of 8-bit samples (row by row) with the filter of each row from kinds."""
    channels = png.CHANNELS[colour]
    stride = width * channels
    raw, prev = b"", bytes(stride)
    for y in range(height):
        line = samples[y * stride:(y + 1) * stride]
        raw += filtered(kinds[y % len(kinds)], line, prev, channels)
        prev = line

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    header = struct.pack(">IIBBBBB", width, height, 8, colour, 0, 0, 0)
    idat = zlib.compress(raw)
    # IDAT split in two, as encoders may.
    return (png.SIGNATURE + chunk(b"IHDR", header) + chunk(b"IDAT", idat[:5]) + chunk(b"IDAT", idat[5:])
            + chunk(b"IEND", b""))


class DecodeTest(unittest.TestCase):
    def test_every_filter_and_colour_type(self):
        rng = random.Random(7)
        width, height = 5, 10
        for colour, channels in png.CHANNELS.items():
            samples = bytes(rng.randrange(256) for _ in range(width * height * channels))
            image = png.decode(make_png(width, height, colour, samples, [0, 1, 2, 3, 4]))
            self.assertEqual((image.width, image.height), (width, height))
            for y in range(height):
                for x in range(width):
                    s = samples[(y * width + x) * channels:(y * width + x + 1) * channels]
                    grey = channels < 3
                    expected = (s[0], s[0] if grey else s[1], s[0] if grey else s[2],
                                s[-1] if channels in (2, 4) else 255)
                    self.assertEqual(image.pixel(x, y), expected, f"colour type {colour}, pixel {x},{y}")

    def test_round_trip(self):
        image = png.Image(3, 2, bytes(range(24)))
        back = png.decode(png.encode(image))
        self.assertEqual((back.width, back.height, back.rgba), (3, 2, image.rgba))

    def test_refuses_what_it_does_not_read(self):
        with self.assertRaisesRegex(ValueError, "not a PNG"):
            png.decode(b"GIF89a")
        sixteen = make_png(1, 1, 2, bytes(3), [0]).replace(struct.pack(">IIBB", 1, 1, 8, 2), struct.pack(">IIBB", 1, 1, 16, 2))
        with self.assertRaisesRegex(ValueError, "bit depth 16"):
            png.decode(sixteen)
        with self.assertRaisesRegex(ValueError, "RGBA pixels"):
            png.Image(2, 2, bytes(3))


class SideBySideTest(unittest.TestCase):
    def test_lays_images_left_to_right_centred(self):
        red = png.Image(2, 2, bytes([255, 0, 0, 255]) * 4)
        blue = png.Image(3, 4, bytes([0, 0, 255, 255]) * 12)
        out = png.side_by_side([red, blue], gap=1, background=(9, 9, 9, 255))
        self.assertEqual((out.width, out.height), (6, 4))
        self.assertEqual(out.pixel(0, 0), (9, 9, 9, 255))  # above the shorter image
        self.assertEqual(out.pixel(1, 1), (255, 0, 0, 255))
        self.assertEqual(out.pixel(1, 3), (9, 9, 9, 255))
        self.assertEqual(out.pixel(2, 2), (9, 9, 9, 255))  # the gap
        self.assertEqual(out.pixel(3, 0), (0, 0, 255, 255))
        self.assertEqual(out.pixel(5, 3), (0, 0, 255, 255))


if __name__ == "__main__":
    unittest.main()
