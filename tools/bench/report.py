"""What a run reports: one JSON document per driver (an earlier one kept as .previous.json), the printed
summary of each, and the plot of them all."""
import json
import math
import os
import platform
import shutil
import time

from .measures import fmt_db, ratios, targets
from .plan import PSNR_TARGET_DB, THREADS, WHITTED_REFERENCE


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


def document(driver, drivers, cpu, plan, elapsed, results, equal_quality, drag, warm, cold=None, soft=None):
    """One driver's document: the machine, the driver, its results, the ratios and the targets' verdicts."""
    model, simd = cpu
    out = {"created": time.strftime("%Y-%m-%dT%H:%M:%S%z"), "host": platform.node(),
           "cpu_model": model, "cpu_simd": simd, "cpus": os.cpu_count(), "quick": plan.quick,
           "threads": THREADS, "label": driver.label, "driver": driver.driver, "device": driver.device,
           "driver_files": driver.files, "ld_library_path": driver.env.get("LD_LIBRARY_PATH") if driver.files else None,
           "drivers_in_run": [x.label for x in drivers], "benchmark_wall_s": elapsed,
           "results": results, "equal_quality": equal_quality, "drag_proxy": drag, "warm_start": warm,
           "cold_start": cold, "soft": soft,
           "ratios": ratios(results, plan.sizes)}
    out["targets"] = targets(out)
    return out


def json_path(out, label):
    """Where a driver's document goes: OUT/benchmark-LABEL.json."""
    return os.path.join(out, f"benchmark-{label}.json")


def write_json(document, out):
    """Writes the document whole (through a temporary file), keeping the earlier one as .previous.json."""
    path = json_path(out, document["label"])
    if os.path.exists(path):
        shutil.copyfile(path, os.path.join(out, f"benchmark-{document['label']}.previous.json"))
    temporary = path + ".partial"
    with open(temporary, "w", encoding="utf-8") as f:
        json.dump(document, f, indent=2)
    os.replace(temporary, path)


def publish(documents, out, elapsed):
    """Writes and prints every driver's document, then the plot and a line naming the files."""
    for document in documents.values():
        write_json(document, out)
        print_summary(document)
    plot_path = os.path.join(out, "benchmark.png")
    if any(doc["results"] or doc["equal_quality"] for doc in documents.values()):
        from .plot import plot  # matplotlib only when there is something to plot
        plot(documents, plot_path)
    print(f"\nbenchmark: {elapsed / 60:.1f} minutes; wrote "
          + ", ".join(json_path(out, label) for label in documents) + f" and {plot_path}", flush=True)


def print_summary(document):
    """One driver's document for people: the fixed-spp and equal-quality results, the drag proxy, ratios, targets."""
    print(f"\n# {document['label']}: {document['driver']} on {document['cpu_model']} ({document['cpus']} CPUs, "
          f"{' '.join(document['cpu_simd'])}); POV-Ray +WT{THREADS}", flush=True)
    for r in document["results"]:
        print_fixed(r)
    for r in document["equal_quality"]:
        print_equal_quality(r)
    drag = document.get("drag_proxy")
    if drag:
        print(f"drag proxy  {drag['width']}x{drag['height']} 1 spp render: "
              f"median {drag['render_median_s'] * 1000:.0f} ms, fastest {drag['render_min_s'] * 1000:.0f} ms "
              f"of {len(drag['render_s'])}", flush=True)
    warm = document.get("warm_start")
    if warm:
        print(f"warm start  {warm['width']}x{warm['height']} whole process: PPM median "
              f"{warm['ppm']['wall_median_s'] * 1000:.0f} ms, PNG median {warm['png']['wall_median_s'] * 1000:.0f} ms "
              f"of {len(warm['ppm']['wall_s'])}", flush=True)
    if document.get("soft"):
        print_soft(document["soft"])
    cold = document.get("cold_start")
    if cold:
        print(f"cold start  {cold['command']}, empty shader caches, whole process: median "
              f"{cold['cold_wall_median_s']:.2f} s; the same run again {cold['warm_wall_median_s']:.2f} s; "
              f"compilation {cold['compile_median_s']:.2f} s (median of {len(cold['cold'])})", flush=True)
    for name, value in document["ratios"].items():
        print(f"{name}: {value:.2f}", flush=True)
    for t in document["targets"]:
        verdict = "met" if t["met"] else (f"missed by {t['missed_by_factor']:.2f}x" if t["missed_by_factor"]
                                          else "not measured")
        print(f"target: {t['target']}: {t['value']:.3f} (limit {t['limit']:.3f}) {verdict}; {t['measured']}",
              flush=True)


