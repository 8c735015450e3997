#!/usr/bin/python3
"""whitted benchmark: renders a fixed set of scenes with whitted and with POV-Ray 3.7, in one run.

  tools/benchmark.py [--quick] [--only NAME[,NAME..]] [--skip-povray] [--sizes small,full]
                     [--full-scenes NAME[,NAME..]|all] [--skip-fixed] [--skip-equal-quality]
                     [--driver-files ICD.json|default [--label NAME]]... [--fresh-references]
                     [--build DIR] [--out DIR]

Two parts, both against POV-Ray measured in the same run (whitted and POV-Ray runs interleaved scene by scene,
so load from other jobs hits both):

Fixed samples per pixel. For every scene and size: BVH build time, render time, rays per second (primary, shadow
and secondary rays as counted by the shader, read from the record `whitted render -o X.png` writes beside the image
as X.json), peak memory, and POV-Ray's time on the same scene (exported by build/whitted_povray_export) at the same
resolution, samples per pixel, maximum depth and thread count, with the ratio. Sizes: small = 640x480 at 1 sample
per pixel, full = 1920x1080 at 16 (by default for the room only: --full-scenes). whitted runs `--aa uniform --spp N`;
POV-Ray `povray -D +WT2 +A0.0 +AM1 +R4` for 16 samples per pixel (method 1, non-adaptive supersampling, threshold 0:
every pixel whose corner samples differ at all takes a 4x4 grid) and `-A` for 1.

Equal quality ("time to a clean image"). For every scene at its equal-quality size (room 1920x1080, the others
640x480), each renderer's own 64-sample uniform image is its reference: whitted `--aa uniform --spp 64`, POV-Ray
`+A0.0 +AM1 +R8` (an 8x8 grid in every pixel whose corners differ at all). Then each renderer tries settings in
order until its image is within 50 dB PSNR of its reference (8-bit sRGB PNG, RGB, 10 log10(1/MSE) on [0, 1]):
whitted its default render (no sampling flags), then `--spp 64`; POV-Ray adaptive `+AM2 +R3` at thresholds
+A0.3, 0.1, 0.03, 0.01. Time to a clean image = whole-process wall time of the first try that reaches 50 dB;
every try's time and PSNR is recorded. References are not timed; they are cached in OUT/work/references/ (keyed by
the binary's or POV-Ray's version, the scene's bytes and the options; --fresh-references renders them again), and
whitted's reference is rendered by the first driver and shared by the others (the record says which; the JSON also
holds each driver's PSNR against the first driver's default render).

Window proxy: `whitted render room.xml --width 640 --height 360 --aa uniform --spp 1 --aov none`, 5 times per
driver, render time from the record (the live window's frame during a camera drag traces this much).

Drivers: --driver-files ICD.json (repeatable; `default` = the Vulkan loader's choice) runs whitted with
VK_DRIVER_FILES=ICD.json and LD_LIBRARY_PATH prefixed by the folder of the JSON's absolute ICD.library_path; --label
names it (default: from the driver whitted reports, e.g. mesa-25.0.7). Every driver's whitted runs are interleaved
with the same POV-Ray runs.

Scenes (--only): room (scenes/room.xml), spheres100 and spheres10k (tools/generate_scenes.py spheres), mesh1m (a
displaced sphere of >= 1M triangles, tools/generate_scenes.py mesh; an OBJ file when whitted can load <file>, else
inline <polygons>). --quick: tiny scenes and sizes (a CI smoke test): checks the JSON is well-formed and every count
is positive, never a time.

Output: OUT/benchmark-LABEL.json per driver (an earlier one is kept as benchmark-LABEL.previous.json) and
OUT/benchmark.png (default OUT: build/benchmark). The CPU model and the driver are in the JSON and the printout.
"""
import argparse
import hashlib
import json
import math
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MAX_DEPTH = 6  # whitted's default: secondary bounces (POV-Ray: max_trace_level 7, set by the exporter)
THREADS = 2
PSNR_TARGET_DB = 50.0
REFERENCE_SPP = 64
WHITTED_REFERENCE = ["--aa", "uniform", "--spp", str(REFERENCE_SPP)]
WHITTED_TRIES = [[], ["--spp", "64"]]  # default render first
POVRAY_REFERENCE = ["+A0.0", "+AM1", "+R8"]  # 8x8 = 64 samples
POVRAY_THRESHOLDS = [0.3, 0.1, 0.03, 0.01]
POVRAY_ADAPTIVE = ["+AM2", "+R3"]
DRAG_SIZE = (640, 360)
DRAG_REPEATS = 5


def fail(message, status=2):
    print(f"benchmark.py: {message}", file=sys.stderr)
    sys.exit(status)


