// glint — colour management through OpenColorIO: which config is in use, its displays and
// views, and the scene-linear → display/view transform applied before 8-bit output.
//
// The config is $OCIO when set (as every colour-managed tool does), else the one shipped in
// assets/ocio/config.ocio. OCIO types stay inside color.cpp.
#pragma once

#include <span>
#include <string>
#include <utility>
#include <vector>

#include "geometry/error.h"

namespace glint {

// Bad colour settings: an OCIO config that does not load, an unknown display or view, an
// unknown tone-map operator. It is the user's input, so the CLI exits with code 2.
class ColorError : public InputError {
 public:
  using InputError::InputError;
};

struct DisplayViews {
  std::string display;
  std::vector<std::string> views;  // active views, in config order
  std::string defaultView;
};

struct ColorConfigInfo {
  std::string path;  // the config file that was loaded
  std::string defaultDisplay;
  std::vector<DisplayViews> displays;  // active displays, in config order
};

// The config file glint ships, used without $OCIO: an installed glint's
// (PREFIX/share/glint/ocio/config.ocio, image/install_layout.h), else the source tree's
// (its path compiled in).
std::string defaultOcioConfigPath();

// Loads (or reuses) the config in effect now: $OCIO, falling back to the shipped config with a
// warning on stderr when $OCIO does not load. Throws ColorError when neither loads.
ColorConfigInfo colorConfigInfo();

// Resolves empty names to the config's defaults and checks both exist; returns {display, view}.
// Throws ColorError naming the available displays (or views) otherwise. Cheap: call it before
// rendering so a typo costs nothing.
std::pair<std::string, std::string> resolveDisplayView(const std::string& display,
                                                       const std::string& view);

// Applies the OCIO display/view transform from the config's scene_linear role to `rgb`
// (interleaved RGB triples, display-relative scene-linear in, display code values out) in
// place. Empty names mean the config's defaults. Throws ColorError.
void applyDisplayView(std::span<float> rgb, const std::string& display, const std::string& view);

}  // namespace glint
