// Area lights in a render: a quad light behind a knife edge casts a soft shadow (a penumbra
// of values strictly between umbra and lit) where a point light casts a hard one.
#include <gtest/gtest.h>

#include "test_support.h"

namespace glint {
namespace {

// Looking straight down at the floor x in [-0.2, 2.2]. A blocker at y = 2 covers x < -1; the
// light, centred at x = -3, y = 4, casts the blocker's edge onto the floor at x = 1: a
// 1-wide quad light gives a penumbra over x in [0.5, 1.5], a point light a hard edge.
Film renderKnifeEdge(const std::string& light, bool blocker = true) {
  const std::string text = R"({
    "render": {"width": 48, "height": 12, "spp": 64, "camera": "c", "seed": 5},
    "cameras": [{"name": "c", "type": "orthographic", "xmag": 1.2, "ymag": 0.3,
                 "position": [1, 5, 0], "look_at": [1, 0, 0], "up": [0, 0, -1]}],
    "lights": [)" + light + R"(],
    "materials": [{"name": "white", "type": "lambert", "diffuse": [0.8, 0.8, 0.8]}],
    "objects": [{"type": "plane", "material": "white"})" +
                           std::string(blocker ? R"(,
                {"type": "quad", "corner": [-10, 2, 10], "edge_u": [9, 0, 0], "edge_v": [0, 0, -20],
                 "material": "white"})"
                                               : "") +
                           "]}";
  test::Rendered r = test::renderJson(text);
  EXPECT_EQ(r.stats.nonfiniteSamples, 0u);
  return r.film;
}

// The middle rows' mean luminance per column.
std::vector<float> profile(const Film& film) {
  std::vector<float> p(size_t(film.width), 0);
  for (int y = film.height / 2 - 2; y < film.height / 2 + 2; ++y)
    for (int x = 0; x < film.width; ++x)
      p[size_t(x)] += luminance(film.color[size_t(y * film.width + x)]) / 4;
  return p;
}

// The visibility of the light per column: the blocked image over the unblocked one.
std::vector<float> visibility(const std::string& light) {
  const std::vector<float> blocked = profile(renderKnifeEdge(light)),
                           open = profile(renderKnifeEdge(light, false));
  std::vector<float> v(blocked.size());
  for (size_t x = 0; x < v.size(); ++x) {
    EXPECT_GT(open[x], 0) << x;
    v[x] = blocked[x] / open[x];
  }
  return v;
}

// Columns strictly between umbra and lit, by a margin.
int penumbraColumns(const std::vector<float>& v) {
  int n = 0;
  for (float x : v)
    if (x > 0.1f && x < 0.9f) ++n;
  return n;
}

TEST(AreaLightRender, QuadLightCastsASoftShadow) {
  const std::vector<float> soft = visibility(
      R"({"type": "quad", "corner": [-3.5, 4, -0.5], "edge_u": [1, 0, 0], "edge_v": [0, 0, 1],
          "intensity": 10})");
  const std::vector<float> hard =
      visibility(R"({"type": "point", "position": [-3, 4, 0], "intensity": 20})");
  // Both: dark under the blocker, lit beyond it.
  EXPECT_LT(soft.front(), 0.01f);
  EXPECT_LT(hard.front(), 0.01f);
  EXPECT_GT(soft.back(), 0.99f);
  EXPECT_GT(hard.back(), 0.99f);
  // The penumbra spans x in [0.5, 1.5] of the 2.4 in view: 20 of 48 columns, of which about
  // 16 lie within the margins; the point light's edge is one column of antialiasing.
  EXPECT_GE(penumbraColumns(soft), 12);
  EXPECT_LE(penumbraColumns(hard), 2);
  // The soft shadow brightens steadily across the penumbra (up to noise).
  for (size_t x = 1; x < soft.size(); ++x) EXPECT_GE(soft[x], soft[x - 1] - 0.05f) << x;
}

}  // namespace
}  // namespace glint
