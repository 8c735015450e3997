"""A small synthetic data set: meshes from numpy, 20 random objects a frame, 10 frames from K and pose matrices,
each with depth, normals, object masks and the id -> name legend.   python3 tools/examples/dataset.py [OUT]"""
import json, pathlib, sys
import numpy as np
import whitted

rng = np.random.default_rng(7)
out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "dataset"); out.mkdir(parents=True, exist_ok=True)
scene = whitted.Scene()
scene.ambient_light = (0.1, 0.1, 0.1)
scene.add_plane((0, 0, 0), (0, 1, 0), material=whitted.Material(diffuse_color=(0.8, 0.8, 0.8)), name="floor")
scene.add_light(position=(4, 8, 6), color=(1, 1, 1))
# A unit tetrahedron and an octahedron, as vertex and face arrays.
tetra = (np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], float) * 0.35 + [0, 0.35, 0],
         np.array([[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]]))
octa = (np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float) * 0.4 + [0, 0.4, 0],
        np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]]))
K = np.array([[220.0, 0, 159.5], [0, 220.0, 119.5], [0, 0, 1]])
renderer = whitted.Renderer()
for frame in range(10):
    placed = []
    for k in range(20):
        colour = tuple(rng.uniform(0.2, 1.0, 3))
        material = whitted.Material(diffuse_color=colour)
        x, z = rng.uniform(-3, 3, 2)
        if k % 3 == 0:
            placed.append(scene.add_sphere((x, 0.3, z), 0.3, material=material, name=f"sphere {k}"))
        else:
            vertices, faces = tetra if k % 3 == 1 else octa
            pose = np.eye(4)
            pose[:3, 3] = (x, 0, z)
            placed.append(scene.add_mesh(vertices, faces, material=material, name=f"mesh {k}", transform=pose))
    angle = 2 * np.pi * frame / 10  # the camera circles the objects, looking at the origin (OpenCV axes)
    eye = np.array([7 * np.sin(angle), 4.0, 7 * np.cos(angle)])
    forward = -eye / np.linalg.norm(eye)
    right = np.cross(forward, (0, 1, 0)); right /= np.linalg.norm(right)
    pose = np.eye(4)
    pose[:3, :3] = np.column_stack([right, np.cross(forward, right), forward])
    pose[:3, 3] = eye
    scene.camera.set_from_matrices(K, pose, 320, 240, convention="opencv")
    result = renderer.render(scene, aovs=("depth", "normal", "object_id"))
    result.save(str(out / f"frame{frame:02d}.exr"))
    legend = {int(i): entry["name"] for i, entry in result.masks.items()}
    (out / f"frame{frame:02d}.legend.json").write_text(json.dumps(legend, indent=1))
    for handle in placed:
        scene.remove(handle)
print(f"wrote 10 frames into {out}")
