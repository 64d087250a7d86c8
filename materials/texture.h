// glint — textures: colour as a function of a surface point.
//
// Image textures here are decoded into linear floats once and filtered bilinearly; issue 5
// moves them to OpenImageIO's TextureSystem (MIP-mapping) behind the same interface.
#pragma once

#include <memory>
#include <vector>

#include "geometry/interaction.h"

namespace glint {

class Texture {
 public:
  virtual ~Texture() = default;
  // Colour (linear RGB) and alpha at the surface point.
  virtual Vec4f evaluate(const SurfaceInteraction& si) const = 0;
};

enum class TextureWrap { Repeat, Clamp, Mirror };

struct ImageData {
  int width = 0, height = 0;
  std::vector<Vec4f> texels;  // linear RGBA, rows top to bottom
};

// Converts stored pixels (`channels` floats each in [0,1]) into linear RGBA. `srgb` decodes
// the colour channels with the sRGB transfer function (alpha stays linear).
ImageData makeImageData(int width, int height, int channels, const std::vector<float>& pixels,
                        bool srgb);

// An image looked up by the primitive's UVs (glTF convention: v = 0 is the top row).
class ImageTexture final : public Texture {
 public:
  ImageTexture(std::shared_ptr<const ImageData> image, TextureWrap wrapU, TextureWrap wrapV,
               bool nearest);
  Vec4f evaluate(const SurfaceInteraction& si) const override { return lookup(si.uv); }
  Vec4f lookup(Vec2f uv) const;

 private:
  Vec4f texel(int x, int y) const;
  std::shared_ptr<const ImageData> image_;
  TextureWrap wrapU_, wrapV_;
  bool nearest_;
};

// sRGB transfer function (IEC 61966-2-1), encoded value -> linear.
float srgbToLinear(float v);

}  // namespace glint
