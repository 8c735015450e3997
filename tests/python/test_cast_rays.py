# Renderer.cast_rays (host/python/README.md "Ray casting"): rays cast on the
# device by the tracer's own closest-hit query, checked against analytic hits,
# the object_id mask of a render, a numpy mesh's triangles and cameras set
# from K and a pose; and Camera.rays, the renderer's camera rays.
import math

import numpy as np
import pytest
import whitted

NO_HIT = 0xFFFFFFFF
SIZE = dict(width=160, height=120)


def unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def sphere_and_box():
    scene = whitted.Scene()
    scene.add_sphere((0.5, -0.25, 0.0), 1.25, name="ball")
    scene.add_box((3.0, -1.0, -0.5), (2.0, 1.5, 1.0), name="crate")  # min corner, size
    return scene


def names(renderer, scene):
    """object id -> name, from the masks legend of a small render of `scene`."""
    result = renderer.render(scene, width=8, height=6, spp=1, aovs=("object_id",))
    return {k: v["name"] for k, v in result.masks.items()}


def test_sphere_hits_match_the_analytic_ones(renderer):
    rng = np.random.default_rng(1)
    scene = sphere_and_box()
    centre, radius = np.array([0.5, -0.25, 0.0]), 1.25
    n = 2000
    # Origins around the sphere, 3 to 6 radii away; directions (not unit, of
    # lengths 0.5 to 2) aimed at points inside it, so every ray hits.
    # On the -x side, out of the box's way (it starts at x = 3).
    around = unit(rng.normal(size=(n, 3)))
    around[:, 0] = -np.abs(around[:, 0])
    origins = centre + around * rng.uniform(3, 6, (n, 1)) * radius
    targets = centre + unit(rng.normal(size=(n, 3))) * rng.uniform(0, 0.9, (n, 1)) * radius
    directions = unit(targets - origins) * rng.uniform(0.5, 2.0, (n, 1))
    hits = renderer.cast_rays(scene, origins, directions)
    # Nearest root of |o + t d - c|^2 = r^2, in float64.
    oc = origins - centre
    a = np.sum(directions * directions, axis=1)
    b = np.sum(oc * directions, axis=1)
    c = np.sum(oc * oc, axis=1) - radius * radius
    t = (-b - np.sqrt(b * b - a * c)) / a
    normal = (origins + t[:, None] * directions - centre) / radius
    ids = names(renderer, scene)
    assert set(hits) == {"t", "object_id", "primitive_id", "normal", "uv"}
    assert hits["t"].dtype == np.float32 and hits["t"].shape == (n,)
    assert hits["object_id"].dtype == np.uint32 and hits["primitive_id"].dtype == np.uint32
    assert hits["normal"].shape == (n, 3) and hits["uv"].shape == (n, 2)
    assert all(ids[k] == "ball" for k in hits["object_id"])
    assert np.all(hits["primitive_id"] == 0)
    np.testing.assert_allclose(hits["t"], t, rtol=1e-5)
    np.testing.assert_allclose(hits["normal"], normal, atol=1e-5)  # unit vectors: relative 1e-5
    # The sphere's mapping (shaders/shapes/sphere.glsl): u the longitude from +x towards +z, v from the south pole.
    u = np.arctan2(normal[:, 2], normal[:, 0]) / (2 * math.pi) % 1.0
    v = 0.5 + np.arcsin(np.clip(normal[:, 1], -1, 1)) / math.pi
    away_from_seam = np.minimum(u, 1 - u) > 1e-3
    np.testing.assert_allclose(hits["uv"][away_from_seam, 0], u[away_from_seam], atol=1e-5)
    # v is the shader's asin: lavapipe's is within 4e-4 radians (measured 3.9e-4; Vulkan lets asin inherit
    # atan2's 4096 ulp), 1.3e-4 in v; every other step is float's.
    np.testing.assert_allclose(hits["uv"][:, 1], v, atol=1.5e-4)


