#!/usr/bin/env python3
"""Instances against flattened copies (scenes/README.md "Instances").

Writes a sphere mesh (OBJ, 2 * N * N triangles) and two scenes of COUNT
copies of it scattered on a floor, each rotated and scaled: one of
<instances> of one <prototype>, one of COUNT mesh objects naming the same
file (the copies the loader flattens into world space). Renders both with
the given whitted at 160x120, one after the other, and prints as JSON the
whole process's wall time and peak RSS, the load, BVH and render times the
executable reports, and the PSNR between the two images.

  tools/bench/instances.py build/whitted --count 200 --n 100 --out /tmp/instances
"""
import argparse
import json
import math
import os
import random
import re
import resource
import subprocess
import time


def sphere_obj(path, n):
    with open(path, "w") as out:
        for i in range(n + 1):
            theta = math.pi * i / n
            for j in range(n):
                phi = 2 * math.pi * j / n
                out.write("v %f %f %f\n" % (math.sin(theta) * math.cos(phi), math.cos(theta),
                                            math.sin(theta) * math.sin(phi)))
        for i in range(n):
            for j in range(n):
                a, b = i * n + j + 1, i * n + (j + 1) % n + 1
                c, d = a + n, b + n
                out.write("f %d %d %d\nf %d %d %d\n" % (a, c, b, b, c, d))


def scenes(out, count):
    random.seed(1)
    head = ('<scene><camera><position x="0" y="25" z="40"/><window_position x="0" y="24.4" z="39.2"/>'
            '<width>160</width><height>120</height></camera><lights><light><position x="10" y="40" z="20"/>'
            '<color r="1" g="1" b="1"/></light></lights><objects>')
    colour = '<diffuse_color r="0.8" g="0.5" b="0.3"/>'
    flat, inst = head, head + ('</objects><prototypes><prototype><name>ball</name><objects><object>' + colour +
                               '<properties><type>mesh</type><file>ball.obj</file></properties></object>'
                               '</objects></prototype></prototypes><instances>')
    for _ in range(count):
        position = '<position x="%g" y="0" z="%g"/>' % (random.uniform(-20, 20), random.uniform(-20, 20))
        placement = '<rotation x="0" y="%g" z="0"/><scale>%g</scale>' % (random.uniform(0, 360),
                                                                           random.uniform(0.5, 1.5))
        flat += ('<object>' + position + colour + '<properties><type>mesh</type><file>ball.obj</file>' +
                 placement + '</properties></object>')
        inst += '<instance><prototype>ball</prototype>' + position + placement + '</instance>'
    for name, text in (("flat", flat + '</objects></scene>'), ("instances", inst + '</instances></scene>')):
        with open(os.path.join(out, name + ".xml"), "w") as f:
            f.write(text)


def render(whitted, out, name):
    start = time.monotonic()
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    run = subprocess.run([whitted, "render", name + ".xml", "-o", name + ".exr"], cwd=out, capture_output=True,
                         text=True, check=True)
    wall = time.monotonic() - start
    rss = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    log = run.stderr
    seconds = lambda pattern: float(re.search(pattern, log).group(1))
    return {"wall_s": round(wall, 3), "peak_rss_mib": round(max(rss, before) / 1024, 1),
            "load_s": seconds(r"scene loaded in ([0-9.]+) s"), "bvh_s": seconds(r"built in ([0-9.]+) s"),
            "render_s": seconds(r"\) in ([0-9.]+) s")}


def psnr(out):
    import numpy as np
    import OpenImageIO as oiio
    a, b = (oiio.ImageBuf(os.path.join(out, n + ".exr")).get_pixels(oiio.FLOAT)[..., :3].clip(0, 1)
            for n in ("instances", "flat"))
    mse = float(((a - b) ** 2).mean())
    return 99.0 if mse == 0 else round(10 * math.log10(1 / mse), 2)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("whitted")
    p.add_argument("--count", type=int, default=200)
    p.add_argument("--n", type=int, default=100, help="the sphere's rings and segments: 2 n^2 triangles")
    p.add_argument("--out", default="/tmp/whitted-instances")
    a = p.parse_args()
    a.whitted = os.path.abspath(a.whitted)
    os.makedirs(a.out, exist_ok=True)
    sphere_obj(os.path.join(a.out, "ball.obj"), a.n)
    scenes(a.out, a.count)
    # Peak RSS is the children's maximum so far: the smaller (instanced) render goes first.
    result = {"copies": a.count, "prototype_triangles": 2 * a.n * a.n,
              "instances": render(a.whitted, a.out, "instances"), "flat": render(a.whitted, a.out, "flat")}
    result["psnr_db"] = psnr(a.out)
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
