# The world around the scene (scenes/README.md "Environment"): an equirectangular image environment seen
# directly by camera rays and in a mirror sphere, checked pixel by pixel against the image looked up in numpy
# along each ray's direction, on both trace paths; the mapping's convention follows the README's formula.
import math

import numpy as np
import OpenImageIO as oiio
import pytest
import whitted

WIDTH, HEIGHT = 160, 120
ROTATION = 30.0  # degrees about +y


def panorama(w=64, h=32):
    """A smooth equirectangular image (no edges: a lookup a fraction of a texel off differs little), its
    values rounded to half floats, the texels' type on the device, so the device holds exactly these."""
    u = (np.arange(w) + 0.5) / w
    t = (np.arange(h) + 0.5) / h
    uu, tt = np.meshgrid(u, t)
    rgb = np.stack([0.5 + 0.4 * np.sin(2 * np.pi * uu), 0.2 + 0.7 * tt,
                    0.5 + 0.4 * np.cos(2 * np.pi * (uu + tt))], axis=-1)
    return rgb.astype(np.float16).astype(np.float32)


def write_exr(path, rgb):
    out = oiio.ImageOutput.create(str(path))
    assert out.open(str(path), oiio.ImageSpec(rgb.shape[1], rgb.shape[0], 3, oiio.FLOAT))
    assert out.write_image(rgb)
    out.close()


def lookup(image, d, rotation_degrees):
    """The README's mapping: d turned back by the rotation about +y, then u = 0.5 + atan2(x, -z) / 2pi across
    from the left edge (the image's centre looks along -z, u = 0.75 along +x), t = acos(y) / pi down from the
    top row; read bilinearly, u wrapping, t clamped to the first and last rows' centres."""
    h, w, _ = image.shape
    a = -math.radians(rotation_degrees)
    x = math.cos(a) * d[..., 0] + math.sin(a) * d[..., 2]
    z = -math.sin(a) * d[..., 0] + math.cos(a) * d[..., 2]
    u = 0.5 + np.arctan2(x, -z) / (2 * np.pi)
    t = np.clip(np.arccos(np.clip(d[..., 1], -1, 1)) / np.pi, 0.5 / h, 1 - 0.5 / h)
    px, py = u * w - 0.5, t * h - 0.5
    x0, y0 = np.floor(px), np.floor(py)
    fx, fy = (px - x0)[..., None], (py - y0)[..., None]
    x0 = x0.astype(int) % w
    x1 = (x0 + 1) % w
    y0 = y0.astype(int)
    y1 = np.minimum(y0 + 1, h - 1)
    return ((1 - fy) * ((1 - fx) * image[y0, x0] + fx * image[y0, x1]) +
            fy * ((1 - fx) * image[y1, x0] + fx * image[y1, x1]))


def psnr(a, b):
    return 10 * math.log10(1.0 / float(np.mean((a - b) ** 2)))


def mirror_scene(folder, image):
    write_exr(folder / "sky.exr", image)
    (folder / "mirror.xml").write_text(f"""<scene>
  <camera><position x="0" y="0.3" z="4"/><window_position x="0" y="0.2" z="3"/><fov>50</fov>
    <width>{WIDTH}</width><height>{HEIGHT}</height></camera>
  <environment><image>sky.exr</image><rotation>{ROTATION}</rotation><shadow_samples>0</shadow_samples></environment>
  <ambient_light r="0" g="0" b="0"/>
  <lights></lights>
  <objects>
    <object><position x="0" y="0" z="0"/><specular_color r="1" g="1" b="1"/>
      <properties><type>sphere</type><radius>1</radius><diffuse_coef>0</diffuse_coef><specular_coef>0</specular_coef>
        <reflection_coef>1</reflection_coef></properties></object>
  </objects>
</scene>
""")
    return whitted.load(str(folder / "mirror.xml"))


