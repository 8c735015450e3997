# Cameras from matrices (K and a camera-to-world pose, OpenCV or OpenGL
# axes), batches of cameras over one upload, and the errors of bad matrices.
import numpy as np
import pytest
import whitted

from conftest import ROOT

W, H = 64, 48
NO_OBJECT = 0xFFFFFFFF
LIGHT = """  <camera><position><x>0</x><y>0</y><z>0</z></position>
    <window_position><x>0</x><y>0</y><z>-1</z></window_position></camera>
  <lights><light><position><x>0</x><y>10</y><z>0</z></position>
    <color><r>1</r><g>1</g><b>1</b><a>1</a></color></light></lights>
"""


def sphere_xml(centre, radius):
    x, y, z = (repr(float(v)) for v in centre)
    return f"""    <object>
      <position><x>{x}</x><y>{y}</y><z>{z}</z></position>
      <diffuse_color><r>0.8</r><g>0.8</g><b>0.8</b><a>1</a></diffuse_color>
      <specular_color><r>1</r><g>1</g><b>1</b><a>1</a></specular_color>
      <properties><type>sphere</type><refraction_coef>1</refraction_coef><transmission_coef>0</transmission_coef>
        <specular_coef>0</specular_coef><diffuse_coef>0.8</diffuse_coef><ambiente_coef>0.15</ambiente_coef>
        <reflective>false</reflective><radius>{radius!r}</radius></properties>
    </object>
"""


def random_pose(rng):
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q @ np.diag(np.sign(np.diag(r)))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    pose = np.eye(4)
    pose[:3, :3] = q
    pose[:3, 3] = rng.uniform(-5, 5, size=3)
    return pose


def project(K, cam_to_world, convention, point):
    """The pixel (u, v) of a scene point, OpenCV pixels, in numpy; and its depth."""
    R, t = cam_to_world[:3, :3], cam_to_world[:3, 3]
    c = R.T @ (point - t)
    if convention == "opengl":  # y up, -z forward -> OpenCV's y down, z forward
        c = c * np.array([1.0, -1.0, -1.0])
    uvw = K @ c
    return uvw[:2] / uvw[2], c[2]


def points_in_view(K, cam_to_world, convention, rng):
    """20 scene points in front of the camera, one per cell of a 5 x 4 grid of
    the image (well apart), at depths 2..8; each with a radius ~2 pixels."""
    cv_to_conv = np.array([1.0, -1.0, -1.0]) if convention == "opengl" else np.ones(3)
    points, radii = [], []
    for row in range(4):
        for col in range(5):
            u = rng.uniform(col * W / 5 + 4, (col + 1) * W / 5 - 4)
            v = rng.uniform(row * H / 4 + 4, (row + 1) * H / 4 - 4)
            z = rng.uniform(2, 8)
            c = z * np.linalg.solve(K, [u, v, 1.0])  # OpenCV camera space
            points.append(cam_to_world[:3, :3] @ (c * cv_to_conv) + cam_to_world[:3, 3])
            radii.append(2.0 * z / min(K[0, 0], K[1, 1]))
    return points, radii


CASES = [
    ("opencv", np.array([[70.0, 0, 29.3], [0, 55.0, 26.1], [0, 0, 1]])),   # fx != fy, principal point off centre
    ("opengl", np.array([[48.0, 0, 36.8], [0, 61.0, 20.2], [0, 0, 1]])),
    ("opencv", np.array([[60.0, 0, 31.5], [0, 60.0, 23.5], [0, 0, 1]])),   # centred, square pixels
]


