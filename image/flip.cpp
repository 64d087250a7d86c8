// glint — LDR- and HDR-FLIP (Andersson et al. 2020, 2021); see flip.h for the references and
// the deviations from them.
#include "image/flip.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace glint {

namespace {

constexpr double kPiD = 3.14159265358979323846;

// ---- the papers' constants -------------------------------------------------------------------

// Contrast sensitivity of each opponent channel as a sum of two Gaussians in the spatial
// domain, a1·√(π/b1)·exp(−π²r²/b1) + a2·√(π/b2)·exp(−π²r²/b2), r in degrees (HPG 2020, Sec. 4.1;
// b in deg²). A and RG use one Gaussian (a2 = 0).
struct Csf {
  double a1, b1, a2, b2;
};
constexpr Csf kCsfA{1.0, 0.0047, 0.0, 1.0};  // b2 unused where a2 = 0
constexpr Csf kCsfRG{1.0, 0.0053, 0.0, 1.0};
constexpr Csf kCsfBY{34.1, 0.04, 13.5, 0.025};
constexpr double kCsfWidestB = 0.04;  // every CSF kernel gets the radius of the widest Gaussian

constexpr float kQc = 0.7f;   // exponent on the HyAB distance
constexpr float kPc = 0.4f;   // the re-mapping's knee: a fraction pc of the largest distance …
constexpr float kPt = 0.95f;  // … maps to pt
constexpr double kW = 0.082;  // peak-to-trough width of the edge detector, in degrees
constexpr float kQf = 0.5f;   // exponent on the feature difference

// ---- colour spaces ---------------------------------------------------------------------------
//
// sRGB primaries with the D65 white (IEC 61966-2-1): the XYZ matrix derived from the primaries'
// chromaticities, in exact rational form, and the reference white as its row sums.

struct Mat3 {
  std::array<double, 9> m;
  constexpr Vec3f operator()(Vec3f v) const {
    return {float(m[0] * v.x + m[1] * v.y + m[2] * v.z),
            float(m[3] * v.x + m[4] * v.y + m[5] * v.z),
            float(m[6] * v.x + m[7] * v.y + m[8] * v.z)};
  }
};

constexpr Mat3 kXyzFromLinear{
    {10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0,
     2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0, 1425312.0 / 73733382.0,
     8788810.0 / 73733382.0, 70074185.0 / 73733382.0}};

constexpr Mat3 inverse(const Mat3& a) {
  const auto& m = a.m;
  double c00 = m[4] * m[8] - m[5] * m[7], c01 = m[5] * m[6] - m[3] * m[8],
         c02 = m[3] * m[7] - m[4] * m[6];
  double det = m[0] * c00 + m[1] * c01 + m[2] * c02;
  return {{c00 / det, (m[2] * m[7] - m[1] * m[8]) / det, (m[1] * m[5] - m[2] * m[4]) / det,
           c01 / det, (m[0] * m[8] - m[2] * m[6]) / det, (m[2] * m[3] - m[0] * m[5]) / det,
           c02 / det, (m[1] * m[6] - m[0] * m[7]) / det, (m[0] * m[4] - m[1] * m[3]) / det}};
}

constexpr Mat3 kLinearFromXyz = inverse(kXyzFromLinear);

constexpr Vec3f kWhite = kXyzFromLinear({1, 1, 1});  // D65, Y = 1
constexpr Vec3f kInvWhite = {1 / kWhite.x, 1 / kWhite.y, 1 / kWhite.z};

float srgbToLinear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

float linearToSrgb(float c) {
  return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1 / 2.4f) - 0.055f;
}

// YCxCz (Edge, Allebach and coworkers' linearised L*a*b*): opponent channels linear in XYZ.
Vec3f ycxczFromXyz(Vec3f xyz) {
  Vec3f n = xyz * kInvWhite;
  return {116 * n.y - 16, 500 * (n.x - n.y), 200 * (n.y - n.z)};
}

Vec3f xyzFromYcxcz(Vec3f c) {
  float y = (c.x + 16) / 116;
  return Vec3f{y + c.y / 500, y, y - c.z / 200} * kWhite;
}

Vec3f labFromXyz(Vec3f xyz) {
  constexpr float delta = 6.0f / 29.0f;
  constexpr float deltaCube = delta * delta * delta;
  auto f = [&](float t) {
    return t > deltaCube ? std::cbrt(t) : t / (3 * delta * delta) + 4.0f / 29.0f;
  };
  Vec3f n = xyz * kInvWhite;
  float fx = f(n.x), fy = f(n.y), fz = f(n.z);
  return {116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)};
}

// Hunt effect: chroma is scaled with lightness, so dark colours differ less.
Vec3f huntLabFromLinear(Vec3f linear) {
  Vec3f lab = labFromXyz(kXyzFromLinear(linear));
  return {lab.x, 0.01f * lab.x * lab.y, 0.01f * lab.x * lab.z};
}

// HyAB: city-block in lightness, Euclidean in the chromatic plane.
float hyab(Vec3f a, Vec3f b) {
  return std::abs(a.x - b.x) + std::sqrt((a.y - b.y) * (a.y - b.y) + (a.z - b.z) * (a.z - b.z));
}

// The largest HyAB distance in Hunt-adjusted L*a*b* between colours of the RGB cube, pure green
// against pure blue, raised to qc.
float cmax() {
  static const float c =
      std::pow(hyab(huntLabFromLinear({0, 1, 0}), huntLabFromLinear({0, 0, 1})), kQc);
  return c;
}

// Re-maps the distance^qc to [0, 1]: [0, pc·cmax) linearly onto [0, pt), the rest onto [pt, 1],
// so the small differences that matter get most of the range.
float remapColorError(float distance) {
  const float e = std::pow(distance, kQc), c = cmax(), knee = kPc * c;
  return e < knee ? kPt / knee * e : kPt + (e - knee) / (c - knee) * (1 - kPt);
}

