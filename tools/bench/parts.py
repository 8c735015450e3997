"""The benchmark's parts, whitted against POV-Ray in the same run: fixed samples per pixel and equal quality
(time to a clean image) scene by scene, then the window's drag proxy. Every part interleaves the drivers' whitted
runs with the POV-Ray runs, so that load from other jobs hits both."""
import dataclasses
import hashlib
import json
import os
import shutil
import statistics
import sys
import tempfile

from .measures import clean, psnr
from .plan import (DRAG_SIZE, STARTUP_SIZE, MAX_DEPTH, POVRAY_ADAPTIVE, POVRAY_REFERENCE, POVRAY_THRESHOLDS, PSNR_TARGET_DB, ROOM,
                   SOFT, SOFT_POVRAY_BLUR_SAMPLES, SOFT_REFERENCE_SAMPLES, SOFT_TARGET_DB, SOFT_WHITTED_TRIES,
                   WHITTED_REFERENCE, WHITTED_TRIES, povray_fixed_antialias)
from .measures import read_record
from .runners import export_pov, make_scene, povray_version, run, run_anchor, run_povray, run_whitted, sha256_file


@dataclasses.dataclass
class Bench:
    """What every part runs with: the tools, the drivers and the work folder."""
    whitted: str
    exporter: str  # whitted_povray_export; None when POV-Ray is skipped
    drivers: list
    work: str
    anchor: str = None  # whitted_embree_anchor (tools/embree_anchor.cpp); None when not built


def progress(line):
    """A line on stderr saying what runs now."""
    print(f"== {line}", file=sys.stderr, flush=True)


def run_scenes(bench, plan):
    """Both parts for every scene of the plan: (label -> fixed-spp results, label -> equal-quality results)."""
    results = {d.label: [] for d in bench.drivers}
    eq_results = {d.label: [] for d in bench.drivers}
    for name, (how, arg) in plan.scenes.items():
        scene, note = make_scene(name, how, arg, bench.work, bench.whitted, bench.drivers[0].env)
        for size, (width, height, spp) in plan.sizes:
            if size == "full" and name not in plan.full_scenes:
                continue
            for label, result in fixed_samples(bench, name, scene, note, size, width, height, spp).items():
                results[label].append(result)
        if plan.equal_quality:
            width, height = plan.equal_quality_sizes[name]
            for label, entry in equal_quality(bench, name, scene, width, height, plan.fresh_references).items():
                entry["mesh_source"] = note
                eq_results[label].append(entry)
    return results, eq_results


def fixed_samples(bench, name, scene, note, size, width, height, spp):
    """Every driver's whitted and POV-Ray at one scene, size and sample count. Returns label -> result."""
    tag = f"{name}_{size}"
    progress(f"{name} {width}x{height} {spp} spp")
    ours = {d.label: run_whitted(bench.whitted, d, scene, os.path.join(bench.work, f"{tag}_{d.label}.png"), width,
                                 height, ["--aa", "uniform", "--spp", str(spp)]) for d in bench.drivers}
    pov = None
    if bench.exporter:
        pov = run_povray(export_pov(bench.exporter, scene, bench.work, tag, width, height),
                         os.path.join(bench.work, tag + ".pov.png"), width, height, povray_fixed_antialias(spp))
    embree = None
    if bench.anchor:
        progress(f"{name} {width}x{height} {spp} spp Embree anchor")
        embree = run_anchor(bench.anchor, scene, width, height, spp)
    out = {}
    for d in bench.drivers:
        result = {"scene": name, "size": size, "width": width, "height": height, "spp": spp,
                  "max_depth": MAX_DEPTH, "mesh_source": note, "whitted": ours[d.label], "povray": pov,
                  "embree": embree}
        if pov and pov["render_s"]:
            result["povray_over_whitted"] = {"wall": pov["wall_s"] / ours[d.label]["wall_s"],
                                             "render": pov["render_s"] / ours[d.label]["render_s"]}
        if embree and embree["supported"]:
            result["whitted_over_embree"] = whitted_over_embree(ours[d.label], embree)
        out[d.label] = result
    return out


