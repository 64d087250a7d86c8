// glint — numeric image comparison: images from image/io.h's reader, compared with
// OpenImageIO's ImageBufAlgo (idiff's own metrics).
#include "image/diff.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

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

// The channels `order` of `image` as an ImageBuf at origin 0,0: the pixel grids are compared,
// whatever the files' data-window origins.
OIIO::ImageBuf select(const Image& image, const std::vector<int>& order) {
  const int nch = int(order.size());
  OIIO::ImageBuf out(OIIO::ImageSpec(image.width, image.height, nch, OIIO::TypeDesc::FLOAT));
  std::vector<float> px(image.pixelCount() * size_t(nch));
  for (size_t i = 0; i < image.pixelCount(); ++i)
    for (int c = 0; c < nch; ++c)
      px[i * size_t(nch) + size_t(c)] =
          image.pixels[i * size_t(image.channels) + size_t(order[size_t(c)])];
  out.set_pixels(out.roi(), OIIO::TypeDesc::FLOAT, px.data());
  return out;
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
  OIIO::ImageBuf A = select(fileA, map.a);
  OIIO::ImageBuf B = select(fileB, map.b);
  r.pixels = uint64_t(fileA.pixelCount());

  namespace IBA = OIIO::ImageBufAlgo;
  IBA::CompareResults cr = IBA::compare(A, B, float(t.fail), float(t.warn));
  // cr.error is also set when pixels fail; only a recorded message is a real error.
  if (std::string why = OIIO::geterror(); cr.error && !why.empty())
    throw ImageReadError(fmt::format("{} vs {}: {}", pathA, pathB, why));
  r.meanAbsError = cr.meanerror;
  r.rmse = cr.rms_error;
  r.psnr = cr.rms_error > 0 ? 20.0 * std::log10(1.0 / cr.rms_error)
                            : std::numeric_limits<double>::infinity();
  r.maxError = cr.maxerror;
  r.maxX = cr.maxx;
  r.maxY = cr.maxy;
  r.maxChannel = cr.maxc >= 0 && cr.maxc < int(r.channels.size()) ? r.channels[cr.maxc] : "";
  r.failPixels = cr.nfail;
  r.warnPixels = cr.nwarn;
  double pixels = double(std::max<uint64_t>(r.pixels, 1));
  r.failPixelPercent = 100.0 * double(cr.nfail) / pixels;
  r.warnPixelPercent = 100.0 * double(cr.nwarn) / pixels;

  // Relative MSE (as in Rousselle et al. / Mitsuba's tests): (a−b)² / (b² + 0.01), averaged.
  OIIO::ImageBuf diff = IBA::sub(A, B);
  OIIO::ImageBuf relative = IBA::div(IBA::mul(diff, diff), IBA::add(IBA::mul(B, B), 0.01f));
  IBA::PixelStats stats = IBA::computePixelStats(relative);
  double sum = 0;
  for (float avg : stats.avg) sum += avg;
  r.relMse = stats.avg.empty() ? 0 : sum / double(stats.avg.size());

  // idiff's rule: more than P % of the pixels over the threshold.
  if (double(cr.nfail) > t.failPercent / 100.0 * double(r.pixels))
    r.verdict = DiffVerdict::Fail;
  else if (double(cr.nwarn) > t.warnPercent / 100.0 * double(r.pixels))
    r.verdict = DiffVerdict::Warn;
  return r;
}

}  // namespace glint
