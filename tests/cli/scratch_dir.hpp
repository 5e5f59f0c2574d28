// A fresh scratch directory per test (temp dir / PREFIX + the test's name), removed
// afterwards, with the helpers the command-line tests share.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

namespace rheo::testing_support {

class ScratchDirTest : public testing::Test {
 protected:
  explicit ScratchDirTest(std::string prefix) : prefix_(std::move(prefix)) {}
  void SetUp() override {
    // Built with append(): operator+ chains trip GCC 12's -Wrestrict.
    std::string name(prefix_);
    name.append(testing::UnitTest::GetInstance()->current_test_info()->name());
    root_ = std::filesystem::temp_directory_path() / name;
    std::filesystem::remove_all(root_);
    std::filesystem::create_directories(root_);
  }
  void TearDown() override { std::filesystem::remove_all(root_); }

  std::string path(const std::string& name) const { return (root_ / name).string(); }
  // Writes `text` to `name` under the scratch directory (its folders created); returns its path.
  std::string write(const std::string& name, const std::string& text) const {
    std::filesystem::create_directories((root_ / name).parent_path());
    std::ofstream(root_ / name, std::ios::binary) << text;
    return path(name);
  }

  std::filesystem::path root_;

 private:
  std::string prefix_;
};

}  // namespace rheo::testing_support
