// glint — majorant grids.
#include "materials/majorant_grid.h"

#include <algorithm>
#include <cmath>

namespace glint {

MajorantGrid::MajorantGrid(const Bounds3f& bounds, int nx, int ny, int nz)
    : bounds_(bounds), res_{nx, ny, nz}, cells_(size_t(nx) * size_t(ny) * size_t(nz), 0.0f) {}

void MajorantGrid::include(const Bounds3f& box, float value) {
  int lo[3], hi[3];
  for (int a = 0; a < 3; ++a) cellRange(a, box.lower[a], box.upper[a], &lo[a], &hi[a]);
  includeCells(lo, hi, value);
}

void MajorantGrid::cellRange(int axis, float lo, float hi, int* first, int* last) const {
  const float extent = bounds_.upper[axis] - bounds_.lower[axis];
  if (!(extent > 0)) {
    *first = 0, *last = res_[axis] - 1;
    return;
  }
  // Cells are half-open, but a box edge exactly on a cell boundary still raises the cell
  // beyond it: a point there may be looked up in either, so both must bound it.
  const float f0 = (lo - bounds_.lower[axis]) / extent * float(res_[axis]);
  const float f1 = (hi - bounds_.lower[axis]) / extent * float(res_[axis]);
  *first = std::clamp(int(std::floor(f0)), 0, res_[axis] - 1);
  *last = std::clamp(int(std::floor(f1)), 0, res_[axis] - 1);
}

void MajorantGrid::includeCells(const int first[3], const int last[3], float value) {
  for (int z = first[2]; z <= last[2]; ++z)
    for (int y = first[1]; y <= last[1]; ++y)
      for (int x = first[0]; x <= last[0]; ++x) {
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
