// Bad input through the `glint` command line: every malformed file or option exits with code 2,
// prints one line naming the file (and JSON pointer where there is one), does not crash, and
// never writes or replaces an output image.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "test_support.h"

namespace glint {
namespace {

namespace fs = std::filesystem;

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

size_t lineCount(const std::string& s) {
  size_t n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

// Runs `glint render ARGS -o OUT` over a pre-existing "good" OUT and checks the contract.
void expectRejected(const std::string& name, const std::string& args,
                    const std::vector<std::string>& mustMention) {
  std::string dir = test::scratchDir("bad_input_" + name);
  std::string out = dir + "/out.png";
  const std::string good = "a previous good image";
  std::ofstream(out) << good;
  test::CommandResult r = test::runGlint("render " + args + " -o '" + out + "'");
  EXPECT_EQ(r.exitCode, 2) << name << ": stderr: " << r.err;
  EXPECT_EQ(lineCount(r.err), 1u) << name << ": expected a one-line message, got: " << r.err;
  EXPECT_EQ(r.err.rfind("glint: ", 0), 0u) << name << ": " << r.err;
  for (const std::string& m : mustMention)
    EXPECT_NE(r.err.find(m), std::string::npos)
        << name << ": message lacks '" << m << "': " << r.err;
  EXPECT_EQ(readFile(out), good) << name << ": the previous output was touched";
  // No temporary files left behind either.
  size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
  EXPECT_EQ(files, 1u) << name;
}

std::string shellQuote(const std::string& s) { return "'" + s + "'"; }

// Each malformed glTF in tests/data/bad, with the JSON pointer (or phrase) its message names.
struct BadFile {
  const char* file;
  const char* mention;
};

class BadGltfFile : public testing::TestWithParam<BadFile> {};

TEST_P(BadGltfFile, IsRejectedWithExitCode2AndNoOutput) {
  const BadFile& c = GetParam();
  std::string path = test::dataDir() + "/bad/" + c.file;
  ASSERT_TRUE(fs::exists(path)) << path;
  expectRejected(fs::path(c.file).stem().string(), shellQuote(path), {c.file, c.mention});
}

INSTANTIATE_TEST_SUITE_P(
    Cli, BadGltfFile,
    testing::Values(BadFile{"truncated.glb", "truncated"},
                    BadFile{"accessor_out_of_bounds.gltf", "/accessors/"},
                    BadFile{"buffer_view_out_of_bounds.gltf", "/bufferViews/"},
                    BadFile{"missing_bin.gltf", "/buffers/0/uri"},
                    BadFile{"index_out_of_range.gltf", "/meshes/0/primitives/0/indices"},
                    BadFile{"nan_positions.gltf", "/accessors/"},
                    BadFile{"inf_positions.gltf", "/accessors/"},
                    BadFile{"zero_length_normals.gltf", "/accessors/"},
                    BadFile{"camera_znear_ge_zfar.gltf", "/cameras/0/perspective/zfar"},
                    BadFile{"buffer_uri_outside_folder.gltf", "/buffers/0/uri"},
                    BadFile{"absolute_uri.gltf", "/buffers/0/uri"},
                    BadFile{"json_syntax_error.gltf", "syntax error"},
                    BadFile{"wrong_type.gltf", "wrong_type.gltf"},
                    BadFile{"unsupported_required_extension.gltf", "/extensionsRequired/0"},
                    BadFile{"material_index_out_of_range.gltf", "/meshes/0/primitives/0/material"},
                    BadFile{"node_cycle.gltf", "/nodes/"},
                    BadFile{"singular_matrix.gltf", "/nodes/0/matrix"},
                    BadFile{"bin_too_short.gltf", "/buffers/0"}),
    [](const testing::TestParamInfo<BadFile>& p) {
      std::string n = fs::path(p.param.file).stem().string();
      for (char& ch : n)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      return n;
    });

TEST(CliBadInput, MissingSceneFile) {
  std::string path = test::dataDir() + "/bad/does_not_exist.gltf";
  expectRejected("missing_file", shellQuote(path), {"does_not_exist.gltf"});
}

// A sidecar next to a copy of a good scene, with one problem each.
void expectBadSidecar(const std::string& name, const std::string& sidecar,
                      const std::vector<std::string>& mention) {
  std::string dir = test::scratchDir("bad_sidecar_" + name);
  fs::copy_file(test::dataDir() + "/scenes/lambert_plane.gltf", dir + "/scene.gltf");
  std::ofstream(dir + "/scene.glint.json") << sidecar;
  std::vector<std::string> all = mention;
  all.push_back("scene.glint.json");
  expectRejected(name, shellQuote(dir + "/scene.gltf"), all);
}

TEST(CliBadInput, SidecarJsonSyntaxErrorReportsLineAndColumn) {
  expectBadSidecar("syntax", "{\n  \"render\": {\"spp\": 4,,}\n}\n", {":2:"});
}

TEST(CliBadInput, ObjectWithNegativeRadius) {
  expectBadSidecar("negative_radius", R"({"objects": [{"type": "sphere", "radius": -1}]})",
                   {"/objects/0/radius", "must be > 0"});
}

TEST(CliBadInput, ObjectWithNonFiniteSize) {
  expectBadSidecar("nonfinite_radius", R"({"objects": [{"type": "cone", "radius": 1e39,
                   "height": 1}]})",
                   {"/objects/0/radius", "finite"});
}

