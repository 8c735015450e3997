#!/usr/bin/python3
"""Writes the textures of scenes/showcase.xml into scenes/textures/.

The textures are generated, not photographed, so the repository owns them
outright and anyone can regenerate them bit for bit:
  bricks.png         diffuse colour (sRGB): running-bond bricks, mortar
  bricks_normal.png  the bricks' tangent-space normal map (linear, OpenGL
                     green-up: +y points to increasing v, the image's top)
  planet.png         an equirectangular (longitude/latitude) planet for the
                     sphere mapping: oceans, continents, ice caps
Usage: tools/make_showcase_textures.py [OUTPUT_DIR]
"""
import os
import sys

import numpy as np
import OpenImageIO as oiio


def value_noise(shape, cells, rng, octaves=4):
    """Fractal value noise in [0, 1], tileable in x (bilinear lattice)."""
    h, w = shape
    total = np.zeros(shape)
    amplitude, norm = 1.0, 0.0
    for octave in range(octaves):
        cy, cx = cells[0] * 2**octave, cells[1] * 2**octave
        lattice = rng.random((cy + 1, cx))
        y = np.linspace(0, cy, h, endpoint=False)[:, None]
        x = np.linspace(0, cx, w, endpoint=False)[None, :]
        y0, x0 = np.floor(y).astype(int), np.floor(x).astype(int)
        fy, fx = y - y0, x - x0
        fy, fx = fy * fy * (3 - 2 * fy), fx * fx * (3 - 2 * fx)  # smoothstep
        x1 = (x0 + 1) % cx
        a = lattice[y0, x0] * (1 - fx) + lattice[y0, x1] * fx
        b = lattice[y0 + 1, x0] * (1 - fx) + lattice[y0 + 1, x1] * fx
        total += amplitude * (a * (1 - fy) + b * fy)
        norm += amplitude
        amplitude *= 0.5
    return total / norm


def write(path, pixels, srgb):
    """Writes float pixels in [0, 1] as 8-bit PNG, atomically."""
    h, w, c = pixels.shape
    spec = oiio.ImageSpec(w, h, c, oiio.UINT8)
    spec.attribute("oiio:ColorSpace", "sRGB" if srgb else "linear")
    tmp = path + ".tmp.png"
    out = oiio.ImageOutput.create(tmp)
    if not out or not out.open(tmp, spec):
        sys.exit(f"make_showcase_textures: cannot write {path}: {oiio.geterror()}")
    out.write_image(np.clip(np.rint(pixels * 255.0), 0, 255).astype(np.uint8))
    out.close()
    os.replace(tmp, path)


def bricks(size, rng):
    """Colour and height of 4 x 8 running-bond bricks over a square tile."""
    rows, cols, mortar = 8, 4, 0.06
    v = (np.arange(size)[:, None] + 0.5) / size * rows  # brick rows, top of image = row 0
    u = (np.arange(size)[None, :] + 0.5) / size * cols
    row = np.floor(v).astype(int)
    u = u + 0.5 * (row % 2)  # every other row shifted by half a brick
    col = np.floor(u).astype(int) % cols
    fu, fv = u - np.floor(u), v - np.floor(v)
    # Distance to the nearest mortar line, in brick-height units.
    edge = np.minimum(np.minimum(fu, 1 - fu) * rows / cols, np.minimum(fv, 1 - fv))
    height = np.clip(edge / mortar, 0.0, 1.0)
    height = height * height * (3 - 2 * height)  # rounded brick edges
    tint = rng.random((rows, cols))[row % rows, col]
    grain = value_noise((size, size), (16, 16), rng, octaves=3)
    brick = np.stack([0.55 + 0.2 * tint, 0.22 + 0.08 * tint, 0.14 + 0.05 * tint], -1)
    brick *= (0.8 + 0.4 * grain)[..., None]
    mortar_colour = np.array([0.78, 0.76, 0.7]) * (0.9 + 0.2 * grain)[..., None]
    colour = brick * height[..., None] + mortar_colour * (1 - height[..., None])
    return colour, height + 0.08 * grain * height


def normal_map(height, strength):
    """Tangent-space normals of a tileable height field (u right, v up)."""
    size = height.shape[0]
    dh_du = (np.roll(height, -1, 1) - np.roll(height, 1, 1)) * size / 2
    dh_drow = (np.roll(height, -1, 0) - np.roll(height, 1, 0)) * size / 2
    dh_dv = -dh_drow  # image rows grow downwards, v upwards
    n = np.stack([-strength * dh_du, -strength * dh_dv, np.ones_like(height)], -1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    return n * 0.5 + 0.5


def planet(width, rng):
    h = width // 2
    land = value_noise((h, width), (4, 8), rng, octaves=5)
    lat = (0.5 - (np.arange(h)[:, None] + 0.5) / h) * np.pi  # +pi/2 at the top row
    ocean = np.array([0.05, 0.16, 0.42])
    shallow = np.array([0.1, 0.35, 0.6])
    green = np.array([0.18, 0.42, 0.14])
    desert = np.array([0.72, 0.6, 0.36])
    ice = np.array([0.93, 0.95, 0.97])
    sea_level = 0.56
    colour = np.where((land < sea_level)[..., None],
                      ocean + (shallow - ocean) * np.clip((land - 0.42) / 0.1, 0, 1)[..., None],
                      green + (desert - green) * np.clip((land - 0.68) / 0.1, 0, 1)[..., None])
    polar = np.clip((np.abs(lat) - 1.28 + 0.15 * (land - 0.5)) / 0.08, 0, 1)
    return colour * (1 - polar[..., None]) + ice * polar[..., None]


def main():
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "scenes", "textures")
    os.makedirs(out_dir, exist_ok=True)
    rng = np.random.default_rng(20261201)
    colour, height = bricks(256, rng)
    write(os.path.join(out_dir, "bricks.png"), colour, srgb=True)
    write(os.path.join(out_dir, "bricks_normal.png"), normal_map(height, 0.008), srgb=False)
    write(os.path.join(out_dir, "planet.png"), planet(512, rng), srgb=True)


if __name__ == "__main__":
    main()
