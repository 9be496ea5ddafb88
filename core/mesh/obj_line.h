// Pieces the OBJ reader shares between its statement and tag parsers: splitting a line into
// tokens, whole-token number parsing, and the "source:line: " context every reader error carries.
// Internal to core/mesh/obj_reader.cpp and core/mesh/obj_tags.cpp; not part of core's API.
#pragma once

#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <string_view>

#include "core/base/error.h"

namespace tessera::obj_detail {

// Where a statement came from. Errors name it so that a user can open the file at that line.
struct SourceLine {
  const std::string& source;
  int line = 0;

  std::string prefix() const { return source + ":" + std::to_string(line) + ": "; }
};

[[noreturn]] inline void failInvalid(const SourceLine& at, const std::string& what) {
  throwInvalid(at.prefix() + what);
}
[[noreturn]] inline void failUnsupported(const SourceLine& at, const std::string& what) {
  throwUnsupported(at.prefix() + what);
}
[[noreturn]] inline void failLimit(const SourceLine& at, const std::string& what) {
  throwLimit(at.prefix() + what);
}

// Makes a token safe to show in a message. The input may be binary and messages end up in gRPC
// statuses (UTF-8 only), so anything but printable ASCII is escaped and long tokens are cut short.
inline std::string printable(std::string_view token) {
  constexpr size_t kMaxShown = 40;
  std::string out;
  for (size_t i = 0; i < token.size() && i < kMaxShown; ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\x%02x", c);
      out += escaped;
    }
  }
  if (token.size() > kMaxShown) out += "...";
  return out;
}

// Appends rather than `"'" + ...`, which trips GCC 12's false -Wrestrict warning (bug 105651).
inline std::string quoted(std::string_view token) {
  std::string text = "'";
  text += printable(token);
  text += '\'';
  return text;
}

// %g keeps messages short and shows nan and inf as such.
inline std::string formatNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

// Splits one line at blanks. '\r' counts as a blank, which is all CRLF files need.
class LineTokens {
 public:
  explicit LineTokens(std::string_view line) : rest_(line) {}

  bool next(std::string_view& token) {
    size_t begin = 0;
    while (begin < rest_.size() && isBlank(rest_[begin])) ++begin;
    if (begin == rest_.size()) return false;
    size_t end = begin;
    while (end < rest_.size() && !isBlank(rest_[end])) ++end;
    token = rest_.substr(begin, end - begin);
    rest_.remove_prefix(end);
    return true;
  }

 private:
  static bool isBlank(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
  }
  std::string_view rest_;
};

// from_chars takes no leading '+', which some exporters write.
inline std::string_view withoutPlusSign(std::string_view token) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-' && token[1] != '+') {
    token.remove_prefix(1);
  }
  return token;
}

// The whole token must be the number: "12abc" is an error, not 12.
inline bool parseInt(std::string_view token, int& value) {
  token = withoutPlusSign(token);
  const char* end = token.data() + token.size();
  auto [ptr, ec] = std::from_chars(token.data(), end, value);
  return ec == std::errc() && ptr == end;
}

enum class NumberParse { kOk, kMalformed, kBeyondFloat };

// Goes through double so that values too small for float become zero or a denormal instead of
// an error; values too large for float are an error rather than a silent infinity. NaN and
// infinity spelled out ("nan", "inf") parse: callers decide whether they make sense.
// The number in double precision, refused (kBeyondFloat) where a float could not hold it.
inline NumberParse parseWide(std::string_view token, double& wide) {
  token = withoutPlusSign(token);
  const char* end = token.data() + token.size();
  auto [ptr, ec] = std::from_chars(token.data(), end, wide);
  if (ptr != end || (ec != std::errc() && ec != std::errc::result_out_of_range)) {
    return NumberParse::kMalformed;
  }
  if (ec == std::errc::result_out_of_range) return NumberParse::kBeyondFloat;
  if (std::isfinite(wide) && std::abs(wide) > std::numeric_limits<float>::max()) {
    return NumberParse::kBeyondFloat;
  }
  return NumberParse::kOk;
}

inline NumberParse parseFloat(std::string_view token, float& value) {
  double wide = 0.0;
  const NumberParse parsed = parseWide(token, wide);
  if (parsed == NumberParse::kOk) value = static_cast<float>(wide);
  return parsed;
}

}  // namespace tessera::obj_detail
