// A named pipe given as an input: refused by name when nobody writes to it, read as usual
// when a program does (the shell's <(...)), and a plain file passes straight through.
#include "sim/input_pipe.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "sim/error.hpp"
#include "sim/scenario.hpp"
#include "sim/scenarios/builtin.hpp"

namespace rheo {
namespace {

namespace fs = std::filesystem;

class InputPipe : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("rheo_pipe_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    fifo_ = (dir_ / "scenario.json").string();
    ASSERT_EQ(::mkfifo(fifo_.c_str(), 0600), 0);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
  std::string fifo_;
};

TEST_F(InputPipe, APipeNobodyWritesToIsRefusedByNameNotWaitedOnForEver) {
  const auto start = std::chrono::steady_clock::now();
  try {
    read_if_pipe(fifo_, 1 << 20, 200);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(fifo_ + ": a named pipe that no program wrote to"),
              std::string::npos)
        << e.what();
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
}

TEST_F(InputPipe, APipeWithAWriterIsReadAsAFile) {
  const std::string text = *find_builtin_scenario_text("block5");
  std::thread writer([&] { std::ofstream(fifo_) << text; });
  const Scenario s = load_scenario(fifo_);
  writer.join();
  EXPECT_EQ(s.name, "block5");
  const std::string file = (dir_ / "plain.json").string();
  std::ofstream(file) << text;
  EXPECT_FALSE(read_if_pipe(file, 1 << 20, 0).has_value()) << "a file is opened as a file";
}

}  // namespace
}  // namespace rheo
