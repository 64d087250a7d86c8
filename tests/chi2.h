// glint tests — a chi-square goodness-of-fit test for direction sampling routines.
//
// The approach of pbrt-v4's bsdfs_test and Mitsuba's chi2.py: split the sphere of directions
// into bins, draw many samples and count them per bin, integrate the claimed pdf over every
// bin for the expected counts, pool the bins that expect too few samples, and ask Pearson's
// chi-square statistic whether the counts could come from the pdf. A sampler may fail (return
// nothing, e.g. a direction below the surface): then the pdf integrates to less than 1, and
// the fraction of failed samples must match the missing mass.
//
// Only continuous pdfs: a delta lobe puts all its samples into one bin with zero expected
// mass, which fails. The pdf is integrated with adaptive Gauss–Legendre cubature whose error
// is kept far below the statistical noise of each bin; Gauss points never touch a bin's edge,
// so a pdf that jumps exactly on a bin edge (the horizon, with binFrame = the normal's frame)
// costs nothing.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "geometry/math.h"

namespace glint::test {

// Draws one direction from two uniform numbers for the direction and one for the lobe choice,
// or nothing when the sample fails. Directions must be unit vectors.
using DirectionSampler = std::function<std::optional<Vec3f>(Vec2f u, float uLobe)>;
// The solid-angle density with which the sampler returns a unit direction.
using DirectionPdf = std::function<float(Vec3f w)>;

struct Chi2Options {
  // Bins are uniform in cos(theta) and phi measured in binFrame (so every bin spans the same
  // solid angle). Aligning binFrame.n with a surface normal puts the horizon on a bin edge.
  Frame binFrame{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  int thetaBins = 32;  // even, so that cos(theta) = 0 is a bin edge
  int phiBins = 64;
  // When above -1, `thetaBins` rings cover only the cap cos(theta) >= capCosTheta and
  // `outerThetaBins` rings the rest of the sphere: resolution for a peaked lobe around
  // binFrame.n.
  float capCosTheta = -1;
  int outerThetaBins = 8;
  int64_t sampleCount = 1'000'000;
  uint64_t seed = 1;
  // Family-wise significance, Šidák-corrected over `testCount` tests: each single test uses
  // 1 - (1 - significance)^(1 / testCount).
  double significance = 0.01;
  int testCount = 1;
  // Bins expecting fewer samples than this are pooled into one.
  double minExpected = 5;
};

struct Chi2Result {
  bool passed = false;
  double pValue = 0;            // of the chi-square statistic
  double chi2 = 0;              // Pearson's statistic over the pooled bins
  int dof = 0;                  // degrees of freedom: pooled bins - 1
  double pdfIntegral = 0;       // the pdf's integral over the sphere (<= 1)
  double integrationError = 0;  // estimated absolute error of pdfIntegral
  double failureFraction = 0;   // fraction of samples the sampler did not return
  double failurePValue = 1;     // two-sided, of failureFraction against 1 - pdfIntegral
  double significance = 0;      // the corrected per-test significance that was applied
  std::string message;          // why it failed (with the worst bins), or a summary
};

// Runs the test. Deterministic for a given options.seed.
Chi2Result chi2Test(const DirectionSampler& sample, const DirectionPdf& pdf,
                    const Chi2Options& options = {});

// The regularized upper incomplete gamma function Q(a, x) = Gamma(a, x) / Gamma(a), a > 0,
// x >= 0.
double regularizedGammaQ(double a, double x);
// P(X >= x) for X chi-square distributed with `dof` degrees of freedom.
double chi2SurvivalFunction(double x, int dof);

}  // namespace glint::test
