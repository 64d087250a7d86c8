// glint — `glint assemble`: joins the partial EXRs of `glint render --crop/--tile` into the
// whole frame.
#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "apps/cli_common.h"
#include "apps/commands.h"
#include "apps/frames.h"
#include "image/io.h"
#include "renderer/render.h"

namespace glint::app {

namespace {

struct AssembleArgs {
  std::vector<std::string> inputs;  // files, or one pattern with a run of '#' for the tile
  std::string output;
};

// Stitches partial EXRs (each a data window of the same whole frame, as `glint render --crop`
// and `--tile` write them) into one EXR at `output`, written atomically. The pieces must agree
// on the frame size, the channels and glint's render metadata (scene, spp, seed, integrator),
// must not overlap, and must cover the whole frame; the result carries the first piece's
// metadata, with render seconds the sum of the pieces'. Pixel values are copied, never
// resampled, so an assembled frame is bit-identical to the frame rendered whole. Throws
// ImageReadError (an unreadable or inconsistent piece, a gap, an overlap) or OutputError.
void assembleExr(const std::vector<std::string>& pieces, const std::string& output) {
  if (pieces.empty()) throw ImageReadError("assemble: no input images");
  Image whole;
  std::vector<uint8_t> covered;
  double seconds = 0;
  bool interrupted = false;
  int nch = 0;
  for (const std::string& path : pieces) {
    const Image piece = readImage(path);
    if (piece.fullX != 0 || piece.fullY != 0 || piece.fullWidth <= 0 || piece.fullHeight <= 0)
      throw ImageReadError(fmt::format("{}: its display window does not start at 0,0", path));
    seconds += piece.meta.renderSeconds;
    interrupted = interrupted || piece.meta.stop == "interrupted";
    if (covered.empty()) {
      whole = piece;  // the first piece's channels, storage and metadata
      whole.x = whole.y = 0;
      whole.width = piece.fullWidth, whole.height = piece.fullHeight;
      nch = piece.channels;
      covered.assign(size_t(piece.fullWidth) * size_t(piece.fullHeight), 0);
      whole.pixels.assign(covered.size() * size_t(nch), 0.0f);
    } else {
      if (piece.fullWidth != whole.fullWidth || piece.fullHeight != whole.fullHeight)
        throw ImageReadError(fmt::format("{}: a piece of a {}x{} frame, not {}x{} like {}", path,
                                         piece.fullWidth, piece.fullHeight, whole.fullWidth,
                                         whole.fullHeight, pieces.front()));
      if (piece.names != whole.names)
        throw ImageReadError(
            fmt::format("{}: its channels differ from {}'s", path, pieces.front()));
      for (const char* key :
           {"glint:scene", "glint:spp", "glint:seed", "glint:integrator", "glint:time"})
        if (piece.attribute(key) != whole.attribute(key))
          throw ImageReadError(fmt::format("{}: {} is {}, but {} in {}: not the same render", path,
                                           key, piece.attribute(key), whole.attribute(key),
                                           pieces.front()));
    }
    if (piece.x < 0 || piece.y < 0 || piece.x + piece.width > whole.width ||
        piece.y + piece.height > whole.height)
      throw ImageReadError(fmt::format("{}: its data window leaves the frame", path));
    for (int y = 0; y < piece.height; ++y)
      for (int x = 0; x < piece.width; ++x) {
        const size_t to = size_t(piece.y + y) * size_t(whole.width) + size_t(piece.x + x);
        if (covered[to])
          throw ImageReadError(fmt::format("{}: pixel {},{} is also in an earlier piece", path,
                                           piece.x + x, piece.y + y));
        covered[to] = 1;
        const float* from =
            &piece.pixels[(size_t(y) * size_t(piece.width) + size_t(x)) * size_t(nch)];
        std::copy(from, from + nch, &whole.pixels[to * size_t(nch)]);
      }
  }
  const size_t missing = size_t(std::count(covered.begin(), covered.end(), uint8_t(0)));
  if (missing > 0) {
    const size_t first =
        size_t(std::find(covered.begin(), covered.end(), uint8_t(0)) - covered.begin());
    throw ImageReadError(
        fmt::format("assemble: {} pixel{} of the {}x{} frame in no piece (the "
                    "first at {},{})",
                    missing, missing == 1 ? "" : "s", whole.width, whole.height,
                    first % size_t(whole.width), first / size_t(whole.width)));
  }
  whole.meta.renderSeconds = seconds;
  if (interrupted) whole.meta.stop = "interrupted";
  // The frame's estimated error, not the first piece's: from its mean and variance channels.
  const int c[3] = {whole.channel("R"), whole.channel("G"), whole.channel("B")};
  const int v[3] = {whole.channel("variance.R"), whole.channel("variance.G"),
                    whole.channel("variance.B")};
  if (!whole.meta.stop.empty() && std::min({c[0], c[1], c[2], v[0], v[1], v[2]}) >= 0) {
    Film frame(whole.width, whole.height, false);
    frame.samples.assign(frame.samples.size(), uint32_t(std::max(0, whole.meta.spp)));
    for (size_t i = 0; i < covered.size(); ++i) {
      const float* p = &whole.pixels[i * size_t(nch)];
      frame.color[i] = Rgb{p[c[0]], p[c[1]], p[c[2]]};
      frame.variance[i] = Rgb{p[v[0]], p[v[1]], p[v[2]]};
    }
    whole.meta.error = estimatedRelativeError(frame);
  }
  // Read back as float, every value is exactly what the pieces stored: the writer's checksum is
  // that of the frame rendered whole.
  writeImageFile(output, std::move(whole));
}

// The pieces: the files given, where a single argument with a run of '#' stands for every
// existing file it matches (tiles/frame_0001_##.exr: the tile numbers). Throws InputError for
// a bad pattern or one that matches nothing.
std::vector<std::string> pieces(const AssembleArgs& args) {
  if (args.inputs.size() != 1) return args.inputs;
  const FramePattern pattern = parseFramePattern(args.inputs.front());
  if (!pattern.isPattern()) return args.inputs;
  std::vector<std::string> files;
  for (int n : findFrames(pattern, std::nullopt)) files.push_back(pattern.path(n));
  return files;
}

void runAssemble(const AssembleArgs& args) {
  if (std::filesystem::path(args.output).extension() != ".exr")
    throw InputError(args.output + ": glint assemble writes an EXR");
  assembleExr(pieces(args), args.output);
}

}  // namespace

void addAssembleCommand(CLI::App& app) {
  auto args = std::make_shared<AssembleArgs>();
  CLI::App* cmd = app.add_subcommand(
      "assemble", "join the partial EXRs of `glint render --crop/--tile` into the whole frame");
  cmd->add_option("inputs", args->inputs,
                  "the pieces: EXR files, or one pattern such as 'tiles/f_0001_##.exr'")
      ->required();
  cmd->add_option("-o,--output", args->output, "the whole frame (.exr)")->required();
  cmd->callback([args] { runAssemble(*args); });
}

}  // namespace glint::app