TEST(CliBadInput, ObjectWithSingularTransform) {
  expectBadSidecar("singular_object", R"({"objects": [{"type": "box", "min": [0, 0, 0],
                   "max": [1, 1, 1], "transform": [{"shear": {"xy": 2, "yx": 0.5}}]}]})",
                   {"/objects/0/transform/0/shear", "singular"});
}

TEST(CliBadInput, CsgFileWithStackUnderflow) {
  std::string dir = test::scratchDir("bad_csg_file");
  fs::copy_file(test::dataDir() + "/scenes/lambert_plane.gltf", dir + "/scene.gltf");
  std::ofstream(dir + "/tree.csg") << "sphere center 0 0 0 radius 1\ndifference\n";
  std::ofstream(dir + "/scene.glint.json")
      << R"({"objects": [{"type": "csg", "file": "tree.csg"}]})";
  expectRejected("csg_underflow", shellQuote(dir + "/scene.gltf"), {"tree.csg:2", "underflow"});
}

// A .vol grid whose header asks for 4096^3 values over a file of a few bytes: exit code 2
// naming the sidecar's key and the .vol file (it was "cannot build the scene: std::bad_alloc",
// exit code 1).
TEST(CliBadInput, VolFileWithAHeaderLargerThanTheFile) {
  std::string dir = test::scratchDir("bad_vol_file");
  fs::copy_file(test::dataDir() + "/scenes/lambert_plane.gltf", dir + "/scene.gltf");
  {
    std::ofstream vol(dir + "/smoke.vol", std::ios::binary);
    vol.write("VOL\3", 4);
    const int32_t header[5] = {1, 4096, 4096, 4096, 1};
    const float box[6] = {0, 0, 0, 1, 1, 1};
    vol.write(reinterpret_cast<const char*>(header), sizeof header);
    vol.write(reinterpret_cast<const char*>(box), sizeof box);
  }
  std::ofstream(dir + "/scene.glint.json")
      << R"({"media": [{"sigma_s": 1, "density": {"type": "grid", "file": "smoke.vol"}}]})";
  expectRejected("vol_header", shellQuote(dir + "/scene.gltf"),
                 {"scene.glint.json: /media/0/density/file: ", "smoke.vol: truncated data"});
}

TEST(CliBadInput, UnknownMaterialType) {
  expectBadSidecar("unknown_material_type", R"({"materials": [{"name": "m", "type": "velvet"}]})",
                   {"/materials/0/type", "velvet"});
}

TEST(CliBadInput, NegativeIor) {
  expectBadSidecar("negative_ior",
                   R"({"materials": [{"name": "m", "type": "glass", "ior": -1.5}]})",
                   {"/materials/0/ior", "must be > 0"});
}

TEST(CliBadInput, RoughnessOutsideTheUnitInterval) {
  expectBadSidecar("roughness_range",
                   R"({"materials": [{"name": "m", "type": "pbr", "roughness": 1.2}]})",
                   {"/materials/0/roughness", "<= 1"});
}

