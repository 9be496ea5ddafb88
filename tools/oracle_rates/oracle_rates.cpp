// tessera-oracle-rates: the "oracle uniform rate" that Tessera's adaptive tessellation is compared
// with. For each model and tolerance eps (relative to the control mesh's bounding-box diagonal),
// the smallest rate R at which OpenSubdiv's Bfr::Tessellation, uniform rate R on every face and
// watertight (reference/uniform_tessellation.h), has a measured two-sided distance to the
// exact limit surface (reference/limit_distance.h) of at most eps·diagonal.
//
// The error falls roughly like 1/R², so R = 1, 2, 4, ... is measured until one is within eps, then
// the rates between the last failing and the first passing one are bisected, assuming the error
// is monotonic in R; every measurement is printed so that a non-monotonic case shows in the log.
// Measurements are shared between tolerances. The table is checked in as bench/oracle_rates.csv.
//
//   build/tools/tessera-oracle-rates                       # the default list, eps 1e-2,1e-3,1e-4
//   build/tools/tessera-oracle-rates --models bigguy,opensubdiv-shapes/catmark_rook --eps 1e-3
//       --out /tmp/rates.csv --measurements /tmp/all.csv --threads 2
//
// Names are looked up in --models-dir ($TESSERA_MODELS_DIR, else ../shared/models: run it from the
// repository root); paths are taken as they are. A tolerance whose next rate would pass
// --max-triangles (memory: ~100 bytes a triangle while measured) is written as ">R", R the
// largest rate measured.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>

#include "core/mesh/obj_reader.h"
#include "reference/limit_distance.h"
#include "reference/uniform_tessellation.h"

namespace tessera {
namespace {

using testing::LimitDistanceReport;
using testing::LimitSurface;

constexpr int kTriangleSamples = 4;

const char* const kDefaultModels[] = {"bigguy",
                                      "monsterfrog",
                                      "armorguy",
                                      "t-rex",
                                      "car",
                                      "opensubdiv-shapes/catmark_bishop",
                                      "opensubdiv-shapes/catmark_rook",
                                      "opensubdiv-shapes/catmark_cubes_semisharp",
                                      "opensubdiv-shapes/catmark_torus_creases0"};

struct Measurement {
  int rate = 0, limitSamples = 0;
  size_t triangles = 0, vertices = 0;
  LimitDistanceReport report;
  double seconds = 0;
};

// The measured distance of Bfr's uniform tessellation of one model, per rate, computed once.
class RateMeasurer {
 public:
  RateMeasurer(const std::string& name, const ControlMesh& mesh, size_t maxTriangles,
               std::ostream* measurements)
      : name_(name), surface_(mesh), maxTriangles_(maxTriangles), measurements_(measurements) {}

  const LimitSurface& surface() const { return surface_; }
  // Whether a rate's mesh fits the triangle budget (memory: ~100 bytes a triangle while measured).
  bool affordable(int rate) const {
    return testing::uniformTriangleCount(surface_, rate) <= maxTriangles_;
  }

  const Measurement& measure(int rate) {
    auto found = cache_.find(rate);
    if (found != cache_.end()) return found->second;
    const auto start = std::chrono::steady_clock::now();
    Measurement m;
    m.rate = rate;
    m.limitSamples = std::max(16, 2 * rate);
    {
      const testing::UniformTessellation mesh = testing::tessellateUniform(surface_, rate);
      m.triangles = mesh.triangleCount();
      m.vertices = mesh.positions.size();
      testing::LimitDistanceOptions options;
      options.triangleSamples = kTriangleSamples;
      options.limitSamples = m.limitSamples;
      m.report = testing::measureLimitDistance(surface_, mesh.view(), options);
    }
    m.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    log(m);
    return cache_[rate] = m;
  }

 private:
  void log(const Measurement& m) const {
    const testing::SurfaceLocation& at = m.report.twoSidedAt();
    std::printf(
        "%-24s R=%4d  %10zu tris  measured %.3e (limit->mesh %.3e, mesh->limit %.3e) at face %d/%d "
        "(%.3f, %.3f)"
        "  reprojected %zu  %.1f s\n",
        name_.c_str(), m.rate, m.triangles, m.report.twoSidedRelative(),
        m.report.limitToMeshRelative(), m.report.meshToLimitRelative(), at.face, at.subFace, at.u,
        at.v, m.report.trianglesReprojected, m.seconds);
    std::fflush(stdout);
    if (measurements_) {
      *measurements_ << name_ << ',' << m.rate << ',' << m.triangles << ',' << m.vertices << ','
                     << m.report.twoSidedRelative() << ',' << m.report.limitToMeshRelative() << ','
                     << m.report.meshToLimitRelative() << ',' << m.limitSamples << ','
                     << kTriangleSamples << ',' << m.seconds << std::endl;
    }
  }