def whitted_over_embree(ours, embree):
    """whitted's rays per second as a fraction of the Embree anchor's, from the same run: all of whitted's rays, and
    its camera plus shadow rays alone (what the anchor traces) over its render time."""
    rays = ours["rays"]
    return {"rays_per_s": ours["rays_per_s"] / embree["rays_per_s"],
            "primary_shadow_rays_per_s": (rays["primary"] + rays["shadow"]) / ours["render_s"] / embree["rays_per_s"],
            # How closely the anchor's rays are whitted's: its counts over whitted's.
            "camera_rays_ratio": embree["camera_rays"] / rays["primary"] if rays["primary"] else None,
            "shadow_rays_ratio": embree["shadow_rays"] / rays["shadow"] if rays["shadow"] else None}


def cached_reference(cache, key, make, fresh):
    """Returns (image path, record) of a reference: from the cache unless `fresh`, or made by make(path) -> record."""
    os.makedirs(cache, exist_ok=True)
    path = os.path.join(cache, key + ".png")
    meta = os.path.join(cache, key + ".meta.json")
    if fresh:
        for stale in (path, meta, os.path.join(cache, key + ".json")):
            if os.path.exists(stale):
                os.remove(stale)
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


def reference_key(renderer, *parts):
    """A cache key: the renderer's name and a hash of what makes its reference (binary, scene, options)."""
    return renderer + "_" + hashlib.sha256(" ".join(str(p) for p in parts).encode()).hexdigest()[:24]


def whitted_reference(bench, scene, width, height, fresh):
    """whitted's 64-sample uniform reference, rendered by the first driver: (image path, record)."""
    first = bench.drivers[0]
    whitted_hash = sha256_file(bench.whitted, os.environ.get("WHITTED_SHADER_SPV", ""))
    key = reference_key("whitted", whitted_hash, sha256_file(scene), f"{width}x{height}", WHITTED_REFERENCE,
                        MAX_DEPTH)
    return cached_reference(os.path.join(bench.work, "references"), key, lambda path: dict(
        run_whitted(bench.whitted, first, scene, path, width, height, WHITTED_REFERENCE), reference_driver=first.label),
        fresh)


def povray_reference(pov, work, width, height, fresh):
    """POV-Ray's 64-sample reference of an exported scene: (image path, record)."""
    version = povray_version()
    key = reference_key("povray", version, sha256_file(pov), f"{width}x{height}", POVRAY_REFERENCE)
    return cached_reference(os.path.join(work, "references"), key, lambda path: dict(
        run_povray(pov, path, width, height, POVRAY_REFERENCE), version=version), fresh)


