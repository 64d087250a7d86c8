// glint — the analytic shapes a scene file can name: each shape's keyword, the parameters it
// reads, and the function that makes it from them.
//
// This is the one registration a shape needs. Adding a shape is one header + one .cpp in this
// folder (intersection, surface, sampling, and a static `create(ShapeParameters&)` that reads
// and checks its parameters) plus one line in `shapeKinds()` (registry.cpp). The sidecar
// JSON's "objects", CSG trees (JSON and .csg files), media regions, area lights and `glint info`
// then all know it; nothing in scenes/ or renderer/ names individual shapes.
//
// geometry/ knows no file formats, so parameters arrive through ShapeParameters, which scenes/
// implements over the sidecar JSON (errors at a JSON pointer) and over a .csg line (errors at
// file:line). (pbrt-v4 does the same with its ParameterDictionary and Shape::Create.)
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/shape.h"

namespace glint {

// A shape's parameters as some scene format gives them. Each getter reports bad or missing
// values as that format's bad-input error (it does not return).
class ShapeParameters {
 public:
  virtual ~ShapeParameters() = default;
  // A finite number > 0; without a fallback the key is required.
  virtual float positive(const char* key, std::optional<float> fallback = std::nullopt) = 0;
  // A finite 3-vector; without a fallback the key is required.
  virtual Vec3f vector(const char* key, std::optional<Vec3f> fallback = std::nullopt) = 0;
  virtual bool flag(const char* key, bool fallback) = 0;
  // Rejects the value of `key` with `message` ("must not be zero"), located where the format
  // can say it.
  [[noreturn]] virtual void invalid(const char* key, const std::string& message) = 0;
};

// One number (1) or one vector (3) a shape reads, as the .csg format spells it after the
// keyword: `sphere center 0 0 0 radius 1`.
struct ShapeKey {
  const char* name;
  int count;
};

struct ShapeKind {
  const char* name;  // the keyword: "sphere"
  // The .csg format's keys for this shape, every one required there (the JSON has defaults,
  // see create). Empty for shapes that are never closed solids (disk, quad): they are not CSG
  // leaves, so the .csg format has no keyword for them.
  std::vector<ShapeKey> csgKeys;
  std::unique_ptr<Shape> (*create)(ShapeParameters&);
};

// Every registered shape, in the order messages list them.
const std::vector<ShapeKind>& shapeKinds();
// The shape called `name`, or nullptr.
const ShapeKind* findShapeKind(std::string_view name);

}  // namespace glint
