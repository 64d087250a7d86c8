// Image textures, in memory (MipMap) and in OpenImageIO's TextureSystem: exact texels with
// Nearest, averages with Linear, the four wrap modes, sRGB and linear decoding, grey images,
// MIP-map filtering in linear space, anisotropic footprints, PNG files (written here), where
// each image is kept, both storages agreeing, bad files, threads, and the UV mapping.
#include "materials/image_texture.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>
#include <thread>

#include "geometry/error.h"
#include "image/oiio/plugin.h"
#include "test_support.h"

namespace glint {
namespace {

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

// A distinct RGBA value per texel of a 4x4 image: red codes x, green codes y.
Vec4f texel4x4(int x, int y) {
  return {0.125f + 0.25f * float(x), 0.125f + 0.25f * float(y), (x + y) % 2 ? 1.0f : 0.0f, 0.75f};
}

std::vector<float> pixels4x4() {
  std::vector<float> p;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) {
      Vec4f t = texel4x4(x, y);
      p.insert(p.end(), {t.x, t.y, t.z, t.w});
    }
  return p;
}

// The centre of texel (x, y) of an n x n image.
TexCoord2 centre(int x, int y, int n) {
  return {{(float(x) + 0.5f) / float(n), (float(y) + 0.5f) / float(n)}, {}, {}};
}

// A one-channel n x n checker of texel values a (even) and b (odd).
std::vector<float> checker(int n, float a, float b) {
  std::vector<float> p(size_t(n) * size_t(n));
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) p[size_t(y) * size_t(n) + size_t(x)] = (x + y) % 2 ? b : a;
  return p;
}

void expectNear(Vec4f got, Vec4f want, float tol) {
  EXPECT_NEAR(got.x, want.x, tol);
  EXPECT_NEAR(got.y, want.y, tol);
  EXPECT_NEAR(got.z, want.z, tol);
  EXPECT_NEAR(got.w, want.w, tol);
}

void expectEq(Vec4f got, Vec4f want) {
  EXPECT_EQ(got.x, want.x);
  EXPECT_EQ(got.y, want.y);
  EXPECT_EQ(got.z, want.z);
  EXPECT_EQ(got.w, want.w);
}

// Writes 8-bit pixels as a PNG.
void writePng(const std::string& path, int w, int h, int channels,
              const std::vector<unsigned char>& pixels) {
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out) << OIIO::geterror();
  OIIO::ImageSpec spec(w, h, channels, OIIO::TypeUInt8);
  spec.attribute("oiio:UnassociatedAlpha", 1);  // the pixels are straight alpha: keep them
  ASSERT_TRUE(out->open(path, spec)) << out->geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeUInt8, pixels.data())) << out->geterror();
  ASSERT_TRUE(out->close());
}

const TexCoord2 kWholeImage{{0.5f, 0.5f}, {1, 0}, {0, 1}};  // a footprint covering it all

// ---------------------------------------------------------------------------------------------
// In-memory images
// ---------------------------------------------------------------------------------------------

TEST(TextureImages, NearestReturnsExactTexelsAtCentresTopRowFirst) {
  TextureImages images(&oiio::imageDecoder);
  auto h = images.addPixels("grid", 4, 4, 4, pixels4x4(), ColorEncoding::Linear);
  ASSERT_TRUE(h.valid());
  EXPECT_EQ(images.width(h), 4);
  EXPECT_EQ(images.height(h), 4);
  EXPECT_EQ(images.channels(h), 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) {
      SCOPED_TRACE(testing::Message() << "texel " << x << "," << y);
      expectEq(images.lookup(h, centre(x, y, 4), TextureWrap::Repeat, TextureWrap::Repeat,
                             TextureFilter::Nearest),
               texel4x4(x, y));
      // Anywhere inside the texel gives the same value.
      TexCoord2 c = centre(x, y, 4);
      c.st = c.st + Vec2f{0.1f, -0.1f};
      expectEq(
          images.lookup(h, c, TextureWrap::Repeat, TextureWrap::Repeat, TextureFilter::Nearest),
          texel4x4(x, y));
    }
}

TEST(TextureImages, LinearAveragesMidwayBetweenTexelCentres) {
  TextureImages images(&oiio::imageDecoder);
  auto h = images.addPixels("grid", 4, 4, 4, pixels4x4(), ColorEncoding::Linear);
  auto avg = [](Vec4f a, Vec4f b) {
    return Vec4f{(a.x + b.x) / 2, (a.y + b.y) / 2, (a.z + b.z) / 2, (a.w + b.w) / 2};
  };
  auto lookup = [&](float s, float t) {
    return images.lookup(h, {{s, t}, {}, {}}, TextureWrap::Clamp, TextureWrap::Clamp,
                         TextureFilter::Linear);
  };
  // At a texel centre: the texel itself.
  expectNear(lookup(0.375f, 0.625f), texel4x4(1, 2), 1e-6f);
  // Midway between texels (1, 2) and (2, 2), between (0, 1) and (0, 2), and among four.
  expectNear(lookup(0.5f, 0.625f), avg(texel4x4(1, 2), texel4x4(2, 2)), 1e-6f);
  expectNear(lookup(0.125f, 0.5f), avg(texel4x4(0, 1), texel4x4(0, 2)), 1e-6f);
  expectNear(lookup(0.5f, 0.5f),
             avg(avg(texel4x4(1, 1), texel4x4(2, 1)), avg(texel4x4(1, 2), texel4x4(2, 2))), 1e-6f);
  // A quarter of the way: 3:1 weights.
  Vec4f a = texel4x4(1, 2), b = texel4x4(2, 2), q = lookup(0.4375f, 0.625f);
  EXPECT_NEAR(q.x, 0.75f * a.x + 0.25f * b.x, 1e-6f);
  EXPECT_NEAR(q.z, 0.75f * a.z + 0.25f * b.z, 1e-6f);
}

