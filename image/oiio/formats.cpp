// glint — the OpenImageIO plugin's image half: reading any format OpenImageIO reads, writing
// PNG, JPEG and TIFF, and idiff's comparison; and the plugin's entry point.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstdlib>

#include "image/oiio/plugin.h"
#include "image/oiio/textures.h"

namespace glint::oiio {

namespace {

// ---- metadata --------------------------------------------------------------------------------

void addMetadata(OIIO::ImageSpec& spec, const ImageMetadata& meta) {
  spec.attribute("glint:scene", meta.scene);
  spec.attribute("glint:spp", meta.spp);
  spec.attribute("glint:seed", std::to_string(meta.seed));  // 64-bit: as in EXR files
  double seconds = meta.renderSeconds;
  spec.attribute("glint:render_seconds", OIIO::TypeDesc::DOUBLE, &seconds);
  spec.attribute("glint:accel", meta.accel);
  spec.attribute("glint:integrator", meta.integrator);
  double time = meta.time;
  spec.attribute("glint:time", OIIO::TypeDesc::DOUBLE, &time);
  if (!meta.stop.empty()) {
    spec.attribute("glint:stop", meta.stop);
    double error = meta.error;
    spec.attribute("glint:error", OIIO::TypeDesc::DOUBLE, &error);
  }
}

// glint's attributes of an image (what addMetadata wrote); absent ones keep their defaults.
ImageMetadata metadataOf(const OIIO::ImageSpec& spec) {
  ImageMetadata meta;
  meta.scene = spec.get_string_attribute("glint:scene");
  meta.spp = spec.get_int_attribute("glint:spp");
  meta.seed = std::strtoull(spec.get_string_attribute("glint:seed", "0").c_str(), nullptr, 10);
  meta.renderSeconds = spec.get_float_attribute("glint:render_seconds");
  meta.accel = spec.get_string_attribute("glint:accel");
  meta.integrator = spec.get_string_attribute("glint:integrator");
  if (const OIIO::ParamValue* t = spec.find_attribute("glint:time", OIIO::TypeDesc::DOUBLE))
    meta.time = t->get<double>();
  meta.stop = spec.get_string_attribute("glint:stop");
  if (const OIIO::ParamValue* e = spec.find_attribute("glint:error", OIIO::TypeDesc::DOUBLE))
    meta.error = e->get<double>();
  return meta;
}

PixelType pixelTypeOf(OIIO::TypeDesc t) {
  if (t == OIIO::TypeDesc::HALF) return PixelType::Half;
  if (t == OIIO::TypeDesc::UINT8) return PixelType::UInt8;
  if (t == OIIO::TypeDesc::UINT16) return PixelType::UInt16;
  return PixelType::Float;
}

OIIO::TypeDesc typeDescOf(PixelType t) {
  switch (t) {
    case PixelType::UInt8:
      return OIIO::TypeDesc::UINT8;
    case PixelType::UInt16:
      return OIIO::TypeDesc::UINT16;
    case PixelType::Half:
      return OIIO::TypeDesc::HALF;
    case PixelType::Float:
      break;
  }
  return OIIO::TypeDesc::FLOAT;
}

// The channels of a width × height × channels buffer as an ImageBuf at origin 0,0.
OIIO::ImageBuf bufferOf(const std::vector<float>& px, int width, int height, int channels) {
  OIIO::ImageBuf out(OIIO::ImageSpec(width, height, channels, OIIO::TypeDesc::FLOAT));
  out.set_pixels(out.roi(), OIIO::TypeDesc::FLOAT, px.data());
  return out;
}

class OiioPlugin final : public Plugin {
 public:
  bool readImage(const std::string& path, bool pixels, Image* image, std::string* why,
                 bool* afterHeader) const override {
    *afterHeader = false;
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
      *why = OIIO::geterror();
      return false;
    }
    const OIIO::ImageSpec spec = in->spec();
    image->format = in->format_name();
    image->width = spec.width;
    image->depth = std::max(spec.depth, 1);
    image->height = spec.height * image->depth;
    image->channels = spec.nchannels;
    image->names = spec.channelnames;
    image->x = spec.x, image->y = spec.y;
    image->fullX = spec.full_x, image->fullY = spec.full_y;
    image->fullWidth = spec.full_width, image->fullHeight = spec.full_height;
    image->floatingPoint = spec.format.is_floating_point();  // as stored, not as read
    image->type = pixelTypeOf(spec.format);
    for (const OIIO::TypeDesc& t : spec.channelformats)
      if (t == OIIO::TypeDesc::HALF) image->type = PixelType::Half;
    image->meta = metadataOf(spec);
    image->hasMeta = spec.find_attribute("glint:scene") != nullptr;
    image->hasSeed = spec.find_attribute("glint:seed") != nullptr;
    image->hasTime = spec.find_attribute("glint:time", OIIO::TypeDesc::DOUBLE) != nullptr;
    for (const OIIO::ParamValue& p : spec.extra_attribs)
      if (p.name().string().rfind("glint:", 0) == 0)
        image->glintAttributes.emplace_back(p.name().string(), spec.metadata_val(p));
    image->checksum = spec.get_string_attribute("glint:checksum");
    if (!pixels) return true;