TEST(CliBadInput, MissingTextureFile) {
  expectBadSidecar("missing_texture",
                   R"({"textures": [{"name": "t", "type": "image", "file": "gone.png"}]})",
                   {"/textures/0/file", "gone.png"});
}

// A tiled, MIP-mapped EXR (which the texture cache reads tile by tile, image/oiio/textures.cpp)
// cut in half: its header reads, so the scene loads, and the damage shows only when the render
// looks the texture up. Exit code 2 naming the file (it was a std::runtime_error, which the
// render command gave as "render failed", exit code 1).
TEST(CliBadInput, TextureFileDamagedPastItsHeader) {
  std::string dir = test::scratchDir("bad_texture_tiles");
  fs::copy_file(test::dataDir() + "/scenes/lambert_plane.gltf", dir + "/scene.gltf");
  const std::string texture = dir + "/cut.exr";
  {
    // As maketx makes it: tiled, with every MIP level in the file (uncompressed: the cut loses
    // the tiles, not the offsets).
    OIIO::ImageBuf src(OIIO::ImageSpec(256, 256, 3, OIIO::TypeFloat));
    const float grey[3] = {0.5f, 0.5f, 0.5f};
    ASSERT_TRUE(OIIO::ImageBufAlgo::fill(src, grey));
    OIIO::ImageSpec config;
    config.tile_width = config.tile_height = 32;
    config.attribute("compression", "none");
    ASSERT_TRUE(
        OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, src, texture, config))
        << OIIO::geterror();
  }
  fs::resize_file(texture, fs::file_size(texture) / 2);
  std::ofstream(dir + "/scene.glint.json") << R"({
    "textures": [{"name": "t", "type": "image", "file": "cut.exr",
                  "mapping": {"space": "world", "plane": "xz"}}],
    "materials": [{"name": "Plane", "base_color": "t"}]})";
  expectRejected("texture_tiles", shellQuote(dir + "/scene.gltf") + " --spp 1", {texture + ": "});
}

TEST(CliBadInput, SidecarWrongType) {
  expectBadSidecar("wrong_type", R"({"render": {"spp": "many"}})", {"/render/spp"});
}

TEST(CliBadInput, SidecarUnknownKey) {
  expectBadSidecar("unknown_key", R"({"render": {"spq": 4}})", {"/render/spq"});
}

TEST(CliBadInput, SidecarNegativeSpp) {
  expectBadSidecar("negative_spp", R"({"render": {"spp": -4}})", {"/render/spp"});
}

TEST(CliBadInput, SidecarZeroResolution) {
  expectBadSidecar("zero_width", R"({"render": {"width": 0}})", {"/render/width"});
}

TEST(CliBadInput, SidecarNegativeLightIntensity) {
  expectBadSidecar("negative_intensity",
                   R"({"lights": [{"type": "point", "position": [0, 1, 0], "intensity": -1}]})",
                   {"/lights/0/intensity"});
}

class BadOption : public testing::TestWithParam<std::pair<const char*, const char*>> {};

