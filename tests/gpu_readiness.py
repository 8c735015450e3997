#!/usr/bin/env python3
"""The GPU-readiness tier (tests/README.md "GPU readiness"): every shipped scene, and the
textured scene of tests/gpu_scenes/, rendered small, traced (`whitted trace`) and cast into
(`Renderer.cast_rays`) under one of the Khronos validation layer's extra checks:

  gpu-assisted     VK_VALIDATION_FEATURE_ENABLE_GPU_ASSISTED_EXT: every device-address and
                   descriptor access of the shaders checked against the buffers' bounds
  synchronization  VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT: hazards
                   between dispatches, copies and host access
  best-practices   VK_VALIDATION_FEATURE_ENABLE_BEST_PRACTICES_EXT with the NVIDIA and AMD
                   checks; every run also with memory as on a discrete GPU
                   (WHITTED_DISCRETE_MEMORY=1: device-local buffers, staging copies). A
                   message on ALLOWED, each with the reason its practice does not apply
                   here, is filtered out by the layer (VK_LAYER_MESSAGE_ID_FILTER)

Renders go through both trace paths where the device has ray queries. Any validation
message, or any failed run, fails the test. --count runs every case without the
allow-list and prints how many messages of each kind came (nothing fails then).
showcase.xml is left out: under GPU-assisted validation lavapipe takes minutes to
compile its textured build; textured.xml covers that build with one small texture.

  gpu_readiness.py --check gpu-assisted --whitted build/whitted [--python build/python] [--scene room.xml]
  gpu_readiness.py --check best-practices --whitted build/whitted --count
"""
import argparse
import collections
import os
import pathlib
import re
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
FEATURES = {
    "gpu-assisted": "VK_VALIDATION_FEATURE_ENABLE_GPU_ASSISTED_EXT",
    "synchronization": "VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT",
    "best-practices": "VK_VALIDATION_FEATURE_ENABLE_BEST_PRACTICES_EXT:VALIDATION_CHECK_ENABLE_VENDOR_SPECIFIC_NVIDIA:"
                      "VALIDATION_CHECK_ENABLE_VENDOR_SPECIFIC_AMD",
}
# The best practices that do not apply to whitted, each with the reason; every other
# message fails the tier.
ALLOWED = {
    "best-practices": {
        "UNASSIGNED-BestPractices-Pipeline-SortAndBind":
            "[AMD][NVIDIA] 'pipeline bound twice in the frame': a frame ends at vkQueuePresentKHR, and "
            "a render never presents, so the layer's frame is the whole run; each submission is a "
            "command buffer of its own (progress and Ctrl+C come between them, render/bands.cpp), "
            "and a command buffer starts with no pipeline bound: each binds it once",
        "UNASSIGNED-BestPractices-AccelerationStructure-NotAsync":
            "[NVIDIA] 'build acceleration structures on an asynchronous compute queue': a render "
            "(headless) takes a queue family that computes without drawing where the device has one "
            "(host/vk/context.cpp, findComputeQueueFamily); lavapipe has one family only, which draws too",
        "UNASSIGNED-BestPractices-CreatePipelineLayout-LargePipelineLayout":
            "[NVIDIA] 'less than 256 bytes to allow fast reads for all non-bindless descriptors': "
            "the non-bindless descriptors (one uniform block, 9 storage buffers, with ray queries the "
            "acceleration structure) take 152 or 160 bytes; "
            "the rest is the bindless texture array (kMaxTextures combined image samplers, "
            "indexed per material with nonuniformEXT, shaders/texture.glsl)",
        "UNASSIGNED-BestPractices-CreatePipelinesLayout-KeepLayoutSmall":
            "[AMD] 'pipeline layout size is too large' (over 13 DWORDs of user data): the push "
            "constants are the tile parameters (gpu::TileParams, 80 bytes), which every dispatch "
            "changes and the shader reads once per invocation, not per sample or per ray; the "
            "scene is read through one uniform block and device addresses",
    },
}
MESSAGE_ID = re.compile(r"\[ ([A-Za-z0-9_.:-]+) \]")
SIZE = ("--width", "32", "--height", "24")
# One pixel of the 32x24 image whose ray tree `whitted trace` records.
PIXEL = "16,12"