def print_fixed(r):
    """One fixed-spp result: whitted's times, rays and memory, POV-Ray's beside them with the ratios."""
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
    embree = r.get("embree")
    if embree and embree["supported"]:
        ratio = r["whitted_over_embree"]
        line += (f"\n{'':11s} Embree {embree['embree']}: {embree['rays_per_s'] / 1e6:.2f} Mrays/s ({embree['packet']}-ray "
                 f"packets, {embree['threads']} threads; camera {embree['camera_rays']}, shadow {embree['shadow_rays']})"
                 f"  whitted/Embree: {ratio['primary_shadow_rays_per_s']:.3f} (primary + shadow rays)")
    elif embree:
        line += f"\n{'':11s} Embree anchor: none ({embree['reason']})"
    if ours["lost_samples"]:
        line += f"\n{'':11s} WARNING: {ours['lost_samples']} camera samples lost: the image is incomplete"
    print(line, flush=True)


def print_equal_quality(r):
    """One equal-quality result: the reference, every try of both renderers, and when each got clean."""
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
    how = mine["reached"] is not None and mine["tries"][mine["reached"]]["sampling"]
    verdict = f"{'':13s}clean: whitted " + reached(mine["time_to_clean_s"], mine["tries"], how)
    if pov:
        verdict += ", POV-Ray " + reached(pov["time_to_clean_s"], pov["tries"], f"+A{pov['reached_threshold']}")
    if "povray_over_whitted" in r and "time_to_clean" in r["povray_over_whitted"]:
        verdict += f"  POV-Ray/whitted {r['povray_over_whitted']['time_to_clean']:.2f}x"
    print(verdict, flush=True)


def print_soft(r):
    """The distribution part: each renderer's tries against its own reference, and when each got clean."""
    mine, pov = r["whitted"], r["povray"]
    print(f"soft        {r['width']}x{r['height']} time to >= {r['psnr_target_db']:.0f} dB of each one's own "
          f"{r['reference_samples']}-sample reference", flush=True)
    for t in mine["tries"]:
        print(f"{'':13s}whitted {t['sampling']:22s} wall {t['wall_s']:.2f} s  render {t['render_s']:.2f} s  "
              f"{t['mean_spp']:.2f} spp  {fmt_db(t['psnr_db'])}", flush=True)
    for t in (pov or {}).get("tries", []):
        print(f"{'':13s}POV-Ray blur_samples {t['blur_samples']:<9} wall {t['wall_s']:.2f} s  render {t['render_s']} s"
              f"  {fmt_db(t['psnr_db'])}", flush=True)
    how = mine["reached"] is not None and mine["tries"][mine["reached"]]["sampling"]
    verdict = f"{'':13s}clean: whitted " + reached(mine["time_to_clean_s"], mine["tries"], how)
    if pov:
        verdict += ", POV-Ray " + reached(pov["time_to_clean_s"], pov["tries"],
                                          f"blur_samples {pov['reached_blur_samples']}")
    if "povray_over_whitted" in r:
        verdict += f"  POV-Ray/whitted {r['povray_over_whitted']['time_to_clean']:.2f}x"
    print(verdict, flush=True)


def reached(seconds, tries, how):
    """When a renderer got clean and with what, or the best PSNR of its tries when it did not."""
    if seconds is not None:
        return f"{seconds:.2f} s ({how})"
    best = max((t["psnr_db"] for t in tries), key=lambda d: math.inf if d is None else d)
    return f"not reached (best {fmt_db(best)})"
