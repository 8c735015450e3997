#!/usr/bin/python3
"""Tests of tools/farm.py (render farm on Dask): merged tiles and frames equal single renders, pixel for pixel.

Usage: farm_test.py --whitted PATH [--keep DIR]"""

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
import traceback

import numpy as np
import OpenImageIO as oiio

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FARM = os.path.join(ROOT, "tools", "farm.py")
SCENE = os.path.join(ROOT, "scenes", "three_diffuse_spheres.xml")
SCENE2 = os.path.join(ROOT, "scenes", "one_mirror.xml")
OPTS = ["--width", "160", "--height", "120", "--spp", "4"]

p = argparse.ArgumentParser()
p.add_argument("--whitted", required=True)
p.add_argument("--keep")
cli = p.parse_args()
WHITTED = os.path.abspath(cli.whitted)
work = cli.keep or tempfile.mkdtemp(prefix="farm-test-")
os.makedirs(work, exist_ok=True)


def run(cmd, env=None):
    e = dict(os.environ)
    e.update(env or {})
    t = time.monotonic()
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=e)
    return r.returncode, r.stderr.decode(errors="replace"), time.monotonic() - t


def farm(args, env=None):
    return run([sys.executable, FARM, "--whitted", WHITTED, "-q"] + args, env)


def single(scene, out, extra):
    rc, err, _ = run([WHITTED, "render", scene, "-o", out, "-q"] + extra)
    assert rc == 0, f"whitted render failed: {err}"


def pixels(path):
    inp = oiio.ImageInput.open(path)
    assert inp is not None, f"{path}: {oiio.geterror()}"
    s = inp.spec()
    px = inp.read_image(inp.spec().format)  # native type: exact
    inp.close()
    return (s.width, s.height, s.nchannels, s.x, s.y, s.full_width, s.full_height), px


def same(a, b):
    sa, pa = pixels(a)
    sb, pb = pixels(b)
    assert sa == sb, f"{a} vs {b}: spec {sa} != {sb}"
    assert pa.dtype == pb.dtype, f"{a} vs {b}: type {pa.dtype} != {pb.dtype}"
    assert np.array_equal(pa.view(np.uint8), pb.view(np.uint8)), \
        f"{a} vs {b}: {int(np.count_nonzero(pa != pb))} values differ"


def files_in(d):
    return sorted(os.listdir(d)) if os.path.isdir(d) else []


results = []


def case(fn):
    t = time.monotonic()
    try:
        fn()
        results.append(True)
        print(f"PASS {fn.__name__} ({time.monotonic() - t:.1f} s)", flush=True)
    except Exception:
        results.append(False)
        print(f"FAIL {fn.__name__} ({time.monotonic() - t:.1f} s)", flush=True)
        traceback.print_exc()


def tiles_png():
    """(a) 2 local workers, 48-pixel tiles, PNG with auxiliary images (8-bit depth encoded at the merge)."""
    d = os.path.join(work, "png")
    os.makedirs(d, exist_ok=True)
    extra = OPTS + ["--aov", "diffuse,depth,samples,normal"]
    single(SCENE, os.path.join(d, "ref.png"), extra)
    rc, err, _ = farm([SCENE, "-o", os.path.join(d, "farm.png"), "--local-workers", "2", "--tile-size", "48"] + extra)
    assert rc == 0, err
    for suffix in ["", ".diffuse", ".depth", ".samples", ".normal"]:
        same(os.path.join(d, "ref" + suffix + ".png"), os.path.join(d, "farm" + suffix + ".png"))
    assert os.path.isfile(os.path.join(d, "farm.json"))
    assert not [f for f in files_in(d) if f.startswith(".")], files_in(d)


def tiles_exr_killed_worker():
    """(a, b) EXR with auxiliary images; the first task attempt kills its worker, the retry recovers."""
    d = os.path.join(work, "exr")
    os.makedirs(d, exist_ok=True)
    marker = os.path.join(d, "killed")
    extra = OPTS + ["--aov", "depth,specular"]
    single(SCENE, os.path.join(d, "ref.exr"), extra)
    rc, err, _ = farm([SCENE, "-o", os.path.join(d, "farm.exr"), "--local-workers", "2", "--tile-size", "64"] + extra,
                      {"WHITTED_FARM_TEST_KILL": marker})
    assert rc == 0, err
    assert os.path.isfile(marker), "the test hook did not kill a worker"
    for suffix in ["", ".depth", ".specular"]:
        same(os.path.join(d, "ref" + suffix + ".exr"), os.path.join(d, "farm" + suffix + ".exr"))


