// The per-model figures of shared/models/MODELS-STATS.csv, read at test time, so that reader and
// topology tests compare against counts that a separate tool computed from the same files.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "reference/models.h"

namespace tessera::testing {

struct ModelStats {
  std::string file;  // relative to modelsDir(), e.g. "opensubdiv-shapes/catmark_cube.obj"
  int vertices = 0;
  int faces = 0;
  int nonmanifoldEdges = 0;
  std::map<int, int> faceSizeHistogram;  // face size -> number of faces
  std::map<std::string, int> tagLines;   // tag name -> number of `t` lines with that name
};

// Rows of modelsDir()/MODELS-STATS.csv; columns are found by their header names. Throws
// std::runtime_error when the file is missing or a row does not parse.
std::vector<ModelStats> readModelStats();

}  // namespace tessera::testing