TEST_P(BadOption, IsAUsageErrorWithExitCode2) {
  std::string scene = shellQuote(test::dataDir() + "/scenes/lambert_plane.gltf");
  std::string dir = test::scratchDir("bad_option");
  std::string out = dir + "/out.exr";
  test::CommandResult r =
      test::runGlint("render " + scene + " " + GetParam().first + " -o '" + out + "'");
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find(GetParam().second), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

INSTANTIATE_TEST_SUITE_P(Cli, BadOption,
                         testing::Values(std::make_pair("--spp -1", "--spp"),
                                         std::make_pair("--spp 0", "--spp"),
                                         std::make_pair("--width 0", "--width"),
                                         std::make_pair("--height -5", "--height"),
                                         std::make_pair("--threads -1", "--threads"),
                                         std::make_pair("--accel octree", "--accel"),
                                         std::make_pair("--camera Nowhere", "Nowhere"),
                                         std::make_pair("--frobnicate", "frobnicate")),
                         [](const auto& p) {
                           std::string n = p.param.first;
                           std::string out;
                           for (char ch : n)
                             if (std::isalnum(static_cast<unsigned char>(ch))) out += ch;
                           return out;
                         });

// An unknown option is a usage error that names the option meant, as an unknown sidecar key
// does (the same closestMatch), on one line.
TEST(CliBadInput, UnknownOptionSuggestsTheOptionMeant) {
  const std::string scene = shellQuote(test::dataDir() + "/scenes/lambert_plane.gltf");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"render " + scene + " --sp 4", "unknown option --sp; did you mean --spp?"},
      {"render " + scene + " --widht 8", "unknown option --widht; did you mean --width?"},
      {"render " + scene + " --sed=3", "unknown option --sed; did you mean --seed?"},
      {"info " + scene + " --intergrator path",
       "unknown option --intergrator; did you mean --integrator?"},
      {"diff a.exr b.exr --statisticl", "unknown option --statisticl; did you mean --statistical?"},
      {"tonemap in.exr --sequnce", "unknown option --sequnce; did you mean --sequence?"},
      {"render " + scene + " --frobnicate",
       "unknown option --frobnicate (`glint render --help` lists the options)"},
      {"rendr " + scene, "unknown command 'rendr'; did you mean 'render'?"},
      {"rendr " + scene + " -o x.png", "unknown command 'rendr'; did you mean 'render'?"},
      {"--frobnicate", "unknown option --frobnicate (`glint --help` lists the options)"},
      {"",
       "a command is required: 'render', 'info', 'diff', 'bench-accel', 'tonemap', "
       "'assemble', 'preview' (`glint --help` says what each does)"},
  };
  for (const auto& [args, message] : cases) {
    test::CommandResult r = test::runGlint(args);
    EXPECT_EQ(r.exitCode, 2) << args << ": " << r.err;
    EXPECT_EQ(r.err, "glint: " + message + "\n") << args;
  }
}

// A number out of range says the range in words, as the sidecar's checks do, not CLI11's
// bounds (DBL_MAX written out in 309 digits).
TEST(CliBadInput, NumericOptionsSayTheirRangeInWords) {
  const std::string scene = shellQuote(test::dataDir() + "/scenes/lambert_plane.gltf");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"render " + scene + " --width 0", "--width: must be >= 1, got 0"},
      {"render " + scene + " --height -5", "--height: must be >= 1, got -5"},
      {"render " + scene + " --spp 0", "--spp: must be >= 1, got 0"},
      {"render " + scene + " --spp 1.5", "--spp: expected a whole number, got '1.5'"},
      {"render " + scene + " --spp 9999999999", "--spp: must be <= 2147483647, got 9999999999"},
      {"render " + scene + " --threads -1", "--threads: must be >= 0, got -1"},
      {"render " + scene + " --max-depth -2", "--max-depth: must be >= 0, got -2"},
      {"render " + scene + " --adaptive -0.5", "--adaptive: must be >= 0, got -0.5"},
      {"info " + scene + " --env-strength -1", "--env-strength: must be >= 0, got -1"},
      {"tonemap in.exr --ldmax 0", "--ldmax: must be > 0, got 0"},
      {"tonemap in.exr --scene-luminance nan", "--scene-luminance: must be finite, got 'nan'"},
      {"diff a.exr b.exr --significance 0", "--significance: must be >= 1e-12 and <= 0.5, got 0"},
      {"diff a.exr b.exr --min-pass 150", "--min-pass: must be >= 0 and <= 100, got 150"},
      {"diff a.exr b.exr --fail -1", "--fail: must be >= 0, got -1"},
      {"diff a.exr b.exr --spp-a 0", "--spp-a: must be >= 1, got 0"},
  };
  for (const auto& [args, message] : cases) {
    test::CommandResult r = test::runGlint(args);
    EXPECT_EQ(r.exitCode, 2) << args << ": " << r.err;
    EXPECT_EQ(r.err, "glint: " + message + "\n") << args;
  }
}

TEST(CliBadInput, UnsupportedOutputExtension) {
  std::string scene = shellQuote(test::dataDir() + "/scenes/lambert_plane.gltf");
  std::string out = test::scratchDir("bad_ext") + "/out.bmpx";
  test::CommandResult r = test::runGlint("render " + scene + " -o '" + out + "'");
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_NE(r.err.find("out.bmpx"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST(CliBadInput, InfoRejectsBadFilesToo) {
  test::CommandResult r =
      test::runGlint("info " + shellQuote(test::dataDir() + "/bad/truncated.glb"));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("truncated.glb"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace glint