def expected_mirror_image(scene, image):
    """Each pixel centre's ray: where it hits the unit sphere at the origin, the environment along its
    reflection; elsewhere along the ray itself."""
    origins, dirs = scene.camera.rays(WIDTH, HEIGHT)
    b = np.sum(origins * dirs, axis=1)
    c = np.sum(origins * origins, axis=1) - 1.0
    disc = b * b - c
    hit = disc > 0
    t = -b - np.sqrt(np.where(hit, disc, 0.0))
    n = origins + t[:, None] * dirs
    reflected = dirs - 2 * np.sum(dirs * n, axis=1)[:, None] * n
    seen = np.where(hit[:, None], reflected, dirs)
    return lookup(image, seen, ROTATION).reshape(HEIGHT, WIDTH, 3), hit.reshape(HEIGHT, WIDTH)


def trace_paths():
    paths = ["bvh"]
    if any(d["ray_query"] and d["suitable"] for d in whitted.devices()):
        paths.append("rayquery")
    return paths


@pytest.mark.parametrize("trace", ["bvh", "rayquery"])
def test_mirror_sphere_reflects_the_environment_along_the_reflected_direction(renderer, tmp_path, trace):
    if trace not in trace_paths():
        pytest.skip("the device has no ray queries")
    image = panorama()
    scene = mirror_scene(tmp_path, image)
    want, hit = expected_mirror_image(scene, image)
    assert 0.1 < hit.mean() < 0.6  # both the sphere and the background fill a good part of the image
    got = renderer.render(scene, spp=1, aa="uniform", trace=trace).image
    assert psnr(got[hit], want[hit]) >= 45.0, "in the mirror"
    assert psnr(got[~hit], want[~hit]) >= 45.0, "seen directly"


def furnace_scene(folder, environment, colour=(0.9, 0.5, 0.25), kd=0.8):
    (folder / "furnace.xml").write_text(f"""<scene>
  <camera><position x="0" y="0" z="4"/><window_position x="0" y="0" z="3"/><fov>40</fov>
    <width>64</width><height>48</height></camera>
  {environment}
  <ambient_light r="0" g="0" b="0"/>
  <lights></lights>
  <objects>
    <object><position x="0" y="0" z="0"/><diffuse_color r="{colour[0]}" g="{colour[1]}" b="{colour[2]}"/>
      <properties><type>sphere</type><radius>1</radius><diffuse_coef>{kd}</diffuse_coef><specular_coef>0</specular_coef>
        </properties></object>
  </objects>
</scene>
""")
    return whitted.load(str(folder / "furnace.xml"))


def inner_sphere_pixels(scene, width=64, height=48):
    """The pixels whose whole footprint lies on the unit sphere at the origin (well inside its outline)."""
    origins, dirs = scene.camera.rays(width, height)
    b = np.sum(origins * dirs, axis=1)
    disc = b * b - (np.sum(origins * origins, axis=1) - 1.0)
    return (disc > 0.15).reshape(height, width)


def test_white_furnace_a_constant_environment_lights_a_diffuse_sphere_to_kd_cd(renderer, tmp_path):
    """A constant environment of radiance 1 lights an unoccluded diffuse surface to kd Cd: the environment's
    light is the point light's formula with each solid angle dw a light of colour dw / pi."""
    colour, kd = np.array([0.9, 0.5, 0.25]), 0.8
    scene = furnace_scene(tmp_path, '<environment><color r="1" g="1" b="1"/></environment>', colour, kd)
    result = renderer.render(scene, spp=64, aa="uniform", aovs=("diffuse",))
    inside = inner_sphere_pixels(scene)
    assert inside.sum() > 300
    want = kd * colour
    got = result.image[inside]
    assert np.all(np.abs(got - want) <= 0.01 * want), (got.min(axis=0), got.max(axis=0), want)
    assert np.allclose(result.aovs["diffuse"][inside], got, atol=1e-6)  # all of it is diffuse light
    assert np.allclose(result.image[~inside & (result.image.sum(axis=2) > 2.99)], 1.0)  # the background: 1


