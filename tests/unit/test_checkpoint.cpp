// The HDF5 checkpoint file: bit-exact round trips of every kind of entry, errors that name the file, and
// crash safety of the atomic write (a writer killed with SIGKILL mid-write leaves the previous checkpoint).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "../../src/io/checkpoint_seal.hpp"  // to re-seal files edited on purpose
#include "mpm/core/errors.hpp"
#include "mpm/io/checkpoint.hpp"

namespace {

namespace fs = std::filesystem;
using mpm::io::CheckpointData;
using mpm::io::read_checkpoint;
using mpm::io::write_checkpoint;

/// A fresh directory per test, removed afterwards.
class Checkpoint : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("mpm_test_checkpoint_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// Temporary files of a write to `file` in progress or interrupted (see checkpoint_temp_prefix).
  std::vector<fs::path> temp_files(const fs::path& file) const {
    const std::string prefix = mpm::io::checkpoint_temp_prefix(file).filename().string();
    std::vector<fs::path> found;
    for (const auto& entry : fs::directory_iterator(dir_))
      if (entry.path().filename().string().rfind(prefix, 0) == 0) found.push_back(entry.path());
    return found;
  }

  fs::path dir_;
};

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

/// Asserts a == b with doubles compared by their bits (so -0.0 differs from 0.0).
void expect_bitwise_equal(const CheckpointData& a, const CheckpointData& b) {
  ASSERT_EQ(a.reals.size(), b.reals.size());
  for (const auto& [name, values] : a.reals) {
    ASSERT_EQ(b.reals.count(name), 1u) << name;
    const auto& other = b.reals.at(name);
    ASSERT_EQ(values.size(), other.size()) << name;
    // memcmp of an empty vector's data() (possibly null) is undefined even for zero bytes: compare only
    // values
    if (!values.empty()) {
      EXPECT_EQ(std::memcmp(values.data(), other.data(), values.size() * sizeof(double)), 0) << name;
    }
  }
  ASSERT_EQ(a.real_scalars.size(), b.real_scalars.size());
  for (const auto& [name, value] : a.real_scalars) {
    ASSERT_EQ(b.real_scalars.count(name), 1u) << name;
    EXPECT_TRUE(same_bits(value, b.real_scalars.at(name))) << name;
  }
  EXPECT_EQ(a.integers, b.integers);
  EXPECT_EQ(a.integer_scalars, b.integer_scalars);
  EXPECT_EQ(a.texts, b.texts);
}

/// The message of the mpm::InputError that read_checkpoint(file) throws; a test failure if none.
std::string read_error(const fs::path& file) {
  try {
    read_checkpoint(file);
  } catch (const mpm::InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "read_checkpoint(" << file << ") did not throw InputError";
  return {};
}

std::string file_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void put_file_bytes(const fs::path& file, const std::string& bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

CheckpointData special_values() {
  using limits = std::numeric_limits<double>;
  CheckpointData d;
  d.reals["special"] = {limits::denorm_min(),
                        -limits::denorm_min(),
                        2.5e-310,
                        -0.0,
                        0.0,
                        1e308,
                        -1e308,
                        limits::max(),
                        limits::lowest(),
                        limits::min(),
                        limits::epsilon(),
                        0.1 + 0.2,
                        1.0 / 3.0,
                        limits::infinity(),
                        -limits::infinity()};
  d.reals["x"] = {0.1, 0.2, 0.30000000000000004, -1.5, 2.0, 3.0};
  d.reals["empty"] = {};
  d.integers["ids"] = {0, 1, -1, std::numeric_limits<std::int64_t>::min(),
                       std::numeric_limits<std::int64_t>::max()};
  d.integers["none"] = {};
  d.real_scalars["time"] = 0.1 + 0.2;
  d.real_scalars["negative_zero"] = -0.0;
  d.real_scalars["denormal"] = limits::denorm_min();
  d.real_scalars["huge"] = 1e308;
  d.integer_scalars["steps"] = 123456789012345;
  d.integer_scalars["dim"] = 3;
  d.integer_scalars["min"] = std::numeric_limits<std::int64_t>::min();
  d.texts["scene"] = "{\n  \"name\": \"block \\\"A\\\"\",\n\t'single' quotes, UTF-8 \xcf\x83_xx\n}\n";
  d.texts["version"] = "0.1.0";
  d.texts["empty"] = "";
  d.texts["with_nul"] = std::string("a\0b\0", 4);  // embedded and trailing NUL bytes kept
  return d;
}

TEST_F(Checkpoint, RoundTripIsBitExact) {
  const CheckpointData d = special_values();
  const fs::path file = dir_ / "state.h5";
  write_checkpoint(file, d);
  const CheckpointData r = read_checkpoint(file);
  expect_bitwise_equal(d, r);
  EXPECT_TRUE(d == r);
  // The special values really are what the test claims (guards against a constant-folded test).
  EXPECT_TRUE(std::signbit(r.real_scalars.at("negative_zero")));
  EXPECT_EQ(r.reals.at("special")[0], 4.9406564584124654e-324);
  EXPECT_EQ(r.reals.at("special")[11], 0.30000000000000004);
  EXPECT_TRUE(r.reals.at("empty").empty());
  EXPECT_TRUE(r.integers.at("none").empty());
  EXPECT_EQ(r.texts.at("empty"), "");
  EXPECT_EQ(r.texts.at("with_nul").size(), 4u);
  EXPECT_TRUE(temp_files(file).empty());
}

TEST_F(Checkpoint, EmptyCheckpointRoundTrips) {
  const fs::path file = dir_ / "empty.h5";
  write_checkpoint(file, {});
  EXPECT_TRUE(read_checkpoint(file) == CheckpointData{});
}

TEST_F(Checkpoint, NanPayloadRoundTripsBitwise) {
  std::uint64_t bits = 0x7ff8'0000'dead'beefULL;  // quiet NaN with a payload
  double nan = 0;
  std::memcpy(&nan, &bits, sizeof nan);
  CheckpointData d;
  d.reals["nan"] = {nan, -std::numeric_limits<double>::quiet_NaN()};
  d.real_scalars["nan"] = nan;
  const fs::path file = dir_ / "nan.h5";
  write_checkpoint(file, d);
  expect_bitwise_equal(d, read_checkpoint(file));
}

TEST_F(Checkpoint, MissingFileIsInputErrorNamingIt) {
  const fs::path file = dir_ / "missing.h5";
  const std::string msg = read_error(file);
  EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("no such file"), std::string::npos) << msg;
}

TEST_F(Checkpoint, NonHdf5FileIsInputErrorNamingIt) {
  const fs::path file = dir_ / "text.h5";
  put_file_bytes(file, "this is not an HDF5 file\n");
  const std::string msg = read_error(file);
  EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("not an HDF5 file"), std::string::npos) << msg;
}

// An HDF5 file without the marker, made by renaming the root attribute "format" in the bytes of a valid
// checkpoint (the default, 1.8-compatible object headers carry no checksum), and one with a different marker.
TEST_F(Checkpoint, Hdf5FileWithoutMarkerIsInputErrorNamingIt) {
  const fs::path good = dir_ / "good.h5";
  write_checkpoint(good, special_values());
  const std::string bytes = file_bytes(good);

  // Edited after the seal (the first 512 bytes), then sealed again: what another writer could produce.
  const std::size_t seal = mpm::io::seal::userblock_bytes;
  std::string unmarked = bytes;
  const std::size_t name_at = unmarked.find(std::string("format\0", 7), seal);
  ASSERT_NE(name_at, std::string::npos);
  unmarked[name_at + 5] = 'X';
  const fs::path file = dir_ / "unmarked.h5";
  put_file_bytes(file, unmarked);
  ASSERT_TRUE(mpm::io::seal::write(file));
  std::string msg = read_error(file);
  EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("not an mpm checkpoint"), std::string::npos) << msg;

