// The values the CLI's camera flags take, parsed once for the local and the remote commands:
// "X,Y,Z" (--eye, --target, --up) and "WIDTHxHEIGHT" (--size). nullopt when malformed or
// followed by anything; each command names the flag in its own error.
#pragma once

#include <cstdio>
#include <optional>
#include <string>

namespace tessera::cli {

struct FlagVector {
  double x, y, z;
};

struct FlagSize {
  int width, height;
};

inline std::optional<FlagVector> parseXyz(const std::string& text) {
  FlagVector v;
  char tail;
  if (std::sscanf(text.c_str(), "%lf,%lf,%lf%c", &v.x, &v.y, &v.z, &tail) != 3) return std::nullopt;
  return v;
}

inline std::optional<FlagSize> parseWxH(const std::string& text) {
  FlagSize s;
  char tail;
  if (std::sscanf(text.c_str(), "%dx%d%c", &s.width, &s.height, &tail) != 2) return std::nullopt;
  return s;
}

}  // namespace tessera::cli
