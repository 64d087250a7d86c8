// glint tests — JsonReader, the transform parser and the sidecar / .json scene schema (no
// glTF files needed: the scene is built in memory).
#include "scenes/sidecar.h"

#include <gtest/gtest.h>

#include <array>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "scene_error_support.h"
#include "scenes/json_reader.h"
#include "scenes/json_util.h"

namespace glint {
namespace {

using test::errorFrom;

using nlohmann::json;

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

constexpr const char* kFile = "demo.glint.json";

SceneDescription apply(const std::string& text, SceneDescription scene = {},
                       SceneJsonKind kind = SceneJsonKind::Sidecar) {
  applySceneJsonText(text, kFile, kind, &scene);
  return scene;
}

SceneError applyError(const std::string& text, SceneDescription scene = {},
                      SceneJsonKind kind = SceneJsonKind::Sidecar) {
  return errorFrom([&] { applySceneJsonText(text, kFile, kind, &scene); });
}

// Reads {"value": ...} as T through a reader, like every schema does.
template <class T>
T readOne(const std::string& text, const Range& range = {}) {
  json doc = parseJson(text, "t.json");
  JsonReader r(doc, {"t.json", ""});
  T v = r.get<T>("value", range);
  r.finish();
  return v;
}

template <class T>
SceneError readOneError(const std::string& text, const Range& range = {}) {
  return errorFrom([&] { readOne<T>(text, range); });
}

Transform transformOf(const std::string& text) {
  json doc = parseJson(text, "t.json");
  return readTransform(doc, {"t.json", "/transform"});
}

SceneError transformError(const std::string& text) {
  return errorFrom([&] { transformOf(text); });
}

void expectNear(Vec3f a, Vec3f b, float tolerance = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

// ---------------------------------------------------------------------------------------------
// JsonReader
// ---------------------------------------------------------------------------------------------

TEST(JsonReader, ReadsTypedValuesAndFallbacks) {
  json doc = parseJson(R"({"i": 3, "f": 2.5, "b": true, "s": "x", "v": [1, 2, 3], "u": 7})", "t");
  JsonReader r(doc, {"t", ""});
  EXPECT_EQ(r.get<int>("i"), 3);
  EXPECT_FLOAT_EQ(r.get<float>("f"), 2.5f);
  EXPECT_TRUE(r.get<bool>("b"));
  EXPECT_EQ(r.get<std::string>("s"), "x");
  EXPECT_EQ(r.get<Vec3f>("v"), (Vec3f{1, 2, 3}));
  EXPECT_EQ(r.get<uint64_t>("u"), 7u);
  EXPECT_EQ(r.get<int>("missing", 42), 42);
  EXPECT_FALSE(r.optional<float>("also missing").has_value());
  EXPECT_NO_THROW(r.finish());
}

TEST(JsonReader, IntegerIsAcceptedAsNumber) {
  EXPECT_FLOAT_EQ(readOne<float>(R"({"value": 4})"), 4);
}

TEST(JsonReader, WrongTypeNamesExpectedAndActual) {
  EXPECT_SCENE_ERROR(readOneError<int>(R"({"value": "64"})"), "t.json", "/value",
                     "expected integer, got string");
  EXPECT_SCENE_ERROR(readOneError<int>(R"({"value": 6.5})"), "t.json", "/value",
                     "expected integer, got number");
  EXPECT_SCENE_ERROR(readOneError<bool>(R"({"value": 1})"), "t.json", "/value",
                     "expected boolean, got integer");
  EXPECT_SCENE_ERROR(readOneError<float>(R"({"value": null})"), "t.json", "/value",
                     "expected number, got null");
}

TEST(JsonReader, RangeViolationNamesTheBound) {
  EXPECT_SCENE_ERROR(readOneError<int>(R"({"value": 0})", kPositive), "t.json", "/value",
                     "must be > 0");
  EXPECT_SCENE_ERROR(readOneError<float>(R"({"value": -0.5})", kNonNegative), "t.json", "/value",
                     "must be >= 0");
  EXPECT_SCENE_ERROR(readOneError<float>(R"({"value": 180})", {.gt = 0, .lt = 180}), "t.json",
                     "/value", "must be > 0 and < 180");
  EXPECT_FLOAT_EQ(readOne<float>(R"({"value": 90})", {.ge = 0, .le = 90}), 90);
}

TEST(JsonReader, NumbersBeyondFloatRangeAreNotFinite) {
  EXPECT_SCENE_ERROR(readOneError<float>(R"({"value": 1e39})"), "t.json", "/value",
                     "must be finite");
  json inf = {{"value", -std::numeric_limits<double>::infinity()}};
  EXPECT_SCENE_ERROR(errorFrom([&] {
                       readValue<float>(inf["value"], {"t.json", "/value"});
                     }),
                     "t.json", "/value", "must be finite");
  EXPECT_SCENE_ERROR(readOneError<Vec3f>(R"({"value": [0, 1e39, 0]})"), "t.json", "/value/1",
                     "must be finite");
}

TEST(JsonReader, IntegerOutOfRangeIsRejected) {
  EXPECT_SCENE_ERROR(readOneError<int>(R"({"value": 3000000000})"), "t.json", "/value",
                     "out of range");
  EXPECT_SCENE_ERROR(readOneError<uint64_t>(R"({"value": -1})"), "t.json", "/value",
                     "must be >= 0");
}

TEST(JsonReader, VectorsNeedExactlyThreeNumbers) {
  EXPECT_SCENE_ERROR(readOneError<Vec3f>(R"({"value": [1, 2]})"), "t.json", "/value",
                     "expected 3 numbers, got 2");
  EXPECT_SCENE_ERROR(readOneError<Vec3f>(R"({"value": 1})"), "t.json", "/value",
                     "expected an array of 3 numbers, got integer");
  EXPECT_SCENE_ERROR(readOneError<Vec3f>(R"({"value": [1, "2", 3]})"), "t.json", "/value/1",
                     "expected number, got string");
  EXPECT_SCENE_ERROR(readOneError<Vec3f>(R"({"value": [1, -2, 3]})", kNonNegative), "t.json",
                     "/value/1", "must be >= 0");
}

TEST(JsonReader, MissingRequiredKeyIsReportedAtTheObject) {
  json doc = parseJson(R"({"inner": {}})", "t.json");
  JsonReader r(doc, {"t.json", ""});
  EXPECT_SCENE_ERROR(errorFrom([&] { r.object("inner").get<float>("radius"); }), "t.json", "/inner",
                     "missing required key 'radius'");
}

TEST(JsonReader, UnknownKeySuggestsTheClosestKnownKey) {
  json doc = parseJson(R"({"spq": 4})", "t.json");
  JsonReader r(doc, {"t.json", "/render"});
  r.get<int>("spp", 16);
  r.get<int>("seed", 0);
  EXPECT_SCENE_ERROR(errorFrom([&] { r.finish(); }), "t.json", "/render/spq",
                     "unknown key 'spq'; did you mean 'spp'?");
}

TEST(JsonReader, UnknownKeyWithoutACloseMatchHasNoSuggestion) {
  json doc = parseJson(R"({"completely_different": 4})", "t.json");
  JsonReader r(doc, {"t.json", ""});
  r.get<int>("spp", 16);
  SceneError e = errorFrom([&] { r.finish(); });
  EXPECT_SCENE_ERROR(e, "t.json", "/completely_different", "unknown key 'completely_different'");
  EXPECT_EQ(e.message().find("did you mean"), std::string::npos);
}

TEST(JsonReader, FinishChecksChildReaders) {
  json doc = parseJson(R"({"list": [{"a": 1}, {"a": 2, "b": 3}], "obj": {"c": 1}})", "t.json");
  JsonReader r(doc, {"t.json", ""});
  for (JsonReader* item : r.objects("list")) item->get<int>("a");
  r.object("obj").get<int>("c");
  EXPECT_SCENE_ERROR(errorFrom([&] { r.finish(); }), "t.json", "/list/1/b", "unknown key 'b'");
}

TEST(JsonReader, ObjectOfWrongTypeIsRejected) {
  json doc = parseJson(R"({"filter": [1]})", "t.json");
  JsonReader r(doc, {"t.json", "/render"});
  EXPECT_SCENE_ERROR(errorFrom([&] { r.object("filter"); }), "t.json", "/render/filter",
                     "expected object, got array");
}

TEST(JsonReader, OneOfRejectsOtherStringsAndSuggests) {
  json doc = parseJson(R"({"type": "gausian", "kind": "b"})", "t.json");
  JsonReader r(doc, {"t.json", ""});
  SceneError e = errorFrom([&] { r.oneOf("type", {"box", "tent", "gaussian"}); });
  EXPECT_SCENE_ERROR(e, "t.json", "/type", "'gausian' is not one of 'box', 'tent', 'gaussian'");
  EXPECT_NE(e.message().find("did you mean 'gaussian'?"), std::string::npos);
  enum class Kind { A, B };
  EXPECT_EQ(r.oneOf<Kind>("kind", {{"a", Kind::A}, {"b", Kind::B}}), Kind::B);
  EXPECT_EQ(r.oneOf<Kind>("absent", {{"a", Kind::A}, {"b", Kind::B}}, Kind::A), Kind::A);
  EXPECT_EQ(r.oneOf("absent too", {"x", "y"}, "y"), "y");
}

TEST(JsonReader, ClosestMatchToleratesTranspositions) {
  EXPECT_EQ(closestMatch("transalte", {"translate", "rotate"}), "translate");
  EXPECT_EQ(closestMatch("radus", {"radius", "type"}), "radius");
  EXPECT_EQ(closestMatch("zzz", {"radius", "type"}), "");
}

// --- sizes, indices, number arrays, lenient mode (the glTF reader's needs) ---

TEST(JsonReader, DoublesAreReadAsWritten) {
  EXPECT_EQ(readOne<double>(R"({"value": 1.0000000001})"), 1.0000000001);
  // The range is checked before rounding: 1.0000000001 is a float 1, but it is not <= 1.
  EXPECT_SCENE_ERROR(readOneError<double>(R"({"value": 1.0000000001})", kUnit), "t.json", "/value",
                     "must be >= 0 and <= 1");
  // Strict doubles (the sidecar's time and fps) need only be finite; lenient ones (glTF's
  // numbers, kept as floats) must fit a float.
  EXPECT_EQ(readOne<double>(R"({"value": 1e39})"), 1e39);
  json doc = parseJson(R"({"value": 1e39, "fits": -3.4e38})", "t.gltf");
  JsonReader lenient(doc, {"t.gltf", ""}, JsonMode::Lenient);
  EXPECT_SCENE_ERROR(errorFrom([&] { lenient.get<double>("value"); }), "t.gltf", "/value",
                     "must be finite (the number is too large for a float)");
  EXPECT_EQ(lenient.get<double>("fits"), -3.4e38);
}

TEST(JsonReader, SizesAcceptIntegralNumbersOnly) {
  json doc = parseJson(
      R"({"a": 3, "b": 3.0, "c": -3, "d": 2.5, "e": "three", "f": -1.0, "g": null, "h": 1e16})",
      "t.json");
  JsonReader r(doc, {"t.json", ""});
  EXPECT_EQ(r.getSize("a"), 3u);
  EXPECT_EQ(r.getSize("b"), 3u);
  EXPECT_EQ(r.getSize("missing", 7), 7u);
  EXPECT_SCENE_ERROR(errorFrom([&] { r.getSize("c"); }), "t.json", "/c",
                     "must not be negative (got -3)");
  EXPECT_SCENE_ERROR(errorFrom([&] { r.getSize("d"); }), "t.json", "/d",
                     "expected a non-negative integer, got number 2.5");
  EXPECT_SCENE_ERROR(errorFrom([&] { r.getSize("e"); }), "t.json", "/e",
                     "expected a non-negative integer, got string \"three\"");
  EXPECT_SCENE_ERROR(errorFrom([&] { r.getSize("f"); }), "t.json", "/f",
                     "expected a non-negative integer, got number -1.0");
  EXPECT_SCENE_ERROR(errorFrom([&] { r.getSize("g"); }), "t.json", "/g",
                     "expected a non-negative integer, got null");
  // Beyond 2^53 a double no longer holds every integer: written as a number, it is refused.
  EXPECT_SCENE_ERROR(errorFrom([&] { r.getSize("h"); }), "t.json", "/h",
                     "expected a non-negative integer");
  EXPECT_SCENE_ERROR(errorFrom([&] { r.getSize("absent"); }), "t.json", "",
                     "missing required key 'absent'");
  EXPECT_NO_THROW(r.finish());
}

TEST(JsonReader, IndicesNameWhatDoesNotExist) {
  json doc = parseJson(R"({"accessor": 7, "mesh": 2, "ok": 2.0, "nodes": [0, 5]})", "t.json");
  JsonReader r(doc, {"t.json", "/meshes/0"});
  EXPECT_EQ(r.index("ok", 3, "accessor"), 2);
  EXPECT_EQ(r.index("absent", 3, "accessor", -1), -1);
  EXPECT_SCENE_ERROR(errorFrom([&] { r.index("accessor", 3, "accessor"); }), "t.json",
                     "/meshes/0/accessor", "accessor 7 does not exist (3 accessors in the file)");
  EXPECT_SCENE_ERROR(errorFrom([&] { r.index("accessor", 1, "accessor", -1); }), "t.json",
                     "/meshes/0/accessor", "accessor 7 does not exist (1 accessor in the file)");
  EXPECT_SCENE_ERROR(errorFrom([&] { r.index("mesh", 2, "mesh"); }), "t.json", "/meshes/0/mesh",
                     "mesh 2 does not exist (2 meshes in the file)");
  std::vector<JsonItem> nodes = r.array("nodes");
  EXPECT_EQ(nodes[0].asIndex(5, "node"), 0);
  EXPECT_SCENE_ERROR(errorFrom([&] { nodes[1].asIndex(5, "node"); }), "t.json", "/meshes/0/nodes/1",
                     "node 5 does not exist (5 nodes in the file)");
}

TEST(JsonReader, NumberArraysHaveExactlyNElements) {
  json doc =
      parseJson(R"({"v": [1, 2.5, 1.0000000001], "short": [1, 2], "big": [0, 1e39]})", "t.json");
  JsonReader r(doc, {"t.json", ""});
  std::array<double, 3> v = r.numbers<3>("v");
  EXPECT_EQ(v[1], 2.5);
  EXPECT_EQ(v[2], 1.0000000001);  // as written, not rounded to a float
  EXPECT_SCENE_ERROR(errorFrom([&] { r.numbers<3>("short"); }), "t.json", "/short",
                     "expected 3 numbers, got 2");
  JsonReader lenient(doc, {"t.gltf", ""}, JsonMode::Lenient);
  EXPECT_SCENE_ERROR(errorFrom([&] { lenient.numbers<2>("big"); }), "t.gltf", "/big/1",
                     "must be finite");
  EXPECT_SCENE_ERROR(errorFrom([&] { r.numbers<3>("v", {.le = 2}); }), "t.json", "/v/1",
                     "must be <= 2");
}

TEST(JsonReader, LenientFinishAcceptsUnknownKeysInEveryChild) {
  json doc = parseJson(R"({"asset": {"version": "2.0", "generator": "x", "extras": {"a": 1}},
                           "nodes": [{"name": "n", "extensions": {"VENDOR_thing": {}}}],
                           "unknownTopLevel": 1})",
                       "t.gltf");
  JsonReader lenient(doc, {"t.gltf", ""}, JsonMode::Lenient);
  EXPECT_EQ(lenient.mode(), JsonMode::Lenient);
  EXPECT_EQ(lenient.object("asset").get<std::string>("version"), "2.0");
  for (JsonReader* node : lenient.objects("nodes")) {
    EXPECT_EQ(node->mode(), JsonMode::Lenient);
    node->get<std::string>("name");
  }
  EXPECT_NO_THROW(lenient.finish());
  // The same reads in strict mode refuse the first key never read.
  JsonReader strict(doc, {"t.gltf", ""});
  strict.object("asset").get<std::string>("version");
  for (JsonReader* node : strict.objects("nodes")) node->get<std::string>("name");
  EXPECT_SCENE_ERROR(errorFrom([&] { strict.finish(); }), "t.gltf", "/unknownTopLevel",
                     "unknown key 'unknownTopLevel'");
}

TEST(JsonReader, AnElementReaderIsItsOwnAndKeepsTheMode) {
  json doc = parseJson(R"({"list": [{"a": 1, "b": 2}, 3]})", "t.json");
  JsonReader r(doc, {"t.json", ""});
  std::vector<JsonItem> items = r.array("list");
  JsonReader element(items[0]);
  EXPECT_EQ(element.where().pointer, "/list/0");
  EXPECT_EQ(element.mode(), JsonMode::Strict);
  EXPECT_EQ(element.get<int>("a"), 1);
  EXPECT_NO_THROW(r.finish());  // the parent does not own it
  EXPECT_SCENE_ERROR(errorFrom([&] { element.finish(); }), "t.json", "/list/0/b",
                     "unknown key 'b'");
  EXPECT_SCENE_ERROR(errorFrom([&] { JsonReader notAnObject(items[1]); }), "t.json", "/list/1",
                     "expected object, got integer");
  JsonReader lenient(doc, {"t.gltf", ""}, JsonMode::Lenient);
  std::vector<JsonItem> lenientItems = lenient.array("list");
  JsonReader lenientElement(lenientItems[0]);
  EXPECT_EQ(lenientElement.mode(), JsonMode::Lenient);
  EXPECT_NO_THROW(lenientElement.finish());
  EXPECT_SCENE_ERROR(errorFrom([&] { JsonReader notAnObject(lenientItems[1]); }), "t.gltf",
                     "/list/1", "expected an object, got integer");
}

TEST(JsonReader, LenientModeKeepsTheGltfWording) {
  json doc = parseJson(
      R"({"o": [1], "n": "1", "a": {}, "v": [1, 2], "w": 1, "k": {"keys": [[0, 1]]}, "s": [1, "x"]})",
      "t.gltf");
  JsonReader r(doc, {"t.gltf", "/materials/0"}, JsonMode::Lenient);
  EXPECT_SCENE_ERROR(errorFrom([&] { r.get<double>("absent"); }), "t.gltf", "/materials/0",
                     "missing required property 'absent'");
  EXPECT_SCENE_ERROR(errorFrom([&] { r.object("o"); }), "t.gltf", "/materials/0/o",
                     "expected an object, got array");
  EXPECT_SCENE_ERROR(errorFrom([&] { r.get<double>("n"); }), "t.gltf", "/materials/0/n",
                     "expected a number, got string");
  EXPECT_SCENE_ERROR(errorFrom([&] { r.array("a"); }), "t.gltf", "/materials/0/a",
                     "expected an array, got object");
  EXPECT_SCENE_ERROR(errorFrom([&] { r.numbers<3>("v"); }), "t.gltf", "/materials/0/v",
                     "expected an array of 3 numbers");
  EXPECT_SCENE_ERROR(errorFrom([&] { r.numbers<3>("w"); }), "t.gltf", "/materials/0/w",
                     "expected an array of 3 numbers");
  // glTF has no keyframe objects: one is a value of the wrong type.
  EXPECT_SCENE_ERROR(errorFrom([&] { r.get<float>("k"); }), "t.gltf", "/materials/0/k",
                     "expected a number, got object");
  // Array elements carry the mode.
  std::vector<JsonItem> s = r.array("s");
  EXPECT_EQ(s[1].as<std::string>(), "x");
  EXPECT_SCENE_ERROR(errorFrom([&] { s[0].as<std::string>(); }), "t.gltf", "/materials/0/s/0",
                     "expected a string, got integer");
  // Strict wording for the same problems, unchanged.
  JsonReader strict(doc, {"t.json", ""});
  EXPECT_SCENE_ERROR(errorFrom([&] { strict.get<double>("absent"); }), "t.json", "",
                     "missing required key 'absent'");
  EXPECT_SCENE_ERROR(errorFrom([&] { strict.get<double>("n"); }), "t.json", "/n",
                     "expected number, got string");
  EXPECT_SCENE_ERROR(errorFrom([&] { strict.get<float>("k"); }), "t.json", "/k",
                     "keyframes are not allowed here");
}

// ---------------------------------------------------------------------------------------------
// Transforms
// ---------------------------------------------------------------------------------------------

TEST(JsonReader, TransformFromSixteenNumbersIsRowMajor) {
  Transform t = transformOf("[1,0,0,5, 0,1,0,6, 0,0,1,7, 0,0,0,1]");
  EXPECT_EQ(t.point({0, 0, 0}), (Vec3f{5, 6, 7}));
  expectNear(t.inverse().point({5, 6, 7}), {0, 0, 0});
}

TEST(JsonReader, TransformFromFourRows) {
  Transform t = transformOf("[[2,0,0,1], [0,2,0,0], [0,0,2,0], [0,0,0,1]]");
  EXPECT_EQ(t.point({1, 1, 1}), (Vec3f{3, 2, 2}));
}

TEST(JsonReader, TransformOperationsApplyInOrder) {
  // Scale first, then translate: (1,0,0) -> (2,0,0) -> (2,0,3).
  Transform t = transformOf(R"([{"scale": 2}, {"translate": [0, 0, 3]}])");
  expectNear(t.point({1, 0, 0}), {2, 0, 3});
  // Translate first, then scale: (1,0,0) -> (1,0,3) -> (2,0,6).
  Transform u = transformOf(R"([{"translate": [0, 0, 3]}, {"scale": [2, 2, 2]}])");
  expectNear(u.point({1, 0, 0}), {2, 0, 6});
  expectNear(u.inverse().point({2, 0, 6}), {1, 0, 0});
}

TEST(JsonReader, TransformRotateAndMatrixOperations) {
  Transform r = transformOf(R"([{"rotate": {"axis": [0, 0, 1], "degrees": 90}}])");
  expectNear(r.point({1, 0, 0}), {0, 1, 0});
  Transform m = transformOf(
      R"([{"matrix": [1,0,0,1, 0,1,0,0, 0,0,1,0, 0,0,0,1]},
          {"rotate": {"axis": [0,0,1], "degrees": 90}}])");
  expectNear(m.point({0, 0, 0}), {0, 1, 0});  // moved to (1,0,0), then rotated
  EXPECT_TRUE(transformOf("[]").isIdentity());
}

