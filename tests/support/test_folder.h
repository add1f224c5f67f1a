// A fresh folder for the running test. CTest runs each test case as its own process, several at a
// time, so the folder is named after the test and the process; it is emptied before the test and
// removed after it.
#pragma once

#include <unistd.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace tavis::testing {

// <temp>/tavis_<prefix>_<pid>_<test name> ('/' of parameterised names as '_').
inline std::filesystem::path TestFolderPath(const std::string& prefix) {
  std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
  for (char& c : test) c = c == '/' ? '_' : c;
  return std::filesystem::temp_directory_path() / ("tavis_" + prefix + "_" + std::to_string(::getpid()) + "_" + test);
}

// Writes `text` as the whole of the file at `path`, creating its folders.
inline void WriteTextFile(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

// The whole of the file at `path` ("" when it cannot be read).
inline std::string ReadTextFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// A fixture whose root() is that folder, created empty for each test. The folder's prefix is the
// test suite's name unless one is given.
class TestFolder : public ::testing::Test {
 protected:
  TestFolder() = default;
  explicit TestFolder(std::string prefix) : prefix_(std::move(prefix)) {}
  void SetUp() override {
    root_ = TestFolderPath(prefix_.empty() ? ::testing::UnitTest::GetInstance()->current_test_info()->test_suite_name()
                                           : prefix_);
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
