#include <filesystem>

#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/common/Error.h"
#include "tkgslam/io/OutputFolder.h"

namespace tkgslam {
namespace {

std::string errorOf(const std::filesystem::path& p) {
  try {
    io::createOutputFolder(p.string());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(OutputFolder, MissingParentsAreCreatedAndAnExistingFolderIsFine) {
  test::TempDir tmp;
  EXPECT_EQ(errorOf(tmp / "a" / "b"), "");
  EXPECT_TRUE(std::filesystem::is_directory(tmp / "a" / "b"));
  EXPECT_EQ(errorOf(tmp / "a" / "b"), "");
}

TEST(OutputFolder, AFileInTheWayIsAnInputErrorNamingThePath) {
  test::TempDir tmp;
  test::writeText(tmp / "taken", "x");
  const std::string e = errorOf(tmp / "taken");
  EXPECT_NE(e.find("cannot create output folder"), std::string::npos) << e;
  EXPECT_NE(e.find("taken"), std::string::npos) << e;
  EXPECT_NE(errorOf(tmp / "taken" / "sub").find("cannot create output folder"), std::string::npos);
}

}  // namespace
}  // namespace tkgslam