TEST(TextureImages, WrapModesOutsideTheUnitSquare) {
  TextureImages images(&oiio::imageDecoder);
  auto h = images.addPixels("grid", 4, 4, 4, pixels4x4(), ColorEncoding::Linear);
  const float t = 0.375f;  // row 1
  auto at = [&](float s, TextureWrap w) {
    return images.lookup(h, {{s, t}, {}, {}}, w, TextureWrap::Clamp, TextureFilter::Nearest);
  };
  // s = -0.1 is texel column -1 (x = -0.4), s = 1.1 is column 4 (x = 4.4).
  expectEq(at(-0.1f, TextureWrap::Repeat), texel4x4(3, 1));
  expectEq(at(1.1f, TextureWrap::Repeat), texel4x4(0, 1));
  expectEq(at(-0.1f, TextureWrap::Clamp), texel4x4(0, 1));
  expectEq(at(1.1f, TextureWrap::Clamp), texel4x4(3, 1));
  expectEq(at(-0.1f, TextureWrap::Mirror), texel4x4(0, 1));
  expectEq(at(1.1f, TextureWrap::Mirror), texel4x4(3, 1));
  expectEq(at(-0.6f, TextureWrap::Mirror), texel4x4(2, 1));  // column -3 mirrors to 2
  expectEq(at(-0.1f, TextureWrap::Black), Vec4f{0, 0, 0, 0});
  expectEq(at(1.1f, TextureWrap::Black), Vec4f{0, 0, 0, 0});
  expectEq(at(0.9f, TextureWrap::Black), texel4x4(3, 1));  // inside: untouched
  // The t direction has its own mode.
  expectEq(images.lookup(h, {{0.125f, -0.1f}, {}, {}}, TextureWrap::Clamp, TextureWrap::Repeat,
                         TextureFilter::Nearest),
           texel4x4(0, 3));
  expectEq(images.lookup(h, {{0.125f, -0.1f}, {}, {}}, TextureWrap::Repeat, TextureWrap::Clamp,
                         TextureFilter::Nearest),
           texel4x4(0, 0));
  // Black around an image without alpha stays opaque.
  auto rgb = images.addPixels("rgb", 1, 1, 3, {0.2f, 0.4f, 0.6f}, ColorEncoding::Linear);
  expectEq(images.lookup(rgb, {{1.5f, 0.5f}, {}, {}}, TextureWrap::Black, TextureWrap::Black,
                         TextureFilter::Nearest),
           Vec4f{0, 0, 0, 1});
}

TEST(TextureImages, DecodesSrgbColourButNotAlpha) {
  TextureImages images(&oiio::imageDecoder);
  std::vector<float> px{0.5f, 0.5f, 0.5f, 0.5f};
  auto s = images.addPixels("srgb", 1, 1, 4, px, ColorEncoding::Srgb);
  auto l = images.addPixels("linear", 1, 1, 4, px, ColorEncoding::Linear);
  const float want = srgbToLinear(0.5f);
  EXPECT_NEAR(want, 0.214f, 1e-3f);
  for (TextureFilter f : {TextureFilter::Nearest, TextureFilter::Linear, TextureFilter::Mipmap}) {
    SCOPED_TRACE(int(f));
    expectNear(images.lookup(s, centre(0, 0, 1), TextureWrap::Repeat, TextureWrap::Repeat, f),
               {want, want, want, 0.5f}, 1e-3f);
    expectNear(images.lookup(l, centre(0, 0, 1), TextureWrap::Repeat, TextureWrap::Repeat, f),
               {0.5f, 0.5f, 0.5f, 0.5f}, 1e-6f);
  }
}

TEST(TextureImages, GreyImagesFillRgbAndAlpha) {
  TextureImages images(&oiio::imageDecoder);
  auto g1 = images.addPixels("grey", 2, 1, 1, {0.25f, 0.75f}, ColorEncoding::Linear);
  auto g2 =
      images.addPixels("grey+alpha", 2, 1, 2, {0.25f, 0.5f, 0.75f, 0.1f}, ColorEncoding::Srgb);
  EXPECT_EQ(images.channels(g1), 1);
  EXPECT_EQ(images.channels(g2), 2);
  auto at = [&](TextureImages::Handle h, int x) {
    return images.lookup(h, {{(float(x) + 0.5f) / 2, 0.5f}, {}, {}}, TextureWrap::Repeat,
                         TextureWrap::Repeat, TextureFilter::Nearest);
  };
  expectEq(at(g1, 0), {0.25f, 0.25f, 0.25f, 1});
  expectEq(at(g1, 1), {0.75f, 0.75f, 0.75f, 1});
  float a = srgbToLinear(0.25f), b = srgbToLinear(0.75f);
  expectNear(at(g2, 0), {a, a, a, 0.5f}, 1e-6f);
  expectNear(at(g2, 1), {b, b, b, 0.1f}, 1e-6f);
}

