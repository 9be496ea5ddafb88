#include "server/operations/log_format.h"

#include <fmt/chrono.h>
#include <fmt/format.h>
#include <spdlog/pattern_formatter.h>
#include <spdlog/spdlog.h>

#include <nlohmann/json.hpp>
#include <stdexcept>

namespace tessera::server {
namespace {

constexpr const char* kTextPattern = "%Y-%m-%dT%H:%M:%S.%eZ %l %v";

// time and level, then a structured line's fields (its payload is a JSON object) or the message.
class JsonLineFormatter final : public spdlog::formatter {
 public:
  void format(const spdlog::details::log_msg& message, spdlog::memory_buf_t& out) override {
    const auto since = message.time.time_since_epoch();
    const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(since);
    const auto millis =
        std::chrono::duration_cast<std::chrono::milliseconds>(since - seconds).count();
    nlohmann::ordered_json line;
    line["time"] = fmt::format("{:%Y-%m-%dT%H:%M:%S}.{:03}Z",
                               fmt::gmtime(std::time_t(seconds.count())), millis);
    const auto level = spdlog::level::to_string_view(message.level);
    line["level"] = std::string(level.data(), level.size());
    const std::string payload(message.payload.data(), message.payload.size());
    // Only a structured line (structuredPayload) is an object; plain messages are not parsed.
    const nlohmann::ordered_json fields =
        !payload.empty() && payload.front() == '{'
            ? nlohmann::ordered_json::parse(payload, nullptr, false)
            : nlohmann::ordered_json();
    if (fields.is_object()) {
      for (const auto& [key, value] : fields.items()) line[key] = value;
    } else {
      line["message"] = payload;
    }
    // Invalid UTF-8 in a message (a client's name) is replaced, not thrown.
    const std::string text =
        line.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
    out.append(text.data(), text.data() + text.size());
  }
  std::unique_ptr<spdlog::formatter> clone() const override {
    return std::make_unique<JsonLineFormatter>();
  }
};

bool needsQuotes(const std::string& value) {
  return value.empty() || value.find_first_of(" \"=\n\t") != std::string::npos;
}

}  // namespace

LogFormat logFormatNamed(const std::string& name) {
  if (name == "text") return LogFormat::kText;
  if (name == "json") return LogFormat::kJson;
  throw std::invalid_argument("--log-format must be text or json, not " + name);
}

void useLogFormat(LogFormat format) {
  if (format == LogFormat::kJson)
    return spdlog::set_formatter(std::make_unique<JsonLineFormatter>());
  spdlog::set_pattern(kTextPattern, spdlog::pattern_time_type::utc);
}

std::string structuredPayload(LogFormat format, const std::vector<LogField>& fields) {
  if (format == LogFormat::kJson) {
    nlohmann::ordered_json object = nlohmann::ordered_json::object();
    for (const LogField& f : fields) {
      if (f.kind == LogField::Kind::kNumber) {
        object[f.key] = nlohmann::ordered_json::parse(f.value, nullptr, false);
      } else {
        object[f.key] = f.value;
      }
    }
    return object.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
  }
  std::string line;
  for (const LogField& f : fields) {
    if (!line.empty()) line += ' ';
    const bool quoted = f.kind == LogField::Kind::kQuoted ||
                        (f.kind == LogField::Kind::kText && needsQuotes(f.value));
    line += quoted ? fmt::format("{}={:?}", f.key, f.value) : f.key + "=" + f.value;
  }
  return line;
}

}  // namespace tessera::server