// ---- planes and separable filters ------------------------------------------------------------

struct Plane {
  int width = 0, height = 0;
  std::vector<float> v;
  void resize(int w, int h) {
    width = w, height = h;
    v.resize(size_t(w) * size_t(h));
  }
  float* row(int y) { return v.data() + size_t(y) * size_t(width); }
  const float* row(int y) const { return v.data() + size_t(y) * size_t(width); }
};

template <class F>
void forRows(int height, F&& f) {
  tbb::parallel_for(tbb::blocked_range<int>(0, height, 8), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y != r.end(); ++y) f(y);
  });
}

// A 1-D kernel of odd length, centred; applied as a correlation (the kernels here are symmetric
// or antisymmetric, and only magnitudes of the antisymmetric ones are used).
using Kernel = std::vector<float>;

// dst[x] (+)= scale · Σ_t k[t] · src[t][x] for x < n. Blocks of 8 outputs accumulate in
// registers, a shape GCC's -O2 vectoriser takes.
void weightedSum(const float* const* src, const Kernel& k, int n, float* __restrict dst,
                 float scale, bool accumulate) {
  const int taps = int(k.size());
  auto store = [&](int x, float acc) { dst[x] = accumulate ? dst[x] + scale * acc : scale * acc; };
  int x = 0;
  for (; x + 8 <= n; x += 8) {
    float acc[8] = {};
    for (int t = 0; t < taps; ++t) {
      const float* __restrict s = src[t] + x;
      const float w = k[size_t(t)];
      for (int j = 0; j < 8; ++j) acc[j] += w * s[j];
    }
    for (int j = 0; j < 8; ++j) store(x + j, acc[j]);
  }
  for (; x < n; ++x) {
    float acc = 0;
    for (int t = 0; t < taps; ++t) acc += k[size_t(t)] * src[t][x];
    store(x, acc);
  }
}

// outs[i] = in ⋆ kernels[i] along rows, edges replicated. All kernels have the same length.
void filterRows(const Plane& in, std::initializer_list<const Kernel*> kernels,
                std::initializer_list<Plane*> outs) {
  const int w = in.width, taps = int((*kernels.begin())->size()), r = taps / 2;
  for (Plane* o : outs) o->resize(in.width, in.height);
  tbb::parallel_for(tbb::blocked_range<int>(0, in.height, 8),
                    [&](const tbb::blocked_range<int>& rows) {
                      std::vector<float> padded(size_t(w + 2 * r));
                      std::vector<const float*> src(static_cast<size_t>(taps));
                      for (int t = 0; t < taps; ++t) src[size_t(t)] = padded.data() + t;
                      for (int y = rows.begin(); y != rows.end(); ++y) {
                        const float* row = in.row(y);
                        std::fill(padded.begin(), padded.begin() + r, row[0]);
                        std::copy(row, row + w, padded.begin() + r);
                        std::fill(padded.begin() + r + w, padded.end(), row[w - 1]);
                        auto out = outs.begin();
                        for (const Kernel* k : kernels)
                          weightedSum(src.data(), *k, w, (*out++)->row(y), 1, false);
                      }
                    });
}

// out (+)= scale · (in ⋆ k) along columns, edges replicated.
void filterColumns(const Plane& in, const Kernel& k, Plane& out, float scale = 1,
                   bool accumulate = false) {
  const int h = in.height, taps = int(k.size()), r = taps / 2;
  if (!accumulate) out.resize(in.width, in.height);
  tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& rows) {
    std::vector<const float*> src(static_cast<size_t>(taps));
    for (int y = rows.begin(); y != rows.end(); ++y) {
      for (int t = 0; t < taps; ++t) src[size_t(t)] = in.row(std::clamp(y + t - r, 0, h - 1));
      weightedSum(src.data(), k, in.width, out.row(y), scale, accumulate);
    }
  });
}

// A CSF channel as separable terms: the 2-D filter is Σ weight_i · g_i(x) g_i(y), with each g_i
// normalised to sum 1 and Σ weight_i = 1, which is the paper's 2-D kernel normalised to sum 1.
struct CsfFilter {
  std::vector<Kernel> g;
  std::vector<float> weight;
};

CsfFilter makeCsfFilter(const Csf& c, double ppd) {
  const int r = int(std::ceil(3 * std::sqrt(kCsfWidestB / (2 * kPiD * kPiD)) * ppd));
  CsfFilter f;
  std::vector<double> mass;
  for (auto [a, b] : {std::pair{c.a1, c.b1}, std::pair{c.a2, c.b2}}) {
    if (a == 0) continue;
    Kernel g(size_t(2 * r + 1));
    double sum = 0;
    for (int x = -r; x <= r; ++x) {
      double d = x / ppd;  // degrees
      double v = std::exp(-kPiD * kPiD * d * d / b);
      g[size_t(x + r)] = float(v);
      sum += v;
    }
    for (float& v : g) v = float(v / sum);
    f.g.push_back(std::move(g));
    mass.push_back(a * std::sqrt(kPiD / b) * sum * sum);  // the term's 2-D kernel sum
  }
  double total = 0;
  for (double m : mass) total += m;
  for (double m : mass) f.weight.push_back(float(m / total));
  return f;
}

// Filters `plane` in place; `a` and `b` are scratch.
void applyCsf(Plane& plane, const CsfFilter& f, Plane& a, Plane& b) {
  if (f.g.size() == 1) {
    filterRows(plane, {&f.g[0]}, {&a});
    filterColumns(a, f.g[0], plane);
    return;
  }
  for (size_t i = 0; i < f.g.size(); ++i) {
    filterRows(plane, {&f.g[i]}, {&a});
    filterColumns(a, f.g[i], b, f.weight[i], /*accumulate=*/i > 0);
  }
  std::swap(plane.v, b.v);
}

