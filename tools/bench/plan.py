"""What the benchmark measures: the scenes and sizes, whitted's and POV-Ray's sampling settings, the quality
target, and the Plan that the command line chooses from them."""
import dataclasses
import os

from . import ROOT

ROOM = os.path.join(ROOT, "scenes", "room.xml")
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
STARTUP_SIZE = (8, 8)  # the warm-start part: the fixed cost of a render
STARTUP_REPEATS = 7
COLD_REPEATS = 5  # the cold-start part: README command 1's render with empty caches
# The distribution part (scenes/soft.xml: area lights, gloss, a lens): each renderer's own reference at
# SOFT_REFERENCE_SAMPLES, then tries in order until within SOFT_TARGET_DB of it. whitted: its default render,
# then uniform sample counts; POV-Ray: focal_blur blur_samples (all traced; they also antialias), the area
# lights' jittered grids as the scene's <shadow_samples>.
SOFT = os.path.join(ROOT, "scenes", "soft.xml")
SOFT_TARGET_DB = 45.0  # scenes/README.md "Clean images": the default render of a soft shadow reaches it
SOFT_REFERENCE_SAMPLES = 256
SOFT_WHITTED_TRIES = [[], ["--aa", "uniform", "--spp", "32"], ["--aa", "uniform", "--spp", "64"],
                      ["--aa", "uniform", "--spp", "128"]]
SOFT_POVRAY_BLUR_SAMPLES = [8, 16, 32, 64, 128]


@dataclasses.dataclass
class Plan:
    """What one run renders, as the command line chose it."""
    quick: bool
    scenes: dict  # name -> (how to make it, arguments), in the benchmark's order, only those --only names
    sizes: list  # the fixed-spp sizes in --sizes order: (name, (width, height, spp)); empty with --skip-fixed
    full_scenes: list  # the scenes rendered at the full size
    equal_quality_sizes: dict  # scene name -> (width, height)
    fixed: bool  # the fixed-spp part runs (and with it the drag proxy, when the room is among the scenes)
    equal_quality: bool
    povray: bool
    fresh_references: bool
    cold_start: bool = True  # the cold-start part runs (when the room is among the scenes)
    soft: bool = True  # the distribution part runs (scenes/soft.xml at soft_size)
    soft_size: tuple = (320, 180)


def scene_set(quick):
    """name -> (how to make it, arguments). Quick: the same kinds of scenes, tiny."""
    if quick:
        return {"room": ("file", ROOM), "spheres100": ("spheres", 8), "spheres10k": ("spheres", 64),
                "mesh1m": ("mesh", 2000)}
    return {"room": ("file", ROOM), "spheres100": ("spheres", 100), "spheres10k": ("spheres", 10000),
            "mesh1m": ("mesh", 1000000)}


def size_set(quick):
    """size name -> (width, height, samples per pixel) of the fixed-spp part."""
    if quick:
        return {"small": (64, 48, 1), "full": (96, 54, 4)}
    return {"small": (640, 480, 1), "full": (1920, 1080, 16)}


def equal_quality_sizes(quick):
    """scene name -> (width, height) of the equal-quality part."""
    if quick:
        return {"room": (96, 54), "spheres100": (64, 48), "spheres10k": (64, 48), "mesh1m": (64, 48)}
    return {"room": (1920, 1080), "spheres100": (640, 480), "spheres10k": (640, 480), "mesh1m": (640, 480)}


def povray_fixed_antialias(spp):
    """POV-Ray's options for `spp` uniform samples per pixel: a non-adaptive grid, or none for 1."""
    return ["+A0.0", "+AM1", "+R4"] if spp == 16 else (
        ["+A0.0", "+AM1", f"+R{max(2, round(spp ** 0.5))}"] if spp > 1 else ["-A"])
