// glint tests — the chi-square goodness-of-fit test for direction sampling (see chi2.h).
#include "chi2.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <vector>

namespace glint::test {

// ---------------------------------------------------------------------------------------------
// The chi-square distribution
// ---------------------------------------------------------------------------------------------

double regularizedGammaQ(double a, double x) {
  if (x <= 0) return 1;
  // x^a e^-x / Gamma(a), in logs so that large a and x do not overflow.
  const double prefactor = std::exp(a * std::log(x) - x - std::lgamma(a));
  constexpr double kEpsilon = 1e-15;
  constexpr int kMaxIterations = 100000;
  if (x < a + 1) {
    // The lower function P from its power series, which converges fast here; Q = 1 - P.
    double term = 1 / a, sum = term;
    for (int n = 1; n < kMaxIterations; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::abs(term) < std::abs(sum) * kEpsilon) break;
    }
    return std::clamp(1 - prefactor * sum, 0.0, 1.0);
  }
  // Q itself from its continued fraction, evaluated front to back with Lentz's method.
  constexpr double kTiny = 1e-300;
  double b = x + 1 - a, c = 1 / kTiny, d = 1 / b, fraction = d;
  for (int i = 1; i < kMaxIterations; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1 / d;
    const double step = d * c;
    fraction *= step;
    if (std::abs(step - 1) < kEpsilon) break;
  }
  return std::clamp(prefactor * fraction, 0.0, 1.0);
}

double chi2SurvivalFunction(double x, int dof) { return regularizedGammaQ(dof / 2.0, x / 2); }

namespace {

// ---------------------------------------------------------------------------------------------
// Integrating the pdf over a bin
// ---------------------------------------------------------------------------------------------

// A bin of the (cos theta, phi) plane; solid angle is dcos(theta) dphi, so no Jacobian.
struct Rect {
  double c0, c1, phi0, phi1;
};

class BinIntegrator {
 public:
  BinIntegrator(const DirectionPdf& pdf, const Frame& frame, int64_t sampleCount)
      : pdf_(pdf), frame_(frame), n_(double(sampleCount)) {}

  // The integral of the pdf over the bin `r`, with its estimated absolute error added to
  // *error. The first `minDepth` levels of subdivision are made whatever the error test says.
  double integrate(const Rect& r, int minDepth, double* error) {
    // Bins that touch a pole are split towards it geometrically: there the (cos theta, phi)
    // plane squeezes whole lobes into a sliver next to cos(theta) = +-1 that no Gauss node
    // of the bin would reach.
    constexpr int kPoleSplits = 16;
    if (r.c1 == 1 || r.c0 == -1) {
      const bool top = r.c1 == 1;
      const double pole = top ? 1 : -1;
      double edge = top ? r.c0 : r.c1, sum = 0;
      for (int i = 1; i <= kPoleSplits; ++i) {
        // Each piece takes half of what is left between the edge and the pole.
        const double next = i == kPoleSplits ? pole : (edge + pole) / 2;
        const Rect piece =
            top ? Rect{edge, next, r.phi0, r.phi1} : Rect{next, edge, r.phi0, r.phi1};
        sum += integratePiece(piece, minDepth, error);
        edge = next;
      }
      return sum;
    }
    return integratePiece(r, minDepth, error);
  }

  int badValues() const { return badValues_; }
  Vec3f firstBadDirection() const { return firstBad_; }
  float firstBadValue() const { return firstBadValue_; }

 private:
  static constexpr int kMaxDepth = 7;

  double integratePiece(const Rect& r, int minDepth, double* error) {
    const double whole = gauss(r);
    // Keep the error of the expected count far below that count's noise, sqrt(expected).
    const double tolerance = 1e-3 * std::sqrt(std::max(n_ * std::abs(whole), 1.0)) / n_;
    return refine(r, whole, tolerance, 0, minDepth, error);
  }