// The feature detectors' 1-D factors (σ = w/2 · ppd, radius ⌈3σ⌉): the Gaussian g normalised to
// sum 1, and its first and second derivatives with positive weights summing to 1 and negative
// ones to −1. The paper's 2-D edge filter along x is dg(x)·g(y), the point filter ddg(x)·g(y);
// normalising the 2-D kernels this way factors into these 1-D normalisations.
struct FeatureFilter {
  Kernel g, dg, ddg;
};

FeatureFilter makeFeatureFilter(double ppd) {
  const double sd = 0.5 * kW * ppd;
  const int r = int(std::ceil(3 * sd));
  FeatureFilter f{Kernel(size_t(2 * r + 1)), Kernel(size_t(2 * r + 1)), Kernel(size_t(2 * r + 1))};
  std::vector<double> g(f.g.size()), dg(g.size()), ddg(g.size());
  for (int x = -r; x <= r; ++x) {
    size_t i = size_t(x + r);
    g[i] = std::exp(-double(x) * x / (2 * sd * sd));
    dg[i] = -x * g[i];
    ddg[i] = (double(x) * x / (sd * sd) - 1) * g[i];
  }
  auto normalise = [](const std::vector<double>& in, Kernel& out) {
    double pos = 0, neg = 0;
    for (double v : in) (v > 0 ? pos : neg) += std::abs(v);
    for (size_t i = 0; i < in.size(); ++i)
      out[i] = float(in[i] > 0 ? in[i] / pos : (neg > 0 ? in[i] / neg : 0.0));
  };
  normalise(g, f.g);
  normalise(dg, f.dg);
  normalise(ddg, f.ddg);
  return f;
}

// ---- the two pipelines on one image ----------------------------------------------------------

struct Filters {
  CsfFilter a, rg, by;
  FeatureFilter feature;
  explicit Filters(double ppd)
      : a(makeCsfFilter(kCsfA, ppd)),
        rg(makeCsfFilter(kCsfRG, ppd)),
        by(makeCsfFilter(kCsfBY, ppd)),
        feature(makeFeatureFilter(ppd)) {}
};

float sanitizeLdr(float v) { return std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f; }

// One image through both pipelines. The planes are reused from call to call (HDR-FLIP runs
// many), so a 1080p image does not fault in fresh pages for every pass.
struct Prepared {
  std::array<Plane, 3> c;  // YCxCz, then CSF-filtered, then Hunt-adjusted L*a*b*
  Plane edge, point;       // feature detector response magnitudes
};

struct Scratch {
  Plane a, b, c;
};

// The sRGB image as the three YCxCz planes.
void opponentPlanes(std::span<const float> srgb, int w, int h, std::array<Plane, 3>& p) {
  for (Plane& q : p) q.resize(w, h);
  forRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      size_t i = size_t(y) * size_t(w) + size_t(x);
      Vec3f lin{srgbToLinear(sanitizeLdr(srgb[3 * i])), srgbToLinear(sanitizeLdr(srgb[3 * i + 1])),
                srgbToLinear(sanitizeLdr(srgb[3 * i + 2]))};
      Vec3f c = ycxczFromXyz(kXyzFromLinear(lin));
      p[0].v[i] = c.x, p[1].v[i] = c.y, p[2].v[i] = c.z;
    }
  });
}

// CSF-filters the YCxCz planes in place, then hands each pixel, back in linear RGB clamped to
// the unit cube, to `sink(i, rgb)`.
template <class Sink>
void filterOpponent(std::array<Plane, 3>& c, const Filters& f, Scratch& s, Sink&& sink) {
  applyCsf(c[0], f.a, s.a, s.b);
  applyCsf(c[1], f.rg, s.a, s.b);
  applyCsf(c[2], f.by, s.a, s.b);
  const int w = c[0].width;
  forRows(c[0].height, [&](int y) {
    for (int x = 0; x < w; ++x) {
      size_t i = size_t(y) * size_t(w) + size_t(x);
      Vec3f lin = kLinearFromXyz(xyzFromYcxcz({c[0].v[i], c[1].v[i], c[2].v[i]}));
      sink(i, Vec3f{std::clamp(lin.x, 0.0f, 1.0f), std::clamp(lin.y, 0.0f, 1.0f),
                    std::clamp(lin.z, 0.0f, 1.0f)});
    }
  });
}

void prepare(std::span<const float> srgb, int w, int h, const Filters& f, Prepared& p, Scratch& s) {
  opponentPlanes(srgb, w, h, p.c);

  // Features on the achromatic channel normalised to [0, 1]: (Y + 16) / 116 = Y / Y_white.
  Plane& lum = s.a;
  lum.resize(w, h);
  for (size_t i = 0; i < lum.v.size(); ++i) lum.v[i] = (p.c[0].v[i] + 16) / 116;
  const FeatureFilter& ff = f.feature;
  Plane& hg = s.b;  // rows: Gaussian; edge and point hold the rows' derivatives for now
  filterRows(lum, {&ff.g, &ff.dg, &ff.ddg}, {&hg, &p.edge, &p.point});
  for (auto [derivative, out] : {std::pair{&ff.dg, &p.edge}, std::pair{&ff.ddg, &p.point}}) {
    filterColumns(*out, ff.g, s.a);       // derivative across x, Gaussian along y
    filterColumns(hg, *derivative, s.c);  // Gaussian across x, derivative along y
    for (size_t i = 0; i < out->v.size(); ++i) out->v[i] = std::hypot(s.a.v[i], s.c.v[i]);
  }

  filterOpponent(p.c, f, s, [&](size_t i, Vec3f lin) {
    Vec3f lab = huntLabFromLinear(lin);
    p.c[0].v[i] = lab.x, p.c[1].v[i] = lab.y, p.c[2].v[i] = lab.z;
  });
}

