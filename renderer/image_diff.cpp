// glint — numeric image comparison on OpenImageIO's ImageBufAlgo.
#include "renderer/image_diff.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

namespace glint {

namespace {

OIIO::ImageBuf readImage(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw ImageReadError(fmt::format("{}: no such file", path));
  if (std::filesystem::is_directory(path, ec))
    throw ImageReadError(fmt::format("{}: is a folder, not an image", path));
  OIIO::ImageBuf image(path);
  // Read everything now, as float, so a truncated file fails here and not half-way through.
  if (!image.read(0, 0, /*force=*/true, OIIO::TypeDesc::FLOAT) || image.has_error()) {
    std::string why = image.geterror();
    if (why.empty()) why = "cannot read the image";
    throw ImageReadError(fmt::format("{}: {}", path, why));
  }
  return image;
}

// Channel indices (into a and b) of the channels to compare, and their names.
struct ChannelMap {
  std::vector<int> a, b;
  std::vector<std::string> names;
};

ChannelMap commonChannels(const OIIO::ImageSpec& a, const OIIO::ImageSpec& b) {
  ChannelMap map;
  for (const char* name : {"R", "G", "B", "A"}) {
    int ia = a.channelindex(name), ib = b.channelindex(name);
    if (ia >= 0 && ib >= 0) {
      map.a.push_back(ia);
      map.b.push_back(ib);
      map.names.emplace_back(name);
    }
  }
  if (map.names.empty()) {  // e.g. two greyscale images ("Y"): compare by position
    int n = std::min(a.nchannels, b.nchannels);
    for (int c = 0; c < n; ++c) {
      map.a.push_back(c);
      map.b.push_back(c);
      map.names.push_back(a.channel_name(c));
    }
  }
  return map;
}

OIIO::ImageBuf select(const OIIO::ImageBuf& src, const std::vector<int>& order,
                      const std::string& path) {
  OIIO::ImageBuf out = OIIO::ImageBufAlgo::channels(src, int(order.size()), order);
  if (out.has_error()) throw ImageReadError(fmt::format("{}: {}", path, out.geterror()));
  // Compare the pixel grids, whatever the files' data-window origins.
  out.set_origin(0, 0);
  return out;
}

}  // namespace

int DiffImage::channel(const std::string& name) const {
  for (size_t c = 0; c < names.size(); ++c)
    if (names[c] == name) return int(c);
  return -1;
}

DiffImage readDiffImage(const std::string& path) {
  OIIO::ImageBuf file = readImage(path);
  const OIIO::ImageSpec& spec = file.spec();
  DiffImage image;
  image.width = spec.width;
  image.height = spec.height * std::max(spec.depth, 1);
  image.channels = spec.nchannels;
  image.names = spec.channelnames;
  image.spp = spec.get_int_attribute("glint:spp", 0);
  image.floatingPoint = file.nativespec().format.is_floating_point();  // as stored, not as read
  image.pixels.resize(size_t(image.width) * size_t(image.height) * size_t(image.channels));
  if (!file.get_pixels(file.roi(), OIIO::TypeDesc::FLOAT, image.pixels.data()))
    throw ImageReadError(fmt::format("{}: {}", path, file.geterror()));
  return image;
}

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
  OIIO::ImageBuf fileA = readImage(pathA);
  OIIO::ImageBuf fileB = readImage(pathB);
  const OIIO::ImageSpec& specA = fileA.spec();
  const OIIO::ImageSpec& specB = fileB.spec();

  DiffResult r;
  r.widthA = specA.width, r.heightA = specA.height;
  r.widthB = specB.width, r.heightB = specB.height;
  if (r.widthA != r.widthB || r.heightA != r.heightB || specA.depth != specB.depth) {
    r.sizeMismatch = true;
    r.verdict = DiffVerdict::Fail;
    return r;
  }
  ChannelMap map = commonChannels(specA, specB);
  if (map.names.empty())
    throw ImageReadError(fmt::format("{}: no channels in common with {}", pathA, pathB));
  r.channels = map.names;
  OIIO::ImageBuf A = select(fileA, map.a, pathA);
  OIIO::ImageBuf B = select(fileB, map.b, pathB);
  r.pixels = uint64_t(r.widthA) * uint64_t(r.heightA) * uint64_t(std::max(specA.depth, 1));

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
