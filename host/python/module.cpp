// The Python module `whitted` (host/python/README.md).
#include "python/python_api.h"

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>

namespace py = pybind11;

PYBIND11_MODULE(whitted, m) {
    m.doc() = "whitted: a Whitted-style ray tracer on Vulkan (host/python/README.md)";
    m.attr("__version__") = WHITTED_VERSION;
#ifdef WHITTED_TEST_HOOKS
    m.attr("_test_hooks") = true;  // a test build: WHITTED_INJECT_FAULT, WHITTED_DISCRETE_MEMORY (host/vk/)
#else
    m.attr("_test_hooks") = false;
#endif
    // Each class before the signatures that name it.
    whitted::python::addSceneErrorApi(m);
    whitted::python::addCameraApi(m);
    whitted::python::addMaterialApi(m);
    whitted::python::addObjectApi(m);
    whitted::python::addLightApi(m);
    whitted::python::addMeshApi(m);
    whitted::python::addSceneApi(m);
    whitted::python::addEnvironmentApi(m);
    whitted::python::addRenderApi(m);
    m.attr("_renderer") = py::none();
    // whitted.render(scene_or_path, **options): one renderer for the module,
    // made on first use.
    m.def(
        "render",
        [](py::object scene, py::kwargs options) {
            py::module_ self = py::module_::import("whitted");
            if (self.attr("_renderer").is_none()) self.attr("_renderer") = self.attr("Renderer")();
            if (py::isinstance<py::str>(scene) || py::hasattr(scene, "__fspath__")) scene = self.attr("load")(scene);
            return self.attr("_renderer").attr("render")(scene, **options);
        },
        py::arg("scene"),
        "Renders a Scene or a scene/model file path with the module's renderer (Renderer.render's options)");
}
