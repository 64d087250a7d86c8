// glint — walking a majorant grid along a ray: the cells a ray segment crosses, in order, each
// with the stretch of the ray inside it (a 3D DDA, Amanatides and Woo 1987; pbrt-v4's
// DDAMajorantIterator), and MajorantWalk, the stretches of one majorant that trackers sample
// collisions in (renderer/volume.cpp).
#pragma once

#include <algorithm>
#include <cmath>

#include "geometry/math.h"
#include "materials/majorant_grid.h"
#include "renderer/sampler.h"

namespace glint {

class MajorantDda {
 public:
  // The segment t in [tMin, tMax] of the object-space ray o + t d (d need not be unit: t is
  // the caller's ray parameter) through `grid`, clipped to the grid's box.
  // `aux`: a second grid over the same cells whose values come along (null: 0).
  MajorantDda() = default;  // no cells
  MajorantDda(const MajorantGrid& grid, Vec3f o, Vec3f d, float tMin, float tMax,
              const MajorantGrid* aux = nullptr)
      : grid_(&grid), aux_(aux) {
    const Bounds3f& b = grid.bounds();
    const Vec3f extent = b.diagonal();
    // The ray in grid space, where the grid is [0, 1]^3.
    Vec3f oG, dG;
    for (int a = 0; a < 3; ++a) {
      oG[a] = (o[a] - b.lower[a]) / extent[a];
      dG[a] = d[a] / extent[a];
      const float inv = 1 / dG[a];
      float t0 = (0 - oG[a]) * inv, t1 = (1 - oG[a]) * inv;
      if (t0 > t1) std::swap(t0, t1);
      // NaN (a parallel ray on a slab plane) leaves the segment as it is.
      if (t0 > tMin) tMin = t0;
      if (t1 < tMax) tMax = t1;
    }
    t_ = tMin, tEnd_ = tMax;
    if (!(t_ < tEnd_)) return;
    const Vec3f p = oG + dG * t_;
    for (int a = 0; a < 3; ++a) {
      const int n = grid.res(a);
      cell_[a] = std::clamp(int(p[a] * float(n)), 0, n - 1);
      if (dG[a] == 0) {
        next_[a] = kInfinity, delta_[a] = 0, step_[a] = 0, stop_[a] = -2;
        continue;
      }
      delta_[a] = 1 / (std::abs(dG[a]) * float(n));
      if (dG[a] > 0) {
        next_[a] = t_ + (float(cell_[a] + 1) / float(n) - p[a]) / dG[a];
        step_[a] = 1, stop_[a] = n;
      } else {
        next_[a] = t_ + (float(cell_[a]) / float(n) - p[a]) / dG[a];
        step_[a] = -1, stop_[a] = -1;
      }
    }
  }

  // The next cell: the ray stretch [*t0, *t1] inside it and its value (and `aux`'s, into
  // *auxValue). False when done.
  bool next(float* t0, float* t1, float* value, float* auxValue = nullptr) {
    if (!(t_ < tEnd_)) return false;
    const int a =
        next_[0] < next_[1] ? (next_[0] < next_[2] ? 0 : 2) : (next_[1] < next_[2] ? 1 : 2);
    *t0 = t_;
    *t1 = std::max(t_, std::min(tEnd_, next_[a]));
    *value = grid_->at(cell_[0], cell_[1], cell_[2]);
    if (auxValue) *auxValue = aux_ ? aux_->at(cell_[0], cell_[1], cell_[2]) : 0.0f;
    t_ = *t1;
    cell_[a] += step_[a];
    next_[a] += delta_[a];
    if (cell_[a] == stop_[a]) t_ = tEnd_;
    return true;
  }

