# What the module does with arguments it cannot take (host/python/README.md):
# each refusal names the field, with the exception the README says.
import numpy as np
import pytest
import whitted

NO_HIT = 0xFFFFFFFF


def scene_views():
    scene = whitted.Scene()
    ball = scene.add_sphere((0, 0, 0), 1)
    light = scene.add_light(position=(0, 2, 0))
    return {"scene": scene, "object": ball, "light": light, "camera": scene.camera}


# (target, field, value, message): a value of the wrong type set on a field.
WRONG_TYPES = [
    ("object", "diffuse_color", "red", "Object.diffuse_color: expected 3 numbers, got str"),
    ("object", "diffuse_color", None, "Object.diffuse_color: expected 3 numbers, got NoneType"),
    ("object", "diffuse_color", (1, "a", 0), "Object.diffuse_color[1]: expected a number, got str"),
    ("object", "diffuse", "high", "Object.diffuse: expected a number, got str"),
    ("object", "fresnel", "yes", "Object.fresnel: expected True or False, got str"),
    ("object", "ambient_color", "grey", "Object.ambient_color: expected 3 numbers, got str"),
    ("object", "radius", "1", "Object.radius: expected a number, got str"),
    ("object", "operation", 3, "Object.operation: expected a string, got int"),
    ("object", "checker_size", None, "Object.checker_size: expected a number, got NoneType"),
    ("object", "position", 5, "Object.position: expected 3 numbers, got int"),
    ("light", "intensity", "1", "Light.intensity: expected a number, got str"),
    ("light", "color", "white", "Light.color: expected 3 numbers, got str"),
    ("light", "radius", [0.5], "Light.radius: expected a number, got list"),
    ("light", "shadow_samples", 2.5, "Light.shadow_samples: expected an integer, got float"),
    ("light", "two_sided", "no", "Light.two_sided: expected True or False, got str"),
    ("camera", "fov", "wide", "Camera.fov: expected a number, got str"),
    ("camera", "width", 1.5, "Camera.width: expected an integer, got float"),
    ("camera", "projection", 1, "Camera.projection: expected a string, got int"),
    ("camera", "window_height", None, "Camera.window_height: expected a number, got NoneType"),
    ("camera", "aperture_radius", "0", "Camera.aperture_radius: expected a number, got str"),
    ("camera", "focus_distance", "far", "Camera.focus_distance: expected a number or None, got str"),
    ("camera", "position", "eye", "Camera.position: expected 3 numbers, got str"),
    ("scene", "ambient_light", b"xyz", "Scene.ambient_light: expected 3 numbers, got bytes"),
]


@pytest.mark.parametrize("target, field, value, message", WRONG_TYPES,
                         ids=[f"{t}.{f}={v!r}" for t, f, v, _ in WRONG_TYPES])
def test_wrong_types_raise_type_error_naming_the_field(target, field, value, message):
    view = scene_views()[target]
    before = getattr(view, field)
    with pytest.raises(TypeError) as e:
        setattr(view, field, value)
    assert str(e.value) == message
    assert getattr(view, field) == before


# (call, arguments, message): constructors given a value of the wrong type.
WRONG_ARGUMENTS = [
    ("Material", dict(diffuse_color="red"), "Material.diffuse_color: expected 3 numbers, got str"),
    ("Material", dict(diffuse_color=None), "Material.diffuse_color: expected 3 numbers, got NoneType"),
    ("Material", dict(specular="0.5"), "Material.specular: expected a number, got str"),
    ("Material", dict(checker_size="big"), "Material.checker_size: expected a number, got str"),
    ("add_sphere", dict(center=(0, 0, 0), radius="1"), "add_sphere.radius: expected a number, got str"),
    ("add_sphere", dict(center="origin", radius=1), "add_sphere.center: expected 3 numbers, got str"),
    ("add_cylinder", dict(base=(0, 0, 0), axis=(0, 1, 0), radius=1, height="tall"),
     "add_cylinder.height: expected a number, got str"),
    ("add_light", dict(position=(0, 0, 0), intensity="1"), "add_light.intensity: expected a number, got str"),
    ("add_light", dict(position=(0, 0, 0), type=1), "add_light.type: expected a string, got int"),
    ("add_light", dict(position=(0, 0, 0), falloff=None), "add_light.falloff: expected a string, got NoneType"),
    ("add_light", dict(type="spot", position=(0, 0, 0), direction=(0, -1, 0), inner_angle="10"),
     "add_light.inner_angle: expected a number, got str"),
    ("add_light", dict(position=(0, 0, 0), radius=0.5, shadow_samples="4"),
     "add_light.shadow_samples: expected an integer, got str"),
    ("add_light", dict(type="rect", position=(0, 0, 0), u=(1, 0, 0), v=(0, 0, 1), two_sided="yes"),
     "add_light.two_sided: expected True or False, got str"),
]


