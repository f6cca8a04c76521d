// tkgslam: RGB-D SLAM for dynamic scenes. Thin CLI over libtkgslam.
// Exit codes: 0 success, 1 internal error, 2 bad input (files, config, arguments).
#include <cstdio>
#include <exception>
#include <map>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include "Commands.h"
#include "tkgslam/common/Error.h"

int main(int argc, char** argv) {
  CLI::App app{"tkgslam - RGB-D SLAM that keeps working when people fill the view"};
  app.require_subcommand(1);
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
