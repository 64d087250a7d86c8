// glint — reading and writing OpenEXR files with the OpenEXR library (see exr.h).
#include "image/exr.h"

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfThreading.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <fstream>
#include <mutex>
#include <thread>
#include <type_traits>

namespace glint {

namespace {

// OpenEXR's thread pool, once: as many threads as cores (compression and decompression of
// separate line blocks run in parallel).
int exrThreads() {
  static std::once_flag once;
  static int threads = 1;
  std::call_once(once, [] {
    threads = int(std::max(1u, std::thread::hardware_concurrency()));
    Imf::setGlobalThreadCount(threads);
  });
  return threads;
}

bool equalsIgnoringCase(const std::string& a, const char* b) {
  size_t n = 0;
  for (; b[n]; ++n)
    if (n >= a.size() || std::tolower(static_cast<unsigned char>(a[n])) !=
                             std::tolower(static_cast<unsigned char>(b[n])))
      return false;
  return n == a.size();
}

// OpenImageIO's presentation order of EXR channels: by layer (the name up to its last dot),
// then colour, alpha and depth names in this order, then the rest by name.
struct ChannelOrder {
  std::string name, layer, suffix;
  int special = 10000;

  explicit ChannelOrder(std::string full) : name(std::move(full)) {
    const size_t dot = name.find_last_of('.');
    layer = dot == std::string::npos ? "" : name.substr(0, dot + 1);
    suffix = dot == std::string::npos ? name : name.substr(dot + 1);
    static constexpr std::array<const char*, 20> kSpecial = {
        "R",     "Red", "G",  "Green", "B",  "Blue", "Y",  "real", "imag",  "A",
        "Alpha", "AR",  "RA", "AG",    "GA", "AB",   "BA", "Z",    "Depth", "Zback"};
    for (size_t i = 0; i < kSpecial.size(); ++i)
      if (equalsIgnoringCase(suffix, kSpecial[i])) {
        special = int(i);
        break;
      }
  }
  bool operator<(const ChannelOrder& o) const {
    if (layer != o.layer) return layer < o.layer;
    if (special != o.special) return special < o.special;
    return suffix < o.suffix;
  }
};

// An attribute's text as OpenImageIO's metadata_val gave it (strings quoted).
std::string attributeText(const Imf::Attribute& a) {
  if (auto* s = dynamic_cast<const Imf::StringAttribute*>(&a)) return "\"" + s->value() + "\"";
  if (auto* i = dynamic_cast<const Imf::IntAttribute*>(&a)) return std::to_string(i->value());
  if (auto* d = dynamic_cast<const Imf::DoubleAttribute*>(&a))
    return fmt::format("{:g}", d->value());
  return std::string("<") + a.typeName() + ">";
}

template <class T>
const T* typed(const Imf::Header& h, const char* name) {
  return h.findTypedAttribute<T>(name);
}

void readMetadata(const Imf::Header& h, Image* image) {
  forEachMetadataField(image->meta, [&](const char* name, auto& field, bool) {
    using T = std::decay_t<decltype(field)>;
    if constexpr (std::is_same_v<T, std::string>) {
      if (auto* a = typed<Imf::StringAttribute>(h, name)) field = a->value();
    } else if constexpr (std::is_same_v<T, int>) {
      if (auto* a = typed<Imf::IntAttribute>(h, name)) field = a->value();
    } else if constexpr (std::is_same_v<T, uint64_t>) {
      if (auto* a = typed<Imf::StringAttribute>(h, name)) parseMetadataText(a->value(), &field);
    } else {
      static_assert(std::is_same_v<T, double>);
      if (auto* a = typed<Imf::DoubleAttribute>(h, name)) field = a->value();
    }
  });
  image->hasMeta = h.find("glint:scene") != h.end();
  image->hasSeed = h.find("glint:seed") != h.end();
  image->hasTime = typed<Imf::DoubleAttribute>(h, "glint:time") != nullptr;
  if (auto* a = typed<Imf::StringAttribute>(h, "glint:checksum")) image->checksum = a->value();
  for (auto it = h.begin(); it != h.end(); ++it)
    if (std::string(it.name()).rfind("glint:", 0) == 0)
      image->glintAttributes.emplace_back(it.name(), attributeText(it.attribute()));
}

void writeMetadata(Imf::Header& h, const ImageMetadata& meta) {
  forEachMetadataField(meta, [&](const char* name, const auto& field, bool whenStopped) {
    if (whenStopped && meta.stop.empty()) return;
    using T = std::decay_t<decltype(field)>;
    if constexpr (std::is_same_v<T, std::string>)
      h.insert(name, Imf::StringAttribute(field));
    else if constexpr (std::is_same_v<T, int>)
      h.insert(name, Imf::IntAttribute(field));
    else if constexpr (std::is_same_v<T, uint64_t>)
      h.insert(name, Imf::StringAttribute(metadataText(field)));
    else
      h.insert(name, Imf::DoubleAttribute(field));
  });
}

}  // namespace

bool isExrFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[4] = {};
  return in.read(magic, 4) && magic[0] == 0x76 && magic[1] == 0x2f && magic[2] == 0x31 &&
         magic[3] == 0x01;
}

