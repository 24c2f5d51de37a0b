// Numbers in error messages.
#pragma once
#include <sstream>
#include <string>

namespace gw {

// v with up to `digits` significant digits ("0.01", "1e+30", "inf").
inline std::string format_number(double v, int digits = 10) {
    std::ostringstream out;
    out.precision(digits);
    out << v;
    return out.str();
}

}  // namespace gw