def equal_quality(bench, name, scene, width, height, fresh):
    """Time to a clean image for every driver and for POV-Ray at one scene and size. Returns label -> result."""
    tag = f"{name}_eq_{width}x{height}"
    progress(f"{name} {width}x{height} equal quality: references")
    reference, reference_record = whitted_reference(bench, scene, width, height, fresh)
    pov = pov_reference = pov_reference_record = None
    if bench.exporter:
        pov = export_pov(bench.exporter, scene, bench.work, tag, width, height)
        pov_reference, pov_reference_record = povray_reference(pov, bench.work, width, height, fresh)

    ours = {d.label: {"reference": reference_record, "tries": [], "reached": None, "time_to_clean_s": None}
            for d in bench.drivers}
    theirs = {"reference": pov_reference_record, "tries": [], "reached_threshold": None, "time_to_clean_s": None}
    defaults = {}
    # Rounds: each driver's next whitted try, then POV-Ray's next threshold, until all are clean or out of tries.
    for step in range(max(len(WHITTED_TRIES), len(POVRAY_THRESHOLDS))):
        for d in bench.drivers:
            mine = ours[d.label]
            if mine["reached"] is not None or step >= len(WHITTED_TRIES):
                continue
            image = os.path.join(bench.work, f"{tag}_{d.label}_try{step}.png")
            progress(f"{name} {width}x{height} whitted {d.label} {' '.join(WHITTED_TRIES[step]) or 'default'}")
            result = run_whitted(bench.whitted, d, scene, image, width, height, WHITTED_TRIES[step])
            result["psnr_db"] = psnr(image, reference)
            mine["tries"].append(result)
            if step == 0:
                defaults[d.label] = image
            if clean(result["psnr_db"]):
                mine["reached"] = step
                mine["time_to_clean_s"] = result["wall_s"]
        if pov and step < len(POVRAY_THRESHOLDS) and theirs["reached_threshold"] is None:
            threshold = POVRAY_THRESHOLDS[step]
            image = os.path.join(bench.work, f"{tag}_povray_A{threshold}.png")
            progress(f"{name} {width}x{height} POV-Ray +A{threshold}")
            result = run_povray(pov, image, width, height, [f"+A{threshold}", *POVRAY_ADAPTIVE])
            result["threshold"] = threshold
            result["psnr_db"] = psnr(image, pov_reference)
            theirs["tries"].append(result)
            if clean(result["psnr_db"]):
                theirs["reached_threshold"] = threshold
                theirs["time_to_clean_s"] = result["wall_s"]
    return {d.label: equal_quality_entry(bench.drivers[0], d, name, width, height, ours[d.label],
                                         theirs if pov else None, defaults) for d in bench.drivers}


def equal_quality_entry(first, driver, name, width, height, mine, theirs, defaults):
    """One driver's equal-quality result from its tries and POV-Ray's (None when skipped), with the ratios."""
    entry = {"scene": name, "width": width, "height": height, "psnr_target_db": PSNR_TARGET_DB,
             "whitted": mine, "povray": theirs}
    if driver is not first and first.label in defaults and driver.label in defaults:
        # The reference is the first driver's; how far this driver's own default render is from that driver's.
        mine["default_psnr_against_" + first.label + "_db"] = psnr(defaults[driver.label], defaults[first.label])
    if theirs and theirs["time_to_clean_s"] and mine["time_to_clean_s"]:
        entry["povray_over_whitted"] = {"time_to_clean": theirs["time_to_clean_s"] / mine["time_to_clean_s"]}
    if theirs and theirs["tries"] and mine["tries"]:
        entry.setdefault("povray_over_whitted", {})["first_tries"] = (theirs["tries"][0]["wall_s"] /
                                                                     mine["tries"][0]["wall_s"])
    return entry


def drag_proxy(bench, repeats):
    """Render time of 640x360 at 1 spp (the window's frame in a camera drag), interleaved between drivers."""
    progress("drag proxy")
    width, height = DRAG_SIZE
    times = {d.label: [] for d in bench.drivers}
    walls = {d.label: [] for d in bench.drivers}
    for _ in range(repeats):
        for d in bench.drivers:
            image = os.path.join(bench.work, f"drag_{d.label}.png")
            result = run_whitted(bench.whitted, d, ROOM, image, width, height, ["--aa", "uniform", "--spp", "1"])
            times[d.label].append(result["render_s"])
            walls[d.label].append(result["wall_s"])
    return {d.label: {"scene": "room", "width": width, "height": height, "spp": 1, "render_s": times[d.label],
                      "render_median_s": statistics.median(times[d.label]), "render_min_s": min(times[d.label]),
                      "wall_median_s": statistics.median(walls[d.label])} for d in bench.drivers}


