#include "io/ReplaceFile.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "TempDir.h"
#include "io/FormatError.h"

using ambler::io::FormatError;
using ambler::io::writeThenReplace;

namespace {

std::string contents(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

}  // namespace

TEST(ReplaceFile, TheFinishedFileTakesThePlaceOfTheOld) {
  TempDir dir;
  writeText(dir / "map.json", "old");
  writeThenReplace(dir / "map.json", [&](const std::filesystem::path& partial) {
    EXPECT_EQ(partial, dir / "map.json.partial");
    EXPECT_EQ(contents(dir / "map.json"), "old");  // readers still see the old file
    writeText(partial, "new");
  });
  EXPECT_EQ(contents(dir / "map.json"), "new");
  EXPECT_FALSE(std::filesystem::exists(dir / "map.json.partial"));
}

TEST(ReplaceFile, AFailedWriteLeavesTheOldFileAndNoPartialOne) {
  TempDir dir;
  writeText(dir / "map.json", "old");
  EXPECT_THROW(writeThenReplace(dir / "map.json",
                                [](const std::filesystem::path& partial) {
                                  writeText(partial, "half");
                                  throw std::runtime_error("disk full");
                                }),
               std::runtime_error);
  EXPECT_EQ(contents(dir / "map.json"), "old");
  EXPECT_FALSE(std::filesystem::exists(dir / "map.json.partial"));
}

// A directory with contents cannot be replaced by a file.
TEST(ReplaceFile, AFailedMoveNamesTheFileAndRemovesThePartialOne) {
  TempDir dir;
  std::filesystem::create_directories(dir / "layer.tif" / "inside");
  try {
    writeThenReplace(dir / "layer.tif",
                     [](const std::filesystem::path& partial) { writeText(partial, "pixels"); });
    FAIL() << "the move should have failed";
  } catch (const FormatError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find((dir / "layer.tif").string()), std::string::npos) << what;
    EXPECT_NE(what.find("cannot move the finished file into place"), std::string::npos) << what;
  }
  EXPECT_TRUE(std::filesystem::is_directory(dir / "layer.tif" / "inside"));
  EXPECT_FALSE(std::filesystem::exists(dir / "layer.tif.partial"));
}
