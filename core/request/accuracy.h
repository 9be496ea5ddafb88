// A request's accuracy, one type from the RPC to the planner and the renderer: ε in model
// units, ε as a fraction of the control mesh's bounding-box diagonal, ε as pixels on screen
// for the request's camera (core/surface/tolerance_model.h projects it back per piece, MATH.md §4), or
// the paper's uniform level p (Table 2), which asks for no ε at all.
#pragma once

#include <cstdint>
#include <string_view>

namespace tessera {

// The finest uniform level a request may ask for (the planner's tables go that far).
inline constexpr int kMaxUniformLevel = 4096;

struct Accuracy {
  enum class Mode : uint8_t { kAbsolute, kRelative, kPixel, kUniformLevel };

  Mode mode = Mode::kAbsolute;
  double tolerance = 1e-3;  // kAbsolute: model units; kRelative: a fraction of the diagonal
  double pixels = 0.5;      // kPixel: on screen, for the camera that comes with the request
  int level = 0;            // kUniformLevel: p, per base face

  static Accuracy absolute(double epsilon) { return {Mode::kAbsolute, epsilon}; }
  static Accuracy relative(double fraction) { return {Mode::kRelative, fraction}; }
  static Accuracy pixel(double pixels) { return {Mode::kPixel, 0, pixels}; }
  static Accuracy uniformLevel(int p) { return {Mode::kUniformLevel, 0, 0, p}; }

  bool pixelAccurate() const { return mode == Mode::kPixel; }
  bool uniform() const { return mode == Mode::kUniformLevel; }
  // ε in model units on a mesh whose bounding-box diagonal is `diagonal` (a relative tolerance is
  // a fraction of it); 0 for pixels, whose ε depends on the view, and for a level, which has none.
  double epsilonFor(double diagonal) const {
    return mode == Mode::kRelative ? tolerance * diagonal : mode == Mode::kAbsolute ? tolerance : 0.0;
  }
};

// The checks, each written once; `where` names the field in messages ("relative",
// "settings.pixel_accuracy"). Each throws TesseraError (kInvalidInput):
// a finite number > 0 ("where: must be a finite number (got nan)", "where: must be positive");
void validatePositiveFinite(double value, std::string_view where);
// a tolerance: positive and finite, and below 1 when it is a fraction of the diagonal;
void validateTolerance(double tolerance, bool relative, std::string_view where);
// a uniform level in [1, kMaxUniformLevel];
void validateUniformLevel(int p, std::string_view where);
// whichever of the above the mode asks for (pixels: positive and finite; the camera is checked
// by validateCamera, and the pixels against its viewport by validatePixelsForViewport).
void validateAccuracy(const Accuracy& accuracy, std::string_view where);
// A pixel accuracy no larger than the viewport's larger side (a coarser one is meaningless).
void validatePixelsForViewport(double pixels, int width, int height, std::string_view where);
// η, the share of ε for the Bézier approximation (paper §5.1): in [0, 1), 0 the single-phase baseline.
void validateEta(double eta, std::string_view where);

}  // namespace tessera