void checkInputs(std::span<const float> a, std::span<const float> b, int w, int h, double ppd) {
  if (w <= 0 || h <= 0)
    throw std::logic_error("FLIP: image size " + std::to_string(w) + "×" + std::to_string(h) +
                           " is not positive");
  size_t n = size_t(w) * size_t(h) * 3;
  if (a.size() != n || b.size() != n)
    throw std::logic_error("FLIP: RGB buffers of " + std::to_string(a.size()) + " and " +
                           std::to_string(b.size()) + " floats for a " + std::to_string(w) + "×" +
                           std::to_string(h) + " image (" + std::to_string(n) + " expected)");
  if (!(ppd > 0) || !std::isfinite(ppd))
    throw std::logic_error("FLIP: pixels per degree must be positive");
}

// Everything one LDR-FLIP evaluation needs, kept for the next (HDR-FLIP's exposures).
struct Workspace {
  Prepared ref, test;
  Scratch scratch;
};

// Calls `pixel(i, ΔE_c, ΔE_f)` for every pixel i, in parallel.
template <class F>
void ldrFlip(std::span<const float> ref, std::span<const float> test, int w, int h,
             const Filters& f, Workspace& ws, F&& pixel) {
  prepare(ref, w, h, f, ws.ref, ws.scratch);
  prepare(test, w, h, f, ws.test, ws.scratch);
  const Prepared &r = ws.ref, &t = ws.test;
  forRows(h, [&](int y) {
    for (size_t i = size_t(y) * size_t(w); i < size_t(y + 1) * size_t(w); ++i) {
      Vec3f a{r.c[0].v[i], r.c[1].v[i], r.c[2].v[i]};
      Vec3f b{t.c[0].v[i], t.c[1].v[i], t.c[2].v[i]};
      float color = remapColorError(hyab(a, b));
      float df =
          std::max(std::abs(r.edge.v[i] - t.edge.v[i]), std::abs(r.point.v[i] - t.point.v[i]));
      pixel(i, color, std::pow(df / std::sqrt(2.0f), kQf));
    }
  });
}

// ΔE = ΔE_c^(1 − ΔE_f).
float combine(float color, float feature) { return std::pow(color, 1 - feature); }

// ---- HDR -------------------------------------------------------------------------------------

// The rational tone curves as (k0·x² + k1·x + k2) / (k3·x² + k4·x + k5). Reinhard's is listed as
// x / (1 + x) for the exposure range; the image itself is mapped with its luminance.
struct ToneCurve {
  double k[6];
};

ToneCurve toneCurve(FlipToneMapper tm) {
  switch (tm) {
    case FlipToneMapper::Aces:  // Narkowicz 2016, the 0.6 pre-exposure folded in
      return {{0.6 * 0.6 * 2.51, 0.6 * 0.03, 0, 0.6 * 0.6 * 2.43, 0.6 * 0.59, 0.14}};
    case FlipToneMapper::Hable: {
      // ((x(Ax + CB) + DE) / (x(Ax + B) + DF)) − E/F, scaled by the white point 11.2, input ×2.
      const double A = 0.15, B = 0.50, C = 0.10, D = 0.20, E = 0.02, F = 0.30, W = 11.2;
      double k0 = A * F - A * E, k1 = C * B * F - B * E, k3 = A * F, k4 = B * F, k5 = D * F * F;
      double white = (k3 * W * W + k4 * W + k5) / (k0 * W * W + k1 * W);
      return {{4 * k0 * white, 2 * k1 * white, 0, 4 * k3, 2 * k4, k5}};
    }
    case FlipToneMapper::Reinhard:
      return {{0, 1, 0, 0, 1, 1}};
  }
  return {};
}

float sanitizeHdr(float v) { return std::isnan(v) || v < 0 ? 0.0f : v; }

}  // namespace

// ---- public ----------------------------------------------------------------------------------

double flipPixelsPerDegree(double distanceMeters, double monitorWidthPixels,
                           double monitorWidthMeters) {
  return distanceMeters * (monitorWidthPixels / monitorWidthMeters) * kPiD / 180.0;
}

FlipComponents flipLdrComponents(std::span<const float> reference, std::span<const float> test,
                                 int width, int height, double pixelsPerDegree) {
  checkInputs(reference, test, width, height, pixelsPerDegree);
  const size_t n = size_t(width) * size_t(height);
  FlipComponents c{width, height, std::vector<float>(n), std::vector<float>(n)};
  Workspace ws;
  ldrFlip(reference, test, width, height, Filters(pixelsPerDegree), ws,
          [&](size_t i, float color, float feature) {
            c.color[i] = color;
            c.feature[i] = feature;
          });
  return c;
}

FlipResult flipLdr(std::span<const float> reference, std::span<const float> test, int width,
                   int height, double pixelsPerDegree) {
  checkInputs(reference, test, width, height, pixelsPerDegree);
  FlipResult r;
  r.width = width, r.height = height;
  r.error.resize(size_t(width) * size_t(height));
  Workspace ws;
  ldrFlip(reference, test, width, height, Filters(pixelsPerDegree), ws,
          [&](size_t i, float color, float feature) { r.error[i] = combine(color, feature); });
  r.stats = flipStatistics(r.error, width);
  return r;
}

