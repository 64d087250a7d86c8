// glint — the accelerator factory: backends chosen by name.
#include "geometry/accel/accelerator.h"

#include <stdexcept>

#include "geometry/accel/embree_accel.h"

namespace glint {

std::unique_ptr<Accelerator> makeAccelerator(const std::string& name,
                                             const GeometryScene& scene) {
  if (name == "embree") return std::make_unique<EmbreeAccelerator>(scene);
  throw std::invalid_argument("unknown accelerator '" + name + "'");
}

std::vector<std::string> acceleratorNames() { return {"embree"}; }

}  // namespace glint
