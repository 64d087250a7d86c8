// glint — the one image reader and the one atomic image writer: OpenEXR through the OpenEXR
// library (exr.cpp), every other format through the OpenImageIO plugin (oiio/plugin.h).
#include "image/io.h"

#include <Imath/half.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>

#include "image/exr.h"
#include "image/oiio/plugin.h"

namespace fs = std::filesystem;

namespace glint {

namespace {

enum class Format { Exr, Png, Jpeg, Tiff, Unknown };

Format formatOf(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".exr") return Format::Exr;
  if (ext == ".png") return Format::Png;
  if (ext == ".jpg" || ext == ".jpeg") return Format::Jpeg;
  if (ext == ".tif" || ext == ".tiff") return Format::Tiff;
  return Format::Unknown;
}

// ---- atomic write ----------------------------------------------------------------------------

// The path temporaryOutputInFlight() reports: a fixed buffer, so a signal handler reads it
// without allocating. Writes happen one at a time.
char inFlightPath[4096];
std::atomic<bool> inFlight{false};

// Removes the temporary file unless the write got as far as the rename.
struct TempFile {
  fs::path path;
  bool keep = false;
  explicit TempFile(fs::path p) : path(std::move(p)) {
    const std::string& s = path.native();
    if (s.size() < sizeof inFlightPath) {
      std::memcpy(inFlightPath, s.c_str(), s.size() + 1);
      inFlight.store(true);
    }
  }
  ~TempFile() {
    inFlight.store(false);
    std::error_code ec;
    if (!keep) fs::remove(path, ec);
  }
};

fs::path temporaryPath(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  // Same folder (so the rename is atomic), hidden, and keeping the extension that selects the
  // format.
  std::string name = fmt::format(".{}.tmp-{}-{}{}", target.stem().string(), ::getpid(),
                                 counter.fetch_add(1), target.extension().string());
  return target.parent_path() / name;
}

void syncFile(const fs::path& path) {
  int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0 || ::fsync(fd) != 0) {
    int err = errno;
    if (fd >= 0) ::close(fd);
    throw OutputError(fmt::format("cannot write '{}': {}", path.string(), std::strerror(err)));
  }
  ::close(fd);
}

// Runs `write` on a temporary file beside `target`, then renames it over `target`. `write`
// throws OutputError on failure.
void writeAtomically(const std::string& target,
                     const std::function<void(const std::string& file)>& write) {
  TempFile temp{temporaryPath(fs::path(target))};
  auto fail = [&](const std::string& why) {
    return OutputError(fmt::format("cannot write '{}': {}", target, why));
  };
  write(temp.path.string());
  syncFile(temp.path);

  std::error_code ec;
  fs::rename(temp.path, target, ec);
  if (ec) throw fail(ec.message());
  temp.keep = true;
}

}  // namespace

const char* temporaryOutputInFlight() { return inFlight.load() ? inFlightPath : nullptr; }

// ---- reading ---------------------------------------------------------------------------------

std::string Image::attribute(const std::string& name) const {
  for (const auto& [key, value] : glintAttributes)
    if (key == name) return value;
  return "(none)";
}

Image readImage(const std::string& path, bool pixels) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw ImageReadError(fmt::format("{}: no such file", path));
  if (fs::is_directory(path, ec))
    throw ImageReadError(fmt::format("{}: is a folder, not an image", path));
  if (isExrFile(path)) return readExrImage(path, pixels);
  Image image;
  std::string why;
  bool afterHeader = false;
  if (!oiio::plugin().readImage(path, pixels, &image, &why, &afterHeader))
    throw DecodeError(path, why.empty() ? "cannot read the image" : why, afterHeader);
  return image;
}

// ---- writing ---------------------------------------------------------------------------------

bool isSupportedOutput(const std::string& path, std::string* why) {
  if (formatOf(path) != Format::Unknown) return true;
  if (why) {
    std::string ext = fs::path(path).extension().string();
    *why = fmt::format("'{}': {}; glint writes .exr, .png, .jpg/.jpeg and .tif/.tiff", path,
                       ext.empty() ? std::string("no file extension")
                                   : fmt::format("unsupported image format '{}'", ext));
  }
  return false;
}

bool isExrPath(const std::string& path) { return formatOf(path) == Format::Exr; }
bool isTiffPath(const std::string& path) { return formatOf(path) == Format::Tiff; }

void writeImageFile(const std::string& path, Image image) {
  const Format format = formatOf(path);
  std::string why;
  if (format == Format::Unknown) {
    isSupportedOutput(path, &why);
    throw OutputError(why);
  }
  const int nch = image.channels;
  if (image.width <= 0 || image.height <= 0 || nch <= 0 ||
      image.pixels.size() != image.pixelCount() * size_t(nch))
    throw OutputError(fmt::format("cannot write '{}': the image is empty", path));

  if (format == Format::Exr) {
    // Unnamed channels get OpenImageIO's default names, as before.
    if (image.names.size() != size_t(nch)) {
      image.names.clear();
      for (int c = 0; c < nch; ++c)
        image.names.push_back(c < 4 ? std::string(1, "RGBA"[c]) : fmt::format("channel{}", c));
    }
    // Round half channels first (Imath's rounding, to nearest even, as OpenEXR's), so the
    // checksum is of the values the file holds.
    const int z = image.channel("Z");
    if (image.type == PixelType::Half)
      for (size_t i = 0; i < image.pixels.size(); ++i)
        if (int(i % size_t(nch)) != z) image.pixels[i] = float(Imath::half(image.pixels[i]));
    const std::string checksum = pixelChecksum(image.pixels, image.names);
    writeAtomically(path,
                    [&](const std::string& file) { writeExrImage(file, path, image, checksum); });
    return;
  }
  writeAtomically(path, [&](const std::string& file) {
    std::string failure;
    if (!oiio::plugin().writeImage(file, path, image, &failure))
      throw OutputError(fmt::format("cannot write '{}': {}", path, failure));
  });
}

std::string pixelChecksum(const std::vector<float>& pixels,
                          const std::vector<std::string>& channelNames) {
  uint64_t hash = 0xcbf29ce484222325ull;  // FNV-1a offset basis
  const auto mix = [&](uint8_t byte) {
    hash ^= byte;
    hash *= 0x100000001b3ull;
  };
  const size_t nch = channelNames.size();
  std::vector<size_t> order(nch);
  for (size_t c = 0; c < nch; ++c) order[c] = c;
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return channelNames[a] < channelNames[b]; });
  for (size_t c : order) {
    for (char ch : channelNames[c]) mix(uint8_t(ch));
    mix(0);
    for (size_t i = c; i < pixels.size(); i += nch) {
      uint32_t bits;
      std::memcpy(&bits, &pixels[i], sizeof bits);
      for (int byte = 0; byte < 4; ++byte) mix(uint8_t(bits >> (8 * byte)));  // little-endian
    }
  }
  return fmt::format("{:016x}", hash);
}

}  // namespace glint
