#include "bench/oracle_rate.h"

#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <utility>

namespace tessera::bench {
namespace {

std::string epsKey(double eps) {
  char key[32];
  std::snprintf(key, sizeof key, "%g", eps);
  return key;
}

// bench/oracle_rates.csv: model,eps,rate,triangles,vertices,measured_rel,...
std::map<std::pair<std::string, std::string>, OracleRate> readOracleTable() {
  std::map<std::pair<std::string, std::string>, OracleRate> rows;
  std::ifstream in(std::string(TESSERA_SOURCE_DIR) + "/bench/oracle_rates.csv");
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line.rfind("model,", 0) == 0) continue;
    std::stringstream fields(line);
    std::string model, eps, rate, triangles, vertices, measured;
    std::getline(fields, model, ',');
    std::getline(fields, eps, ',');
    std::getline(fields, rate, ',');
    std::getline(fields, triangles, ',');
    std::getline(fields, vertices, ',');
    std::getline(fields, measured, ',');
    const bool beyond = !rate.empty() && rate[0] == '>';
    rows[{model, epsKey(std::stod(eps))}] = {std::stoi(beyond ? rate.substr(1) : rate),
                                             std::stoll(triangles), std::stod(measured), beyond};
  }
  return rows;
}

}  // namespace

OracleRate oracleRate(const std::string& model, double eps) {
  static const std::map<std::pair<std::string, std::string>, OracleRate> table = readOracleTable();
  const auto found = table.find({model, epsKey(eps)});
  return found == table.end() ? OracleRate{} : found->second;
}

}  // namespace tessera::bench
