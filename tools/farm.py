#!/usr/bin/python3
"""Render farm for whitted on Dask distributed.

One scene is split into square regions (--tile-size), each rendered by
`whitted render --region` on a Dask worker; the tiles come back as file bytes
in the task results (no shared folder for outputs) and are pasted together,
giving the same pixels as a single render. Several scenes are one task per
frame, written through a printf-style pattern (-o frames/%04d.png).

Scene files (and the meshes they name) must be readable at the same absolute
path on every worker; `whitted` must be on each worker's PATH (or --whitted).
See tools/README.md, "Render farm".
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

PASS_THROUGH = ["width", "height", "spp", "max-depth", "aov", "aov-bounces", "aa", "aa-threshold"]
AOV_NAMES = ["ambient", "diffuse", "specular", "reflection", "transmission", "ambient_coef", "diffuse_coef",
             "specular_coef", "reflection_coef", "transmission_coef", "ior", "depth", "normal", "samples",
             "object_id", "material_id"]
# The masks: ids in EXR files are UINT channels, carried as they are (tiles are pasted, never blended).
ID_AOVS = {"object_id", "material_id"}
COLOUR_AOVS = {"ambient", "diffuse", "specular", "reflection", "transmission"}


def split_aov_names(bounces):
    """The images of --aov-bounces B, in the order whitted's --aov all writes them (after "transmission")."""
    return [f"{part}.{k}" for part in ("reflection", "transmission") for k in range(1, (bounces or 0) + 1)]


def is_colour(name):
    return name in COLOUR_AOVS or name.split(".")[0] in ("reflection", "transmission")


class Refused(Exception):
    """Bad input: exit status 2, before any work where possible."""


# ---------------------------------------------------------------------------
# Worker side (these functions are shipped to the workers by cloudpickle)

def render_task(whitted, scene, args, name, region, kill_marker):
    """Runs one `whitted render` in a private temporary folder; returns the files it wrote as bytes.

    A bad-input failure (status 2) comes back as a result so that it is not retried; any other
    failure raises, and Dask retries the task (elsewhere when the worker died)."""
    if kill_marker:  # test hook: the first attempt to reach here kills its worker process
        try:
            os.close(os.open(kill_marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY))
            os._exit(17)
        except FileExistsError:
            pass
    folder = tempfile.mkdtemp(prefix="whitted-farm-")
    try:
        cmd = [whitted, "render", scene, "-o", os.path.join(folder, name), "-q"] + list(args)
        if region:
            cmd += ["--region", ",".join(map(str, region))]
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        stderr = p.stderr.decode(errors="replace")
        if p.returncode == 2:
            return {"status": 2, "stderr": stderr, "files": {}}
        if p.returncode != 0:
            raise RuntimeError(f"whitted exited with status {p.returncode}: {stderr.strip()}")
        files = {}
        for f in os.listdir(folder):
            with open(os.path.join(folder, f), "rb") as fh:
                files[f] = fh.read()
        return {"status": 0, "stderr": stderr, "files": files}
    finally:
        shutil.rmtree(folder, ignore_errors=True)


# ---------------------------------------------------------------------------
# Client side

def scene_size(scene, width, height):
    """The image size: --width/--height, else the scene's <camera><width>/<height>, else 640x480."""
    if width and height:
        return width, height
    w, h = 640, 480
    try:
        cam = ET.parse(scene).getroot().find("camera")
    except (ET.ParseError, OSError) as e:
        raise Refused(f"{scene}: cannot read the scene: {e}")
    if cam is not None:
        for key in ("width", "height"):
            e = cam.find(key)
            text = e.text if e is not None else cam.get(key)
            if text is not None:
                try:
                    v = int(text.strip())
                except ValueError:
                    raise Refused(f"{scene}: <camera><{key}> is not an integer: '{text.strip()}'")
                if key == "width":
                    w = v
                else:
                    h = v
    return width or w, height or h


def aux_name(path, aov):
    stem, ext = os.path.splitext(path)
    return f"{stem}.{aov}{ext}"


def positive_int(text):
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got '{text}'")
    if v <= 0:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got '{text}'")
    return v


