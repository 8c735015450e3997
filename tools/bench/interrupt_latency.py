#!/usr/bin/python3
"""How soon a render answers Ctrl+C, and how often it reports progress.

One band of many submissions (scenes/three_diffuse_spheres.xml, 320x240,
1024 samples a pixel, uniform): the render that once ignored Ctrl+C until it
ended.

  Python: progress's calls (count, the longest gap between two) in a whole
  render; then the same render with SIGINT sent after 2 s, and the time
  from the signal to KeyboardInterrupt; then a render on the same renderer.
  CLI: `whitted render` on a pseudo-terminal: the longest gap between two
  redraws of its progress bar; then SIGINT after 2 s, the time to its exit,
  and whether it wrote anything.

  /usr/bin/python3 tools/bench/interrupt_latency.py [--build build] [--json FILE]
"""
import argparse
import json
import os
import pathlib
import pty
import select
import signal
import subprocess
import sys
import tempfile
import threading
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCENE = ROOT / "scenes" / "three_diffuse_spheres.xml"
RENDER = dict(width=320, height=240, aa="uniform", spp=1024)


def longest_gap(times):
    return max((b - a for a, b in zip(times, times[1:])), default=float("nan"))


def python_part(build):
    sys.path.insert(0, str(build / "python"))
    import whitted

    renderer = whitted.Renderer()
    scene = whitted.load(SCENE)
    calls = []
    start = time.perf_counter()
    renderer.render(scene, progress=lambda f: calls.append(time.perf_counter()), **RENDER)
    whole = time.perf_counter() - start
    gaps = [start] + calls

    sent = []

    def ctrl_c():
        sent.append(time.perf_counter())
        os.kill(os.getpid(), signal.SIGINT)

    timer = threading.Timer(2.0, ctrl_c)
    timer.start()
    try:
        renderer.render(scene, **RENDER)
        stopped = None
    except KeyboardInterrupt:
        stopped = time.perf_counter() - sent[0]
    timer.cancel()
    usable = renderer.render(scene, width=32, height=24).image.shape == (24, 32, 3)
    return {"render_s": whole, "progress_calls": len(calls), "longest_progress_gap_s": longest_gap(gaps),
            "sigint_to_keyboard_interrupt_s": stopped, "renderer_usable_after": usable}


def cli_part(build):
    out = pathlib.Path(tempfile.mkdtemp()) / "x.png"
    command = [str(build / "whitted"), "render", str(SCENE), "-o", str(out), "--width", "320", "--height", "240",
               "--aa", "uniform", "--spp", "1024", "--aov", "none"]

    def run(interrupt_after):
        # stderr on a terminal: the bar draws only there.
        leader, follower = pty.openpty()
        start = time.perf_counter()
        process = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=follower)
        os.close(follower)
        redraws, sent = [start], None
        while True:
            if interrupt_after is not None and sent is None and time.perf_counter() - start > interrupt_after:
                process.send_signal(signal.SIGINT)
                sent = time.perf_counter()
            ready, _, _ = select.select([leader], [], [], 0.01)
            if ready:
                try:
                    chunk = os.read(leader, 4096)
                except OSError:
                    chunk = b""
                if not chunk:
                    break
                redraws += [time.perf_counter()] * chunk.count(b"\r")
            elif process.poll() is not None:
                break
        process.wait()
        ended = time.perf_counter()
        os.close(leader)
        return process.returncode, redraws, sent, ended

    status, redraws, _, ended = run(None)
    whole = {"exit": status, "render_s": ended - redraws[0], "bar_redraws": len(redraws) - 1,
             "longest_bar_gap_s": longest_gap(redraws)}
    for f in out.parent.iterdir():
        f.unlink()
    status, _, sent, ended = run(2.0)
    left = sorted(p.name for p in out.parent.iterdir())
    return {"whole": whole, "sigint": {"exit": status, "sigint_to_exit_s": ended - sent, "files_left": left}}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=str(ROOT / "build"))
    parser.add_argument("--json")
    args = parser.parse_args()
    build = pathlib.Path(args.build).resolve()
    result = {"scene": SCENE.name, "render": RENDER, "python": python_part(build), "cli": cli_part(build)}
    text = json.dumps(result, indent=2)
    print(text)
    if args.json:
        pathlib.Path(args.json).write_text(text + "\n")


if __name__ == "__main__":
    main()
