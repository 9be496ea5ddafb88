#include "tests/support/model_stats.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace tessera::testing {
namespace {

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::stringstream stream(text);
  for (std::string part; std::getline(stream, part, separator);) parts.push_back(part);
  if (!text.empty() && text.back() == separator) parts.emplace_back();
  return parts;
}

// "3:238 4:8339" or "crease:7101 hole:1": space-separated name:count pairs.
template <typename Key>
std::map<Key, int> parseCounts(const std::string& text) {
  std::map<Key, int> counts;
  for (const std::string& pair : split(text, ' ')) {
    if (pair.empty()) continue;
    const size_t colon = pair.rfind(':');
    if (colon == std::string::npos) throw std::runtime_error("bad count '" + pair + "'");
    std::istringstream key(pair.substr(0, colon));
    Key name{};
    key >> name;
    counts[name] = std::stoi(pair.substr(colon + 1));
  }
  return counts;
}

}  // namespace

std::vector<ModelStats> readModelStats() {
  const std::string path = modelsDir() + "/MODELS-STATS.csv";
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::string line;
  std::getline(in, line);
  std::map<std::string, size_t> column;
  const std::vector<std::string> header = split(line, ',');
  for (size_t i = 0; i < header.size(); ++i) column[header[i]] = i;
  for (const char* name :
       {"file", "vertices", "faces", "face_sizes", "nonmanifold_edges", "tags"}) {
    if (!column.count(name)) throw std::runtime_error(path + " has no column " + name);
  }
  std::vector<ModelStats> rows;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const std::vector<std::string> cells = split(line, ',');
    if (cells.size() != header.size()) throw std::runtime_error("bad row in " + path + ": " + line);
    ModelStats row;
    row.file = cells[column["file"]];
    row.vertices = std::stoi(cells[column["vertices"]]);
    row.faces = std::stoi(cells[column["faces"]]);
    row.nonmanifoldEdges = std::stoi(cells[column["nonmanifold_edges"]]);
    row.faceSizeHistogram = parseCounts<int>(cells[column["face_sizes"]]);
    row.tagLines = parseCounts<std::string>(cells[column["tags"]]);
    rows.push_back(row);
  }
  return rows;
}

}  // namespace tessera::testing
