# Renderer.trace_pixel (host/python/README.md): the dict `whitted trace --json`
# prints, from the same recorder and the same JSON builder
# (host/output/ray_tree_json.h).
import json
import subprocess

import pytest

from conftest import EXECUTABLE, SCENES

# 160x120: ten pixels over the image, corners (background in most scenes), the centre, objects, glass and
# mirrors of the scenes that have them; one `whitted trace` with ten --pixel prints the ten records as an array.
PIXELS = [(5, 5), (80, 60), (40, 90), (120, 30), (20, 60), (140, 100), (80, 20), (60, 75), (100, 70), (155, 115)]


@pytest.mark.parametrize("path", SCENES, ids=[p.stem for p in SCENES])
def test_trace_pixel_equals_the_cli(renderer, path):
    import whitted
    scene = whitted.load(str(path))
    args = [str(EXECUTABLE), "trace", str(path), "--width", "160", "--height", "120", "--json"]
    for x, y in PIXELS:
        args += ["--pixel", f"{x},{y}"]
    cli = subprocess.run(args, capture_output=True, text=True, timeout=300)
    assert cli.returncode == 0, cli.stderr
    records = json.loads(cli.stdout)
    assert isinstance(records, list) and len(records) == len(PIXELS)
    for (x, y), record in zip(PIXELS, records):
        got = renderer.trace_pixel(scene, x, y, width=160, height=120)
        assert got == record, (path.name, x, y)
        assert got["pixel"] == [x, y] and got["rays"][0]["kind"] == "camera"


# An object in the tree carries the id the object_id mask and result.masks give it, which after a removal is no
# longer its index in the scene's list.
def test_trace_pixel_names_objects_by_their_mask_ids(renderer):
    import whitted
    scene = whitted.Scene()
    scene.camera.position, scene.camera.look_at = (0, 0, 5), (0, 0, 0)
    scene.add_light(position=(0, 5, 5), color=(1, 1, 1))
    first = scene.add_sphere((-1.5, 0, 0), 0.5, name="first")
    scene.add_sphere((1.5, 0, 0), 0.5, name="second")
    scene.remove(first)
    scene.add_sphere((0, 0, 0), 0.5, name="third")
    result = renderer.render(scene, width=64, height=48, aovs=("object_id",))
    legend = {v["name"]: k for k, v in result.masks.items()}
    assert legend["third"] != 1  # the index of "third" in the scene's list
    for x, name in ((32, "third"), (47, "second")):
        obj = renderer.trace_pixel(scene, x, 24, width=64, height=48)["rays"][0]["hit"]["object"]
        assert obj["name"] == name and obj["id"] == legend[name] == result.aovs["object_id"][24, x]


def test_trace_pixel_refuses_bad_values(renderer):
    import whitted
    scene = whitted.load(str(SCENES[0]))
    with pytest.raises(ValueError, match=r"^x: 160 is outside the 160x120 image$"):
        renderer.trace_pixel(scene, 160, 0, width=160, height=120)
    with pytest.raises(ValueError, match=r"^y: -1 is outside the 160x120 image$"):
        renderer.trace_pixel(scene, 0, -1, width=160, height=120)
    with pytest.raises(ValueError, match=r"^max_depth: must be in 0\.\."):
        renderer.trace_pixel(scene, 0, 0, width=160, height=120, max_depth=-1)