  double refine(const Rect& r, double whole, double tolerance, int depth, int minDepth,
                double* error) {
    const double cm = (r.c0 + r.c1) / 2, pm = (r.phi0 + r.phi1) / 2;
    const Rect quarters[4] = {{r.c0, cm, r.phi0, pm},
                              {cm, r.c1, r.phi0, pm},
                              {r.c0, cm, pm, r.phi1},
                              {cm, r.c1, pm, r.phi1}};
    double parts[4], sum = 0;
    for (int i = 0; i < 4; ++i) sum += parts[i] = gauss(quarters[i]);
    const double difference = std::abs(sum - whole);
    if ((difference <= tolerance && depth >= minDepth) || depth == kMaxDepth) {
      *error += difference;
      return sum;
    }
    double total = 0;
    for (int i = 0; i < 4; ++i)
      total += refine(quarters[i], parts[i], tolerance / 2, depth + 1, minDepth, error);
    return total;
  }

  // Tensor-product 4-point Gauss–Legendre rule: exact for polynomials of degree 7 in each
  // variable, and its nodes stay inside the rectangle.
  double gauss(const Rect& r) {
    static constexpr double kNodes[4] = {-0.86113631159405257522, -0.33998104358485626480,
                                         0.33998104358485626480, 0.86113631159405257522};
    static constexpr double kWeights[4] = {0.34785484513745385737, 0.65214515486254614263,
                                           0.65214515486254614263, 0.34785484513745385737};
    const double hc = (r.c1 - r.c0) / 2, mc = (r.c0 + r.c1) / 2;
    const double hp = (r.phi1 - r.phi0) / 2, mp = (r.phi0 + r.phi1) / 2;
    double sum = 0;
    for (int i = 0; i < 4; ++i) {
      const double c = mc + hc * kNodes[i];
      const double s = std::sqrt(std::max(0.0, 1 - c * c));
      for (int j = 0; j < 4; ++j) {
        const double phi = mp + hp * kNodes[j];
        sum += kWeights[i] * kWeights[j] * evaluate(c, s, phi);
      }
    }
    return sum * hc * hp;
  }

  double evaluate(double c, double s, double phi) {
    const Vec3f local{float(s * std::cos(phi)), float(s * std::sin(phi)), float(c)};
    const Vec3f w = frame_.fromLocal(local);
    const float value = pdf_(w);
    if (!std::isfinite(value) || value < 0) {
      if (badValues_++ == 0) firstBad_ = w, firstBadValue_ = value;
      return 0;
    }
    return value;
  }