TEST(TextureImages, MipmapFiltersOverTheFootprintInLinearSpace) {
  TextureImages images(&oiio::imageDecoder);
  const int n = 64;
  auto bw = images.addPixels("bw", n, n, 1, checker(n, 0, 1), ColorEncoding::Linear);
  // sRGB 0 and 0.5: the mean of the linear values (0.107) differs from the decoded mean of the
  // sRGB values (0.051) and from that mean undecoded (0.25).
  auto srgb = images.addPixels("srgb", n, n, 1, checker(n, 0, 0.5f), ColorEncoding::Srgb);
  const float linearMean = srgbToLinear(0.5f) / 2;
  for (TextureWrap w : {TextureWrap::Repeat, TextureWrap::Clamp, TextureWrap::Mirror}) {
    SCOPED_TRACE(int(w));
    EXPECT_NEAR(images.lookup(bw, kWholeImage, w, w, TextureFilter::Mipmap).x, 0.5f, 0.01f);
    EXPECT_NEAR(images.lookup(srgb, kWholeImage, w, w, TextureFilter::Mipmap).x, linearMean,
                0.005f);
  }
  // A zero footprint is a point sample: the texel itself, at every texel centre.
  for (int y = 0; y < n; y += 7)
    for (int x = 0; x < n; x += 5) {
      float want = (x + y) % 2 ? 1.0f : 0.0f;
      EXPECT_NEAR(images
                      .lookup(bw, centre(x, y, n), TextureWrap::Repeat, TextureWrap::Repeat,
                              TextureFilter::Mipmap)
                      .x,
                  want, 1e-6f);
    }
  // A footprint of four texels across averages the checker too; one of 1/4 texel barely does.
  TexCoord2 c = centre(10, 10, n);
  c.dstdx = {4.0f / n, 0}, c.dstdy = {0, 4.0f / n};
  EXPECT_NEAR(
      images.lookup(bw, c, TextureWrap::Repeat, TextureWrap::Repeat, TextureFilter::Mipmap).x, 0.5f,
      0.1f);
  c.dstdx = {0.25f / n, 0}, c.dstdy = {0, 0.25f / n};
  EXPECT_LT(images.lookup(bw, c, TextureWrap::Repeat, TextureWrap::Repeat, TextureFilter::Mipmap).x,
            0.1f);
  // Nearest and Linear ignore the footprint.
  EXPECT_EQ(images
                .lookup(bw, {centre(1, 0, n).st, {1, 0}, {0, 1}}, TextureWrap::Repeat,
                        TextureWrap::Repeat, TextureFilter::Linear)
                .x,
            1.0f);
}

TEST(TextureImages, MipmapKeepsTheMeanOfOddSizedImages) {
  TextureImages images(&oiio::imageDecoder);
  for (auto [w, h] : {std::pair{3, 5}, {100, 60}, {7, 2}}) {
    SCOPED_TRACE(testing::Message() << w << "x" << h);
    std::vector<float> px(size_t(w) * size_t(h));
    double sum = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) sum += px[size_t(y * w + x)] = float((x * 7 + y * 3) % 11) / 10;
    auto img = images.addPixels(std::to_string(w) + "x" + std::to_string(h), w, h, 1, px,
                                ColorEncoding::Linear);
    // OIIO picks the level from the footprint's minor axis in s-t units measured against the
    // level's smaller side, so a non-square image needs a footprint past the unit square to
    // reach its 1x1 level; that level must be the mean (OIIO's own "automip" gave 0.75, not
    // 0.49, for the 3x5 image).
    const TexCoord2 huge{{0.5f, 0.5f}, {16, 0}, {0, 16}};
    EXPECT_NEAR(
        images.lookup(img, huge, TextureWrap::Repeat, TextureWrap::Repeat, TextureFilter::Mipmap).x,
        sum / (w * h), 1e-5);
  }
}

TEST(TextureImages, RejectsBadPixelBuffersAndRepeatedNames) {
  TextureImages images(&oiio::imageDecoder);
  EXPECT_THROW(images.addPixels("short", 2, 2, 3, std::vector<float>(11), ColorEncoding::Linear),
               std::logic_error);
  EXPECT_THROW(images.addPixels("five", 1, 1, 5, std::vector<float>(5), ColorEncoding::Linear),
               std::logic_error);
  images.addPixels("a", 1, 1, 1, {0.5f}, ColorEncoding::Linear);
  EXPECT_THROW(images.addPixels("a", 1, 1, 1, {0.5f}, ColorEncoding::Linear), std::logic_error);
}

TEST(TextureImages, SameNameInTwoSetsServesEachItsOwnPixels) {
  TextureImages a, b;
  auto ha = a.addPixels("same", 1, 1, 1, {0.25f}, ColorEncoding::Linear);
  auto hb = b.addPixels("same", 1, 1, 1, {0.75f}, ColorEncoding::Linear);
  EXPECT_EQ(a.lookup(ha, centre(0, 0, 1), TextureWrap::Repeat, TextureWrap::Repeat,
                     TextureFilter::Nearest)
                .x,
            0.25f);
  EXPECT_EQ(b.lookup(hb, centre(0, 0, 1), TextureWrap::Repeat, TextureWrap::Repeat,
                     TextureFilter::Nearest)
                .x,
            0.75f);
}

