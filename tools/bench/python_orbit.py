#!/usr/bin/env python3
"""The Python module's benchmark (issue 17; tools/README.md "Python module benchmark"): 100 frames of a camera
orbit around scenes/room.xml at 320x240, default anti-aliasing, (a) one whitted.Renderer in a Python loop against
(b) one `whitted render` process per frame; frames per second of both, their ratio, the CPU and the driver, and
the fixed cost of a render on a warm renderer (8x8).

Part "moving" (--part moving): a 1,000-object scene built from Python (800 spheres and 200 small meshes, an
octahedron of 8 triangles each, on a floor plane), 100 of them moved per frame by Object.transform for --frames
frames at 320x240, 1 sample per pixel (aa "uniform", spp 1): the build time, frames per second, what each frame
uploaded (result.record["uploads"]), and the frame time of a camera-only change on the same scene; the target is
a moving frame at most 2x a camera-only frame.

Part "moving-mesh" (--part moving-mesh): the same with a static terrain of 524,288 triangles under the objects,
where a renderer's BVH parts count (render/gpu_scene.h BvhPartCache): the terrain's tree is built on the first
edit and reused by every later one, so a frame rebuilds the trees of the 1,000 objects and the top level only. It
reports what each frame built (result.record["bvh"]: parts reused, primitives whose trees were built).

  PYTHONPATH=build/python /usr/bin/python3 tools/bench/python_orbit.py [--part orbit|moving|moving-mesh|all]
      [--frames 100]
      [--out FILE.json]
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


def octahedron():
    v = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    f = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
    return v, f


def terrain(n):
    """A wavy n x n grid over [-16, 16]^2 near y = -0.8: 2 n^2 triangles."""
    import numpy as np
    xs = np.linspace(-16.0, 16.0, n + 1)
    x, z = np.meshgrid(xs, xs)
    y = -0.8 + 0.3 * np.sin(0.7 * x) * np.cos(0.5 * z)
    vertices = np.stack([x.ravel(), y.ravel(), z.ravel()], 1)
    index = np.arange((n + 1) * (n + 1)).reshape(n + 1, n + 1)
    a, b, c, d = index[:-1, :-1].ravel(), index[:-1, 1:].ravel(), index[1:, :-1].ravel(), index[1:, 1:].ravel()
    return vertices, np.concatenate([np.stack([a, c, b], 1), np.stack([b, c, d], 1)]).astype(np.int32)


def moving_objects(whitted, frames, width, height, terrain_quads=0):
    """The 1,000-object scene built in Python, 100 objects moved a frame, against camera-only frames; with
    terrain_quads, a static terrain mesh of 2 terrain_quads^2 triangles under them."""
    import numpy as np
    rng = np.random.default_rng(7)
    verts, faces = (np.array(a, dtype=float) for a in octahedron())
    faces = faces.astype(np.int32)
    start = time.perf_counter()
    scene = whitted.Scene()
    scene.camera.position = (0, 14, 30)
    scene.camera.look_at = (0, 0, 0)
    scene.ambient_light = (0.15, 0.15, 0.15)
    scene.add_light(position=(10, 30, 20), color=(1, 1, 1))
    scene.add_plane((0, -1, 0), (0, 1, 0), material=whitted.Material(checker_color=(0.2, 0.2, 0.2), checker_size=2))
    if terrain_quads:
        scene.add_mesh(*terrain(terrain_quads), material=whitted.Material(diffuse_color=(0.5, 0.6, 0.4)),
                       name="terrain")
    objects, homes = [], []
    for k in range(1000):
        home = rng.uniform([-15, 0, -15], [15, 6, 15])
        colour = tuple(rng.uniform(0.2, 0.9, 3))
        material = whitted.Material(diffuse_color=colour, specular=0.3)
        if k % 5 == 4:
            place = np.eye(4)
            place[:3, :3] *= 0.4
            place[:3, 3] = home
            objects.append(scene.add_mesh(verts, faces, material=material))
            objects[-1].transform = place
        else:
            objects.append(scene.add_sphere(tuple(home), 0.35, material=material))
        homes.append(home)
    build_seconds = time.perf_counter() - start

    renderer = whitted.Renderer()
    options = dict(width=width, height=height, spp=1, aa="uniform")
    t = time.perf_counter()
    first = renderer.render(scene, **options)
    first_seconds = time.perf_counter() - t

    moving, edit, uploads, built = [], [], {}, {}
    for frame in range(frames):
        t = time.perf_counter()
        for k in rng.choice(len(objects), 100, replace=False):
            m = np.eye(4)
            if k % 5 == 4:
                m[:3, :3] *= 0.4
            m[:3, 3] = homes[k] + [0, 0.5 * math.sin(0.3 * frame + k), 0]
            objects[k].transform = m
        t_render = time.perf_counter()
        result = renderer.render(scene, **options)
        done = time.perf_counter()
        edit.append(t_render - t)
        moving.append(done - t)
        key = json.dumps(result.record["uploads"], sort_keys=True)
        uploads[key] = uploads.get(key, 0) + 1
        bvh = result.record["bvh"]
        key = json.dumps({k: bvh.get(k) for k in ("parts", "parts_reused", "primitives_built")}, sort_keys=True)
        built[key] = built.get(key, 0) + 1
    last = result

    camera, camera_uploads = [], {}
    for frame in range(frames):
        t = time.perf_counter()
        a = 0.3 * frame / frames
        scene.camera.position = (30 * math.sin(a), 14, 30 * math.cos(a))
        result = renderer.render(scene, **options)
        camera.append(time.perf_counter() - t)
        key = json.dumps(result.record["uploads"], sort_keys=True)
        camera_uploads[key] = camera_uploads.get(key, 0) + 1

    median = lambda xs: sorted(xs)[len(xs) // 2]
    return last, {
        "objects": 1000,
        "static_terrain_triangles": 2 * terrain_quads * terrain_quads,
        "spheres": 800,
        "meshes": "200 octahedra, 8 triangles each",
        "moved_per_frame": 100,
        "frames": frames,
        "size": [width, height],
        "anti_aliasing": "uniform, spp 1",
        "build_seconds": round(build_seconds, 3),
        "first_render_seconds": round(first_seconds, 3),
        "moving_fps": round(frames / sum(moving), 2),
        "moving_frame_seconds_median": round(median(moving), 4),
        "moving_edit_seconds_median": round(median(edit), 4),
        "moving_uploads": {k: v for k, v in uploads.items()},
        "moving_bvh_built": built,
        "camera_fps": round(frames / sum(camera), 2),
        "camera_frame_seconds_median": round(median(camera), 4),
        "camera_uploads": {k: v for k, v in camera_uploads.items()},
        "ratio_moving_to_camera": round(median(moving) / median(camera), 2),
        "target_ratio": 2,
        "first_image_max": round(float(first.image.max()), 3),
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--frames", type=int, default=100)
    parser.add_argument("--size", default="320x240")
    parser.add_argument("--build", default=str(ROOT / "build"))
    parser.add_argument("--out", default=None, help="JSON file [print only]")
    parser.add_argument("--part", choices=("orbit", "moving", "moving-mesh", "all"), default="all")
    parser.add_argument("--image", default=None,
                        help="FILE.png: the last moving frame of each part as FILE-PART.png, with its AOVs [none]")
    args = parser.parse_args()
    sys.path.insert(0, str(pathlib.Path(args.build) / "python"))
    import whitted

    width, height = map(int, args.size.split("x"))
    report = {"benchmark": "python_orbit", "cpu": cpu_model(), "cores": os.cpu_count()}
    for part, key, quads in (("moving", "moving", 0), ("moving-mesh", "moving_with_mesh", 512)):
        if args.part not in (part, "all"):
            continue
        load_before = os.getloadavg()[0]
        last, report[key] = moving_objects(whitted, args.frames, width, height, quads)
        report[key]["load_average_1min"] = [round(load_before, 2), round(os.getloadavg()[0], 2)]
        report["device"] = whitted.Renderer().device
        if args.image:
            last.save(args.image.replace(".png", f"-{part}.png"))
    if args.part in ("moving", "moving-mesh"):
        text = json.dumps(report, indent=2)
        print(text)
        if args.out:
            pathlib.Path(args.out).write_text(text + "\n")
        return
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
    report.update({
        "scene": "scenes/room.xml",
        "frames": args.frames,
        "size": [width, height],
        "anti_aliasing": "adaptive, spp 16 (the default)",
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
    })
    text = json.dumps(report, indent=2)
    print(text)
    if args.out:
        pathlib.Path(args.out).write_text(text + "\n")


if __name__ == "__main__":
    main()
