// gridwalk._core.sky_table / sky_sun: the clear sky's light (sky.h), for
// gridwalk.sky, which lays the table out as Blender does.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "bindings.h"
#include "gil_release.h"
#include "sky.h"

namespace nb = nanobind;
using namespace nb::literals;

namespace gw {

namespace {
void check_model(const std::string& model) {
    if (model != "single" && model != "multiple") throw std::invalid_argument("sky model must be single or multiple, got " + model);
}

// Finite settings, densities not below 0 (a NaN would index the tables anywhere).
SkyAtmosphere atmosphere(float altitude, float air, float dust, float ozone) {
    for (float v : {altitude, air, dust, ozone})
        if (!std::isfinite(v)) throw std::invalid_argument("sky settings must be finite numbers");
    if (air < 0 || dust < 0 || ozone < 0 || altitude < 0)
        throw std::invalid_argument("sky densities and altitude must not be negative");
    SkyAtmosphere a;
    a.altitude = altitude, a.air = air, a.dust = dust, a.ozone = ozone;
    return a;
}
}  // namespace

void bind_sky(nb::module_& m) {
    m.def(
        "sky_table",
        [](const std::string& model, nb::ndarray<const float, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu> views,
           float sun_elevation, float altitude, float air, float dust, float ozone, int threads) {
            check_model(model);
            const SkyAtmosphere a = atmosphere(altitude, air, dust, ozone);
            if (!std::isfinite(sun_elevation)) throw std::invalid_argument("the sun's elevation must be a finite number");
            const size_t n = views.shape(0);
            for (size_t i = 0; i < 3 * n; ++i)
                if (!std::isfinite(views.data()[i])) throw std::invalid_argument("sky view directions must be finite");
            float* out = new float[3 * n];
            nb::capsule owner(out, [](void* p) noexcept { delete[] static_cast<float*>(p); });
            {
                GilRelease release;
                if (model == "single") sky_single_scattering(views.data(), n, sun_elevation, a, out, threads);
                else sky_multiple_scattering(views.data(), n, sun_elevation, a, out, threads);
            }
            return nb::ndarray<nb::numpy, float, nb::ndim<2>>(out, {n, size_t(3)}, owner);
        },
        "model"_a, "views"_a, "sun_elevation"_a, "altitude"_a, "air"_a, "dust"_a, "ozone"_a, "threads"_a = 0,
        "XYZ radiance (n, 3) along unit view directions (n, 3) (sky.h).");
    m.def(
        "sky_sun",
        [](const std::string& model, float elevation, float solid_angle, float altitude, float air, float dust,
           float ozone) {
            check_model(model);
            const SkyAtmosphere a = atmosphere(altitude, air, dust, ozone);
            if (!std::isfinite(elevation)) throw std::invalid_argument("the sun's elevation must be a finite number");
            if (!(solid_angle > 0) || !std::isfinite(solid_angle))
                throw std::invalid_argument("the sun's solid angle must be a positive number");
            float xyz[3];
            sky_sun(model == "multiple", elevation, solid_angle, a, xyz);
            return nb::make_tuple(xyz[0], xyz[1], xyz[2]);
        },
        "model"_a, "elevation"_a, "solid_angle"_a, "altitude"_a, "air"_a, "dust"_a, "ozone"_a,
        "XYZ radiance of the sun's disc seen at an elevation (sky.h).");
}

}  // namespace gw
