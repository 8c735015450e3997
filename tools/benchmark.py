#!/usr/bin/python3
"""whitted benchmark: renders a fixed set of scenes with whitted and with POV-Ray 3.7, in one run.

  tools/benchmark.py [--quick] [--only NAME[,NAME..]] [--skip-povray] [--sizes small,full]
                     [--full-scenes NAME[,NAME..]|all] [--skip-fixed] [--skip-equal-quality] [--skip-embree]
                     [--driver-files ICD.json|default [--label NAME]]... [--fresh-references]
                     [--build DIR] [--out DIR] [--skip-soft] [--skip-cold-start | --cold-start-only]

Two parts, both against POV-Ray measured in the same run (whitted and POV-Ray runs interleaved scene by scene,
so load from other jobs hits both):

Fixed samples per pixel. For every scene and size: BVH build time, render time, rays per second (primary, shadow
and secondary rays as counted by the shader, read from the record `whitted render -o X.png` writes beside the image
as X.json), peak memory, and POV-Ray's time on the same scene (exported by build/whitted_povray_export) at the same
resolution, samples per pixel, maximum depth and thread count, with the ratio. Sizes: small = 640x480 at 1 sample
per pixel, full = 1920x1080 at 16 (by default for the room only: --full-scenes). whitted runs `--aa uniform --spp N`;
POV-Ray `povray -D +WT2 +A0.0 +AM1 +R4` for 16 samples per pixel (method 1, non-adaptive supersampling, threshold 0:
every pixel whose corner samples differ at all takes a 4x4 grid) and `-A` for 1.

Embree anchor (the limit of this CPU): at every fixed-spp scene and size, build/whitted_embree_anchor
(tools/embree_anchor.cpp, built when Debian's libembree-dev is installed) traces the same camera rays and shadow
rays with Embree 3's rtcIntersect/rtcOccluded packets of 4, 8 and 16 on every core, the fastest reported; the JSON
holds whitted's rays per second as a fraction of Embree's (whitted_over_embree), from the same run. It traces
triangles, meshes, boxes, spheres and planes; a scene with cylinders or csg objects (the room) gets none.

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

Distribution ("soft"): scenes/soft.xml (two area lights, glossy metal, rough glass, a lens) at 320x180, time to a
clean image against POV-Ray's area_light + focal_blur render of its export (whose mirrors stay sharp: POV-Ray has no
glossy reflection). Each renderer's reference is its own at 256 samples (whitted `--aa uniform --spp 256`, POV-Ray
blur_samples 256, which also antialias); tries until within 45 dB of it: whitted its default render, then `--aa
uniform --spp` 32, 64, 128; POV-Ray blur_samples 8, 16, 32, 64, 128 (all traced), the area lights' jittered grids
as the scene's <shadow_samples>. `--skip-soft` leaves it out; `--only soft` runs it alone.

Window proxy: `whitted render room.xml --width 640 --height 360 --aa uniform --spp 1 --aov none`, 5 times per
driver, render time from the record (the live window's frame during a camera drag traces this much).

Warm start: `whitted render room.xml --width 8 --height 8 --aov none` after one untimed run, 7 times per driver into a
PPM and into a PNG (both written without loading OpenImageIO), whole-process wall time: the fixed cost of a render
on a machine that has run it before.

Cold start: README command 1's render, `whitted render scenes/room.xml` (default size, sampling and auxiliary
images), 5 times per driver with Mesa's shader cache and whitted's pipeline cache in a new empty folder, so that the
driver compiles the tracer as on a machine that never ran whitted; whole-process wall time, and after each the same
run again with the caches it filled (the difference is the compilation). `--cold-start-only` runs this part alone.

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
import os
import re
import shutil
import sys
import time

sys.dont_write_bytecode = True  # a run leaves no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # tools/bench, from any working directory
from bench import ROOT, fail  # noqa: E402 (after the path is set)
from bench.check import quick_check  # noqa: E402
from bench.parts import Bench, cold_start, drag_proxy, run_scenes, soft_quality, warm_start  # noqa: E402
from bench.plan import COLD_REPEATS, DRAG_REPEATS, STARTUP_REPEATS, Plan, equal_quality_sizes, scene_set, size_set  # noqa: E402
from bench.report import cpu_model, document, publish  # noqa: E402
from bench.runners import Driver  # noqa: E402


def parse_args():
    """The command line; a usage error exits with status 2."""
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="tiny scenes and sizes; checks the output, not times")
    parser.add_argument("--only", action="append", default=[], help="scene names (room, spheres100, spheres10k, "
                        "mesh1m; soft: the distribution part), comma-separated or repeated")
    parser.add_argument("--sizes", default="small,full", help="fixed-spp sizes: small (640x480 1 spp), full "
                        "(1920x1080 16 spp)")
    parser.add_argument("--full-scenes", default="room", help="scenes rendered at the full size [room]; all = every "
                          "scene")
    parser.add_argument("--skip-fixed", action="store_true", help="no fixed-spp part")
    parser.add_argument("--skip-equal-quality", action="store_true", help="no time-to-a-clean-image part")
    parser.add_argument("--skip-povray", action="store_true", help="do not run POV-Ray")
    parser.add_argument("--skip-embree", action="store_true", help="do not run the Embree anchor")
    parser.add_argument("--driver-files", action="append", default=[], help="Vulkan ICD JSON whitted runs on "
                        "(VK_DRIVER_FILES), or 'default'; repeatable [default]")
    parser.add_argument("--label", action="append", default=[], help="a name for each --driver-files, in order "
                        "[from the driver string, e.g. mesa-25.0.7]")
    parser.add_argument("--equal-quality-size", default=None, metavar="WxH", help="one size for every scene's "
                        "equal-quality part [room 1920x1080, the others 640x480]")
    parser.add_argument("--fresh-references", action="store_true", help="render the 64-sample references again")
    parser.add_argument("--skip-soft", action="store_true", help="no distribution part (scenes/soft.xml)")
    parser.add_argument("--skip-cold-start", action="store_true", help="no cold-start part")
    parser.add_argument("--cold-start-only", action="store_true", help="only the cold-start part (no POV-Ray, no "
                        "other part)")
    parser.add_argument("--build", default=os.path.join(ROOT, "build"), help="build folder [build]")
    parser.add_argument("--out", default=None, help="output folder [BUILD/benchmark]")
    try:
        return parser.parse_args()
    except SystemExit as e:
        sys.exit(2 if e.code else 0)


def plan_from(args):
    """The scenes and sizes the options choose; an unknown name or a bad size fails with status 2."""
    if args.cold_start_only:
        if args.skip_cold_start or args.only not in ([], ["room"]):
            fail("--cold-start-only: it renders the room only; no --skip-cold-start, no other --only")
        args.only, args.skip_fixed, args.skip_equal_quality, args.skip_povray = ["room"], True, True, True
        args.skip_embree = args.skip_soft = True
    scenes = scene_set(args.quick)
    sizes = size_set(args.quick)
    only = [n for item in args.only for n in item.split(",") if n]
    for n in only:
        if n not in scenes and n != "soft":
            fail(f"--only: unknown scene '{n}', expected one of {', '.join(scenes)}, soft")
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
    return Plan(quick=args.quick, scenes={n: v for n, v in scenes.items() if not only or n in only},
                sizes=[] if args.skip_fixed else [(s, sizes[s]) for s in chosen_sizes], full_scenes=full_scenes,
                equal_quality_sizes=sizes_eq, fixed=not args.skip_fixed, equal_quality=not args.skip_equal_quality,
                povray=not args.skip_povray, fresh_references=args.fresh_references,
                cold_start=not args.skip_cold_start and (not only or "room" in only),
                soft=not args.skip_soft and not args.skip_equal_quality and (not only or "soft" in only),
                soft_size=(64, 36) if args.quick else (320, 180))


def drivers_from(args):
    """One Driver per --driver-files, named by its --label where one is given."""
    if len(args.label) > max(1, len(args.driver_files)):
        fail("--label: more labels than --driver-files")
    files = args.driver_files or ["default"]
    labels = args.label + [None] * (len(files) - len(args.label))
    return [Driver(None if f == "default" else f, label) for f, label in zip(files, labels)]


def bench_from(args, plan, drivers, out):
    """The tools and the work folder (OUT/work, made here); a missing tool fails with status 1."""
    whitted = os.path.join(args.build, "whitted")
    exporter = os.path.join(args.build, "whitted_povray_export")
    for tool in [whitted] + ([exporter] if plan.povray else []):
        if not os.access(tool, os.X_OK):
            fail(f"{tool} not found: build first (cmake -S . -B {args.build} -DWHITTED_BUILD_TESTS=ON && "
                 f"cmake --build {args.build})", 1)
    if plan.povray and not shutil.which("povray"):
        fail("povray not found: run tools/install_deps.sh --all, or pass --skip-povray", 1)
    work = os.path.join(out, "work")
    os.makedirs(work, exist_ok=True)
    anchor = os.path.join(args.build, "whitted_embree_anchor")
    if args.skip_embree:
        anchor = None
    elif not os.access(anchor, os.X_OK):
        print(f"benchmark.py: {anchor} not built (needs libembree-dev and -DWHITTED_BUILD_TESTS=ON): no Embree anchor",
              file=sys.stderr)
        anchor = None
    return Bench(whitted=whitted, exporter=exporter if plan.povray else None, drivers=drivers, work=work,
                 anchor=anchor)


def probe_drivers(bench):
    """Learns every driver's name and label; two drivers with one label fail with status 2."""
    for d in bench.drivers:
        d.probe(bench.whitted, bench.work)
    if len({d.label for d in bench.drivers}) != len(bench.drivers):
        fail("two drivers have the same label: give each --driver-files its own --label")