def test_box_hits_match_the_analytic_ones(renderer):
    rng = np.random.default_rng(2)
    scene = sphere_and_box()
    lo, hi = np.array([3.0, -1.0, -0.5]), np.array([5.0, 0.5, 0.5])
    n = 600
    # Rays straight at each face of the box, from 2 units off it, at points
    # inside the face: t = 2 / |d| and the face's outward normal.
    expected_t, expected_n, origins, directions = [], [], [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            m = n // 6
            p = rng.uniform(lo + 0.01 * (hi - lo), hi - 0.01 * (hi - lo), (m, 3))
            p[:, axis] = hi[axis] if sign > 0 else lo[axis]
            face_normal = np.zeros(3)
            face_normal[axis] = sign
            scale = rng.uniform(0.25, 4.0, (m, 1))
            origins.append(p + 2.0 * face_normal)
            directions.append(-face_normal * scale)
            expected_t.append(2.0 / scale[:, 0])
            expected_n.append(np.tile(face_normal, (m, 1)))
    origins, directions = np.vstack(origins), np.vstack(directions)
    # The sphere lies in the way of rays towards the -x face: those start at x = 1 (2 off the face)
    # and the sphere reaches x = 1.75, so they are left out.
    keep = ~((origins[:, 0] < 2) & (np.linalg.norm(origins - [0.5, -0.25, 0.0], axis=1) < 1.3))
    hits = renderer.cast_rays(scene, origins[keep].astype(np.float32), directions[keep].astype(np.float32))
    ids = names(renderer, scene)
    assert all(ids[k] == "crate" for k in hits["object_id"])
    np.testing.assert_allclose(hits["t"], np.concatenate(expected_t)[keep], rtol=1e-5)
    np.testing.assert_array_equal(hits["normal"], np.vstack(expected_n)[keep])


def test_misses_give_inf_and_no_object(renderer):
    scene = sphere_and_box()
    origins = np.array([[0.0, 5.0, 0.0], [0.5, -0.25, 5.0], [0.5, -0.25, 5.0], [4.0, 0.0, -3.0]])
    directions = np.array([[0.0, 1.0, 0.0],     # away from everything
                           [0.0, 0.0, -1.0],    # at the sphere, stopped short by t_max
                           [1.0, 0.0, 0.0],     # past everything
                           [0.0, 0.0, 2.0]])    # at the box, stopped short: t_max is in units of d
    hits = renderer.cast_rays(scene, origins, directions, t_max=np.array([np.inf, 3.7, np.inf, 1.2]))
    assert np.all(np.isinf(hits["t"]))
    assert np.all(hits["object_id"] == NO_HIT) and np.all(hits["primitive_id"] == NO_HIT)
    assert not hits["normal"].any() and not hits["uv"].any()
    # The same rays a little longer hit: the sphere at 5 - 1.25, the box at (3 - 0.5) / 2.
    longer = renderer.cast_rays(scene, origins[[1, 3]], directions[[1, 3]], t_max=3.76)
    np.testing.assert_allclose(longer["t"], [3.75, 1.25], rtol=1e-6)


def test_a_million_rays_in_one_call(renderer):
    # 1.1M rays down onto the sphere from a grid: two bands (render/ray_cast.h, 2^20 rays a band).
    scene = sphere_and_box()
    side = 1049  # 1049^2 = 1,100,401 rays
    x, z = np.meshgrid(np.linspace(-1.0, 2.0, side), np.linspace(-1.5, 1.5, side))
    origins = np.column_stack([x.ravel(), np.full(x.size, 4.0), z.ravel()]).astype(np.float32)
    directions = np.tile(np.float32([0, -1, 0]), (x.size, 1))
    hits = renderer.cast_rays(scene, origins, directions)
    r2 = (origins[:, 0].astype(np.float64) - 0.5) ** 2 + origins[:, 2].astype(np.float64) ** 2
    clear = np.abs(np.sqrt(r2) - 1.25) > 1e-4  # rays grazing the silhouette may go either way
    inside = r2 < 1.25 ** 2
    ids = names(renderer, scene)
    ball = next(k for k, v in ids.items() if v == "ball")
    assert np.all(hits["object_id"][clear & inside] == ball)
    assert np.all(hits["object_id"][clear & ~inside] == NO_HIT)
    t = 4.0 - (-0.25 + np.sqrt(np.maximum(1.25 ** 2 - r2, 0)))
    np.testing.assert_allclose(hits["t"][clear & inside], t[clear & inside], rtol=1e-5)
    assert np.all(np.isinf(hits["t"][clear & ~inside]))


def test_object_ids_are_the_masks_ids(renderer):
    """Every pixel centre's ray (Camera.rays) hits what the object_id mask of a render shows, with the
    legend's ids, after a removal has made the ids differ from the objects' indices."""
    scene = whitted.Scene()
    scene.camera.position = (0.4, 1.5, 6.0)
    scene.camera.look_at = (0.5, 0.0, 0.0)
    scene.camera.width, scene.camera.height = SIZE["width"], SIZE["height"]
    gone = scene.add_sphere((-3, 0, 0), 0.5, name="gone")
    scene.add_sphere((-0.8, 0.2, 0.0), 0.8, name="ball")
    scene.add_box((0.6, -0.7, -0.6), (1.2, 1.2, 1.2), name="crate")
    scene.add_cylinder((2.4, -0.7, 0.2), (0, 1, 0), 0.4, 1.3, name="post")
    scene.add_plane((0, -0.7, 0), (0, 1, 0), name="floor")
    scene.remove(gone)
    result = renderer.render(scene, spp=1, aa="uniform", aovs=("object_id", "depth"))
    assert set(result.masks) == {1, 2, 3, 4}
    origins, directions = scene.camera.rays()
    hits = renderer.cast_rays(scene, origins, directions)
    mask = result.aovs["object_id"]
    cast = hits["object_id"].reshape(mask.shape)
    np.testing.assert_array_equal(cast, mask)
    assert set(np.unique(cast)) == {1, 2, 3, 4, NO_HIT}  # every object seen, and the sky where rays miss


def grid_mesh(n=6):
    """An n x n grid of quads in the plane y = 0, two triangles each, wound to face +y."""
    xs = np.linspace(-1.0, 1.0, n + 1)
    vertices = np.array([[x, 0.0, z] for z in xs for x in xs])
    faces = []
    for j in range(n):
        for i in range(n):
            a, b, c, d = j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i, (j + 1) * (n + 1) + i + 1
            faces += [[a, c, b], [b, c, d]]
    return vertices, np.array(faces, dtype=np.int64)


def test_mesh_triangles_are_numbered_as_their_faces(renderer):
    vertices, faces = grid_mesh()
    scene = whitted.Scene()
    scene.add_sphere((0, -3, 0), 0.5, name="below")
    scene.add_mesh(vertices, faces, name="grid")
    chosen = np.array([0, 1, 7, 30, 41, 71])
    centroids = vertices[faces[chosen]].mean(axis=1)
    origins = centroids + [0.05, 2.0, -0.03]
    hits = renderer.cast_rays(scene, origins, np.tile([-0.05, -2.0, 0.03], (len(chosen), 1)))
    ids = names(renderer, scene)
    assert [ids[k] for k in hits["object_id"]] == ["grid"] * len(chosen)
    np.testing.assert_array_equal(hits["primitive_id"], chosen)
    np.testing.assert_allclose(hits["t"], 1.0, rtol=1e-5)
    np.testing.assert_allclose(hits["normal"], np.tile([0.0, 1.0, 0.0], (len(chosen), 1)), atol=1e-6)
    # From below: the same triangles, their normal still the winding's (+y), not turned to the ray.
    under = renderer.cast_rays(scene, centroids - [0, 1, 0], np.tile([0.0, 1.0, 0.0], (len(chosen), 1)))
    np.testing.assert_array_equal(under["primitive_id"], chosen)
    np.testing.assert_allclose(under["normal"][:, 1], 1.0, atol=1e-6)


def test_a_large_meshs_triangles_keep_their_numbers_in_a_bvh_part():
    """After an edit, a renderer gives a mesh of 4,096 triangles or more a BVH part of its own, its triangles stored in
    the part's leaf order: cast_rays still names each by its face index, and a second edit reuses the part."""
    renderer = whitted.Renderer()
    vertices, faces = grid_mesh(48)  # 4,608 triangles
    scene = whitted.Scene()
    ball = scene.add_sphere((0, -3, 0), 0.5, name="below")
    scene.add_mesh(vertices, faces, name="grid")
    renderer.render(scene, width=16, height=12, spp=1)
    chosen = np.random.default_rng(3).choice(len(faces), 200, replace=False)
    centroids = vertices[faces[chosen]].mean(axis=1)
    for step, (reused, built) in enumerate([(0, 4608 + 1), (1, 1)]):
        move = np.eye(4)
        move[0, 3] = 0.1 * (step + 1)
        ball.transform = move
        record = renderer.render(scene, width=16, height=12, spp=1).record
        assert record["bvh"]["parts"] == 1
        assert (record["bvh"]["parts_reused"], record["bvh"]["primitives_built"]) == (reused, built)
        hits = renderer.cast_rays(scene, centroids + [0.0, 2.0, 0.0], np.tile([0.0, -1.0, 0.0], (len(chosen), 1)))
        np.testing.assert_array_equal(hits["primitive_id"], chosen)
        np.testing.assert_allclose(hits["t"], 2.0, rtol=1e-5)


CSG_SCENE = """<scene><camera><position x="0" y="0" z="5"/><window_position x="0" y="0" z="4"/><up x="0" y="1" z="0"/>
<fov>60</fov><width>32</width><height>24</height></camera><ambient_light r="0" g="0" b="0"/><lights></lights>
<objects>
 <object><name>ball</name><position x="-4" y="0" z="0"/><properties><type>sphere</type><radius>0.5</radius></properties>
 </object>
 <object><name>bitten</name><properties><type>csg</type><operation>difference</operation></properties>
  <objects>
   <object><position x="-1" y="-1" z="-1"/><properties><type>box</type><size x="2" y="2" z="2"/></properties></object>
   <object><position x="1" y="0" z="0"/><properties><type>sphere</type><radius>0.5</radius></properties></object>
   <object><position x="0" y="0" z="0"/>
    <properties><type>cylinder</type><radius>0.3</radius><height>2</height><axis x="0" y="1" z="0"/></properties>
   </object>
  </objects>
 </object>
</objects></scene>"""


def test_csg_hits_name_the_leaf_struck(renderer):
    """A csg object's primitive_id is the place of the leaf struck among its leaves, in the order the file lists
    them (the box 0, the bite 1, the drill 2); its normal is the solid's outward one (out of the cavities)."""
    scene = whitted.loads(CSG_SCENE)
    origins = np.array([[5, 0, 0], [5, 0.8, 0], [0, 5, 0], [0, 5, 0.6]], dtype=float)
    directions = np.array([[-1, 0, 0], [-1, 0, 0], [0, -1, 0], [0, -1, 0]], dtype=float)
    hits = renderer.cast_rays(scene, origins, directions)
    ids = names(renderer, scene)
    assert [ids[k] for k in hits["object_id"]] == ["bitten"] * 4
    np.testing.assert_array_equal(hits["primitive_id"], [1, 0, 2, 0])
    np.testing.assert_allclose(hits["t"], [4.5, 4.0, 5.0, 4.0], rtol=1e-6)
    np.testing.assert_allclose(hits["normal"], [[1, 0, 0], [1, 0, 0], [0, 1, 0], [0, 1, 0]], atol=1e-6)


BAD = [
    (dict(origins=np.zeros((4, 2))), "origins: must be an \\(N, 3\\) array, got shape \\(4, 2\\)"),
    (dict(origins=np.zeros(3)), "origins: must be an \\(N, 3\\) array, got shape \\(3\\)"),
    (dict(directions=np.ones((5, 3))), "directions: 5 rows, but origins has 4"),
    (dict(origins=[["a", "b", "c"]] * 4), "origins: must be an \\(N, 3\\) array of numbers"),
    (dict(origins=np.array([[0, 0, 0]] * 3 + [[0, np.nan, 0]])), "origins: row 3 .* is not finite"),
    (dict(directions=np.array([[1, 0, 0]] * 3 + [[0, np.inf, 0]])), "directions: row 3 .* is not finite"),
    (dict(directions=np.array([[1, 0, 0], [0, 0, 0], [1, 0, 0], [1, 0, 0]])), "directions: row 1 has length 0"),
    (dict(origins=np.array([[1e39, 0, 0]] * 4)), "origins: row 0 .* is not finite"),
    (dict(t_max=0.0), "t_max: must be > 0"),
    (dict(t_max=-1.0), "t_max: must be > 0"),
    (dict(t_max=float("nan")), "t_max: must be > 0"),
    (dict(t_max=np.array([1.0, 2.0, 0.0, 1.0])), "t_max: must be > 0 \\(inf allowed\\), got 0.0+ for ray 2"),
    (dict(t_max=np.ones(3)), "t_max: must be one number or one per ray \\(4\\), got 3"),
    (dict(t_max=np.ones((4, 1))), "t_max: must be a number or an \\(N,\\) array of numbers"),
]


@pytest.mark.parametrize("change, error", BAD, ids=lambda x: x if isinstance(x, str) else "")
def test_bad_inputs_name_the_argument(renderer, change, error):
    args = dict(origins=np.zeros((4, 3)), directions=np.tile([1.0, 0.0, 0.0], (4, 1)), t_max=math.inf)
    args.update(change)
    with pytest.raises(ValueError, match=error):
        renderer.cast_rays(sphere_and_box(), **args)


def rotation(rng):
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q *= np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


@pytest.mark.parametrize("convention", ["opencv", "opengl"])
def test_rays_through_projected_points_hit_them(renderer, convention):
    """20 points projected with numpy from K (fx != fy, principal point off centre) and a pose; the renderer's
    camera ray through each projected pixel (Camera.rays, the pixel convention of shaders/camera.glsl: K's (u, v)
    is the renderer's (u + 0.5, v + 0.5)) hits the tiny sphere at that point."""
    rng = np.random.default_rng(7 if convention == "opencv" else 8)
    width, height = 160, 120
    K = np.array([[150.0, 0.0, 92.3], [0.0, 118.0, 51.7], [0.0, 0.0, 1.0]])
    pose = np.eye(4)
    pose[:3, :3] = rotation(rng)
    pose[:3, 3] = rng.uniform(-2, 2, 3)
    # Points in OpenCV camera axes (x right, y down, z forward) inside the image, far apart in angle.
    points_cam = []
    while len(points_cam) < 20:
        u, v = rng.uniform([3, 3], [width - 4, height - 4])
        z = rng.uniform(2, 8)
        p = z * np.linalg.solve(K, [u, v, 1.0])
        if all(np.linalg.norm(unit(p) - unit(q)) > 0.02 for q in points_cam):
            points_cam.append(p)
    points_cam = np.array(points_cam)
    world = points_cam @ pose[:3, :3].T + pose[:3, 3]
    scene = whitted.Scene()
    # The same camera in OpenGL's axes: y up, z backward (the pose's y and z columns turned over).
    scene.camera.set_from_matrices(K, pose if convention == "opencv" else pose @ np.diag([1, -1, -1, 1]),
                                   width, height, convention=convention)
    for i, p in enumerate(world):
        scene.add_sphere(tuple(p), 0.004, name=f"p{i}")
    # Projected with numpy from K and the pose alone.
    cam = (world - pose[:3, 3]) @ pose[:3, :3]
    uv = cam[:, :2] / cam[:, 2:] * [K[0, 0], K[1, 1]] + [K[0, 2], K[1, 2]]
    origins, directions = scene.camera.rays(width, height, pixels=uv + 0.5)
    np.testing.assert_allclose(origins, np.tile(pose[:3, 3], (20, 1)), atol=1e-6)
    hits = renderer.cast_rays(scene, origins, directions)
    ids = names(renderer, scene)
    assert [ids.get(int(k)) for k in hits["object_id"]] == [f"p{i}" for i in range(20)]
    np.testing.assert_allclose(hits["t"], np.linalg.norm(cam, axis=1) - 0.004, rtol=1e-4)