  const DirectionPdf& pdf_;
  Frame frame_;
  double n_;
  int badValues_ = 0;
  Vec3f firstBad_;
  float firstBadValue_ = 0;
};

// ---------------------------------------------------------------------------------------------
// Bins
// ---------------------------------------------------------------------------------------------

// Ring edges in cos(theta), ascending from -1 to 1.
std::vector<double> ringEdges(const Chi2Options& options) {
  std::vector<double> edges;
  auto addUniform = [&](double from, double to, int count) {
    for (int i = 0; i < count; ++i) edges.push_back(from + (to - from) * i / count);
  };
  if (options.capCosTheta > 0 && options.outerThetaBins >= 2) {
    // Keep the horizon (cos(theta) = 0) on an edge here too.
    addUniform(-1, 0, options.outerThetaBins / 2);
    addUniform(0, options.capCosTheta, options.outerThetaBins - options.outerThetaBins / 2);
    addUniform(options.capCosTheta, 1, options.thetaBins);
  } else if (options.capCosTheta > -1) {
    addUniform(-1, options.capCosTheta, options.outerThetaBins);
    addUniform(options.capCosTheta, 1, options.thetaBins);
  } else {
    addUniform(-1, 1, options.thetaBins);
  }
  edges.push_back(1);
  return edges;
}

// A uniform float in [0, 1) from 24 random bits (never rounds up to 1).
float uniformFloat(std::mt19937_64& rng) { return float(rng() >> 40) * 0x1p-24f; }

std::string formatVector(Vec3f v) {
  std::ostringstream s;
  s << "(" << v.x << ", " << v.y << ", " << v.z << ")";
  return s.str();
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// The test
// ---------------------------------------------------------------------------------------------

Chi2Result chi2Test(const DirectionSampler& sample, const DirectionPdf& pdf,
                    const Chi2Options& options) {
  Chi2Result result;
  const double alpha = -std::expm1(std::log1p(-options.significance) / options.testCount);
  result.significance = alpha;
  const std::vector<double> edges = ringEdges(options);
  const int rings = int(edges.size()) - 1, phis = options.phiBins, bins = rings * phis;
  const double phiStep = 2 * kPi / phis;
  const int64_t n = options.sampleCount;

  // Histogram of the samples.
  std::vector<int64_t> observed(bins, 0);
  int64_t failures = 0, invalid = 0;
  std::optional<Vec3f> firstInvalid;
  std::mt19937_64 rng(options.seed);
  for (int64_t i = 0; i < n; ++i) {
    const float u0 = uniformFloat(rng), u1 = uniformFloat(rng), uLobe = uniformFloat(rng);
    const std::optional<Vec3f> w = sample(Vec2f{u0, u1}, uLobe);
    if (!w) {
      ++failures;
      continue;
    }
    if (!isFinite(*w) || std::abs(length(*w) - 1) > 1e-3f) {
      if (invalid++ == 0) firstInvalid = *w;
      continue;
    }
    const Vec3f local = options.binFrame.toLocal(*w);
    const double c = std::clamp(double(local.z), -1.0, 1.0);
    int ring = int(std::upper_bound(edges.begin(), edges.end(), c) - edges.begin()) - 1;
    ring = std::clamp(ring, 0, rings - 1);
    double phi = std::atan2(double(local.y), double(local.x));
    if (phi < 0) phi += 2 * kPi;
    const int wedge = std::clamp(int(phi / phiStep), 0, phis - 1);
    ++observed[ring * phis + wedge];
  }
  result.failureFraction = double(failures) / double(n);

  // Probability of every bin under the pdf.
  BinIntegrator integrator(pdf, options.binFrame, n);
  std::vector<double> probability(bins);
  double integral = 0, error = 0;
  constexpr int kMaxRelooks = 16;
  int relooks = 0;
  for (int r = 0; r < rings; ++r)
    for (int p = 0; p < phis; ++p) {
      const Rect rect{edges[r], edges[r + 1], p * phiStep, (p + 1) * phiStep};
      const int b = r * phis + p;
      double binError = 0;
      probability[b] = integrator.integrate(rect, 0, &binError);
      // Samples where the cubature saw no mass at all: look again, much closer, for a narrow
      // feature (the edge of a lobe clipping a corner) that fell between the nodes. A few
      // bins at most: beyond that the sampler is wrong, not the cubature.
      if (observed[b] > 0 && probability[b] <= 0 && relooks++ < kMaxRelooks) {
        binError = 0;
        probability[b] = integrator.integrate(rect, 5, &binError);
      }
      integral += probability[b];
      error += binError;
    }
  result.pdfIntegral = integral;
  result.integrationError = error;

  std::ostringstream message;
  bool passed = true;
  auto fail = [&](const std::string& why) {
    passed = false;
    message << why << "\n";
  };
  if (invalid > 0)
    fail(std::to_string(invalid) + " samples are not finite unit vectors, e.g. " +
         formatVector(*firstInvalid));
  if (integrator.badValues() > 0) {
    std::ostringstream s;
    s << integrator.badValues() << " pdf values are negative or not finite, e.g. pdf"
      << formatVector(integrator.firstBadDirection()) << " = " << integrator.firstBadValue();
    fail(s.str());
  }
  if (integral <= 0) {
    fail("the pdf integrates to " + std::to_string(integral));
    result.message = message.str();
    return result;
  }
  if (integral > 1 + std::max(1e-4, 3 * error))
    fail("the pdf integrates to " + std::to_string(integral) + " > 1");

  // The failed samples against the pdf's missing mass: a binomial count, approximated by a
  // normal whose deviation is at least one sample; the integration error is given away.
  {
    const double missing = 1 - integral, q = std::clamp(missing, 0.0, 1.0);
    const double sd = std::max(std::sqrt(q * (1 - q) / double(n)), 1 / double(n));
    const double deviation = std::max(0.0, std::abs(result.failureFraction - missing) - 2 * error);
    result.failurePValue = std::erfc(deviation / sd / std::sqrt(2.0));
    if (result.failurePValue <= alpha) {
      std::ostringstream s;
      s << "the sampler failed for a fraction " << result.failureFraction
        << " of the samples, but the pdf misses " << missing
        << " of its mass (p = " << result.failurePValue << ")";
      fail(s.str());
    }
  }

  // Expected counts given the samples that succeeded; pool the sparse bins.
  struct Cell {
    double observed = 0, expected = 0;
    int bin = -1;  // -1: the pooled cell
  };
  const double returned = double(n - failures - invalid);
  std::vector<Cell> cells;
  Cell pool;
  int64_t impossible = 0;
  int firstImpossible = -1;
  for (int b = 0; b < bins; ++b) {
    const double expected = returned * probability[b] / integral;
    if (expected <= 0 && observed[b] > 0) {
      impossible += observed[b];
      if (firstImpossible < 0) firstImpossible = b;
    }
    if (expected < options.minExpected) {
      pool.observed += double(observed[b]);
      pool.expected += expected;
    } else {
      cells.push_back({double(observed[b]), expected, b});
    }
  }
  auto describeBin = [&](int b) {
    std::ostringstream s;
    if (b < 0) return std::string("pooled sparse bins");
    const int r = b / phis, p = b % phis;
    s << "cos(theta) in [" << edges[r] << ", " << edges[r + 1] << "], phi in [" << p * phiStep
      << ", " << (p + 1) * phiStep << "]";
    return s.str();
  };
  if (impossible > 0)
    fail(std::to_string(impossible) + " samples fell where the pdf is zero, e.g. " +
         describeBin(firstImpossible));
  if (pool.expected >= options.minExpected || cells.empty()) {
    if (pool.expected > 0 || pool.observed > 0) cells.push_back(pool);
  } else if (pool.expected > 0 || pool.observed > 0) {
    // Too little to stand alone: merge into the sparsest regular cell.
    auto sparsest = std::min_element(cells.begin(), cells.end(), [](const Cell& a, const Cell& b) {
      return a.expected < b.expected;
    });
    sparsest->observed += pool.observed;
    sparsest->expected += pool.expected;
  }

  // Pearson's statistic.
  std::vector<std::pair<double, int>> contributions;
  for (size_t i = 0; i < cells.size(); ++i) {
    const Cell& cell = cells[i];
    const double d = cell.observed - cell.expected;
    const double term = cell.expected > 0 ? d * d / cell.expected : (cell.observed > 0 ? 1e30 : 0);
    result.chi2 += term;
    contributions.push_back({term, int(i)});
  }
  result.dof = int(cells.size()) - 1;
  if (result.dof < 1) {
    fail("fewer than two bins expect " + std::to_string(options.minExpected) +
         " samples: a delta lobe, or too few samples");
  } else {
    result.pValue = chi2SurvivalFunction(result.chi2, result.dof);
    if (result.pValue <= alpha) {
      std::ostringstream s;
      s << "chi2 = " << result.chi2 << " with " << result.dof << " dof: p = " << result.pValue
        << " <= " << alpha << "; the worst bins:";
      std::sort(contributions.rbegin(), contributions.rend());
      for (size_t i = 0; i < std::min<size_t>(5, contributions.size()); ++i) {
        const Cell& cell = cells[contributions[i].second];
        s << "\n  " << describeBin(cell.bin) << ": observed " << cell.observed << ", expected "
          << cell.expected << " (adds " << contributions[i].first << ")";
      }
      fail(s.str());
    }
  }

  result.passed = passed;
  if (passed) {
    std::ostringstream s;
    s << "chi2 = " << result.chi2 << " with " << result.dof << " dof (p = " << result.pValue
      << "); pdf integral " << result.pdfIntegral << ", failures " << result.failureFraction;
    result.message = s.str();
  } else {
    result.message = message.str();
  }
  return result;
}

}  // namespace glint::test
