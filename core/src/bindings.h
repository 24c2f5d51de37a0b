// The parts of the private module gridwalk._core, each bound in its own file.
#pragma once
#include <nanobind/nanobind.h>

namespace gw {
void bind_settings(nanobind::module_& m);   // bind_settings.cpp
void bind_records(nanobind::module_& m);    // bind_records.cpp
void bind_viewport(nanobind::module_& m);   // bind_viewport.cpp
void bind_sky(nanobind::module_& m);        // bind_sky.cpp
}  // namespace gw
