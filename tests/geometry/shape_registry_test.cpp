// The shape registry: every registered shape is made by its own create(), answers to its
// keyword, reads every key the .csg format writes for it, and clones faithfully.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <stdexcept>
#include <string>

#include "geometry/shapes/registry.h"

namespace glint {
namespace {

// Valid values by key (a box's min below its max, a quad's edges not parallel), recording
// which keys a shape asked for.
class RecordingParameters : public ShapeParameters {
 public:
  float positive(const char* key, std::optional<float> fallback) override {
    asked.insert(key);
    return fallback.value_or(0.75f);
  }
  Vec3f vector(const char* key, std::optional<Vec3f> fallback) override {
    asked.insert(key);
    static const std::map<std::string, Vec3f> values = {
        {"min", {-1, -2, -3}}, {"max", {1, 2, 3}},     {"corner", {0, 0, 0}},
        {"edge_u", {1, 0, 0}}, {"edge_v", {0, 0, -1}}, {"normal", {0, 2, 0}}};
    auto it = values.find(key);
    return it != values.end() ? it->second : fallback.value_or(Vec3f{0.5f, 0.25f, 0});
  }
  bool flag(const char* key, bool fallback) override {
    asked.insert(key);
    return fallback;
  }
  [[noreturn]] void invalid(const char* key, const std::string& message) override {
    throw std::runtime_error(std::string(key) + ": " + message);
  }

  std::set<std::string> asked;
};

TEST(ShapeRegistry, EveryShapeIsMadeByItsKeyword) {
  ASSERT_GE(shapeKinds().size(), 7u);
  std::set<std::string> names;
  for (const ShapeKind& kind : shapeKinds()) {
    SCOPED_TRACE(kind.name);
    EXPECT_TRUE(names.insert(kind.name).second) << "registered twice";
    EXPECT_EQ(findShapeKind(kind.name), &kind);
    RecordingParameters params;
    std::unique_ptr<Shape> shape = kind.create(params);
    ASSERT_TRUE(shape);
    EXPECT_STREQ(shape->typeName(), kind.name);
    // The .csg format passes exactly these keys; create() must read each of them.
    for (const ShapeKey& key : kind.csgKeys) {
      EXPECT_TRUE(params.asked.count(key.name)) << key.name;
      EXPECT_TRUE(key.count == 1 || key.count == 3) << key.name;
    }
    // A shape the .csg format can name is a solid with its defaults (a CSG leaf).
    if (!kind.csgKeys.empty()) {
      EXPECT_TRUE(shape->isSolid());
    }
    std::unique_ptr<Shape> copy = shape->clone();
    EXPECT_STREQ(copy->typeName(), kind.name);
    EXPECT_EQ(copy->bounds().lower, shape->bounds().lower);
    EXPECT_EQ(copy->bounds().upper, shape->bounds().upper);
    EXPECT_EQ(copy->area(), shape->area());
  }
  EXPECT_EQ(findShapeKind("torus"), nullptr);
}

TEST(ShapeRegistry, ShapesRejectTheirInvalidParameters) {
  struct Bad : RecordingParameters {
    Vec3f vector(const char* key, std::optional<Vec3f> fallback) override {
      if (std::string(key) == "max") return {1, -2, 3};    // below min in y
      if (std::string(key) == "edge_v") return {2, 0, 0};  // parallel to edge_u
      if (std::string(key) == "normal") return {0, 0, 0};
      return RecordingParameters::vector(key, fallback);
    }
  };
  for (const char* name : {"box", "quad", "plane"}) {
    Bad params;
    EXPECT_THROW(findShapeKind(name)->create(params), std::runtime_error) << name;
  }
}

}  // namespace
}  // namespace glint
