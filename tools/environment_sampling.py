#!/usr/bin/env python3
"""How fast the environment's light converges (scenes/README.md "Environment light"): a black environment with
one small bright sun disc lights a diffuse floor past the straight edge of a slab; the camera looks straight down
at the penumbra. The same render is made with the image importance-sampled (luminance x sin theta, the default)
and with directions drawn uniformly over the sphere, at growing numbers of light samples per pixel (spp x
<shadow_samples>), and each is compared with a reference: uniform sampling at 16 times the most samples measured.
Prints and writes (--json) the PSNR of each, and the fewest samples at which each reaches --target dB.

    PYTHONPATH=build/python /usr/bin/python3 tools/environment_sampling.py --json out.json
"""
import argparse
import json
import math
import pathlib
import platform
import subprocess
import tempfile
import time

import numpy as np
import OpenImageIO as oiio
import whitted

SUN_ELEVATION = 50.0     # degrees above the horizon, from +x
SUN_RADIUS = 8.0         # degrees
WIDTH, HEIGHT = 16, 4    # the image: the penumbra across it (few pixels: the reference takes 2^20 samples each)
IMAGE_W, IMAGE_H = 256, 128


def sun_panorama():
    """Black but for a disc whose radiance L gives it the light of a directional light of colour 1
    (L * solid angle / pi = 1: the environment light's normalisation)."""
    e = math.radians(SUN_ELEVATION)
    sun = np.array([math.cos(e), math.sin(e), 0.0])
    u = (np.arange(IMAGE_W) + 0.5) / IMAGE_W
    t = (np.arange(IMAGE_H) + 0.5) / IMAGE_H
    uu, tt = np.meshgrid(u, t)
    theta, phi = tt * np.pi, (uu - 0.5) * 2 * np.pi  # the README's mapping, no rotation
    d = np.stack([np.sin(theta) * np.sin(phi), np.cos(theta), -np.sin(theta) * np.cos(phi)], axis=-1)
    inside = d @ sun >= math.cos(math.radians(SUN_RADIUS))
    texel_solid_angle = (2 * np.pi / IMAGE_W) * (np.pi / IMAGE_H) * np.sin(theta)
    radiance = np.pi / float(np.sum(texel_solid_angle[inside]))
    image = np.zeros((IMAGE_H, IMAGE_W, 3), np.float32)
    image[inside] = radiance
    return image


def scene_file(folder, shadow_samples):
    edge = -1.0 / math.tan(math.radians(SUN_ELEVATION))  # where the slab's edge casts its shadow's centre
    path = folder / f"sun_{shadow_samples}.xml"
    path.write_text(f"""<scene>
  <camera><position x="{edge}" y="5" z="0"/><window_position x="{edge}" y="4" z="0"/><up x="0" y="0" z="-1"/>
    <projection>orthographic</projection><window_height>0.25</window_height>
    <width>{WIDTH}</width><height>{HEIGHT}</height></camera>
  <environment><image>sun.exr</image><shadow_samples>{shadow_samples}</shadow_samples></environment>
  <ambient_light r="0" g="0" b="0"/>
  <lights></lights>
  <objects>
    <object><position x="0" y="0" z="0"/><diffuse_color r="0.8" g="0.8" b="0.8"/>
      <properties><type>plane</type><normal x="0" y="1" z="0"/><diffuse_coef>1</diffuse_coef></properties></object>
    <object><position x="-6" y="1" z="-6"/><diffuse_color r="0.5" g="0.5" b="0.5"/>
      <properties><type>box</type><size x="6" y="0.2" z="12"/></properties></object>
  </objects>
</scene>
""")
    return whitted.load(str(path))


def render(renderer, folder, samples, sampling, seed=0):
    """samples light samples per pixel: spp x shadow_samples with shadow_samples up to 256."""
    shadow = min(samples, 256)
    spp = samples // shadow
    scene = scene_file(folder, shadow)
    start = time.perf_counter()
    result = renderer.render(scene, spp=spp, aa="uniform", environment_sampling=sampling, seed=seed)
    return result.image, time.perf_counter() - start, result.record


def psnr(a, b):
    return 10 * math.log10(1.0 / float(np.mean((a - b) ** 2)))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--max-samples", type=int, default=65536, help="the most light samples per pixel measured")
    parser.add_argument("--target", type=float, default=40.0, help="the PSNR (dB) to reach")
    parser.add_argument("--json", help="write the results here")
    args = parser.parse_args()
    renderer = whitted.Renderer()
    with tempfile.TemporaryDirectory() as tmp:
        folder = pathlib.Path(tmp)
        out = oiio.ImageOutput.create(str(folder / "sun.exr"))
        out.open(str(folder / "sun.exr"), oiio.ImageSpec(IMAGE_W, IMAGE_H, 3, oiio.FLOAT))
        out.write_image(sun_panorama())
        out.close()
        reference, reference_seconds, record = render(renderer, folder, 16 * args.max_samples, "uniform", seed=1)
        rows = []
        counts = [4 ** k for k in range(1, 20) if 4 ** k <= args.max_samples]
        for sampling in ("importance", "uniform"):
            for n in counts:
                image, seconds, _ = render(renderer, folder, n, sampling)
                rows.append({"sampling": sampling, "samples_per_pixel": n, "psnr_db": round(psnr(image, reference), 2),
                             "seconds": round(seconds, 3)})
                print(f"{sampling:10} {n:7} samples/pixel: {rows[-1]['psnr_db']:6.2f} dB  {seconds:.2f} s", flush=True)
    reached = {s: min((r["samples_per_pixel"] for r in rows if r["sampling"] == s and r["psnr_db"] >= args.target),
                      default=None) for s in ("importance", "uniform")}
    print(f"reference: uniform, {16 * args.max_samples} samples/pixel ({reference_seconds:.1f} s); "
          f"{args.target} dB reached at: {reached}")
    if args.json:
        cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "")
        load = open("/proc/loadavg").read().split()[:3]
        result = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "cpu": cpu,
                  "device": record.get("device"), "load_average": load, "python": platform.python_version(),
                  "git": subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                                        text=True).stdout.strip(),
                  "scene": {"image": [WIDTH, HEIGHT], "panorama": [IMAGE_W, IMAGE_H],
                            "sun_elevation_deg": SUN_ELEVATION, "sun_radius_deg": SUN_RADIUS},
                  "reference": {"sampling": "uniform", "samples_per_pixel": 16 * args.max_samples, "seed": 1,
                                "seconds": round(reference_seconds, 2)},
                  "target_db": args.target, "reached_at": reached, "runs": rows}
        pathlib.Path(args.json).write_text(json.dumps(result, indent=2) + "\n")


if __name__ == "__main__":
    main()
