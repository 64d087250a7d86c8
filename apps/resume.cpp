// glint — the completeness check of `glint render --resume`, on image/io.h's reader.
#include "apps/resume.h"

#include <fmt/format.h>

#include <filesystem>

#include "image/io.h"

namespace fs = std::filesystem;

namespace glint::app {

std::string whyIncomplete(const std::string& path, const ExpectedImage& expected) {
  std::error_code ec;
  if (!fs::exists(path, ec)) return "missing";
  if (!fs::is_regular_file(path, ec)) return "not a regular file";
  Image header;
  try {
    header = readImage(path, /*pixels=*/false);  // the cheap checks first
  } catch (const DecodeError& e) {
    return "cannot read: " + e.why();
  }
  const bool exr = isExrPath(path);
  if (exr != (header.format == "openexr")) return fmt::format("holds a {} image", header.format);
  if (exr) {
    if (header.fullWidth != expected.fullWidth || header.fullHeight != expected.fullHeight)
      return fmt::format("a {}x{} frame, not {}x{}", header.fullWidth, header.fullHeight,
                         expected.fullWidth, expected.fullHeight);
    if (header.x != expected.x0 || header.y != expected.y0 || header.width != expected.width ||
        header.height != expected.height)
      return fmt::format("holds pixels {},{}..{},{}, not {},{}..{},{}", header.x, header.y,
                         header.x + header.width, header.y + header.height, expected.x0,
                         expected.y0, expected.x0 + expected.width, expected.y0 + expected.height);
    const ImageMetadata& meta = header.meta;
    const std::string scene = fs::path(meta.scene).filename();
    const std::string expectedScene = fs::path(expected.scene).filename();
    if (scene != expectedScene)
      return fmt::format("a render of '{}', not '{}'", scene, expectedScene);
    if (meta.spp != expected.spp)
      return fmt::format("rendered with {} spp, not {}", meta.spp, expected.spp);
    if (!header.hasSeed) return fmt::format("rendered with seed (none), not {}", expected.seed);
    if (meta.seed != expected.seed)
      return fmt::format("rendered with seed {}, not {}", meta.seed, expected.seed);
    if (!header.hasTime) return "no glint:time (written by an older glint)";
    if (meta.time != expected.time)
      return fmt::format("the frame at time {} s, not {} s", meta.time, expected.time);
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

}  // namespace glint::app