  std::string other = bytes;
  const std::size_t value_at = other.find("mpm-checkpoint", seal);
  ASSERT_NE(value_at, std::string::npos);
  other.replace(value_at, 3, "xyz");
  const fs::path file2 = dir_ / "other.h5";
  put_file_bytes(file2, other);
  ASSERT_TRUE(mpm::io::seal::write(file2));
  msg = read_error(file2);
  EXPECT_NE(msg.find(file2.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("xyz-checkpoint"), std::string::npos) << msg;
}

TEST_F(Checkpoint, TruncatedFileIsInputErrorNamingIt) {
  CheckpointData d;
  d.reals["x"] = std::vector<double>(100000, 1.25);
  const fs::path good = dir_ / "good.h5";
  write_checkpoint(good, d);
  const std::string bytes = file_bytes(good);
  ASSERT_GT(bytes.size(), 800000u);
  const fs::path file = dir_ / "truncated.h5";
  put_file_bytes(file, bytes.substr(0, bytes.size() / 2));
  const std::string msg = read_error(file);
  EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
}

// A checkpoint that cannot be written is an output failure (exit status 1), not an input error.
TEST_F(Checkpoint, UnwritablePathIsOutputErrorNamingIt) {
  const fs::path file = dir_ / "no_such_dir" / "state.h5";
  try {
    write_checkpoint(file, special_values());
    ADD_FAILURE() << "no OutputError";
  } catch (const mpm::OutputError& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(file));
}

TEST_F(Checkpoint, InvalidNameIsRejectedAndLeavesOldFile) {
  const fs::path file = dir_ / "state.h5";
  const CheckpointData a = special_values();
  write_checkpoint(file, a);
  CheckpointData bad;
  bad.reals["a/b"] = {1.0};
  EXPECT_THROW(write_checkpoint(file, bad), mpm::InputError);
  expect_bitwise_equal(a, read_checkpoint(file));
  EXPECT_TRUE(temp_files(file).empty());
}

TEST_F(Checkpoint, SecondWriteReplacesFirst) {
  const fs::path file = dir_ / "state.h5";
  const CheckpointData a = special_values();
  write_checkpoint(file, a);
  CheckpointData b;
  b.reals["x"].resize(2'000'000);
  for (std::size_t i = 0; i < b.reals["x"].size(); ++i) b.reals["x"][i] = 0.1 * static_cast<double>(i);
  b.integer_scalars["steps"] = 7;
  b.texts["scene"] = "B";
  write_checkpoint(file, b);
  const CheckpointData r = read_checkpoint(file);
  expect_bitwise_equal(b, r);
  EXPECT_EQ(r.reals.at("x")[1999999], 0.1 * 1999999.0);
  EXPECT_EQ(r.reals.count("special"), 0u);
  EXPECT_TRUE(temp_files(file).empty());
}

// A child process starts writing a 400 MB checkpoint B over checkpoint A and is killed with SIGKILL as soon
// as its temporary file "state.h5.tmp-PID-N" appears (plus 20 ms, to be inside the write): FILE must still be
// A.
TEST_F(Checkpoint, WriterKilledMidWriteLeavesPreviousCheckpoint) {
  const fs::path file = dir_ / "state.h5";
  const CheckpointData a = special_values();
  write_checkpoint(file, a);

  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    try {
      CheckpointData b;
      b.reals["x"].assign(50'000'000, 2.0);  // 400 MB
      b.texts["scene"] = "B";
      write_checkpoint(file, b);
      ::_exit(0);
    } catch (...) {
      ::_exit(1);
    }
  }

