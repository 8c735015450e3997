#!/usr/bin/python3
"""Tests of whitted_kit (tools/gpu_kit/whitted_kit.cpp), the GPU check's helper, against the Python it stands in for
on a machine without Python: its PSNR against tools/bench/measures.py's psnr(), its mesh against
tools/generate_scenes.py's, byte for byte, its measures against a record's numbers.

Usage: gpu_kit_test.py --tool PATH"""

import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tools"))
sys.dont_write_bytecode = True
from bench.measures import psnr  # noqa: E402 (after the path is set)

p = argparse.ArgumentParser()
p.add_argument("--tool", required=True)
TOOL = os.path.abspath(p.parse_args().tool)
work = tempfile.mkdtemp(prefix="gpu-kit-test-")
failures = []


def check(condition, what):
    print(("ok      " if condition else "FAILED  ") + what)
    if not condition:
        failures.append(what)


def tool(*args):
    r = subprocess.run([TOOL, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    return r.returncode, r.stdout, r.stderr


def write_png(path, pixels):
    out = oiio.ImageOutput.create(path)
    out.open(path, oiio.ImageSpec(pixels.shape[1], pixels.shape[0], pixels.shape[2], oiio.UINT8))
    out.write_image(pixels)
    out.close()


def test_psnr():
    rng = np.random.default_rng(7)
    a = rng.integers(0, 256, (48, 64, 3), dtype=np.uint8)
    b = a.copy()
    b[10:20, 5:9] = np.clip(b[10:20, 5:9].astype(int) + rng.integers(-40, 40, (10, 4, 3)), 0, 255).astype(np.uint8)
    write_png(os.path.join(work, "a.png"), a)
    write_png(os.path.join(work, "b.png"), b)
    # An RGBA reference of the same RGB: the alpha channel is not compared.
    write_png(os.path.join(work, "a_rgba.png"), np.dstack([a, np.full((48, 64), 255, np.uint8)]))
    status, out, err = tool("psnr", os.path.join(work, "b.png"), os.path.join(work, "a.png"), "--diff",
                            os.path.join(work, "diff.png"))
    result = json.loads(out) if status == 0 else {}
    expected = psnr(os.path.join(work, "b.png"), os.path.join(work, "a.png"))
    check(status == 0 and math.isclose(result["psnr_db"], expected, rel_tol=1e-12),
          f"psnr equals tools/bench/measures.py's ({result.get('psnr_db')} against {expected:.6f} dB) {err}")
    d = np.abs(b.astype(int) - a.astype(int))
    check(result.get("max_abs_diff") == int(d.max()) and result.get("differing_pixels") == int((d.max(axis=2) > 0).sum()),
          f"psnr counts the largest difference ({result.get('max_abs_diff')}) and the differing pixels "
          f"({result.get('differing_pixels')})")
    diff = oiio.ImageBuf(os.path.join(work, "diff.png")).get_pixels(oiio.UINT8)
    check(diff is not None and np.array_equal(diff, np.minimum(255, d * 8)), "--diff writes |image - reference| x 8")
    status, out, _ = tool("psnr", os.path.join(work, "a.png"), os.path.join(work, "a_rgba.png"))
    check(status == 0 and json.loads(out)["psnr_db"] is None, "identical RGB (an RGBA reference) gives null")
    write_png(os.path.join(work, "small.png"), a[:24])
    status, _, err = tool("psnr", os.path.join(work, "a.png"), os.path.join(work, "small.png"))
    check(status == 1 and "64x48" in err and "64x24" in err, f"images of two sizes: exit 1 naming both ({err.strip()})")
    status, _, err = tool("psnr", os.path.join(work, "missing.png"), os.path.join(work, "a.png"))
    check(status == 1 and "missing.png" in err, f"a missing image: exit 1 naming it ({err.strip()})")


def test_mesh():
    for triangles in (8, 2000, 50000):
        xml = os.path.join(work, f"mesh{triangles}.xml")
        subprocess.run([sys.executable, os.path.join(ROOT, "tools", "generate_scenes.py"), "mesh", str(triangles), xml],
                       check=True, stderr=subprocess.DEVNULL)
        ours = os.path.join(work, f"kit{triangles}.obj")
        status, _, err = tool("mesh-obj", str(triangles), ours)
        with open(xml[:-4] + ".obj", "rb") as f, open(ours, "rb") as g:
            same = status == 0 and f.read() == g.read()
        check(same, f"mesh-obj {triangles} is generate_scenes.py's OBJ byte for byte {err}")
    status, _, err = tool("mesh-obj", "7", os.path.join(work, "bad.obj"))
    check(status == 2 and "outside 8..20000000" in err and not os.listdir(work).count("bad.obj"),
          f"mesh-obj 7: exit 2, nothing written ({err.strip()})")


def record(path, primary, shadow, secondary, render):
    total = primary + shadow + secondary
    doc = {"settings": {"trace": "bvh"}, "sampling": {"camera_samples": primary}, "lost_samples": 0,
           "device": {"name": "gpu", "type": "discrete", "driver": "d"},
           "timings_s": {"load": 0.1, "bvh_build": 0.2, "acceleration_structure_build": 0.0, "pipeline": 0.3,
                         "upload": 0.01, "render": render},
           "memory_bytes": {"device_buffers": 1000, "peak_rss": 2000},
           "rays": {"primary": primary, "shadow": shadow, "secondary": secondary, "per_second": total / render}}
    with open(path, "w", encoding="utf-8") as f:
        json.dump(doc, f)


def test_measure():
    paths = [os.path.join(work, f"r{k}.json") for k in range(3)]
    for path, render in zip(paths, (0.5, 0.25, 1.0)):
        record(path, 3_000_000, 1_000_000, 500_000, render)
    status, out, err = tool("measure", paths[0])
    one = json.loads(out) if status == 0 else {}
    check(status == 0 and math.isclose(one["primary_shadow_mrays_per_s"], 8.0) and
          math.isclose(one["mrays_per_s"], 9.0) and one["device_type"] == "discrete",
          f"measure: camera plus shadow rays over the render time, all rays from the record {err}")
    status, out, err = tool("measure", *paths)
    many = json.loads(out) if status == 0 else {}
    check(status == 0 and len(many["runs"]) == 3 and math.isclose(many["median"]["render_s"], 0.5) and
          math.isclose(many["median"]["primary_shadow_mrays_per_s"], 8.0),
          f"measure of three records: every run and the medians {err}")
    with open(os.path.join(work, "bad.json"), "w", encoding="utf-8") as f:
        f.write("{}")
    status, _, err = tool("measure", os.path.join(work, "bad.json"))
    check(status == 1 and "not a whitted render record" in err, f"measure of a non-record: exit 1 ({err.strip()})")


try:
    test_psnr()
    test_mesh()
    test_measure()
finally:
    shutil.rmtree(work, ignore_errors=True)
print(f"{len(failures)} failed" if failures else "all passed")
sys.exit(1 if failures else 0)
