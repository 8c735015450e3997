# whitted as a Python module: the same pixels as the CLI, uploads of only
# what changed, errors with the CLI's words, threads, Ctrl+C, memory, pip.
import _thread
import os
import pathlib
import subprocess
import sys
import threading

import numpy as np
import OpenImageIO as oiio
import pytest
import whitted

from conftest import BUILD, ROOT, SCENES, run_cli

SIZE = dict(width=64, height=48)


def read_exr(path):
    image = oiio.ImageInput.open(str(path))
    # The masks' EXR channel is UINT: read as the ids themselves.
    pixels = image.read_image("uint" if image.spec().format == oiio.TypeDesc("uint") else "float")
    image.close()
    return pixels[:, :, 0] if pixels.shape[2] == 1 else pixels


@pytest.mark.parametrize("scene", SCENES, ids=lambda p: p.stem)
def test_render_equals_cli_exr(scene, tmp_path):
    status, err = run_cli("render", scene, "-o", tmp_path / "x.exr", "--width", 64, "--height", 48, "--aov", "all", "-q")
    assert status == 0, err
    result = whitted.render(str(scene), aovs="all", **SIZE)
    assert result.image.dtype == np.float32 and result.image.shape == (48, 64, 3)
    assert np.array_equal(result.image, read_exr(tmp_path / "x.exr"))
    assert len(result.aovs) == 16  # 14 images and the two masks
    for name in ("object_id", "material_id"):
        assert result.aovs[name].dtype == np.uint32, name
    for name, values in result.aovs.items():
        expected = read_exr(tmp_path / f"x.{name}.exr")
        assert values.dtype == expected.dtype and np.array_equal(values, expected), name
    # save() writes the same files through the same writers.
    (tmp_path / "py").mkdir()
    written = [pathlib.Path(p) for p in result.save(tmp_path / "py" / "x.exr")]
    assert sorted(p.name for p in written) == sorted(p.name for p in tmp_path.glob("x*.exr"))
    for path in written:
        assert np.array_equal(read_exr(path), read_exr(tmp_path / path.name)), path.name
    assert (tmp_path / "py" / "x.json").exists()


def test_region_and_split_aovs_equal_cli(tmp_path):
    scene = ROOT / "scenes" / "showcase.xml"
    status, err = run_cli("render", scene, "-o", tmp_path / "x.exr", "--width", 64, "--height", 48, "--region",
                          "8,4,40,30", "--aov", "reflection.1,reflection.2,depth", "--aov-bounces", 2,
                          "--aa", "uniform", "--spp", 4, "-q")
    assert status == 0, err
    result = whitted.render(str(scene), region=(8, 4, 40, 30), aovs=("reflection.1", "reflection.2", "depth"),
                            aov_bounces=2, aa="uniform", spp=4, **SIZE)
    assert result.image.shape == (26, 32, 3)
    assert np.array_equal(result.image, read_exr(tmp_path / "x.exr"))
    for name in ("reflection.1", "reflection.2", "depth"):
        assert np.array_equal(result.aovs[name], read_exr(tmp_path / f"x.{name}.exr")), name


def test_record_and_png(renderer):
    result = renderer.render(whitted.load(ROOT / "scenes" / "one_mirror.xml"), **SIZE)
    record = result.record
    assert (record["settings"]["width"], record["settings"]["height"], record["settings"]["spp"]) == (64, 48, 16)
    assert record["scene"].endswith("one_mirror.xml") and record["rays"]
    assert set(record["uploads"]) >= {"geometry", "bvh", "materials", "lights", "camera"}
    assert result._repr_png_().startswith(b"\x89PNG\r\n\x1a\n")


def same_result(a, b):
    assert np.array_equal(a.image, b.image)
    for name in a.aovs:
        assert np.array_equal(a.aovs[name], b.aovs[name]), name


