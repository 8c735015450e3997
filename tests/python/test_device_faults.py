# A lost device and exhausted memory (tests/README.md "Device loss and exhaustion"): test
# builds fail the Nth queue submission or memory allocation on request
# (WHITTED_INJECT_FAULT, host/vk/device_events.h). Every submission and every allocation
# of a small render is failed in turn, with memory as lavapipe has it and as on a discrete
# GPU (WHITTED_DISCRETE_MEMORY=1: staging copies, more of both): the command line says
# which device, scene and step, exits 1 and leaves no file. In Python the first, a middle
# and the last of a call's raise whitted.DeviceError, and the renderer renders again.
import os
import re
import subprocess

import pytest
import whitted

from conftest import EXECUTABLE, ROOT

SCENE = ROOT / "scenes" / "room.xml"
SMALL = ("--width", "16", "--height", "12", "--spp", "2", "-q")
DEVICE = r"device '[^']+'"
LOST = DEVICE + r" was lost \(VK_ERROR_DEVICE_LOST\) at queue submission {n}, [a-z][^;]*"
OUT_OF_MEMORY = (DEVICE + r" is out of device memory \(VK_ERROR_OUT_OF_DEVICE_MEMORY\) at memory allocation {n} "
                 r"\(\d+ bytes, \d+ MiB, of [a-z -]+ memory\), [a-z][^;]*")
FAULTS = {"submit": LOST, "allocate": OUT_OF_MEMORY}
MODES = {"unified": "0", "discrete": "1"}

pytestmark = pytest.mark.skipif(not whitted._test_hooks, reason="a product build: no fault injection")


def run(args, fault, mode, cwd=None):
    # Without the validation layer: the injected failure is the subject, and a run takes a
    # third of the time.
    env = dict(os.environ, WHITTED_INJECT_FAULT=fault, WHITTED_DISCRETE_MEMORY=mode, WHITTED_VALIDATION="0")
    return subprocess.run([str(EXECUTABLE), *map(str, args)], capture_output=True, text=True, env=env, cwd=cwd,
                          timeout=300)


def files_under(folder):
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*") if p.is_file())


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize("at", FAULTS)
def test_cli_every_submission_and_allocation(tmp_path, at, mode):
    """The Nth submission (lost) or allocation (out of device memory) for N = 1, 2, ... until
    a render has fewer: each gives the message, exit status 1 and an empty folder."""
    out = tmp_path / "out"
    out.mkdir()
    n = 1
    while True:
        p = run(["render", SCENE, *SMALL, "--aov", "all", "-o", out / "image.exr"], f"{at}:{n}", MODES[mode])
        if p.returncode == 0:
            break
        expected = "whitted: " + re.escape(str(SCENE)) + ": (.*: )?" + FAULTS[at].format(n=n) + "; nothing written\n"
        assert p.returncode == 1 and re.fullmatch(expected, p.stderr), (n, p.returncode, p.stderr)
        assert files_under(tmp_path) == [], n
        n += 1
    # A render has a few of each (more through staging copies); then it writes its files.
    assert n > (4 if at == "submit" else 10), n
    assert "image.exr" in files_under(out)



def test_cli_host_memory_into_a_history_folder(tmp_path):
    p = run(["render", SCENE, *SMALL], "allocate:4:host-memory", "1", cwd=tmp_path)
    assert p.returncode == 1
    assert re.fullmatch("whitted: " + re.escape(str(SCENE)) + ": " + DEVICE +
                        r" is out of host memory \(VK_ERROR_OUT_OF_HOST_MEMORY\) at memory allocation 4 .*"
                        r"; nothing written\n", p.stderr), p.stderr
    assert files_under(tmp_path) == []


def test_cli_trace_device_lost(tmp_path):
    p = run(["trace", SCENE, "--width", "16", "--height", "12", "--pixel", "8,6"], "submit:2", "1")
    assert p.returncode == 1 and p.stdout == ""
    assert re.fullmatch("whitted: " + re.escape(str(SCENE)) + ": (.*: )?" + LOST.format(n=2) + "; nothing printed\n",
                        p.stderr), p.stderr


def test_malformed_fault_is_refused(tmp_path):
    p = run(["render", SCENE, *SMALL, "-o", tmp_path / "image.png"], "submit:x", "0")
    assert p.returncode == 1 and "WHITTED_INJECT_FAULT=submit:x: expected submit:N or allocate:N" in p.stderr
    assert files_under(tmp_path) == []


def python_call(kind, renderer, scene):
    if kind == "render":
        return renderer.render(scene, width=16, height=12, spp=2, aovs=("depth",))
    if kind == "cast_rays":
        origins, directions = scene.camera.rays(width=8, height=6)
        return renderer.cast_rays(scene, origins, directions)
    return renderer.trace_pixel(scene, 8, 6, width=16, height=12)


@pytest.mark.parametrize("kind", ["render", "cast_rays", "trace_pixel"])
@pytest.mark.parametrize("at", FAULTS)
def test_python_faults_raise_and_the_renderer_renders_again(monkeypatch, at, kind):
    """The first, a middle and the last submission or allocation of a fresh renderer's first
    call (for cast_rays and trace_pixel, the last is their own): each raises whitted.DeviceError
    naming the scene, and the same renderer's next call works."""
    scene = whitted.load(SCENE)
    monkeypatch.setenv("WHITTED_VALIDATION", "0")  # as on the command line: a third of the time
    probe = whitted.Renderer()
    python_call(kind, probe, scene)
    last = probe._device_events["submissions" if at == "submit" else "allocations"]
    assert last > 2, last
    for n in sorted({1, last // 2, last}):
        monkeypatch.setenv("WHITTED_INJECT_FAULT", f"{at}:{n}")
        renderer = whitted.Renderer()
        with pytest.raises(whitted.DeviceError) as failure:
            python_call(kind, renderer, scene)
        monkeypatch.delenv("WHITTED_INJECT_FAULT")
        assert isinstance(failure.value, RuntimeError)
        message = str(failure.value)
        assert re.fullmatch(re.escape(str(SCENE)) + ": (.*: )?" + FAULTS[at].format(n=n), message), (n, message)
        # The fault spent (a lost device is opened again, without it), the same renderer works.
        again = python_call(kind, renderer, scene)
        if kind == "render":
            assert again.image.shape == (12, 16, 3) and again.image.max() > 0