def main():
    args = parse_args()
    plan = plan_from(args)
    drivers = drivers_from(args)
    out = args.out or os.path.join(args.build, "benchmark")
    bench = bench_from(args, plan, drivers, out)
    probe_drivers(bench)
    cpu = cpu_model()
    started = time.monotonic()
    print(f"CPU: {cpu[0]} ({os.cpu_count()} CPUs, {' '.join(cpu[1])}); drivers: "
          + "; ".join(f"{d.label} = {d.driver}" for d in drivers), flush=True)

    results, eq_results = run_scenes(bench, plan)
    soft = None
    if plan.soft:
        soft = soft_quality(bench, *plan.soft_size, plan.fresh_references)
    drag = None
    if plan.fixed and "room" in plan.scenes:
        drag = drag_proxy(bench, 1 if plan.quick else DRAG_REPEATS)
    warm = None
    if plan.fixed and "room" in plan.scenes:
        warm = warm_start(bench, 1 if plan.quick else STARTUP_REPEATS)
    cold = None
    if plan.cold_start:
        cold = cold_start(bench, 1 if plan.quick else COLD_REPEATS)
    elapsed = time.monotonic() - started

    documents = {d.label: document(d, drivers, cpu, plan, elapsed, results[d.label], eq_results[d.label],
                                   drag and drag[d.label], warm and warm[d.label],
                                   cold and cold[d.label], soft and soft[d.label]) for d in drivers}
    publish(documents, out, elapsed)
    if plan.quick:
        quick_check(documents, out, plan)


if __name__ == "__main__":
    main()