    *afterHeader = true;
    image->pixels.resize(image->pixelCount() * size_t(image->channels));
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image->pixels.data())) {
      *why = in->geterror();
      return false;
    }
    return true;
  }

  bool writeImage(const std::string& file, const std::string& formatPath, const Image& image,
                  std::string* why) const override {
    OIIO::ImageSpec spec(image.width, image.height, image.channels, typeDescOf(image.type));
    if (!image.names.empty()) {
      spec.channelnames = image.names;
      spec.alpha_channel = image.channel("A");
      spec.z_channel = image.channel("Z");
    }
    spec.attribute("Software", "glint");
    if (image.hasMeta) addMetadata(spec, image.meta);
    auto out = OIIO::ImageOutput::create(formatPath);
    if (!out) {
      *why = OIIO::geterror();
      return false;
    }
    if (!out->open(file, spec)) {
      *why = out->geterror();
      return false;
    }
    if (!out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data())) {
      *why = out->geterror();
      out->close();
      return false;
    }
    if (!out->close()) {
      *why = out->geterror();
      return false;
    }
    return true;
  }

  CompareStats compare(const std::vector<float>& a, const std::vector<float>& b, int width,
                       int height, int channels, float failThreshold,
                       float warnThreshold) const override {
    const OIIO::ImageBuf A = bufferOf(a, width, height, channels);
    const OIIO::ImageBuf B = bufferOf(b, width, height, channels);
    namespace IBA = OIIO::ImageBufAlgo;
    CompareStats r;
    IBA::CompareResults cr = IBA::compare(A, B, failThreshold, warnThreshold);
    // cr.error is also set when pixels fail; only a recorded message is a real error.
    if (std::string why = OIIO::geterror(); cr.error && !why.empty()) {
      r.error = why;
      return r;
    }
    r.meanError = cr.meanerror;
    r.rmsError = cr.rms_error;
    r.maxError = cr.maxerror;
    r.maxX = cr.maxx, r.maxY = cr.maxy, r.maxChannel = cr.maxc;
    r.failPixels = cr.nfail, r.warnPixels = cr.nwarn;
    // Relative MSE (as in Rousselle et al. / Mitsuba's tests): (a−b)² / (b² + 0.01), averaged.
    OIIO::ImageBuf diff = IBA::sub(A, B);
    OIIO::ImageBuf relative = IBA::div(IBA::mul(diff, diff), IBA::add(IBA::mul(B, B), 0.01f));
    IBA::PixelStats stats = IBA::computePixelStats(relative);
    double sum = 0;
    for (float avg : stats.avg) sum += avg;
    r.relMse = stats.avg.empty() ? 0 : sum / double(stats.avg.size());
    return r;
  }

  std::unique_ptr<TextureImages::Backend> newTextureImages() const override {
    return oiio::newTextureImages();
  }
  EncodedImageInfo probeEncodedImage(const std::string& bytes) const override {
    return oiio::probeEncodedImage(bytes);
  }
  std::vector<float> decodeEncodedImage(const std::string& bytes,
                                        EncodedImageInfo* info) const override {
    return oiio::decodeEncodedImage(bytes, info);
  }
};

}  // namespace

}  // namespace glint::oiio

extern "C" __attribute__((visibility("default"))) const glint::oiio::Plugin* glint_oiio_plugin() {
  static const glint::oiio::OiioPlugin plugin;
  return &plugin;
}
