// glint tests — the majorant grid's DDA: the cells a ray crosses, in order, contiguous, each
// with its own value, over random rays through a non-cubic grid.
#include "renderer/majorant_dda.h"

#include <gtest/gtest.h>

#include <random>

namespace glint {
namespace {

TEST(MajorantDda, VisitsTheCellsAlongTheRayInOrder) {
  const Bounds3f box{{-1, 0, 2}, {3, 1, 2.5f}};
  MajorantGrid grid(box, 7, 3, 5);
  // Every cell holds its own index, so a segment's value says which cell it came from.
  for (int z = 0; z < 5; ++z)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 7; ++x) {
        const Vec3f lo = box.lower + box.diagonal() * Vec3f{(x + 0.25f) / 7.0f, (y + 0.25f) / 3.0f,
                                                            (z + 0.25f) / 5.0f};
        const Vec3f hi = box.lower + box.diagonal() * Vec3f{(x + 0.5f) / 7.0f, (y + 0.5f) / 3.0f,
                                                            (z + 0.5f) / 5.0f};
        grid.include({lo, hi}, float(x + 7 * (y + 3 * z)));
      }
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-1, 1);
  int crossed = 0;
  for (int n = 0; n < 2000; ++n) {
    const Vec3f o{u(rng) * 4, u(rng) * 2, 2.25f + u(rng)};
    const Vec3f d{u(rng), u(rng), n % 10 == 0 ? 0.0f : u(rng)};  // some parallel to a slab
    float t0, t1, value, last = -1;
    MajorantDda dda(grid, o, d, 0, 10);
    bool first = true;
    while (dda.next(&t0, &t1, &value)) {
      ASSERT_LE(t0, t1);
      if (!first) {
        ASSERT_NEAR(t0, last, 1e-5f);  // contiguous
      }
      first = false;
      last = t1;
      // The segment's middle lies in the cell whose value it carries.
      const Vec3f p = o + d * (0.5f * (t0 + t1));
      int c[3];
      for (int a = 0; a < 3; ++a)
        c[a] = std::clamp(int((p[a] - box.lower[a]) / box.diagonal()[a] * float(grid.res(a))), 0,
                          grid.res(a) - 1);
      if (t1 - t0 > 1e-4f) {
        EXPECT_EQ(value, float(c[0] + 7 * (c[1] + 3 * c[2])));
      }
      ++crossed;
    }
  }
  EXPECT_GT(crossed, 500);  // about half the rays miss the grid
}

}  // namespace
}  // namespace glint
