// glint — the shape registry: one line per shape (see registry.h).
#include "geometry/shapes/registry.h"

#include "geometry/shapes/box.h"
#include "geometry/shapes/cone.h"
#include "geometry/shapes/cylinder.h"
#include "geometry/shapes/disk.h"
#include "geometry/shapes/plane.h"
#include "geometry/shapes/quad.h"
#include "geometry/shapes/sphere.h"

namespace glint {

const std::vector<ShapeKind>& shapeKinds() {
  static const std::vector<ShapeKind> kinds = {
      {"sphere", {{"center", 3}, {"radius", 1}}, &Sphere::create},
      {"box", {{"min", 3}, {"max", 3}}, &Box::create},
      {"cylinder", {{"radius", 1}, {"height", 1}}, &Cylinder::create},
      {"cone", {{"radius", 1}, {"height", 1}}, &Cone::create},
      {"plane", {{"point", 3}, {"normal", 3}}, &Plane::create},
      {"disk", {}, &Disk::create},
      {"quad", {}, &Quad::create},
  };
  return kinds;
}

const ShapeKind* findShapeKind(std::string_view name) {
  for (const ShapeKind& kind : shapeKinds())
    if (name == kind.name) return &kind;
  return nullptr;
}

}  // namespace glint
