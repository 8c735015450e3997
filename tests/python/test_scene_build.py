# Scenes built in Python (host/python/README.md "Building a scene"): add and
# remove objects and lights, numpy meshes, whitted.Material, save and pickle.
import math
import pickle

import numpy as np
import pytest
import whitted

from conftest import run_cli
from test_module import read_exr, same_result

SIZE = dict(width=80, height=60)


def ring_mesh():
    """A bumpy disc of 12 triangles around a centre: vertices, faces, unit normals, uvs."""
    angles = np.linspace(0, 2 * math.pi, 12, endpoint=False)
    rim = np.stack([np.cos(angles), 0.2 * np.sin(3 * angles), np.sin(angles)], axis=1) * 0.6
    vertices = np.vstack([[0.0, 0.35, 0.0], rim])
    faces = np.array([[0, 1 + (i + 1) % 12, 1 + i] for i in range(12)], dtype=np.int32)
    normals = vertices - [0.0, -0.5, 0.0]
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    uvs = np.column_stack([vertices[:, 0] + 0.5, vertices[:, 2] + 0.5])
    return vertices, faces, normals, uvs


def built_scene():
    scene = whitted.Scene()
    scene.camera.position = (0.3, 1.2, 4.0)
    scene.camera.look_at = (0, 0.3, 0)
    scene.camera.width, scene.camera.height = SIZE["width"], SIZE["height"]
    scene.ambient_light = (0.1, 0.1, 0.12)
    vertices, faces, normals, uvs = ring_mesh()
    shift = np.eye(4)
    shift[:3, 3] = (-0.9, 0.1, 0.3)
    scene.add_mesh(vertices, faces, normals=normals, uvs=uvs, transform=shift, name="ring",
                   material=whitted.Material(diffuse_color=(0.9, 0.5, 0.2), specular=0.4, shininess=20))
    scene.add_sphere((0.7, 0.5, -0.3), 0.5, name="ball",
                     material=whitted.Material(diffuse_color=(0.8, 0.8, 0.9), specular=0.6, reflection=0.3))
    scene.add_box((-0.2, -0.5, 0.6), (0.4, 0.3, 0.5), name="crate",
                  material=whitted.Material(diffuse_color=(0.2, 0.6, 0.3), transmission=0.4, ior=1.3))
    scene.add_plane((0, -0.5, 0), (0, 1, 0.05), name="floor",
                    material=whitted.Material(checker_color=(0.1, 0.1, 0.1), checker_size=0.5, ambient=0.3))
    scene.add_light(position=(3, 4, 3), color=(0.8, 0.8, 0.7), name="key")
    scene.add_light(position=(-2, 3, 2), color=(1, 0.9, 0.8), type="spot", direction=(0.5, -0.8, -0.4),
                    intensity=9, falloff="inverse_square", inner_angle=10, outer_angle=35)
    return scene


def test_built_scene_equals_cli_of_saved_file(tmp_path):
    scene = built_scene()
    assert [o.type for o in scene.objects] == ["mesh", "sphere", "box", "plane"]
    path = tmp_path / "built.xml"
    scene.save(path)
    status, err = run_cli("render", path, "-o", tmp_path / "x.exr", "--aov", "all", "-q")
    assert status == 0, err
    result = whitted.render(scene, aovs="all")
    assert result.image.shape == (60, 80, 3) and result.image.max() > 0.05
    assert np.array_equal(result.image, read_exr(tmp_path / "x.exr"))
    for name, values in result.aovs.items():
        assert np.array_equal(values, read_exr(tmp_path / f"x.{name}.exr")), name
    # Every object is in view: each has pixels in the object-id mask.
    assert len(np.unique(result.aovs["object_id"])) >= 5  # four objects and the background
    # The saved file loads back to the same XML (nothing rounded on the way).
    assert whitted.load(path).to_xml() == scene.to_xml()