def test_white_furnace_through_the_image_sampler(renderer, tmp_path):
    """The same through an image environment of constant radiance 1, sampled by its distribution (luminance x
    sin theta: uniform over directions here): each pixel is an unbiased estimate of kd Cd; their mean over the
    sphere is within 1 %."""
    colour, kd = np.array([0.9, 0.5, 0.25]), 0.8
    write_exr(tmp_path / "white.exr", np.ones((16, 32, 3), np.float32))
    scene = furnace_scene(tmp_path, '<environment><image>white.exr</image><shadow_samples>4</shadow_samples>'
                                    '</environment>', colour, kd)
    result = renderer.render(scene, spp=64, aa="uniform")
    inside = inner_sphere_pixels(scene)
    mean = result.image[inside].mean(axis=0)
    assert np.all(np.abs(mean - kd * colour) <= 0.01 * kd * colour), mean


def test_transparent_background_gives_the_coverage_as_alpha(renderer, tmp_path):
    scene = furnace_scene(tmp_path, '<environment><color r="1" g="1" b="1"/></environment>')
    result = renderer.render(scene, spp=16, aa="uniform", alpha=True)
    image = result.image
    assert image.shape == (48, 64, 4)
    alpha = image[..., 3]
    inside = inner_sphere_pixels(scene)
    assert np.all(alpha[inside] == 1.0)
    origins, dirs = scene.camera.rays(64, 48)
    b = np.sum(origins * dirs, axis=1)
    far = (b * b - (np.sum(origins * origins, axis=1) - 1.0) < -0.15).reshape(48, 64)
    assert np.all(alpha[far] == 0.0)
    assert np.all(image[far][:, :3] == 0.0)  # the background is not seen, so the colour is premultiplied
    edge = (alpha > 0) & (alpha < 1)
    assert edge.sum() > 20  # anti-aliased edges are fractional
    # Inside, the environment still lights the sphere (kd Cd, as without alpha).
    assert np.allclose(image[inside][:, :3], 0.8 * np.array([0.9, 0.5, 0.25]), rtol=0.01)
    png = tmp_path / "out.png"
    result.save(png)
    spec = oiio.ImageInput.open(str(png))
    assert spec.spec().nchannels == 4
    spec.close()


def test_environment_from_python_renders_as_the_scene_file_and_saves(renderer, tmp_path):
    """Scene.environment = whitted.Environment(image=array, ...) renders as the XML element with the same image
    file does, and save() writes the array beside the scene, where the saved file finds it again."""
    image = panorama()
    from_file = mirror_scene(tmp_path, image)
    built = whitted.load(str(tmp_path / "mirror.xml"))
    built.environment = whitted.Environment(image=image, rotation=ROTATION, shadow_samples=0)
    assert built.environment.kind == "image" and built.environment.rotation == ROTATION
    a = renderer.render(from_file, spp=1, aa="uniform").image
    b = renderer.render(built, spp=1, aa="uniform").image
    assert np.array_equal(a, b)
    built.save(tmp_path / "saved.xml")
    again = whitted.load(str(tmp_path / "saved.xml"))
    assert again.environment.kind == "image" and again.environment.image
    assert np.array_equal(renderer.render(again, spp=1, aa="uniform").image, a)
    built.environment = None
    assert built.environment is None
    assert np.all(renderer.render(built, spp=1, aa="uniform").image == 0.0)  # no light, no ambient, black


