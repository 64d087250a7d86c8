// glint — an image in memory as a MIP pyramid (mipmap.h).
#include "materials/mipmap.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <new>
#include <stdexcept>
#include <string>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace glint {

namespace {

// The 256 values of an 8-bit channel: sRGB-decoded or plain.
const std::array<float, 256>& srgbTable() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int v = 0; v < 256; ++v) t[size_t(v)] = srgbToLinear(float(v) / 255.0f);
    return t;
  }();
  return table;
}
const std::array<float, 256>& linearTable() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int v = 0; v < 256; ++v) t[size_t(v)] = float(v) / 255.0f;
    return t;
  }();
  return table;
}

// Encodes linear values back to 8 bits: the byte whose decoded value (through an increasing
// 256-entry table) is nearest. A 4,096-bucket index gives the first candidate; the codes are
// at most a few buckets apart even where sRGB packs them densest (near black), so a short walk
// finishes it.
class Encoder {
 public:
  explicit Encoder(const std::array<float, 256>& table) : table_(table) {
    for (int b = 0; b < kBuckets; ++b) {
      const float v = float(b) / kBuckets;
      const auto above = std::upper_bound(table.begin(), table.end(), v);
      start_[size_t(b)] = uint8_t(above - table.begin() - 1);
    }
  }
  uint8_t operator()(float v) const {
    if (!(v > table_[0])) return 0;  // also NaN
    if (v >= table_[255]) return 255;
    size_t i = start_[size_t(v * kBuckets)];  // table_[i] <= v
    while (i < 255 && table_[i + 1] <= v) ++i;
    return uint8_t(v - table_[i] <= table_[i + 1] - v ? i : i + 1);
  }

 private:
  static constexpr int kBuckets = 4096;
  const std::array<float, 256>& table_;
  std::array<uint8_t, kBuckets> start_{};
};

const Encoder& srgbEncoder() {
  static const Encoder e(srgbTable());
  return e;
}
const Encoder& linearEncoder() {
  static const Encoder e(linearTable());
  return e;
}

// Which channels hold colour (RGB, or the grey channel), as opposed to alpha.
bool isColourChannel(int channels, int c) { return channels >= 3 ? c < 3 : c == 0; }

// The texel index i of a row or column of n texels under wrap mode w; -1 for Black outside.
// Indices come from reduced coordinates (reduce below), so Repeat is at most one period off.
inline int wrapIndex(int i, int n, TextureWrap w) {
  switch (w) {
    case TextureWrap::Repeat:
      if (i < 0) return i + n;
      return i >= n ? i - n : i;
    case TextureWrap::Clamp:
      return std::clamp(i, 0, n - 1);
    case TextureWrap::Mirror: {
      if (i < 0) i = -i - 1;
      const int period = i / n;
      i -= period * n;
      return period & 1 ? n - 1 - i : i;
    }
    case TextureWrap::Black:
    default:
      return i < 0 || i >= n ? -1 : i;
  }
}

// A coordinate brought near [0, 1] without changing what the wrap mode makes of it, so that
// scaling it to texels cannot overflow an int.
inline float reduce(float s, TextureWrap w) {
  switch (w) {
    case TextureWrap::Repeat:
      return s - std::floor(s);
    case TextureWrap::Mirror:
      return s - 2.0f * std::floor(0.5f * s);
    default:  // Clamp and Black: everything beyond one image width away reads the same
      return std::clamp(s, -1.0f, 2.0f);
  }
}

inline float finiteOrZero(float v) { return std::isfinite(v) ? v : 0.0f; }

