// glint — what every film renderer sets up first (the pass loop, render.cpp, and subdivision,
// subdivide.cpp): the pixels it covers and the threads it runs on.
#pragma once

#include <fmt/format.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <memory>
#include <thread>

#include "geometry/error.h"
#include "renderer/render.h"

namespace glint {

// The pixels a render covers: options.crop, or the whole width x height image. Throws
// InputError for a crop that is empty or reaches outside the image.
inline PixelWindow renderWindow(const RenderOptions& options, int width, int height) {
  const PixelWindow w = options.crop.value_or(PixelWindow{0, 0, width, height});
  if (w.x0 < 0 || w.y0 < 0 || w.x1 > width || w.y1 > height || w.width() <= 0 || w.height() <= 0)
    throw InputError(fmt::format("crop window {},{},{},{} is empty or outside the {}x{} image",
                                 w.x0, w.y0, w.x1, w.y1, width, height));
  return w;
}

// A render's worker threads: `requested`, or all hardware threads for 0, in an arena of their
// own. More threads than TBB's default (the cores) are what the user asked for: allowed,
// rather than TBB's warning and one worker fewer than asked.
struct RenderThreads {
  explicit RenderThreads(int requested)
      : count(requested > 0 ? requested : std::max(1, int(std::thread::hardware_concurrency()))) {
    if (count > tbb::info::default_concurrency())
      allow = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                    size_t(count));
    arena = std::make_unique<tbb::task_arena>(count);
  }
  int count;
  std::unique_ptr<tbb::global_control> allow;  // set only above the default
  std::unique_ptr<tbb::task_arena> arena;
};

}  // namespace glint
