#!/usr/bin/env python3
"""A turntable: N frames around a model (or scene), each as PNGs with depth, normals and object masks.

  PYTHONPATH=build/python tools/examples/turntable.py MODEL.glb OUT_DIR [--frames 24] [--size 320x240]
"""
import argparse
import math
import pathlib

import whitted

parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("model", help="a model file (a quick look) or a scene .xml")
parser.add_argument("out", type=pathlib.Path)
parser.add_argument("--frames", type=int, default=24)
parser.add_argument("--size", default="320x240")
args = parser.parse_args()
width, height = map(int, args.size.split("x"))

scene = whitted.load(args.model)
renderer = whitted.Renderer()
centre = scene.camera.look_at
offset = [p - c for p, c in zip(scene.camera.position, centre)]
radius, lift = math.hypot(offset[0], offset[2]), offset[1]
args.out.mkdir(parents=True, exist_ok=True)
for frame in range(args.frames):
    angle = math.atan2(offset[2], offset[0]) + 2 * math.pi * frame / args.frames
    scene.camera.position = (centre[0] + radius * math.cos(angle), centre[1] + lift,
                             centre[2] + radius * math.sin(angle))  # only the camera is uploaded again
    result = renderer.render(scene, width=width, height=height, aovs=("depth", "normal", "object_id"))
    result.save(args.out / f"frame{frame:03d}.png")  # frameNNN.png, .depth.png, .normal.png, .object_id.png, .json
    print(f"frame {frame + 1}/{args.frames}: {result.record['timings_s']['render']:.3f} s")