// ---------------------------------------------------------------------------------------------
// Files
// ---------------------------------------------------------------------------------------------

TEST(TextureImages, ReadsPngFilesAsSrgbOrLinear) {
  const std::string dir = test::scratchDir("TextureImages.ReadsPngFiles");
  const std::string path = dir + "/checker.png";
  const int n = 64;
  // RGBA: a checker of 0 and 128 in RGB (128 on blue only in odd texels), alpha 255 or 51.
  std::vector<unsigned char> px;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      bool odd = (x + y) % 2;
      px.insert(
          px.end(),
          {static_cast<unsigned char>(odd ? 128 : 0), static_cast<unsigned char>(odd ? 128 : 0),
           static_cast<unsigned char>(128), static_cast<unsigned char>(odd ? 51 : 255)});
    }
  writePng(path, n, n, 4, px);

  TextureImages images(&oiio::imageDecoder);
  auto s = images.addFile(path, ColorEncoding::Srgb);
  auto l = images.addFile(path, ColorEncoding::Linear);
  EXPECT_EQ(images.width(s), n);
  EXPECT_EQ(images.height(s), n);
  EXPECT_EQ(images.channels(s), 4);
  EXPECT_EQ(images.width(l), n);
  const float v = 128.0f / 255.0f, lin = srgbToLinear(v), a = 51.0f / 255.0f;
  auto at = [&](TextureImages::Handle h, const TexCoord2& c, TextureFilter f) {
    return images.lookup(h, c, TextureWrap::Repeat, TextureWrap::Repeat, f);
  };
  // Texels: straight (not premultiplied) colour, alpha never decoded.
  expectNear(at(s, centre(1, 0, n), TextureFilter::Nearest), {lin, lin, lin, a}, 1e-3f);
  expectNear(at(s, centre(0, 0, n), TextureFilter::Nearest), {0, 0, lin, 1}, 1e-3f);
  expectNear(at(l, centre(1, 0, n), TextureFilter::Nearest), {v, v, v, a}, 1e-6f);
  expectNear(at(s, centre(5, 2, n), TextureFilter::Mipmap), {lin, lin, lin, a}, 1e-3f);
  // The whole-image mean is the mean of linear values.
  expectNear(at(s, kWholeImage, TextureFilter::Mipmap), {lin / 2, lin / 2, lin, (1 + a) / 2},
             0.005f);
  expectNear(at(l, kWholeImage, TextureFilter::Mipmap), {v / 2, v / 2, v, (1 + a) / 2}, 0.005f);
}

// The bytes of a file.
std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(TextureImages, EncodedImagesDecodeInTheBackgroundLikeDecodedPixels) {
  const std::string dir = test::scratchDir("TextureImages.EncodedImages");
  const int n = 64;
  std::vector<unsigned char> px;
  std::mt19937 rng(7);
  for (int i = 0; i < n * n * 4; ++i) px.push_back(static_cast<unsigned char>(rng() & 255));
  writePng(dir + "/noise.png", n, n, 4, px);
  auto bytes = std::make_shared<const std::string>(fileBytes(dir + "/noise.png"));

  const EncodedImageInfo info = oiio::plugin().probeEncodedImage(*bytes);
  EXPECT_EQ(info.width, n);
  EXPECT_EQ(info.height, n);
  EXPECT_EQ(info.channels, 4);
  EXPECT_EQ(info.bits, 8);
  const std::vector<float> decoded = oiio::plugin().decodeEncodedImage(*bytes, nullptr);
  ASSERT_EQ(decoded.size(), px.size());
  for (size_t i = 0; i < px.size(); ++i) ASSERT_NEAR(decoded[i], px[i] / 255.0f, 1e-6f) << i;

  for (ColorEncoding enc : {ColorEncoding::Srgb, ColorEncoding::Linear}) {
    TextureImages images(&oiio::imageDecoder);
    auto e = images.addEncoded("encoded", bytes, enc);
    auto d = images.addPixels("decoded", n, n, 4, decoded, enc);
    EXPECT_EQ(images.width(e), n);  // known from the header, before any decoding
    EXPECT_EQ(images.channels(e), 4);
    images.startDecoding();
    // Lookups may start while the decode runs: they wait for it. Halves hold the 8-bit
    // values' linear images to half precision (3 significant digits).
    std::mt19937 pick(3);
    std::uniform_real_distribution<float> u(0, 1);
    for (TextureFilter f : {TextureFilter::Nearest, TextureFilter::Linear, TextureFilter::Mipmap})
      for (int i = 0; i < 200; ++i) {
        TexCoord2 c;
        c.st = {u(pick), u(pick)};
        c.dstdx = {0.01f * u(pick), 0};
        c.dstdy = {0, 0.01f * u(pick)};
        const Vec4f a = images.lookup(e, c, TextureWrap::Repeat, TextureWrap::Repeat, f);
        const Vec4f b = images.lookup(d, c, TextureWrap::Repeat, TextureWrap::Repeat, f);
        for (int k = 0; k < 4; ++k) ASSERT_NEAR(a[k], b[k], 1e-3f * std::max(1.0f, b[k]));
      }
    EXPECT_TRUE(images.waitForDecodes().empty());
  }
}

