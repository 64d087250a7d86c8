// glint — majorant grids: coarse grids of density maxima that let tracking skip empty space.
//
// A medium tracked against one majorant for its whole region spends most of its tentative
// collisions where the density is far below the maximum: in the empty corners of a cloud's box
// and its thin outskirts. A majorant grid (pbrt-v4's MajorantGrid) stores, for each cell of a
// coarse grid over the region, a bound of the density inside that cell; a tracker then walks
// the cells along the ray (renderer/majorant_dda.h) and samples collisions at each cell's own
// rate, so a cell whose bound is 0 costs one step and no collision at all.
#pragma once

#include <cstddef>
#include <vector>

#include "geometry/math.h"

namespace glint {

class MajorantGrid {
 public:
  // nx x ny x nz cells (each >= 1) tiling the object-space box `bounds`, all 0.
  MajorantGrid(const Bounds3f& bounds, int nx, int ny, int nz);

  // Raises every cell that overlaps the object-space box `box` to at least `value`.
  void include(const Bounds3f& box, float value);
  // include's cells along `axis` for the interval [lo, hi] of the box: *first to *last.
  void cellRange(int axis, float lo, float hi, int* first, int* last) const;
  // Raises the cells first[a] ... last[a] (per axis, inclusive) to at least `value`.
  void includeCells(const int first[3], const int last[3], float value);

  // Multiplies every cell by `factor` (>= 0).
  void scale(float factor) {
    for (float& c : cells_) c *= factor;
  }

  float at(int x, int y, int z) const { return cells_[(size_t(z) * res_[1] + y) * res_[0] + x]; }
  void set(int x, int y, int z, float value) {
    cells_[(size_t(z) * res_[1] + y) * res_[0] + x] = value;
  }
  const Bounds3f& bounds() const { return bounds_; }
  int res(int axis) const { return res_[axis]; }
  // The largest cell value (the single majorant the grid refines).
  float maxValue() const;
  // Bytes of the cells.
  size_t bytes() const { return cells_.size() * sizeof(float); }
  // The fraction of cells whose value is 0 (empty space the trackers skip).
  float emptyFraction() const;

 private:
  Bounds3f bounds_;
  int res_[3];
  std::vector<float> cells_;
};

}  // namespace glint