@pytest.mark.parametrize("convention,K", CASES, ids=["opencv-offcentre", "opengl-offcentre", "opencv-centred"])
def test_spheres_land_on_their_projected_pixels(renderer, convention, K):
    rng = np.random.default_rng(24)
    pose = random_pose(rng)
    points, radii = points_in_view(K, pose, convention, rng)
    xml = "<scene>\n" + LIGHT + "  <objects>\n" + "".join(sphere_xml(p, r) for p, r in zip(points, radii)) + \
        "  </objects>\n</scene>\n"
    scene = whitted.loads(xml)
    scene.camera.set_from_matrices(K, pose, W, H, convention=convention)
    np.testing.assert_allclose(scene.camera.intrinsics(), K, rtol=0, atol=1e-12)
    np.testing.assert_allclose(scene.camera.cam_to_world(convention), pose, rtol=0, atol=1e-12)
    ids = renderer.render(scene, spp=1, aa="uniform", aovs=("object_id",)).aovs["object_id"]
    assert ids.shape == (H, W)
    vs, us = np.mgrid[0:H, 0:W]
    for k, point in enumerate(points):
        (u, v), depth = project(K, pose, convention, point)
        assert depth > 0
        # The pixel holding the projected centre shows sphere k ...
        assert ids[int(round(v)), int(round(u))] == k, (k, u, v)
        # ... and the centroid of its pixels is the projected centre.
        mask = ids == k
        assert mask.sum() >= 4, k
        centroid = np.array([us[mask].mean(), vs[mask].mean()])
        assert np.linalg.norm(centroid - [u, v]) < 0.5, (k, centroid, (u, v))
    assert set(np.unique(ids)) == set(range(len(points))) | {NO_OBJECT}
    # A render at twice the size scales K with it: pixel centre u -> 2u + 0.5.
    big = renderer.render(scene, spp=1, aa="uniform", aovs=("object_id",), width=2 * W, height=2 * H)
    for k, point in enumerate(points):
        (u, v), _ = project(K, pose, convention, point)
        assert big.aovs["object_id"][int(round(2 * v + 0.5)), int(round(2 * u + 0.5))] == k, (k, u, v)


def test_matrices_read_back_and_conventions_agree():
    scene = whitted.load(ROOT / "scenes" / "three_diffuse_spheres.xml")
    cam = scene.camera
    pose = random_pose(np.random.default_rng(7))
    K = np.array([[100.0, 0, 40.0], [0, 90.0, 30.0], [0, 0, 1]])
    cam.set_from_matrices(K, pose, 80, 60, convention="opengl")
    assert cam.has_intrinsics and (cam.width, cam.height) == (80, 60)
    np.testing.assert_allclose(cam.intrinsics(), K, rtol=0, atol=1e-12)
    np.testing.assert_allclose(cam.cam_to_world("opengl"), pose, rtol=0, atol=1e-12)
    flip = np.diag([1.0, -1.0, -1.0, 1.0])
    np.testing.assert_allclose(cam.cam_to_world("opencv"), pose @ flip, rtol=0, atol=1e-12)
    np.testing.assert_allclose(cam.position, pose[:3, 3], rtol=0, atol=0)
    # The same camera set the OpenCV way gives the same device camera: the same pixels.
    other = whitted.load(ROOT / "scenes" / "three_diffuse_spheres.xml")
    other.camera.set_from_matrices(K, pose @ flip, 80, 60)
    r = whitted.Renderer()
    a = r.render(scene, spp=1, aa="uniform").image
    b = r.render(other, spp=1, aa="uniform").image
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-6)
    # A camera without K gives the K its fov means (square pixels, centred).
    plain = whitted.load(ROOT / "scenes" / "three_diffuse_spheres.xml").camera
    f = plain.height / (2 * np.tan(np.radians(plain.fov) / 2))
    np.testing.assert_allclose(plain.intrinsics(),
                               [[f, 0, (plain.width - 1) / 2], [0, f, (plain.height - 1) / 2], [0, 0, 1]], rtol=1e-12)
    # That K set back renders what the fov renders.
    fov_scene = whitted.load(ROOT / "scenes" / "three_diffuse_spheres.xml")
    k_scene = whitted.load(ROOT / "scenes" / "three_diffuse_spheres.xml")
    k_scene.camera.set_from_matrices(plain.intrinsics(), plain.cam_to_world(), plain.width, plain.height)
    a = r.render(fov_scene, spp=1, aa="uniform", width=W, height=H).image
    b = r.render(k_scene, spp=1, aa="uniform", width=W, height=H).image
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-5)
    # clear_intrinsics: the fov again.
    k_scene.camera.clear_intrinsics()
    assert not k_scene.camera.has_intrinsics