def warm_start(bench, repeats):
    """Whole-process wall time of a warm 8x8 render of the room (default sampling, --aov none): the fixed cost of a
    render. One untimed run first warms the caches (Mesa's and the pipeline cache); then `repeats` runs into a PPM
    and into a PNG (both written without the image library since 2026-12-02; before, a PNG loaded it), interleaved
    between drivers."""
    progress("warm start")
    width, height = STARTUP_SIZE
    out = {}
    for d in bench.drivers:
        run_whitted(bench.whitted, d, ROOM, os.path.join(bench.work, f"warm_{d.label}.ppm"), width, height, [])
    walls = {(d.label, ext): [] for d in bench.drivers for ext in ("ppm", "png")}
    stages = {(d.label, ext): [] for d in bench.drivers for ext in ("ppm", "png")}
    for _ in range(repeats):
        for d in bench.drivers:
            for ext in ("ppm", "png"):
                result = run_whitted(bench.whitted, d, ROOM, os.path.join(bench.work, f"warm_{d.label}.{ext}"),
                                     width, height, [])
                walls[(d.label, ext)].append(result["wall_s"])
                stages[(d.label, ext)].append(result.get("pipeline_s"))
    for d in bench.drivers:
        out[d.label] = {"scene": "room", "width": width, "height": height, "sampling": "default", "aov": "none"}
        for ext in ("ppm", "png"):
            w = walls[(d.label, ext)]
            out[d.label][ext] = {"wall_s": w, "wall_median_s": statistics.median(w), "wall_min_s": min(w),
                                 "pipeline_s": stages[(d.label, ext)]}
    return out


def cold_start(bench, repeats):
    """Whole-process wall time of README command 1's render, `whitted render scenes/room.xml` (default size,
    sampling and auxiliary images), on a machine that has never run it: Mesa's shader cache and whitted's pipeline
    cache both in a new empty folder (XDG_CACHE_HOME, MESA_SHADER_CACHE_DIR, WHITTED_PIPELINE_CACHE), so that the
    driver compiles the tracer. Each cold run is followed by a warm one with the same caches (the command run a
    second time); cold minus warm is the compilation. `repeats` pairs, interleaved between drivers."""
    progress("cold start")
    cold = {d.label: [] for d in bench.drivers}
    warm = {d.label: [] for d in bench.drivers}
    for _ in range(repeats):
        for d in bench.drivers:
            caches = tempfile.mkdtemp(prefix="whitted-cold-", dir=bench.work)
            env = dict(d.env, XDG_CACHE_HOME=caches, MESA_SHADER_CACHE_DIR=os.path.join(caches, "mesa"),
                       WHITTED_PIPELINE_CACHE=os.path.join(caches, "whitted"))
            env.pop("MESA_SHADER_CACHE_DISABLE", None)
            for runs, name in ((cold, "cold"), (warm, "warm")):
                image = os.path.join(bench.work, f"{name}_{d.label}.png")
                status, output, wall, _ = run([bench.whitted, "render", ROOM, "-o", image, "-q"], env=env)
                if status != 0:
                    fail(f"whitted failed on {ROOM} with driver {d.label} (exit {status}):\n{output}", 1)
                timings = read_record(image)["timings_s"]
                runs[d.label].append({"wall_s": wall, "pipeline_s": timings["pipeline"],
                                      "render_s": timings["render"]})
            shutil.rmtree(caches, ignore_errors=True)
    out = {}
    for d in bench.drivers:
        cold_walls = [r["wall_s"] for r in cold[d.label]]
        warm_walls = [r["wall_s"] for r in warm[d.label]]
        out[d.label] = {"scene": "room", "command": "whitted render scenes/room.xml", "cold": cold[d.label],
                        "warm": warm[d.label], "cold_wall_median_s": statistics.median(cold_walls),
                        "warm_wall_median_s": statistics.median(warm_walls),
                        "compile_median_s": statistics.median(c - w for c, w in zip(cold_walls, warm_walls))}
    return out