def test_camera_edit_uploads_no_geometry(renderer):
    scene = whitted.load(ROOT / "scenes" / "room.xml")
    renderer.render(scene, aovs=("depth", "normal"), **SIZE)
    x, y, z = scene.camera.position
    scene.camera.position = (x + 0.3, y - 0.1, z + 0.2)
    scene.camera.fov = 50
    edited = renderer.render(scene, aovs=("depth", "normal"), **SIZE)
    uploads = edited.record["uploads"]
    assert uploads["camera"] and not uploads["geometry"] and not uploads["bvh"] and not uploads["renderer"]
    fresh = whitted.Renderer().render(scene.copy(), aovs=("depth", "normal"), **SIZE)
    assert fresh.record["uploads"]["geometry"]
    same_result(edited, fresh)


@pytest.mark.parametrize("field,value", [("diffuse", 0.25), ("diffuse_color", (0.9, 0.2, 0.1)),
                                         ("transmission", 0.5), ("reflection", 0.4)])
def test_material_edit_rebuilds_no_bvh(renderer, field, value):
    scene = whitted.load(ROOT / "scenes" / "three_diffuse_spheres.xml")
    renderer.render(scene, aovs=("diffuse",), **SIZE)
    setattr(scene.objects[0], field, value)
    edited = renderer.render(scene, aovs=("diffuse",), **SIZE)
    uploads = edited.record["uploads"]
    assert uploads["materials"] and not uploads["geometry"] and not uploads["bvh"] and not uploads["camera"]
    fresh = whitted.Renderer().render(scene.copy(), aovs=("diffuse",), **SIZE)
    same_result(edited, fresh)
    assert getattr(scene.objects[0], field) == value


# Six AOV sets, each ordered pair of them rendered in turn by one renderer:
# an Eulerian circuit of the complete directed graph on the sets (Hierholzer),
# so 31 renders cover all 30 changes A -> B. Each render equals a fresh
# renderer's render of B (a renderer once reused itself without the mask
# layer and returned ids read past the pixel buffer).
AOV_SETS = [("normal",), ("normal", "object_id"), ("object_id", "material_id"), ("depth", "diffuse"), "all", "none"]


def every_ordered_pair(n):
    unused = {a: [b for b in range(n) if b != a] for a in range(n)}
    stack, circuit = [0], []
    while stack:
        if unused[stack[-1]]:
            stack.append(unused[stack[-1]].pop())
        else:
            circuit.append(stack.pop())
    return circuit[::-1]


def test_aov_set_changes_equal_a_fresh_renderer():
    scene = whitted.load(ROOT / "scenes" / "three_diffuse_spheres.xml")
    size = dict(width=32, height=24)
    fresh = [whitted.Renderer().render(scene, aovs=aovs, **size) for aovs in AOV_SETS]
    order = every_ordered_pair(len(AOV_SETS))
    assert len(order) == 31 and {(a, b) for a, b in zip(order, order[1:])} == {
        (a, b) for a in range(6) for b in range(6) if a != b}
    reused = whitted.Renderer()
    for step, k in enumerate(order):
        result = reused.render(scene, aovs=AOV_SETS[k], **size)
        assert sorted(result.aovs) == sorted(fresh[k].aovs), (step, AOV_SETS[k])
        same_result(result, fresh[k])
        if "object_id" in result.aovs:
            assert set(np.unique(result.aovs["object_id"])) <= {0, 1, 2, 3, 0xFFFFFFFF}, AOV_SETS[k]


def test_light_and_geometry_edits(renderer):
    scene = whitted.load(ROOT / "scenes" / "three_diffuse_spheres.xml")
    renderer.render(scene, **SIZE)
    scene.lights[0].color = (0.5, 0.5, 0.2)
    lit = renderer.render(scene, **SIZE)
    assert lit.record["uploads"]["lights"] and not lit.record["uploads"]["geometry"]
    same_result(lit, whitted.Renderer().render(scene.copy(), **SIZE))
    x, y, z = scene.objects[0].position
    scene.objects[0].position = (x + 0.2, y, z)
    moved = renderer.render(scene, **SIZE)
    assert moved.record["uploads"]["geometry"] and moved.record["uploads"]["bvh"]
    same_result(moved, whitted.Renderer().render(scene.copy(), **SIZE))


