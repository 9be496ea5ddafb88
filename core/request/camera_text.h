// A camera's vectors and viewport as people type them, parsed once for the CLI's flags and the
// HTTP front door's query parameters: "X,Y,Z" (eye, target, up) and "WIDTHxHEIGHT" (size).
// nullopt when malformed or followed by anything; each caller names the flag or parameter in its
// own error.
#pragma once

#include <cstdio>
#include <optional>
#include <string>

namespace tessera {

struct TypedVector {
  double x, y, z;
};

struct TypedSize {
  int width, height;
};

inline std::optional<TypedVector> parseXyz(const std::string& text) {
  TypedVector v;
  char tail;
  if (std::sscanf(text.c_str(), "%lf,%lf,%lf%c", &v.x, &v.y, &v.z, &tail) != 3) return std::nullopt;
  return v;
}

inline std::optional<TypedSize> parseWxH(const std::string& text) {
  TypedSize s;
  char tail;
  if (std::sscanf(text.c_str(), "%dx%d%c", &s.width, &s.height, &tail) != 2) return std::nullopt;
  return s;
}

}  // namespace tessera