// The next MIP level of a w x h image of linear floats (each side halved, rounded down, at
// least 1): every new texel is the area-weighted mean of the texels it covers. For even sides
// that is the 2x2 box; for odd ones it still keeps the image's mean (a resampling at the new
// texel centres, as OpenImageIO's "automip" does, skips texels).
std::vector<float> downsample(const std::vector<float>& in, int inWidth, int inHeight, int nch,
                              int* outWidth, int* outHeight) {
  const int ow = std::max(1, inWidth / 2), oh = std::max(1, inHeight / 2);
  *outWidth = ow, *outHeight = oh;
  const size_t n = size_t(nch), inW = size_t(inWidth), outW = size_t(ow);
  std::vector<float> out(size_t(oh) * outW * n);
  if (inWidth % 2 == 0 && inHeight % 2 == 0) {
    for (size_t y = 0; y < size_t(oh); ++y) {
      const float* row0 = &in[2 * y * inW * n];
      const float* row1 = row0 + inW * n;
      float* dst = &out[y * outW * n];
      for (size_t x = 0; x < outW; ++x)
        for (size_t c = 0; c < n; ++c) {
          const size_t i = 2 * x * n + c;
          dst[x * n + c] = 0.25f * ((row0[i] + row0[i + n]) + (row1[i] + row1[i + n]));
        }
    }
    return out;
  }
  // For each coarse texel along one axis of m -> k texels: the first fine texel it covers and
  // the weights of the fine texels from there on (they sum to 1).
  struct Taps {
    size_t first = 0;
    std::vector<float> w;
  };
  auto taps = [](int m, int k) {
    std::vector<Taps> t(static_cast<size_t>(k));
    const double ratio = double(m) / double(k);
    for (int i = 0; i < k; ++i) {
      const double a = i * ratio, b = (i + 1) * ratio;
      Taps& tap = t[size_t(i)];
      tap.first = size_t(a);
      for (int j = int(a); j < m && j < b; ++j)
        tap.w.push_back(float((std::min(b, j + 1.0) - std::max(a, double(j))) / ratio));
    }
    return t;
  };
  const std::vector<Taps> tx = taps(inWidth, ow), ty = taps(inHeight, oh);
  // Along rows first (inHeight x ow texels), then along columns.
  std::vector<float> rows(size_t(inHeight) * outW * n, 0.0f);
  for (size_t y = 0; y < size_t(inHeight); ++y)
    for (size_t x = 0; x < outW; ++x) {
      float* dst = &rows[(y * outW + x) * n];
      for (size_t k = 0; k < tx[x].w.size(); ++k) {
        const float* src = &in[(y * inW + tx[x].first + k) * n];
        for (size_t c = 0; c < n; ++c) dst[c] += tx[x].w[k] * src[c];
      }
    }
  for (size_t y = 0; y < size_t(oh); ++y) {
    float* dst = &out[y * outW * n];
    for (size_t k = 0; k < ty[y].w.size(); ++k) {
      const float* src = &rows[(ty[y].first + k) * outW * n];
      for (size_t i = 0; i < outW * n; ++i) dst[i] += ty[y].w[k] * src[i];
    }
  }
  return out;
}

void checkSize(int width, int height, int channels, size_t samples) {
  if (width <= 0 || height <= 0 || channels < 1 || channels > 4 ||
      samples != size_t(width) * size_t(height) * size_t(channels))
    throw std::logic_error("MipMap: " + std::to_string(samples) + " samples do not make a " +
                           std::to_string(width) + "x" + std::to_string(height) + " image of " +
                           std::to_string(channels) + " channels");
}

}  // namespace

size_t MipMap::residentBytes(int width, int height, int channels, Texel texel) {
  size_t texels = 0;
  for (int w = width, h = height;; w = std::max(1, w / 2), h = std::max(1, h / 2)) {
    texels += size_t(w) * size_t(h);
    if (w == 1 && h == 1) break;
  }
  return texels * size_t(channels) * (texel == Texel::Byte ? 1 : sizeof(float));
}

