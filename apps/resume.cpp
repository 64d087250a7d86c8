// glint — the completeness check of `glint render --resume`, on image/io.h's reader.
#include "apps/resume.h"

#include <fmt/format.h>

#include <filesystem>

#include "image/input.h"
#include "image/io.h"

namespace fs = std::filesystem;

namespace glint::app {

namespace {

// Why the EXR header `header` is not of the render `expected` describes (frame, window, scene,
// seed, time), or empty.
std::string identityMismatch(const Image& header, const ExpectedImage& expected) {
  if (header.fullWidth != expected.fullWidth || header.fullHeight != expected.fullHeight)
    return fmt::format("a {}x{} frame, not {}x{}", header.fullWidth, header.fullHeight,
                       expected.fullWidth, expected.fullHeight);
  if (header.x != expected.x0 || header.y != expected.y0 || header.width != expected.width ||
      header.height != expected.height)
    return fmt::format("holds pixels {},{}..{},{}, not {},{}..{},{}", header.x, header.y,
                       header.x + header.width, header.y + header.height, expected.x0, expected.y0,
                       expected.x0 + expected.width, expected.y0 + expected.height);
  const ImageMetadata& meta = header.meta;
  const std::string scene = fs::path(meta.scene).filename();
  const std::string expectedScene = fs::path(expected.scene).filename();
  if (scene != expectedScene)
    return fmt::format("a render of '{}', not '{}'", scene, expectedScene);
  if (!header.hasSeed) return fmt::format("rendered with seed (none), not {}", expected.seed);
  if (meta.seed != expected.seed)
    return fmt::format("rendered with seed {}, not {}", meta.seed, expected.seed);
  if (!header.hasTime) return "no glint:time (written by an older glint)";
  if (meta.time != expected.time)
    return fmt::format("the frame at time {} s, not {} s", meta.time, expected.time);
  return "";
}

// Why a render of the right identity that reached `meta.spp` is not finished, or empty.
std::string whyUnfinished(const ImageMetadata& meta, const ExpectedImage& expected) {
  if (meta.stop == "interrupted") return fmt::format("interrupted at {} spp", meta.spp);
  if (!expected.budget) {
    if (meta.spp != expected.spp)
      return fmt::format("rendered with {} spp, not {}", meta.spp, expected.spp);
    return "";
  }
  if (meta.spp >= expected.spp) return "";  // the cap
  if (expected.noiseTarget > 0 && !(meta.error > 0 && meta.error <= expected.noiseTarget))
    return fmt::format("its estimated error {:.3g} is above the target {:.3g}", meta.error,
                       expected.noiseTarget);
  return "";
}

// The checks every completeness or continuation test starts with; fills *header.
std::string checkHeader(const std::string& path, const ExpectedImage& expected, Image* header) {
  std::error_code ec;
  if (!fs::exists(path, ec)) return "missing";
  if (!fs::is_regular_file(path, ec)) return "not a regular file";
  try {
    *header = readImage(path, /*pixels=*/false);  // the cheap checks first
  } catch (const DecodeError& e) {
    return "cannot read: " + e.why();
  }
  const bool exr = isExrPath(path);
  if (exr != (header->format == "openexr")) return fmt::format("holds a {} image", header->format);
  return exr ? identityMismatch(*header, expected) : "";
}

}  // namespace

std::string whyIncomplete(const std::string& path, const ExpectedImage& expected) {
  Image header;
  if (std::string why = checkHeader(path, expected, &header); !why.empty()) return why;
  const bool exr = isExrPath(path);
  if (exr) {
    if (std::string why = whyUnfinished(header.meta, expected); !why.empty()) return why;
  } else if (header.width != expected.width || header.height != expected.height) {
    return fmt::format("{}x{} pixels, not {}x{}", header.width, header.height, expected.width,
                       expected.height);
  }
  Image image;
  try {
    image = readImage(path);
  } catch (const DecodeError& e) {
    return (e.afterHeader() ? "cannot read its pixels: " : "cannot read: ") + e.why();
  } catch (const ImageReadError& e) {  // removed since the first look
    return e.what();
  }
  if (exr) {
    if (image.checksum.empty()) return "no glint:checksum (written by an older glint)";
    if (image.checksum != pixelChecksum(image.pixels, image.names))
      return "its pixels do not match glint:checksum";
  }
  return "";
}

std::optional<PartialRender> continuableRender(const std::string& path,
                                               const ExpectedImage& expected, std::string* whyNot) {
  const auto no = [&](std::string why) -> std::optional<PartialRender> {
    if (whyNot) *whyNot = std::move(why);
    return std::nullopt;
  };
  if (!isExrPath(path)) return no("not an EXR");
  Image header;
  if (std::string why = checkHeader(path, expected, &header); !why.empty()) return no(why);
  if (whyUnfinished(header.meta, expected).empty()) return no("already complete");
  if (header.meta.spp <= 0) return no("no samples");
  if (header.meta.spp >= expected.spp)
    return no(fmt::format("rendered with {} spp, not below {}", header.meta.spp, expected.spp));
  try {
    Image image = readImage(path);
    if (image.checksum.empty()) return no("no glint:checksum (written by an older glint)");
    if (image.checksum != pixelChecksum(image.pixels, image.names))
      return no("its pixels do not match glint:checksum");
    PartialRender partial;
    ImageMetadata meta;
    std::string why;
    partial.film = readRenderState(path, &meta, &why);
    if (partial.film.width == 0) return no(why);
    partial.path = path;
    partial.spp = uint32_t(meta.spp);
    partial.seconds = meta.renderSeconds;
    partial.integrator = meta.integrator;
    return partial;
  } catch (const std::exception& e) {  // DecodeError, ImageReadError: changed since the look
    return no(e.what());
  }
}

}  // namespace glint::app