def test_save_and_reload(tmp_path):
    scene = whitted.load(ROOT / "scenes" / "three_diffuse_spheres.xml")
    scene.objects[1].diffuse = 0.125
    scene.save(tmp_path / "s.xml")
    assert whitted.load(tmp_path / "s.xml").objects[1].diffuse == 0.125


BAD = ["coef_above_one.xml", "colour_above_one.xml", "csg_one_child.xml", "camera_at_window.xml",
       "box_flat.xml", "binary_garbage.xml"]


@pytest.mark.parametrize("name", BAD)
def test_scene_error_matches_cli(name):
    path = ROOT / "tests" / "bad_scenes" / name
    status, err = run_cli("render", path, "-o", "/nonexistent-folder/x.png", "-q")
    assert status == 2
    with pytest.raises(whitted.SceneError) as caught:
        whitted.load(path)
    e = caught.value
    assert str(e) == err.splitlines()[0]
    assert e.file == str(path)
    assert str(e) == (f"{e.file}:{e.line}: {e.message}" if e.line > 0 else f"{e.file}: {e.message}")
    assert isinstance(e, ValueError)


def test_loads_error_has_line():
    with pytest.raises(whitted.SceneError) as caught:
        whitted.loads("<scene>\n<camera>\n</scene>\n", base_dir="/tmp")  # the unclosed <camera>
    assert caught.value.line == 2 and caught.value.file == "/tmp/<string>"


@pytest.mark.parametrize("options,words", [
    (dict(spp=-1), "spp"), (dict(spp=0), "spp"), (dict(aovs=("bogus",)), "bogus"),
    (dict(region=(0, 0, 100, 10)), "region"), (dict(region=(5, 5, 5, 9)), "region"),
    (dict(aa="best"), "aa"), (dict(max_depth=-2), "max_depth"), (dict(aa_threshold=float("nan")), "aa_threshold"),
    (dict(width=0), "width"), (dict(aovs=("reflection.3",), aov_bounces=2), "reflection.3"),
])
def test_bad_options_raise_value_error(renderer, options, words):
    scene = whitted.load(ROOT / "scenes" / "one_mirror.xml")
    with pytest.raises(ValueError, match=words.replace(".", r"\.")):
        renderer.render(scene, **{**SIZE, **options})


@pytest.mark.parametrize("target,field,value,words", [
    ("object", "diffuse", 1.5, r"Object\.diffuse: must be in \[0, 1\], got 1\.5"),
    ("object", "ior", 50, r"Object\.ior"), ("object", "diffuse_color", (2, 0, 0), r"Object\.diffuse_color"),
    ("object", "radius", -1, r"Object\.radius"), ("object", "shininess", -3, r"Object\.shininess"),
    ("camera", "fov", 0, r"Camera\.fov"), ("camera", "fov", 180, r"Camera\.fov"),
    ("camera", "width", 0, r"Camera\.width"),
    ("camera", "projection", "fisheye", r"Camera\.projection: must be 'perspective' or 'orthographic', got 'fisheye'"),
    ("camera", "window_height", 0, r"Camera\.window_height"),
    ("camera", "aperture_radius", -0.1, r"Camera\.aperture_radius"),
    ("camera", "aperture_radius", float("nan"), r"Camera\.aperture_radius"),
    ("camera", "focus_distance", 0, r"Camera\.focus_distance"),
    ("object", "roughness", 1.5, r"Object\.roughness: must be in \[0, 1\], got 1\.5"),
    ("object", "roughness", -0.1, r"Object\.roughness"),
    ("camera", "up", (0, 0, 0), r"Camera\.up"), ("light", "intensity", -1, r"Light\.intensity"),
])
def test_bad_field_values_raise_value_error(target, field, value, words):
    scene = whitted.load(ROOT / "scenes" / "three_diffuse_spheres.xml")
    obj = {"object": scene.objects[0], "camera": scene.camera, "light": scene.lights[0]}[target]
    before = getattr(obj, field)
    with pytest.raises(ValueError, match=words):
        setattr(obj, field, value)
    assert getattr(obj, field) == before


