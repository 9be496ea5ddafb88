// The malformed-input catalogue: every file in tests/data/malformed/ must be refused by
// readObjFile + cutIntoSheets (what an upload runs) with the kind and message that expected.tsv
// lists for it. Non-manifold meshes left it when they were accepted (manifold_sheets_test.cpp).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/mesh/manifold_sheets.h"
#include "core/mesh/obj_reader.h"

namespace tessera {
namespace {

const std::string kCatalogueDir = std::string(TESSERA_SOURCE_DIR) + "/tests/data/malformed";

struct CatalogueEntry {
  std::string file;
  ErrorKind kind;
  std::string messagePart;
};

bool parseKind(const std::string& text, ErrorKind& kind) {
  static const std::map<std::string, ErrorKind> kKinds = {
      {"kInvalidInput", ErrorKind::kInvalidInput},
      {"kUnsupported", ErrorKind::kUnsupported},
      {"kLimitExceeded", ErrorKind::kLimitExceeded}};
  const auto found = kKinds.find(text);
  if (found == kKinds.end()) return false;
  kind = found->second;
  return true;
}

// expected.tsv: file <TAB> kind <TAB> message part; '#' starts a comment line.
std::vector<CatalogueEntry> readCatalogue() {
  std::ifstream in(kCatalogueDir + "/expected.tsv");
  EXPECT_TRUE(in) << "cannot open expected.tsv";
  std::vector<CatalogueEntry> entries;
  int lineNumber = 0;
  for (std::string line; std::getline(in, line);) {
    ++lineNumber;
    if (line.empty() || line[0] == '#') continue;
    const size_t tab1 = line.find('\t');
    const size_t tab2 = tab1 == std::string::npos ? tab1 : line.find('\t', tab1 + 1);
    CatalogueEntry entry;
    if (tab2 == std::string::npos ||
        !parseKind(line.substr(tab1 + 1, tab2 - tab1 - 1), entry.kind) || tab2 + 1 == line.size()) {
      ADD_FAILURE() << "expected.tsv:" << lineNumber << " is not 'file<TAB>kind<TAB>message'";
      continue;
    }
    entry.file = line.substr(0, tab1);
    entry.messagePart = line.substr(tab2 + 1);
    entries.push_back(entry);
  }
  return entries;
}

std::set<std::string> catalogueFiles() {
  std::set<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(kCatalogueDir)) {
    if (entry.path().extension() == ".obj") files.insert(entry.path().filename().string());
  }
  return files;
}

TEST(MalformedCatalogue, EveryFileIsRefusedAsExpected) {
  const std::vector<CatalogueEntry> entries = readCatalogue();
  EXPECT_GE(entries.size(), 20u);
  for (const CatalogueEntry& entry : entries) {
    SCOPED_TRACE(entry.file);
    const std::string path = kCatalogueDir + "/" + entry.file;
    try {
      cutIntoSheets(readObjFile(path));
      ADD_FAILURE() << "accepted";
    } catch (const TesseraError& error) {
      EXPECT_EQ(error.kind(), entry.kind) << error.what();
      EXPECT_NE(std::string(error.what()).find(entry.messagePart), std::string::npos)
          << "message: " << error.what() << "\nexpected to contain: " << entry.messagePart;
    }
  }
}

TEST(MalformedCatalogue, EveryFileHasExactlyOneEntry) {
  std::map<std::string, int> entriesPerFile;
  for (const CatalogueEntry& entry : readCatalogue()) ++entriesPerFile[entry.file];
  const std::set<std::string> files = catalogueFiles();
  const std::regex kNaming("[0-9][0-9]-[a-z0-9-]+\\.obj");
  for (const std::string& file : files) {
    EXPECT_TRUE(std::regex_match(file, kNaming)) << file << " is not named NN-short-name.obj";
    EXPECT_EQ(entriesPerFile[file], 1) << file << " needs exactly one line in expected.tsv";
  }
  for (const auto& [file, count] : entriesPerFile) {
    EXPECT_TRUE(files.count(file)) << "expected.tsv lists " << file << ", which does not exist";
  }
}

}  // namespace
}  // namespace tessera