  std::string name_;
  LimitSurface surface_;
  size_t maxTriangles_;
  std::ostream* measurements_;
  std::map<int, Measurement> cache_;
};

// Doubling, then bisection between the last failing and the first passing rate; nullopt when no
// rate up to maxRate (and within the triangle budget) is within eps, with `failing` the last
// rate measured.
std::optional<Measurement> oracleRate(RateMeasurer& measurer, double eps, int maxRate,
                                      int& failing) {
  failing = 0;
  int passing = 1;
  while (measurer.measure(passing).report.twoSidedRelative() > eps) {
    failing = passing;
    passing *= 2;
    if (passing <= maxRate && measurer.affordable(passing)) continue;
    // The doubled rate is over budget: the largest affordable rate below it is the last chance.
    int cap = failing;
    for (int step = (std::min(passing - 1, maxRate) - failing + 1) / 2; step > 0; step /= 2) {
      while (cap + step <= std::min(passing - 1, maxRate) && measurer.affordable(cap + step))
        cap += step;
    }
    if (cap == failing) return std::nullopt;
    passing = cap;
    if (measurer.measure(cap).report.twoSidedRelative() > eps) {
      failing = cap;
      return std::nullopt;
    }
    break;
  }
  while (passing - failing > 1) {
    const int middle = (failing + passing) / 2;
    (measurer.measure(middle).report.twoSidedRelative() <= eps ? passing : failing) = middle;
  }
  return measurer.measure(passing);
}

std::string resolveModel(const std::string& entry, const std::string& modelsDir) {
  if (std::filesystem::exists(entry)) return entry;
  return modelsDir + "/" + entry + ".obj";
}

std::string machineDescription() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line, cpu = "unknown CPU";
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) == 0) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  }
  char host[256] = "unknown";
  gethostname(host, sizeof host - 1);
  return std::string(host) + ", " + cpu + ", " +
         std::to_string(std::thread::hardware_concurrency()) + " hardware threads";
}

std::string utcNow() {
  const std::time_t now = std::time(nullptr);
  char text[64];
  std::strftime(text, sizeof text, "%Y-%m-%d %H:%M:%S UTC", std::gmtime(&now));
  return text;
}

void writeHeader(std::ostream& out, const std::string& command, int threads) {
  out << "# Oracle uniform rates: the smallest R at which OpenSubdiv Bfr::Tessellation at uniform "
         "rate R on every\n"
         "# face (watertight, quads as two triangles) is within eps * bounding-box diagonal of the "
         "exact limit\n"
         "# surface, measured two-sided (reference/limit_distance.h): mesh->limit from K x K "
         "barycentric\n"
         "# samples per triangle projected onto the limit surface, limit->mesh from an S x S grid "
         "per face domain,\n"
         "# S = max(16, 2R). Reference and tessellation positions: Bfr, approximation levels "
      << LimitSurface::kApproxLevel << "/" << LimitSurface::kApproxLevel
      << " (Far for interior\n"
         "# valence 2). Search: R = 1, 2, 4, ... then bisection, assuming the error is monotonic "
         "in R.\n"
         "# *_rel columns are distances divided by the control mesh's bounding-box diagonal.\n"
         "# rate \">R\": no rate within the triangle budget met eps; the row gives R's figures.\n";
  out << "# machine: " << machineDescription() << ", " << threads << " threads used\n";
  out << "# date: " << utcNow() << "\n";
  out << "# command: " << command << "\n";
  out << "model,eps,rate,triangles,vertices,measured_rel,limit_to_mesh_rel,mesh_to_limit_rel,"
         "samples_S,samples_K\n";
}