@pytest.mark.parametrize("kwargs, message", [
    (dict(), "give exactly one of color, gradient or image, got 0"),
    (dict(color=(1, 1, 1), image="sky.exr"), "give exactly one of color, gradient or image, got 2"),
    (dict(color=(1, 1, 1), intensity=float("nan")), "Environment.intensity"),
    (dict(color=(1, 1, 1), intensity=-1), "Environment.intensity"),
    (dict(color=(-1, 1, 1)), "Environment.color"),
    (dict(gradient=((0, 0, 1), (1, 1, 1))), "Environment.gradient"),
    (dict(image="no_such_sky.exr"), "does not exist"),
    (dict(color=(1, 1, 1), shadow_samples=300), "Environment.shadow_samples"),
])
def test_environment_refuses_what_the_loader_refuses(kwargs, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        whitted.Environment(**kwargs)


def test_background_depth_is_infinite_with_an_environment(renderer, tmp_path):
    scene = furnace_scene(tmp_path, '<environment><color r="1" g="1" b="1"/><shadow_samples>0</shadow_samples>'
                                    '</environment>')
    result = renderer.render(scene, spp=4, aa="uniform", aovs=("depth", "object_id"))
    depth, ids = result.aovs["depth"], result.aovs["object_id"]
    inside = inner_sphere_pixels(scene)
    assert np.all(np.isfinite(depth[inside])) and np.all(depth[inside] > 2.9)
    background = ids == 0xFFFFFFFF
    assert background.sum() > 1000
    assert np.all(np.isinf(depth[background]) | (depth[background] > 2.9))  # edge pixels: the hits' mean depth
    assert np.isinf(depth[0, 0]) and ids[0, 0] == 0xFFFFFFFF
    scene.environment = None  # without one, 0 as before
    assert renderer.render(scene, spp=4, aa="uniform", aovs=("depth",)).aovs["depth"][0, 0] == 0.0


def test_a_small_disc_lights_like_a_directional_light_of_its_radiance_times_solid_angle_over_pi(renderer, tmp_path):
    """The normalisation, diffuse and specular: a black environment with a disc of radiance L and solid angle
    omega lights a floor as a directional light of colour L omega / pi along the disc's centre does."""
    w, h, radius = 256, 128, math.radians(4.0)
    elevation, azimuth = math.radians(55.0), math.radians(30.0)
    sun = np.array([math.cos(elevation) * math.sin(azimuth), math.sin(elevation),
                    -math.cos(elevation) * math.cos(azimuth)])
    t = (np.arange(h) + 0.5) / h
    u = (np.arange(w) + 0.5) / w
    uu, tt = np.meshgrid(u, t)
    theta, phi = tt * np.pi, (uu - 0.5) * 2 * np.pi
    d = np.stack([np.sin(theta) * np.sin(phi), np.cos(theta), -np.sin(theta) * np.cos(phi)], axis=-1)
    inside = d @ sun >= math.cos(radius)
    solid_angle = float(np.sum(((2 * np.pi / w) * (np.pi / h) * np.sin(theta))[inside]))
    image = np.zeros((h, w, 3), np.float32)
    image[inside] = 100.0
    write_exr(tmp_path / "disc.exr", image)
    colour = 100.0 * solid_angle / math.pi

    def floor(world):
        return whitted.loads(f"""<scene>
  <camera><position x="0" y="3" z="3"/><window_position x="0" y="2.3" z="2.3"/><fov>40</fov>
    <width>48</width><height>36</height></camera>
  {world}
  <ambient_light r="0" g="0" b="0"/>
  <objects><object><position x="0" y="0" z="0"/><diffuse_color r="0.8" g="0.6" b="0.4"/>
    <properties><type>plane</type><normal x="0" y="1" z="0"/><diffuse_coef>0.7</diffuse_coef>
      <specular_coef>0.3</specular_coef><shininess>8</shininess></properties></object></objects>
</scene>""", base_dir=str(tmp_path))

    lit = floor('<environment><image>disc.exr</image><shadow_samples>16</shadow_samples></environment>'
                '<lights></lights>')
    direction = -sun
    point = floor(f'<lights><light><type>directional</type><direction x="{direction[0]}" y="{direction[1]}" '
                  f'z="{direction[2]}"/><color r="{colour}" g="{colour}" b="{colour}"/></light></lights>')
    a = renderer.render(lit, spp=16, aa="uniform", aovs=("diffuse", "specular"))
    b = renderer.render(point, spp=16, aa="uniform", aovs=("diffuse", "specular"))
    for name in ("diffuse", "specular"):
        got, want = a.aovs[name].mean(axis=(0, 1)), b.aovs[name].mean(axis=(0, 1))
        assert np.all(want > 0.01), (name, want)
        assert np.allclose(got, want, rtol=0.02), (name, got, want)