TEST(JsonReader, SingularMatrixIsAnErrorAtItsPointer) {
  EXPECT_SCENE_ERROR(transformError("[1,0,0,0, 0,0,0,0, 0,0,1,0, 0,0,0,1]"), "t.json", "/transform",
                     "singular");
  EXPECT_SCENE_ERROR(
      transformError(
          R"([{"translate": [1,0,0]}, {"matrix": [[1,2,0,0],[2,4,0,0],[0,0,1,0],[0,0,0,1]]}])"),
      "t.json", "/transform/1/matrix", "singular");
  EXPECT_SCENE_ERROR(transformError(R"([{"scale": [1, 0, 1]}])"), "t.json", "/transform/0/scale",
                     "must not be zero");
}

TEST(JsonReader, MalformedTransformsAreRejected) {
  EXPECT_SCENE_ERROR(transformError("[1,0,0,0, 0,1,0,0, 0,0,1,0, 1,0,0,1]"), "t.json", "/transform",
                     "[0, 0, 0, 1]");
  EXPECT_SCENE_ERROR(transformError("[1, 2, 3]"), "t.json", "/transform", "4x4 matrix");
  EXPECT_SCENE_ERROR(transformError(R"("identity")"), "t.json", "/transform", "got string");
  EXPECT_SCENE_ERROR(transformError(R"([{"transalte": [1, 0, 0]}])"), "t.json",
                     "/transform/0/transalte", "did you mean 'translate'?");
  EXPECT_SCENE_ERROR(transformError(R"([{"translate": [1, 0, 0], "scale": 2}])"), "t.json",
                     "/transform/0", "exactly one key");
  EXPECT_SCENE_ERROR(transformError(R"([{"rotate": {"axis": [0, 0, 0], "degrees": 5}}])"), "t.json",
                     "/transform/0/rotate/axis", "must not be zero");
  EXPECT_SCENE_ERROR(transformError(R"([{"rotate": {"axis": [0, 1, 0], "degree": 5}}])"), "t.json",
                     "/transform/0/rotate", "missing required key 'degrees'");
  EXPECT_SCENE_ERROR(transformError(R"([{"translate": [0, 1e39, 0]}])"), "t.json",
                     "/transform/0/translate/1", "must be finite");
}