def parse_args(argv):
    p = argparse.ArgumentParser(prog="farm.py", description="Render whitted scenes on a Dask cluster.")
    p.add_argument("scenes", nargs="+", metavar="SCENE")
    p.add_argument("-o", "--output", required=True, help="OUT.png|OUT.exr; with several scenes a pattern "
                   "such as frames/%%04d.png (frame index = position in the list + --first-frame)")
    p.add_argument("--tile-size", type=positive_int, default=256, help="tile edge in pixels [256]")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--scheduler", help="address of a running Dask scheduler, e.g. tcp://HOST:8786")
    g.add_argument("--local-workers", type=positive_int, help="start a local cluster of N worker processes "
                   "(default when no --scheduler: the number of CPUs)")
    p.add_argument("--whitted", help="path of the whitted executable on the workers [whitted on PATH]")
    p.add_argument("--first-frame", type=int, default=0, help="index of the first frame [0]")
    p.add_argument("--retries", type=int, default=3, help="retries of a failed task [3]")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress counter")
    p.add_argument("--width", type=positive_int)
    p.add_argument("--height", type=positive_int)
    p.add_argument("--spp", type=positive_int)
    p.add_argument("--max-depth", type=int)
    p.add_argument("--aov")
    p.add_argument("--aov-bounces", type=int)
    p.add_argument("--aa", choices=["adaptive", "uniform"])
    p.add_argument("--aa-threshold", type=float)
    return p.parse_args(argv)


def render_args(a):
    out = []
    for opt in PASS_THROUGH:
        v = getattr(a, opt.replace("-", "_"))
        if v is not None:
            out += ["--" + opt, str(v)]
    return out


def aov_list(text, bounces=None):
    split = split_aov_names(bounces)
    if text is None or text in ("", "none"):
        return []
    if text == "all":
        i = AOV_NAMES.index("transmission") + 1
        return AOV_NAMES[:i] + split + AOV_NAMES[i:]
    names = []
    for n in text.split(","):
        if n not in AOV_NAMES and n not in split:
            known = ", ".join(AOV_NAMES + split)
            raise Refused(f"--aov: unknown auxiliary image '{n}' (known: {known}, all, none; "
                          "reflection.K and transmission.K need --aov-bounces K or more)")
        if n not in names:
            names.append(n)
    return names


def plan(a):
    """Checks everything that can be checked before any work; returns the job description."""
    ext = os.path.splitext(a.output)[1].lower()
    if ext not in (".png", ".exr"):
        raise Refused(f"{a.output}: the output must be a .png or .exr file")
    scenes = []
    for s in a.scenes:
        if not os.path.isfile(s):
            raise Refused(f"{s}: no such scene file")
        scenes.append(os.path.abspath(s))
    frames = len(scenes) > 1 or "%" in a.output
    outputs = []
    if frames:
        try:
            outputs = [a.output % (a.first_frame + i) for i in range(len(scenes))]
        except (TypeError, ValueError):
            raise Refused(f"{a.output}: several scenes need an output pattern with one integer field, "
                          "e.g. frames/%04d.png")
        if len(set(outputs)) != len(outputs):
            raise Refused(f"{a.output}: the pattern gives the same name to several frames")
    else:
        outputs = [a.output]
    for o in outputs:
        d = os.path.dirname(o) or "."
        if os.path.exists(d) and not os.path.isdir(d):
            raise Refused(f"{o}: {d} is not a folder")
    if a.aa_threshold is not None and not a.aa_threshold >= 0:
        raise Refused("--aa-threshold must be >= 0")
    if a.max_depth is not None and a.max_depth < 0:
        raise Refused("--max-depth must be >= 0")
    if a.aov_bounces is not None and not 0 <= a.aov_bounces <= 16:
        raise Refused("--aov-bounces must be in 0..16")
    aovs = aov_list(a.aov, a.aov_bounces)
    whitted = a.whitted or "whitted"
    if a.scheduler is None:  # local workers: the executable must be here
        found = shutil.which(whitted)
        if not found:
            raise Refused(f"{whitted}: whitted executable not found (give --whitted PATH)")
        whitted = os.path.abspath(found)
    return {"ext": ext, "scenes": scenes, "outputs": outputs, "frames": frames, "aovs": aovs, "whitted": whitted}


def write_atomically(files):
    """files: [(path, writer(temp_path))]. Writes every temporary first, then renames them all."""
    temps = []
    try:
        for path, writer in files:
            d = os.path.dirname(path) or "."
            os.makedirs(d, exist_ok=True)
            stem, ext = os.path.splitext(os.path.basename(path))
            tmp = os.path.join(d, f".{stem}.farm-{os.getpid()}{ext}")
            temps.append((tmp, path))
            writer(tmp)
        for tmp, path in temps:
            os.replace(tmp, path)
        temps = []
    finally:
        for tmp, _ in temps:
            try:
                os.remove(tmp)
            except OSError:
                pass


