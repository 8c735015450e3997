#!/usr/bin/python3
"""Writes scenes/pictures/authored.gltf: a glTF 2.0 scene as an author would
set it up, for the README's picture of authored scenes (scenes/README.md
"Authored scenes"). A chrome sphere (metallic 1, roughness 0), a glass
sphere (KHR_materials_transmission, KHR_materials_ior, KHR_materials_volume),
a diffuse box on a diffuse floor before a wall, a perspective camera, and
the three KHR_lights_punctual types: a point light (inverse-square falloff),
a spot light and a directional light. Python's standard library only; the
buffer is embedded as base64, so the file stands alone. Deterministic.

    tools/make_authored_scene.py [OUT.gltf]     # default: scenes/pictures/authored.gltf
    build/whitted render scenes/pictures/authored.gltf --width 480 --height 270 --spp 4 --aov none \\
        -o scenes/pictures/authored.png
"""

import base64
import json
import math
import pathlib
import struct
import sys


def sphere(stacks=24, slices=48):
    """A UV sphere of radius 1 with unit vertex normals; counter-clockwise outside."""
    positions, indices = [], []
    for i in range(stacks + 1):
        theta = math.pi * i / stacks
        for k in range(slices + 1):
            phi = 2 * math.pi * k / slices
            positions.append((math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi)))
    for i in range(stacks):
        for k in range(slices):
            a = i * (slices + 1) + k
            b = a + slices + 1
            indices += [a, a + 1, b, a + 1, b + 1, b]
    return positions, list(positions), indices


def box():
    """The unit cube [-0.5, 0.5]^3, four vertices per face so that its normals are flat."""
    positions, normals, indices = [], [], []
    for axis in range(3):
        for sign in (-1, 1):
            n = [0, 0, 0]
            n[axis] = sign
            u = [0, 0, 0]
            u[(axis + 1) % 3] = 1
            v = [0, 0, 0]
            v[(axis + 2) % 3] = 1
            first = len(positions)
            for du, dv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                positions.append(tuple(0.5 * (n[c] + du * u[c] + dv * v[c]) for c in range(3)))
                normals.append(tuple(n))
            quad = [first, first + 1, first + 2, first, first + 2, first + 3]
            if sign < 0:  # keep the winding counter-clockwise seen from outside
                quad = [first, first + 2, first + 1, first, first + 3, first + 2]
            indices += quad
    return positions, normals, indices


def quad(corners, normal):
    return list(corners), [normal] * 4, [0, 1, 2, 0, 2, 3]


def quaternion(degrees, axis):
    length = math.sqrt(sum(c * c for c in axis))
    s = math.sin(math.radians(degrees) / 2) / length
    return [axis[0] * s, axis[1] * s, axis[2] * s, math.cos(math.radians(degrees) / 2)]


def look_rotation(direction):
    """The rotation that turns -Z towards `direction` (about an axis in the xz plane or y, no roll)."""
    x, y, z = direction
    yaw = math.degrees(math.atan2(-x, -z))
    pitch = math.degrees(math.atan2(y, math.hypot(x, z)))
    qy = quaternion(yaw, (0, 1, 0))
    qx = quaternion(pitch, (1, 0, 0))
    # qy * qx
    (ax, ay, az, aw), (bx, by, bz, bw) = qy, qx
    return [aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz]


