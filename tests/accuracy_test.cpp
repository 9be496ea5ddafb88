// core/request/accuracy.h: ε in model units for each mode, and η's range, each written once and
// used by the planner (core/surface/tolerance_model.h) and the server (server/calls/accuracy_limits.h).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/base/error.h"
#include "core/request/accuracy.h"

namespace tessera {
namespace {

TEST(Accuracy, EpsilonForScalesOnlyARelativeToleranceByTheDiagonal) {
  EXPECT_EQ(Accuracy::relative(1e-3).epsilonFor(250.0), 1e-3 * 250.0);
  EXPECT_EQ(Accuracy::absolute(0.02).epsilonFor(250.0), 0.02);
  // Pixels wait for a view, and a level asks for no ε.
  EXPECT_EQ(Accuracy::pixel(0.5).epsilonFor(250.0), 0.0);
  EXPECT_EQ(Accuracy::uniformLevel(8).epsilonFor(250.0), 0.0);
}

std::string refusal(double eta) {
  try {
    validateEta(eta, "request.eta");
  } catch (const TesseraError& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kInvalidInput);
    return e.what();
  }
  return "";
}

TEST(Accuracy, EtaOutsideZeroToOneIsRefusedNamingTheField) {
  EXPECT_EQ(refusal(0.0), "");  // the single-phase baseline
  EXPECT_EQ(refusal(0.5), "");
  EXPECT_EQ(refusal(std::nextafter(1.0, 0.0)), "");
  for (double eta : {1.0, -0.25, double(NAN), double(INFINITY)}) {
    const std::string message = refusal(eta);
    EXPECT_EQ(message.rfind("request.eta: must be in [0, 1)", 0), 0u) << eta << ": " << message;
  }
}

}  // namespace
}  // namespace tessera
