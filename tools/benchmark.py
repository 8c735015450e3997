#!/usr/bin/python3
"""whitted benchmark: renders a fixed set of scenes with whitted and with POV-Ray 3.7, in one run.

  tools/benchmark.py [--quick] [--only NAME[,NAME..]] [--skip-povray] [--sizes small,full]
                     [--build DIR] [--out DIR]

For every scene and size it prints and records: BVH build time, render time, rays per second (primary,
shadow and secondary rays as counted by the shader, read from the render.json record that
`whitted render -o X.png` writes beside the image as X.json), peak memory, and POV-Ray's time on the same
scene (exported by build/whitted_povray_export) at the same resolution, samples per pixel, maximum depth
and thread count, with the ratio.

Scenes: room (scenes/room.xml), spheres100 and spheres10k (tools/generate_scenes.py spheres), mesh1m (a
displaced sphere of >= 1M triangles, tools/generate_scenes.py mesh; an OBJ file when whitted can load
<file>, else inline <polygons>). Sizes: small = 640x480 at 1 sample per pixel, full = 1920x1080 at 16.
--quick: tiny scenes and sizes (a CI smoke test): checks the JSON is well-formed and every count is
positive, never a time.

POV-Ray runs as `povray -D +WT2 +A0.0 +AM1 +R4` for 16 samples per pixel (method 1, non-adaptive
supersampling: threshold 0 makes every pixel whose corner samples differ at all take a 4x4 grid of samples,
so up to 16; flat areas take fewer) and without antialiasing for 1 sample per pixel. whitted renders
without auxiliary images (--aov none): POV-Ray computes none either.

Output: OUT/benchmark.json and OUT/benchmark.png (default OUT: build/benchmark). An earlier
OUT/benchmark.json is kept as benchmark.previous.json and drawn beside the new numbers in the plot.
"""
import argparse
import json
import os
import platform
import re
import shutil
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MAX_DEPTH = 6  # whitted's default: secondary bounces (POV-Ray: max_trace_level 7, set by the exporter)
THREADS = 2


def fail(message, status=2):
    print(f"benchmark.py: {message}", file=sys.stderr)
    sys.exit(status)