def test_scene_with_matrix_camera_saves_intrinsics_and_cli_renders_it_bit_for_bit(tmp_path):
    from conftest import run_cli
    from test_module import read_exr
    scene = whitted.load(ROOT / "scenes" / "three_diffuse_spheres.xml")
    K = np.array([[70.0, 0, 29.3], [0, 55.0, 26.1], [0, 0, 1]])  # fx != fy, principal point off the centre
    scene.camera.set_from_matrices(K, scene.camera.cam_to_world(), W, H)
    path = tmp_path / "k.xml"
    scene.save(path)
    assert '<intrinsics fx="70" fy="55" cx="29.300000000000001" cy="26.100000000000001"/>' in path.read_text()
    assert "<fov>" not in path.read_text()
    back = whitted.load(path)
    assert back.camera.has_intrinsics and back.camera.fov == scene.camera.fov
    np.testing.assert_array_equal(back.camera.intrinsics(), K)
    assert back.to_xml() == scene.to_xml()
    status, err = run_cli("render", path, "-o", tmp_path / "k.exr", "--aov", "depth", "-q")
    assert status == 0, err
    result = whitted.render(scene, aovs=("depth",))
    assert result.image.max() > 0.05
    assert np.array_equal(result.image, read_exr(tmp_path / "k.exr"))
    assert np.array_equal(result.aovs["depth"], read_exr(tmp_path / "k.depth.exr"))
    # The same pose with the fov's centred K renders another image: K is what was used.
    scene.camera.clear_intrinsics()
    assert not np.array_equal(whitted.render(scene).image, result.image)
    # A K the format cannot hold is refused when set.
    with pytest.raises(ValueError, match="within ±1e6"):
        scene.camera.set_from_matrices(np.array([[70.0, 0, 2e6], [0, 55.0, 26.1], [0, 0, 1]]), np.eye(4), W, H)


def test_batch_equals_single_renders_and_uploads_geometry_once():
    rng = np.random.default_rng(5)
    base = whitted.load(ROOT / "scenes" / "three_diffuse_spheres.xml")
    eye = np.array(base.camera.position)
    K = np.array([[62.0, 0, 30.0], [0, 58.0, 25.0], [0, 0, 1]])
    cameras, matrices = [], []
    for i in range(5):
        pose = base.camera.cam_to_world()
        pose[:3, 3] = eye + rng.uniform(-0.3, 0.3, size=3)
        cam = base.camera.copy()
        cam.set_from_matrices(K, pose, W, H)
        cameras.append(cam)
        matrices.append(pose)
    before = base.camera.position
    options = dict(spp=4, aovs=("object_id", "depth"))
    batch_renderer = whitted.Renderer()
    results = batch_renderer.render(base, cameras=cameras, **options)
    assert base.camera.position == before and not base.camera.has_intrinsics  # copies are detached
    assert isinstance(results, list) and len(results) == 5
    uploads = [r.record["uploads"] for r in results]
    assert uploads[0]["geometry"] and uploads[0]["bvh"] and uploads[0]["camera"]
    for u in uploads[1:]:
        assert u == {"renderer": False, "geometry": False, "bvh": False, "materials": False, "lights": False,
                     "camera": True, "textures": False}
    single_renderer = whitted.Renderer()
    for pose, result in zip(matrices, results):
        scene = whitted.load(ROOT / "scenes" / "three_diffuse_spheres.xml")
        scene.camera.set_from_matrices(K, pose, W, H)
        single = single_renderer.render(scene, **options)
        assert result.width == W and result.height == H
        assert np.array_equal(single.image, result.image)
        for name in options["aovs"]:
            assert np.array_equal(single.aovs[name], result.aovs[name]), name
    # After a batch the scene's own camera is sent again.
    after = batch_renderer.render(base, width=W, height=H, **options)
    assert after.record["uploads"]["camera"] and not after.record["uploads"]["geometry"]
    fresh = whitted.Renderer().render(base, width=W, height=H, **options)
    assert np.array_equal(after.image, fresh.image)
    assert not np.array_equal(after.image, results[-1].image)


GOOD_K = [[70.0, 0, 29.3], [0, 55.0, 26.1], [0, 0, 1]]