# The camera's frame is checked as the XML loader checks it, and its
# projection is the file's: an orthographic camera set here is saved, loaded
# back as orthographic and renders as `whitted render` renders the file.
def test_camera_frame_and_projection(tmp_path):
    scene = whitted.load(ROOT / "scenes" / "three_diffuse_spheres.xml")
    camera = scene.camera
    position, look_at, up = camera.position, camera.look_at, camera.up
    with pytest.raises(ValueError, match=r"^Camera\.look_at: Camera\.position and Camera\.look_at would coincide$"):
        camera.look_at = position
    with pytest.raises(ValueError, match=r"^Camera\.position: Camera\.position and Camera\.look_at would coincide$"):
        camera.position = look_at
    view = tuple(b - a for a, b in zip(position, look_at))
    with pytest.raises(ValueError, match=r"^Camera\.up: Camera\.up would be parallel to the viewing direction$"):
        camera.up = tuple(-3 * x for x in view)
    assert (camera.position, camera.look_at, camera.up) == (position, look_at, up)
    assert camera.projection == "perspective"

    camera.projection = "orthographic"
    camera.window_height = 3.0
    scene.save(tmp_path / "ortho.xml")
    reloaded = whitted.load(tmp_path / "ortho.xml")
    assert (reloaded.camera.projection, reloaded.camera.window_height) == ("orthographic", 3.0)
    status, err = run_cli("render", tmp_path / "ortho.xml", "-o", tmp_path / "x.exr", "--width", 64, "--height", 48,
                          "--aov", "none", "-q")
    assert status == 0, err
    image = whitted.render(scene, aovs="none", **SIZE).image
    assert np.array_equal(image, read_exr(tmp_path / "x.exr"))
    assert not np.array_equal(image, whitted.render(whitted.load(ROOT / "scenes" / "three_diffuse_spheres.xml"),
                                                    aovs="none", **SIZE).image)


# Depth of field and glossy reflection from Python (scenes/README.md "Depth of field"): the lens and the
# roughness are saved and loaded back, render as `whitted render` renders the saved file, and change the image.
def test_lens_and_roughness(tmp_path):
    scene = whitted.load(ROOT / "scenes" / "one_mirror.xml")
    camera = scene.camera
    look = sum((b - a) ** 2 for a, b in zip(camera.position, camera.look_at)) ** 0.5
    assert camera.aperture_radius == 0 and camera.focus_distance == pytest.approx(look)
    camera.aperture_radius = 0.15
    camera.focus_distance = 4.0
    mirror = next(o for o in scene.objects if o.reflection > 0)
    mirror.roughness = 0.3
    assert whitted.Material(roughness=0.2).roughness == 0.2
    scene.save(tmp_path / "lens.xml")
    reloaded = whitted.load(tmp_path / "lens.xml")
    assert (reloaded.camera.aperture_radius, reloaded.camera.focus_distance) == (0.15, 4.0)
    assert max(o.roughness for o in reloaded.objects) == 0.3
    status, err = run_cli("render", tmp_path / "lens.xml", "-o", tmp_path / "x.exr", "--width", 64, "--height", 48,
                          "--aov", "none", "-q")
    assert status == 0, err
    image = whitted.render(scene, aovs="none", **SIZE).image
    assert np.array_equal(image, read_exr(tmp_path / "x.exr"))
    camera.focus_distance = None
    assert camera.focus_distance == pytest.approx(look)
    camera.aperture_radius = 0
    mirror.roughness = 0
    plain = whitted.render(whitted.load(ROOT / "scenes" / "one_mirror.xml"), aovs="none", **SIZE).image
    assert np.array_equal(whitted.render(scene, aovs="none", **SIZE).image, plain)
    assert not np.array_equal(image, plain)