def bytes_writer(data):
    def w(tmp):
        with open(tmp, "wb") as f:
            f.write(data)
    return w


def image_writer(pixels, colour, full=None):
    """Writes a numpy array (H, W, C) uint8 or float32 through OpenImageIO like whitted does."""
    import OpenImageIO as oiio

    def w(tmp):
        h, wd, c = pixels.shape
        is_float = pixels.dtype.kind == "f"
        is_uint32 = pixels.dtype == "uint32"
        spec = oiio.ImageSpec(wd, h, c, "float" if is_float else "uint" if is_uint32 else "uint8")
        if not is_float and not is_uint32 and colour:
            spec.attribute("oiio:ColorSpace", "sRGB")
        if is_float or is_uint32:
            spec.attribute("compression", "zip")
        out = oiio.ImageOutput.create(tmp)
        if out is None or not out.open(tmp, spec) or not out.write_image(pixels) or not out.close():
            raise RuntimeError(f"{tmp}: cannot write image: {oiio.geterror()}")
    return w


def decode(data, suffix, fmt):
    """Decodes image bytes: (pixels (h, w, c), data-window x, y)."""
    import OpenImageIO as oiio
    with tempfile.NamedTemporaryFile(suffix=suffix) as f:
        f.write(data)
        f.flush()
        inp = oiio.ImageInput.open(f.name)
        if inp is None:
            raise RuntimeError(f"cannot read a tile: {oiio.geterror()}")
        spec = inp.spec()
        px = inp.read_image(fmt)
        inp.close()
    return px.reshape(spec.height, spec.width, spec.nchannels), spec.x, spec.y


