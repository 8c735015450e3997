#!/usr/bin/env python3
"""The GPU-readiness tier (tests/README.md "GPU readiness"): every shipped scene, and the
textured scene of tests/gpu_scenes/, rendered small, traced (`whitted trace`) and cast into
(`Renderer.cast_rays`) under one of the Khronos validation layer's extra checks:

  gpu-assisted     VK_VALIDATION_FEATURE_ENABLE_GPU_ASSISTED_EXT: every device-address and
                   descriptor access of the shaders checked against the buffers' bounds
  synchronization  VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT: hazards
                   between dispatches, copies and host access

Renders go through both trace paths where the device has ray queries. Any validation
message, or any failed run, fails the test. showcase.xml is left out: under GPU-assisted
validation lavapipe takes minutes to compile its textured build; textured.xml covers
that build with one small texture.

  gpu_readiness.py --check gpu-assisted --whitted build/whitted [--python build/python] [--scene room.xml]
"""
import argparse
import os
import pathlib
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
FEATURES = {
    "gpu-assisted": "VK_VALIDATION_FEATURE_ENABLE_GPU_ASSISTED_EXT",
    "synchronization": "VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT",
}
SIZE = ("--width", "32", "--height", "24")
# One pixel of the 32x24 image whose ray tree `whitted trace` records.
PIXEL = "16,12"

# cast_rays on a scene: the camera's rays through every pixel of a 32x24 image, and the same
# rays from a point beside the eye in every direction, so that most rays miss.
CAST = """
import sys, numpy as np, whitted
renderer = whitted.Renderer()
for path in sys.argv[1:]:
    scene = whitted.load(path)
    origins, directions = scene.camera.rays(width=32, height=24)
    hits = renderer.cast_rays(scene, origins, directions)
    rng = np.random.default_rng(0)
    around = rng.normal(size=directions.shape)
    renderer.cast_rays(scene, origins + 0.01, around / np.linalg.norm(around, axis=1, keepdims=True))
    print(path, int((hits["object_id"] != 0xFFFFFFFF).sum()), "of", len(hits["t"]), "rays hit")
"""


def scenes():
    shipped = [p for p in sorted((ROOT / "scenes").glob("*.xml")) if p.name != "showcase.xml"]
    return shipped + sorted((ROOT / "tests" / "gpu_scenes").glob("*.xml"))


def has_ray_query(whitted, out):
    """Whether the device renders through ray queries: a tiny render without validation says."""
    p = subprocess.run([whitted, "render", str(ROOT / "scenes" / "three_diffuse_spheres.xml"), "--width", "4",
                        "--height", "3", "--spp", "1", "--aov", "none", "--trace", "rayquery", "-q",
                        "-o", os.path.join(out, "probe.png")], capture_output=True, text=True, timeout=300)
    if p.returncode != 0 and "lacks VK_KHR_ray_query" not in p.stderr:
        raise RuntimeError("the probe render failed: " + p.stderr)
    return p.returncode == 0


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--check", choices=sorted(FEATURES), required=True)
    parser.add_argument("--whitted", required=True, help="the whitted executable")
    parser.add_argument("--python", help="the folder of the Python module (cast_rays); left out: not run")
    parser.add_argument("--scene", action="append", help="only this scene file name (again for more)")
    args = parser.parse_args()
    chosen = [p for p in scenes() if not args.scene or p.name in args.scene]

    env = dict(os.environ, WHITTED_VALIDATION="1", VK_LAYER_ENABLES=FEATURES[args.check], WHITTED_PIPELINE_CACHE="0")
    runs = []
    with tempfile.TemporaryDirectory() as out:
        paths = ["bvh"] + (["rayquery"] if has_ray_query(args.whitted, out) else [])
        if len(paths) == 1:
            print("the device has no ray queries: the BVH path only")
        for scene in chosen:
            for path in paths:
                runs.append((f"render {scene.name} --trace {path}",
                             [args.whitted, "render", str(scene), *SIZE, "--trace", path, "-q", "--aov", "all",
                              "-o", os.path.join(out, f"{scene.stem}.{path}.png")]))
            runs.append((f"trace {scene.name}", [args.whitted, "trace", str(scene), *SIZE, "--pixel", PIXEL]))
        if args.python:
            runs.append(("cast_rays", [sys.executable, "-c", CAST, *map(str, chosen)]))
            env["PYTHONPATH"] = args.python + os.pathsep + env.get("PYTHONPATH", "")
        failed = []
        for name, command in runs:
            start = time.monotonic()
            p = subprocess.run(command, capture_output=True, text=True, env=env, timeout=3600)
            seconds = time.monotonic() - start
            bad = p.returncode != 0 or "validation" in p.stderr.lower()
            print(f"{'FAIL' if bad else 'ok  '} {seconds:6.1f} s  {name}", flush=True)
            if bad:
                failed.append(name)
                print(p.stderr.strip(), flush=True)
    print(f"{len(runs) - len(failed)} of {len(runs)} runs clean under {args.check} validation")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