// ---------------------------------------------------------------------------------------------
// Sidecar: errors
// ---------------------------------------------------------------------------------------------

TEST(Sidecar, SyntaxErrorReportsLineAndColumn) {
  SceneError e = applyError("{\n  \"render\": {\n    \"spp\": 4,\n  }\n}\n");
  EXPECT_EQ(e.where().file, std::string(kFile) + ":4:3");
  EXPECT_EQ(e.where().pointer, "");
  EXPECT_NE(e.message().find("syntax error"), std::string::npos) << e.what();
}

TEST(Sidecar, AKeyGivenTwiceIsAnErrorAtItsObject) {
  // The second "transform" would silently win: a cone would lose its placement.
  EXPECT_SCENE_ERROR(applyError(R"({"objects": [{"type": "sphere", "radius": 1},
      {"type": "cone", "radius": 1, "height": 2, "transform": [{"translate": [0, -1, 0]}],
       "material": "grey", "transform": [{"rotate": {"axis": [1, 0, 0], "degrees": 30}}]}]})"),
                     kFile, "/objects/1", "key 'transform' given twice");
  // Inside nested arrays and objects, and at the root.
  EXPECT_SCENE_ERROR(
      applyError(R"({"render": {"spp": 4}, "lights": [[], {"a": {"b": 1, "b": 2}}]})"), kFile,
      "/lights/1/a", "key 'b' given twice");
  EXPECT_SCENE_ERROR(applyError(R"({"render": {"spp": 4}, "render": {}})"), kFile, "",
                     "key 'render' given twice");
  // The same key in two objects is fine (this one then fails on what it says, not twice).
  EXPECT_EQ(applyError(R"({"render": {"spp": 4, "bogus": {"spp": 1}}})").message().find("twice"),
            std::string::npos);
}

