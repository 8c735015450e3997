// whitted.Camera: the scene's camera as a view (its frame, lens and image
// size, checked as the XML loader checks <camera>), cameras from and to the
// matrices of computer-vision tools (scene/camera_matrices.h;
// host/python/README.md "Cameras from matrices") and the rays the renderer
// traces through its pixels.
#include "python/arguments.h"
#include "python/python_api.h"
#include "render/gpu_scene.h"
#include "render/ray_cast.h"
#include "scene/camera_matrices.h"
#include "scene/scene_loader.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace whitted::python {
namespace {

using CameraClass = py::class_<CameraView>;

// Sets one of the camera's frame vectors, refusing (and undoing) a value
// that leaves it without an image frame, in the XML loader's terms
// (scene/scene.h cameraFrameProblem).
void setCameraFrame(Camera& camera, glm::dvec3 Camera::*member, const glm::dvec3& value, const std::string& field) {
    const glm::dvec3 was = camera.*member;
    camera.*member = value;
    const CameraFrameProblem frame = cameraFrameProblem(camera);
    if (frame == CameraFrameProblem::None) return;
    camera.*member = was;
    throw py::value_error(field + ": " +
                          (frame == CameraFrameProblem::EyeAtWindow ? "Camera.position and Camera.look_at would coincide"
                                                             : "Camera.up would be parallel to the viewing direction"));
}

using Matrix = py::array_t<double, py::array::c_style | py::array::forcecast>;

// A rows x cols matrix of numbers, or ValueError naming the field.
Matrix matrixArg(const py::object& x, const char* field, py::ssize_t rows, py::ssize_t cols) {
    std::string want = std::to_string(rows) + "x" + std::to_string(cols);
    Matrix a;
    try {
        a = x.cast<Matrix>();
    } catch (const py::cast_error&) {
        throw py::value_error(std::string(field) + ": must be a " + want + " matrix of numbers");
    } catch (const py::error_already_set&) {  // numpy could not make numbers of it
        throw py::value_error(std::string(field) + ": must be a " + want + " matrix of numbers");
    }
    if (a.ndim() != 2 || a.shape(0) != rows || a.shape(1) != cols) {
        std::string got;
        for (py::ssize_t i = 0; i < a.ndim(); ++i) got += (i ? "x" : "") + std::to_string(a.shape(i));
        throw py::value_error(std::string(field) + ": must be a " + want + " matrix, got shape " +
                              (got.empty() ? "()" : got));
    }
    return a;
}

CameraConvention conventionArg(const std::string& c) {
    if (c == "opencv") return CameraConvention::OpenCV;
    if (c == "opengl") return CameraConvention::OpenGL;
    throw py::value_error("convention: must be 'opencv' or 'opengl', got '" + c + "'");
}

py::array_t<double> toArray(const double* columnMajor, py::ssize_t n) {
    py::array_t<double> out({n, n});
    auto m = out.mutable_unchecked<2>();
    for (py::ssize_t r = 0; r < n; ++r)
        for (py::ssize_t c = 0; c < n; ++c) m(r, c) = columnMajor[c * n + r];
    return out;
}

// The frame and the image size.
void addFrameFields(CameraClass& camera) {
    camera
        .def_property(
            "position", [](const CameraView& v) { return toTuple(v.c().eye); },
            [](const CameraView& v, py::object x) {
                setCameraFrame(v.c(), &Camera::eye, checked("Camera.position", toVec(x, "Camera.position"), xml::kAnyValue),
                               "Camera.position");
                v.edited();
            },
            "the eye")
        .def_property(
            "look_at", [](const CameraView& v) { return toTuple(v.c().windowCenter); },
            [](const CameraView& v, py::object x) {
                setCameraFrame(v.c(), &Camera::windowCenter,
                               checked("Camera.look_at", toVec(x, "Camera.look_at"), xml::kAnyValue), "Camera.look_at");
                v.edited();
            },
            "the point the camera looks at (the image plane's centre)")
        .def_property(
            "up", [](const CameraView& v) { return toTuple(v.c().up); },
            [](const CameraView& v, py::object x) {
                setCameraFrame(v.c(), &Camera::up, unit("Camera.up", toVec(x, "Camera.up")), "Camera.up");
                v.edited();
            },
            "the up direction (any length but 0)")
        .def_property(
            "fov", [](const CameraView& v) { return v.c().verticalFovDegrees; },
            [](const CameraView& v, Arg<double> x) {
                v.c().verticalFovDegrees = checked("Camera.fov", x, kFovRange);
                v.edited();
            },
            "vertical field of view in degrees")
        .def_property(
            "width", [](const CameraView& v) { return v.c().width; },
            [](const CameraView& v, Arg<long long> x) {
                v.c().width = int(checked("Camera.width", x, kImageSide));
                v.edited();
            },
            "image width in pixels (the render's default)")
        .def_property(
            "height", [](const CameraView& v) { return v.c().height; },
            [](const CameraView& v, Arg<long long> x) {
                v.c().height = int(checked("Camera.height", x, kImageSide));
                v.edited();
            },
            "image height in pixels (the render's default)");
}

// The projection and the thin lens.
void addLensFields(CameraClass& camera) {
    camera
        .def_property(
            "projection",
            [](const CameraView& v) {
                return std::string(v.c().projection == Camera::Projection::Orthographic ? "orthographic" : "perspective");
            },
            [](const CameraView& v, Arg<std::string> x) {
                std::string p = x.get("Camera.projection");
                if (p != "perspective" && p != "orthographic")
                    refuse("Camera.projection", "'perspective' or 'orthographic'", "'" + p + "'");
                v.c().projection = p == "orthographic" ? Camera::Projection::Orthographic : Camera::Projection::Perspective;
                v.edited();
            },
            "'perspective' (fov) or 'orthographic' (window_height), as <projection>")
        .def_property(
            "window_height", [](const CameraView& v) { return v.c().windowHeight; },
            [](const CameraView& v, Arg<double> x) {
                v.c().windowHeight = checked("Camera.window_height", x, xml::kPositive);
                v.edited();
            },
            "an orthographic camera's window height in scene units (<window_height>)")
        .def_property(
            "aperture_radius", [](const CameraView& v) { return v.c().apertureRadius; },
            [](const CameraView& v, Arg<double> x) {
                v.c().apertureRadius = checked("Camera.aperture_radius", x, xml::kNonNegative);
                v.edited();
            },
            "the thin lens's radius in scene units (<aperture_radius>); 0: a pinhole, everything sharp")
        .def_property(
            "focus_distance", [](const CameraView& v) { return v.c().focusDistanceOrDefault(); },
            [](const CameraView& v, py::object x) {
                if (x.is_none()) v.c().focusDistance.reset();
                else if (!py::isinstance<py::float_>(x) && !py::isinstance<py::int_>(x))
                    throw py::type_error("Camera.focus_distance: expected a number or None, got " + typeName(x));
                else v.c().focusDistance = checked("Camera.focus_distance", x.cast<double>(), xml::kPositive);
                v.edited();
            },
            "the distance of the plane in focus along the view (<focus_distance>); None: look_at's distance")
        .def("__repr__", [](const CameraView& v) {
            return "Camera(position=" + py::repr(toTuple(v.c().eye)).cast<std::string>() +
                   ", look_at=" + py::repr(toTuple(v.c().windowCenter)).cast<std::string>() +
                   ", fov=" + shown(v.c().verticalFovDegrees) + ")";
        });
}

// K and the pose.
void addMatrixMethods(CameraClass& camera) {
    camera
        .def(
            "set_from_matrices",
            [](const CameraView& v, const py::object& K, const py::object& pose, int width, int height,
               const std::string& convention) {
                CameraConvention conv = conventionArg(convention);
                Matrix k = matrixArg(K, "K", 3, 3), p = matrixArg(pose, "cam_to_world", 4, 4);
                glm::dmat3 km;
                glm::dmat4 pm;
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c) km[c][r] = k.at(r, c);
                for (int r = 0; r < 4; ++r)
                    for (int c = 0; c < 4; ++c) pm[c][r] = p.at(r, c);
                try {
                    v.c() = cameraFromMatrices(v.c(), km, pm, width, height, conv);
                } catch (const std::invalid_argument& e) {
                    throw py::value_error(e.what());
                }
                v.edited();
            },
            py::arg("K"), py::arg("cam_to_world"), py::arg("width"), py::arg("height"), py::arg("convention") = "opencv",
            "Sets the camera from a 3x3 intrinsic matrix K (pixels: u right, v down, (0, 0) the top-left pixel's "
            "centre; fx != fy and any principal point allowed, skew must be 0) and a 4x4 rigid camera-to-world pose "
            "whose columns are the camera's x, y, z axes and position: convention 'opencv' (x right, y down, "
            "z forward) or 'opengl' (x right, y up, -z forward). K is for a width x height image; a render at "
            "another size scales it. The scene format cannot hold such a camera: Scene.save refuses it.")
        .def(
            "intrinsics",
            [](const CameraView& v) {
                glm::dmat3 k;
                try {
                    k = cameraIntrinsicMatrix(v.c());
                } catch (const std::invalid_argument& e) {
                    throw py::value_error(e.what());
                }
                return toArray(&k[0][0], 3);
            },
            "K (3x3 float64, pixels of the width x height image, the conventions of set_from_matrices): the matrix "
            "set, or the one the fov gives (fx = fy, centred); ValueError for an orthographic camera")
        .def(
            "cam_to_world",
            [](const CameraView& v, const std::string& convention) {
                glm::dmat4 m4 = cameraToWorld(v.c(), conventionArg(convention));
                return toArray(&m4[0][0], 4);
            },
            py::arg("convention") = "opencv",
            "The 4x4 camera-to-world pose (float64): columns x, y, z axes and position, 'opencv' or 'opengl' axes")
        .def_property_readonly(
            "has_intrinsics", [](const CameraView& v) { return v.c().intrinsics.has_value(); },
            "whether set_from_matrices set K (then fov is not used)")
        .def(
            "clear_intrinsics",
            [](const CameraView& v) {
                v.c().intrinsics.reset();
                v.edited();
            },
            "Drops the K of set_from_matrices: the fov gives the window again (the pose stays)");
}

