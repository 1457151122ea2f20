#include <cmath>
#include <sstream>

#include "mcpose/camera.h"

namespace mcpose {

bool Intrinsics::IsValid(std::string* error) const {
  std::ostringstream os;
  if (!std::isfinite(fx) || !std::isfinite(fy) || !std::isfinite(cx) || !std::isfinite(cy)) {
    os << "intrinsics are not finite (fx=" << fx << ", fy=" << fy << ", cx=" << cx << ", cy=" << cy
       << ")";
  } else if (fx <= 0 || fy <= 0) {
    os << "focal lengths must be positive (fx=" << fx << ", fy=" << fy << ")";
  } else if (width <= 0 || height <= 0) {
    os << "image size must be positive (" << width << "x" << height << ")";
  } else {
    return true;
  }
  if (error) *error = os.str();
  return false;
}

}  // namespace mcpose