TEST(Sidecar, WrongTypeIsAnErrorWithPointer) {
  EXPECT_SCENE_ERROR(applyError(R"({"render": {"spp": "many"}})"), kFile, "/render/spp",
                     "expected integer, got string");
  EXPECT_SCENE_ERROR(applyError(R"({"render": 3})"), kFile, "/render",
                     "expected object, got integer");
  EXPECT_SCENE_ERROR(applyError(R"({"lights": {}})"), kFile, "/lights",
                     "expected array, got object");
}

TEST(Sidecar, UnknownKeyIsAnErrorWithPointer) {
  SceneError e = applyError(R"({"render": {"spq": 4}})");
  EXPECT_SCENE_ERROR(e, kFile, "/render/spq", "unknown key 'spq'");
  EXPECT_NE(e.message().find("did you mean 'spp'?"), std::string::npos);
  EXPECT_EQ(std::string(e.what()),
            "demo.glint.json: /render/spq: unknown key 'spq'; did you mean 'spp'?");
}

TEST(Sidecar, UnknownNestedKeyIsAnErrorWithPointer) {
  EXPECT_SCENE_ERROR(applyError(R"({"render": {"filter": {"type": "box", "radus": 1}}})"), kFile,
                     "/render/filter/radus", "did you mean 'radius'?");
  EXPECT_SCENE_ERROR(applyError(R"({"render": {"tonemap": {"ward": {"display_maxx": 1}}}})"), kFile,
                     "/render/tonemap/ward/display_maxx", "did you mean 'display_max'?");
  EXPECT_SCENE_ERROR(
      applyError(R"({"lights": [{"type": "point", "position": [0,0,0], "colour": [1,1,1]}]})"),
      kFile, "/lights/0/colour", "did you mean 'color'?");
}