# A reused renderer takes a lens, gloss and an area light in and out through its edit paths (the pipeline is
# specialised for the distribution effects a scene has: device_types.h kSpecDistribution), each render equal to
# a fresh renderer's.
def test_reused_renderer_follows_lens_gloss_and_area_lights(renderer):
    scene = whitted.load(ROOT / "scenes" / "one_mirror.xml")
    mirror = next(o for o in scene.objects if o.reflection > 0)

    def check():
        reused = renderer.render(scene, aovs="none", spp=4, **SIZE).image
        assert np.array_equal(reused, whitted.render(scene, aovs="none", spp=4, **SIZE).image)
        return reused

    images = [check()]
    scene.camera.aperture_radius = 0.15
    images.append(check())
    mirror.roughness = 0.3
    images.append(check())
    scene.lights[0].radius = 0.5
    images.append(check())
    scene.camera.aperture_radius = 0
    mirror.roughness = 0
    scene.lights[0].radius = 0
    images.append(check())
    assert all(not np.array_equal(a, b) for a, b in zip(images[:3], images[1:4]))
    assert np.array_equal(images[0], images[-1])


# The same for the shading features (device_types.h kSpecFeatures): Fresnel, absorption, a checker, spot and
# directional lights with falloff, and smooth mesh triangles come in through a reused renderer's edit paths and go
# again, each render equal to a fresh renderer's, each step changing the image.
def test_reused_renderer_follows_shading_features(renderer):
    scene = whitted.load(ROOT / "scenes" / "one_mirror.xml")
    mirror = next(o for o in scene.objects if o.reflection > 0)
    floor = scene.objects[0]

    def check():
        reused = renderer.render(scene, aovs="none", **SIZE).image
        assert np.array_equal(reused, whitted.Renderer().render(scene, aovs="none", **SIZE).image)
        return reused

    images = [check()]
    mirror.fresnel = True
    images.append(check())
    glass = scene.add_sphere((0.2, 0.5, -2.2), 0.45, material=whitted.Material(
        transmission=0.8, ior=1.5, specular=0.2, reflection=0.1, absorption=(0.2, 1.0, 2.0)))
    images.append(check())
    floor.checker_size = 0.4
    floor.checker_color = (0.1, 0.1, 0.1)
    images.append(check())
    spot = scene.add_light(position=(0.5, 3, -1), type="spot", direction=(0, -1, -0.3), intensity=6,
                           falloff="inverse_square", inner_angle=10, outer_angle=30)
    sun = scene.add_light(type="directional", direction=(-0.3, -1, -0.5), color=(0.3, 0.3, 0.25))
    images.append(check())
    rim = np.array([[np.cos(a), 0.0, np.sin(a)] for a in np.linspace(0, 2 * np.pi, 12, endpoint=False)]) * 0.4
    vertices = np.vstack([[0.0, 0.4, 0.0], rim]) + [0.8, 0.2, -2.6]
    faces = np.array([[0, 1 + (i + 1) % 12, 1 + i] for i in range(12)], dtype=np.int32)
    normals = vertices - [0.8, -0.3, -2.6]
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    flat = scene.add_mesh(vertices, faces, name="flat")
    images.append(check())
    scene.remove(flat)
    smooth = scene.add_mesh(vertices, faces, normals=normals, name="smooth")
    images.append(check())
    for handle in (smooth, sun, spot, glass):
        scene.remove(handle)
    floor.checker_size = 0
    mirror.fresnel = False
    images.append(check())
    assert all(not np.array_equal(a, b) for a, b in zip(images[:-2], images[1:-1]))
    assert np.array_equal(images[0], images[-1])


def rss_mib():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024


def test_memory_steady_over_300_renders(renderer):
    scene = whitted.load(ROOT / "scenes" / "three_diffuse_spheres.xml")
    for i in range(300):
        scene.camera.fov = 50 + (i % 10)
        result = renderer.render(scene, width=16, height=12, aovs=("depth",))
        assert result.image.shape == (12, 16, 3)
        if i == 9:
            after_ten = rss_mib()
    assert rss_mib() - after_ten < 20


