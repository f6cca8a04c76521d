#pragma once
// Subcommands of the tkgslam CLI. Each registers its options and returns the action to run.
#include <functional>

#include <CLI/CLI.hpp>

namespace tkgslam::app {

using Action = std::function<int()>;

Action addEvalCommand(CLI::App& app);
Action addRunCommand(CLI::App& app);
Action addDetectCommand(CLI::App& app);
Action addAugmentCommand(CLI::App& app);
Action addReportCommand(CLI::App& app);

}  // namespace tkgslam::app