 private:
  const MajorantGrid* grid_ = nullptr;
  const MajorantGrid* aux_ = nullptr;
  float t_ = 0, tEnd_ = 0;
  int cell_[3] = {0, 0, 0}, step_[3] = {0, 0, 0}, stop_[3] = {0, 0, 0};
  float next_[3] = {kInfinity, kInfinity, kInfinity}, delta_[3] = {0, 0, 0};
};

// A stretch [t0, t1] of a ray with one majorant (max over channels of sigma_t); `cell` is the
// majorant grid's value there (0 without a grid), for trackers that need each channel's, and
// `emission` the emission bound's there (EmissionField::luminanceBound; 0 without one).
struct MajorantSegment {
  float t0, t1, majorant;
  float cell = 0, emission = 0;
};

// The majorant along [a, b] of a ray, stretch by stretch, as a tracker advances: one stretch of
// `constant`, or the cells of a majorant grid along the ray (each cell's value times `scale`,
// plus `constant`), runs of equal majorant joined. Lazy: a walk that ends at a real collision
// walks no further cells.
class MajorantWalk {
 public:
  MajorantWalk(float a, float b, float constant) : t_(a), b_(b), constant_(constant) {}
  // `o`, `d`: the ray in the grid's (object) space; t is the caller's ray parameter.
  // `emission`: an emission bound over the same cells, whose values the stretches carry.
  MajorantWalk(const MajorantGrid& grid, float scale, Vec3f o, Vec3f d, float a, float b,
               float constant, const MajorantGrid* emission = nullptr)
      : t_(a),
        b_(b),
        constant_(constant),
        scale_(scale),
        dda_(grid, o, d, a, b, emission),
        gridded_(true) {}

  // The next stretch; false when the walk has reached b.
  bool next(MajorantSegment* out) {
    if (!(t_ < b_)) return false;
    if (!gridded_) {
      *out = {t_, b_, constant_};
      t_ = b_;
      return true;
    }
    if (!haveCell_ && !nextCell()) {
      // Past the grid's box (by rounding at its faces: the density there is 0).
      *out = {t_, b_, constant_};
      t_ = b_;
      return true;
    }
    if (c0_ > t_) {  // before the grid's box, likewise
      *out = {t_, std::min(c0_, b_), constant_};
      t_ = out->t1;
      return true;
    }
    // This cell, and the following ones of the same values (one stretch for the tracker).
    const float value = value_, emission = emission_;
    float t1 = std::min(c1_, b_);
    haveCell_ = false;
    if (!(t1 > t_)) return next(out);  // a cell left behind by rounding
    while (t1 < b_ && nextCell()) {
      if (value_ != value || emission_ != emission || c0_ > t1) break;
      t1 = std::min(c1_, b_);
      haveCell_ = false;
    }
    *out = {t_, t1, constant_ + value * scale_, value, emission};
    t_ = t1;
    return true;
  }

 private:
  // The DDA's next cell into (c0_, c1_, value_), skipping empty stretches; false when done.
  bool nextCell() {
    while (dda_.next(&c0_, &c1_, &value_, &emission_))
      if (c1_ > c0_ && c1_ > t_) return haveCell_ = true;
    return false;
  }

  float t_, b_, constant_, scale_ = 0;
  MajorantDda dda_;
  bool gridded_ = false, haveCell_ = false;
  float c0_ = 0, c1_ = 0, value_ = 0, emission_ = 0;
};

// Tentative collisions along the stretches of a MajorantWalk: the majorant's optical depth to
// the next collision is exponentially distributed, so one draw serves however many stretches it
// crosses. A stretch that ends first passes the depth left over on to the next, and a ray pays
// one random number and one logarithm per collision rather than per cell it crosses. (Drawing
// afresh at every stretch, as pbrt-v4 does, is as correct and costs a draw per cell.) Within one
// stretch the collisions are those of x += -log(1 - u) / majorant, bit for bit.
class CollisionStepper {
 public:
  // Makes the next collision's optical depth -log(1 - u) rather than a draw from the sampler.
  void start(float u) { tau_ = -std::log1p(-u), have_ = true; }
  // The next collision after *x in a stretch of length s with majorant m > 0: true and *x moved
  // to it, or false when it lies beyond s (the depth left over is kept for the next stretch).
  bool next(float m, float s, float* x, Sampler& sampler) {
    if (!have_) tau_ = -std::log1p(-sampler.get1D()), have_ = true;
    const float step = tau_ / m;
    if (*x + step >= s) {
      tau_ = std::max(0.0f, tau_ - (s - *x) * m);
      return false;
    }
    *x += step;
    have_ = false;
    return true;
  }

 private:
  float tau_ = 0;
  bool have_ = false;
};

}  // namespace glint
