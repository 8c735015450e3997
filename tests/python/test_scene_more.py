# More of building scenes in Python (host/python/README.md "Building a
# scene"): textures on a Material from files and numpy arrays, saved beside
# the scene file.
import numpy as np
import pytest
import whitted

from conftest import ROOT, run_cli
from test_module import read_exr

SIZE = dict(width=80, height=60)


def lit_scene():
    scene = whitted.Scene()
    scene.camera.position = (0, 1.0, 4.0)
    scene.camera.look_at = (0, 0.2, 0)
    scene.camera.width, scene.camera.height = SIZE["width"], SIZE["height"]
    scene.ambient_light = (0.2, 0.2, 0.2)
    scene.add_light(position=(2, 4, 3), color=(1, 1, 1))
    return scene


def gradient(h, w):
    """An (h, w, 3) float pattern with every texel different."""
    y, x = np.mgrid[0:h, 0:w]
    return np.stack([x / (w - 1), y / (h - 1), 0.5 + 0.5 * np.sin(x * 0.7 + y * 0.3)], axis=2).astype(np.float32)


def textured_scene():
    scene = lit_scene()
    srgb = (gradient(16, 32) * 255).astype(np.uint8)
    scene.add_sphere((-0.7, 0.4, 0), 0.6, name="ball", material=whitted.Material(diffuse_texture=srgb))
    linear = np.concatenate([gradient(8, 8)[::-1] * 2.0, np.ones((8, 8, 1), np.float32)], axis=2)  # RGBA, > 1
    scene.add_plane((0, -0.2, 0), (0, 1, 0), name="floor",
                    material=whitted.Material(diffuse_texture=linear, texture_scale=0.7))
    bumps = np.zeros((8, 8, 3), np.uint8)
    bumps[..., 0] = np.linspace(60, 200, 8).astype(np.uint8)[None, :]
    bumps[..., 1] = 128
    bumps[..., 2] = 220
    scene.add_box((0.3, -0.2, -0.3), (0.6, 0.6, 0.6), name="crate",
                  material=whitted.Material(diffuse_color=(0.8, 0.7, 0.5), normal_map=bumps,
                                            emission_texture=srgb, emission=(0.2, 0.1, 0.0)))
    return scene


def test_array_textures_save_beside_the_scene_and_render_bit_for_bit(tmp_path):
    scene = textured_scene()
    assert scene.objects[0].material.textured
    assert scene.objects[0].material.diffuse_texture == "<array 16x32>"
    path = tmp_path / "tex.xml"
    scene.save(path)
    text = path.read_text()
    for name in ("tex.ball.diffuse_texture.png", "tex.floor.diffuse_texture.exr", "tex.crate.normal_map.png",
                 "tex.crate.emission_texture.png"):
        assert f">{name}<" in text, name
        assert (tmp_path / name).is_file(), name
    status, err = run_cli("render", path, "-o", tmp_path / "x.exr", "--aov", "diffuse", "-q")
    assert status == 0, err
    result = whitted.render(scene, aovs=("diffuse",))
    assert np.array_equal(result.image, read_exr(tmp_path / "x.exr"))
    assert np.array_equal(result.aovs["diffuse"], read_exr(tmp_path / "x.diffuse.exr"))
    # The textures show: without them the image is another.
    plain = lit_scene()
    plain.add_sphere((-0.7, 0.4, 0), 0.6)
    plain.add_plane((0, -0.2, 0), (0, 1, 0))
    plain.add_box((0.3, -0.2, -0.3), (0.6, 0.6, 0.6), material=whitted.Material(diffuse_color=(0.8, 0.7, 0.5)))
    assert np.abs(whitted.render(plain).image - result.image).max() > 0.1
    # The saved scene loads back with the files; it names them (so to_xml works on it).
    back = whitted.load(path)
    assert back.objects[0].material.diffuse_texture.endswith("tex.ball.diffuse_texture.png")
    # The scene itself still has array textures, which to_xml and pickle cannot name.
    with pytest.raises(ValueError, match="made from an array.*save"):
        scene.to_xml()


