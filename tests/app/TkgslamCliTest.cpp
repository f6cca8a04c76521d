// The CLI's top level: --version, and a mistyped command named as such.
#include <gtest/gtest.h>

#include "TestSupport.h"

namespace tkgslam {
namespace {

TEST(TkgslamCli, VersionIsTheProjectsVersion) {
  std::string out;
  EXPECT_EQ(test::runCli("--version", &out), 0) << out;
  EXPECT_EQ(out, std::string("tkgslam ") + TKGSLAM_VERSION + "\n");
}

TEST(TkgslamCli, AMistypedCommandIsNamedWithTheCommandsThereAre) {
  std::string out;
  EXPECT_EQ(test::runCli("rnu -c x.yaml", &out), 2) << out;
  EXPECT_NE(out.find("unknown command 'rnu' (the commands: run, eval, detect, augment, report"), std::string::npos)
      << out;
  EXPECT_EQ(test::runCli("", &out), 2) << out;
  EXPECT_NE(out.find("A subcommand is required"), std::string::npos) << out;
}

}  // namespace
}  // namespace tkgslam
