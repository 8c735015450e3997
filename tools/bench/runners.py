"""Whole processes, timed: whitted on a Vulkan driver, the POV-Ray exporter and POV-Ray, the scene generator.

Each runner fails the benchmark when its process fails, and hands what the process left to measures.py."""
import hashlib
import json
import os
import re
import subprocess
import sys
import time

from . import ROOT, fail
from .measures import povray_measures, read_record, whitted_measures
from .plan import MAX_DEPTH, ROOM, THREADS


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
    """The SHA-256 of `extra` followed by the file's bytes, in hex."""
    digest = hashlib.sha256(extra.encode())
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def probe_render(whitted, scene, image, env):
    """An 8x6 render without AOVs, to learn whether this build and driver render the scene: (status, output)."""
    status, output, _, _ = run([whitted, "render", scene, "-o", image, "--width", "8", "--height", "6",
                                "--aov", "none", "-q"], env=env)
    return status, output


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
        status, output = probe_render(whitted, ROOM, image, self.env)
        if status != 0:
            fail(f"whitted does not render with driver {self.files or 'default'} (exit {status}):\n{output}", 1)
        record = read_record(image)
        self.driver = record["device"].get("driver", "?")
        self.device = record["device"]["name"]
        if not self.label:
            match = re.search(r"Mesa (\d+\.\d+(?:\.\d+)?)", self.driver)
            self.label = ("mesa-" + match.group(1)) if match else re.sub(r"[^A-Za-z0-9.]+", "-", self.driver)[:40]


GENERATOR = os.path.join(ROOT, "tools", "generate_scenes.py")


def generate(kind, count, path, *flags):
    """tools/generate_scenes.py KIND COUNT PATH [FLAGS]."""
    status, output, _, _ = run([sys.executable, GENERATOR, kind, str(count), path, *flags])
    if status != 0:
        fail(f"generate_scenes.py {' '.join([kind, *flags])} failed:\n{output}", 1)


def make_scene(name, how, arg, work, whitted, env):
    """Returns (scene path, note); generated scenes go into `work`, kept while the generator and arguments are the
    same."""
    if how == "file":
        return arg, ""
    path = os.path.join(work, name + ".xml")
    stamp_path = path + ".stamp"
    stamp = sha256_file(GENERATOR, f"{how} {arg}")
    try:
        with open(stamp_path, encoding="utf-8") as f:
            old_stamp, old_note = f.read().split("\n", 1)
        if old_stamp == stamp and os.path.exists(path):
            return path, old_note
    except (OSError, ValueError):
        pass
    generate(how, arg, path)
    note = ""
    if how == "mesh":
        # A mesh: an OBJ file if this build loads <file>, else inline polygons.
        probe, probe_output = probe_render(whitted, path, os.path.join(work, "probe.png"), env)
        note = "OBJ file"
        if probe != 0:
            print(f"benchmark.py: {name}: this build does not load <file> meshes "
                  f"({probe_output.strip().splitlines()[-1]}); using inline <polygons>", file=sys.stderr)
            generate(how, arg, path, "--inline")
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
    return whitted_measures(read_record(out_png), " ".join(command[5:]), " ".join(sampling) or "default", wall, rss)


def run_anchor(anchor, scene, width, height, spp):
    """tools/embree_anchor.cpp on a scene: Embree tracing whitted's camera and shadow rays of the same image on every
    core. Returns its JSON with the process's wall time; its "supported" is false for shapes it does not trace."""
    command = [anchor, scene, "--width", str(width), "--height", str(height), "--spp", str(spp)]
    status, output, wall, _ = run(command)
    if status != 0:
        fail(f"whitted_embree_anchor failed on {scene} (exit {status}):\n{output}", 1)
    try:
        result = json.loads(output)
    except ValueError as e:
        fail(f"whitted_embree_anchor printed no JSON on {scene} ({e}):\n{output[-2000:]}", 1)
    result["wall_s"] = wall
    result.pop("scene", None)
    return result


def export_pov(exporter, scene, work, tag, width, height, blur_samples=None):
    """Exports a scene to WORK/TAG.pov for POV-Ray at the given size and whitted's maximum depth (with a lens:
    focal_blur's blur_samples, else the exporter's default)."""
    pov = os.path.join(work, tag + ".pov")
    blur = ["--blur-samples", str(blur_samples)] if blur_samples else []
    status, output, _, _ = run([exporter, scene, pov, "--width", str(width), "--height", str(height),
                                "--max-depth", str(MAX_DEPTH), *blur])
    if status != 0:
        fail(f"whitted_povray_export failed on {scene} (exit {status}):\n{output}", 1)
    return pov


def povray_version():
    """POV-Ray's version line, e.g. "POV-Ray 3.7.0.10.unofficial", or "?"."""
    version = run(["povray", "--version"])[1].strip().splitlines()
    return next((line for line in version if line.startswith("POV-Ray")), "?")


def run_povray(pov, image, width, height, antialias):
    """One whole POV-Ray process on an exported scene."""
    command = ["povray", "-D", f"+WT{THREADS}", f"+W{width}", f"+H{height}", *antialias, "+FN",
               f"+I{pov}", f"+O{image}"]
    if os.path.exists(image):
        os.remove(image)
    status, output, wall, rss = run(command, cwd=os.path.dirname(pov))
    if status != 0 or not os.path.exists(image):
        fail(f"povray failed on {pov} (exit {status}):\n{output[-3000:]}", 1)
    return povray_measures(output, " ".join(a for a in command[1:] if not a.startswith(("+I", "+O"))), wall, rss)