TEST(TextureImages, EncodedImagesThatDoNotDecodeAreReportedByName) {
  const std::string dir = test::scratchDir("TextureImages.EncodedBroken");
  std::vector<unsigned char> px;
  std::mt19937 rng(5);
  for (int i = 0; i < 32 * 32 * 3; ++i) px.push_back(static_cast<unsigned char>(rng() & 255));
  writePng(dir + "/noise.png", 32, 32, 3, px);
  std::string whole = fileBytes(dir + "/noise.png");
  // The header survives, most of the pixel data does not.
  auto cut = std::make_shared<const std::string>(whole.substr(0, whole.size() / 3));
  TextureImages images(&oiio::imageDecoder);
  EXPECT_THROW(oiio::plugin().probeEncodedImage("not an image"), std::runtime_error);
  auto h = images.addEncoded("cut", cut, ColorEncoding::Srgb);
  EXPECT_EQ(images.width(h), 32);
  const auto failed = images.waitForDecodes();
  ASSERT_EQ(failed.size(), 1u);
  EXPECT_EQ(failed[0].first, "cut");
  EXPECT_FALSE(failed[0].second.empty());
  // A lookup of it is bad input naming the image (exit code 2), not an internal error.
  try {
    images.lookup(h, centre(1, 1, 32), TextureWrap::Repeat, TextureWrap::Repeat,
                  TextureFilter::Linear);
    ADD_FAILURE() << "no exception";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "cut: " + failed[0].second);
  }
}

TEST(TextureImages, MissingFileThrowsWithThePath) {
  TextureImages images(&oiio::imageDecoder);
  const std::string path = test::scratchDir("TextureImages.MissingFile") + "/nothere.png";
  for (ColorEncoding enc : {ColorEncoding::Linear, ColorEncoding::Srgb}) {
    try {
      images.addFile(path, enc);
      ADD_FAILURE() << "no exception";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), path + ": no such file");
    }
  }
}

TEST(TextureImages, CorruptFileThrows) {
  const std::string path = test::scratchDir("TextureImages.CorruptFile") + "/noise.png";
  {
    std::ofstream out(path, std::ios::binary);
    std::mt19937 rng(1);
    for (int i = 0; i < 4096; ++i) out.put(char(rng() & 0xff));
  }
  TextureImages images(&oiio::imageDecoder);
  for (ColorEncoding enc : {ColorEncoding::Linear, ColorEncoding::Srgb}) {
    try {
      images.addFile(path, enc);
      ADD_FAILURE() << "no exception";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
      EXPECT_GT(std::string(e.what()).size(), path.size() + 2) << "no reason given";
    }
  }
}

TEST(TextureImages, ReadsTheKhronosCesiumLogo) {
  const std::string path = test::assetsDir() + "/gltf/BoxTextured/glTF/CesiumLogoFlat.png";
  ASSERT_TRUE(std::filesystem::exists(path))
      << path << " is missing: set GLINT_ASSETS to the shared asset folder "
      << "(benchmarks/get_assets.sh explains how to get it)";
  TextureImages images(&oiio::imageDecoder);
  auto h = images.addFile(path, ColorEncoding::Srgb);
  EXPECT_EQ(images.width(h), 256);
  EXPECT_EQ(images.height(h), 256);
  EXPECT_EQ(images.channels(h), 4);
  // Texels agree with the file read directly and decoded here.
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in) << OIIO::geterror();
  std::vector<unsigned char> px(256 * 256 * 4);
  ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeUInt8, px.data()));
  for (auto [x, y] : {std::pair{0, 0}, {128, 128}, {40, 200}, {255, 17}}) {
    const unsigned char* p = &px[(size_t(y) * 256 + size_t(x)) * 4];
    ASSERT_EQ(p[3], 255) << "expected an opaque texel";
    expectNear(
        images.lookup(h, centre(x, y, 256), TextureWrap::Repeat, TextureWrap::Repeat,
                      TextureFilter::Nearest),
        {srgbToLinear(p[0] / 255.0f), srgbToLinear(p[1] / 255.0f), srgbToLinear(p[2] / 255.0f), 1},
        1e-3f);
  }
}

// ---------------------------------------------------------------------------------------------
// Threads and the Texture interface
// ---------------------------------------------------------------------------------------------

