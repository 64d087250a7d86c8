// glint — the arguments of --crop and --tile.
#include "apps/tiles.h"

#include <charconv>

#include "geometry/error.h"

namespace glint::app {

namespace {

// The integers of `text` separated by `separator`; false when anything else is there.
bool parseInts(const std::string& text, char separator, std::vector<int>* out) {
  const char* p = text.data();
  const char* end = p + text.size();
  while (true) {
    int v = 0;
    auto [next, ec] = std::from_chars(p, end, v);
    if (ec != std::errc() || next == p) return false;
    out->push_back(v);
    if (next == end) return true;
    if (*next != separator) return false;
    p = next + 1;
  }
}

}  // namespace

PixelWindow parseCropWindow(const std::string& text) {
  std::vector<int> v;
  if (!parseInts(text, ',', &v) || v.size() != 4)
    throw InputError("--crop: expected X0,Y0,X1,Y1 (four integers), got '" + text + "'");
  const PixelWindow w{v[0], v[1], v[2], v[3]};
  if (w.x0 < 0 || w.y0 < 0 || w.x1 <= w.x0 || w.y1 <= w.y0)
    throw InputError("--crop: need 0 <= X0 < X1 and 0 <= Y0 < Y1, got '" + text + "'");
  return w;
}

TileSpec parseTileSpec(const std::string& text) {
  std::vector<int> v;
  if (!parseInts(text, '/', &v) || v.size() != 2)
    throw InputError("--tile: expected I/N (two integers), got '" + text + "'");
  const TileSpec t{v[0], v[1]};
  if (t.count < 1 || t.index < 0 || t.index >= t.count)
    throw InputError("--tile: need 0 <= I < N, got '" + text + "'");
  return t;
}

}  // namespace glint::app