def run(command, cwd=None, env=None):
    """Runs a command; returns (exit status, output, wall seconds, peak RSS bytes of the child)."""
    start = time.monotonic()
    process = subprocess.Popen(command, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    output = process.stdout.read().decode("utf-8", "replace")
    _, status, usage = os.wait4(process.pid, 0)
    wall = time.monotonic() - start
    process.returncode = os.waitstatus_to_exitcode(status)
    return process.returncode, output, wall, usage.ru_maxrss * 1024


def sha256_file(path, extra=""):
    digest = hashlib.sha256(extra.encode())
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def cpu_model():
    """(/proc/cpuinfo's first model name, the SIMD extensions llvmpipe can use)."""
    model, flags = None, None
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                key, _, value = line.partition(":")
                if key.strip() == "model name" and model is None:
                    model = value.strip()
                elif key.strip() == "flags" and flags is None:
                    flags = [f for f in ("avx", "avx2", "fma", "avx512f") if f in value.split()]
    except OSError:
        pass
    return model or platform.processor() or "?", flags or []


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


def equal_quality_sizes(quick):
    if quick:
        return {"room": (96, 54), "spheres100": (64, 48), "spheres10k": (64, 48), "mesh1m": (64, 48)}
    return {"room": (1920, 1080), "spheres100": (640, 480), "spheres10k": (640, 480), "mesh1m": (640, 480)}


class Driver:
    """A Vulkan driver whitted runs on: the loader's default, or an ICD JSON file (VK_DRIVER_FILES)."""

    def __init__(self, files, label):
        self.files, self.label, self.env = files, label, dict(os.environ)
        self.driver = self.device = None
        if files:
            try:
                with open(files, encoding="utf-8") as f:
                    library = json.load(f)["ICD"]["library_path"]
            except (OSError, ValueError, KeyError, TypeError) as e:
                fail(f"--driver-files {files}: not a Vulkan ICD JSON file with ICD.library_path ({e})")
            self.env["VK_DRIVER_FILES"] = os.path.abspath(files)
            self.env["VK_ICD_FILENAMES"] = os.path.abspath(files)  # loaders older than 1.3.207
            if os.path.isabs(library):
                if not os.path.exists(library):
                    fail(f"--driver-files {files}: its library_path {library} does not exist")
                old = self.env.get("LD_LIBRARY_PATH")
                self.env["LD_LIBRARY_PATH"] = os.path.dirname(library) + (":" + old if old else "")

    def probe(self, whitted, work):
        """Renders a tiny image to learn the driver string; labels the driver from it unless --label did."""
        image = os.path.join(work, "probe_driver.png")
        status, output, _, _ = run([whitted, "render", os.path.join(ROOT, "scenes", "room.xml"), "-o", image,
                                    "--width", "8", "--height", "6", "--aov", "none", "-q"], env=self.env)
        if status != 0:
            fail(f"whitted does not render with driver {self.files or 'default'} (exit {status}):\n{output}", 1)
        record = read_record(image)
        self.driver = record["device"].get("driver", "?")
        self.device = record["device"]["name"]
        if not self.label:
            match = re.search(r"Mesa (\d+\.\d+(?:\.\d+)?)", self.driver)
            self.label = ("mesa-" + match.group(1)) if match else re.sub(r"[^A-Za-z0-9.]+", "-", self.driver)[:40]


def read_record(png):
    with open(os.path.splitext(png)[0] + ".json", encoding="utf-8") as f:
        return json.load(f)


def make_scene(name, how, arg, work, whitted, env):
    """Returns (scene path, note); generated scenes go into `work` (kept while the generator and arguments are the same)."""
    generator = [sys.executable, os.path.join(ROOT, "tools", "generate_scenes.py")]
    if how == "file":
        return arg, ""
    path = os.path.join(work, name + ".xml")
    stamp_path = path + ".stamp"
    stamp = sha256_file(generator[1], f"{how} {arg}")
    try:
        with open(stamp_path, encoding="utf-8") as f:
            old_stamp, old_note = f.read().split("\n", 1)
        if old_stamp == stamp and os.path.exists(path):
            return path, old_note
    except (OSError, ValueError):
        pass
    if how == "spheres":
        status, output, _, _ = run(generator + ["spheres", str(arg), path])
        if status != 0:
            fail(f"generate_scenes.py spheres failed:\n{output}", 1)
        note = ""
    else:
        # A mesh: an OBJ file if this build loads <file>, else inline polygons.
        status, output, _, _ = run(generator + ["mesh", str(arg), path])
        if status != 0:
            fail(f"generate_scenes.py mesh failed:\n{output}", 1)
        probe, probe_output, _, _ = run([whitted, "render", path, "-o", os.path.join(work, "probe.png"),
                                         "--width", "8", "--height", "6", "--aov", "none", "-q"], env=env)
        note = "OBJ file"
        if probe != 0:
            print(f"benchmark.py: {name}: this build does not load <file> meshes "
                  f"({probe_output.strip().splitlines()[-1]}); using inline <polygons>", file=sys.stderr)
            status, output, _, _ = run(generator + ["mesh", str(arg), path, "--inline"])
            if status != 0:
                fail(f"generate_scenes.py mesh --inline failed:\n{output}", 1)
            note = "inline <polygons>"
    with open(stamp_path, "w", encoding="utf-8") as f:
        f.write(f"{stamp}\n{note}")
    return path, note


def run_whitted(whitted, driver, scene, out_png, width, height, sampling):
    """One whole whitted process; `sampling` are the sampling flags (none: the default adaptive render)."""
    command = [whitted, "render", scene, "-o", out_png, "--width", str(width), "--height", str(height),
               *sampling, "--max-depth", str(MAX_DEPTH), "--aov", "none", "-q"]
    status, output, wall, rss = run(command, env=driver.env)
    if status != 0:
        fail(f"whitted failed on {scene} with driver {driver.label} (exit {status}):\n{output}", 1)
    record = read_record(out_png)
    rays = record["rays"]
    timings = record["timings_s"]
    sampling_record = record.get("sampling", {})
    return {
        "options": " ".join(command[5:]),
        "sampling": " ".join(sampling) or "default",
        "wall_s": wall,
        "load_s": timings["load"],
        "bvh_build_s": timings["bvh_build"],
        "pipeline_s": timings["pipeline"],
        "upload_s": timings["upload"],
        "render_s": timings["render"],
        "rays": {"primary": rays["primary"], "shadow": rays["shadow"], "secondary": rays["secondary"]},
        "rays_per_s": rays["per_second"],
        "camera_samples": sampling_record.get("camera_samples"),
        "mean_spp": sampling_record.get("mean_spp"),
        "bvh": record["bvh"],
        "peak_rss_bytes": rss,
        "device_buffer_bytes": record["memory_bytes"]["device_buffers"],
        "device": record["device"]["name"],
        "driver": record["device"].get("driver"),
        # Camera samples the driver cut short (lavapipe's loop iteration cap): must be 0.
        "lost_samples": record.get("lost_samples", 0),
    }


POV_TIME = re.compile(r"(Parse|Bounding|Trace)\s+Time:\s+(\d+)\s+hours\s+(\d+)\s+minutes\s+([\d.]+)\s+seconds"
                      r"\s+\(([\d.]+) seconds\)")
POV_SAMPLES = re.compile(r"Pixels:\s+(\d+)\s+Samples:\s+(\d+)\s+Smpls/Pxl:\s+([\d.]+)")


def export_pov(exporter, scene, work, tag, width, height):
    pov = os.path.join(work, tag + ".pov")
    status, output, _, _ = run([exporter, scene, pov, "--width", str(width), "--height", str(height),
                                "--max-depth", str(MAX_DEPTH)])
    if status != 0:
        fail(f"whitted_povray_export failed on {scene} (exit {status}):\n{output}", 1)
    return pov


def run_povray(pov, image, width, height, antialias):
    """One whole POV-Ray process on an exported scene."""
    command = ["povray", "-D", f"+WT{THREADS}", f"+W{width}", f"+H{height}", *antialias, "+FN",
               f"+I{pov}", f"+O{image}"]
    if os.path.exists(image):
        os.remove(image)
    status, output, wall, rss = run(command, cwd=os.path.dirname(pov))
    if status != 0 or not os.path.exists(image):
        fail(f"povray failed on {pov} (exit {status}):\n{output[-3000:]}", 1)
    times = {m.group(1).lower(): float(m.group(5)) for m in POV_TIME.finditer(output)}
    samples = POV_SAMPLES.search(output)
    return {"wall_s": wall, "parse_s": times.get("parse"), "bounding_s": times.get("bounding"),
            "render_s": times.get("trace"), "peak_rss_bytes": rss,
            # POV-Ray's own counters (its "Pixels" include a border row and column it traces for antialiasing)
            "pixels": int(samples.group(1)) if samples else None,
            "samples": int(samples.group(2)) if samples else None,
            "options": " ".join(a for a in command[1:] if not a.startswith(("+I", "+O")))}


def povray_fixed_antialias(spp):
    return ["+A0.0", "+AM1", "+R4"] if spp == 16 else (
        ["+A0.0", "+AM1", f"+R{max(2, round(spp ** 0.5))}"] if spp > 1 else ["-A"])


def read_rgb8(path):
    import numpy as np
    import OpenImageIO as oiio
    buf = oiio.ImageBuf(path)
    pixels = buf.get_pixels(oiio.UINT8)
    if pixels is None or buf.has_error:
        fail(f"cannot read {path}: {buf.geterror()}", 1)
    return np.asarray(pixels)[..., :3].astype(np.float64) / 255.0


def psnr(path, reference):
    """PSNR in dB of two 8-bit images over RGB on [0, 1]; None when identical (infinite)."""
    import numpy as np
    a, b = read_rgb8(path), read_rgb8(reference)
    if a.shape != b.shape:
        fail(f"{path} is {a.shape}, its reference {reference} {b.shape}", 1)
    mse = float(np.mean((a - b) ** 2))
    return None if mse == 0 else 10 * math.log10(1 / mse)


def clean(db):
    return db is None or db >= PSNR_TARGET_DB


def cached_reference(cache, key, make):
    """Returns (image path, record) of a reference: from the cache, or made by make(path) -> record."""
    os.makedirs(cache, exist_ok=True)
    path = os.path.join(cache, key + ".png")
    meta = os.path.join(cache, key + ".meta.json")
    if os.path.exists(path) and os.path.exists(meta):
        with open(meta, encoding="utf-8") as f:
            record = json.load(f)
        record["cached"] = True
        return path, record
    partial = os.path.join(cache, key + ".partial.png")
    record = make(partial)
    os.replace(partial, path)
    partial_json = os.path.splitext(partial)[0] + ".json"
    if os.path.exists(partial_json):
        os.replace(partial_json, os.path.join(cache, key + ".json"))
    with open(meta, "w", encoding="utf-8") as f:
        json.dump(record, f, indent=2)
    record["cached"] = False
    return path, record


def equal_quality(name, scene, width, height, drivers, whitted, exporter, work, skip_povray, fresh):
    """Time to a clean image for every driver and for POV-Ray at one scene and size. Returns label -> result."""
    tag = f"{name}_eq_{width}x{height}"
    cache = os.path.join(work, "references")
    whitted_hash = sha256_file(whitted, os.environ.get("WHITTED_SHADER_SPV", ""))
    scene_hash = sha256_file(scene)
    key = hashlib.sha256(f"{whitted_hash} {scene_hash} {width}x{height} {WHITTED_REFERENCE} {MAX_DEPTH}".encode())
    key = "whitted_" + key.hexdigest()[:24]
    if fresh:
        for suffix in (".png", ".meta.json", ".json"):
            if os.path.exists(os.path.join(cache, key + suffix)):
                os.remove(os.path.join(cache, key + suffix))
    first = drivers[0]
    print(f"== {name} {width}x{height} equal quality: references", file=sys.stderr, flush=True)
    whitted_reference, reference_record = cached_reference(cache, key, lambda path: dict(
        run_whitted(whitted, first, scene, path, width, height, WHITTED_REFERENCE), reference_driver=first.label))
    pov = pov_reference = pov_reference_record = None
    if not skip_povray:
        pov = export_pov(exporter, scene, work, tag, width, height)
        version = run(["povray", "--version"])[1].strip().splitlines()
        version = next((line for line in version if line.startswith("POV-Ray")), "?")
        pov_key = hashlib.sha256(f"{version} {sha256_file(pov)} {width}x{height} {POVRAY_REFERENCE}".encode())
        pov_key = "povray_" + pov_key.hexdigest()[:24]
        if fresh and os.path.exists(os.path.join(cache, pov_key + ".png")):
            os.remove(os.path.join(cache, pov_key + ".png"))
        pov_reference, pov_reference_record = cached_reference(
            cache, pov_key, lambda path: dict(run_povray(pov, path, width, height, POVRAY_REFERENCE), version=version))

    ours = {d.label: {"reference": reference_record, "tries": [], "reached": None, "time_to_clean_s": None}
            for d in drivers}
    theirs = {"reference": pov_reference_record, "tries": [], "reached_threshold": None, "time_to_clean_s": None}
    defaults = {}
    # Rounds: each driver's next whitted try, then POV-Ray's next threshold, until all are clean or out of tries.
    for step in range(max(len(WHITTED_TRIES), len(POVRAY_THRESHOLDS))):
        for d in drivers:
            mine = ours[d.label]
            if mine["reached"] is not None or step >= len(WHITTED_TRIES):
                continue
            image = os.path.join(work, f"{tag}_{d.label}_try{step}.png")
            print(f"== {name} {width}x{height} whitted {d.label} {' '.join(WHITTED_TRIES[step]) or 'default'}",
                  file=sys.stderr, flush=True)
            result = run_whitted(whitted, d, scene, image, width, height, WHITTED_TRIES[step])
            result["psnr_db"] = psnr(image, whitted_reference)
            mine["tries"].append(result)
            if step == 0:
                defaults[d.label] = image
            if clean(result["psnr_db"]):
                mine["reached"] = step
                mine["time_to_clean_s"] = result["wall_s"]
        if pov and step < len(POVRAY_THRESHOLDS) and theirs["reached_threshold"] is None:
            threshold = POVRAY_THRESHOLDS[step]
            image = os.path.join(work, f"{tag}_povray_A{threshold}.png")
            print(f"== {name} {width}x{height} POV-Ray +A{threshold}", file=sys.stderr, flush=True)
            result = run_povray(pov, image, width, height, [f"+A{threshold}", *POVRAY_ADAPTIVE])
            result["threshold"] = threshold
            result["psnr_db"] = psnr(image, pov_reference)
            theirs["tries"].append(result)
            if clean(result["psnr_db"]):
                theirs["reached_threshold"] = threshold
                theirs["time_to_clean_s"] = result["wall_s"]

    out = {}
    for d in drivers:
        mine = ours[d.label]
        entry = {"scene": name, "width": width, "height": height, "psnr_target_db": PSNR_TARGET_DB,
                 "whitted": mine, "povray": theirs if pov else None}
        if d is not first and first.label in defaults and d.label in defaults:
            # The reference is the first driver's; how far this driver's own default render is from that driver's.
            entry["whitted"]["default_psnr_against_" + first.label + "_db"] = psnr(defaults[d.label],
                                                                                 defaults[first.label])
        if pov and theirs["time_to_clean_s"] and mine["time_to_clean_s"]:
            entry["povray_over_whitted"] = {"time_to_clean": theirs["time_to_clean_s"] / mine["time_to_clean_s"]}
        if pov and theirs["tries"] and mine["tries"]:
            entry.setdefault("povray_over_whitted", {})["first_tries"] = (theirs["tries"][0]["wall_s"] /
                                                                         mine["tries"][0]["wall_s"])
        out[d.label] = entry
    return out


def drag_proxy(whitted, drivers, work, repeats):
    """Render time of 640x360 at 1 spp (the window's frame in a camera drag), interleaved between drivers."""
    width, height = DRAG_SIZE
    times = {d.label: [] for d in drivers}
    walls = {d.label: [] for d in drivers}
    for _ in range(repeats):
        for d in drivers:
            image = os.path.join(work, f"drag_{d.label}.png")
            result = run_whitted(whitted, d, os.path.join(ROOT, "scenes", "room.xml"), image, width, height,
                                 ["--aa", "uniform", "--spp", "1"])
            times[d.label].append(result["render_s"])
            walls[d.label].append(result["wall_s"])
    return {d.label: {"scene": "room", "width": width, "height": height, "spp": 1, "render_s": times[d.label],
                      "render_median_s": statistics.median(times[d.label]), "render_min_s": min(times[d.label]),
                      "wall_median_s": statistics.median(walls[d.label])} for d in drivers}


def targets(document):
    """Issue 8's targets with measured verdicts, from one driver's document."""
    out = []
    fixed = {(r["scene"], r["size"]): r for r in document["results"]}
    eq = {r["scene"]: r for r in document["equal_quality"]}

    def add(target, value, limit, better, measured):
        met = value is not None and (value <= limit if better == "lower" else value >= limit)
        by = None
        if value is not None and not met:
            by = value / limit if better == "lower" else limit / value
        out.append({"target": target, "value": value, "limit": limit, "better": better, "met": met,
                    "missed_by_factor": by, "measured": measured})

    room = eq.get("room")
    if room and room["povray"] and room["povray"]["tries"] and room["whitted"]["time_to_clean_s"]:
        w, p = room["whitted"]["time_to_clean_s"], room["povray"]["time_to_clean_s"]
        pov = f"POV-Ray +A{room['povray']['reached_threshold']} +AM2 +R3 {p and round(p, 2)} s"
        if p is None:  # POV-Ray reached no 50 dB: its last try's time is a lower bound of its time to a clean image
            last = room["povray"]["tries"][-1]
            p = last["wall_s"]
            pov = f"POV-Ray reached no {PSNR_TARGET_DB:.0f} dB; its last try, +A{last['threshold']} ({fmt_db(last['psnr_db'])}), took {p:.2f} s (a lower bound)"
        add(f"{room['width']}x{room['height']} room: time to a clean image <= 1/3 of POV-Ray's adaptive whole-process "
            "time", w / p, 1 / 3, "lower",
            f"whitted {room['whitted']['tries'][room['whitted']['reached']]['sampling']} {w:.2f} s, {pov}")
    full = fixed.get(("room", "full"))
    if full and full["povray"] and full["povray"]["render_s"]:
        w, p = full["whitted"]["render_s"], full["povray"]["render_s"]
        add(f"{full['width']}x{full['height']} room at {full['spp']} spp uniform <= 1/3 of POV-Ray "
            f"{' '.join(povray_fixed_antialias(full['spp']))}", w / p, 1 / 3, "lower",
            f"render {w:.2f} s against trace {p:.2f} s; whole process {full['whitted']['wall_s']:.2f} s against "
            f"{full['povray']['wall_s']:.2f} s")
    for size in ("small", "full"):
        a, b = fixed.get(("spheres10k", size)), fixed.get(("spheres100", size))
        if a and b:
            add(f"10,000 spheres <= 1.5x the time of 100 ({a['width']}x{a['height']} {a['spp']} spp, render time)",
                a["whitted"]["render_s"] / b["whitted"]["render_s"], 1.5, "lower",
                f"{a['whitted']['render_s']:.3f} s against {b['whitted']['render_s']:.3f} s")
    a, b = eq.get("spheres10k"), eq.get("spheres100")
    if a and b and a["whitted"]["time_to_clean_s"] and b["whitted"]["time_to_clean_s"]:
        ra, rb = a["whitted"]["tries"][a["whitted"]["reached"]], b["whitted"]["tries"][b["whitted"]["reached"]]
        add(f"10,000 spheres <= 1.5x the time of 100 ({a['width']}x{a['height']} clean image, render time)",
            ra["render_s"] / rb["render_s"], 1.5, "lower", f"{ra['render_s']:.3f} s against {rb['render_s']:.3f} s")
    for size in ("small", "full"):
        mesh = fixed.get(("mesh1m", size))
        if mesh and mesh["povray"] and mesh["povray"]["render_s"]:
            w, p = mesh["whitted"]["render_s"], mesh["povray"]["render_s"]
            add(f"1M-triangle mesh >= 2x POV-Ray's trace speed ({mesh['width']}x{mesh['height']} {mesh['spp']} spp: "
                "POV-Ray trace time / whitted render time)", p / w, 2.0, "higher",
                f"render {w:.3f} s against trace {p:.3f} s")
    drag = document.get("drag_proxy")
    if drag:
        add(f"window during a camera drag: {drag['width']}x{drag['height']} at 1 spp in <= 50 ms (proxy: median "
            "render time of `whitted render --aa uniform --spp 1 --aov none`)", drag["render_median_s"], 0.050,
            "lower", f"median {drag['render_median_s'] * 1000:.0f} ms, fastest {drag['render_min_s'] * 1000:.0f} ms "
            f"of {len(drag['render_s'])}")
    return out


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


def equal_quality_counts(entry):
    """What the quick check requires of an equal-quality entry, as (label, value)."""
    w = entry["whitted"]
    checks = [("whitted.tries", len(w["tries"])), ("whitted.reference.camera_samples",
                                                  w["reference"].get("camera_samples"))]
    for i, t in enumerate(w["tries"]):
        checks += [(f"whitted.tries[{i}].wall_s", t["wall_s"]), (f"whitted.tries[{i}].camera_samples",
                                                                 t["camera_samples"]),
                   (f"whitted.tries[{i}].rays.primary", t["rays"]["primary"]),
                   (f"whitted.tries[{i}].psnr_db", 1 if t["psnr_db"] is None else t["psnr_db"])]
    p = entry.get("povray")
    if p:
        checks += [("povray.tries", len(p["tries"])), ("povray.reference.samples", p["reference"].get("samples"))]
        for i, t in enumerate(p["tries"]):
            checks += [(f"povray.tries[{i}].wall_s", t["wall_s"]),
                       (f"povray.tries[{i}].psnr_db", 1 if t["psnr_db"] is None else t["psnr_db"])]
    return checks


def fmt_db(db):
    return "identical" if db is None else f"{db:.1f} dB"


def plot(documents, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FuncFormatter, LogLocator

    labels = list(documents)
    colours = ["#1f5fa8", "#6aa84f", "#8e44ad", "#17becf"]
    pov_colour = "#d9822b"
    first = documents[labels[0]]
    fixed = [(r["scene"], r["size"], r["width"], r["height"], r["spp"]) for r in first["results"]]
    eq = [(r["scene"], r["width"], r["height"]) for r in first["equal_quality"]]
    n = len(labels) + 1
    width = 0.8 / n
    panels = [p for p, rows in (("fixed", fixed), ("eq", eq), ("rays", fixed)) if rows]
    fig, axes = plt.subplots(len(panels), 1, figsize=(max(8, 1.6 * max(len(fixed), len(eq), 1)), 3.6 * len(panels)))
    axes = list(axes) if len(panels) > 1 else [axes]

    def offset(i):
        return (i - n / 2 + 0.5) * width

    def log_axis(ax, values):
        ax.set_yscale("log")
        ax.yaxis.set_major_locator(LogLocator(subs=(1, 2, 5)))
        ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        ax.yaxis.set_minor_formatter(plt.NullFormatter())
        positive = [v for v in values if v]
        if positive:
            ax.set_ylim(min(positive) / 2, max(positive) * 6)  # room for the labels above the bars

    for ax, panel in zip(axes, panels):
        if panel == "fixed":
            rows = {label: {(r["scene"], r["size"]): r for r in documents[label]["results"]} for label in labels}
            x = list(range(len(fixed)))
            values = []
            for k, (s, z, *_) in enumerate(fixed):
                pov = (rows[labels[0]][(s, z)]["povray"] or {}).get("wall_s")
                mine = [rows[label][(s, z)]["whitted"]["wall_s"] for label in labels]
                values += mine + [pov]
                for i, v in enumerate(mine):
                    ax.bar(k + offset(i), v, width, color=colours[i % len(colours)],
                           label=f"whitted, {labels[i]}" if k == 0 else None)
                    if pov:
                        ax.text(k + offset(i), v * 1.1, f"{pov / v:.2g}x", ha="center", fontsize=7)
                if pov:
                    ax.bar(k + offset(n - 1), pov, width, color=pov_colour, label="POV-Ray 3.7 (+WT2)" if k == 0 else None)
            ax.set_xticks(x)
            ax.set_xticklabels([f"{s}\n{w}x{h} {spp} spp" for s, _, w, h, spp in fixed], fontsize=8)
            ax.set_title(f"fixed samples per pixel (whitted --aa uniform; POV-Ray -A or +A0.0 +AM1), whole process\n"
                         "label = POV-Ray time / whitted time", fontsize=9)
            ax.set_ylabel("seconds")
            log_axis(ax, values)
        elif panel == "eq":
            rows = {label: {r["scene"]: r for r in documents[label]["equal_quality"]} for label in labels}
            x = list(range(len(eq)))
            values = []
            for k, (s, *_) in enumerate(eq):
                pov = rows[labels[0]][s]["povray"]
                pov_time = pov_note = None
                if pov and pov["tries"]:
                    if pov["time_to_clean_s"]:
                        pov_time, pov_note = pov["time_to_clean_s"], f"+A{pov['reached_threshold']}"
                    else:
                        pov_time, pov_note = pov["tries"][-1]["wall_s"], f"+A{pov['tries'][-1]['threshold']}: <50 dB"
                for i, label in enumerate(labels):
                    mine = rows[label][s]["whitted"]
                    if mine["time_to_clean_s"]:
                        v, note = mine["time_to_clean_s"], mine["tries"][mine["reached"]]["sampling"]
                    else:
                        v, note = mine["tries"][-1]["wall_s"], "<50 dB"
                    values.append(v)
                    ax.bar(k + offset(i), v, width, color=colours[i % len(colours)],
                           hatch=None if mine["time_to_clean_s"] else "//",
                           label=f"whitted, {label}" if k == 0 else None)
                    text = note if note != "default" else ""
                    if pov_time:
                        text = f"{pov_time / v:.2g}x" + (f"\n{text}" if text else "")
                    ax.text(k + offset(i), v * 1.1, text, ha="center", fontsize=7)
                if pov_time:
                    values.append(pov_time)
                    ax.bar(k + offset(n - 1), pov_time, width, color=pov_colour,
                           hatch=None if pov["time_to_clean_s"] else "//",
                           label="POV-Ray +AM2 +R3, first threshold reaching 50 dB" if k == 0 else None)
                    ax.text(k + offset(n - 1), pov_time * 1.1, pov_note, ha="center", fontsize=7)
            ax.set_xticks(x)
            ax.set_xticklabels([f"{s}\n{w}x{h}" for s, w, h in eq], fontsize=8)
            ax.set_title(f"time to a clean image (>= {PSNR_TARGET_DB:.0f} dB against the renderer's own 64-sample "
                         "uniform image), whole process\nlabel = POV-Ray / whitted time; hatched: 50 dB not reached "
                         "(last try shown)", fontsize=9)
            ax.set_ylabel("seconds")
            log_axis(ax, values)
        else:
            rows = {label: {(r["scene"], r["size"]): r for r in documents[label]["results"]} for label in labels}
            x = list(range(len(fixed)))
            for i, label in enumerate(labels):
                ax.bar([k + (i - len(labels) / 2 + 0.5) * width for k in x],
                       [rows[label][(s, z)]["whitted"]["rays_per_s"] / 1e6 for s, z, *_ in fixed], width,
                       color=colours[i % len(colours)], label=f"{label}: {documents[label]['driver']}")
            ax.set_xticks(x)
            ax.set_xticklabels([f"{s}\n{w}x{h} {spp} spp" for s, _, w, h, spp in fixed], fontsize=8)
            ax.set_title(f"whitted rays per second (shader counts: primary + shadow + secondary) on "
                         f"{first['cpu_model']}, {first['cpus']} CPUs", fontsize=9)
            ax.set_ylabel("Mrays/s")
        ax.legend(fontsize=7, loc="upper left" if panel != "rays" else "best")
    fig.tight_layout()
    temporary = path + ".partial.png"
    fig.savefig(temporary, dpi=80)
    os.replace(temporary, path)


def print_summary(document):
    label = document["label"]
    print(f"\n# {label}: {document['driver']} on {document['cpu_model']} ({document['cpus']} CPUs, "
          f"{' '.join(document['cpu_simd'])}); POV-Ray +WT{THREADS}", flush=True)
    for r in document["results"]:
        ours, pov = r["whitted"], r["povray"]
        rays = ours["rays"]
        line = (f"{r['scene']:11s} {r['width']}x{r['height']} {r['spp']:2d}spp  bvh {ours['bvh_build_s']:.3f} s  "
                f"render {ours['render_s']:.2f} s  wall {ours['wall_s']:.2f} s  "
                f"{ours['rays_per_s'] / 1e6:.2f} Mrays/s (p {rays['primary']} s {rays['shadow']} "
                f"r {rays['secondary']})  rss {ours['peak_rss_bytes'] / 2**20:.0f} MiB")
        if pov:
            line += (f"\n{'':11s} POV-Ray: render {pov['render_s']} s  wall {pov['wall_s']:.2f} s  "
                     f"rss {pov['peak_rss_bytes'] / 2**20:.0f} MiB")
            if "povray_over_whitted" in r:
                ratio = r["povray_over_whitted"]
                line += f"  POV-Ray/whitted: wall {ratio['wall']:.2f}x, render {ratio['render']:.2f}x"
        if ours["lost_samples"]:
            line += f"\n{'':11s} WARNING: {ours['lost_samples']} camera samples lost: the image is incomplete"
        print(line, flush=True)
    for r in document["equal_quality"]:
        mine, pov = r["whitted"], r["povray"]
        ref = mine["reference"]
        made = "cached" if ref.get("cached") else f"{ref['wall_s']:.1f} s"
        print(f"{r['scene']:11s} {r['width']}x{r['height']} time to >= {PSNR_TARGET_DB:.0f} dB: whitted reference "
              f"{' '.join(WHITTED_REFERENCE)} ({ref.get('reference_driver')}, {made})", flush=True)
        for t in mine["tries"]:
            print(f"{'':13s}whitted {t['sampling']:14s} "
                  f"wall {t['wall_s']:.2f} s  render {t['render_s']:.2f} s  {t['mean_spp']:.2f} spp  "
                  f"{t['rays_per_s'] / 1e6:.2f} Mrays/s  {fmt_db(t['psnr_db'])}", flush=True)
        if pov:
            for t in pov["tries"]:
                print(f"{'':13s}POV-Ray +A{t['threshold']:<5} +AM2 +R3  wall {t['wall_s']:.2f} s  render {t['render_s']} s"
                      f"  {fmt_db(t['psnr_db'])}", flush=True)
        def reached(seconds, tries, how):
            if seconds is not None:
                return f"{seconds:.2f} s ({how})"
            return "not reached (best " + fmt_db(max((t["psnr_db"] for t in tries), key=lambda d: math.inf if d is None else d)) + ")"
        verdict = f"{'':13s}clean: whitted " + reached(
            mine["time_to_clean_s"], mine["tries"], mine["reached"] is not None and mine["tries"][mine["reached"]]["sampling"])
        if pov:
            verdict += ", POV-Ray " + reached(pov["time_to_clean_s"], pov["tries"], f"+A{pov['reached_threshold']}")
        if "povray_over_whitted" in r and "time_to_clean" in r["povray_over_whitted"]:
            verdict += f"  POV-Ray/whitted {r['povray_over_whitted']['time_to_clean']:.2f}x"
        print(verdict, flush=True)
    drag = document.get("drag_proxy")
    if drag:
        print(f"drag proxy  {drag['width']}x{drag['height']} 1 spp render: median {drag['render_median_s'] * 1000:.0f} ms, "
              f"fastest {drag['render_min_s'] * 1000:.0f} ms of {len(drag['render_s'])}", flush=True)
    for name, value in document["ratios"].items():
        print(f"{name}: {value:.2f}", flush=True)
    for t in document["targets"]:
        verdict = "met" if t["met"] else (f"missed by {t['missed_by_factor']:.2f}x" if t["missed_by_factor"]
                                          else "not measured")
        print(f"target: {t['target']}: {t['value']:.3f} (limit {t['limit']:.3f}) {verdict}; {t['measured']}",
              flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="tiny scenes and sizes; checks the output, not times")
    parser.add_argument("--only", action="append", default=[], help="scene names (room, spheres100, spheres10k, "
                        "mesh1m), comma-separated or repeated")
    parser.add_argument("--sizes", default="small,full", help="fixed-spp sizes: small (640x480 1 spp), full "
                        "(1920x1080 16 spp)")
    parser.add_argument("--full-scenes", default="room", help="scenes rendered at the full size [room]; all = every "
                          "scene")
    parser.add_argument("--skip-fixed", action="store_true", help="no fixed-spp part")
    parser.add_argument("--skip-equal-quality", action="store_true", help="no time-to-a-clean-image part")
    parser.add_argument("--skip-povray", action="store_true", help="do not run POV-Ray")
    parser.add_argument("--driver-files", action="append", default=[], help="Vulkan ICD JSON whitted runs on "
                        "(VK_DRIVER_FILES), or 'default'; repeatable [default]")
    parser.add_argument("--label", action="append", default=[], help="a name for each --driver-files, in order "
                        "[from the driver string, e.g. mesa-25.0.7]")
    parser.add_argument("--equal-quality-size", default=None, metavar="WxH", help="one size for every scene's "
                        "equal-quality part [room 1920x1080, the others 640x480]")
    parser.add_argument("--fresh-references", action="store_true", help="render the 64-sample references again")
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
    full_scenes = list(scenes) if args.full_scenes == "all" or args.quick else [
        n for n in args.full_scenes.split(",") if n]
    for n in full_scenes:
        if n not in scenes:
            fail(f"--full-scenes: unknown scene '{n}', expected one of {', '.join(scenes)} or all")
    sizes_eq = equal_quality_sizes(args.quick)
    if args.equal_quality_size:
        match = re.fullmatch(r"(\d+)x(\d+)", args.equal_quality_size)
        if not match or not all(0 < int(v) <= 16384 for v in match.groups()):
            fail(f"--equal-quality-size: expected WxH, got '{args.equal_quality_size}'")
        sizes_eq = {name: (int(match.group(1)), int(match.group(2))) for name in sizes_eq}
    if len(args.label) > max(1, len(args.driver_files)):
        fail("--label: more labels than --driver-files")
    files = args.driver_files or ["default"]
    labels = args.label + [None] * (len(files) - len(args.label))
    drivers = [Driver(None if f == "default" else f, label) for f, label in zip(files, labels)]
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
    for d in drivers:
        d.probe(whitted, work)
    if len({d.label for d in drivers}) != len(drivers):
        fail("two drivers have the same label: give each --driver-files its own --label")
    model, simd = cpu_model()
    started = time.monotonic()
    print(f"CPU: {model} ({os.cpu_count()} CPUs, {' '.join(simd)}); drivers: "
          + "; ".join(f"{d.label} = {d.driver}" for d in drivers), flush=True)

    results = {d.label: [] for d in drivers}
    eq_results = {d.label: [] for d in drivers}
    for name, (how, arg) in scenes.items():
        if only and name not in only:
            continue
        scene, note = make_scene(name, how, arg, work, whitted, drivers[0].env)
        for size in [] if args.skip_fixed else chosen_sizes:
            if size == "full" and name not in full_scenes:
                continue
            width, height, spp = sizes[size]
            tag = f"{name}_{size}"
            print(f"== {name} {width}x{height} {spp} spp", file=sys.stderr, flush=True)
            ours = {d.label: run_whitted(whitted, d, scene, os.path.join(work, f"{tag}_{d.label}.png"), width, height,
                                         ["--aa", "uniform", "--spp", str(spp)]) for d in drivers}
            pov = None
            if not args.skip_povray:
                pov = run_povray(export_pov(exporter, scene, work, tag, width, height),
                                 os.path.join(work, tag + ".pov.png"), width, height, povray_fixed_antialias(spp))
            for d in drivers:
                result = {"scene": name, "size": size, "width": width, "height": height, "spp": spp,
                          "max_depth": MAX_DEPTH, "mesh_source": note, "whitted": ours[d.label], "povray": pov}
                if pov and pov["render_s"]:
                    result["povray_over_whitted"] = {"wall": pov["wall_s"] / ours[d.label]["wall_s"],
                                                     "render": pov["render_s"] / ours[d.label]["render_s"]}
                results[d.label].append(result)
        if not args.skip_equal_quality:
            width, height = sizes_eq[name]
            for label, entry in equal_quality(name, scene, width, height, drivers, whitted, exporter, work,
                                              args.skip_povray, args.fresh_references).items():
                entry["mesh_source"] = note
                eq_results[label].append(entry)
    drag = None
    if not args.skip_fixed and (not only or "room" in only):
        print("== drag proxy", file=sys.stderr, flush=True)
        drag = drag_proxy(whitted, drivers, work, 1 if args.quick else DRAG_REPEATS)
    elapsed = time.monotonic() - started

    documents = {}
    for d in drivers:
        ratios = {}
        by_key = {(r["scene"], r["size"]): r for r in results[d.label]}
        for size in chosen_sizes:
            a, b = by_key.get(("spheres10k", size)), by_key.get(("spheres100", size))
            if a and b:
                ratios[f"spheres10k_over_spheres100_{size}"] = a["whitted"]["render_s"] / b["whitted"]["render_s"]
        document = {"created": time.strftime("%Y-%m-%dT%H:%M:%S%z"), "host": platform.node(),
                    "cpu_model": model, "cpu_simd": simd, "cpus": os.cpu_count(), "quick": args.quick,
                    "threads": THREADS, "label": d.label, "driver": d.driver, "device": d.device,
                    "driver_files": d.files, "ld_library_path": d.env.get("LD_LIBRARY_PATH") if d.files else None,
                    "drivers_in_run": [x.label for x in drivers], "benchmark_wall_s": elapsed,
                    "results": results[d.label], "equal_quality": eq_results[d.label],
                    "drag_proxy": drag and drag[d.label], "ratios": ratios}
        document["targets"] = targets(document)
        documents[d.label] = document
        json_path = os.path.join(out, f"benchmark-{d.label}.json")
        if os.path.exists(json_path):
            shutil.copyfile(json_path, os.path.join(out, f"benchmark-{d.label}.previous.json"))
        temporary = json_path + ".partial"
        with open(temporary, "w", encoding="utf-8") as f:
            json.dump(document, f, indent=2)
        os.replace(temporary, json_path)
        print_summary(document)
    if any(doc["results"] or doc["equal_quality"] for doc in documents.values()):
        plot(documents, os.path.join(out, "benchmark.png"))
    print(f"\nbenchmark: {elapsed / 60:.1f} minutes; wrote "
          + ", ".join(os.path.join(out, f"benchmark-{label}.json") for label in documents)
          + f" and {os.path.join(out, 'benchmark.png')}", flush=True)

    if args.quick:
        # The smoke test: the files parse back and every count is positive.
        bad = []
        for label in documents:
            with open(os.path.join(out, f"benchmark-{label}.json"), encoding="utf-8") as f:
                reread = json.load(f)
            bad += [f"{label} {r['scene']} {r['size']}: {name} = {value}" for r in reread["results"]
                    for name, value in positive_counts(r) if not (isinstance(value, (int, float)) and value > 0)]
            bad += [f"{label} {r['scene']} {r['size']}: {r['whitted']['lost_samples']} camera samples lost"
                    for r in reread["results"] if r["whitted"]["lost_samples"] != 0]
            bad += [f"{label} {r['scene']} equal quality: {name} = {value}" for r in reread["equal_quality"]
                    for name, value in equal_quality_counts(r) if not (isinstance(value, (int, float)) and value > 0)]
            if not args.skip_fixed and not reread["results"]:
                bad.append(f"{label}: no fixed-spp results")
            if not args.skip_equal_quality and not reread["equal_quality"]:
                bad.append(f"{label}: no equal-quality results")
            if reread["drag_proxy"] and not all(t > 0 for t in reread["drag_proxy"]["render_s"]):
                bad.append(f"{label}: drag proxy render times {reread['drag_proxy']['render_s']}")
            if not reread["cpu_model"] or not reread["driver"]:
                bad.append(f"{label}: no CPU model or driver")
        if bad:
            fail("quick check failed:\n  " + "\n  ".join(bad), 1)
        print(f"quick check: {sum(len(d['results']) + len(d['equal_quality']) for d in documents.values())} results, "
              "every count > 0", flush=True)


if __name__ == "__main__":
    main()
