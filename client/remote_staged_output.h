// Where a remote command writes a result while it arrives: FILE.partial, renamed over FILE once
// whole and checked, so that no reader sees half of one. Where FILE exists and is not a regular
// file (/dev/null, a FIFO, a terminal) the result goes to FILE itself: a rename would replace it
// with a regular file (as root, /dev/null for the whole machine), and there is nothing there for
// a reader to see half of.
#pragma once

#include <filesystem>
#include <string>
#include <system_error>

namespace tessera::cli {

class StagedOutput {
 public:
  explicit StagedOutput(std::string file) : file_(std::move(file)) {
    std::error_code error;
    const std::filesystem::file_status status = std::filesystem::status(file_, error);
    inPlace_ = !error && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status);
    path_ = inPlace_ ? file_ : file_ + ".partial";
  }
  // What to open and write.
  const std::string& path() const { return path_; }
  // The result whole: the staged file renamed onto FILE (an error where that fails).
  std::error_code publish() const {
    std::error_code error;
    if (!inPlace_) std::filesystem::rename(path_, file_, error);
    return error;
  }
  // The result abandoned: the staged file removed (FILE written in place is left as it is).
  void discard() const {
    std::error_code ignored;
    if (!inPlace_) std::filesystem::remove(path_, ignored);
  }

 private:
  std::string file_, path_;
  bool inPlace_ = false;
};

}  // namespace tessera::cli