def test_two_renderers_on_two_threads():
    names = ["room.xml", "showcase.xml"]
    scenes = [whitted.load(ROOT / "scenes" / n) for n in names]
    one_after_other = [whitted.Renderer().render(s, aovs=("depth",), **SIZE) for s in scenes]
    results = [None, None]

    def work(i):
        results[i] = whitted.Renderer().render(scenes[i], aovs=("depth",), **SIZE)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for a, b in zip(one_after_other, results):
        same_result(a, b)


LONG = dict(width=1024, height=1024, aovs="all", aa="uniform", spp=1)  # several bands
# One band of many submissions: 6 tiles x 256 dispatches of 4 samples a pixel.
ONE_BAND = dict(width=320, height=240, aa="uniform", spp=1024)


def test_progress_between_bands(renderer):
    fractions = []
    renderer.render(whitted.load(ROOT / "scenes" / "three_diffuse_spheres.xml"), progress=fractions.append, **LONG)
    assert len(fractions) > 1 and fractions == sorted(fractions) and fractions[-1] == 1.0


def test_progress_within_one_band(renderer):
    fractions = []
    result = renderer.render(whitted.load(ROOT / "scenes" / "three_diffuse_spheres.xml"), progress=fractions.append,
                             **ONE_BAND)
    assert result.record["sampling"]["bands"] == 1
    # After every submission of at most 4 dispatches: 384 calls or more
    # (fewer dispatches a submission where they run long), the last at 1.0.
    assert len(fractions) >= 6 * 256 // 4 and fractions == sorted(fractions) and fractions[-1] == 1.0
    assert fractions[0] < 0.01 and fractions[-2] > 0.99


def test_progress_must_be_callable(renderer):
    scene = whitted.load(ROOT / "scenes" / "three_diffuse_spheres.xml")
    with pytest.raises(TypeError, match=r"progress: must be callable .* got a list"):
        renderer.render(scene, progress=[], **SIZE)


def test_keyboard_interrupt_leaves_renderer_usable(renderer):
    scene = whitted.load(ROOT / "scenes" / "three_diffuse_spheres.xml")
    seen = []

    def ctrl_c(fraction):  # Ctrl+C arrives while the render runs
        seen.append(fraction)
        _thread.interrupt_main()

    # The signal is checked right after progress returns, so the render stops
    # at the first call, whenever the interpreter would handle it itself.
    with pytest.raises(KeyboardInterrupt):
        renderer.render(scene, progress=ctrl_c, **ONE_BAND)
    assert len(seen) == 1 and seen[0] < 0.01
    again = renderer.render(scene, aovs=("depth",), **SIZE)
    same_result(again, whitted.Renderer().render(scene.copy(), aovs=("depth",), **SIZE))


@pytest.mark.skipif(os.environ.get("WHITTED_SKIP_PIP_TEST") == "1", reason="WHITTED_SKIP_PIP_TEST=1")
def test_pip_install_into_fresh_venv(tmp_path):
    venv = tmp_path / "venv"
    subprocess.run(["/usr/bin/python3", "-m", "venv", "--system-site-packages", str(venv)], check=True)
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    install = subprocess.run([str(venv / "bin" / "pip"), "install", "--no-build-isolation", "--no-index", str(ROOT)],
                             env=env, capture_output=True, text=True, timeout=3000)
    assert install.returncode == 0, install.stdout[-3000:] + install.stderr[-3000:]
    check = subprocess.run([str(venv / "bin" / "python"), "-c",
                            "import whitted; r = whitted.render('scenes/room.xml', width=32, height=24); "
                            "print(whitted.__file__, r.image.shape)"],
                           cwd=ROOT, env=env, capture_output=True, text=True, timeout=600)
    assert check.returncode == 0, check.stderr
    assert str(venv) in check.stdout and "(24, 32, 3)" in check.stdout