@pytest.mark.parametrize("K,pose,kwargs,words", [
    ([[0.0, 0, 30], [0, 50, 20], [0, 0, 1]], np.eye(4), {}, r"K: fx \(K\[0\]\[0\]\) must be > 0"),
    ([[50.0, 0, 30], [0, -1, 20], [0, 0, 1]], np.eye(4), {}, r"K: fy"),
    ([[50.0, 0.5, 30], [0, 50, 20], [0, 0, 1]], np.eye(4), {}, r"K: skew"),
    ([[50.0, 0, float("nan")], [0, 50, 20], [0, 0, 1]], np.eye(4), {}, r"K: every value must be finite"),
    ([[50.0, 0, 30], [0, 50, 20]], np.eye(4), {}, r"K: must be a 3x3 matrix, got shape 2x3"),
    ([[50.0, 0, 30], [0, 50, 20], [0, 0, 2]], np.eye(4), {}, r"K: the last row"),
    ("abc", np.eye(4), {}, r"K: must be a 3x3 matrix"),
    (GOOD_K, np.diag([2.0, 2, 2, 1]), {}, r"cam_to_world: the rotation part must be orthonormal"),
    (GOOD_K, np.diag([1.0, 1, -1, 1]), {}, r"cam_to_world: the rotation part must have determinant \+1"),
    (GOOD_K, np.eye(3), {}, r"cam_to_world: must be a 4x4 matrix, got shape 3x3"),
    (GOOD_K, np.where(np.eye(4) == 1, np.inf, 0), {}, r"cam_to_world: every value must be finite"),
    (GOOD_K, np.array([[1.0, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]]), {}, r"cam_to_world: the last row"),
    (GOOD_K, np.eye(4), dict(convention="blender"), r"convention: must be 'opencv' or 'opengl', got 'blender'"),
    (GOOD_K, np.eye(4), dict(width=0), r"width: must be in 1\.\.16384, got 0"),
    (GOOD_K, np.eye(4), dict(height=-4), r"height: must be in 1\.\.16384"),
])
def test_bad_matrices_raise_value_error_naming_the_field(K, pose, kwargs, words):
    scene = whitted.load(ROOT / "scenes" / "three_diffuse_spheres.xml")
    before = scene.camera.position
    size = dict(width=W, height=H)
    size.update(kwargs)
    with pytest.raises(ValueError, match=words):
        scene.camera.set_from_matrices(K, pose, **size)
    assert scene.camera.position == before and not scene.camera.has_intrinsics


def test_bad_camera_lists_raise_value_error(renderer):
    scene = whitted.load(ROOT / "scenes" / "three_diffuse_spheres.xml")
    small = scene.camera.copy()
    small.width = 32
    for cameras, words in [([], "cameras: the list is empty"), ([1, 2], "cameras: must be a list of Camera"),
                           ("abc", "cameras: must be a list of Camera"),
                           ([scene.camera.copy(), small], "cameras: of different image sizes")]:
        with pytest.raises(ValueError, match=words):
            renderer.render(scene, cameras=cameras, spp=1)
    with pytest.raises(ValueError, match="intrinsics: an orthographic camera"):
        cam = scene.camera.copy()
        cam.projection = "orthographic"
        cam.intrinsics()


def test_seed_changes_only_the_sample_patterns_reproducibly(renderer):
    scene = whitted.load(ROOT / "scenes" / "three_diffuse_spheres.xml")
    options = dict(width=W, height=H, spp=4, aa="uniform")
    default = renderer.render(scene, **options).image
    assert np.array_equal(renderer.render(scene, seed=0, **options).image, default)  # default = seed 0
    seeded = renderer.render(scene, seed=12345, **options).image
    assert not np.array_equal(seeded, default)
    assert np.array_equal(whitted.Renderer().render(scene, seed=12345, **options).image, seeded)  # another renderer
    region = renderer.render(scene, seed=12345, region=(8, 4, 40, 30), **options).image  # a tile of it
    assert np.array_equal(region, seeded[4:30, 8:40])
    for bad in (-1, 2 ** 32, 1.5, "7", True):
        with pytest.raises(ValueError, match="seed: must be"):
            renderer.render(scene, seed=bad, **options)
