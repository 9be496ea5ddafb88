// The server's log lines as text (`time level key=value ...`, the default) or as one JSON object
// a line (`--log-format json`, for log collectors): time, level, and either the line's fields
// (a request's id, method, status, duration, peer, mesh, triangles, bytes) or its message.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace tessera::server {

enum class LogFormat { kText, kJson };

LogFormat logFormatNamed(const std::string& name);  // "text" or "json"
// Installs the format on spdlog's default logger.
void useLogFormat(LogFormat format);

// One structured line's payload: key=value pairs, or a JSON object that the JSON formatter
// merges into the line. Numbers stay unquoted in JSON; quoted text (a status message) is always
// quoted in text, other text only where it holds a space, a quote or nothing.
struct LogField {
  enum class Kind { kText, kQuoted, kNumber };
  std::string key, value;
  Kind kind = Kind::kText;
};
std::string structuredPayload(LogFormat format, const std::vector<LogField>& fields);

}  // namespace tessera::server