MipMap MipMap::fromBytes(int width, int height, int channels, std::vector<uint8_t> pixels,
                         ColorEncoding enc) {
  checkSize(width, height, channels, pixels.size());
  MipMap m;
  m.channels_ = channels;
  m.texel_ = Texel::Byte;
  for (int c = 0; c < channels; ++c)
    m.decode_[c] =
        (enc == ColorEncoding::Srgb && isColourChannel(channels, c) ? srgbTable() : linearTable())
            .data();
  m.levels_.push_back({width, height, 0});
  auto* out = static_cast<uint8_t*>(m.allocate(residentBytes(width, height, channels, m.texel_)));
  std::memcpy(out, pixels.data(), pixels.size());
  m.byteTexels_ = out;
  std::vector<float> level0(pixels.size());
  const size_t n = size_t(channels);
  for (size_t i = 0; i < pixels.size(); i += n)
    for (size_t c = 0; c < n; ++c) level0[i + c] = m.decode_[c][pixels[i + c]];
  pixels = {};
  m.buildLevels(out, std::move(level0));
  return m;
}

MipMap MipMap::fromFloats(int width, int height, int channels, std::vector<float> pixels,
                          ColorEncoding enc) {
  checkSize(width, height, channels, pixels.size());
  MipMap m;
  m.channels_ = channels;
  m.texel_ = Texel::Float;
  if (enc == ColorEncoding::Srgb)
    for (size_t i = 0; i < pixels.size(); ++i)
      if (isColourChannel(channels, int(i % size_t(channels)))) pixels[i] = srgbToLinear(pixels[i]);
  m.levels_.push_back({width, height, 0});
  auto* out = static_cast<float*>(m.allocate(residentBytes(width, height, channels, m.texel_)));
  std::memcpy(out, pixels.data(), pixels.size() * sizeof(float));
  m.floatTexels_ = out;
  m.buildLevels(out, std::move(pixels));
  return m;
}

// Writes the levels below level 0 (already at `out`) after it, each made from the previous one
// in linear float (`current`, level 0's linear values), so 8-bit levels are rounded once each,
// not once per level above them.
template <class T>
void MipMap::buildLevels(T* out, std::vector<float> current) {
  const size_t n = size_t(channels_);
  int w = levels_[0].width, h = levels_[0].height;
  size_t at = current.size();
  const Encoder* encoders[4] = {};
  if constexpr (std::is_same_v<T, uint8_t>)
    for (size_t c = 0; c < n; ++c)
      encoders[c] = decode_[c] == srgbTable().data() ? &srgbEncoder() : &linearEncoder();
  while (w > 1 || h > 1) {
    int nw = 0, nh = 0;
    std::vector<float> next = downsample(current, w, h, channels_, &nw, &nh);
    levels_.push_back({nw, nh, at});
    if constexpr (std::is_same_v<T, uint8_t>) {
      for (size_t i = 0; i < next.size(); i += n)
        for (size_t c = 0; c < n; ++c) out[at + i + c] = (*encoders[c])(next[i + c]);
    } else {
      std::memcpy(out + at, next.data(), next.size() * sizeof(float));
    }
    at += next.size();
    current = std::move(next);
    w = nw, h = nh;
  }
  assert(at * sizeof(T) == texelBytes_);
}

void MipMap::Free::operator()(void* p) const { std::free(p); }

void* MipMap::allocate(size_t bytes) {
  texelBytes_ = bytes;
  constexpr size_t kHugePage = size_t(2) << 20;
  void* block = nullptr;
  if (bytes >= kHugePage) {
    const size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    block = std::aligned_alloc(kHugePage, rounded);
#ifdef MADV_HUGEPAGE
    if (block) madvise(block, rounded, MADV_HUGEPAGE);  // a hint: no harm when refused
#endif
  }
  if (!block) block = std::malloc(std::max<size_t>(bytes, 1));
  if (!block) throw std::bad_alloc();
  texels_.reset(block);
  return block;
}

