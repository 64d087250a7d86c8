// glint — `glint diff` from Python (see compare.h).
#include "python/compare.h"

#include <nlohmann/json.hpp>
#include <string>

#include "image/compare.h"
#include "scenes/json_reader.h"
#include "scenes/json_util.h"

namespace py = pybind11;

namespace glint::python {

namespace {

// The comparison `options` ask for: a JSON object with "a", "b" (the files) and the keys of
// `glint diff`'s options, named as in Python (fail, fail_percent, warn, warn_percent,
// statistical, significance, min_pass, max_error, spp_a, spp_b, heatmap, flip, ppd, flip_max,
// flip_map), in the command line's ranges. Errors name "diff()".
CompareOptions compareOptions(const std::string& options) {
  const std::string where = "diff()";
  const nlohmann::json doc = parseSceneJson(options, where);
  JsonReader r(doc, {where, ""});
  CompareOptions o;
  const Range percent{.ge = 0, .le = 100};
  o.a = r.get<std::string>("a");
  o.b = r.get<std::string>("b");
  o.thresholds.fail = r.get<double>("fail", o.thresholds.fail, kNonNegative);
  o.thresholds.failPercent = r.get<double>("fail_percent", o.thresholds.failPercent, percent);
  o.thresholds.warn = r.get<double>("warn", o.thresholds.warn, kNonNegative);
  o.thresholds.warnPercent = r.get<double>("warn_percent", o.thresholds.warnPercent, percent);
  o.statistical = r.get<bool>("statistical", false);
  StatisticalThresholds& t = o.statistics;
  t.significance = r.get<double>("significance", t.significance, {.ge = 1e-12, .le = 0.5});
  t.minPassPercent = r.get<double>("min_pass", t.minPassPercent, percent);
  t.maxError = r.get<double>("max_error", t.maxError, kNonNegative);
  t.sppA = r.get<int>("spp_a", t.sppA, kPositive);
  t.sppB = r.get<int>("spp_b", t.sppB, kPositive);
  o.heatMap = r.get<std::string>("heatmap", o.heatMap);
  o.flip = r.get<bool>("flip", o.flip);
  o.pixelsPerDegree = r.get<double>("ppd", o.pixelsPerDegree, kPositive);
  o.flipMax = r.get<double>("flip_max", o.flipMax, kUnit);
  o.flipMap = r.get<std::string>("flip_map", o.flipMap);
  r.finish();
  return o;
}

}  // namespace

void registerCompare(py::module_& m) {
  m.def(
      "compare",
      [](const std::string& options) {
        const CompareOptions o = compareOptions(options);
        const Comparison c = compareImages(o);
        return comparisonJson(o, c);
      },
      py::arg("options"), py::call_guard<py::gil_scoped_release>());
}

}  // namespace glint::python