def soft_quality(bench, width, height, fresh):
    """Time to a clean image of scenes/soft.xml (area lights, glossy metal and glass, a lens) for every driver and
    for POV-Ray (area_light + focal_blur; its mirrors stay sharp: povray_export.h). Each renderer's reference is
    its own at SOFT_REFERENCE_SAMPLES (whitted uniform, POV-Ray blur_samples; not timed, cached); then tries in
    order (SOFT_WHITTED_TRIES, SOFT_POVRAY_BLUR_SAMPLES), interleaved, until within SOFT_TARGET_DB of it. Time to a
    clean image = whole-process wall time of the first try that reaches it. Returns label -> result."""
    tag = f"soft_{width}x{height}"
    progress(f"soft {width}x{height}: references")
    first = bench.drivers[0]
    reference_flags = ["--aa", "uniform", "--spp", str(SOFT_REFERENCE_SAMPLES)]
    key = reference_key("whitted", sha256_file(bench.whitted, os.environ.get("WHITTED_SHADER_SPV", "")),
                        sha256_file(SOFT), f"{width}x{height}", *reference_flags, MAX_DEPTH)
    reference, reference_record = cached_reference(os.path.join(bench.work, "references"), key, lambda path: dict(
        run_whitted(bench.whitted, first, SOFT, path, width, height, reference_flags), reference_driver=first.label),
        fresh)
    pov_reference = pov_reference_record = None
    if bench.exporter:
        pov = export_pov(bench.exporter, SOFT, bench.work, f"{tag}_ref", width, height, SOFT_REFERENCE_SAMPLES)
        version = povray_version()
        key = reference_key("povray", version, sha256_file(pov), f"{width}x{height}")
        pov_reference, pov_reference_record = cached_reference(os.path.join(bench.work, "references"), key,
                                                               lambda path: dict(run_povray(pov, path, width, height,
                                                                                            []), version=version),
                                                               fresh)
    ours = {d.label: {"reference": reference_record, "tries": [], "reached": None, "time_to_clean_s": None}
            for d in bench.drivers}
    theirs = {"reference": pov_reference_record, "tries": [], "reached_blur_samples": None, "time_to_clean_s": None}
    for step in range(max(len(SOFT_WHITTED_TRIES), len(SOFT_POVRAY_BLUR_SAMPLES))):
        for d in bench.drivers:
            mine = ours[d.label]
            if mine["reached"] is not None or step >= len(SOFT_WHITTED_TRIES):
                continue
            flags = SOFT_WHITTED_TRIES[step]
            image = os.path.join(bench.work, f"{tag}_{d.label}_try{step}.png")
            progress(f"soft {width}x{height} whitted {d.label} {' '.join(flags) or 'default'}")
            result = run_whitted(bench.whitted, d, SOFT, image, width, height, flags)
            result["psnr_db"] = psnr(image, reference)
            mine["tries"].append(result)
            if result["psnr_db"] is None or result["psnr_db"] >= SOFT_TARGET_DB:
                mine["reached"] = step
                mine["time_to_clean_s"] = result["wall_s"]
        if pov_reference and step < len(SOFT_POVRAY_BLUR_SAMPLES) and theirs["reached_blur_samples"] is None:
            samples = SOFT_POVRAY_BLUR_SAMPLES[step]
            pov = export_pov(bench.exporter, SOFT, bench.work, f"{tag}_blur{samples}", width, height, samples)
            image = os.path.join(bench.work, f"{tag}_povray_blur{samples}.png")
            progress(f"soft {width}x{height} POV-Ray blur_samples {samples}")
            result = run_povray(pov, image, width, height, [])
            result["blur_samples"] = samples
            result["psnr_db"] = psnr(image, pov_reference)
            theirs["tries"].append(result)
            if result["psnr_db"] is None or result["psnr_db"] >= SOFT_TARGET_DB:
                theirs["reached_blur_samples"] = samples
                theirs["time_to_clean_s"] = result["wall_s"]
    out = {}
    for d in bench.drivers:
        entry = {"scene": "soft", "width": width, "height": height, "psnr_target_db": SOFT_TARGET_DB,
                 "reference_samples": SOFT_REFERENCE_SAMPLES, "whitted": ours[d.label],
                 "povray": theirs if pov_reference else None}
        if pov_reference and theirs["time_to_clean_s"] and ours[d.label]["time_to_clean_s"]:
            entry["povray_over_whitted"] = {"time_to_clean": theirs["time_to_clean_s"] /
                                            ours[d.label]["time_to_clean_s"]}
        out[d.label] = entry
    return out
