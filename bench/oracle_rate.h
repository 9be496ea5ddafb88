// The oracle uniform rate of a (model, ε) case: the smallest Bfr::Tessellation rate whose
// measured two-sided distance to the limit surface is within ε (relative to the bounding-box
// diagonal), found in hindsight by tools/oracle_rates and stored in bench/oracle_rates.csv.
// The baseline every benchmark against OpenSubdiv at "the oracle rate" runs at.
#pragma once

#include <cstdint>
#include <string>

namespace tessera::bench {

struct OracleRate {
  int rate = 0;  // 0: the case is not in the table
  int64_t triangles = 0;
  double measured = 0;  // relative to the diagonal
  // Rate ">R" in the table: no rate within the tool's triangle budget met ε, and R (the last one
  // measured) is run instead; its triangles and time are lower bounds of the oracle's.
  bool beyond = false;
};

// The row model,eps of bench/oracle_rates.csv (read once per process); eps matched by "%g".
OracleRate oracleRate(const std::string& model, double eps);

}  // namespace tessera::bench
