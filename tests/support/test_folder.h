// A fresh folder for the running test. CTest runs each test case as its own process, several at a
// time, so the folder is named after the test and the process; it is emptied before the test and
// removed after it.
#pragma once

#include <unistd.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace tavis::testing {

// <temp>/tavis_<prefix>_<pid>_<test name> ('/' of parameterised names as '_').
inline std::filesystem::path TestFolderPath(const std::string& prefix) {
  std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
  for (char& c : test) c = c == '/' ? '_' : c;
  return std::filesystem::temp_directory_path() / ("tavis_" + prefix + "_" + std::to_string(::getpid()) + "_" + test);
}

// A fixture whose root() is that folder, created empty for each test.
class TestFolder : public ::testing::Test {
 protected:
  explicit TestFolder(std::string prefix) : prefix_(std::move(prefix)) {}
  void SetUp() override {
    root_ = TestFolderPath(prefix_);
    std::filesystem::remove_all(root_);
    std::filesystem::create_directories(root_);
  }
  void TearDown() override { std::filesystem::remove_all(root_); }
  const std::filesystem::path& root() const { return root_; }

  std::filesystem::path root_;

 private:
  std::string prefix_;
};

}  // namespace tavis::testing
