// glint — an image in memory as a MIP pyramid, with nearest, bilinear and filtered (trilinear,
// anisotropic) lookups driven by a pixel's footprint in texture space.
//
// This is how glint serves the images it decodes whole anyway (glTF's PNG and JPEG, small image
// files): 8-bit images stay 8-bit (their colour channels decoded from sRGB through a table on
// lookup), others are kept as linear floats. pbrt-v4's MIPMap and Cycles' image manager work
// the same way; OpenImageIO's TextureSystem (image/oiio/textures.cpp) serves only the files
// that should stay on disk: tiled, MIP-mapped textures (.tx) and very large images.
//
// Conventions, as OpenImageIO's (so both serve the same image): texel (x, y) covers
// [x, x + 1) / width by [y, y + 1) / height in (s, t), t = 0 is the top row, and bilinear
// weights are taken between texel centres.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <vector>

#include "materials/texture.h"

namespace glint {

// Nearest: the closest texel of the full image. Linear: bilinear in the full image. Mipmap:
// filtered over the footprint: trilinear between the two MIP levels whose texels match the
// footprint's minor axis, with probes along its major axis when it is elongated (weighted
// towards the middle), level choice and weights as OpenImageIO's TextureSystem makes them.
enum class TextureFilter { Nearest, Linear, Mipmap };

// How the stored colour channels are encoded; alpha is always linear.
enum class ColorEncoding { Linear, Srgb };

class MipMap {
 public:
  enum class Texel : uint8_t { Byte, Float };
  // The longest footprint, in minor axes, that Mipmap lookups follow with probes; beyond it the
  // minor axis is widened (blurring along it) so a lookup never takes more probes than this.
  static constexpr int kMaxAnisotropy = 8;

  MipMap() = default;
  // 8-bit samples as stored, `channels` (1..4) per pixel, rows top to bottom; with Srgb the
  // colour channels (RGB or grey, never alpha) are sRGB-encoded. The MIP levels are made here
  // by averaging in linear space and stored 8-bit in the same encoding.
  static MipMap fromBytes(int width, int height, int channels, std::vector<uint8_t> pixels,
                          ColorEncoding enc);
  // Float samples (any range); with Srgb the colour channels are linearised once, here.
  static MipMap fromFloats(int width, int height, int channels, std::vector<float> pixels,
                           ColorEncoding enc);
  // What fromBytes / fromFloats would keep in memory for such an image, MIP levels included.
  static size_t residentBytes(int width, int height, int channels, Texel texel);

  // Linear RGBA at c.st (outside [0, 1] the wrap modes apply) over the footprint c.dstdx,
  // c.dstdy (Mipmap only). Grey images give (g, g, g, a); a missing alpha is 1; colour is not
  // premultiplied. Non-finite coordinates give (0, 0, 0, 1); non-finite footprints a point
  // sample. Thread-safe (reads only).
  Vec4f lookup(const TexCoord2& c, TextureWrap wrapS, TextureWrap wrapT,
               TextureFilter filter) const;

  int width() const { return levels_.empty() ? 0 : levels_[0].width; }
  int height() const { return levels_.empty() ? 0 : levels_[0].height; }
  int channels() const { return channels_; }
  int levelCount() const { return int(levels_.size()); }
  Texel texel() const { return texel_; }
  bool empty() const { return levels_.empty(); }
  size_t bytes() const { return texelBytes_; }

  // One level, rows top to bottom; `first` indexes the level's first sample.
  struct Level {
    int width = 0, height = 0;
    size_t first = 0;
  };

 private:
  template <class T, int N>
  Vec4f lookupAs(const TexCoord2& c, TextureWrap wrapS, TextureWrap wrapT,
                 TextureFilter filter) const;
  template <class T, int N>
  void bilinear(int level, float s, float t, TextureWrap wrapS, TextureWrap wrapT, float weight,
                float out[N]) const;
  template <class T, int N>
  void trilinear(float minor, float s, float t, TextureWrap wrapS, TextureWrap wrapT, float weight,
                 float out[N]) const;
  template <class T, int N>
  void fetch(const Level& level, int x, int y, float w, float out[N]) const;
  template <class T>
  void buildLevels(T* out, std::vector<float> level0);
  // The block holding every level (level 0 first), `bytes` long, on 2 MiB pages where the
  // system grants them (lookups at random points, as bounce rays make, then miss the TLB far
  // less often).
  void* allocate(size_t bytes);

  std::vector<Level> levels_;
  struct Free {
    void operator()(void* p) const;
  };
  std::unique_ptr<void, Free> texels_;
  size_t texelBytes_ = 0;
  const uint8_t* byteTexels_ = nullptr;
  const float* floatTexels_ = nullptr;
  int channels_ = 0;
  Texel texel_ = Texel::Float;
  // Texel::Byte: each channel's decoding table (sRGB or linear; 256 entries).
  const float* decode_[4] = {nullptr, nullptr, nullptr, nullptr};
};

}  // namespace glint