TEST(Sidecar, NumberOverflowingADoubleIsASceneError) {
  SceneError e = applyError(R"({"render": {"background": [0, 1e400, 0]}})");
  EXPECT_EQ(e.where().file, kFile) << e.what();
  EXPECT_NE(e.message().find("1e400"), std::string::npos) << e.what();
}

TEST(Sidecar, UnknownTopLevelSectionIsAnError) {
  EXPECT_SCENE_ERROR(applyError(R"({"camras": []})"), kFile, "/camras", "did you mean 'cameras'?");
}

TEST(Sidecar, NegativeSppIsRejected) {
  EXPECT_SCENE_ERROR(applyError(R"({"render": {"spp": -4}})"), kFile, "/render/spp", "must be > 0");
}

TEST(Sidecar, MinWeightOutsideZeroToOneIsRejected) {
  EXPECT_SCENE_ERROR(applyError(R"({"render": {"integrator": {"min_weight": -0.1}}})"), kFile,
                     "/render/integrator/min_weight", "must be >= 0");
  EXPECT_SCENE_ERROR(applyError(R"({"render": {"integrator": {"min_weight": 2}}})"), kFile,
                     "/render/integrator/min_weight", "<= 1");
}

TEST(Sidecar, ZeroWidthIsRejected) {
  EXPECT_SCENE_ERROR(applyError(R"({"render": {"width": 0}})"), kFile, "/render/width",
                     "must be > 0");
  EXPECT_SCENE_ERROR(applyError(R"({"render": {"filter": {"radius": 0}}})"), kFile,
                     "/render/filter/radius", "must be > 0");
}

TEST(Sidecar, BadEnumIsRejected) {
  EXPECT_SCENE_ERROR(applyError(R"({"render": {"filter": {"type": "mitchell"}}})"), kFile,
                     "/render/filter/type", "'mitchell' is not one of 'box', 'tent', 'gaussian'");
  EXPECT_SCENE_ERROR(applyError(R"({"render": {"accel": "bvh"}})"), kFile, "/render/accel",
                     "is not one of 'embree'");
  EXPECT_SCENE_ERROR(applyError(R"({"render": {"integrator": "photon"}})"), kFile,
                     "/render/integrator", "is not one of 'whitted', 'path'");
  EXPECT_SCENE_ERROR(applyError(R"({"render": {"tonemap": {"operator": "aces"}}})"), kFile,
                     "/render/tonemap/operator", "is not one of 'none', 'ward'");
  EXPECT_SCENE_ERROR(applyError(R"({"lights": [{"type": "area"}]})"), kFile, "/lights/0/type",
                     "is not one of 'point', 'spot', 'directional'");
}

TEST(Sidecar, ZnearNotBelowZfarIsRejected) {
  EXPECT_SCENE_ERROR(
      applyError(
          R"({"cameras": [{"position": [0,0,1], "look_at": [0,0,0], "znear": 5, "zfar": 5}]})"),
      kFile, "/cameras/0/znear", "must be < zfar");
}

