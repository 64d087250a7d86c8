// glint tests — Mitsuba's .vol grids: a round trip, and every malformed file an InputError
// (SceneError) naming the file, never a std::runtime_error main would call internal.
#include "scenes/vol_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "image/io.h"
#include "scene_error_support.h"
#include "test_support.h"

namespace glint {
namespace {

using test::errorFrom;

// A .vol file's bytes, field by field: each test damages one.
struct VolBytes {
  std::string magic = "VOL";
  uint8_t version = 3;
  int32_t encoding = 1, res[3] = {2, 2, 1}, channels = 1;
  float box[6] = {0, 0, 0, 1, 1, 1};
  std::vector<float> values = {0, 0.5f, 1, 2};

  std::string bytes() const {
    std::string s = magic;
    auto put = [&s](const void* p, size_t n) { s.append(static_cast<const char*>(p), n); };
    put(&version, 1);
    put(&encoding, 4);
    put(res, sizeof res);
    put(&channels, 4);
    put(box, sizeof box);
    put(values.data(), values.size() * sizeof(float));
    return s;
  }
};

std::string writeBytes(const std::string& name, const std::string& bytes) {
  const std::string path = test::scratchDir("VolFile") + "/" + name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

// The SceneError reading `bytes` as `name` gives: about the file itself (no JSON pointer), and
// its message contains `phrase`.
void expectBadFile(const std::string& name, const std::string& bytes, const std::string& phrase) {
  SCOPED_TRACE(name);
  const std::string path = writeBytes(name, bytes);
  EXPECT_SCENE_ERROR(errorFrom([&] { readVolFile(path); }), path, "", phrase);
  // main's exit code 2: bad input, not an internal error.
  try {
    readVolFile(path);
  } catch (const Error& e) {
    EXPECT_EQ(e.exitCode(), 2) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
  }
}

TEST(VolFile, RoundTrip) {
  VolumeGrid grid;
  grid.nx = 2, grid.ny = 3, grid.nz = 1;
  grid.values = {0, 1, 2, 3, 4, 5};
  grid.bounds = {{-1, 0, 0.5f}, {1, 2, 3}};
  const std::string path = test::scratchDir("VolFile.RoundTrip") + "/smoke.vol";
  writeVolFile(path, grid);
  const VolumeGrid back = readVolFile(path);
  EXPECT_EQ(back.nx, 2);
  EXPECT_EQ(back.ny, 3);
  EXPECT_EQ(back.nz, 1);
  EXPECT_EQ(back.values, grid.values);
  EXPECT_EQ(back.bounds.lower, grid.bounds.lower);
  EXPECT_EQ(back.bounds.upper, grid.bounds.upper);
  // The same bytes as the reference layout.
  VolBytes v;
  v.res[0] = 2, v.res[1] = 3, v.res[2] = 1;
  std::memcpy(v.box, &grid.bounds.lower, sizeof(Vec3f));
  std::memcpy(v.box + 3, &grid.bounds.upper, sizeof(Vec3f));
  v.values = grid.values;
  EXPECT_EQ(test::slurp(path), v.bytes());
}

TEST(VolFile, MalformedFilesAreInputErrorsNamingTheFile) {
  VolBytes v;
  expectBadFile("empty.vol", "", "not a .vol grid");

  v = {}, v.magic = "VOX";
  expectBadFile("magic.vol", v.bytes(), "not a .vol grid");
  v = {}, v.version = 4;
  expectBadFile("version.vol", v.bytes(), "header: unsupported .vol version 4");
  v = {}, v.encoding = 2;
  expectBadFile("encoding.vol", v.bytes(), "header: unsupported encoding 2");
  v = {}, v.res[1] = 0;
  expectBadFile("zero_size.vol", v.bytes(), "header: bad resolution");
  v = {}, v.res[2] = 5000;
  expectBadFile("huge_size.vol", v.bytes(), "header: bad resolution");
  v = {}, v.channels = 3;
  expectBadFile("channels.vol", v.bytes(), "header: 3 channels");
  v = {};
  expectBadFile("short_header.vol", v.bytes().substr(0, 30), "truncated header");
  v = {};
  expectBadFile("short_data.vol", v.bytes().substr(0, v.bytes().size() - 2),
                "truncated data (the header's 2x2x1 grid needs 16 bytes of values, the file has "
                "14)");
  v = {}, v.values[2] = -1;
  expectBadFile("negative.vol", v.bytes(), "value 2: densities must be finite and >= 0");
  v = {}, v.values[3] = std::numeric_limits<float>::quiet_NaN();
  expectBadFile("nan.vol", v.bytes(), "value 3: densities must be finite and >= 0");
}

// A header asking for the largest grid over a file of a few bytes is refused before the
// 256 GiB of values are allocated (which was a std::bad_alloc, not bad input).
TEST(VolFile, AHugeHeaderOverAShortFileAllocatesNothing) {
  VolBytes v;
  v.res[0] = v.res[1] = v.res[2] = 4096;
  expectBadFile("huge_header.vol", v.bytes(), "the header's 4096x4096x4096 grid needs");
}

TEST(VolFile, MissingFileNamesIt) {
  const std::string path = test::scratchDir("VolFile.Missing") + "/nothere.vol";
  EXPECT_SCENE_ERROR(errorFrom([&] { readVolFile(path); }), path, "", "cannot open");
}

// Writing into a folder that does not exist is a failure (exit code 1), naming the file.
TEST(VolFile, AFailedWriteIsAnOutputError) {
  const std::string path = test::scratchDir("VolFile.Unwritable") + "/no/such/folder/g.vol";
  VolumeGrid grid;
  grid.nx = grid.ny = grid.nz = 1;
  grid.values = {1};
  try {
    writeVolFile(path, grid);
    ADD_FAILURE() << "no exception";
  } catch (const OutputError& e) {
    EXPECT_EQ(e.exitCode(), 1);
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace glint