def build():
    meshes = {
        "sphere": sphere(),
        "box": box(),
        "floor": quad([(-6, 0, 4), (6, 0, 4), (6, 0, -4), (-6, 0, -4)], (0, 1, 0)),
        "wall": quad([(-8, 0, -2.5), (8, 0, -2.5), (8, 8, -2.5), (-8, 8, -2.5)], (0, 0, 1)),
    }
    buffer = bytearray()
    views, accessors, gltf_meshes = [], [], []

    def add_view(data, target):
        while len(buffer) % 4:
            buffer.append(0)
        views.append({"buffer": 0, "byteOffset": len(buffer), "byteLength": len(data), "target": target})
        buffer.extend(data)
        return len(views) - 1

    materials = [
        {"name": "chrome", "pbrMetallicRoughness": {"baseColorFactor": [0.95, 0.93, 0.88, 1], "metallicFactor": 1,
                                                     "roughnessFactor": 0}},
        {"name": "glass", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0,
                                                    "roughnessFactor": 0},
         "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1},
                        "KHR_materials_ior": {"ior": 1.5},
                        "KHR_materials_volume": {"thicknessFactor": 1, "attenuationColor": [0.75, 0.92, 0.85],
                                                 "attenuationDistance": 1.5}}},
        {"name": "floor", "pbrMetallicRoughness": {"baseColorFactor": [0.75, 0.75, 0.72, 1], "metallicFactor": 0,
                                                    "roughnessFactor": 1}},
        {"name": "wall", "pbrMetallicRoughness": {"baseColorFactor": [0.55, 0.6, 0.7, 1], "metallicFactor": 0,
                                                   "roughnessFactor": 1}},
        {"name": "red plastic", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.15, 0.1, 1], "metallicFactor": 0,
                                                          "roughnessFactor": 0.4}},
    ]
    mesh_material = {"chrome ball": ("sphere", 0), "glass ball": ("sphere", 1), "floor": ("floor", 2),
                     "wall": ("wall", 3), "box": ("box", 4)}
    geometry = {}
    for name, (positions, normals, indices) in meshes.items():
        p = add_view(struct.pack("<%df" % (3 * len(positions)), *[c for v in positions for c in v]), 34962)
        n = add_view(struct.pack("<%df" % (3 * len(normals)), *[c for v in normals for c in v]), 34962)
        i = add_view(struct.pack("<%dH" % len(indices), *indices), 34963)
        lo = [min(v[c] for v in positions) for c in range(3)]
        hi = [max(v[c] for v in positions) for c in range(3)]
        accessors += [
            {"bufferView": p, "componentType": 5126, "count": len(positions), "type": "VEC3", "min": lo, "max": hi},
            {"bufferView": n, "componentType": 5126, "count": len(normals), "type": "VEC3"},
            {"bufferView": i, "componentType": 5123, "count": len(indices), "type": "SCALAR"},
        ]
        geometry[name] = len(accessors) - 3
    mesh_index = {}
    for name, (shape, material) in mesh_material.items():
        a = geometry[shape]
        gltf_meshes.append({"name": name, "primitives": [
            {"attributes": {"POSITION": a, "NORMAL": a + 1}, "indices": a + 2, "material": material}]})
        mesh_index[name] = len(gltf_meshes) - 1

    eye, target = (0.3, 2.5, 6.6), (0.3, 0.6, 0)
    nodes = [
        {"name": "props", "children": [1, 2, 3], "translation": [0, 0, 0]},
        {"name": "chrome ball", "mesh": mesh_index["chrome ball"], "translation": [-1.35, 0.75, 0], "scale": [0.75] * 3},
        {"name": "glass ball", "mesh": mesh_index["glass ball"], "translation": [0.2, 0.6, 1.0], "scale": [0.6] * 3},
        {"name": "box", "mesh": mesh_index["box"], "translation": [1.5, 0.5, -0.9], "rotation": quaternion(30, (0, 1, 0))},
        {"name": "floor", "mesh": mesh_index["floor"]},
        {"name": "wall", "mesh": mesh_index["wall"]},
        {"name": "camera", "camera": 0, "translation": list(eye),
         "rotation": look_rotation([target[c] - eye[c] for c in range(3)])},
        {"name": "bulb", "translation": [-2.2, 3.0, 2.2], "extensions": {"KHR_lights_punctual": {"light": 0}}},
        {"name": "spot", "translation": [3.4, 3.4, 2.6],
         "rotation": look_rotation([2.4 - 3.4, 0 - 3.4, 1.4 - 2.6]),
         "extensions": {"KHR_lights_punctual": {"light": 1}}},
        {"name": "sun", "rotation": look_rotation([0.5, -1.0, -0.55]),
         "extensions": {"KHR_lights_punctual": {"light": 2}}},
    ]
    return {
        "asset": {"version": "2.0", "generator": "whitted tools/make_authored_scene.py"},
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_transmission", "KHR_materials_ior",
                           "KHR_materials_volume"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"name": "bulb", "type": "point", "color": [1, 0.85, 0.7], "intensity": 30},
            {"name": "spot", "type": "spot", "color": [0.6, 0.8, 1], "intensity": 60,
             "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.32}},
            {"name": "sun", "type": "directional", "color": [1, 1, 0.95], "intensity": 1.6},
        ]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 4, 5, 6, 7, 8, 9]}],
        "nodes": nodes,
        "cameras": [{"name": "camera", "type": "perspective",
                     "perspective": {"yfov": math.radians(38), "aspectRatio": 16 / 9, "znear": 0.1}}],
        "meshes": gltf_meshes,
        "materials": materials,
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(buffer),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(buffer)).decode()}],
    }


def main():
    out = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else \
        pathlib.Path(__file__).resolve().parent.parent / "scenes" / "pictures" / "authored.gltf"
    out.write_text(json.dumps(build(), indent=1) + "\n")
    print(out)


if __name__ == "__main__":
    main()
