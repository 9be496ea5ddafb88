#include "server/operations/metrics.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tessera::server {
namespace {

std::string escapeLabelValue(const std::string& value) {
  std::string out;
  for (char c : value) {
    if (c == '\\') out += "\\\\";
    else if (c == '"') out += "\\\"";
    else if (c == '\n') out += "\\n";
    else out += c;
  }
  return out;
}

std::string formatValue(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "+Inf" : "-Inf";
  return fmt::format("{}", v);
}

class SampledFamily final : public MetricFamily {
 public:
  SampledFamily(std::string name, std::string help, const char* type, std::function<double()> read)
      : MetricFamily(std::move(name), std::move(help), {}), type_(type), read_(std::move(read)) {}
  void render(std::string& out) const override {
    header(out, type_);
    double value = 0.0;
    // A failing source (the database is down) must not break the whole scrape.
    try {
      value = read_();
    } catch (const std::exception&) {
      value = std::nan("");
    }
    out += series(name_, {}) + " " + formatValue(value) + "\n";
  }

 private:
  const char* type_;
  std::function<double()> read_;
};

class InfoFamily final : public MetricFamily {
 public:
  InfoFamily(std::string name, std::string help, std::vector<std::string> labelNames, LabelValues values)
      : MetricFamily(std::move(name), std::move(help), std::move(labelNames)), values_(std::move(values)) {}
  void render(std::string& out) const override {
    header(out, "gauge");
    out += series(name_, values_) + " 1\n";
  }

 private:
  const LabelValues values_;
};

}  // namespace

void MetricFamily::header(std::string& out, const char* type) const {
  out += fmt::format("# HELP {} {}\n# TYPE {} {}\n", name_, help_, name_, type);
}

std::string MetricFamily::series(const std::string& name, const LabelValues& values,
                                 const std::string& extra) const {
  std::string labels;
  for (size_t i = 0; i < labelNames_.size() && i < values.size(); ++i) {
    if (!labels.empty()) labels += ',';
    labels += fmt::format("{}=\"{}\"", labelNames_[i], escapeLabelValue(values[i]));
  }
  if (!extra.empty()) labels += (labels.empty() ? "" : ",") + extra;
  return labels.empty() ? name : name + "{" + labels + "}";
}

void CounterFamily::add(const LabelValues& labels, double delta) {
  std::lock_guard lock(mutex_);
  values_[labels] += delta;
}

void CounterFamily::render(std::string& out) const {
  header(out, "counter");
  std::lock_guard lock(mutex_);
  if (values_.empty() && labelNames_.empty()) out += name_ + " 0\n";
  for (const auto& [labels, value] : values_) {
    out += series(name_, labels) + " " + formatValue(value) + "\n";
  }
}

HistogramFamily::HistogramFamily(std::string name, std::string help,
                                 std::vector<std::string> labelNames,
                                 std::vector<double> upperBounds)
    : MetricFamily(std::move(name), std::move(help), std::move(labelNames)),
      upperBounds_(std::move(upperBounds)) {
  if (!std::is_sorted(upperBounds_.begin(), upperBounds_.end())) {
    throw std::invalid_argument("histogram bounds must be sorted");
  }
}

void HistogramFamily::observe(const LabelValues& labels, double value) {
  std::lock_guard lock(mutex_);
  Series& s = series_[labels];
  if (s.buckets.empty()) s.buckets.assign(upperBounds_.size(), 0);
  auto bucket = std::lower_bound(upperBounds_.begin(), upperBounds_.end(), value);
  if (bucket != upperBounds_.end()) ++s.buckets[bucket - upperBounds_.begin()];
  ++s.count;
  s.sum += value;
}

void HistogramFamily::render(std::string& out) const {
  header(out, "histogram");
  std::lock_guard lock(mutex_);
  for (const auto& [labels, s] : series_) {
    uint64_t cumulative = 0;
    for (size_t i = 0; i < upperBounds_.size(); ++i) {
      cumulative += s.buckets[i];
      std::string le = fmt::format("le=\"{}\"", formatValue(upperBounds_[i]));
      out += series(name_ + "_bucket", labels, le) + " " + std::to_string(cumulative) + "\n";
    }
    out += series(name_ + "_bucket", labels, "le=\"+Inf\"") + " " + std::to_string(s.count) + "\n";
    out += series(name_ + "_sum", labels) + " " + formatValue(s.sum) + "\n";
    out += series(name_ + "_count", labels) + " " + std::to_string(s.count) + "\n";
  }
}

CounterFamily& MetricsRegistry::counter(std::string name, std::string help,
                                        std::vector<std::string> labelNames) {
  auto family = std::make_unique<CounterFamily>(std::move(name), std::move(help),
                                                std::move(labelNames));
  CounterFamily& ref = *family;
  std::lock_guard lock(mutex_);
  families_.push_back(std::move(family));
  return ref;
}

HistogramFamily& MetricsRegistry::histogram(std::string name, std::string help,
                                            std::vector<std::string> labelNames,
                                            std::vector<double> upperBounds) {
  auto family = std::make_unique<HistogramFamily>(std::move(name), std::move(help),
                                                  std::move(labelNames), std::move(upperBounds));
  HistogramFamily& ref = *family;
  std::lock_guard lock(mutex_);
  families_.push_back(std::move(family));
  return ref;
}

void MetricsRegistry::sampled(std::string name, std::string help, const char* type,
                              std::function<double()> read) {
  std::lock_guard lock(mutex_);
  families_.push_back(
      std::make_unique<SampledFamily>(std::move(name), std::move(help), type, std::move(read)));
}

void MetricsRegistry::info(std::string name, std::string help, std::vector<std::string> labelNames,
                           LabelValues labelValues) {
  std::lock_guard lock(mutex_);
  families_.push_back(std::make_unique<InfoFamily>(std::move(name), std::move(help), std::move(labelNames),
                                                   std::move(labelValues)));
}

std::string MetricsRegistry::render() const {
  std::lock_guard lock(mutex_);
  std::string out;
  for (const auto& family : families_) family->render(out);
  return out;
}

}  // namespace tessera::server