  using clock = std::chrono::steady_clock;
  const auto deadline = clock::now() + std::chrono::seconds(20);
  bool started = false;
  while (!started && clock::now() < deadline) {
    started = !temp_files(file).empty();
    if (!started) std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  if (started) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_EQ(::kill(child, SIGKILL), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(started) << "the child never created its temporary file";
  // Killed before it finished: the signal ended it, and its temporary file was never renamed.
  ASSERT_TRUE(WIFSIGNALED(status)) << "child exited normally with status " << WEXITSTATUS(status);
  EXPECT_EQ(WTERMSIG(status), SIGKILL);
  const auto left = temp_files(file);
  ASSERT_EQ(left.size(), 1u);
  EXPECT_EQ(left[0].filename().string().rfind("state.h5.tmp-" + std::to_string(child) + "-", 0), 0u);

  expect_bitwise_equal(a, read_checkpoint(file));

  // The interrupted write leaves a stale temporary file that a later write neither needs nor trips over.
  CheckpointData c;
  c.reals["x"] = {3.0};
  write_checkpoint(file, c);
  expect_bitwise_equal(c, read_checkpoint(file));
}

// The seal: any byte changed or removed after writing is refused before HDF5 reads the file, with one line
// that says so.
TEST_F(Checkpoint, SealRefusesChangedOrTruncatedFiles) {
  const fs::path good = dir_ / "good.h5";
  write_checkpoint(good, special_values());
  const std::string bytes = file_bytes(good);
  ASSERT_EQ(bytes.rfind("mpm-checkpoint-seal 1\nbytes ", 0), 0u);
  for (std::size_t at : {std::size_t{600}, bytes.size() / 2, bytes.size() - 1}) {
    std::string flipped = bytes;
    flipped[at] = static_cast<char>(flipped[at] ^ 0x01);
    const fs::path file = dir_ / "flipped.h5";
    put_file_bytes(file, flipped);
    const std::string msg = read_error(file);
    EXPECT_NE(msg.find("corrupt: its contents do not match the checksum"), std::string::npos)
        << at << ": " << msg;
  }
  const fs::path cut = dir_ / "cut.h5";
  put_file_bytes(cut, bytes.substr(0, bytes.size() - 100));
  EXPECT_NE(read_error(cut).find("truncated or extended"), std::string::npos) << read_error(cut);
  put_file_bytes(cut, bytes.substr(0, 300));
  EXPECT_NE(read_error(cut).find("truncated inside its header"), std::string::npos) << read_error(cut);
  // A zeroed seal: neither a seal nor an HDF5 signature at the start, so HDF5 is not asked to read it.
  std::string zeroed = bytes;
  std::fill(zeroed.begin(), zeroed.begin() + 512, '\0');
  put_file_bytes(cut, zeroed);
  EXPECT_NE(read_error(cut).find("not an HDF5 file"), std::string::npos) << read_error(cut);
}

}  // namespace
