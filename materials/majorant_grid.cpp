// glint — majorant grids.
#include "materials/majorant_grid.h"

#include <algorithm>
#include <cmath>

namespace glint {

MajorantGrid::MajorantGrid(const Bounds3f& bounds, int nx, int ny, int nz)
    : bounds_(bounds), res_{nx, ny, nz}, cells_(size_t(nx) * size_t(ny) * size_t(nz), 0.0f) {}

void MajorantGrid::include(const Bounds3f& box, float value) {
  const Vec3f extent = bounds_.diagonal();
  int lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    // Cells are half-open, but a box edge exactly on a cell boundary still raises the cell
    // beyond it: a point there may be looked up in either, so both must bound it.
    const float f0 = (box.lower[a] - bounds_.lower[a]) / extent[a] * float(res_[a]);
    const float f1 = (box.upper[a] - bounds_.lower[a]) / extent[a] * float(res_[a]);
    lo[a] = std::clamp(int(std::floor(f0)), 0, res_[a] - 1);
    hi[a] = std::clamp(int(std::floor(f1)), 0, res_[a] - 1);
    if (!(extent[a] > 0)) lo[a] = 0, hi[a] = res_[a] - 1;
  }
  for (int z = lo[2]; z <= hi[2]; ++z)
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int x = lo[0]; x <= hi[0]; ++x) {
        float& c = cells_[(size_t(z) * res_[1] + y) * res_[0] + x];
        c = std::max(c, value);
      }
}

float MajorantGrid::maxValue() const {
  return cells_.empty() ? 0.0f : *std::max_element(cells_.begin(), cells_.end());
}

float MajorantGrid::emptyFraction() const {
  if (cells_.empty()) return 0;
  const auto empty = std::count(cells_.begin(), cells_.end(), 0.0f);
  return float(empty) / float(cells_.size());
}

}  // namespace glint