def test_add_then_remove_renders_as_before():
    scene = built_scene()
    renderer = whitted.Renderer()
    before = renderer.render(scene, aovs=("object_id", "depth"))
    ball = scene.objects[1]
    extra = scene.add_sphere((0, 0.3, 1.5), 0.3, material=whitted.Material(diffuse_color=(1, 0, 0)))
    added = renderer.render(scene, aovs=("object_id", "depth"))
    assert added.record["uploads"]["geometry"] and not np.array_equal(added.image, before.image)
    scene.remove(extra)
    after = renderer.render(scene, aovs=("object_id", "depth"))
    assert after.record["uploads"]["geometry"]
    same_result(after, before)
    with pytest.raises(KeyError):
        extra.radius
    with pytest.raises(KeyError):
        scene.remove(extra)
    # The other handles still point at their objects.
    assert ball.name == "ball" and ball.radius == 0.5
    scene.remove(scene.objects[0])
    assert ball.name == "ball" and [o.name for o in scene.objects] == ["ball", "crate", "floor"]
    ball.radius = 0.4
    assert scene.objects[0].radius == 0.4
    # Lights too.
    spot = scene.lights[1]
    scene.remove(scene.lights[0])
    assert spot.type == "spot" and len(scene.lights) == 1


def test_pickle_round_trip_renders_the_same():
    scene = built_scene()
    again = pickle.loads(pickle.dumps(scene))
    assert again.to_xml() == scene.to_xml() and [o.name for o in again.objects] == [o.name for o in scene.objects]
    same_result(whitted.render(again, aovs=("normal", "object_id")), whitted.render(scene, aovs=("normal", "object_id")))


def test_empty_scene_and_material_copy():
    scene = whitted.Scene()
    assert scene.objects == [] and scene.lights == [] and scene.ambient_light == (0, 0, 0)
    m = whitted.Material(diffuse=0.25, fresnel=True, ambient_color=(0.1, 0.2, 0.3))
    triangle = scene.add_triangle((0, 0, -3), (1, 0, -3), (0, 1, -3), material=m)
    assert triangle.diffuse == 0.25 and triangle.fresnel and triangle.material.ambient_color == (0.1, 0.2, 0.3)
    m.diffuse = 0.5  # the object took a copy
    assert triangle.diffuse == 0.25
    triangle.material = m
    assert triangle.diffuse == 0.5
    # A transform that mirrors turns the winding over, as the loader's <matrix> does.
    mirror = np.diag([-1.0, 1, 1, 1])
    mesh = scene.add_mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.array([[0, 1, 2]]), transform=mirror)
    assert mesh.type == "mesh" and "<vertex x=\"-1\" y=\"0\" z=\"0\"/>" in scene.to_xml()


BAD = [
    ("add_sphere", dict(center=(0, 0, 0), radius=-1), "add_sphere.radius", ValueError),
    ("add_sphere", dict(center=(0, float("nan"), 0), radius=1), "add_sphere.center", ValueError),
    ("add_box", dict(min=(0, 0, 0), size=(1, 0, 1)), "add_box.size", ValueError),
    ("add_plane", dict(point=(0, 0, 0), normal=(0, 0, 0)), "add_plane.normal", ValueError),
    ("add_cylinder", dict(base=(0, 0, 0), axis=(0, 1, 0), radius=1, height=0), "add_cylinder.height", ValueError),
    ("add_triangle", dict(a=(0, 0, 0), b=(1, 1, 1), c=(2, 2, 2)), "add_triangle.c", ValueError),
    ("add_mesh", dict(vertices=np.zeros((3, 3)) + np.eye(3), faces=np.array([[0, 1, 3]])), "add_mesh.faces[0]", ValueError),
    ("add_mesh", dict(vertices=np.array([[0, 0, 0], [1, 0, np.nan], [0, 1, 0]]), faces=np.array([[0, 1, 2]])),
     "add_mesh.vertices[1]", ValueError),
    ("add_mesh", dict(vertices=np.eye(3), faces=np.array([[0.0, 1, 2]])), "add_mesh.faces", ValueError),
    ("add_mesh", dict(vertices=np.eye(3), faces=np.array([[0, 1, 2]]), transform=np.eye(3)), "add_mesh.transform",
     ValueError),
    ("add_mesh", dict(vertices=np.eye(3), faces=np.array([[0, 1, 2]]), normals=np.zeros((3, 3))),
     "add_mesh.normals[0]", ValueError),
    ("add_mesh", dict(vertices=np.eye(3), faces=np.array([[0, 1, 2]]), uvs=np.zeros((2, 2))), "add_mesh.uvs",
     ValueError),
    ("add_mesh", dict(vertices=np.eye(3) * 2e6, faces=np.array([[0, 1, 2]])), "add_mesh.vertices[0]", ValueError),
    ("add_light", dict(position=(0, 0, 0), color=(-1, 0, 0)), "add_light.color", ValueError),
    ("add_light", dict(type="spot", position=(0, 0, 0), direction=(0, -1, 0), inner_angle=40, outer_angle=30),
     "add_light.outer_angle", ValueError),
    ("add_light", dict(type="directional", position=(0, 0, 0), direction=(0, -1, 0)), "add_light.position",
     ValueError),
    ("add_light", dict(type="area", position=(0, 0, 0)), "add_light.type", ValueError),
    ("add_light", dict(position=(0, 0, 0), radius=-1), "add_light.radius", ValueError),
    ("add_light", dict(position=(0, 0, 0), radius=float("nan")), "add_light.radius", ValueError),
    ("add_light", dict(type="rect", position=(0, 0, 0), u=(1, 0, 0), v=(-2, 0, 0)), "add_light.v", ValueError),
    ("add_light", dict(type="rect", position=(0, 0, 0), u=(0, 0, 0), v=(0, 0, 1)), "add_light.v", ValueError),
    ("add_light", dict(type="rect", position=(0, 0, 0), u=(1, 0, 0)), "add_light.v", ValueError),
    ("add_light", dict(position=(0, 0, 0), u=(1, 0, 0)), "add_light.u", ValueError),
    ("add_light", dict(position=(0, 0, 0), radius=0.5, shadow_samples=0), "add_light.shadow_samples", ValueError),
    ("add_light", dict(position=(0, 0, 0), radius=0.5, shadow_samples=257), "add_light.shadow_samples", ValueError),
    ("add_light", dict(position=(0, 0, 0), shadow_samples=4), "add_light.shadow_samples", ValueError),
    ("add_sphere", dict(center=(0, 0, 0), radius=1, material="red"), "add_sphere.material", TypeError),
    ("add_sphere", dict(center=(0, 0, 0), radius=1, name=" ball"), "add_sphere.name", ValueError),
    ("add_light", dict(position=(0, 0, 0), name="key\x01"), "add_light.name", ValueError),
]


