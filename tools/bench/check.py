"""The --quick smoke test (ctest Benchmark.Quick): every driver's JSON file parses back, every count is positive,
no camera sample is lost. It checks the output's shape, never a time."""
import json

from . import fail
from .report import json_path


def positive(value):
    """Whether a count is a number > 0."""
    return isinstance(value, (int, float)) and value > 0


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
    embree = result.get("embree")
    if embree and embree["supported"]:
        checks += [("embree.camera_rays", embree["camera_rays"]), ("embree.rays_per_s", embree["rays_per_s"])]
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


def problems(label, document, plan):
    """What is wrong with one driver's document as read back, one line each."""
    bad = [f"{label} {r['scene']} {r['size']}: {name} = {value}" for r in document["results"]
           for name, value in positive_counts(r) if not positive(value)]
    bad += [f"{label} {r['scene']} {r['size']}: {r['whitted']['lost_samples']} camera samples lost"
            for r in document["results"] if r["whitted"]["lost_samples"] != 0]
    bad += [f"{label} {r['scene']} equal quality: {name} = {value}" for r in document["equal_quality"]
            for name, value in equal_quality_counts(r) if not positive(value)]
    if plan.fixed and plan.scenes and not document["results"]:
        bad.append(f"{label}: no fixed-spp results")
    if plan.equal_quality and plan.scenes and not document["equal_quality"]:
        bad.append(f"{label}: no equal-quality results")
    if document["drag_proxy"] and not all(t > 0 for t in document["drag_proxy"]["render_s"]):
        bad.append(f"{label}: drag proxy render times {document['drag_proxy']['render_s']}")
    soft = document.get("soft")
    if plan.soft and not (soft and soft["whitted"]["tries"] and all(t["wall_s"] > 0 for t in soft["whitted"]["tries"])):
        bad.append(f"{label}: no distribution (soft) results")
    if soft and plan.povray and not (soft["povray"] and soft["povray"]["tries"]):
        bad.append(f"{label}: no POV-Ray tries in the distribution (soft) part")
    cold = document.get("cold_start")
    if cold and not all(r["wall_s"] > 0 for r in cold["cold"] + cold["warm"]):
        bad.append(f"{label}: cold start times {cold['cold']} {cold['warm']}")
    if plan.cold_start and not cold:
        bad.append(f"{label}: no cold-start results")
    if not document["cpu_model"] or not document["driver"]:
        bad.append(f"{label}: no CPU model or driver")
    return bad


def quick_check(documents, out, plan):
    """Reads every driver's JSON file back; fails the benchmark with what is wrong, else says how many passed."""
    bad = []
    for label in documents:
        with open(json_path(out, label), encoding="utf-8") as f:
            bad += problems(label, json.load(f), plan)
    if bad:
        fail("quick check failed:\n  " + "\n  ".join(bad), 1)
    print(f"quick check: {sum(len(d['results']) + len(d['equal_quality']) for d in documents.values())} results, "
          "every count > 0", flush=True)
