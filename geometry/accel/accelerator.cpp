// glint — the accelerator factory: backends chosen by name.
#include "geometry/accel/accelerator.h"

#include "geometry/accel/embree_accel.h"
#include "geometry/accel/kdtree.h"
#include "geometry/error.h"

namespace glint {

std::unique_ptr<Accelerator> makeAccelerator(const std::string& name, const GeometryScene& scene) {
  if (name == "embree") return std::make_unique<EmbreeAccelerator>(scene);
  if (name == "kdtree") return std::make_unique<KdTreeAccelerator>(scene, KdSplitMethod::Sah);
  if (name == "kdtree-median")
    return std::make_unique<KdTreeAccelerator>(scene, KdSplitMethod::Median);
  throw InputError("unknown accelerator '" + name + "'");
}

std::vector<std::string> acceleratorNames() { return {"embree", "kdtree", "kdtree-median"}; }

}  // namespace glint
