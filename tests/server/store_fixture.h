// A test that runs once per store backend: SQLite in a temporary folder, and PostgreSQL in a
// database of its own when TESSERA_TEST_POSTGRES_URL is set (skipped, saying why, otherwise).
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tests/server/server_process.h"
#include "tests/server/test_support.h"

namespace tessera::test {

enum class Backend { kSqlite, kPostgres };

class StoreTest : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override {
    if (GetParam() == Backend::kPostgres) {
      std::string whyNot;
      database_ = PostgresDatabase::create(&whyNot);
      if (!database_) GTEST_SKIP() << "PostgreSQL store test skipped: " << whyNot;
    }
  }

  std::string storeSpec() const {
    return database_ ? database_->url() : "sqlite:" + (dir_.path() / "meshes.db").string();
  }

  std::unique_ptr<ServerProcess> startServer(std::vector<std::string> flags = {}) {
    flags.insert(flags.begin(), {"--store", storeSpec()});
    return ServerProcess::start(dir_.path(), flags);
  }

  TempDir dir_;
  std::unique_ptr<PostgresDatabase> database_;
};

inline std::string backendName(const ::testing::TestParamInfo<Backend>& info) {
  return info.param == Backend::kSqlite ? "Sqlite" : "Postgres";
}

#define TESSERA_INSTANTIATE_STORE_TESTS(Suite)                                                \
  INSTANTIATE_TEST_SUITE_P(Store, Suite,                                                      \
                           ::testing::Values(::tessera::test::Backend::kSqlite,               \
                                             ::tessera::test::Backend::kPostgres),            \
                           ::tessera::test::backendName)

}  // namespace tessera::test