std::vector<float> flipCsfFiltered(std::span<const float> srgb, int width, int height,
                                   double pixelsPerDegree) {
  checkInputs(srgb, srgb, width, height, pixelsPerDegree);
  std::vector<float> out(srgb.size());
  std::array<Plane, 3> c;
  Scratch s;
  opponentPlanes(srgb, width, height, c);
  filterOpponent(c, Filters(pixelsPerDegree), s, [&](size_t i, Vec3f lin) {
    out[3 * i] = lin.x, out[3 * i + 1] = lin.y, out[3 * i + 2] = lin.z;
  });
  return out;
}

Rgb flipToneMap(Rgb c, float exposure, FlipToneMapper toneMapper) {
  const float m = std::exp2(exposure);
  Vec3f x{sanitizeHdr(c.x) * m, sanitizeHdr(c.y) * m, sanitizeHdr(c.z) * m};
  auto clamp01 = [](float v) { return std::isnan(v) ? 1.0f : std::clamp(v, 0.0f, 1.0f); };
  if (toneMapper == FlipToneMapper::Reinhard) {
    float y = luminance(x);
    if (!std::isfinite(y)) return {clamp01(x.x), clamp01(x.y), clamp01(x.z)};
    return {clamp01(x.x / (1 + y)), clamp01(x.y / (1 + y)), clamp01(x.z / (1 + y))};
  }
  const ToneCurve tc = toneCurve(toneMapper);
  auto curve = [&](float v) {
    if (!std::isfinite(v)) return 1.0f;  // the curves tend to 1 (ACES) or above, clamped
    double d = v;
    return clamp01(float((tc.k[0] * d * d + tc.k[1] * d + tc.k[2]) /
                         (tc.k[3] * d * d + tc.k[4] * d + tc.k[5])));
  };
  return {curve(x.x), curve(x.y), curve(x.z)};
}

FlipExposures flipExposureRange(std::span<const float> reference, int width, int height,
                                FlipToneMapper toneMapper) {
  checkInputs(reference, reference, width, height, 1);
  // The exposure x at which the tone curve reaches t = 0.85: the positive root of
  // (k0 − t·k3)x² + (k1 − t·k4)x + (k2 − t·k5) = 0.
  const ToneCurve tc = toneCurve(toneMapper);
  const double t = 0.85;
  double a = tc.k[0] - t * tc.k[3], b = tc.k[1] - t * tc.k[4], c = tc.k[2] - t * tc.k[5];
  double xt = a == 0 ? -c / b : (-b + std::sqrt(b * b - 4 * a * c)) / (2 * a);

  std::vector<float> lum(size_t(width) * size_t(height));
  for (size_t i = 0; i < lum.size(); ++i) {
    Vec3f p{sanitizeHdr(reference[3 * i]), sanitizeHdr(reference[3 * i + 1]),
            sanitizeHdr(reference[3 * i + 2])};
    lum[i] = luminance(p);
    if (!std::isfinite(lum[i])) lum[i] = std::numeric_limits<float>::max();
  }
  float yMax = *std::max_element(lum.begin(), lum.end());
  if (!(yMax > 0)) return {0, 0, 1};
  auto median = [](std::vector<float>& v) {
    size_t mid = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(mid), v.end());
    double m = v[mid];
    if (v.size() % 2 == 0)
      m = 0.5 * (m + *std::max_element(v.begin(), v.begin() + std::ptrdiff_t(mid)));
    return m;
  };
  double yMedian = median(lum);
  if (!(yMedian > 0)) {  // mostly black: the median of what is lit (see flip.h)
    std::erase_if(lum, [](float v) { return !(v > 0); });
    yMedian = median(lum);
  }
  FlipExposures e;
  e.start = float(std::log2(xt / yMax));
  e.stop = float(std::log2(xt / yMedian));
  e.count = e.start == e.stop ? 1 : std::max(2, int(std::ceil(e.stop - e.start)));
  return e;
}

FlipResult flipHdr(std::span<const float> reference, std::span<const float> test, int width,
                   int height, const FlipHdrOptions& options) {
  checkInputs(reference, test, width, height, options.pixelsPerDegree);
  FlipExposures e;
  if (!options.startExposure || !options.stopExposure)
    e = flipExposureRange(reference, width, height, options.toneMapper);
  if (options.startExposure) e.start = *options.startExposure;
  if (options.stopExposure) e.stop = *options.stopExposure;
  if (!(e.start <= e.stop))
    throw std::logic_error("HDR-FLIP: start exposure " + std::to_string(e.start) +
                           " is after stop exposure " + std::to_string(e.stop));
  e.count = options.exposureCount > 0 ? options.exposureCount
            : e.start == e.stop       ? 1
                                      : std::max(2, int(std::ceil(e.stop - e.start)));

  const Filters filters(options.pixelsPerDegree);
  Workspace ws;
  const size_t n = size_t(width) * size_t(height);
  std::vector<float> ldrRef(3 * n), ldrTest(3 * n);
  auto expose = [&](std::span<const float> in, std::vector<float>& out, float exposure) {
    forRows(height, [&](int y) {
      for (size_t i = size_t(y) * size_t(width); i < size_t(y + 1) * size_t(width); ++i) {
        Rgb c =
            flipToneMap({in[3 * i], in[3 * i + 1], in[3 * i + 2]}, exposure, options.toneMapper);
        out[3 * i] = linearToSrgb(c.x), out[3 * i + 1] = linearToSrgb(c.y);
        out[3 * i + 2] = linearToSrgb(c.z);
      }
    });
  };

  FlipResult r;
  r.width = width, r.height = height;
  r.error.assign(n, 0.0f);
  r.exposures = e;
  const float step = (e.stop - e.start) / float(std::max(e.count - 1, 1));
  for (int k = 0; k < e.count; ++k) {
    const float exposure = e.start + float(k) * step;
    expose(reference, ldrRef, exposure);
    expose(test, ldrTest, exposure);
    ldrFlip(ldrRef, ldrTest, width, height, filters, ws, [&](size_t i, float color, float feature) {
      r.error[i] = std::max(r.error[i], combine(color, feature));
    });
  }
  r.stats = flipStatistics(r.error, width);
  return r;
}