@pytest.mark.parametrize("call, arguments, message", WRONG_ARGUMENTS,
                         ids=[f"{c}({', '.join(a)})" for c, a, _ in WRONG_ARGUMENTS])
def test_wrong_argument_types_raise_type_error_naming_the_field(call, arguments, message):
    scene = whitted.Scene()
    make = whitted.Material if call == "Material" else getattr(scene, call)
    with pytest.raises(TypeError) as e:
        make(**arguments)
    assert str(e.value) == message
    assert scene.objects == [] and scene.lights == []


@pytest.mark.parametrize("name", ["a\tb", "a\nb", "a\rb", "a\x1bb", "a\x7fb", "a\x85b"],
                         ids=["tab", "newline", "return", "escape", "delete", "next line"])
def test_names_refuse_control_characters(name):
    scene = whitted.Scene()
    with pytest.raises(ValueError, match=r"^add_sphere\.name: must be text without control characters"):
        scene.add_sphere((0, 0, 0), 1, name=name)
    with pytest.raises(ValueError, match=r"^add_light\.name: must be text without control characters"):
        scene.add_light(position=(0, 2, 0), name=name)
    assert scene.objects == [] and scene.lights == []
    ball, light = scene.add_sphere((0, 0, 0), 1, name="ball"), scene.add_light(position=(0, 2, 0), name="key")
    with pytest.raises(ValueError, match=r"^Object\.name: must be text without control characters"):
        ball.name = name
    with pytest.raises(ValueError, match=r"^Light\.name: must be text without control characters"):
        light.name = name
    assert (ball.name, light.name) == ("ball", "key")
    ball.name = "ball é ü"  # other text stays welcome
    assert ball.name == "ball é ü"


def test_a_transform_of_the_wrong_shape_asks_for_a_4x4_matrix():
    scene = whitted.Scene()
    vertices, faces = np.eye(3), np.array([[0, 1, 2]])
    for transform, got in [(np.eye(3), "shape (3, 3)"), (np.eye(4)[:3], "shape (3, 4)"), (np.zeros(16), "shape (16,)")]:
        with pytest.raises(ValueError) as e:
            scene.add_mesh(vertices, faces, transform=transform)
        assert str(e.value) == f"add_mesh.transform: must be a 4x4 matrix of numbers, got {got}"
    ball = scene.add_sphere((0, 0, 0), 1)
    with pytest.raises(ValueError, match=r"^Object\.transform: must be a 4x4 matrix of numbers, got shape \(3, 3\)$"):
        ball.transform = np.eye(3)


def test_renderer_device_by_index_or_name(renderer):
    devices = whitted.devices()
    suitable = [d for d in devices if d["suitable"]]
    first = suitable[0]
    assert whitted.Renderer(device=first["index"]).device["index"] == first["index"]
    assert whitted.Renderer(device=first["name"][2:6].upper()).device["index"] == first["index"]
    listed = ", ".join(f"{d['index']}: {d['name']}" for d in devices)
    for index in (len(devices), -1):
        with pytest.raises(ValueError) as e:
            whitted.Renderer(device=index)
        assert str(e.value) == f"device: no device {index}; the devices are {listed}"
    with pytest.raises(TypeError, match=r"^device: expected an index, a name substring or None, got float$"):
        whitted.Renderer(device=1.0)


def test_a_hit_whose_t_overflows_float32_is_a_miss(renderer):
    scene = whitted.Scene()
    scene.add_sphere((0, 0, 0), 1)
    origins = np.zeros((3, 3))
    # From the centre, the sphere is 1 away: t = 1 / |d|, beyond float32 for the first two.
    directions = np.array([[-1.2e-40, -1.4e-40, -5e-40], [0, 0, 1e-39], [0, 0, 1e-30]])
    hits = renderer.cast_rays(scene, origins, directions)
    assert hits["object_id"].tolist() == [NO_HIT, NO_HIT, 0]
    assert hits["primitive_id"].tolist() == [NO_HIT, NO_HIT, 0]
    assert np.isinf(hits["t"][:2]).all()
    np.testing.assert_allclose(hits["t"][2], 1e30, rtol=1e-6)
    assert not hits["normal"][:2].any() and not hits["uv"][:2].any()


def small_scene():
    scene = whitted.Scene()
    scene.add_sphere((0, 0, 0), 1, name="ball")
    return scene


def test_aov_dtypes_are_as_documented(renderer):
    result = renderer.render(small_scene(), width=8, height=6, spp=1, aovs=("depth", "object_id", "material_id"))
    assert result.aovs["depth"].dtype == np.float32
    assert result.aovs["object_id"].dtype == np.uint32 and result.aovs["material_id"].dtype == np.uint32
    doc = whitted.RenderResult.aovs.__doc__
    assert "uint32" in doc and "object_id" in doc
