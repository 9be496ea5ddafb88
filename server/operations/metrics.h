// A small Prometheus metrics registry: counters and histograms with labels, plus gauges and
// counters read from elsewhere at scrape time, rendered in the text exposition format 0.0.4.
// Thread-safe; families live as long as the registry and are registered before serving starts.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace tessera::server {

using LabelValues = std::vector<std::string>;

class MetricFamily {
 public:
  MetricFamily(std::string name, std::string help, std::vector<std::string> labelNames)
      : name_(std::move(name)), help_(std::move(help)), labelNames_(std::move(labelNames)) {}
  virtual ~MetricFamily() = default;
  virtual void render(std::string& out) const = 0;

 protected:
  void header(std::string& out, const char* type) const;
  // name{a="x",b="y"} with extra appended inside the braces (for le="...").
  std::string series(const std::string& name, const LabelValues& values,
                     const std::string& extra = {}) const;
  const std::string name_;
  const std::string help_;
  const std::vector<std::string> labelNames_;
};

class CounterFamily final : public MetricFamily {
 public:
  using MetricFamily::MetricFamily;
  void add(const LabelValues& labels, double delta = 1.0);
  void render(std::string& out) const override;

 private:
  mutable std::mutex mutex_;
  std::map<LabelValues, double> values_;
};

class HistogramFamily final : public MetricFamily {
 public:
  HistogramFamily(std::string name, std::string help, std::vector<std::string> labelNames,
                  std::vector<double> upperBounds);
  void observe(const LabelValues& labels, double value);
  void render(std::string& out) const override;

 private:
  struct Series {
    std::vector<uint64_t> buckets;  // non-cumulative counts per upper bound
    uint64_t count = 0;
    double sum = 0.0;
  };
  const std::vector<double> upperBounds_;
  mutable std::mutex mutex_;
  std::map<LabelValues, Series> series_;
};

class MetricsRegistry {
 public:
  CounterFamily& counter(std::string name, std::string help,
                         std::vector<std::string> labelNames = {});
  HistogramFamily& histogram(std::string name, std::string help,
                             std::vector<std::string> labelNames, std::vector<double> upperBounds);
  // A value sampled at scrape time: "gauge" for levels, "counter" for totals kept elsewhere.
  void sampled(std::string name, std::string help, const char* type,
               std::function<double()> read);
  // A gauge that is always 1 and carries facts in its labels (Prometheus' *_info convention).
  void info(std::string name, std::string help, std::vector<std::string> labelNames,
            LabelValues labelValues);

  std::string render() const;

 private:
  mutable std::mutex mutex_;
  std::vector<std::unique_ptr<MetricFamily>> families_;
};

}  // namespace tessera::server
