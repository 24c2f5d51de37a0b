// Bindings of the settings table (settings.h) and the enums (enums.h):
// gridwalk._core.RenderSettings with one attribute per row, one Python enum
// per C++ enum, and settings_schema(), the table itself as Python data.
#include <nanobind/nanobind.h>
#include <nanobind/stl/string.h>

#include "bind_casters.h"
#include "bindings.h"
#include "lights.h"

namespace nb = nanobind;

namespace gw {
namespace {

template <class T> struct TypeName;
template <> struct TypeName<bool> { static constexpr const char* value = "bool"; };
template <> struct TypeName<int> { static constexpr const char* value = "int32"; };
template <> struct TypeName<uint32_t> { static constexpr const char* value = "uint32"; };
template <> struct TypeName<uint64_t> { static constexpr const char* value = "uint64"; };
template <> struct TypeName<float> { static constexpr const char* value = "float32"; };
template <> struct TypeName<double> { static constexpr const char* value = "float64"; };
template <> struct TypeName<Region> { static constexpr const char* value = "region"; };

template <class E>
nb::list enum_items() {
    nb::list items;
    for (const EnumItem& it : EnumTraits<E>::items) items.append(nb::make_tuple(it.id, it.label, it.help));
    return items;
}

template <class E>
void bind_enum(nb::module_& m) {
    nb::enum_<E> e(m, EnumTraits<E>::name);
    for (int i = 0; i < EnumTraits<E>::count; ++i) e.value(EnumTraits<E>::items[i].id, E(i));
}

// One schema row: the value's kind and default as Python sees them.
template <class T>
void describe(nb::dict& row, const T& def) {
    if constexpr (std::is_enum_v<T>) {
        row["ctype"] = "enum";
        row["enum_type"] = EnumTraits<T>::name;
        row["default"] = enum_id(def);
        row["choices"] = enum_items<T>();
    } else if constexpr (std::is_same_v<T, Region>) {
        row["ctype"] = TypeName<T>::value;
        row["default"] = nb::none();
    } else {
        row["ctype"] = TypeName<T>::value;
        row["default"] = def;
    }
}

nb::list settings_schema() {
    nb::list rows;
#define GW_SCHEMA_ROW(type, name, def, lo, hi, group, when, label, help) \
    {                                                                    \
        nb::dict row;                                                    \
        row["name"] = #name;                                             \
        describe<type>(row, def);                                        \
        row["min"] = double(lo);                                         \
        row["max"] = double(hi);                                         \
        row["group"] = group;                                            \
        row["when"] = when;                                              \
        row["label"] = label;                                            \
        row["help"] = help;                                              \
        rows.append(row);                                                \
    }
    GW_RENDER_SETTINGS(GW_SCHEMA_ROW)
#undef GW_SCHEMA_ROW
    return rows;
}

nb::dict host_defaults() {
    nb::dict d;
#define GW_HOST_ROW(name, value, reason) d[#name] = nb::make_tuple(value, reason);
    GW_HOST_DEFAULTS(GW_HOST_ROW)
#undef GW_HOST_ROW
    return d;
}

}  // namespace

void bind_settings(nb::module_& m) {
    bind_enum<AccelKind>(m);
    bind_enum<AAMode>(m);
    bind_enum<ShadowMode>(m);
    bind_enum<PixelFilter>(m);
    bind_enum<Instancing>(m);
    bind_enum<LightKind>(m);
    bind_enum<Projection>(m);
    bind_enum<Interpolation>(m);
    bind_enum<Extension>(m);
    bind_enum<TextureKind>(m);
    bind_enum<TextureCoords>(m);
    bind_enum<ImageProjection>(m);
    bind_enum<Gradient>(m);
    bind_enum<NoiseType>(m);
    bind_enum<VoronoiFeature>(m);
    bind_enum<VoronoiMetric>(m);
    bind_enum<VoronoiOutput>(m);
    bind_enum<WaveType>(m);
    bind_enum<WaveDirection>(m);
    bind_enum<WaveProfile>(m);
    bind_enum<RampInterpolation>(m);
    m.def("light_kinds", &enum_items<LightKind>);
    m.def("projections", &enum_items<Projection>);
    m.def("interpolations", &enum_items<Interpolation>);
    m.def("extensions", &enum_items<Extension>);
    m.def("texture_kinds", &enum_items<TextureKind>);
    m.def("texture_coords", &enum_items<TextureCoords>);
    m.def("image_projections", &enum_items<ImageProjection>);
    m.def("gradients", &enum_items<Gradient>);
    m.def("noise_types", &enum_items<NoiseType>);
    m.def("voronoi_features", &enum_items<VoronoiFeature>);
    m.def("voronoi_metrics", &enum_items<VoronoiMetric>);
    m.def("voronoi_outputs", &enum_items<VoronoiOutput>);
    m.def("wave_types", &enum_items<WaveType>);
    m.def("wave_directions", &enum_items<WaveDirection>);
    m.def("wave_profiles", &enum_items<WaveProfile>);
    m.def("ramp_interpolations", &enum_items<RampInterpolation>);

    nb::class_<RenderSettings> cls(m, "RenderSettings");
    cls.def(nb::init<>());
#define GW_BIND_SETTING(type, name, def, lo, hi, group, when, label, help) cls.def_rw(#name, &RenderSettings::name);
    GW_RENDER_SETTINGS(GW_BIND_SETTING)
#undef GW_BIND_SETTING
    cls.def("validate", &validate_settings);
    m.def("settings_schema", &settings_schema, "The settings table of settings.h, one dict per setting");
    m.def("host_defaults", &host_defaults, "Settings whose default a host (Blender) changes: {name: (value, reason)}");
}

}  // namespace gw
