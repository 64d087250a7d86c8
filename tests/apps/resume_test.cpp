// Tests for apps/resume: what `glint render --resume` trusts as a complete output of a render.
#include "apps/resume.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "image/output.h"
#include "test_support.h"

namespace fs = std::filesystem;

namespace glint::app {
namespace {

using test::constantFilm;
using test::sampleMetadata;

using test::aovFilm;

ExpectedImage expectedFor(const Film& film, const ImageMetadata& meta) {
  ExpectedImage e;
  e.fullWidth = film.fullWidth, e.fullHeight = film.fullHeight;
  e.x0 = film.originX, e.y0 = film.originY, e.width = film.width, e.height = film.height;
  e.scene = meta.scene, e.spp = meta.spp, e.seed = meta.seed, e.time = meta.time;
  return e;
}

// Rewrites `path` with the same header (glint:checksum included) and one value changed: a file
// whose pixels are not the ones glint wrote, though every byte of it decodes.
void alterOnePixel(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  OIIO::ImageSpec spec = in->spec();
  std::vector<float> px(size_t(spec.image_pixels()) * size_t(spec.nchannels));
  ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
  in->close();
  px[5] += 0.5f;
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out->open(path, spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
  out->close();
}

TEST(Resume, CompleteExrPassesAndEachWayOfBeingIncompleteIsNamed) {
  const std::string dir = test::scratchDir("Output.Completeness");
  for (bool half : {false, true}) {
    SCOPED_TRACE(half ? "half" : "float");
    const std::string path = dir + (half ? "/half.exr" : "/float.exr");
    Film film = aovFilm();
    film.originX = 3, film.originY = 1, film.fullWidth = 10, film.fullHeight = 6;  // a crop
    film.color[2] = {0.1f, 1.0f / 3.0f, 1e-5f};  // values half must round
    RenderSettings settings;
    settings.exrHalf = half;
    ImageMetadata meta = sampleMetadata();
    meta.time = 0.375;
    writeImage(path, film, settings, meta);
    const ExpectedImage expected = expectedFor(film, meta);
    EXPECT_EQ(whyIncomplete(path, expected), "");
    {  // the same scene spelled another way is the same render
      ExpectedImage e = expected;
      e.scene = "/elsewhere/cornell.gltf";
      EXPECT_EQ(whyIncomplete(path, e), "");
    }
    const auto expectReason = [&](const ExpectedImage& e, const std::string& reason) {
      const std::string why = whyIncomplete(path, e);
      EXPECT_NE(why.find(reason), std::string::npos) << "got: " << why;
    };
    ExpectedImage e = expected;
    e.spp = 16;
    expectReason(e, "64 spp, not 16");
    e = expected, e.seed = 1;
    expectReason(e, "seed");
    e = expected, e.time = 0.5;
    expectReason(e, "time 0.375 s, not 0.5 s");
    e = expected, e.y0 = 0;
    expectReason(e, "holds pixels 3,1..7,4");
    e = expected, e.fullWidth = 20;
    expectReason(e, "10x6 frame, not 20x6");
    e = expected, e.scene = "other.json";
    expectReason(e, "not 'other.json'");
    EXPECT_EQ(whyIncomplete(dir + "/none.exr", expected), "missing");

    // A copy cut short, and one whose pixels changed under an intact header.
    const std::string cut = dir + "/cut.exr";
    fs::copy_file(path, cut, fs::copy_options::overwrite_existing);
    fs::resize_file(cut, fs::file_size(cut) - 40);
    EXPECT_NE(whyIncomplete(cut, expected), "");
    alterOnePixel(path);
    expectReason(expected, "do not match glint:checksum");
  }
}

TEST(Resume, DisplayImagesMustDecodeAtTheirSize) {
  const std::string dir = test::scratchDir("Output.DisplayCompleteness");
  const std::string path = dir + "/img.png";
  Film film = constantFilm(12, 9, {0.5f, 0.2f, 0.1f});
  writeImage(path, film, RenderSettings{}, sampleMetadata());
  ExpectedImage e = expectedFor(film, sampleMetadata());
  EXPECT_EQ(whyIncomplete(path, e), "");
  e.width = 13;
  EXPECT_NE(whyIncomplete(path, e).find("12x9 pixels, not 13x9"), std::string::npos);
  e.width = 12;
  fs::resize_file(path, fs::file_size(path) - 20);  // the last chunks (IDAT's end, IEND) gone
  EXPECT_NE(whyIncomplete(path, e), "");
}

}  // namespace
}  // namespace glint::app
