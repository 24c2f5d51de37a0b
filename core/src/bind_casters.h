// nanobind type casters for the core's small value types: Vec3 from any
// sequence of 3 numbers (to a tuple; Vec3d keeps double), Region from 4 integers (to a tuple).
// The gridwalk package checks shapes first and names the field; a caster
// that fails makes nanobind raise TypeError.
#pragma once
#include <nanobind/nanobind.h>

#include "math.h"
#include "settings.h"

namespace nanobind::detail {

// Reads `count` items of a Python sequence into out[] as doubles or int64s.
template <class T>
bool read_sequence(handle src, T* out, Py_ssize_t count) noexcept {
    PyObject* seq = PySequence_Fast(src.ptr(), "");
    if (!seq) { PyErr_Clear(); return false; }
    bool ok = PySequence_Fast_GET_SIZE(seq) == count;
    for (Py_ssize_t i = 0; ok && i < count; ++i) {
        PyObject* item = PySequence_Fast_GET_ITEM(seq, i);
        if constexpr (std::is_floating_point_v<T>) {
            out[i] = T(PyFloat_AsDouble(item));
        } else {
            if (PyFloat_Check(item) || PyBool_Check(item)) { ok = false; break; }   // no silent truncation
            out[i] = T(PyLong_AsLongLong(item));
        }
        if (PyErr_Occurred()) { PyErr_Clear(); ok = false; }
    }
    Py_DECREF(seq);
    return ok;
}

// Vec3 (float) and Vec3d (double, the camera's eye and target).
template <class T>
struct type_caster<gw::V3<T>> {
    NB_TYPE_CASTER(gw::V3<T>, const_name("tuple[float, float, float]"))
    bool from_python(handle src, uint8_t, cleanup_list*) noexcept {
        double v[3];
        if (!read_sequence(src, v, 3)) return false;
        value = gw::V3<T>(T(v[0]), T(v[1]), T(v[2]));
        return true;
    }
    static handle from_cpp(const gw::V3<T>& v, rv_policy, cleanup_list*) noexcept {
        return make_tuple(v.x, v.y, v.z).release();
    }
};

template <>
struct type_caster<gw::Region> {
    NB_TYPE_CASTER(gw::Region, const_name("tuple[int, int, int, int]"))
    bool from_python(handle src, uint8_t, cleanup_list*) noexcept {
        long long v[4];
        if (!read_sequence(src, v, 4)) return false;
        for (long long x : v)
            if (x < 0 || x > INT32_MAX) return false;
        value = gw::Region{int(v[0]), int(v[1]), int(v[2]), int(v[3])};
        return true;
    }
    static handle from_cpp(const gw::Region& r, rv_policy, cleanup_list*) noexcept {
        return make_tuple(r.x, r.y, r.w, r.h).release();
    }
};

}  // namespace nanobind::detail