def run(command, cwd=None):
    """Runs a command; returns (exit status, output, wall seconds, peak RSS bytes of the child)."""
    start = time.monotonic()
    process = subprocess.Popen(command, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    output = process.stdout.read().decode("utf-8", "replace")
    _, status, usage = os.wait4(process.pid, 0)
    wall = time.monotonic() - start
    process.returncode = os.waitstatus_to_exitcode(status)
    return process.returncode, output, wall, usage.ru_maxrss * 1024


def scene_set(quick):
    """name -> (how to make it, arguments). Quick: the same kinds of scenes, tiny."""
    if quick:
        return {"room": ("file", os.path.join(ROOT, "scenes", "room.xml")),
                "spheres100": ("spheres", 8), "spheres10k": ("spheres", 64),
                "mesh1m": ("mesh", 2000)}
    return {"room": ("file", os.path.join(ROOT, "scenes", "room.xml")),
            "spheres100": ("spheres", 100), "spheres10k": ("spheres", 10000),
            "mesh1m": ("mesh", 1000000)}


def size_set(quick):
    if quick:
        return {"small": (64, 48, 1), "full": (96, 54, 4)}
    return {"small": (640, 480, 1), "full": (1920, 1080, 16)}


def make_scene(name, how, arg, work, whitted):
    """Returns (scene path, note); generated scenes go into `work`."""
    generator = [sys.executable, os.path.join(ROOT, "tools", "generate_scenes.py")]
    if how == "file":
        return arg, ""
    path = os.path.join(work, name + ".xml")
    if how == "spheres":
        status, output, _, _ = run(generator + ["spheres", str(arg), path])
        if status != 0:
            fail(f"generate_scenes.py spheres failed:\n{output}", 1)
        return path, ""
    # A mesh: an OBJ file if this build loads <file>, else inline polygons.
    status, output, _, _ = run(generator + ["mesh", str(arg), path])
    if status != 0:
        fail(f"generate_scenes.py mesh failed:\n{output}", 1)
    probe, probe_output, _, _ = run([whitted, "render", path, "-o", os.path.join(work, "probe.png"),
                                     "--width", "8", "--height", "6", "--aov", "none", "-q"])
    if probe == 0:
        return path, "OBJ file"
    print(f"benchmark.py: {name}: this build does not load <file> meshes ({probe_output.strip().splitlines()[-1]}); "
          "using inline <polygons>", file=sys.stderr)
    status, output, _, _ = run(generator + ["mesh", str(arg), path, "--inline"])
    if status != 0:
        fail(f"generate_scenes.py mesh --inline failed:\n{output}", 1)
    return path, "inline <polygons>"


def run_whitted(whitted, scene, out_png, width, height, spp):
    status, output, wall, rss = run([whitted, "render", scene, "-o", out_png, "--width", str(width),
                                     "--height", str(height), "--aa", "uniform", "--spp", str(spp), "--max-depth", str(MAX_DEPTH),
                                     "--aov", "none", "-q"])
    if status != 0:
        fail(f"whitted failed on {scene} (exit {status}):\n{output}", 1)
    with open(os.path.splitext(out_png)[0] + ".json", encoding="utf-8") as f:
        record = json.load(f)
    rays = record["rays"]
    timings = record["timings_s"]
    return {
        "wall_s": wall,
        "load_s": timings["load"],
        "bvh_build_s": timings["bvh_build"],
        "pipeline_s": timings["pipeline"],
        "upload_s": timings["upload"],
        "render_s": timings["render"],
        "rays": {"primary": rays["primary"], "shadow": rays["shadow"], "secondary": rays["secondary"]},
        "rays_per_s": rays["per_second"],
        "bvh": record["bvh"],
        "peak_rss_bytes": rss,
        "device_buffer_bytes": record["memory_bytes"]["device_buffers"],
        "device": record["device"]["name"],
        # Camera samples the driver cut short (lavapipe's loop iteration cap): must be 0.
        "lost_samples": record.get("lost_samples", 0),
    }


POV_TIME = re.compile(r"(Parse|Bounding|Trace)\s+Time:\s+(\d+)\s+hours\s+(\d+)\s+minutes\s+([\d.]+)\s+seconds"
                      r"\s+\(([\d.]+) seconds\)")


def run_povray(exporter, scene, work, name, width, height, spp):
    pov = os.path.join(work, name + ".pov")
    status, output, _, _ = run([exporter, scene, pov, "--width", str(width), "--height", str(height),
                                "--max-depth", str(MAX_DEPTH)])
    if status != 0:
        fail(f"whitted_povray_export failed on {scene} (exit {status}):\n{output}", 1)
    antialias = ["+A0.0", "+AM1", "+R4"] if spp == 16 else (
        ["+A0.0", "+AM1", f"+R{max(2, round(spp ** 0.5))}"] if spp > 1 else ["-A"])
    image = os.path.join(work, name + ".pov.png")
    command = ["povray", "-D", f"+WT{THREADS}", f"+W{width}", f"+H{height}", *antialias, "+FN",
               f"+I{pov}", f"+O{image}"]
    status, output, wall, rss = run(command, cwd=work)
    if status != 0 or not os.path.exists(image):
        fail(f"povray failed on {pov} (exit {status}):\n{output[-3000:]}", 1)
    times = {m.group(1).lower(): float(m.group(5)) for m in POV_TIME.finditer(output)}
    return {"wall_s": wall, "parse_s": times.get("parse"), "bounding_s": times.get("bounding"),
            "render_s": times.get("trace"), "peak_rss_bytes": rss,
            "options": " ".join(a for a in command[1:] if not a.startswith(("+I", "+O")))}


def positive_counts(result):
    """Every count the quick check requires to be > 0, as (label, value)."""
    w = result["whitted"]
    checks = [("rays.primary", w["rays"]["primary"]), ("rays_per_s", w["rays_per_s"]),
              ("render_s", w["render_s"]), ("peak_rss_bytes", w["peak_rss_bytes"]),
              ("device_buffer_bytes", w["device_buffer_bytes"]), ("bvh.nodes", w["bvh"]["nodes"]),
              ("bvh.leaves", w["bvh"]["leaves"])]
    if result["scene"] != "mesh1m":  # a lone mesh has no mirror or glass: no secondary rays
        checks.append(("rays.secondary", w["rays"]["secondary"]))
    checks.append(("rays.shadow", w["rays"]["shadow"]))
    if result.get("povray"):
        checks += [("povray.wall_s", result["povray"]["wall_s"]), ("povray.render_s", result["povray"]["render_s"])]
    return checks


def plot(results, previous, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    labels = [f"{r['scene']}\n{r['width']}x{r['height']} {r['spp']}spp" for r in results]
    ours = [r["whitted"]["wall_s"] for r in results]
    pov = [(r["povray"] or {}).get("wall_s") for r in results]
    before = {}
    for r in (previous or {}).get("results", []):
        before[(r["scene"], r["width"], r["height"], r["spp"])] = r
    old = [before.get((r["scene"], r["width"], r["height"], r["spp"])) for r in results]
    x = list(range(len(results)))
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(max(7, 1.3 * len(results)), 7), sharex=True)
    width = 0.27
    if any(old):
        top.bar([i - width for i in x], [o["whitted"]["wall_s"] if o else 0 for o in old], width,
                color="#b0c4de", label="whitted, previous run")
    top.bar(x, ours, width, color="#1f5fa8", label="whitted")
    top.bar([i + width for i in x], [p or 0 for p in pov], width, color="#d9822b", label="POV-Ray 3.7 (+WT2)")
    for i, (o, p) in enumerate(zip(ours, pov)):
        if p:
            top.text(i, max(o, p) * 1.15, f"{p / o:.1f}x", ha="center", fontsize=8)
    top.set_yscale("log")
    top.set_ylim(top=max(ours + [p or 0 for p in pov]) * 4)  # room for the ratio labels
    top.set_ylabel("seconds, whole process (log)")
    top.set_title("whitted on " + (results[0]["whitted"]["device"] if results else "?") +
                  " vs POV-Ray: label = POV-Ray time / whitted time")
    top.legend(fontsize=8, loc="upper left")
    if any(old):
        bottom.bar([i - width / 2 for i in x], [o["whitted"]["rays_per_s"] / 1e6 if o else 0 for o in old], width,
                   color="#b0c4de", label="previous run")
    bottom.bar([i + width / 2 for i in x], [r["whitted"]["rays_per_s"] / 1e6 for r in results], width,
               color="#1f5fa8", label="this run")
    bottom.set_ylabel("Mrays/s (shader counts)")
    bottom.legend(fontsize=8)
    bottom.set_xticks(x)
    bottom.set_xticklabels(labels, fontsize=8)
    fig.tight_layout()
    temporary = path + ".partial.png"
    fig.savefig(temporary, dpi=80)
    os.replace(temporary, path)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="tiny scenes and sizes; checks the output, not times")
    parser.add_argument("--only", action="append", default=[], help="scene names (room, spheres100, spheres10k, "
                        "mesh1m), comma-separated or repeated")
    parser.add_argument("--sizes", default="small,full", help="small (640x480 1 spp), full (1920x1080 16 spp)")
    parser.add_argument("--skip-povray", action="store_true", help="do not run POV-Ray")
    parser.add_argument("--build", default=os.path.join(ROOT, "build"), help="build folder [build]")
    parser.add_argument("--out", default=None, help="output folder [BUILD/benchmark]")
    try:
        args = parser.parse_args()
    except SystemExit as e:
        sys.exit(2 if e.code else 0)

    scenes = scene_set(args.quick)
    sizes = size_set(args.quick)
    only = [n for item in args.only for n in item.split(",") if n]
    for n in only:
        if n not in scenes:
            fail(f"--only: unknown scene '{n}', expected one of {', '.join(scenes)}")
    chosen_sizes = [s for s in args.sizes.split(",") if s]
    for s in chosen_sizes:
        if s not in sizes:
            fail(f"--sizes: unknown size '{s}', expected small and/or full")
    whitted = os.path.join(args.build, "whitted")
    exporter = os.path.join(args.build, "whitted_povray_export")
    for tool in [whitted] + ([] if args.skip_povray else [exporter]):
        if not os.access(tool, os.X_OK):
            fail(f"{tool} not found: build first (cmake --build {args.build})", 1)
    if not args.skip_povray and not shutil.which("povray"):
        fail("povray not found: run tools/install_deps.sh, or pass --skip-povray", 1)
    out = args.out or os.path.join(args.build, "benchmark")
    os.makedirs(out, exist_ok=True)
    work = os.path.join(out, "work")
    os.makedirs(work, exist_ok=True)

    results = []
    for name, (how, arg) in scenes.items():
        if only and name not in only:
            continue
        scene, note = make_scene(name, how, arg, work, whitted)
        for size in chosen_sizes:
            width, height, spp = sizes[size]
            tag = f"{name}_{size}"
            print(f"== {name} {width}x{height} {spp} spp", file=sys.stderr, flush=True)
            ours = run_whitted(whitted, scene, os.path.join(work, tag + ".png"), width, height, spp)
            pov = None if args.skip_povray else run_povray(exporter, scene, work, tag, width, height, spp)
            result = {"scene": name, "size": size, "width": width, "height": height, "spp": spp,
                      "max_depth": MAX_DEPTH, "mesh_source": note, "whitted": ours, "povray": pov}
            if pov and pov["render_s"]:
                result["povray_over_whitted"] = {"wall": pov["wall_s"] / ours["wall_s"],
                                                 "render": pov["render_s"] / ours["render_s"]}
            results.append(result)
            rays = ours["rays"]
            line = (f"{name:11s} {width}x{height} {spp:2d}spp  bvh {ours['bvh_build_s']:.3f} s  "
                    f"render {ours['render_s']:.2f} s  wall {ours['wall_s']:.2f} s  "
                    f"{ours['rays_per_s'] / 1e6:.2f} Mrays/s (p {rays['primary']} s {rays['shadow']} "
                    f"r {rays['secondary']})  rss {ours['peak_rss_bytes'] / 2**20:.0f} MiB")
            if pov:
                line += (f"\n{'':11s} POV-Ray: render {pov['render_s']} s  wall {pov['wall_s']:.2f} s  "
                         f"rss {pov['peak_rss_bytes'] / 2**20:.0f} MiB")
                if "povray_over_whitted" in result:
                    ratio = result["povray_over_whitted"]
                    line += f"  POV-Ray/whitted: wall {ratio['wall']:.2f}x, render {ratio['render']:.2f}x"
            if ours["lost_samples"]:
                line += f"\n{'':11s} WARNING: {ours['lost_samples']} camera samples lost: the image is incomplete"
            print(line, flush=True)

    ratios = {}
    by_key = {(r["scene"], r["size"]): r for r in results}
    for size in chosen_sizes:
        a, b = by_key.get(("spheres10k", size)), by_key.get(("spheres100", size))
        if a and b:
            ratios[f"spheres10k_over_spheres100_{size}"] = a["whitted"]["render_s"] / b["whitted"]["render_s"]
            print(f"spheres10k / spheres100 render time ({size}): "
                  f"{ratios[f'spheres10k_over_spheres100_{size}']:.2f}", flush=True)

    json_path = os.path.join(out, "benchmark.json")
    previous = None
    if os.path.exists(json_path):
        try:
            with open(json_path, encoding="utf-8") as f:
                previous = json.load(f)
            shutil.copyfile(json_path, os.path.join(out, "benchmark.previous.json"))
        except (OSError, ValueError):
            previous = None
    document = {"created": time.strftime("%Y-%m-%dT%H:%M:%S%z"), "host": platform.node(),
                "cpus": os.cpu_count(), "quick": args.quick, "threads": THREADS, "results": results,
                "ratios": ratios}
    temporary = json_path + ".partial"
    with open(temporary, "w", encoding="utf-8") as f:
        json.dump(document, f, indent=2)
    os.replace(temporary, json_path)
    plot(results, previous, os.path.join(out, "benchmark.png"))
    print(f"wrote {json_path} and {os.path.join(out, 'benchmark.png')}", flush=True)

    if args.quick:
        # The smoke test: the file parses back and every count is positive.
        with open(json_path, encoding="utf-8") as f:
            reread = json.load(f)
        bad = [f"{r['scene']} {r['size']}: {label} = {value}" for r in reread["results"]
               for label, value in positive_counts(r) if not (isinstance(value, (int, float)) and value > 0)]
        bad += [f"{r['scene']} {r['size']}: {r['whitted']['lost_samples']} camera samples lost"
                for r in reread["results"] if r["whitted"]["lost_samples"] != 0]
        if not reread["results"]:
            bad.append("no results")
        if bad:
            fail("quick check failed:\n  " + "\n  ".join(bad), 1)
        print(f"quick check: {len(reread['results'])} results, every count > 0", flush=True)


if __name__ == "__main__":
    main()
