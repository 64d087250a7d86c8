// glint — numeric image comparison: images from image/io.h's reader, compared with
// OpenImageIO's ImageBufAlgo (idiff's own metrics), in the OpenImageIO plugin.
#include "image/diff.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "image/oiio/plugin.h"

namespace glint {

namespace {

// Channel indices (into a and b) of the channels to compare, and their names.
struct ChannelMap {
  std::vector<int> a, b;
  std::vector<std::string> names;
};

ChannelMap commonChannels(const Image& a, const Image& b) {
  ChannelMap map;
  for (const char* name : {"R", "G", "B", "A"}) {
    int ia = a.channel(name), ib = b.channel(name);
    if (ia >= 0 && ib >= 0) {
      map.a.push_back(ia);
      map.b.push_back(ib);
      map.names.emplace_back(name);
    }
  }
  if (map.names.empty()) {  // e.g. two greyscale images ("Y"): compare by position
    int n = std::min(a.channels, b.channels);
    for (int c = 0; c < n; ++c) {
      map.a.push_back(c);
      map.b.push_back(c);
      map.names.push_back(a.names[size_t(c)]);
    }
  }
  return map;
}

// The channels `order` of `image`, interleaved: the pixel grids are compared, whatever the
// files' data-window origins.
std::vector<float> select(const Image& image, const std::vector<int>& order) {
  const int nch = int(order.size());
  std::vector<float> px(image.pixelCount() * size_t(nch));
  for (size_t i = 0; i < image.pixelCount(); ++i)
    for (int c = 0; c < nch; ++c)
      px[i * size_t(nch) + size_t(c)] =
          image.pixels[i * size_t(image.channels) + size_t(order[size_t(c)])];
  return px;
}

}  // namespace

const char* verdictName(DiffVerdict v) {
  switch (v) {
    case DiffVerdict::Pass:
      return "pass";
    case DiffVerdict::Warn:
      return "warn";
    case DiffVerdict::Fail:
      return "fail";
  }
  return "?";
}

DiffResult diffImages(const std::string& pathA, const std::string& pathB, const DiffThresholds& t) {
  const Image fileA = readImage(pathA);
  const Image fileB = readImage(pathB);

  DiffResult r;
  r.widthA = fileA.width, r.heightA = fileA.height / fileA.depth;
  r.widthB = fileB.width, r.heightB = fileB.height / fileB.depth;
  if (r.widthA != r.widthB || r.heightA != r.heightB || fileA.depth != fileB.depth) {
    r.sizeMismatch = true;
    r.verdict = DiffVerdict::Fail;
    return r;
  }
  ChannelMap map = commonChannels(fileA, fileB);
  if (map.names.empty())
    throw ImageReadError(fmt::format("{}: no channels in common with {}", pathA, pathB));
  r.channels = map.names;
  r.pixels = uint64_t(fileA.pixelCount());
  const oiio::CompareStats cr =
      oiio::plugin().compare(select(fileA, map.a), select(fileB, map.b), fileA.width, fileA.height,
                             int(map.names.size()), float(t.fail), float(t.warn));
  if (!cr.error.empty()) throw ImageReadError(fmt::format("{} vs {}: {}", pathA, pathB, cr.error));
  r.meanAbsError = cr.meanError;
  r.rmse = cr.rmsError;
  r.psnr = cr.rmsError > 0 ? 20.0 * std::log10(1.0 / cr.rmsError)
                           : std::numeric_limits<double>::infinity();
  r.maxError = cr.maxError;
  r.maxX = cr.maxX;
  r.maxY = cr.maxY;
  r.maxChannel = cr.maxChannel >= 0 && cr.maxChannel < int(r.channels.size())
                     ? r.channels[size_t(cr.maxChannel)]
                     : "";
  r.failPixels = cr.failPixels;
  r.warnPixels = cr.warnPixels;
  double pixels = double(std::max<uint64_t>(r.pixels, 1));
  r.failPixelPercent = 100.0 * double(cr.failPixels) / pixels;
  r.warnPixelPercent = 100.0 * double(cr.warnPixels) / pixels;
  r.relMse = cr.relMse;

  // idiff's rule: more than P % of the pixels over the threshold.
  if (double(cr.failPixels) > t.failPercent / 100.0 * double(r.pixels))
    r.verdict = DiffVerdict::Fail;
  else if (double(cr.warnPixels) > t.warnPercent / 100.0 * double(r.pixels))
    r.verdict = DiffVerdict::Warn;
  return r;
}

}  // namespace glint