TEST(Sidecar, CameraParametersAreValidated) {
  EXPECT_SCENE_ERROR(
      applyError(
          R"({"cameras": [{"position": [0,0,1], "look_at": [0,0,0], "yfov_degrees": 180}]})"),
      kFile, "/cameras/0/yfov_degrees", "must be > 0 and < 180");
  EXPECT_SCENE_ERROR(
      applyError(
          R"({"cameras": [{"type": "orthographic", "position": [0,0,1], "look_at": [0,0,0],
                        "xmag": 0}]})"),
      kFile, "/cameras/0/xmag", "must be > 0");
  EXPECT_SCENE_ERROR(
      applyError(
          R"({"cameras": [{"type": "orthographic", "position": [0,0,1], "look_at": [0,0,0],
                        "yfov_degrees": 40}]})"),
      kFile, "/cameras/0/yfov_degrees", "unknown key");
  EXPECT_SCENE_ERROR(applyError(R"({"cameras": [{"position": [0,0,1], "look_at": [0,0,1]}]})"),
                     kFile, "/cameras/0/look_at", "must differ from position");
  EXPECT_SCENE_ERROR(
      applyError(R"({"cameras": [{"position": [0,1,0], "look_at": [0,0,0], "up": [0,1,0]}]})"),
      kFile, "/cameras/0/up", "parallel");
  EXPECT_SCENE_ERROR(applyError(R"({"cameras": [{"name": "A"}]})"), kFile, "/cameras/0",
                     "needs 'position' and 'look_at', or a 'transform'");
  EXPECT_SCENE_ERROR(
      applyError(R"({"cameras": [{"position": [0,0,1], "transform": [{"translate": [0,0,1]}]}]})"),
      kFile, "/cameras/0/position", "not both");
  EXPECT_SCENE_ERROR(
      applyError(R"({"cameras": [{"name": "A", "position": [0,0,1], "look_at": [0,0,0]},
                                 {"name": "A", "position": [0,0,2], "look_at": [0,0,0]}]})"),
      kFile, "/cameras/1/name", "duplicate camera name 'A' (also at /cameras/0)");
}

TEST(Sidecar, GltfListIsOnlyAllowedInAJsonScene) {
  EXPECT_SCENE_ERROR(applyError(R"({"gltf": ["model.gltf"]})"), kFile, "/gltf",
                     "only a .json scene may list glTF files");
}

TEST(Sidecar, GltfEntriesAreValidatedInAJsonScene) {
  EXPECT_SCENE_ERROR(applyError(R"({"gltf": [3]})", {}, SceneJsonKind::Scene), kFile, "/gltf/0",
                     "expected a file name or an object with 'file', got integer");
  EXPECT_SCENE_ERROR(applyError(R"({"gltf": ["model.obj"]})", {}, SceneJsonKind::Scene), kFile,
                     "/gltf/0", "expected a .gltf or .glb file");
  EXPECT_SCENE_ERROR(applyError(R"({"gltf": [{"file": "nowhere.glb"}]})", {}, SceneJsonKind::Scene),
                     kFile, "/gltf/0/file", "file not found");
}

TEST(Sidecar, UnknownRenderCameraListsTheAvailableCameras) {
  SceneDescription scene;
  scene.cameras.push_back(CameraDesc{.name = "Main"});
  scene.cameras.push_back(CameraDesc{.name = "Side"});
  EXPECT_SCENE_ERROR(applyError(R"({"render": {"camera": "Top"}})", scene), kFile, "/render/camera",
                     "no camera named 'Top'; available: 'Main', 'Side'");
  EXPECT_SCENE_ERROR(applyError(R"({"render": {"camera": "Top"}})"), kFile, "/render/camera",
                     "the scene has no cameras");
}

TEST(Sidecar, NegativeIntensityIsRejected) {
  EXPECT_SCENE_ERROR(applyError(R"({"lights": [{"type": "point", "position": [0,0,0]},
                                {"type": "point", "position": [0,0,0], "intensity": -1}]})"),
                     kFile, "/lights/1/intensity", "must be >= 0");
  EXPECT_SCENE_ERROR(
      applyError(R"({"lights": [{"type": "point", "position": [0,0,0], "color": [1, -0.1, 1]}]})"),
      kFile, "/lights/0/color/1", "must be >= 0");
}

TEST(Sidecar, SpotConesAreValidated) {
  EXPECT_SCENE_ERROR(
      applyError(R"({"lights": [{"type": "spot", "position": [0,0,0], "direction": [0,-1,0],
                                 "inner_cone_degrees": 40, "outer_cone_degrees": 30}]})"),
      kFile, "/lights/0/inner_cone_degrees", "must be <= outer_cone_degrees");
  EXPECT_SCENE_ERROR(
      applyError(R"({"lights": [{"type": "spot", "position": [0,0,0], "direction": [0,-1,0],
                                 "outer_cone_degrees": 95}]})"),
      kFile, "/lights/0/outer_cone_degrees", "must be >= 0 and <= 90");
  EXPECT_SCENE_ERROR(applyError(R"({"lights": [{"type": "spot", "position": [0,0,0]}]})"), kFile,
                     "/lights/0", "exactly one of 'look_at' or 'direction'");
  EXPECT_SCENE_ERROR(applyError(R"({"lights": [{"type": "directional", "direction": [0,0,0]}]})"),
                     kFile, "/lights/0/direction", "must not be zero");
  EXPECT_SCENE_ERROR(
      applyError(R"({"lights": [{"type": "directional", "direction": [0,-1,0], "range": 3}]})"),
      kFile, "/lights/0/range", "unknown key");
}

TEST(Sidecar, MaterialsAreValidated) {
  EXPECT_SCENE_ERROR(
      applyError(R"({"materials": [{"name": "Floor", "type": "phong", "diffuse": [0.5, -1, 0]}]})"),
      kFile, "/materials/0/diffuse/1", "must be >= 0");
  EXPECT_SCENE_ERROR(
      applyError(R"({"materials": [{"name": "Floor", "type": "phong", "shininess": -2}]})"), kFile,
      "/materials/0/shininess", "must be >= 0");
  EXPECT_SCENE_ERROR(
      applyError(R"({"materials": [{"name": "Floor", "type": "lambert", "shininess": 2}]})"), kFile,
      "/materials/0/shininess", "unknown key 'shininess'");
  EXPECT_SCENE_ERROR(applyError(R"({"materials": [{"name": "Floor"}]})"), kFile, "/materials/0",
                     "a new material needs a 'type'");
  EXPECT_SCENE_ERROR(applyError(R"({"materials": [{"type": "lambert"}]})"), kFile, "/materials/0",
                     "missing required key 'name'");
  EXPECT_SCENE_ERROR(
      applyError(
          R"({"materials": [{"name": "A", "type": "lambert"}, {"name": "A", "type": "phong"}]})"),
      kFile, "/materials/1/name", "duplicate material name 'A'");
}

// ---------------------------------------------------------------------------------------------
// Sidecar: what it does
// ---------------------------------------------------------------------------------------------