double flipWeightedPercentile(std::span<const float> error, double fraction) {
  std::vector<float> sorted(error.begin(), error.end());
  tbb::parallel_sort(sorted.begin(), sorted.end());
  double total = 0;
  for (float e : sorted) total += e;
  double running = 0;
  for (float e : sorted) {
    running += e;
    if (running > fraction * total) return e;
  }
  return 0;
}

FlipStats flipStatistics(std::span<const float> error, int width) {
  FlipStats s;
  if (error.empty()) return s;
  std::vector<float> sorted(error.begin(), error.end());
  tbb::parallel_sort(sorted.begin(), sorted.end());
  double total = 0;
  for (float e : sorted) total += e;
  s.mean = total / double(sorted.size());
  s.min = sorted.front();
  s.max = sorted.back();
  const size_t rank95 = (sorted.size() * 95 + 99) / 100;  // ceil(0.95 n), at least 1
  s.percentile95 = sorted[std::max<size_t>(rank95, 1) - 1];
  size_t at = size_t(std::max_element(error.begin(), error.end()) - error.begin());
  s.maxX = width > 0 ? int(at % size_t(width)) : 0;
  s.maxY = width > 0 ? int(at / size_t(width)) : 0;
  // The three weighted percentiles in one pass over the sorted errors.
  std::array<double, 3> fractions{0.25, 0.5, 0.75}, values{0, 0, 0};
  size_t next = 0;
  double running = 0;
  for (float e : sorted) {
    running += e;
    while (next < 3 && running > fractions[next] * total) values[next++] = e;
    if (next == 3) break;
  }
  s.weightedQuartile1 = values[0];
  s.weightedMedian = values[1];
  s.weightedQuartile3 = values[2];
  return s;
}

// ---- magma -----------------------------------------------------------------------------------