// Adds w × texel (x, y) of `level` (already wrapped; -1 is black) to out.
template <class T, int N>
inline void MipMap::fetch(const Level& level, int x, int y, float w, float out[N]) const {
  if (x < 0 || y < 0) return;
  const size_t i = level.first + (size_t(y) * size_t(level.width) + size_t(x)) * N;
  if constexpr (std::is_same_v<T, uint8_t>) {
    const uint8_t* p = byteTexels_ + i;
    for (int c = 0; c < N; ++c) out[c] += w * decode_[c][p[c]];
  } else {
    const float* p = floatTexels_ + i;
    for (int c = 0; c < N; ++c) out[c] += w * p[c];
  }
}

// Adds weight × the bilinear lookup of `level` at (s, t) to out.
template <class T, int N>
inline void MipMap::bilinear(int level, float s, float t, TextureWrap wrapS, TextureWrap wrapT,
                             float weight, float out[N]) const {
  const Level& l = levels_[size_t(level)];
  const float x = reduce(s, wrapS) * float(l.width) - 0.5f;
  const float y = reduce(t, wrapT) * float(l.height) - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float ax = x - fx, ay = y - fy;
  const int x0 = int(fx), y0 = int(fy);
  const int xa = wrapIndex(x0, l.width, wrapS), xb = wrapIndex(x0 + 1, l.width, wrapS);
  const int ya = wrapIndex(y0, l.height, wrapT), yb = wrapIndex(y0 + 1, l.height, wrapT);
  const float top = weight * (1 - ay), bottom = weight * ay;
  fetch<T, N>(l, xa, ya, top * (1 - ax), out);
  fetch<T, N>(l, xb, ya, top * ax, out);
  fetch<T, N>(l, xa, yb, bottom * (1 - ax), out);
  fetch<T, N>(l, xb, yb, bottom * ax, out);
}

// Adds weight × the lookup for a footprint `minor` texels of level 0 across, blended between
// the two levels around it, to out. As OpenImageIO chooses them (so images stay as they were
// when it served every texture): the finest level where the footprint spans at most 1-2
// texels, and the next one up, blended linearly in the footprint's width (at level l0 it spans
// minor / 2^l0 in [1, 2): weight minor / 2^l0 - 1 on level l0 + 1).
template <class T, int N>
inline void MipMap::trilinear(float minor, float s, float t, TextureWrap wrapS, TextureWrap wrapT,
                              float weight, float out[N]) const {
  const int last = int(levels_.size()) - 1;
  if (!(minor > 1)) return bilinear<T, N>(0, s, t, wrapS, wrapT, weight, out);  // also NaN
  int l0 = 0;
  const float m = std::frexp(minor, &l0);  // minor = m 2^l0, m in [0.5, 1)
  l0 -= 1;                                 // minor = 2m 2^l0, 2m in [1, 2)
  if (l0 >= last) return bilinear<T, N>(last, s, t, wrapS, wrapT, weight, out);
  const float f = 2 * m - 1;
  bilinear<T, N>(l0, s, t, wrapS, wrapT, weight * (1 - f), out);
  if (f > 0) bilinear<T, N>(l0 + 1, s, t, wrapS, wrapT, weight * f, out);
}

namespace {
// Each probe's weight along the major axis, for n probes: exp(-2 x²) at x = (i + 1/2) / n - 1/2,
// normalised (as OpenImageIO weighs its anisotropic samples: the middle counts most).
struct ProbeWeights {
  float w[MipMap::kMaxAnisotropy + 1][MipMap::kMaxAnisotropy] = {};
  ProbeWeights() {
    for (int n = 1; n <= MipMap::kMaxAnisotropy; ++n) {
      float sum = 0;
      for (int i = 0; i < n; ++i) {
        const float x = (float(i) + 0.5f) / float(n) - 0.5f;
        sum += w[n][i] = std::exp(-2 * x * x);
      }
      for (int i = 0; i < n; ++i) w[n][i] /= sum;
    }
  }
};
const ProbeWeights kProbeWeights;
}  // namespace