TEST(TextureImages, LookupsFromTwoThreadsMatchSingleThreaded) {
  // One image in memory and one sRGB PNG (glint's decoding ImageInput), 256x256 RGB noise.
  const int n = 256;
  std::mt19937 rng(7);
  std::vector<unsigned char> bytes(size_t(n) * n * 3);
  for (unsigned char& v : bytes) v = static_cast<unsigned char>(rng() & 0xff);
  std::vector<float> px(bytes.size());
  for (size_t i = 0; i < px.size(); ++i) px[i] = bytes[i] / 255.0f;
  const std::string png = test::scratchDir("TextureImages.LookupsFromTwoThreads") + "/noise.png";
  writePng(png, n, n, 3, bytes);

  std::vector<TexCoord2> coords(4000);
  std::uniform_real_distribution<float> st(-1, 2), d(-0.02f, 0.02f);
  for (TexCoord2& c : coords) c = {{st(rng), st(rng)}, {d(rng), d(rng)}, {d(rng), d(rng)}};
  using Handles = std::pair<TextureImages::Handle, TextureImages::Handle>;
  auto add = [&](TextureImages& images) {
    return Handles{images.addPixels("noise", n, n, 3, px, ColorEncoding::Srgb),
                   images.addFile(png, ColorEncoding::Srgb)};
  };
  auto run = [&](const TextureImages& images, Handles h, std::vector<Vec4f>& out) {
    out.resize(coords.size());
    for (size_t i = 0; i < coords.size(); ++i)
      out[i] = images.lookup(i % 2 ? h.second : h.first, coords[i], TextureWrap::Repeat,
                             TextureWrap::Mirror, TextureFilter(i / 2 % 3));
  };
  std::vector<Vec4f> single, again, a, b;
  {
    TextureImages images(&oiio::imageDecoder);
    Handles h = add(images);
    run(images, h, single);
    run(images, h, again);  // now from a warm cache
  }
  {
    // A fresh set: both threads fill the cache (tiles, MIP levels) at the same time.
    TextureImages images(&oiio::imageDecoder);
    Handles h = add(images);
    std::thread t1([&] { run(images, h, a); });
    std::thread t2([&] { run(images, h, b); });
    t1.join();
    t2.join();
  }
  int mismatches = 0;
  for (size_t i = 0; i < coords.size(); ++i)
    for (const std::vector<Vec4f>* other : {&again, &a, &b}) {
      Vec4f p = single[i], q = (*other)[i];
      mismatches += !(p.x == q.x && p.y == q.y && p.z == q.z && p.w == q.w);
    }
  EXPECT_EQ(mismatches, 0);
}

TEST(TextureImages, DamagedPixelsThrowWhenReadInMemoryAndOnLookupInTheCache) {
  // An uncompressed 128x128 EXR cut in half: the header reads, the lower rows do not.
  const std::string path = test::scratchDir("TextureImages.DamagedPixels") + "/cut.exr";
  const int n = 128;
  {
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(n, n, 3, OIIO::TypeFloat);
    spec.attribute("compression", "none");
    std::vector<float> px(size_t(n) * n * 3, 0.5f);
    ASSERT_TRUE(out->open(path, spec) && out->write_image(OIIO::TypeFloat, px.data()) &&
                out->close());
  }
  std::filesystem::resize_file(path, std::filesystem::file_size(path) / 2);
  for (ColorEncoding enc : {ColorEncoding::Linear, ColorEncoding::Srgb}) {
    TextureImages images(&oiio::imageDecoder);
    // Kept in memory (what a small untiled file gets): decoded when added, so adding fails.
    for (TextureStorage where : {TextureStorage::Auto, TextureStorage::Memory}) {
      try {
        images.addFile(path, enc, where);
        ADD_FAILURE() << "no exception";
      } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
      }
    }
    // In the cache: read tile by tile, so the damage shows when a lookup reaches it.
    auto h = images.addFile(path, enc, TextureStorage::Cache);
    EXPECT_EQ(images.width(h), n);
    EXPECT_EQ(images.storage(h), TextureStorage::Cache);
    try {
      images.lookup(h, centre(10, n - 4, n), TextureWrap::Repeat, TextureWrap::Repeat,
                    TextureFilter::Linear);
      ADD_FAILURE() << "no exception";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
      // The path once: the plugin gives the reason, TextureImages the name.
      EXPECT_EQ(std::string(e.what()).find(path + ": ", 1), std::string::npos) << e.what();
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Where images live: memory or OpenImageIO's cache, chosen per image, serving the same texels
// ---------------------------------------------------------------------------------------------

// A smooth 8-bit RGBA image with some fine detail: gradients, a ring pattern and noise.
std::vector<unsigned char> smoothImage(int w, int h) {
  std::vector<unsigned char> px;
  std::mt19937 rng(11);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float r = std::hypot(float(x - w / 2), float(y - h / 3));
      const float ring = 0.5f + 0.5f * std::sin(r * 0.35f);
      px.insert(px.end(),
                {static_cast<unsigned char>(255.0f * float(x) / float(w - 1)),
                 static_cast<unsigned char>(255.0f * ring), static_cast<unsigned char>(rng() % 256),
                 static_cast<unsigned char>(128 + 127.0f * float(y) / float(h - 1))});
    }
  return px;
}

TEST(TextureImages, SmallFilesLiveInMemoryAndTiledMipmappedFilesInTheCache) {
  const std::string dir = test::scratchDir("TextureImages.Storage");
  const int n = 128;
  writePng(dir + "/plain.png", n, n, 4, smoothImage(n, n));
  // A .tx as maketx makes it: tiled, with every MIP level in the file.
  OIIO::ImageBuf src(dir + "/plain.png");
  OIIO::ImageSpec config;
  config.tile_width = config.tile_height = 32;
  ASSERT_TRUE(OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, src,
                                               dir + "/tiled.tx", config))
      << OIIO::geterror();

  TextureImages images(&oiio::imageDecoder);
  auto png = images.addFile(dir + "/plain.png", ColorEncoding::Srgb);
  auto tx = images.addFile(dir + "/tiled.tx", ColorEncoding::Srgb);
  EXPECT_EQ(images.storage(png), TextureStorage::Memory);
  EXPECT_EQ(images.storage(tx), TextureStorage::Cache);
  // 128² + 64² + ... + 1 texels of 4 bytes: the pyramid, 8-bit as the file is.
  EXPECT_EQ(images.residentBytes(png), size_t(21845) * 4);
  EXPECT_EQ(images.residentBytes(tx), 0u);
  EXPECT_NE(images.describe(png).find("in memory (8-bit MIP pyramid"), std::string::npos)
      << images.describe(png);
  EXPECT_NE(images.describe(tx).find("texture cache (8 MIP levels in the file)"), std::string::npos)
      << images.describe(tx);
  // Asked for, either storage serves either file.
  auto pngCached = images.addFile(dir + "/plain.png", ColorEncoding::Linear, TextureStorage::Cache);
  auto txInMemory =
      images.addFile(dir + "/tiled.tx", ColorEncoding::Linear, TextureStorage::Memory);
  EXPECT_EQ(images.storage(pngCached), TextureStorage::Cache);
  EXPECT_EQ(images.storage(txInMemory), TextureStorage::Memory);
  for (auto h : {png, tx, pngCached, txInMemory}) EXPECT_EQ(images.width(h), n);
}

