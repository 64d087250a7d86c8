// glint — command line entry point: `glint render | info | diff | bench-accel`.
//
// Exit codes: 0 success, 1 render/compare failure, 2 bad input or usage.
#include <cstdio>
#include <exception>

#include "apps/commands.h"
#include "geometry/error.h"

int main(int argc, char** argv) {
  CLI::App app{"glint: a ray tracer for glTF 2.0 scenes with a sidecar JSON, on Intel Embree"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "glint 0.1.0");
  int exitCode = 0;
  glint::app::addRenderCommand(app, &exitCode);
  glint::app::addInfoCommand(app, &exitCode);
  glint::app::addDiffCommand(app, &exitCode);
  glint::app::addBenchAccelCommand(app, &exitCode);
  glint::app::addTonemapCommand(app, &exitCode);
  glint::app::addAssembleCommand(app, &exitCode);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
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
  return exitCode;
}
