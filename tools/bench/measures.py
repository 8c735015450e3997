"""Numbers from what the runs leave: whitted's record (X.json beside X.png), POV-Ray's own counters, PSNR
against a reference, the ratios between scenes and issue 8's targets with their verdicts."""
import json
import math
import os
import re

from . import fail
from .plan import PSNR_TARGET_DB, povray_fixed_antialias


def read_record(png):
    """The record `whitted render -o X.png` writes beside the image as X.json."""
    with open(os.path.splitext(png)[0] + ".json", encoding="utf-8") as f:
        return json.load(f)


def whitted_measures(record, options, sampling, wall, rss):
    """One whitted run's result: its record's times, rays, BVH and memory with the process's wall time and RSS."""
    rays = record["rays"]
    timings = record["timings_s"]
    sampling_record = record.get("sampling", {})
    return {
        "options": options,
        "sampling": sampling,
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


def povray_measures(output, options, wall, rss):
    """One POV-Ray run's result: the times and counters POV-Ray prints with the process's wall time and RSS."""
    times = {m.group(1).lower(): float(m.group(5)) for m in POV_TIME.finditer(output)}
    samples = POV_SAMPLES.search(output)
    return {"wall_s": wall, "parse_s": times.get("parse"), "bounding_s": times.get("bounding"),
            "render_s": times.get("trace"), "peak_rss_bytes": rss,
            # POV-Ray's own counters (its "Pixels" include a border row and column it traces for antialiasing)
            "pixels": int(samples.group(1)) if samples else None,
            "samples": int(samples.group(2)) if samples else None,
            "options": options}


def read_rgb8(path):
    """An 8-bit image's RGB on [0, 1] as a float64 array."""
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
    """Whether an image `db` from its reference counts as clean."""
    return db is None or db >= PSNR_TARGET_DB


def fmt_db(db):
    """A PSNR for people: "identical" for None (infinite)."""
    return "identical" if db is None else f"{db:.1f} dB"


def by_scene_and_size(results):
    """The fixed-spp results keyed by (scene, size)."""
    return {(r["scene"], r["size"]): r for r in results}


def ratios(results, sizes):
    """Render time of 10,000 spheres over 100, at each fixed-spp size both were rendered at."""
    out = {}
    by_key = by_scene_and_size(results)
    for size, _ in sizes:
        a, b = by_key.get(("spheres10k", size)), by_key.get(("spheres100", size))
        if a and b:
            out[f"spheres10k_over_spheres100_{size}"] = a["whitted"]["render_s"] / b["whitted"]["render_s"]
    return out


def targets(document):
    """Issue 8's targets with measured verdicts, from one driver's document."""
    out = []
    fixed = by_scene_and_size(document["results"])
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
            pov = (f"POV-Ray reached no {PSNR_TARGET_DB:.0f} dB; its last try, +A{last['threshold']} "
                   f"({fmt_db(last['psnr_db'])}), took {p:.2f} s (a lower bound)")
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
    for size in ("small", "full"):
        mesh = fixed.get(("mesh1m", size))
        if mesh and mesh.get("whitted_over_embree"):
            e = mesh["embree"]
            add(f"1M-triangle mesh, primary plus shadow rays >= 50% of Embree's rays per second ({mesh['width']}x"
                f"{mesh['height']} {mesh['spp']} spp, Embree {e['embree']} {e['packet']}-ray packets on {e['threads']}"
                " threads)", mesh["whitted_over_embree"]["primary_shadow_rays_per_s"], 0.5, "higher",
                f"whitted {(mesh['whitted']['rays']['primary'] + mesh['whitted']['rays']['shadow']) / mesh['whitted']['render_s'] / 1e6:.2f}"
                f" Mrays/s, Embree {e['rays_per_s'] / 1e6:.2f} Mrays/s")
    drag = document.get("drag_proxy")
    if drag:
        add(f"window during a camera drag: {drag['width']}x{drag['height']} at 1 spp in <= 50 ms (proxy: median "
            "render time of `whitted render --aa uniform --spp 1 --aov none`)", drag["render_median_s"], 0.050,
            "lower", f"median {drag['render_median_s'] * 1000:.0f} ms, fastest {drag['render_min_s'] * 1000:.0f} ms "
            f"of {len(drag['render_s'])}")
    warm = document.get("warm_start")
    if warm:
        for ext in ("ppm", "png"):
            w = warm[ext]
            add(f"a warm render of an {warm['width']}x{warm['height']} image <= 0.1 s as a whole process (room, default "
                f"sampling, --aov none, into {ext.upper()})", w["wall_median_s"], 0.1, "lower",
                f"median {w['wall_median_s'] * 1000:.0f} ms, fastest {w['wall_min_s'] * 1000:.0f} ms of {len(w['wall_s'])}")
    return out
