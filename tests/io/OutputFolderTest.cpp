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

TEST(OutputFolder, AWritableFileIsCheckedWithoutTouchingIt) {
  test::TempDir tmp;
  // A missing file: writable, and not left behind by the check.
  EXPECT_NO_THROW(io::checkWritableFile((tmp / "new.map").string(), "--save-map"));
  EXPECT_FALSE(std::filesystem::exists(tmp / "new.map"));
  // An existing file: writable, its contents untouched.
  test::writeText(tmp / "old.map", "contents");
  EXPECT_NO_THROW(io::checkWritableFile((tmp / "old.map").string(), "--save-map"));
  EXPECT_EQ(test::readFile(tmp / "old.map"), "contents");
  // A folder, or a file in a missing folder: refused, naming the option.
  try {
    io::checkWritableFile(tmp.path().string(), "--save-map");
    ADD_FAILURE() << "a folder was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--save-map '" + tmp.path().string() + "': is a folder"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(io::checkWritableFile((tmp / "missing" / "m.map").string(), "--save-map"), InputError);
}

}  // namespace
}  // namespace tkgslam
