// tkgslam run: placeholder until the SLAM core lands.
#include "Commands.h"

namespace tkgslam::app {
Action addRunCommand(CLI::App& app) {
  app.add_subcommand("run", "Run SLAM on a TUM sequence (not yet implemented)");
  return [] { return 1; };
}
}  // namespace tkgslam::app