TEST(Sidecar, RenderSettingsAreApplied) {
  SceneDescription scene;
  scene.cameras.push_back(CameraDesc{.name = "Main"});
  SceneDescription s = apply(R"({"render": {
      "width": 800, "height": 450, "spp": 64, "seed": 12345678901, "threads": 3,
      "accel": "embree", "camera": "Main", "integrator": {"type": "whitted", "max_depth": 5, "rr_depth": 2,
                     "light_sampler": "uniform", "volume": "emission",
                     "volume_estimator": "track", "volume_step": 0.25,
                     "whole_segment_emission": false, "vpl_paths": 7,
                     "vpl_clamp": 3, "min_weight": 0.01},
      "filter": {"type": "tent", "radius": 2},
      "background": [0.1, 0.2, 0.3],
      "exr": {"half": true, "aovs": true},
      "tonemap": {"exposure": -1.5, "operator": "ward",
                  "ward": {"display_max": 80, "scene_luminance": 200},
                  "display": "sRGB", "view": "Standard"}}})",
                             scene);
  const RenderSettings& r = s.render;
  EXPECT_EQ(r.width, 800);
  EXPECT_EQ(r.height, 450);
  EXPECT_EQ(r.spp, 64);
  EXPECT_EQ(r.seed, 12345678901u);
  EXPECT_EQ(r.threads, 3);
  EXPECT_EQ(r.accel, "embree");
  EXPECT_EQ(r.camera, "Main");
  EXPECT_EQ(r.integrator.type, "whitted");
  EXPECT_EQ(r.integrator.maxDepth, 5);
  EXPECT_EQ(r.integrator.rrDepth, 2);
  EXPECT_EQ(r.integrator.lightSampler, "uniform");
  EXPECT_EQ(r.integrator.volume, "emission");
  EXPECT_EQ(r.integrator.volumeEstimator, "track");
  EXPECT_FLOAT_EQ(r.integrator.volumeStep, 0.25f);
  EXPECT_FALSE(r.integrator.wholeSegmentEmission);
  EXPECT_TRUE(RenderSettings{}.integrator.wholeSegmentEmission);
  EXPECT_EQ(r.integrator.vplPaths, 7);
  EXPECT_FLOAT_EQ(r.integrator.vplClamp, 3);
  EXPECT_FLOAT_EQ(r.integrator.minWeight, 0.01f);
  EXPECT_EQ(r.filter.type, "tent");
  EXPECT_FLOAT_EQ(r.filter.radius, 2);
  EXPECT_EQ(r.background, (Rgb{0.1f, 0.2f, 0.3f}));
  EXPECT_TRUE(r.exrHalf);
  EXPECT_TRUE(r.aovs);
  EXPECT_FLOAT_EQ(r.tonemap.exposure, -1.5f);
  EXPECT_EQ(r.tonemap.op, "ward");
  EXPECT_FLOAT_EQ(r.tonemap.wardDisplayMax, 80);
  EXPECT_FLOAT_EQ(r.tonemap.wardSceneLuminance, 200);
  EXPECT_EQ(r.tonemap.display, "sRGB");
  EXPECT_EQ(r.tonemap.view, "Standard");
}

TEST(Sidecar, MissingKeysKeepTheDefaults) {
  SceneDescription s = apply(R"({"render": {"spp": 2, "filter": {"type": "box"}}})");
  RenderSettings defaults;
  EXPECT_EQ(s.render.spp, 2);
  EXPECT_FALSE(s.render.width.has_value());
  EXPECT_EQ(s.render.filter.type, "box");
  EXPECT_FLOAT_EQ(s.render.filter.radius, defaults.filter.radius);
  EXPECT_EQ(s.render.integrator.maxDepth, defaults.integrator.maxDepth);
  EXPECT_EQ(apply(R"({"render": {"integrator": "whitted"}})").render.integrator.type, "whitted");
  EXPECT_EQ(s.render.tonemap.op, "none");
  SceneDescription empty = apply("{}");
  EXPECT_EQ(empty.render.spp, defaults.spp);
}

TEST(Sidecar, CameraLooksFromPositionAtTarget) {
  SceneDescription s = apply(R"({"cameras": [{"name": "Cam", "position": [0, 1, 5],
      "look_at": [0, 1, 0], "yfov_degrees": 90, "znear": 0.5, "zfar": 100, "aspect_ratio": 2}]})");
  ASSERT_EQ(s.cameras.size(), 1u);
  const CameraDesc& c = s.cameras[0];
  EXPECT_EQ(c.name, "Cam");
  EXPECT_EQ(c.type, CameraType::Perspective);
  EXPECT_NEAR(c.yfov, kPi / 2, 1e-6f);
  EXPECT_FLOAT_EQ(c.aspectRatio, 2);
  EXPECT_FLOAT_EQ(c.znear, 0.5f);
  EXPECT_FLOAT_EQ(c.zfar, 100);
  expectNear(c.worldFromCamera.point({0, 0, 0}), {0, 1, 5});
  expectNear(normalize(c.worldFromCamera.vector({0, 0, -1})), {0, 0, -1});
  expectNear(normalize(c.worldFromCamera.vector({0, 1, 0})), {0, 1, 0});
  EXPECT_EQ(c.where.file, kFile);
  EXPECT_EQ(c.where.pointer, "/cameras/0");
}

TEST(Sidecar, CameraFromTransformAndOrthographic) {
  SceneDescription s = apply(R"({"cameras": [{"type": "orthographic", "xmag": 3, "ymag": 2,
      "transform": [{"rotate": {"axis": [0, 1, 0], "degrees": 90}}, {"translate": [4, 0, 0]}]}]})");
  ASSERT_EQ(s.cameras.size(), 1u);
  const CameraDesc& c = s.cameras[0];
  EXPECT_EQ(c.type, CameraType::Orthographic);
  EXPECT_FLOAT_EQ(c.xmag, 3);
  EXPECT_FLOAT_EQ(c.ymag, 2);
  expectNear(c.worldFromCamera.point({0, 0, 0}), {4, 0, 0});
  expectNear(c.worldFromCamera.vector({0, 0, -1}), {-1, 0, 0});
}

TEST(Sidecar, CameraWithAnExistingNameReplacesIt) {
  SceneDescription scene;
  scene.cameras.push_back(CameraDesc{.name = "Main", .yfov = 0.3f});
  scene.cameras.push_back(CameraDesc{.name = "Side", .yfov = 0.4f});
  SceneDescription s = apply(R"({"cameras": [
      {"name": "Main", "position": [0, 0, 9], "look_at": [0, 0, 0], "yfov_degrees": 60},
      {"name": "New", "position": [0, 0, 1], "look_at": [0, 0, 0]}],
      "render": {"camera": "New"}})",
                             scene);
  ASSERT_EQ(s.cameras.size(), 3u);
  EXPECT_EQ(s.cameras[0].name, "Main");
  EXPECT_NEAR(s.cameras[0].yfov, kPi / 3, 1e-6f);
  expectNear(s.cameras[0].worldFromCamera.point({0, 0, 0}), {0, 0, 9});
  EXPECT_EQ(s.cameras[0].where.pointer, "/cameras/0");
  EXPECT_FLOAT_EQ(s.cameras[1].yfov, 0.4f);
  EXPECT_EQ(s.cameras[2].name, "New");
  EXPECT_EQ(s.render.camera, "New");
}