@pytest.mark.parametrize("call, args, field, error", BAD, ids=lambda x: x if isinstance(x, str) else "")
def test_bad_values_name_the_field(call, args, field, error):
    scene = whitted.Scene()
    with pytest.raises(error, match=field.replace("[", r"\[").replace("]", r"\]")):
        getattr(scene, call)(**args)
    assert scene.objects == [] and scene.lights == []  # nothing half-added
    with pytest.raises(ValueError, match="Material.diffuse"):
        whitted.Material(diffuse=2)
    with pytest.raises(TypeError, match="unknown field 'colour'"):
        whitted.Material(colour=(1, 0, 0))


def test_area_lights_render_as_their_saved_file(tmp_path):
    """Area lights (scenes/README.md "Area lights") from Python: fields read back and checked, and the saved file
    renders through the CLI exactly as the scene does from Python."""
    scene = built_scene()
    sphere = scene.lights[0]
    sphere.radius = 0.4
    sphere.shadow_samples = 4
    rect = scene.add_light(type="rect", position=(0, 2.5, 0.5), color=(0.5, 0.5, 0.6), u=(1, 0, 0), v=(0, 0, -0.5),
                           shadow_samples=2)
    assert rect.type == "rect" and rect.u == (1, 0, 0) and rect.v == (0, 0, -0.5) and not rect.two_sided
    rect.two_sided = True
    with pytest.raises(ValueError, match="Light.v"):
        rect.v = (2, 0, 0)
    with pytest.raises(ValueError, match="Light.radius"):
        rect.radius = 1
    with pytest.raises(ValueError, match="Light.two_sided"):
        sphere.two_sided = True
    assert rect.v == (0, 0, -0.5) and sphere.radius == 0.4 and sphere.shadow_samples == 4
    path = tmp_path / "area.xml"
    scene.save(path)
    status, err = run_cli("render", path, "-o", tmp_path / "x.exr", "--aov", "none", "--spp", "4", "-q")
    assert status == 0, err
    image = whitted.render(scene, spp=4).image
    assert np.array_equal(image, read_exr(tmp_path / "x.exr"))
    again = whitted.load(path)
    assert again.lights[2].two_sided and again.lights[0].shadow_samples == 4 and again.lights[0].radius == 0.4
    sphere.radius = 0  # a point light again: one shadow ray
    assert sphere.shadow_samples == 1


