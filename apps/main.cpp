// glint — command line entry point: `glint render | info | diff | bench-accel | tonemap |
// assemble`.
//
// Exit codes: 0 success, 1 a render or write that failed or images that differ, 2 bad input or
// usage, 128 + signal a render stopped by Ctrl-C or SIGTERM (its outputs written). They are
// decided here and nowhere else, but for a second Ctrl-C: it quits at once from the signal
// handler (apps/interrupt.cpp), where nothing may unwind to main, with the same 128 + signal.
#include <cctype>
#include <cstdio>
#include <exception>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "apps/commands.h"
#include "geometry/error.h"
#include "scenes/json_reader.h"

namespace {

// An argument that names an option ("--sp", "-x", "--sp=4"), not a value such as "-5".
bool looksLikeOption(const std::string& arg) {
  return arg.size() > 1 && arg[0] == '-' && !std::isdigit(static_cast<unsigned char>(arg[1])) &&
         arg[1] != '.';
}

// "unknown option --sp; did you mean --spp?": the option `arg` given to `cmd` (called `command`
// in the hint) with the closest of its options, found as the sidecar's unknown keys find theirs
// (closestMatch). Names are compared without their dashes, so that "-x" is not one edit away
// from every one-letter option.
std::string unknownOption(const CLI::App& cmd, const std::string& command, std::string arg) {
  arg = arg.substr(0, arg.find('='));  // --sp=4
  std::vector<std::string> bare, typed;
  for (const CLI::Option* o : cmd.get_options()) {
    for (const std::string& l : o->get_lnames()) bare.push_back(l), typed.push_back("--" + l);
    for (const std::string& s : o->get_snames()) bare.push_back(s), typed.push_back("-" + s);
  }
  const std::string word = arg.substr(arg.find_first_not_of('-'));
  const std::string guess = glint::closestMatch(word, bare);
  std::string message = "unknown option " + arg;
  if (guess.empty()) return message + " (`" + command + " --help` lists the options)";
  for (size_t i = 0; i < bare.size(); ++i)
    if (bare[i] == guess) return message + "; did you mean " + typed[i] + "?";
  return message;
}

// The names of glint's subcommands, in the order --help lists them.
std::vector<std::string> commandNames(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* sub :
       app.get_subcommands([](const CLI::App* c) { return !c->get_name().empty(); }))
    names.push_back(sub->get_name());
  return names;
}

// For a usage error caused by an argument CLI11 did not expect: an unknown option of the
// subcommand it was given to, or of glint itself, or an unknown or missing subcommand; nullopt
// when nothing of the sort happened (the error is about something else, e.g. a missing scene).
std::optional<std::string> unexpectedArgument(const CLI::App& app) {
  for (const CLI::App* sub : app.get_subcommands())
    for (const std::string& arg : sub->remaining())
      if (looksLikeOption(arg)) return unknownOption(*sub, "glint " + sub->get_name(), arg);
  const std::vector<std::string> left = app.remaining();
  const bool noCommand = app.get_subcommands().empty();
  const std::vector<std::string> commands = commandNames(app);
  // Without a command, the first word that is not an option is the command mistyped (its
  // options, as in `glint rendr x.glb -o x.png`, are then not glint's to judge).
  for (const std::string& arg : left) {
    if (looksLikeOption(arg) || !noCommand) continue;
    const std::string guess = glint::closestMatch(arg, commands);
    return "unknown command '" + arg + "'" +
           (guess.empty() ? "; the commands are " + glint::quotedNames(commands)
                          : "; did you mean '" + guess + "'?");
  }
  for (const std::string& arg : left)
    if (looksLikeOption(arg)) return unknownOption(app, "glint", arg);
  if (noCommand)
    return "a command is required: " + glint::quotedNames(commands) +
           " (`glint --help` says what each does)";
  return std::nullopt;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"glint: a ray tracer for glTF 2.0 scenes with a sidecar JSON, on Intel Embree"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "glint 0.1.0");
  glint::app::Outcome outcome;
  glint::app::addRenderCommand(app, &outcome);
  glint::app::addInfoCommand(app);
  glint::app::addDiffCommand(app, &outcome);
  glint::app::addBenchAccelCommand(app);
  glint::app::addTonemapCommand(app);
  glint::app::addAssembleCommand(app);
  glint::app::addPreviewCommand(app);
  try {
    app.parse(argc, argv);           // runs the subcommand
  } catch (const CLI::Success& e) {  // --help, --help-all, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // A usage error, on one line as every other error: an unknown option with the option
    // meant, or CLI11's message ("--width: must be >= 1", "scene is required").
    std::optional<std::string> unexpected;
    if (dynamic_cast<const CLI::ExtrasError*>(&e) || dynamic_cast<const CLI::RequiredError*>(&e))
      unexpected = unexpectedArgument(app);
    std::fprintf(stderr, "glint: %s\n", unexpected ? unexpected->c_str() : e.what());
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
  // Interrupted: the outputs are written (or there was nothing to write), and the status says
  // the render did not finish, as the shell's would for the signal.
  if (outcome.interruptedBy) return 128 + outcome.interruptedBy;
  return outcome.imagesDiffer ? 1 : 0;
}