TEST(Sidecar, LightsShineDownTheirLocalMinusZ) {
  SceneDescription s = apply(R"({"lights": [
      {"name": "Key", "type": "point", "position": [2, 4, 2], "color": [1, 0.5, 0.25],
       "intensity": 50, "range": 10},
      {"type": "spot", "position": [0, 5, 0], "look_at": [0, 0, 0],
       "inner_cone_degrees": 20, "outer_cone_degrees": 30, "intensity": 80},
      {"type": "spot", "position": [1, 0, 0], "direction": [1, 0, 0]},
      {"type": "directional", "direction": [-1, -1, -0.5], "intensity": 2.0,
       "cast_shadows": false}]})");
  ASSERT_EQ(s.lights.size(), 4u);
  const LightDesc& point = s.lights[0];
  EXPECT_EQ(point.name, "Key");
  EXPECT_EQ(point.type, LightType::Point);
  EXPECT_EQ(point.color, (Rgb{1, 0.5f, 0.25f}));
  EXPECT_FLOAT_EQ(point.intensity, 50);
  EXPECT_FLOAT_EQ(point.range, 10);
  expectNear(point.worldFromLight.point({0, 0, 0}), {2, 4, 2});

  const LightDesc& spot = s.lights[1];
  EXPECT_EQ(spot.type, LightType::Spot);
  EXPECT_NEAR(spot.innerConeAngle, 20 * kPi / 180, 1e-6f);
  EXPECT_NEAR(spot.outerConeAngle, 30 * kPi / 180, 1e-6f);
  expectNear(spot.worldFromLight.point({0, 0, 0}), {0, 5, 0});
  expectNear(normalize(spot.worldFromLight.vector({0, 0, -1})), {0, -1, 0});
  EXPECT_EQ(spot.where.pointer, "/lights/1");

  expectNear(normalize(s.lights[2].worldFromLight.vector({0, 0, -1})), {1, 0, 0});
  EXPECT_NEAR(s.lights[2].outerConeAngle, kPi / 4, 1e-6f);

  const LightDesc& sun = s.lights[3];
  EXPECT_EQ(sun.type, LightType::Directional);
  EXPECT_FALSE(sun.castsShadows);
  expectNear(normalize(sun.worldFromLight.vector({0, 0, -1})), normalize(Vec3f{-1, -1, -0.5f}));
  EXPECT_TRUE(s.lights[0].castsShadows);
}

TEST(Sidecar, MaterialOverrideByNameKeepsTextures) {
  SceneDescription scene;
  MaterialDesc red;
  red.name = "Red";
  red.baseColor = {1, 0, 0};
  red.baseColorTexture = 0;
  red.emissiveTexture = 1;
  red.roughness = 0.25f;
  scene.materials.push_back(red);
  SceneDescription s = apply(R"({"materials": [
      {"name": "Red", "type": "phong", "specular": [0.3, 0.3, 0.3], "shininess": 40},
      {"name": "Floor", "type": "phong", "diffuse": [0.6, 0.6, 0.6],
       "specular": [0.1, 0.1, 0.1], "shininess": 8},
      {"name": "Statue", "type": "lambert", "diffuse": [0.8, 0.7, 0.6]},
      {"name": "Probe", "type": "eyelight", "color": [1, 1, 1]},
      {"name": "Gold", "type": "pbr", "base_color": [1, 0.8, 0.3], "metallic": 1, "roughness": 0.2,
       "emissive": [0, 0, 0], "double_sided": true}]})",
                             scene);
  ASSERT_EQ(s.materials.size(), 5u);
  const MaterialDesc& m = s.materials[0];
  EXPECT_EQ(m.type, MaterialType::Phong);
  EXPECT_EQ(m.baseColor, (Rgb{1, 0, 0}));  // not given: kept
  EXPECT_EQ(m.baseColorTexture, 0);
  EXPECT_EQ(m.emissiveTexture, 1);
  EXPECT_FLOAT_EQ(m.roughness, 0.25f);
  EXPECT_EQ(m.specular, (Rgb{0.3f, 0.3f, 0.3f}));
  EXPECT_FLOAT_EQ(m.shininess, 40);

  EXPECT_EQ(s.materials[1].name, "Floor");
  EXPECT_EQ(s.materials[1].type, MaterialType::Phong);
  EXPECT_EQ(s.materials[1].baseColor, (Rgb{0.6f, 0.6f, 0.6f}));
  EXPECT_EQ(s.materials[1].baseColorTexture, -1);
  EXPECT_EQ(s.materials[1].where.pointer, "/materials/1");
  EXPECT_EQ(s.materials[2].type, MaterialType::Lambert);
  EXPECT_EQ(s.materials[3].type, MaterialType::Eyelight);
  EXPECT_EQ(s.materials[4].type, MaterialType::Pbr);
  EXPECT_FLOAT_EQ(s.materials[4].roughness, 0.2f);
  EXPECT_TRUE(s.materials[4].doubleSided);
}

TEST(Sidecar, MaterialOverrideWithoutTypeKeepsTheType) {
  SceneDescription scene;
  scene.materials.push_back(MaterialDesc{.name = "Metal", .type = MaterialType::Pbr});
  SceneDescription s = apply(
      R"({"materials": [{"name": "Metal", "roughness": 0.1, "base_color": [0.5, 0.5, 0.5]}]})",
      scene);
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].type, MaterialType::Pbr);
  EXPECT_FLOAT_EQ(s.materials[0].roughness, 0.1f);
  EXPECT_SCENE_ERROR(applyError(R"({"materials": [{"name": "Metal", "roughness": 2}]})", scene),
                     kFile, "/materials/0/roughness", "must be >= 0 and <= 1");
}

TEST(Sidecar, DefaultSidecarPathSitsNextToTheGltf) {
  EXPECT_EQ(defaultSidecarPath("dir/demo.gltf"), "dir/demo.glint.json");
  EXPECT_EQ(defaultSidecarPath("demo.glb"), "demo.glint.json");
}

}  // namespace
}  // namespace glint