namespace {

// matplotlib's "magma" (Nathaniel J. Smith, Stéfan van der Walt and Eric Firing; CC0), the 256
// entries of lib/matplotlib/_cm_listed.py.
constexpr float kMagma[256][3] = {
    {0.001462f, 0.000466f, 0.013866f}, {0.002258f, 0.001295f, 0.018331f},
    {0.003279f, 0.002305f, 0.023708f}, {0.004512f, 0.003490f, 0.029965f},
    {0.005950f, 0.004843f, 0.037130f}, {0.007588f, 0.006356f, 0.044973f},
    {0.009426f, 0.008022f, 0.052844f}, {0.011465f, 0.009828f, 0.060750f},
    {0.013708f, 0.011771f, 0.068667f}, {0.016156f, 0.013840f, 0.076603f},
    {0.018815f, 0.016026f, 0.084584f}, {0.021692f, 0.018320f, 0.092610f},
    {0.024792f, 0.020715f, 0.100676f}, {0.028123f, 0.023201f, 0.108787f},
    {0.031696f, 0.025765f, 0.116965f}, {0.035520f, 0.028397f, 0.125209f},
    {0.039608f, 0.031090f, 0.133515f}, {0.043830f, 0.033830f, 0.141886f},
    {0.048062f, 0.036607f, 0.150327f}, {0.052320f, 0.039407f, 0.158841f},
    {0.056615f, 0.042160f, 0.167446f}, {0.060949f, 0.044794f, 0.176129f},
    {0.065330f, 0.047318f, 0.184892f}, {0.069764f, 0.049726f, 0.193735f},
    {0.074257f, 0.052017f, 0.202660f}, {0.078815f, 0.054184f, 0.211667f},
    {0.083446f, 0.056225f, 0.220755f}, {0.088155f, 0.058133f, 0.229922f},
    {0.092949f, 0.059904f, 0.239164f}, {0.097833f, 0.061531f, 0.248477f},
    {0.102815f, 0.063010f, 0.257854f}, {0.107899f, 0.064335f, 0.267289f},
    {0.113094f, 0.065492f, 0.276784f}, {0.118405f, 0.066479f, 0.286321f},
    {0.123833f, 0.067295f, 0.295879f}, {0.129380f, 0.067935f, 0.305443f},
    {0.135053f, 0.068391f, 0.315000f}, {0.140858f, 0.068654f, 0.324538f},
    {0.146785f, 0.068738f, 0.334011f}, {0.152839f, 0.068637f, 0.343404f},
    {0.159018f, 0.068354f, 0.352688f}, {0.165308f, 0.067911f, 0.361816f},
    {0.171713f, 0.067305f, 0.370771f}, {0.178212f, 0.066576f, 0.379497f},
    {0.184801f, 0.065732f, 0.387973f}, {0.191460f, 0.064818f, 0.396152f},
    {0.198177f, 0.063862f, 0.404009f}, {0.204935f, 0.062907f, 0.411514f},
    {0.211718f, 0.061992f, 0.418647f}, {0.218512f, 0.061158f, 0.425392f},
    {0.225302f, 0.060445f, 0.431742f}, {0.232077f, 0.059889f, 0.437695f},
    {0.238826f, 0.059517f, 0.443256f}, {0.245543f, 0.059352f, 0.448436f},
    {0.252220f, 0.059415f, 0.453248f}, {0.258857f, 0.059706f, 0.457710f},
    {0.265447f, 0.060237f, 0.461840f}, {0.271994f, 0.060994f, 0.465660f},
    {0.278493f, 0.061978f, 0.469190f}, {0.284951f, 0.063168f, 0.472451f},
    {0.291366f, 0.064553f, 0.475462f}, {0.297740f, 0.066117f, 0.478243f},
    {0.304081f, 0.067835f, 0.480812f}, {0.310382f, 0.069702f, 0.483186f},
    {0.316654f, 0.071690f, 0.485380f}, {0.322899f, 0.073782f, 0.487408f},
    {0.329114f, 0.075972f, 0.489287f}, {0.335308f, 0.078236f, 0.491024f},
    {0.341482f, 0.080564f, 0.492631f}, {0.347636f, 0.082946f, 0.494121f},
    {0.353773f, 0.085373f, 0.495501f}, {0.359898f, 0.087831f, 0.496778f},
    {0.366012f, 0.090314f, 0.497960f}, {0.372116f, 0.092816f, 0.499053f},
    {0.378211f, 0.095332f, 0.500067f}, {0.384299f, 0.097855f, 0.501002f},
    {0.390384f, 0.100379f, 0.501864f}, {0.396467f, 0.102902f, 0.502658f},
    {0.402548f, 0.105420f, 0.503386f}, {0.408629f, 0.107930f, 0.504052f},
    {0.414709f, 0.110431f, 0.504662f}, {0.420791f, 0.112920f, 0.505215f},
    {0.426877f, 0.115395f, 0.505714f}, {0.432967f, 0.117855f, 0.506160f},
    {0.439062f, 0.120298f, 0.506555f}, {0.445163f, 0.122724f, 0.506901f},
    {0.451271f, 0.125132f, 0.507198f}, {0.457386f, 0.127522f, 0.507448f},
    {0.463508f, 0.129893f, 0.507652f}, {0.469640f, 0.132245f, 0.507809f},
    {0.475780f, 0.134577f, 0.507921f}, {0.481929f, 0.136891f, 0.507989f},
    {0.488088f, 0.139186f, 0.508011f}, {0.494258f, 0.141462f, 0.507988f},
    {0.500438f, 0.143719f, 0.507920f}, {0.506629f, 0.145958f, 0.507806f},
    {0.512831f, 0.148179f, 0.507648f}, {0.519045f, 0.150383f, 0.507443f},
    {0.525270f, 0.152569f, 0.507192f}, {0.531507f, 0.154739f, 0.506895f},
    {0.537755f, 0.156894f, 0.506551f}, {0.544015f, 0.159033f, 0.506159f},
    {0.550287f, 0.161158f, 0.505719f}, {0.556571f, 0.163269f, 0.505230f},
    {0.562866f, 0.165368f, 0.504692f}, {0.569172f, 0.167454f, 0.504105f},
    {0.575490f, 0.169530f, 0.503466f}, {0.581819f, 0.171596f, 0.502777f},
    {0.588158f, 0.173652f, 0.502035f}, {0.594508f, 0.175701f, 0.501241f},
    {0.600868f, 0.177743f, 0.500394f}, {0.607238f, 0.179779f, 0.499492f},
    {0.613617f, 0.181811f, 0.498536f}, {0.620005f, 0.183840f, 0.497524f},
    {0.626401f, 0.185867f, 0.496456f}, {0.632805f, 0.187893f, 0.495332f},
    {0.639216f, 0.189921f, 0.494150f}, {0.645633f, 0.191952f, 0.492910f},
    {0.652056f, 0.193986f, 0.491611f}, {0.658483f, 0.196027f, 0.490253f},
    {0.664915f, 0.198075f, 0.488836f}, {0.671349f, 0.200133f, 0.487358f},
    {0.677786f, 0.202203f, 0.485819f}, {0.684224f, 0.204286f, 0.484219f},
    {0.690661f, 0.206384f, 0.482558f}, {0.697098f, 0.208501f, 0.480835f},
    {0.703532f, 0.210638f, 0.479049f}, {0.709962f, 0.212797f, 0.477201f},
    {0.716387f, 0.214982f, 0.475290f}, {0.722805f, 0.217194f, 0.473316f},
    {0.729216f, 0.219437f, 0.471279f}, {0.735616f, 0.221713f, 0.469180f},
    {0.742004f, 0.224025f, 0.467018f}, {0.748378f, 0.226377f, 0.464794f},
    {0.754737f, 0.228772f, 0.462509f}, {0.761077f, 0.231214f, 0.460162f},
    {0.767398f, 0.233705f, 0.457755f}, {0.773695f, 0.236249f, 0.455289f},
    {0.779968f, 0.238851f, 0.452765f}, {0.786212f, 0.241514f, 0.450184f},
    {0.792427f, 0.244242f, 0.447543f}, {0.798608f, 0.247040f, 0.444848f},
    {0.804752f, 0.249911f, 0.442102f}, {0.810855f, 0.252861f, 0.439305f},
    {0.816914f, 0.255895f, 0.436461f}, {0.822926f, 0.259016f, 0.433573f},
    {0.828886f, 0.262229f, 0.430644f}, {0.834791f, 0.265540f, 0.427671f},
    {0.840636f, 0.268953f, 0.424666f}, {0.846416f, 0.272473f, 0.421631f},
    {0.852126f, 0.276106f, 0.418573f}, {0.857763f, 0.279857f, 0.415496f},
    {0.863320f, 0.283729f, 0.412403f}, {0.868793f, 0.287728f, 0.409303f},
    {0.874176f, 0.291859f, 0.406205f}, {0.879464f, 0.296125f, 0.403118f},
    {0.884651f, 0.300530f, 0.400047f}, {0.889731f, 0.305079f, 0.397002f},
    {0.894700f, 0.309773f, 0.393995f}, {0.899552f, 0.314616f, 0.391037f},
    {0.904281f, 0.319610f, 0.388137f}, {0.908884f, 0.324755f, 0.385308f},
    {0.913354f, 0.330052f, 0.382563f}, {0.917689f, 0.335500f, 0.379915f},
    {0.921884f, 0.341098f, 0.377376f}, {0.925937f, 0.346844f, 0.374959f},
    {0.929845f, 0.352734f, 0.372677f}, {0.933606f, 0.358764f, 0.370541f},
    {0.937221f, 0.364929f, 0.368567f}, {0.940687f, 0.371224f, 0.366762f},
    {0.944006f, 0.377643f, 0.365136f}, {0.947180f, 0.384178f, 0.363701f},
    {0.950210f, 0.390820f, 0.362468f}, {0.953099f, 0.397563f, 0.361438f},
    {0.955849f, 0.404400f, 0.360619f}, {0.958464f, 0.411324f, 0.360014f},
    {0.960949f, 0.418323f, 0.359630f}, {0.963310f, 0.425390f, 0.359469f},
    {0.965549f, 0.432519f, 0.359529f}, {0.967671f, 0.439703f, 0.359810f},
    {0.969680f, 0.446936f, 0.360311f}, {0.971582f, 0.454210f, 0.361030f},
    {0.973381f, 0.461520f, 0.361965f}, {0.975082f, 0.468861f, 0.363111f},
    {0.976690f, 0.476226f, 0.364466f}, {0.978210f, 0.483612f, 0.366025f},
    {0.979645f, 0.491014f, 0.367783f}, {0.981000f, 0.498428f, 0.369734f},
    {0.982279f, 0.505851f, 0.371874f}, {0.983485f, 0.513280f, 0.374198f},
    {0.984622f, 0.520713f, 0.376698f}, {0.985693f, 0.528148f, 0.379371f},
    {0.986700f, 0.535582f, 0.382210f}, {0.987646f, 0.543015f, 0.385210f},
    {0.988533f, 0.550446f, 0.388365f}, {0.989363f, 0.557873f, 0.391671f},
    {0.990138f, 0.565296f, 0.395122f}, {0.990871f, 0.572706f, 0.398714f},
    {0.991558f, 0.580107f, 0.402441f}, {0.992196f, 0.587502f, 0.406299f},
    {0.992785f, 0.594891f, 0.410283f}, {0.993326f, 0.602275f, 0.414390f},
    {0.993834f, 0.609644f, 0.418613f}, {0.994309f, 0.616999f, 0.422950f},
    {0.994738f, 0.624350f, 0.427397f}, {0.995122f, 0.631696f, 0.431951f},
    {0.995480f, 0.639027f, 0.436607f}, {0.995810f, 0.646344f, 0.441361f},
    {0.996096f, 0.653659f, 0.446213f}, {0.996341f, 0.660969f, 0.451160f},
    {0.996580f, 0.668256f, 0.456192f}, {0.996775f, 0.675541f, 0.461314f},
    {0.996925f, 0.682828f, 0.466526f}, {0.997077f, 0.690088f, 0.471811f},
    {0.997186f, 0.697349f, 0.477182f}, {0.997254f, 0.704611f, 0.482635f},
    {0.997325f, 0.711848f, 0.488154f}, {0.997351f, 0.719089f, 0.493755f},
    {0.997351f, 0.726324f, 0.499428f}, {0.997341f, 0.733545f, 0.505167f},
    {0.997285f, 0.740772f, 0.510983f}, {0.997228f, 0.747981f, 0.516859f},
    {0.997138f, 0.755190f, 0.522806f}, {0.997019f, 0.762398f, 0.528821f},
    {0.996898f, 0.769591f, 0.534892f}, {0.996727f, 0.776795f, 0.541039f},
    {0.996571f, 0.783977f, 0.547233f}, {0.996369f, 0.791167f, 0.553499f},
    {0.996162f, 0.798348f, 0.559820f}, {0.995932f, 0.805527f, 0.566202f},
    {0.995680f, 0.812706f, 0.572645f}, {0.995424f, 0.819875f, 0.579140f},
    {0.995131f, 0.827052f, 0.585701f}, {0.994851f, 0.834213f, 0.592307f},
    {0.994524f, 0.841387f, 0.598983f}, {0.994222f, 0.848540f, 0.605696f},
    {0.993866f, 0.855711f, 0.612482f}, {0.993545f, 0.862859f, 0.619299f},
    {0.993170f, 0.870024f, 0.626189f}, {0.992831f, 0.877168f, 0.633109f},
    {0.992440f, 0.884330f, 0.640099f}, {0.992089f, 0.891470f, 0.647116f},
    {0.991688f, 0.898627f, 0.654202f}, {0.991332f, 0.905763f, 0.661309f},
    {0.990930f, 0.912915f, 0.668481f}, {0.990570f, 0.920049f, 0.675675f},
    {0.990175f, 0.927196f, 0.682926f}, {0.989815f, 0.934329f, 0.690198f},
    {0.989434f, 0.941470f, 0.697519f}, {0.989077f, 0.948604f, 0.704863f},
    {0.988717f, 0.955742f, 0.712242f}, {0.988367f, 0.962878f, 0.719649f},
    {0.988033f, 0.970012f, 0.727077f}, {0.987691f, 0.977154f, 0.734536f},
    {0.987387f, 0.984288f, 0.742002f}, {0.987053f, 0.991438f, 0.749504f},
};

}  // namespace

Rgb flipMagma(float t) {
  if (std::isnan(t)) t = 0;
  int i = int(std::lround(std::clamp(t, 0.0f, 1.0f) * 255.0f));
  return {kMagma[i][0], kMagma[i][1], kMagma[i][2]};
}

std::vector<float> flipHeatMap(std::span<const float> error) {
  std::vector<float> rgb(3 * error.size());
  for (size_t i = 0; i < error.size(); ++i) {
    Rgb c = flipMagma(error[i]);
    rgb[3 * i] = c.x, rgb[3 * i + 1] = c.y, rgb[3 * i + 2] = c.z;
  }
  return rgb;
}

}  // namespace glint