Image readExrImage(const std::string& path, bool pixels) {
  bool afterHeader = false;
  try {
    Imf::InputFile file(path.c_str(), exrThreads());
    const Imf::Header& h = file.header();
    const Imath::Box2i data = h.dataWindow(), display = h.displayWindow();
    Image image;
    image.format = "openexr";
    image.x = data.min.x, image.y = data.min.y;
    image.width = data.max.x - data.min.x + 1;
    image.height = data.max.y - data.min.y + 1;
    image.fullX = display.min.x, image.fullY = display.min.y;
    image.fullWidth = display.max.x - display.min.x + 1;
    image.fullHeight = display.max.y - display.min.y + 1;

    std::vector<ChannelOrder> order;
    bool anyHalf = false, anyFloat = false;
    for (auto it = h.channels().begin(); it != h.channels().end(); ++it) {
      const Imf::Channel& c = it.channel();
      if (c.xSampling != 1 || c.ySampling != 1)
        throw DecodeError(path,
                          fmt::format("channel \"{}\" is subsampled ({}x{}); glint reads "
                                      "only full-resolution channels",
                                      it.name(), c.xSampling, c.ySampling),
                          false);
      anyHalf |= c.type == Imf::HALF;
      anyFloat |= c.type != Imf::UINT;
      order.emplace_back(it.name());
    }
    std::sort(order.begin(), order.end());
    for (const ChannelOrder& c : order) image.names.push_back(c.name);
    image.channels = int(order.size());
    // As io.h says (and as OpenImageIO's reader gave it): Half when any channel is half.
    image.type = anyHalf ? PixelType::Half : PixelType::Float;
    image.floatingPoint = anyFloat;
    readMetadata(h, &image);
    if (!pixels) return image;

    afterHeader = true;
    if (image.width <= 0 || image.height <= 0 || image.channels == 0)
      throw DecodeError(path, "the image has no pixels", true);
    image.pixels.resize(image.pixelCount() * size_t(image.channels));
    const size_t xStride = sizeof(float) * size_t(image.channels);
    const size_t yStride = xStride * size_t(image.width);
    // Slices are addressed by absolute pixel coordinates; Slice::Make offsets them by the data
    // window's corner.
    Imf::FrameBuffer fb;
    for (int c = 0; c < image.channels; ++c)
      fb.insert(image.names[size_t(c)],
                Imf::Slice::Make(Imf::FLOAT, &image.pixels[size_t(c)], data, xStride, yStride));
    file.setFrameBuffer(fb);
    file.readPixels(data.min.y, data.max.y);
    return image;
  } catch (const DecodeError&) {
    throw;
  } catch (const std::exception& e) {
    throw DecodeError(path, fmt::format("OpenEXR: {}", e.what()), afterHeader);
  }
}

void writeExrImage(const std::string& file, const std::string& target, const Image& image,
                   const std::string& checksum) {
  const int nch = image.channels;
  const int zChannel = image.channel("Z");
  const int width = image.width, height = image.height;
  const int fullWidth = image.fullWidth > 0 ? image.fullWidth : width;
  const int fullHeight = image.fullHeight > 0 ? image.fullHeight : height;
  const Imath::Box2i display({image.fullX, image.fullY},
                             {image.fullX + fullWidth - 1, image.fullY + fullHeight - 1});
  const Imath::Box2i data({image.x, image.y}, {image.x + width - 1, image.y + height - 1});
  Imf::Header h(display, data);
  h.compression() = Imf::ZIP_COMPRESSION;
  // Deflate's fastest level: on glint's float channels (the variance's mantissas are noise)
  // it makes files within 0.2% of the default level's size in 7-10% less time
  // (benchmarks/README.md, "EXR writing at deflate level 1").
  h.zipCompressionLevel() = 1;
  h.insert("Software", Imf::StringAttribute("glint"));
  if (image.hasMeta) writeMetadata(h, image.meta);
  h.insert("glint:checksum", Imf::StringAttribute(checksum));

  // A Half image keeps its Z channel in float (half tops out at 65504).
  auto isHalf = [&](int c) { return image.type == PixelType::Half && c != zChannel; };
  const std::vector<std::string>& names = image.names;  // one per channel (writeImageFile)
  for (int c = 0; c < nch; ++c)
    h.channels().insert(names[size_t(c)], Imf::Channel(isHalf(c) ? Imf::HALF : Imf::FLOAT));

  // Half channels from their own interleaved buffer; float channels straight from the image.
  std::vector<Imath::half> halves;
  int halfCount = 0;
  for (int c = 0; c < nch; ++c) halfCount += isHalf(c);
  if (halfCount > 0) {
    halves.resize(image.pixelCount() * size_t(halfCount));
    size_t k = 0;
    for (size_t i = 0; i < image.pixelCount(); ++i)
      for (int c = 0; c < nch; ++c)
        if (isHalf(c)) halves[k++] = Imath::half(image.pixels[i * size_t(nch) + size_t(c)]);
  }
  const size_t fx = sizeof(float) * size_t(nch), fy = fx * size_t(width);
  const size_t hx = sizeof(Imath::half) * size_t(halfCount), hy = hx * size_t(width);
  Imf::FrameBuffer fb;
  size_t halfIndex = 0;
  for (int c = 0; c < nch; ++c) {
    if (isHalf(c))
      fb.insert(names[size_t(c)], Imf::Slice::Make(Imf::HALF, &halves[halfIndex++], data, hx, hy));
    else
      fb.insert(names[size_t(c)],
                Imf::Slice::Make(Imf::FLOAT, &image.pixels[size_t(c)], data, fx, fy));
  }
  try {
    Imf::OutputFile out(file.c_str(), h, exrThreads());
    out.setFrameBuffer(fb);
    out.writePixels(height);
  } catch (const std::exception& e) {
    throw OutputError(fmt::format("cannot write '{}': {}", target, e.what()));
  }
}

}  // namespace glint
