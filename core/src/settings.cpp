// Validation of RenderSettings, derived from the table in settings.h.
#include "settings.h"

#include <stdexcept>
#include <string>
#include <type_traits>

#include "text.h"

namespace gw {
namespace {

[[noreturn]] void refuse(const char* name, const std::string& what) {
    throw std::invalid_argument(std::string("RenderSettings.") + name + " " + what);
}

template <class T>
void check(const char* name, T value, double lo, double hi) {
    if constexpr (std::is_enum_v<T>) {   // a named enumeration (enums.h): one of its values
        if (!enum_valid(value)) refuse(name, "has no valid value");
    } else {
        if constexpr (std::is_same_v<T, float>) {   // limits in the setting's own precision
            lo = double(float(lo));
            hi = double(float(hi));
        }
        const double v = double(value);
        if (!(v >= lo && v <= hi)) {   // NaN fails too
            std::string range = "[" + format_number(lo) + ", " + (std::isinf(hi) ? std::string("inf") : format_number(hi)) + "]";
            refuse(name, "must be in " + range + ", got " + format_number(v));
        }
    }
}
void check(const char*, bool, double, double) {}
void check(const char* name, const Region& r, double, double) {
    if (r.x < 0 || r.y < 0 || r.w < 0 || r.h < 0) refuse(name, "must be (x, y, w, h) with non-negative values");
    if ((r.w == 0) != (r.h == 0)) refuse(name, "must have w and h both >= 1 (or both 0: the whole image)");
}

}  // namespace

void validate_settings(const RenderSettings& s) {
#define GW_CHECK_SETTING(type, name, def, lo, hi, group, when, label, help) check(#name, s.name, lo, hi);
    GW_RENDER_SETTINGS(GW_CHECK_SETTING)
#undef GW_CHECK_SETTING
}

}  // namespace gw