// The in-memory pyramid and OpenImageIO's TextureSystem, on the same file at the same points:
// point lookups agree to the 8-bit step; filtered ones to a small fraction of the signal, and
// anisotropic footprints keep detail across their minor axis in both.
TEST(TextureImages, MemoryAndCacheServeTheSameTexels) {
  const std::string dir = test::scratchDir("TextureImages.MemoryAndCache");
  const int w = 256, h = 128;
  writePng(dir + "/image.png", w, h, 4, smoothImage(w, h));
  for (ColorEncoding enc : {ColorEncoding::Srgb, ColorEncoding::Linear}) {
    SCOPED_TRACE(enc == ColorEncoding::Srgb ? "sRGB" : "linear");
    TextureImages images(&oiio::imageDecoder);
    auto mem = images.addFile(dir + "/image.png", enc, TextureStorage::Memory);
    auto cache = images.addFile(dir + "/image.png", enc, TextureStorage::Cache);
    ASSERT_EQ(images.storage(mem), TextureStorage::Memory);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> st(-0.5f, 1.5f), u(0, 1);
    for (TextureWrap wrap :
         {TextureWrap::Repeat, TextureWrap::Clamp, TextureWrap::Mirror, TextureWrap::Black})
      for (TextureFilter f : {TextureFilter::Nearest, TextureFilter::Linear}) {
        SCOPED_TRACE(testing::Message() << "wrap " << int(wrap) << " filter " << int(f));
        for (int i = 0; i < 500; ++i) {
          const TexCoord2 c{{st(rng), st(rng)}, {}, {}};
          const Vec4f a = images.lookup(mem, c, wrap, wrap, f);
          const Vec4f b = images.lookup(cache, c, wrap, wrap, f);
          for (int k = 0; k < 4; ++k) ASSERT_NEAR(a[k], b[k], 2e-3f) << c.st.x << "," << c.st.y;
        }
      }
    // Filtered: isotropic footprints of 0.5 to 16 texels, and footprints 4-8 times longer
    // than wide. Both sides filter differently in detail (OpenImageIO weights its probes along
    // the major axis and blends levels its own way), so compare the mean absolute difference
    // with the image's own variation at the same points.
    for (bool elongated : {false, true}) {
      SCOPED_TRACE(elongated ? "elongated" : "isotropic");
      double diff = 0, spread = 0;
      const int count = 2000;
      for (int i = 0; i < count; ++i) {
        const float texels = std::exp2(-1.0f + 5.0f * u(rng));
        const float angle = 6.2831853f * u(rng), ratio = elongated ? 4.0f + 4.0f * u(rng) : 1.0f;
        const Vec2f major{std::cos(angle) * texels * ratio / w,
                          std::sin(angle) * texels * ratio / h};
        const Vec2f minor{-std::sin(angle) * texels / w, std::cos(angle) * texels / h};
        const TexCoord2 c{{u(rng), u(rng)}, major, minor};
        const Vec4f a =
            images.lookup(mem, c, TextureWrap::Repeat, TextureWrap::Repeat, TextureFilter::Mipmap);
        const Vec4f b = images.lookup(cache, c, TextureWrap::Repeat, TextureWrap::Repeat,
                                      TextureFilter::Mipmap);
        const Vec4f point = images.lookup(mem, {c.st, {}, {}}, TextureWrap::Repeat,
                                          TextureWrap::Repeat, TextureFilter::Linear);
        for (int k = 0; k < 4; ++k) {
          diff += std::abs(a[k] - b[k]);
          spread += std::abs(point[k] - 0.5f);
        }
      }
      diff /= 4 * count, spread /= 4 * count;
      EXPECT_LT(diff, 0.03) << "mean |memory - cache|; the image's mean |x - 0.5| is " << spread;
    }
  }
}

