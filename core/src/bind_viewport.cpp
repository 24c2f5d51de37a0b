// gridwalk._core.ViewportRenderer: the viewport's native controller (see
// viewport_renderer.h). Every call releases the GIL while it waits on the
// controller, and the controller never runs Python.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/shared_ptr.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include "bind_casters.h"
#include "bindings.h"
#include "gil_release.h"
#include "viewport_renderer.h"

namespace nb = nanobind;
using namespace nb::literals;

namespace gw {

void bind_viewport(nb::module_& m) {
    m.attr("HALF_FLOAT_SAFE_LIMIT") = kHalfFloatSafeLimit;
    nb::class_<ViewportRenderer>(m, "ViewportRenderer")
        .def(nb::init<>())
        .def("submit",
             [](ViewportRenderer& v, uint64_t id, std::shared_ptr<Scene> scene,
                const std::vector<std::tuple<std::string, RenderSettings>>& structures,
                const std::vector<std::tuple<int, int, RenderSettings, CameraDesc, int>>& passes, int width, int height,
                bool opaque, float limit, double delay) {
                 ViewportRequest r;
                 r.id = id;
                 r.scene = std::move(scene);
                 for (const auto& [key, settings] : structures) r.structures.push_back({key, settings});
                 for (const auto& [block, structure, settings, camera, repeat] : passes)
                     r.passes.push_back({block, structure, settings, camera, repeat});
                 r.width = width;
                 r.height = height;
                 r.opaque = opaque;
                 r.limit = limit;
                 r.delay = delay;
                 GilRelease release;
                 v.submit(std::move(r));
             },
             "id"_a, "scene"_a.none(), "structures"_a, "passes"_a, "width"_a, "height"_a, "opaque"_a, "limit"_a,
             "delay"_a)
        .def("stop", &ViewportRenderer::stop, nb::call_guard<GilRelease>())
        .def_prop_ro("status", [](const ViewportRenderer& v) {
            ViewportStatus s;
            {
                GilRelease release;
                s = v.status();
            }
            nb::dict d;
            d["request"] = s.request;
            d["finished"] = s.finished;
            d["pass"] = s.pass;
            d["repetition"] = s.repetition;
            d["passes_done"] = s.passes_done;
            d["rendering"] = s.rendering;
            d["error"] = s.error;
            d["version"] = s.version;
            d["first_pixels"] = s.first_pixels;
            d["first_pass_started"] = s.first_pass_started;
            d["structure_ready"] = s.structure_ready;
            d["structure_updated"] = std::vector<bool>(s.structure_updated);
            return d;
        })
        .def("image", [](const ViewportRenderer& v) {
            int w = 0, h = 0;
            uint64_t version = 0;
            auto* pixels = new std::vector<float>();
            {
                GilRelease release;
                *pixels = v.image(w, h, version);
            }
            nb::capsule owner(pixels, [](void* p) noexcept { delete static_cast<std::vector<float>*>(p); });
            const size_t shape[3] = {size_t(h), size_t(w), 4};
            return nb::make_tuple(version, nb::ndarray<nb::numpy, float>(pixels->data(), 3, shape, owner));
        }, "(version, (height, width, 4) float32 copy of the display image, rows bottom-up)");
}

}  // namespace gw