int run(int argc, char** argv) {
  CLI::App app{
      "Oracle uniform rates of OpenSubdiv Bfr tessellation against the exact limit surface"};
  std::vector<std::string> models, positional;
  std::vector<double> epsList = {1e-2, 1e-3, 1e-4};
  std::string out = "bench/oracle_rates.csv", measurementsPath;
  std::string modelsDir =
      std::getenv("TESSERA_MODELS_DIR") ? std::getenv("TESSERA_MODELS_DIR") : "../shared/models";
  int threads = int(std::thread::hardware_concurrency()), maxRate = 512;
  size_t maxTriangles = 100'000'000;
  app.add_option("paths", positional,
                 "OBJ files (or names under --models-dir); default: the benchmark list");
  app.add_option(
         "--models", models,
         "OBJ files or names under --models-dir, e.g. bigguy,opensubdiv-shapes/catmark_rook")
      ->delimiter(',');
  app.add_option("--models-dir", modelsDir,
                 "where names are looked up (default $TESSERA_MODELS_DIR or ../shared/models)");
  app.add_option("--eps", epsList, "tolerances relative to the bounding-box diagonal")
      ->delimiter(',');
  app.add_option("--out", out, "CSV table to write");
  app.add_option("--measurements", measurementsPath,
                 "also write every (model, rate) measurement to this CSV");
  app.add_option("--threads", threads, "worker threads")->check(CLI::PositiveNumber);
  app.add_option("--max-rate", maxRate, "give up on a tolerance beyond this rate")
      ->check(CLI::PositiveNumber);
  app.add_option("--max-triangles", maxTriangles,
                 "give up on a tolerance whose next rate has more triangles");
  CLI11_PARSE(app, argc, argv);

  models.insert(models.end(), positional.begin(), positional.end());
  if (models.empty()) models.assign(std::begin(kDefaultModels), std::end(kDefaultModels));
  std::sort(epsList.begin(), epsList.end(),
            std::greater<>());  // coarse first: its rates are reused
  tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism, size_t(threads));

  std::string command;
  for (int i = 0; i < argc; ++i) command += (i ? " " : "") + std::string(argv[i]);
  std::ofstream table(out);
  if (!table) throw std::runtime_error("cannot write " + out);
  writeHeader(table, command, threads);
  std::unique_ptr<std::ofstream> measurements;
  if (!measurementsPath.empty()) {
    measurements = std::make_unique<std::ofstream>(measurementsPath);
    *measurements << "model,rate,triangles,vertices,measured_rel,limit_to_mesh_rel,mesh_to_limit_"
                     "rel,samples_S,samples_K,seconds\n";
  }

  for (const std::string& entry : models) {
    const std::string path = resolveModel(entry, modelsDir);
    const std::string name = std::filesystem::path(path).stem().string();
    const auto start = std::chrono::steady_clock::now();
    const ControlMesh mesh = readObjFile(path);
    RateMeasurer measurer(name, mesh, maxTriangles, measurements.get());
    std::printf("%s: %d faces, %d domains, diagonal %.6g, reference %s\n", name.c_str(),
                mesh.faceCount(), measurer.surface().domainCount(), measurer.surface().diagonal(),
                measurer.surface().backend() == LimitSurface::Backend::kFar ? "Far" : "Bfr");
    for (double eps : epsList) {
      int failing = 0;
      const std::optional<Measurement> m = oracleRate(measurer, eps, maxRate, failing);
      table << name << ',' << eps << ',';
      if (!m) {  // ">R": R, the last rate measured, still misses eps; the row gives R's figures
        const Measurement& last = measurer.measure(failing);
        table << ">" << failing << ',' << last.triangles << ',' << last.vertices << ','
              << last.report.twoSidedRelative() << ',' << last.report.limitToMeshRelative() << ','
              << last.report.meshToLimitRelative() << ',' << last.limitSamples << ',' << kTriangleSamples
              << '\n' << std::flush;
        std::printf("%s eps %.0e: beyond rate %d (budget)\n", name.c_str(), eps, failing);
        continue;
      }
      table << m->rate << ',' << m->triangles << ',' << m->vertices << ','
            << m->report.twoSidedRelative() << ',' << m->report.limitToMeshRelative() << ','
            << m->report.meshToLimitRelative() << ',' << m->limitSamples << ',' << kTriangleSamples
            << '\n'
            << std::flush;
      std::printf("%s eps %.0e: oracle rate %d\n", name.c_str(), eps, m->rate);
    }
    std::printf("%s done in %.1f s\n", name.c_str(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return 0;
}

}  // namespace
}  // namespace tessera

int main(int argc, char** argv) {
  try {
    return tessera::run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tessera-oracle-rates: %s\n", e.what());
    return 1;
  }
}