// A footprint long along the stripes of an image keeps them; one long across them averages
// them away. Isotropic filtering of the major axis would blur both.
TEST(MipMapFilter, AnisotropicFootprintsBlurOnlyAlongTheirMajorAxis) {
  const int n = 64;
  std::vector<float> stripes(size_t(n) * n);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) stripes[size_t(y * n + x)] = x % 2 ? 1.0f : 0.0f;  // columns
  const MipMap m = MipMap::fromFloats(n, n, 1, stripes, ColorEncoding::Linear);
  EXPECT_EQ(m.levelCount(), 7);
  const float texel = 1.0f / n;
  // At the centre of an odd column: 1 across half a texel; along it 8 texels long.
  const Vec2f at{(5 + 0.5f) * texel, 0.5f};
  const TexCoord2 along{at, {0, 8 * texel}, {0.5f * texel, 0}};
  const TexCoord2 across{at, {8 * texel, 0}, {0, 0.5f * texel}};
  EXPECT_NEAR(m.lookup(along, TextureWrap::Repeat, TextureWrap::Repeat, TextureFilter::Mipmap).x,
              1.0f, 1e-5f);
  EXPECT_NEAR(m.lookup(across, TextureWrap::Repeat, TextureWrap::Repeat, TextureFilter::Mipmap).x,
              0.5f, 0.07f);
  // Beyond kMaxAnisotropy the minor axis widens: a 1/2 x 64 texel footprint reads level 3.
  const TexCoord2 needle{at, {0, 32 * texel}, {0.5f * texel, 0}};
  EXPECT_NEAR(m.lookup(needle, TextureWrap::Repeat, TextureWrap::Repeat, TextureFilter::Mipmap).x,
              0.5f, 1e-5f);
}

// 8-bit sRGB images keep their pyramid 8-bit and sRGB-encoded, averaged in linear space: a
// black and white checker's coarse levels are linear 0.5 (sRGB 188), not sRGB 128 (linear 0.22).
TEST(MipMapFilter, EightBitSrgbLevelsAverageInLinearSpace) {
  const int n = 16;
  std::vector<uint8_t> px(size_t(n) * n * 3);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      for (int c = 0; c < 3; ++c) px[size_t((y * n + x) * 3 + c)] = (x + y) % 2 ? 255 : 0;
  const MipMap m = MipMap::fromBytes(n, n, 3, px, ColorEncoding::Srgb);
  EXPECT_EQ(m.texel(), MipMap::Texel::Byte);
  EXPECT_EQ(m.bytes(), MipMap::residentBytes(n, n, 3, MipMap::Texel::Byte));
  EXPECT_EQ(m.bytes(), size_t(16 * 16 + 8 * 8 + 4 * 4 + 2 * 2 + 1) * 3);
  const TexCoord2 wide{{0.5f, 0.5f}, {4.0f / n, 0}, {0, 4.0f / n}};
  const Vec4f v = m.lookup(wide, TextureWrap::Repeat, TextureWrap::Repeat, TextureFilter::Mipmap);
  // The nearest 8-bit sRGB code to linear 0.5 is 188 (0.5029).
  EXPECT_NEAR(v.x, srgbToLinear(188 / 255.0f), 1e-6f);
  EXPECT_NEAR(v.x, 0.5f, 0.004f);
  EXPECT_EQ(v.w, 1.0f);
  // Level 0 is the bytes themselves, decoded exactly.
  EXPECT_EQ(
      m.lookup(centre(1, 0, n), TextureWrap::Repeat, TextureWrap::Repeat, TextureFilter::Nearest).x,
      1.0f);
}

TEST(ImageTexture, UvScaleAndOffsetRepeatTheImage) {
  TextureImages images(&oiio::imageDecoder);
  auto h = images.addPixels("grid", 4, 4, 4, pixels4x4(), ColorEncoding::Linear);
  TextureMapping m;
  m.scale = {2, 2, 1};
  m.offset = {0.25f, 0, 0};
  ImageTexture tex(images, h, m, TextureWrap::Repeat, TextureWrap::Repeat, TextureFilter::Nearest);
  EXPECT_TRUE(tex.isImage());
  TextureNeeds needs = tex.needs();
  EXPECT_TRUE(needs.uvs);
  EXPECT_FALSE(needs.objectSpace);
  EXPECT_FALSE(needs.footprint);
  auto at = [&](float u, float v) {
    TexturePoint tp;
    tp.uv = {u, v};
    return tex.evaluate(tp);
  };
  // uv (0.05, 0.05) -> st (0.35, 0.1): texel (1, 0); half a uv period on, the same texel.
  expectEq(at(0.05f, 0.05f), texel4x4(1, 0));
  expectEq(at(0.55f, 0.05f), texel4x4(1, 0));
  expectEq(at(0.55f, 0.55f), texel4x4(1, 0));
  // uv (0.2, 0.3) -> st (0.65, 0.6): texel (2, 2).
  expectEq(at(0.2f, 0.3f), texel4x4(2, 2));
  expectEq(at(0.7f, 0.8f), texel4x4(2, 2));

  TextureMapping world;
  world.space = TextureMapping::Space::Object;
  ImageTexture mip(images, h, world, TextureWrap::Repeat, TextureWrap::Repeat,
                   TextureFilter::Mipmap);
  needs = mip.needs();
  EXPECT_FALSE(needs.uvs);
  EXPECT_TRUE(needs.objectSpace);
  EXPECT_TRUE(needs.footprint);
  EXPECT_THROW(ImageTexture(images, TextureImages::Handle{}, m, TextureWrap::Repeat,
                            TextureWrap::Repeat, TextureFilter::Linear),
               std::logic_error);
}

}  // namespace
}  // namespace glint
