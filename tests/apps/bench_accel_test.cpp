// `glint bench-accel` end to end on a small generated mesh: the JSON's shape and values, the
// deterministic rays, --subsample, and usage errors (exit 2).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "test_support.h"

namespace glint {
namespace {

// An open box seen from above: a floor and four walls (10 triangles), so the camera sees
// triangles and some occlusion rays from the floor hit the walls.
std::string writeTray(const std::string& dir) {
  std::string path = dir + "/tray.obj";
  std::ofstream(path) << "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
                         "v -1 -1 0.5\nv 1 -1 0.5\nv 1 1 0.5\nv -1 1 0.5\n"
                         "f 1 2 3 4\n"
                         "f 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\nf 4 8 5 1\n";
  return path;
}

nlohmann::json readJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

std::set<std::string> keys(const nlohmann::json& j) {
  std::set<std::string> k;
  for (auto it = j.begin(); it != j.end(); ++it) k.insert(it.key());
  return k;
}

TEST(CliBenchAccel, JsonHasTheDocumentedShape) {
  std::string dir = test::scratchDir("bench_accel_json");
  std::string mesh = writeTray(dir), out = dir + "/result.json";
  test::CommandResult r =
      test::runGlint("bench-accel '" + mesh +
                     "' --width 64 --height 48 --spp 2 --accel embree --json '" + out + "'");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("embree"), std::string::npos) << r.out;  // the table
  EXPECT_EQ(r.err, "");                                         // no progress without a terminal

  nlohmann::json j = readJson(out);
  EXPECT_EQ(keys(j),
            (std::set<std::string>{"mesh", "triangles", "width", "height", "spp", "threads",
                                   "bare_embree_camera_mrays_per_second", "backends"}));
  EXPECT_EQ(j["mesh"], mesh);
  EXPECT_EQ(j["triangles"], 10);
  EXPECT_EQ(j["width"], 64);
  EXPECT_EQ(j["height"], 48);
  EXPECT_EQ(j["spp"], 2);
  EXPECT_GE(j["threads"].get<int>(), 1);
  EXPECT_GT(j["bare_embree_camera_mrays_per_second"].get<double>(), 0.0);

  ASSERT_EQ(keys(j["backends"]), (std::set<std::string>{"embree"}));
  const nlohmann::json& e = j["backends"]["embree"];
  EXPECT_EQ(keys(e), (std::set<std::string>{"build_seconds", "bytes", "camera_mrays_per_second",
                                            "occlusion_mrays_per_second", "camera_hits", "nodes",
                                            "leaves", "empty_leaves", "max_depth",
                                            "mean_prims_per_leaf", "sah_cost"}));
  EXPECT_GE(e["build_seconds"].get<double>(), 0.0);
  EXPECT_GT(e["camera_mrays_per_second"].get<double>(), 0.0);
  EXPECT_GT(e["occlusion_mrays_per_second"].get<double>(), 0.0);
  EXPECT_GT(e["camera_hits"].get<int64_t>(), 0);
  EXPECT_LE(e["camera_hits"].get<int64_t>(), 64 * 48 * 2);
}

// bench-accel on a tray of 32x24 pixels, 1 spp, Embree and the kd-tree, with `flag`; its JSON
// goes to `out`.
test::CommandResult smallEmbreeAndKdTree(const std::string& dir, const std::string& flag,
                                         const std::string& out) {
  const std::string mesh = writeTray(dir);
  return test::runGlint("bench-accel '" + mesh +
                        "' --width 32 --height 24 --spp 1 --accel embree,kdtree " + flag +
                        " --json '" + out + "'");
}

TEST(CliBenchAccel, HighQualityEmbreeBuildIsAnOptInKey) {
  std::string dir = test::scratchDir("bench_accel_hq");
  std::string out = dir + "/hq.json";
  test::CommandResult r = smallEmbreeAndKdTree(dir, "--embree-high-quality", out);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  nlohmann::json j = readJson(out);
  EXPECT_GE(j["backends"]["embree"]["high_quality_build_seconds"].get<double>(), 0.0);
  EXPECT_FALSE(j["backends"]["kdtree"].contains("high_quality_build_seconds"));
}

// --traversal-counts adds a table of per-ray work for the kd-trees to stdout, nothing to the
// JSON (whose keys the protocol fixes).
TEST(CliBenchAccel, TraversalCountsAreAnOptInTableForKdTrees) {
  std::string dir = test::scratchDir("bench_accel_counts");
  std::string out = dir + "/counts.json";
  test::CommandResult r = smallEmbreeAndKdTree(dir, "--traversal-counts", out);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("traversal per ray"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("kdtree         occlusion"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("embree         camera"), std::string::npos) << r.out;
  nlohmann::json j = readJson(out);
  EXPECT_EQ(keys(j["backends"]["kdtree"]), keys(j["backends"]["embree"]));
  test::CommandResult plain = test::runGlint("bench-accel '" + writeTray(dir) +
                                             "' --width 32 --height 24 --spp 1 --accel kdtree");
  ASSERT_EQ(plain.exitCode, 0) << plain.err;
  EXPECT_EQ(plain.out.find("traversal per ray"), std::string::npos);
}

TEST(CliBenchAccel, RaysAreTheSameForAnyThreadCount) {
  std::string dir = test::scratchDir("bench_accel_seed");
  std::string mesh = writeTray(dir);
  auto hits = [&](const std::string& extra, const std::string& name) {
    std::string out = dir + "/" + name + ".json";
    test::CommandResult r = test::runGlint("bench-accel '" + mesh +
                                           "' --quiet --width 40 --height 30 --spp 3 --accel "
                                           "embree --json '" +
                                           out + "' " + extra);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return readJson(out)["backends"]["embree"]["camera_hits"].get<int64_t>();
  };
  EXPECT_EQ(hits("--threads 1", "a"), hits("--threads 2", "b"));
}

TEST(CliBenchAccel, SubsampleKeepsThatManyTriangles) {
  std::string dir = test::scratchDir("bench_accel_subsample");
  std::string mesh = writeTray(dir), out = dir + "/result.json";
  test::CommandResult r =
      test::runGlint("bench-accel '" + mesh +
                     "' --quiet --width 16 --height 12 --spp 1 --accel embree --subsample 4 "
                     "--json '" +
                     out + "'");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(readJson(out)["triangles"], 4);
  r = test::runGlint("bench-accel '" + mesh + "' --quiet --subsample 11");
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("--subsample"), std::string::npos) << r.err;
}

TEST(CliBenchAccel, UnknownBackendIsAUsageError) {
  std::string dir = test::scratchDir("bench_accel_bad_name");
  std::string mesh = writeTray(dir);
  test::CommandResult r = test::runGlint("bench-accel '" + mesh + "' --accel embree,octree");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("octree"), std::string::npos) << r.err;
}

TEST(CliBenchAccel, MissingMeshIsAnError) {
  std::string dir = test::scratchDir("bench_accel_missing");
  test::CommandResult r = test::runGlint("bench-accel '" + dir + "/nothing.ply' --accel embree");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("nothing.ply"), std::string::npos) << r.err;
}

TEST(CliBenchAccel, MalformedMeshIsAnError) {
  std::string dir = test::scratchDir("bench_accel_malformed");
  std::ofstream(dir + "/bad.ply") << "not a ply\n";
  test::CommandResult r = test::runGlint("bench-accel '" + dir + "/bad.ply' --accel embree");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("bad.ply: cannot read mesh"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace glint
