// glint — writes the VDB files of scenes/volumes/ with libopenvdb: a cumulus cloud (a dense
// core inside a mostly empty box: the case the majorant grid is for) and a small fire
// (density, temperature and flame grids). The files are generated, not stored in the tree.
//
//   cmake --build build --target glint_make_vdb_scenes
//   build/tools/glint_make_vdb_scenes scenes/volumes            # cloud.vdb, fire.vdb
//   build/tools/glint_make_vdb_scenes OUT --cloud-size 256      # a 256^3-voxel cloud box
//
// scenes/volumes/make_scenes.sh runs it. Every voxel is a pure function of its coordinates
// (Perlin noise with fixed seeds), so the files are the same on every run.
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "materials/noise.h"

using namespace glint;

namespace {

float smoothstep(float a, float b, float x) {
  const float t = std::clamp((x - a) / (b - a), 0.0f, 1.0f);
  return t * t * (3 - 2 * t);
}

// A cumulus: a few overlapping puffs with a flat base, their surface broken up by fractal
// noise; density rises from 0 at the surface to `core` inside. `n` voxels along x.
openvdb::FloatGrid::Ptr cloud(int n) {
  const float voxel = 4.0f / float(n);  // the cloud's box is about 4 x 2 x 2.4 units
  const PerlinNoise noise(7);
  struct Puff {
    Vec3f c;
    float r;
  };
  const Puff puffs[] = {{{-1.0f, 0.55f, 0.0f}, 0.7f},
                        {{-0.1f, 0.8f, 0.1f}, 0.9f},
                        {{0.9f, 0.6f, -0.1f}, 0.75f},
                        {{0.35f, 1.25f, 0.05f}, 0.6f},
                        {{-0.55f, 1.1f, 0.2f}, 0.5f}};
  openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
  g->setName("density");
  g->setGridClass(openvdb::GRID_FOG_VOLUME);
  g->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
  auto acc = g->getAccessor();
  const int nx = n, ny = int(float(n) * 0.55f), nz = int(float(n) * 0.6f);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const Vec3f p{float(i - nx / 2) * voxel, float(j) * voxel, float(k - nz / 2) * voxel};
        float shape = -1;  // signed: > 0 inside the puffs
        for (const Puff& puff : puffs) shape = std::max(shape, 1 - length(p - puff.c) / puff.r);
        if (shape < -0.35f) continue;  // beyond the noise's reach
        shape += 0.3f * noise.fbm(p * 3.0f, 5) - 0.05f;
        shape *= smoothstep(0.1f, 0.35f, p.y);  // the flat base
        if (shape <= 0) continue;
        acc.setValue(openvdb::Coord(i, j, k), std::min(1.0f, shape * 4));
      }
  return g;
}

// A small fire: flames rising from a disc of radius 0.3 about 0.9 high, narrowing and cooling
// upwards, licked by noise, with smoke above. Temperature in kelvin (up to 1,900 K), flame in
// [0, 1], density (soot) low in the flame and rising into the smoke.
openvdb::GridPtrVec fire() {
  const float voxel = 0.01f;
  const PerlinNoise noise(11);
  openvdb::GridPtrVec grids;
  auto make = [&](const char* name) {
    openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
    g->setName(name);
    g->setGridClass(openvdb::GRID_FOG_VOLUME);
    g->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
    grids.push_back(g);
    return g;
  };
  auto density = make("density"), temperature = make("temperature"), flame = make("flame");
  auto dAcc = density->getAccessor(), tAcc = temperature->getAccessor();
  auto fAcc = flame->getAccessor();
  for (int k = -40; k <= 40; ++k)
    for (int j = 0; j <= 150; ++j)
      for (int i = -40; i <= 40; ++i) {
        const Vec3f p{float(i) * voxel, float(j) * voxel, float(k) * voxel};
        const float h = p.y / 0.9f;  // 0 at the base, 1 at the flame's tip
        const float n = noise.fbm(Vec3f{p.x * 6, p.y * 4 - 0.5f, p.z * 6}, 4);
        const float radius = 0.3f * std::max(0.0f, 1 - h) * (1 + 0.5f * n) + 0.02f;
        const float r = std::sqrt(p.x * p.x + p.z * p.z);
        const float core = smoothstep(radius, radius * 0.4f, r) * smoothstep(1.05f, 0.6f, h);
        if (core > 0) {
          tAcc.setValue(openvdb::Coord(i, j, k), 900 + 1000 * core);
          fAcc.setValue(openvdb::Coord(i, j, k), core);
        }
        // Smoke: a column widening above the flame.
        const float smokeRadius = 0.12f + 0.25f * std::max(0.0f, h - 0.6f);
        const float smoke = smoothstep(smokeRadius, 0.0f, r + 0.05f * n) *
                            smoothstep(0.5f, 1.2f, h) * smoothstep(1.67f, 1.3f, h);
        const float d = 0.6f * core + 3 * smoke;
        if (d > 0.01f) dAcc.setValue(openvdb::Coord(i, j, k), d);
      }
  return grids;
}

void write(const std::string& path, const openvdb::GridPtrVec& grids) {
  openvdb::io::File file(path);
  file.write(grids);
  file.close();
  std::printf("wrote %s\n", path.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: glint_make_vdb_scenes OUT_FOLDER [--cloud-size N]\n");
    return 2;
  }
  const std::string out = argv[1];
  int size = 200;
  if (argc >= 4 && std::string(argv[2]) == "--cloud-size") size = std::atoi(argv[3]);
  if (size < 8 || size > 2048) {
    std::fprintf(stderr, "glint_make_vdb_scenes: --cloud-size must be 8..2048\n");
    return 2;
  }
  openvdb::initialize();
  write(out + "/cloud.vdb", {cloud(size)});
  write(out + "/fire.vdb", fire());
  return 0;
}