# A roughness texture from an array (its green channel times roughness, scenes/README.md "Textures"): saved
# beside the scene, `whitted render` of the file equals the Python render bit for bit, and the texture changes the
# image against the same roughness without it.
def test_roughness_texture_from_an_array_saves_and_renders_bit_for_bit(tmp_path):
    def scene_with(texture):
        scene = lit_scene()
        scene.add_sphere((-0.7, 0.4, 0), 0.6, name="ball")
        scene.add_box((0.3, -0.2, -0.3), (0.6, 0.6, 0.6), name="crate")
        scene.add_plane((0, -0.2, 0), (0, 1, 0), name="floor",
                        material=whitted.Material(diffuse=0.2, reflection=0.8, roughness=0.4,
                                                  roughness_texture=texture))
        return scene
    green = np.zeros((16, 16, 3), np.float32)
    green[:, 8:, 1] = 1.0  # rough on the right half, a mirror on the left
    scene = scene_with(green)
    assert scene.objects[2].material.roughness_texture == "<array 16x16>"
    path = tmp_path / "rough.xml"
    scene.save(path)
    assert ">rough.floor.roughness_texture.exr<" in path.read_text()
    status, err = run_cli("render", path, "-o", tmp_path / "x.exr", "--aov", "none", "-q")
    assert status == 0, err
    image = whitted.render(scene, aovs="none").image
    assert np.array_equal(image, read_exr(tmp_path / "x.exr"))
    assert np.abs(whitted.render(scene_with(None), aovs="none").image - image).max() > 0.05


def test_uint8_is_srgb_and_float_is_linear_and_files_read_as_the_loader_reads_them(tmp_path):
    codes = (gradient(8, 16) * 255).astype(np.uint8)
    # IEC 61966-2-1's decoding, the one PNG files get.
    c = codes / 255.0
    linear = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4).astype(np.float32)
    images = []
    for texture in (codes, linear):
        scene = lit_scene()
        scene.add_sphere((0, 0.3, 0), 0.8, material=whitted.Material(diffuse_texture=texture))
        images.append(whitted.render(scene, spp=1, aa="uniform", aovs=("diffuse",)).aovs["diffuse"])
    # Both hold the same linear values up to half-float rounding.
    assert images[0].max() > 0.3
    np.testing.assert_allclose(images[0], images[1], rtol=2e-3, atol=1e-4)
    # A file path reads as <diffuse_texture> does.
    tex = ROOT / "scenes" / "textures"
    png = sorted(tex.glob("*.png"))[0]
    m = whitted.Material(diffuse_texture=png)
    assert m.diffuse_texture == str(png)
    scene = lit_scene()
    scene.add_sphere((0, 0.3, 0), 0.8, material=m)
    scene.save(tmp_path / "f.xml")
    saved = whitted.load(tmp_path / "f.xml").objects[0].material.diffuse_texture  # as the file names it: relative
    assert (tmp_path / saved).resolve() == png.resolve()
    m.diffuse_texture = None
    assert not m.textured


@pytest.mark.parametrize("value, error", [
    (np.zeros((4, 4), np.uint8), r"\(H, W, 3\) or \(H, W, 4\).*got shape \(4, 4\)"),
    (np.zeros((4, 4, 2), np.float32), r"got shape \(4, 4, 2\)"),
    (np.zeros((4, 4, 3), np.int32), "got dtype int32"),
    (np.full((2, 2, 3), np.nan, np.float32), "finite values.*got nan at texel 0"),
    (np.full((2, 2, 3), 1e5, np.float32), "within ±65504"),
    (np.zeros((8193, 8193, 3), np.uint8), "2\\^26"),
    ("no/such/file.png", "texture file .*no/such/file.png\" does not exist"),
    (3, "a file path or an"),
])
def test_bad_textures_name_the_field(value, error):
    with pytest.raises(ValueError, match="Material.normal_map: .*" + error):
        whitted.Material(normal_map=value)


def test_textured_material_needs_uvs_on_a_mesh():
    scene = lit_scene()
    with pytest.raises(ValueError, match="add_mesh.material"):
        scene.add_mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float), np.array([[0, 1, 2]]),
                       material=whitted.Material(diffuse_texture=np.zeros((2, 2, 3), np.uint8)))


