#!/usr/bin/python3
"""Writes scenes/textures/sky.exr, the equirectangular HDR panorama of scenes/environment.xml.

Generated, not photographed, so the repository owns it outright and anyone can regenerate it bit for bit.
512x256 texels, linear half floats (scenes/README.md "Environment": the top row looks along +y, the image's
centre along -z, u = 0.75 along +x):
  sky      a blue zenith fading to a pale horizon, with soft clouds
  sun      a disc 3 degrees across, 40 degrees above the horizon towards +x and -z, radiance 900 (it lights
           like a directional light of colour 0.62: radiance x solid angle / pi)
  ground   a dark green field with a checker of pale paths, so that mirrors show a horizon and a pattern
Usage: tools/make_environment_panorama.py [OUTPUT_DIR]
"""
import math
import os
import sys

import numpy as np
import OpenImageIO as oiio

W, H = 512, 256
SUN_ELEVATION, SUN_AZIMUTH, SUN_RADIUS = 40.0, 45.0, 1.5  # degrees; azimuth from -z towards +x
SUN_RADIANCE = 900.0


def directions():
    u = (np.arange(W) + 0.5) / W
    t = (np.arange(H) + 0.5) / H
    uu, tt = np.meshgrid(u, t)
    theta, phi = tt * np.pi, (uu - 0.5) * 2 * np.pi
    return np.stack([np.sin(theta) * np.sin(phi), np.cos(theta), -np.sin(theta) * np.cos(phi)], axis=-1), uu


def clouds(uu, d, rng):
    """Soft value noise over the sky, tileable in u."""
    total, amplitude = np.zeros(uu.shape), 1.0
    for octave in range(4):
        cells = 6 * 2**octave
        lattice = rng.random((cells + 1, cells))
        x = uu * cells
        y = np.clip(d[..., 1], 0, 1) * cells
        x0, y0 = np.floor(x).astype(int) % cells, np.minimum(np.floor(y).astype(int), cells - 1)
        fx, fy = x - np.floor(x), y - np.floor(y)
        fx, fy = fx * fx * (3 - 2 * fx), fy * fy * (3 - 2 * fy)
        x1 = (x0 + 1) % cells
        a = lattice[y0, x0] * (1 - fx) + lattice[y0, x1] * fx
        b = lattice[y0 + 1, x0] * (1 - fx) + lattice[y0 + 1, x1] * fx
        total += amplitude * (a * (1 - fy) + b * fy)
        amplitude *= 0.5
    return np.clip((total / 1.875 - 0.55) * 3.0, 0, 1)


def panorama():
    rng = np.random.default_rng(38)
    d, uu = directions()
    y = d[..., 1]
    up = np.clip(y, 0, 1)[..., None]
    zenith, horizon = np.array([0.18, 0.32, 0.75]), np.array([0.85, 0.88, 0.92])
    sky = horizon + (zenith - horizon) * np.sqrt(up)
    cloud = (clouds(uu, d, rng) * np.clip(y * 6, 0, 1))[..., None]
    sky = sky * (1 - cloud) + np.array([1.1, 1.1, 1.1]) * cloud
    # The ground: a field seen from above, a checker of paths in its plane (y = -1 at distance 1 below).
    below = np.maximum(-y, 1e-3)
    gx, gz = d[..., 0] / below, d[..., 2] / below
    path = ((np.floor(gx * 1.5) + np.floor(gz * 1.5)) % 2 == 0)[..., None]
    ground = np.where(path, np.array([0.35, 0.3, 0.22]), np.array([0.08, 0.12, 0.05]))
    # Towards the horizon the paths shrink below a texel: fade them into their mean, as a filter would.
    near = np.clip(-y * 8, 0, 1)[..., None]
    ground = np.array([0.215, 0.21, 0.135]) * (1 - near) + ground * near
    ground = ground * (0.6 + 0.4 * np.clip(-y * 4, 0, 1))[..., None]
    image = np.where((y >= 0)[..., None], sky, ground)
    e, a = math.radians(SUN_ELEVATION), math.radians(SUN_AZIMUTH)
    sun = np.array([math.cos(e) * math.sin(a), math.sin(e), -math.cos(e) * math.cos(a)])
    image[d @ sun >= math.cos(math.radians(SUN_RADIUS))] = SUN_RADIANCE * np.array([1.0, 0.95, 0.85])
    return image.astype(np.float16).astype(np.float32)


def main():
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "scenes", "textures")
    path = os.path.join(out_dir, "sky.exr")
    out = oiio.ImageOutput.create(path)
    spec = oiio.ImageSpec(W, H, 3, oiio.HALF)
    spec.attribute("compression", "zip")
    if not out or not out.open(path, spec) or not out.write_image(panorama()):
        sys.exit(f"cannot write {path}: {oiio.geterror()}")
    out.close()
    print(path)


if __name__ == "__main__":
    main()
