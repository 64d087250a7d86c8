// glint — pieces of a frame for distributed rendering: the arguments of `glint render --crop
// X0,Y0,X1,Y1` and `--tile I/N` (`glint assemble`, apps/assemble_command.cpp, stitches the
// pieces).
#pragma once

#include <string>
#include <vector>

#include "renderer/render.h"

namespace glint::app {

// "X0,Y0,X1,Y1": pixels [X0, X1) x [Y0, Y1), integers with X0 < X1 and Y0 < Y1, X0, Y0 >= 0.
// Whether it fits the image is checked when the image size is known. Throws InputError naming
// what is wrong.
PixelWindow parseCropWindow(const std::string& text);

// "I/N": the I-th (from 0) of N tiles, 0 <= I < N. Throws InputError.
struct TileSpec {
  int index = 0, count = 1;
};
TileSpec parseTileSpec(const std::string& text);

}  // namespace glint::app
