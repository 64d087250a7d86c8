// glint — command line entry point: `glint render | info | diff | bench-accel | tonemap |
// assemble`.
//
// Exit codes: 0 success, 1 a render or write that failed or images that differ, 2 bad input or
// usage. They are decided here and nowhere else.
#include <cstdio>
#include <exception>

#include "apps/commands.h"
#include "geometry/error.h"

int main(int argc, char** argv) {
  CLI::App app{"glint: a ray tracer for glTF 2.0 scenes with a sidecar JSON, on Intel Embree"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "glint 0.1.0");
  bool imagesDiffer = false;
  glint::app::addRenderCommand(app);
  glint::app::addInfoCommand(app);
  glint::app::addDiffCommand(app, &imagesDiffer);
  glint::app::addBenchAccelCommand(app);
  glint::app::addTonemapCommand(app);
  glint::app::addAssembleCommand(app);
  glint::app::addPreviewCommand(app);
  try {
    app.parse(argc, argv);           // runs the subcommand
  } catch (const CLI::Success& e) {  // --help, --help-all, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);  // prints the usage error
    return 2;
  } catch (const glint::Error& e) {
    // The one place an error becomes an exit code: bad input 2, a failure 1 (geometry/error.h).
    std::fprintf(stderr, "glint: %s\n", e.what());
    return e.exitCode();
  } catch (const std::exception& e) {
    // Anything else is a bug; this is the last line of defence against a crash.
    std::fprintf(stderr, "glint: internal error: %s\n", e.what());
    return 1;
  }
  return imagesDiffer ? 1 : 0;
}