// Camera.rays and Camera.copy.
void addRaysAndCopy(CameraClass& camera) {
    camera
        .def(
            "rays",
            [](const CameraView& v, std::optional<int> widthArg, std::optional<int> heightArg,
               const py::object& pixelsArg) {
                int width = widthArg.value_or(v.c().width), height = heightArg.value_or(v.c().height);
                for (auto [name, side] : {std::pair{"width", width}, std::pair{"height", height}})
                    if (side < 1 || side > int(gpu::kMaxImageSide))
                        throw py::value_error(std::string(name) + ": must be in 1.." +
                                              std::to_string(gpu::kMaxImageSide) + ", got " + std::to_string(side));
                std::vector<glm::dvec2> pixels;
                if (pixelsArg.is_none()) {
                    for (int y = 0; y < height; ++y)
                        for (int x = 0; x < width; ++x) pixels.emplace_back(x + 0.5, y + 0.5);
                } else {
                    Matrix p;
                    try {
                        p = pixelsArg.cast<Matrix>();
                    } catch (const std::exception&) {
                        throw py::value_error("pixels: must be an (N, 2) array of numbers");
                    }
                    if (p.ndim() != 2 || p.shape(1) != 2) throw py::value_error("pixels: must be an (N, 2) array");
                    for (py::ssize_t i = 0; i < p.shape(0); ++i) {
                        if (!std::isfinite(p.at(i, 0)) || !std::isfinite(p.at(i, 1)))
                            throw py::value_error("pixels: row " + std::to_string(i) + " is not finite");
                        pixels.emplace_back(p.at(i, 0), p.at(i, 1));
                    }
                }
                gpu::FrameParams params;
                packCamera(v.c(), width, height, params);
                py::ssize_t n = py::ssize_t(pixels.size());
                py::array_t<double> origins({n, py::ssize_t(3)}), directions({n, py::ssize_t(3)});
                auto o = origins.mutable_unchecked<2>();
                auto d = directions.mutable_unchecked<2>();
                for (py::ssize_t i = 0; i < n; ++i) {
                    CameraRay ray = generateCameraRay(params, pixels[size_t(i)], glm::dvec2(width, height));
                    for (int c = 0; c < 3; ++c) {
                        o(i, c) = ray.origin[c];
                        d(i, c) = ray.direction[c];
                    }
                }
                return py::make_tuple(origins, directions);
            },
            py::arg("width") = py::none(), py::arg("height") = py::none(), py::arg("pixels") = py::none(),
            "The rays the renderer traces through points of a width x height image (default: the camera's size), "
            "for Renderer.cast_rays: (origins, directions), each (N, 3) float64, directions unit. pixels: (N, 2) "
            "points (x, y) in the renderer's pixel units: origin at the image's top-left corner, x right, y down, "
            "so pixel (i, j)'s centre is (i + 0.5, j + 0.5) and K's (u, v) is (u + 0.5, v + 0.5). None: every "
            "pixel's centre, row by row from the top (N = width * height), the rays of the object_id mask.")
        .def(
            "copy",
            [](const CameraView& v) {
                Scene only;
                only.camera = v.c();
                return CameraView{std::make_shared<SceneHandle>(std::move(only))};
            },
            "A detached copy (for Renderer.render(cameras=[...])): edits to it leave the scene alone");
}

}  // namespace

void addCameraApi(py::module_& m) {
    CameraClass camera(m, "Camera", "The scene's pinhole camera (a view: edits change the scene)");
    addFrameFields(camera);
    addLensFields(camera);
    addMatrixMethods(camera);
    addRaysAndCopy(camera);
}

}  // namespace whitted::python
