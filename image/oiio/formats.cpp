// glint — the OpenImageIO plugin's image half: reading any format OpenImageIO reads, writing
// PNG, JPEG and TIFF, and idiff's comparison; and the plugin's entry point.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "image/oiio/plugin.h"
#include "image/oiio/textures.h"

namespace glint::oiio {

namespace {

// ---- metadata --------------------------------------------------------------------------------
//
// glint's attributes (forEachMetadataField) are written as text: PNG keeps text attributes as
// tEXt chunks but drops numbers, and TIFF, JPEG and the rest keep no attributes of their own
// names at all, so there they go into the image description as one JSON object. Read back, a
// field's text is parsed as its type; an attribute stored with a number type (an image another
// program wrote) is taken as it is.

// The glint attributes to write, name and text, in forEachMetadataField's order.
std::vector<std::pair<std::string, std::string>> metadataTexts(const ImageMetadata& meta) {
  std::vector<std::pair<std::string, std::string>> texts;
  forEachMetadataField(meta, [&](const char* name, const auto& field, bool whenStopped) {
    if (whenStopped && meta.stop.empty()) return;
    texts.emplace_back(name, metadataText(field));
  });
  return texts;
}

void addMetadata(OIIO::ImageSpec& spec, const ImageMetadata& meta, bool attributesKept) {
  const auto texts = metadataTexts(meta);
  if (attributesKept) {
    for (const auto& [name, text] : texts) spec.attribute(name, text);
    return;
  }
  nlohmann::ordered_json description = nlohmann::ordered_json::object();
  for (const auto& [name, text] : texts) description[name] = text;
  spec.attribute("ImageDescription", description.dump());
}

// One glint attribute as the file holds it: its text, and whether it was stored as text.
struct StoredAttribute {
  std::string name, text;
  bool isText = true;
};

// glint's attributes of an image: its attributes named glint:..., or else those of a JSON
// object in its description (see addMetadata).
std::vector<StoredAttribute> storedAttributes(const OIIO::ImageSpec& spec) {
  std::vector<StoredAttribute> stored;
  for (const OIIO::ParamValue& p : spec.extra_attribs) {
    if (p.name().string().rfind("glint:", 0) != 0) continue;
    if (p.type() == OIIO::TypeDesc::STRING)
      stored.push_back({p.name().string(), p.get_string(), true});
    else
      stored.push_back({p.name().string(), spec.metadata_val(p), false});
  }
  if (!stored.empty()) return stored;
  const auto description =
      nlohmann::json::parse(spec.get_string_attribute("ImageDescription"), nullptr, false);
  if (!description.is_object()) return stored;
  for (const auto& [name, value] : description.items())
    if (name.rfind("glint:", 0) == 0 && value.is_string())
      stored.push_back({name, value.get<std::string>(), true});
  return stored;
}

const StoredAttribute* findStored(const std::vector<StoredAttribute>& stored,
                                  const std::string& name) {
  for (const StoredAttribute& a : stored)
    if (a.name == name) return &a;
  return nullptr;
}

// Fills image's metadata, its has... flags and its attribute list from `stored`; fields whose
// text is absent or does not parse keep their defaults.
void readMetadata(const std::vector<StoredAttribute>& stored, Image* image) {
  forEachMetadataField(image->meta, [&](const char* name, auto& field, bool) {
    if (const StoredAttribute* a = findStored(stored, name)) parseMetadataText(a->text, &field);
  });
  image->hasMeta = findStored(stored, "glint:scene") != nullptr;
  image->hasSeed = findStored(stored, "glint:seed") != nullptr;
  double time = 0;
  const StoredAttribute* t = findStored(stored, "glint:time");
  image->hasTime = t && parseMetadataText(t->text, &time);
  if (const StoredAttribute* c = findStored(stored, "glint:checksum")) image->checksum = c->text;
  // As the EXR reader shows them: text quoted, numbers bare (a number glint wrote as text
  // included).
  for (const StoredAttribute& a : stored) {
    bool number = !a.isText;
    forEachMetadataField(image->meta, [&](const char* name, const auto& field, bool) {
      if (a.name == name) number = !std::is_same_v<std::decay_t<decltype(field)>, std::string>;
    });
    image->glintAttributes.emplace_back(a.name, number ? a.text : "\"" + a.text + "\"");
  }
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
    readMetadata(storedAttributes(spec), image);
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
    auto out = OIIO::ImageOutput::create(formatPath);
    if (!out) {
      *why = OIIO::geterror();
      return false;
    }
    if (image.hasMeta) addMetadata(spec, image.meta, std::string(out->format_name()) == "png");
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

  std::unique_ptr<TextureImages::Cache> newTextureCache() const override {
    return oiio::newTextureCache();
  }
  EncodedImageInfo probeEncodedImage(const std::string& bytes) const override {
    return oiio::probeEncodedImage(bytes);
  }
  std::vector<float> decodeEncodedImage(const std::string& bytes,
                                        EncodedImageInfo* info) const override {
    return oiio::decodeEncodedImage(bytes, info);
  }
  DecodedImage decodeEncoded(const std::string& bytes) const override {
    return oiio::decodeEncoded(bytes);
  }
  ImageFileInfo probeImageFile(const std::string& path) const override {
    return oiio::probeImageFile(path);
  }
  DecodedImage decodeImageFile(const std::string& path) const override {
    return oiio::decodeImageFile(path);
  }
};

}  // namespace

}  // namespace glint::oiio

extern "C" __attribute__((visibility("default"))) const glint::oiio::Plugin* glint_oiio_plugin() {
  static const glint::oiio::OiioPlugin plugin;
  return &plugin;
}