# cast_rays on a scene: the camera's rays through every pixel of a 32x24 image, and the same
# rays from a point beside the eye in every direction, so that most rays miss.
CAST = """
import os, sys, numpy as np, whitted
renderer = whitted.Renderer()
for path in sys.argv[1:]:
    scene = whitted.load(path)
    origins, directions = scene.camera.rays(width=32, height=24)
    try:
        hits = renderer.cast_rays(scene, origins, directions)
        rng = np.random.default_rng(0)
        around = rng.normal(size=directions.shape)
        renderer.cast_rays(scene, origins + 0.01, around / np.linalg.norm(around, axis=1, keepdims=True))
    except RuntimeError as e:  # --count: a validation message raises; the next scene's are counted too
        if os.environ.get("READINESS_COUNT") != "1" or "validation layer" not in str(e):
            raise
        continue
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
    parser.add_argument("--count", action="store_true",
                        help="no allow-list: count the messages of each kind; nothing fails")
    args = parser.parse_args()
    chosen = [p for p in scenes() if not args.scene or p.name in args.scene]

    env = dict(os.environ, WHITTED_VALIDATION="1", VK_LAYER_ENABLES=FEATURES[args.check], WHITTED_PIPELINE_CACHE="0")
    allowed = ALLOWED.get(args.check, {})
    if args.count:
        env["READINESS_COUNT"] = "1"
    elif allowed:
        env["VK_LAYER_MESSAGE_ID_FILTER"] = ":".join(allowed)
        print("allowed, as their practice does not apply:")
        for message, reason in allowed.items():
            print(f"  {message}: {reason}")
    # Best practices are checked with memory as lavapipe has it and as on a discrete GPU.
    modes = [("", {})]
    if args.check == "best-practices":
        modes.append((" [discrete memory]", {"WHITTED_DISCRETE_MEMORY": "1"}))
    runs = []
    with tempfile.TemporaryDirectory() as out:
        paths = ["bvh"] + (["rayquery"] if has_ray_query(args.whitted, out) else [])
        if len(paths) == 1:
            print("the device has no ray queries: the BVH path only")
        for mode, extra in modes:
            for scene in chosen:
                for path in paths:
                    runs.append((f"render {scene.name} --trace {path}{mode}", extra,
                                 [args.whitted, "render", str(scene), *SIZE, "--trace", path, "-q", "--aov", "all",
                                  "-o", os.path.join(out, f"{scene.stem}.{path}.png")]))
                runs.append((f"trace {scene.name}{mode}", extra,
                             [args.whitted, "trace", str(scene), *SIZE, "--pixel", PIXEL]))
            if args.python:
                runs.append((f"cast_rays{mode}", extra, [sys.executable, "-c", CAST, *map(str, chosen)]))
        if args.python:
            env["PYTHONPATH"] = args.python + os.pathsep + env.get("PYTHONPATH", "")
        failed = []
        counts = collections.Counter()
        for name, extra, command in runs:
            start = time.monotonic()
            p = subprocess.run(command, capture_output=True, text=True, env=dict(env, **extra), timeout=3600)
            seconds = time.monotonic() - start
            messages = [line for line in p.stderr.splitlines() if line.startswith("whitted: validation ")]
            for line in messages:
                found = MESSAGE_ID.search(line)
                counts[found.group(1) if found else line] += 1
            bad = p.returncode != 0 or "validation" in p.stderr.lower()
            if args.count:
                bad = p.returncode not in (0, 3)  # 3: the validation layer spoke
            print(f"{'FAIL' if bad else 'ok  '} {seconds:6.1f} s  {name}"
                  + (f"  ({len(messages)} messages)" if args.count else ""), flush=True)
            if bad:
                failed.append(name)
                print(p.stderr.strip(), flush=True)
    if args.count:
        print(f"{sum(counts.values())} messages in {len(runs)} runs under {args.check} validation:")
        for message, n in counts.most_common():
            print(f"  {n:5d}  {message}" + ("  (allowed)" if message in allowed else ""))
    print(f"{len(runs) - len(failed)} of {len(runs)} runs clean under {args.check} validation")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