template <class T, int N>
Vec4f MipMap::lookupAs(const TexCoord2& c, TextureWrap wrapS, TextureWrap wrapT,
                       TextureFilter filter) const {
  float v[N] = {};
  const float s = c.st.x, t = c.st.y;
  switch (filter) {
    case TextureFilter::Nearest: {
      const Level& l = levels_[0];
      const int x = wrapIndex(int(std::floor(reduce(s, wrapS) * float(l.width))), l.width, wrapS);
      const int y = wrapIndex(int(std::floor(reduce(t, wrapT) * float(l.height))), l.height, wrapT);
      fetch<T, N>(l, x, y, 1.0f, v);
      break;
    }
    case TextureFilter::Linear:
      bilinear<T, N>(0, s, t, wrapS, wrapT, 1.0f, v);
      break;
    case TextureFilter::Mipmap: {
      // The footprint's two axes in texels of level 0; the longer is the major axis, and the
      // minor axis is the parallelogram's height across it (its area over the major length).
      const float w = float(levels_[0].width), h = float(levels_[0].height);
      const Vec2f a{finiteOrZero(c.dstdx.x), finiteOrZero(c.dstdx.y)};
      const Vec2f b{finiteOrZero(c.dstdy.x), finiteOrZero(c.dstdy.y)};
      const float ax = a.x * w, ay = a.y * h, bx = b.x * w, by = b.y * h;
      const float la2 = ax * ax + ay * ay, lb2 = bx * bx + by * by;
      const Vec2f major = la2 >= lb2 ? a : b;
      const float majorLength = std::sqrt(std::max(la2, lb2));
      float minorLength = majorLength > 0 ? std::abs(ax * by - ay * bx) / majorLength : 0.0f;
      minorLength = std::max(minorLength, majorLength * (1.0f / kMaxAnisotropy));
      if (!(minorLength > 0)) {  // a point sample (also for overflowed footprints)
        bilinear<T, N>(0, s, t, wrapS, wrapT, 1.0f, v);
        break;
      }
      const int probes =
          std::clamp(int(std::ceil(majorLength / minorLength - 1e-3f)), 1, kMaxAnisotropy);
      if (probes == 1) {
        trilinear<T, N>(minorLength, s, t, wrapS, wrapT, 1.0f, v);
        break;
      }
      // Probes spread evenly along the major axis, one minor axis apart.
      const float step = 1.0f / float(probes);
      for (int i = 0; i < probes; ++i) {
        const float o = (float(i) + 0.5f) * step - 0.5f;
        trilinear<T, N>(minorLength, s + o * major.x, t + o * major.y, wrapS, wrapT,
                        kProbeWeights.w[probes][i], v);
      }
      break;
    }
  }
  if constexpr (N == 1) return {v[0], v[0], v[0], 1};
  if constexpr (N == 2) return {v[0], v[0], v[0], v[1]};
  if constexpr (N == 3) return {v[0], v[1], v[2], 1};
  if constexpr (N == 4) return {v[0], v[1], v[2], v[3]};
}

Vec4f MipMap::lookup(const TexCoord2& c, TextureWrap wrapS, TextureWrap wrapT,
                     TextureFilter filter) const {
  assert(!levels_.empty());
  if (!std::isfinite(c.st.x) || !std::isfinite(c.st.y)) return {0, 0, 0, 1};
  const bool bytes = texel_ == Texel::Byte;
  switch (channels_) {
    case 1:
      return bytes ? lookupAs<uint8_t, 1>(c, wrapS, wrapT, filter)
                   : lookupAs<float, 1>(c, wrapS, wrapT, filter);
    case 2:
      return bytes ? lookupAs<uint8_t, 2>(c, wrapS, wrapT, filter)
                   : lookupAs<float, 2>(c, wrapS, wrapT, filter);
    case 3:
      return bytes ? lookupAs<uint8_t, 3>(c, wrapS, wrapT, filter)
                   : lookupAs<float, 3>(c, wrapS, wrapT, filter);
    default:
      return bytes ? lookupAs<uint8_t, 4>(c, wrapS, wrapT, filter)
                   : lookupAs<float, 4>(c, wrapS, wrapT, filter);
  }
}

}  // namespace glint
