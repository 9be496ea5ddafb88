#include "core/request/accuracy.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "core/base/error.h"

namespace tessera {
namespace {

// Numbers as a user wrote them (1e-12, not 0.000000).
std::string shown(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

[[noreturn]] void refuse(std::string_view where, const std::string& what) {
  throwInvalid(std::string(where) + ": " + what);
}

}  // namespace

void validatePositiveFinite(double value, std::string_view where) {
  if (!std::isfinite(value)) refuse(where, "must be a finite number (got " + shown(value) + ")");
  if (value <= 0) refuse(where, "must be positive (got " + shown(value) + ")");
}

void validateTolerance(double tolerance, bool relative, std::string_view where) {
  validatePositiveFinite(tolerance, where);
  if (relative && tolerance >= 1) {
    refuse(where, "must be below 1, the whole bounding-box diagonal (got " + shown(tolerance) + ")");
  }
}

void validateUniformLevel(int p, std::string_view where) {
  if (p < 1 || p > kMaxUniformLevel) {
    refuse(where, "must be in [1, " + std::to_string(kMaxUniformLevel) + "] (got " + std::to_string(p) + ")");
  }
}

void validateAccuracy(const Accuracy& a, std::string_view where) {
  switch (a.mode) {
    case Accuracy::Mode::kAbsolute:
    case Accuracy::Mode::kRelative:
      return validateTolerance(a.tolerance, a.mode == Accuracy::Mode::kRelative, where);
    case Accuracy::Mode::kPixel:
      return validatePositiveFinite(a.pixels, where);
    case Accuracy::Mode::kUniformLevel:
      return validateUniformLevel(a.level, where);
  }
  refuse(where, "unknown accuracy mode " + std::to_string(int(a.mode)));
}

void validatePixelsForViewport(double pixels, int width, int height, std::string_view where) {
  if (pixels > std::max(width, height)) {
    refuse(where, shown(pixels) + " pixels is larger than the " + std::to_string(width) + "x" +
                      std::to_string(height) + " viewport");
  }
}

void validateEta(double eta, std::string_view where) {
  if (!std::isfinite(eta) || eta < 0 || eta >= 1) {
    refuse(where, "must be in [0, 1), 0 for the single-phase baseline (got " + shown(eta) + ")");
  }
}

}  // namespace tessera
