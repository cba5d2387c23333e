// Arrays of rows in a checkpoint (CheckpointData::row_widths): their widths round-trip, R ranks reading one
// file each get rows [n r / R, n (r + 1) / R) and together all of them, and inconsistent rows are refused
// with the file's name. Ranks are played in one process by mpm::Alone, a communicator that only says which
// rank it is.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "mpm/core/errors.hpp"
#include "mpm/distributed/communicator.hpp"
#include "mpm/io/checkpoint.hpp"

namespace {

namespace fs = std::filesystem;
using mpm::io::CheckpointData;

fs::path scratch_file(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("mpm_test_checkpoint_rows_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

/// Five particles: positions (2 per row), ids (1 per row), and a whole array beside them.
CheckpointData five_rows() {
  CheckpointData d;
  d.reals["x"] = {0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5};
  d.integers["id"] = {10, 11, 12, 13, 14};
  d.reals["rigid"] = {7.0, 8.0, 9.0};
  d.integer_scalars["particles"] = 5;
  d.row_widths = {{"x", 2}, {"id", 1}};
  return d;
}

TEST(CheckpointRows, WidthsRoundTripInOneProcess) {
  const fs::path file = scratch_file("widths.h5");
  mpm::io::write_checkpoint(file, five_rows());
  EXPECT_TRUE(mpm::io::read_checkpoint(file) == five_rows());
  fs::remove_all(file.parent_path());
}

TEST(CheckpointRows, ThreeRanksReadSharesThatTogetherAreAllRows) {
  const fs::path file = scratch_file("shares.h5");
  mpm::io::write_checkpoint(file, five_rows());
  // Rows [5 r / 3, 5 (r + 1) / 3): 0 | 1 2 | 3 4.
  const std::vector<std::vector<std::int64_t>> ids = {{10}, {11, 12}, {13, 14}};
  const std::vector<std::vector<double>> x = {{0.0, 0.5}, {1.0, 1.5, 2.0, 2.5}, {3.0, 3.5, 4.0, 4.5}};
  for (int r = 0; r < 3; ++r) {
    const CheckpointData share = mpm::io::read_checkpoint(file, mpm::Alone(r, 3));
    EXPECT_EQ(share.integers.at("id"), ids[static_cast<std::size_t>(r)]) << "rank " << r;
    EXPECT_EQ(share.reals.at("x"), x[static_cast<std::size_t>(r)]) << "rank " << r;
    EXPECT_EQ(share.reals.at("rigid"), (std::vector<double>{7.0, 8.0, 9.0})) << "whole on rank " << r;
    EXPECT_EQ(share.integer_scalars.at("particles"), 5);
    EXPECT_EQ(share.row_widths, five_rows().row_widths);
  }
  // More ranks than rows: some get none.
  EXPECT_TRUE(mpm::io::read_checkpoint(file, mpm::Alone(0, 7)).integers.at("id").empty());
  EXPECT_EQ(mpm::io::read_checkpoint(file, mpm::Alone(6, 7)).integers.at("id"),
            (std::vector<std::int64_t>{14}));
  fs::remove_all(file.parent_path());
}

/// The message of the InputError write_checkpoint throws for `d`; empty (and a test failure) if none.
std::string refusal(const CheckpointData& d, const fs::path& file) {
  try {
    mpm::io::write_checkpoint(file, d);
  } catch (const mpm::InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return {};
}

TEST(CheckpointRows, InconsistentRowsAreRefusedNamingTheFile) {
  const fs::path file = scratch_file("bad.h5");
  CheckpointData d = five_rows();
  d.integers["id"].pop_back();
  EXPECT_EQ(refusal(d, file), "checkpoint " + file.string() + ": row arrays of different lengths ('x')");
  d = five_rows();
  d.row_widths["x"] = 3;
  EXPECT_EQ(refusal(d, file),
            "checkpoint " + file.string() + ": row array 'x' of 10 values is not rows of 3");
  d = five_rows();
  d.row_widths["v"] = 2;
  EXPECT_EQ(refusal(d, file),
            "checkpoint " + file.string() + ": row array 'v' is neither a real nor an integer array");
  EXPECT_FALSE(fs::exists(file));
  fs::remove_all(file.parent_path());
}

}  // namespace
