# Renderer.trace_pixel (host/python/README.md): the dict `whitted trace --json`
# prints, from the same recorder and the same JSON builder
# (host/output/ray_tree_json.h).
import json
import subprocess

import pytest

from conftest import EXECUTABLE, SCENES

# 160x120: a corner (background in most scenes), the centre, a lower pixel.
PIXELS = [(5, 5), (80, 60), (40, 90)]


@pytest.mark.parametrize("path", SCENES, ids=[p.stem for p in SCENES])
def test_trace_pixel_equals_the_cli(renderer, path):
    import whitted
    scene = whitted.load(str(path))
    for x, y in PIXELS:
        cli = subprocess.run([str(EXECUTABLE), "trace", str(path), "--pixel", f"{x},{y}", "--width", "160",
                              "--height", "120", "--json"], capture_output=True, text=True, timeout=120)
        assert cli.returncode == 0, cli.stderr
        got = renderer.trace_pixel(scene, x, y, width=160, height=120)
        assert got == json.loads(cli.stdout), (path.name, x, y)
        assert got["pixel"] == [x, y] and got["rays"][0]["kind"] == "camera"


def test_trace_pixel_refuses_bad_values(renderer):
    import whitted
    scene = whitted.load(str(SCENES[0]))
    with pytest.raises(ValueError, match=r"^x: 160 is outside the 160x120 image$"):
        renderer.trace_pixel(scene, 160, 0, width=160, height=120)
    with pytest.raises(ValueError, match=r"^y: -1 is outside the 160x120 image$"):
        renderer.trace_pixel(scene, 0, -1, width=160, height=120)
    with pytest.raises(ValueError, match=r"^max_depth: must be in 0\.\."):
        renderer.trace_pixel(scene, 0, 0, width=160, height=120, max_depth=-1)