def test_masks_legend_ids_are_stable_across_add_and_remove():
    scene = built_scene()
    renderer = whitted.Renderer()
    first = renderer.render(scene, aovs=("object_id",))
    assert first.masks == {0: dict(name="ring", type="mesh", material="ring", material_id=0),
                           1: dict(name="ball", type="sphere", material="ball", material_id=1),
                           2: dict(name="crate", type="box", material="crate", material_id=2),
                           3: dict(name="floor", type="plane", material="floor", material_id=3)}
    ring = scene.objects[0]
    scene.remove(ring)
    scene.add_sphere((0, 0.3, 1.5), 0.3, name="new")  # a new id: 4, never ring's 0
    second = renderer.render(scene, aovs=("object_id",))
    assert {k: v["name"] for k, v in second.masks.items()} == {1: "ball", 2: "crate", 3: "floor", 4: "new"}
    mask = second.aovs["object_id"]
    assert set(np.unique(mask)) == {1, 2, 3, 4, 0xFFFFFFFF}
    # Each object keeps its id and its pixels where nothing new covers them.
    for oid in (1, 3):
        was, now = first.aovs["object_id"] == oid, mask == oid
        assert now.any() and np.array_equal(was & ~(mask == 4), now & ~(first.aovs["object_id"] == 0))
    legend = second.record["masks"]["objects"]
    assert [(o["id"], o["name"]) for o in legend] == [(1, "ball"), (2, "crate"), (3, "floor"), (4, "new")]
    assert [m["object"] for m in second.record["masks"]["materials"]] == [1, 2, 3, 4]


# Scene.copy() continues the original's numbering: the same ids (after a removal too), the same next id, the
# same transforms; the copy is independent of the original.
def test_copy_keeps_ids_and_transforms():
    import copy
    scene = built_scene()
    scene.remove(scene.objects[0])
    ball = next(o for o in scene.objects if o.name == "ball")
    move = np.eye(4)
    move[:3, 3] = (0.2, 0.1, 0.0)
    ball.transform = move
    renderer = whitted.Renderer()
    for make in (lambda s: s.copy(), copy.copy, copy.deepcopy):
        twin = make(scene)
        a = renderer.render(scene, aovs=("object_id",))
        b = renderer.render(twin, aovs=("object_id",))
        assert a.masks == b.masks and np.array_equal(a.aovs["object_id"], b.aovs["object_id"])
        np.testing.assert_array_equal(next(o for o in twin.objects if o.name == "ball").transform, move)
        twin.add_sphere((0, 0.3, 1.5), 0.3, name="new")
        scene.add_sphere((0, 0.3, 1.5), 0.3, name="new")
        assert renderer.render(twin, aovs=("object_id",)).masks == renderer.render(scene, aovs=("object_id",)).masks
        scene.remove(scene.objects[-1])
        assert len(twin.objects) == len(scene.objects) + 1  # independent


def test_module_holds_no_window_code():
    # The scene edits it shares with the window's editor panel live in
    # host/scene/shape_edit.h, so no ImGui or GLFW code is linked in.
    import pathlib
    binary = pathlib.Path(whitted.__file__).read_bytes()
    assert b"ImGui" not in binary and b"glfw" not in binary


def test_dataset_example_writes_ten_frames_with_legends(tmp_path):
    """tools/examples/dataset.py (the README's Python example): 10 frames, each an image with depth, normals and
    object masks whose ids are those of its legend; ids of removed objects are never reused across frames."""
    import json, os, subprocess, sys
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    env = dict(os.environ, PYTHONPATH=os.environ.get("PYTHONPATH", ""))
    subprocess.run([sys.executable, os.path.join(root, "tools", "examples", "dataset.py"), str(tmp_path)],
                   check=True, env=env, capture_output=True)
    seen = set()
    for frame in range(10):
        legend = json.loads((tmp_path / f"frame{frame:02d}.legend.json").read_text())
        ids = {int(k) for k in legend}
        assert legend["0"] == "floor" and len(ids) == 21
        assert not (ids - {0}) & seen, "an id was reused"
        seen |= ids - {0}
        mask = read_exr(str(tmp_path / f"frame{frame:02d}.object_id.exr"))
        shown = set(np.unique(mask).astype(np.int64).tolist()) - {0xFFFFFFFF}
        assert shown <= ids and len(shown) > 10, (frame, shown)
        for name in ("depth", "normal"):
            assert (tmp_path / f"frame{frame:02d}.{name}.exr").is_file()