def test_add_file_gives_the_objects_of_file_and_saves_them_as_file(tmp_path):
    scene = lit_scene()
    move = np.eye(4)
    move[:3, :3] = np.diag([1.5, 1.0, 1.5])
    move[:3, 3] = (0.8, -0.2, 0)
    pyramid = scene.add_file(ROOT / "tests" / "meshes" / "pyramid.obj", transform=move)
    assert [o.type for o in pyramid] == ["mesh"]
    pyramid[0].reflection = 0.4  # (not the colour: a file object keeps its file's, scenes/README.md "Materials")
    sphere = scene.add_file(ROOT / "tests" / "meshes" / "uv_sphere_12x24.obj")
    sphere[0].position = (-0.8, 0.4, 0)
    path = tmp_path / "files.xml"
    scene.save(path)
    text = path.read_text()
    assert text.count("<file>") == 2 and "<polygons>" not in text and "<matrix>" in text
    status, err = run_cli("render", path, "-o", tmp_path / "x.exr", "--aov", "object_id", "-q")
    assert status == 0, err
    result = whitted.render(scene, aovs=("object_id",))
    assert np.array_equal(result.image, read_exr(tmp_path / "x.exr"))
    ids = result.aovs["object_id"]
    assert np.array_equal(ids, read_exr(tmp_path / "x.object_id.exr"))
    assert (ids == 0).sum() > 50 and (ids == 1).sum() > 50  # both in view
    # The pyramid's apex, moved by the matrix: the same as the vertices moved by add_mesh's transform.
    v = np.array([[-0.5, 0, -0.5], [0.5, 0, -0.5], [0.5, 0, 0.5], [-0.5, 0, 0.5], [0, 1, 0]])
    f = np.array([[3, 2, 4], [2, 1, 4], [1, 0, 4], [0, 3, 4], [0, 1, 2], [0, 2, 3]])
    inline = lit_scene()
    inline.add_mesh(v, f, transform=move, material=pyramid[0].material)
    inline.add_file(ROOT / "tests" / "meshes" / "uv_sphere_12x24.obj")[0].position = (-0.8, 0.4, 0)
    assert np.array_equal(whitted.render(inline).image, result.image)


def test_add_file_part_and_errors():
    scene = lit_scene()
    gltf = ROOT / "scenes" / "pictures" / "authored.gltf"
    with pytest.warns(UserWarning, match="add_file: mesh file .*degenerate"):
        part = scene.add_file(gltf, part="mesh 0 primitive 0")
    assert len(part) == 1 and len(scene.objects) == 1
    assert '<file part="mesh 0 primitive 0">' in scene.to_xml()
    with pytest.raises(ValueError, match=r'add_file: mesh file ".*authored.gltf": part "mesh 9 primitive 0": '
                                         r"the file has no mesh 9"):
        scene.add_file(gltf, part="mesh 9 primitive 0")
    with pytest.raises(ValueError, match='add_file: mesh file ".*nope.obj" does not exist'):
        scene.add_file("nope.obj")
    with pytest.raises(ValueError, match="add_file.transform"):
        scene.add_file(gltf, transform=np.zeros((4, 4)))
    assert len(scene.objects) == 1


