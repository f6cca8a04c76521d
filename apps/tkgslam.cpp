// tkgslam: RGB-D SLAM for dynamic scenes. Thin CLI over libtkgslam.
// Exit codes: 0 success, 1 internal error, 2 bad input (files, config, arguments).
#include <csignal>
#include <cstdio>
#include <exception>
#include <map>
#include <string>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include "Commands.h"
#include "tkgslam/common/Error.h"
#include "tkgslam/common/MallocTuning.h"

int main(int argc, char** argv) {
  // Past a file-size limit (ulimit -f) a write then fails with EFBIG and is reported like a full
  // disk, instead of the signal ending the process with half-written outputs.
  std::signal(SIGXFSZ, SIG_IGN);
  // Images of a few MB every frame: without this, their pages were faulted in again each frame.
  tkgslam::common::tuneMallocForFrames();
  // Line-buffered even into a pipe or file (`| tee run.log`): the few summary lines then interleave
  // with the progress on stderr in the order they happen, not all at exit.
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  CLI::App app{"tkgslam - RGB-D SLAM that keeps working when people fill the view"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("tkgslam ") + TKGSLAM_VERSION);
  bool verbose = false;
  app.add_flag("-v,--verbose", verbose, "Debug logging");
  std::map<CLI::App*, tkgslam::app::Action> actions;
  auto add = [&](auto fn) {
    const size_t before = app.get_subcommands({}).size();
    auto action = fn(app);
    actions[app.get_subcommands({})[before]] = action;
  };
  add(tkgslam::app::addRunCommand);
  add(tkgslam::app::addEvalCommand);
  add(tkgslam::app::addDetectCommand);
  add(tkgslam::app::addAugmentCommand);
  add(tkgslam::app::addReportCommand);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11 reports a mistyped command as "A subcommand is required": name it instead.
    std::string names;
    bool known = false;
    for (const auto* sub : app.get_subcommands({})) {
      names += (names.empty() ? "" : ", ") + sub->get_name();
      known = known || (argc > 1 && sub->get_name() == argv[1]);
    }
    if (argc > 1 && argv[1][0] != '-' && !known) {
      std::fprintf(stderr, "unknown command '%s' (the commands: %s; see tkgslam --help)\n", argv[1], names.c_str());
      return 2;
    }
    return app.exit(e) == 0 ? 0 : 2;
  }
  spdlog::set_level(verbose ? spdlog::level::debug : spdlog::level::info);
  spdlog::set_pattern("[%^%l%$] %v");
  try {
    for (auto* sub : app.get_subcommands()) return actions.at(sub)();
  } catch (const tkgslam::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "internal error: %s\n", e.what());
    return 1;
  }
  return 0;
}