def split_aovs():
    """Reflection split by depth (--aov-bounces) merges like every other auxiliary image, PNG and EXR."""
    d = os.path.join(work, "split")
    os.makedirs(d, exist_ok=True)
    extra = OPTS + ["--aov", "reflection,reflection.1,reflection.2,transmission.2", "--aov-bounces", "2"]
    for ext in (".png", ".exr"):
        single(SCENE2, os.path.join(d, "ref" + ext), extra)
        rc, err, _ = farm([SCENE2, "-o", os.path.join(d, "farm" + ext), "--local-workers", "2", "--tile-size", "64"]
                          + extra)
        assert rc == 0, err
        for suffix in ["", ".reflection", ".reflection.1", ".reflection.2", ".transmission.2"]:
            same(os.path.join(d, "ref" + suffix + ext), os.path.join(d, "farm" + suffix + ext))


def masks():
    """The object and material masks merge unblended: EXR UINT channels and PNG hash colours equal a single render's,
    with adaptive anti-aliasing (the default) and tiles that cut through objects."""
    d = os.path.join(work, "masks")
    os.makedirs(d, exist_ok=True)
    scene = os.path.join(ROOT, "scenes", "showcase.xml")
    extra = ["--width", "160", "--height", "90", "--aov", "object_id,material_id"]
    for ext in (".png", ".exr"):
        single(scene, os.path.join(d, "ref" + ext), extra)
        rc, err, _ = farm([scene, "-o", os.path.join(d, "farm" + ext), "--local-workers", "2", "--tile-size", "40"]
                          + extra)
        assert rc == 0, err
        for suffix in ["", ".object_id", ".material_id"]:
            same(os.path.join(d, "ref" + suffix + ext), os.path.join(d, "farm" + suffix + ext))
    _, ids = pixels(os.path.join(d, "farm.object_id.exr"))
    assert ids.dtype == np.uint32, ids.dtype
    assert set(np.unique(ids)) <= set(range(6)) | {0xFFFFFFFF}, np.unique(ids)


def frames():
    """(c) two scenes, -o DIR/%04d.png: one image (and its auxiliary images) per frame, equal to single renders."""
    d = os.path.join(work, "frames")
    os.makedirs(d, exist_ok=True)
    extra = OPTS + ["--aov", "depth"]
    rc, err, _ = farm([SCENE, SCENE2, "-o", os.path.join(d, "%04d.png"), "--local-workers", "2"] + extra)
    assert rc == 0, err
    for i, s in enumerate([SCENE, SCENE2]):
        ref = os.path.join(work, f"frame_ref{i}.png")
        single(s, ref, extra)
        same(ref, os.path.join(d, f"{i:04d}.png"))
        same(aux(ref, "depth"), os.path.join(d, f"{i:04d}.depth.png"))
        assert os.path.isfile(os.path.join(d, f"{i:04d}.json"))


def aux(path, name):
    stem, ext = os.path.splitext(path)
    return f"{stem}.{name}{ext}"


def refusals():
    """(d, e) a missing scene in a frame list, bad tile sizes and outputs: status 2, a clear message, nothing written."""
    d = os.path.join(work, "refused")
    os.makedirs(d, exist_ok=True)
    missing = os.path.join(d, "no_such_scene.xml")
    checks = [
        ([SCENE, missing, "-o", os.path.join(d, "%04d.png")], "no_such_scene.xml: no such scene file"),
        ([SCENE, "-o", os.path.join(d, "a.png"), "--tile-size", "0"], "--tile-size"),
        ([SCENE, "-o", os.path.join(d, "a.png"), "--tile-size", "abc"], "--tile-size"),
        ([SCENE, "-o", os.path.join(d, "a.png"), "--width", "-5"], "--width"),
        ([SCENE, SCENE2, "-o", os.path.join(d, "same.png")], "pattern"),
        ([SCENE, "-o", os.path.join(d, "a.tiff")], ".png or .exr"),
        ([SCENE, "-o", os.path.join(d, "a.png"), "--aov", "bogus"], "bogus"),
        ([SCENE, "-o", os.path.join(d, "a.png"), "--aov", "reflection.3", "--aov-bounces", "2"], "reflection.3"),
        ([SCENE, "-o", os.path.join(d, "a.png"), "--aov-bounces", "17"], "--aov-bounces must be in 0..16"),
    ]
    for args, message in checks:
        rc, err, _ = farm(args + ["--local-workers", "1"])
        assert rc == 2, f"{args}: status {rc}, expected 2: {err}"
        assert message in err, f"{args}: message lacks '{message}': {err}"
    assert files_in(d) == [], files_in(d)


case(refusals)
case(tiles_png)
case(tiles_exr_killed_worker)
case(frames)
case(split_aovs)
case(masks)

passed = sum(results)
failed = len(results) - passed
print(f"{passed} passed, {failed} failed")
if not cli.keep and failed == 0:
    shutil.rmtree(work, ignore_errors=True)
sys.exit(1 if failed else 0)