def test_transform_moves_a_sphere_as_if_built_there_and_reports_the_upload():
    renderer = whitted.Renderer()
    scene = lit_scene()
    ball = scene.add_sphere((-0.5, 0.3, 0.1), 0.5, name="ball")
    tiles = (gradient(16, 16) * 255).astype(np.uint8)
    scene.add_box((0.3, -0.2, -0.3), (0.6, 0.6, 0.6), material=whitted.Material(diffuse_texture=tiles))
    first = renderer.render(scene, spp=1, aa="uniform")
    assert first.record["uploads"]["textures"]
    move = np.eye(4)
    move[:3, 3] = (0.4, 0.25, -0.5)
    ball.transform = move
    moved = renderer.render(scene, spp=1, aa="uniform")
    # A transform re-packs the shapes and rebuilds the BVH (one flat BVH over all primitives), on the same pipeline.
    assert moved.record["uploads"]["geometry"] and moved.record["uploads"]["bvh"]
    # The textures stay on the device (the same ones in the same slots).
    assert not moved.record["uploads"]["renderer"] and not moved.record["uploads"]["textures"]
    there = lit_scene()
    there.add_sphere(tuple(np.array([-0.5, 0.3, 0.1]) + move[:3, 3]), 0.5, name="ball")
    there.add_box((0.3, -0.2, -0.3), (0.6, 0.6, 0.6), material=whitted.Material(diffuse_texture=tiles))
    assert np.array_equal(moved.image, renderer.render(there, spp=1, aa="uniform").image)
    assert not np.array_equal(moved.image, first.image)
    np.testing.assert_array_equal(ball.transform, move)
    # Absolute, not accumulated: the identity puts it back; a uniform scale scales the radius.
    # (Each set applies the new transform after the old one undone, to the last bits of a double.)
    ball.transform = np.eye(4)
    assert ball.position == pytest.approx((-0.5, 0.3, 0.1), abs=1e-15) and ball.radius == 0.5
    ball.transform = np.diag([2.0, 2.0, 2.0, 1.0])
    assert ball.radius == 1.0 and ball.position == pytest.approx((-1.0, 0.6, 0.2), abs=1e-15)
    with pytest.raises(ValueError, match="Object.transform: a sphere takes only a rotation, a uniform scale"):
        ball.transform = np.diag([1.0, 2.0, 1.0, 1.0])
    assert ball.radius == 1.0  # unchanged
    with pytest.raises(ValueError, match="Object.transform: a box stays axis-aligned"):
        scene.objects[1].transform = np.array([[0, -1, 0, 0], [1, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])


def test_transform_of_a_mesh_equals_add_mesh_with_that_transform():
    v = np.array([[-0.5, 0, -0.5], [0.5, 0, -0.5], [0.5, 0, 0.5], [-0.5, 0, 0.5], [0, 1, 0]])
    f = np.array([[3, 2, 4], [2, 1, 4], [1, 0, 4], [0, 3, 4], [0, 1, 2], [0, 2, 3]])
    n = v - [0, 0.3, 0]
    angle = 0.6
    m = np.eye(4)
    m[:3, :3] = [[np.cos(angle), 0, np.sin(angle)], [0, 1, 0], [-np.sin(angle), 0, np.cos(angle)]]
    m[:3, :3] *= [[1.3], [0.8], [1.0]]  # rows scaled: not uniform, fine for a mesh
    m[:3, 3] = (0.2, -0.1, 0.3)
    a, b = lit_scene(), lit_scene()
    a.add_mesh(v, f, normals=n).transform = m
    b.add_mesh(v, f, normals=n, transform=m)
    xa, xb = a.to_xml(), b.to_xml()
    assert xa == xb


def pyramid_arrays():
    v = np.array([[-0.5, 0, -0.5], [0.5, 0, -0.5], [0.5, 0, 0.5], [-0.5, 0, 0.5], [0, 1, 0]])
    f = np.array([[3, 2, 4], [2, 1, 4], [1, 0, 4], [0, 3, 4], [0, 1, 2], [0, 2, 3]])
    n = (v - [0, 0.3, 0]) / np.linalg.norm(v - [0, 0.3, 0], axis=1, keepdims=True)
    uv = v[:, [0, 2]] + 0.5
    return v, f, n, uv


def test_mesh_from_a_trimesh_like_object_equals_add_mesh_of_its_arrays():
    """Mesh.from_trimesh reads .vertices, .faces, .vertex_normals and .visual.uv (what trimesh.Trimesh has);
    a stand-in with those attributes runs it without trimesh installed."""
    from types import SimpleNamespace
    v, f, n, uv = pyramid_arrays()
    stand_in = SimpleNamespace(vertices=v, faces=f, vertex_normals=n, visual=SimpleNamespace(uv=uv))
    mesh = whitted.Mesh.from_trimesh(stand_in)
    assert mesh.normals is not None and mesh.uvs is not None
    a, b = lit_scene(), lit_scene()
    a.add_mesh(mesh, material=whitted.Material(diffuse_texture=np.zeros((2, 2, 3), np.uint8)))
    b.add_mesh(v, f, normals=n, uvs=uv, material=whitted.Material(diffuse_texture=np.zeros((2, 2, 3), np.uint8)))
    assert a.objects[0].type == "mesh"
    assert whitted.Mesh.from_trimesh(stand_in, normals=False).normals is None
    flat = lit_scene()
    flat.add_mesh(whitted.Mesh(v, f))
    assert "<normal" not in flat.to_xml() and "<uv" not in flat.to_xml()
    c = lit_scene()
    c.add_mesh(whitted.Mesh.from_trimesh(stand_in))
    d = lit_scene()
    d.add_mesh(v, f, normals=n, uvs=uv)
    assert c.to_xml() == d.to_xml()
    with pytest.raises(TypeError, match="from_trimesh: expected a trimesh.Trimesh"):
        whitted.Mesh.from_trimesh(3)
    with pytest.raises(TypeError, match="brings its own faces"):
        flat.add_mesh(whitted.Mesh(v, f), f)


def test_mesh_from_trimesh():
    trimesh = pytest.importorskip(
        "trimesh", reason="trimesh is not installed (python3-trimesh is not in Debian 12's archive, so install_deps.sh cannot list it)")
    box = trimesh.creation.box(extents=(0.8, 0.5, 0.6))
    scene = lit_scene()
    handle = scene.add_mesh(whitted.Mesh.from_trimesh(box, normals=False), name="box")
    result = whitted.render(scene, aovs=("object_id",), spp=1, aa="uniform")
    assert (result.aovs["object_id"] == 0).sum() > 100 and handle.type == "mesh"
    inline = lit_scene()
    inline.add_mesh(np.asarray(box.vertices), np.asarray(box.faces), name="box")
    assert inline.to_xml() == scene.to_xml()
