#!/usr/bin/env python3
"""The Python module's benchmark (issue 17; tools/README.md "Python module benchmark"): 100 frames of a camera
orbit around scenes/room.xml at 320x240, default anti-aliasing, (a) one whitted.Renderer in a Python loop against
(b) one `whitted render` process per frame; frames per second of both, their ratio, the CPU and the driver, and
the fixed cost of a render on a warm renderer (8x8).

  PYTHONPATH=build/python /usr/bin/python3 tools/bench/python_orbit.py [--frames 100] [--out FILE.json]
"""
import argparse
import json
import math
import os
import pathlib
import platform
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]


def cpu_model():
    for line in open("/proc/cpuinfo"):
        if line.startswith("model name"):
            return line.split(":", 1)[1].strip()
    return platform.processor()


def orbit(scene, frames):
    """Camera positions around the look-at point, at the scene camera's distance and height."""
    c = scene.camera.look_at
    p = scene.camera.position
    dx, dy, dz = (p[0] - c[0], p[1] - c[1], p[2] - c[2])
    radius, start = math.hypot(dx, dz), math.atan2(dz, dx)
    return [(c[0] + radius * math.cos(start + 0.6 * k / frames), p[1], c[2] + radius * math.sin(start + 0.6 * k / frames))
            for k in range(frames)]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--frames", type=int, default=100)
    parser.add_argument("--size", default="320x240")
    parser.add_argument("--build", default=str(ROOT / "build"))
    parser.add_argument("--out", default=None, help="JSON file [print only]")
    args = parser.parse_args()
    sys.path.insert(0, str(pathlib.Path(args.build) / "python"))
    import whitted

    width, height = map(int, args.size.split("x"))
    scene_path = ROOT / "scenes" / "room.xml"
    scene = whitted.load(scene_path)
    positions = orbit(scene, args.frames)

    load_before = os.getloadavg()[0]
    # (a) One renderer; the first render (device, pipeline, upload) is counted.
    start = time.perf_counter()
    renderer = whitted.Renderer()
    for p in positions:
        scene.camera.position = p
        renderer.render(scene, width=width, height=height)
    module_seconds = time.perf_counter() - start
    # The floor: a warm renderer's 8x8 render (camera moved each time).
    floor = []
    for p in positions[:20]:
        scene.camera.position = p
        t = time.perf_counter()
        renderer.render(scene, width=8, height=8)
        floor.append(time.perf_counter() - t)

    # (b) One process per frame, each with its own edited scene file, to a PNG.
    with tempfile.TemporaryDirectory() as tmp:
        files = []
        for k, p in enumerate(positions):
            scene.camera.position = p
            files.append(pathlib.Path(tmp) / f"orbit{k:03d}.xml")
            scene.save(files[-1])
        exe = pathlib.Path(args.build) / "whitted"
        start = time.perf_counter()
        for k, f in enumerate(files):
            subprocess.run([str(exe), "render", str(f), "-o", str(pathlib.Path(tmp) / f"orbit{k:03d}.png"),
                            "--width", str(width), "--height", str(height), "-q"], check=True)
        process_seconds = time.perf_counter() - start

    module_fps = args.frames / module_seconds
    process_fps = args.frames / process_seconds
    floor.sort()
    report = {
        "benchmark": "python_orbit",
        "scene": "scenes/room.xml",
        "frames": args.frames,
        "size": [width, height],
        "anti_aliasing": "adaptive, spp 16 (the default)",
        "cpu": cpu_model(),
        "cores": os.cpu_count(),
        "device": renderer.device,
        "module_seconds": round(module_seconds, 3),
        "process_seconds": round(process_seconds, 3),
        "module_fps": round(module_fps, 2),
        "process_fps": round(process_fps, 2),
        "ratio": round(module_fps / process_fps, 2),
        "target_ratio": 5,
        "warm_8x8_seconds_median": round(floor[len(floor) // 2], 4),
        "warm_8x8_seconds_min": round(floor[0], 4),
        "load_average_1min": [round(load_before, 2), round(os.getloadavg()[0], 2)],  # before, after: other work
    }
    text = json.dumps(report, indent=2)
    print(text)
    if args.out:
        pathlib.Path(args.out).write_text(text + "\n")


if __name__ == "__main__":
    main()