def encode_depth8(depth):
    """8-bit depth exactly as whitted writes it: m / (m + d) with m the median hit distance
    (rank count/2 of the sorted distances), 0 where nothing was hit; lround(clamp(v) * 255)."""
    import numpy as np
    d = depth.astype(np.float32)
    hits = np.sort(d[d > 0])
    m = hits[len(hits) // 2] if len(hits) else np.float32(0)
    with np.errstate(divide="ignore", invalid="ignore"):
        v = np.where(d > 0, m / (m + d), np.float32(0)).astype(np.float32)
    v = np.clip(v, np.float32(0), np.float32(1)).astype(np.float32) * np.float32(255)
    return np.floor(v.astype(np.float64) + 0.5).astype(np.uint8)


class Progress:
    def __init__(self, total, quiet, what):
        self.total, self.done, self.quiet, self.what = total, 0, quiet, what
        self.start = time.monotonic()
        self.show()

    def show(self):
        if not self.quiet:
            end = "\n" if self.done == self.total else ""
            sys.stderr.write(f"\rfarm: {self.done}/{self.total} {self.what} "
                             f"({time.monotonic() - self.start:.1f} s){end}")
            sys.stderr.flush()

    def step(self):
        self.done += 1
        self.show()


def gather(client, futures, quiet, what):
    from distributed import as_completed
    results = {}
    index = {f.key: i for i, f in enumerate(futures)}
    progress = Progress(len(futures), quiet, what)
    for fut in as_completed(futures):
        r = fut.result()  # raises when the task failed after its retries
        if r["status"] != 0:
            for f in futures:
                f.cancel()
            raise Refused(r["stderr"].strip() or "whitted refused the render")
        results[index[fut.key]] = r
        progress.step()
    return [results[i] for i in range(len(futures))]


def run_frames(client, job, args, a):
    ext = job["ext"]
    futures = [client.submit(render_task, job["whitted"], s, args, "frame" + ext, None, os.environ.get(
        "WHITTED_FARM_TEST_KILL"), retries=a.retries, pure=False) for s in job["scenes"]]
    results = gather(client, futures, a.quiet, "frames")
    files = []
    for out, r in zip(job["outputs"], results):
        stem = os.path.splitext(out)[0]
        for name, data in r["files"].items():
            files.append((stem + name[len("frame"):], bytes_writer(data)))
    write_atomically(files)


def run_tiles(client, job, args, a):
    import numpy as np
    scene, out, ext = job["scenes"][0], job["outputs"][0], job["ext"]
    width, height = scene_size(scene, a.width, a.height)
    size_args = ["--width", str(width), "--height", str(height)]
    args = [x for i, x in enumerate(args) if x not in ("--width", "--height") and
            (i == 0 or args[i - 1] not in ("--width", "--height"))] + size_args
    aovs = job["aovs"]
    # 8-bit depth needs the whole image's median: its tiles are rendered as EXR and encoded here.
    depth8 = ext == ".png" and "depth" in aovs
    main_aovs = [n for n in aovs if not (depth8 and n == "depth")]
    main_args = [x for x in args]
    if a.aov is not None:
        i = main_args.index("--aov")
        main_args[i + 1] = ",".join(main_aovs) if main_aovs else "none"
    t = a.tile_size
    regions = [(x, y, min(x + t, width), min(y + t, height)) for y in range(0, height, t) for x in range(0, width, t)]
    kill = os.environ.get("WHITTED_FARM_TEST_KILL")
    futures = []
    for r in regions:
        futures.append(client.submit(render_task, job["whitted"], scene, main_args, "tile" + ext, r, kill,
                                     retries=a.retries, pure=False))
        if depth8:
            depth_args = [x for x in args]
            depth_args[depth_args.index("--aov") + 1] = "depth"
            futures.append(client.submit(render_task, job["whitted"], scene, depth_args,
                                         "depth.exr", r, None, retries=a.retries, pure=False))
    results = gather(client, futures, a.quiet, "tiles")
    per_tile = 2 if depth8 else 1

    fmt = "float" if ext == ".exr" else "uint8"
    dtype = np.float32 if ext == ".exr" else np.uint8
    images = {}  # file name in the tile folder -> (output path, colour, array)
    images["tile" + ext] = (out, True, None)
    for n in main_aovs:
        images["tile." + n + ext] = (aux_name(out, n), is_colour(n), None)
    depth = np.zeros((height, width), np.float32) if depth8 else None
    records = []
    for k, r in enumerate(regions):
        x0, y0, x1, y1 = r
        res = results[k * per_tile]
        for name, (path, colour, arr) in list(images.items()):
            ids = ext == ".exr" and name.split(".")[1] in ID_AOVS
            px, _, _ = decode(res["files"][name], ext, "uint" if ids else fmt)
            if arr is None:
                arr = np.zeros((height, width, px.shape[2]), np.uint32 if ids else dtype)
                images[name] = (path, colour, arr)
            arr[y0:y1, x0:x1, :] = px
        if "tile.json" in res["files"]:
            records.append(json.loads(res["files"]["tile.json"]))
        if depth8:
            px, _, _ = decode(results[k * per_tile + 1]["files"]["depth.depth.exr"], ".exr", "float")
            depth[y0:y1, x0:x1] = px[:, :, 0]
    files = [(path, image_writer(arr, colour)) for path, colour, arr in images.values()]
    if depth8:
        files.append((aux_name(out, "depth"), image_writer(encode_depth8(depth)[:, :, None], False)))
    record = {"farm": {"scene": scene, "width": width, "height": height, "tile_size": t, "tiles": len(regions),
                       "command": [job["whitted"], "render", scene] + args},
              "tiles": records}
    files.append((os.path.splitext(out)[0] + ".json", bytes_writer((json.dumps(record, indent=2) + "\n").encode())))
    write_atomically(files)


def main(argv):
    try:
        a = parse_args(argv)
    except SystemExit as e:  # argparse: status 2 for bad arguments
        return e.code
    try:
        job = plan(a)
        if not job["frames"]:
            scene_size(job["scenes"][0], a.width, a.height)  # refuse an unreadable size before starting
        from distributed import Client, LocalCluster
        args = render_args(a)
        if a.scheduler:
            client, cluster = Client(a.scheduler), None
        else:
            cluster = LocalCluster(n_workers=a.local_workers or os.cpu_count() or 1, threads_per_worker=1,
                                   processes=True, dashboard_address=None)
            client = Client(cluster)
        try:
            if job["frames"]:
                run_frames(client, job, args, a)
            else:
                run_tiles(client, job, args, a)
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
    except Refused as e:
        print(f"farm.py: {e}", file=sys.stderr)
        return 2
    except Exception as e:  # a task failed after its retries, or a merge failed
        print(f"farm.py: {type(e).__name__}: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
