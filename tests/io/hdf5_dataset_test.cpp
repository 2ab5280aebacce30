#include <gtest/gtest.h>
#include <hdf5.h>

#include <fstream>
#include <sstream>

#include "data/rollout.h"
#include "io/hdf5_dataset.h"
#include "scratch_path.h"

namespace quadfdi {
namespace {

std::string temp(const std::string& name) { return quadfdi::test::scratchPath("h5", name); }

std::string bytesOf(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

TrajectoryBatch smallBatch(int threads) {
  RolloutConfig c;
  c.window = 10;
  c.seed = 3;
  TrajectoryBatch b;
  RolloutEngine(c).run(algorithm1Jobs(0, 6, {0.0, 0.5, 1.0}, {2}), threads, b);
  return b;
}

std::string errorOf(const std::string& path) {
  try {
    readDataset(path);
  } catch (const DatasetError& e) {
    return e.what();
  }
  return "";
}

TEST(Hdf5Dataset, RoundTripPreservesEveryValue) {
  const TrajectoryBatch b = smallBatch(1);
  DatasetMetadata meta;
  meta.window = 10;
  meta.fault_step = 10;
  meta.seed = 3;
  meta.controller = "cbf";
  meta.params = "perturbed";
  const std::string path = temp("roundtrip.h5");
  writeDataset(path, b, meta);
  DatasetMetadata back_meta;
  const TrajectoryBatch back = readDataset(path, &back_meta);
  EXPECT_EQ(back.count, b.count);
  EXPECT_EQ(back.samples, b.samples);
  EXPECT_EQ(back.outputs, b.outputs);
  EXPECT_EQ(back.inputs, b.inputs);
  EXPECT_EQ(back.states, b.states);
  EXPECT_EQ(back.residuals, b.residuals);
  EXPECT_FALSE(b.rates.empty());
  EXPECT_EQ(back.rates, b.rates);
  EXPECT_EQ(back.theta, b.theta);
  EXPECT_EQ(back.fault_step, b.fault_step);
  EXPECT_EQ(back.length, b.length);
  EXPECT_EQ(back.end_status, b.end_status);
  EXPECT_EQ(back.initial_state, b.initial_state);
  EXPECT_EQ(back.goal, b.goal);
  EXPECT_EQ(back.scenario_index, b.scenario_index);
  EXPECT_EQ(back_meta.controller, "cbf");
  EXPECT_EQ(back_meta.params, "perturbed");
  EXPECT_EQ(back_meta.seed, 3u);
  EXPECT_EQ(back_meta.window, 10);
  EXPECT_EQ(back_meta.dt, 0.002);
}

// Files written before the body rates were recorded have no 'rates' dataset: they still read,
// with no rates, and everything else unchanged.
TEST(Hdf5Dataset, AFileWithoutBodyRatesReadsWithNone) {
  TrajectoryBatch b = smallBatch(1);
  b.rates.clear();
  const std::string path = temp("no-rates.h5");
  DatasetMetadata meta;
  meta.window = 10;
  meta.fault_step = 10;
  writeDataset(path, b, meta);
  const TrajectoryBatch back = readDataset(path);
  EXPECT_TRUE(back.rates.empty());
  EXPECT_EQ(back.outputs, b.outputs);
  EXPECT_EQ(back.states, b.states);
}

TEST(Hdf5Dataset, FilesAreByteIdenticalWhateverTheThreadCount) {
  const std::string a = temp("one.h5"), c = temp("two.h5");
  writeDataset(a, smallBatch(1), DatasetMetadata{});
  writeDataset(c, smallBatch(2), DatasetMetadata{});
  const std::string bytes = bytesOf(a);
  EXPECT_GT(bytes.size(), 1000u);
  EXPECT_EQ(bytes, bytesOf(c));
}

TEST(Hdf5Dataset, RefusesMissingForeignTruncatedAndWrongFiles) {
  EXPECT_EQ(errorOf(temp("missing.h5")), temp("missing.h5") + ": cannot open for reading");
  const std::string text = temp("text.h5");
  std::ofstream(text) << "t,x,y\n1,2,3\n";
  EXPECT_EQ(errorOf(text), text + ": not an HDF5 file (or truncated)");

  const std::string good = temp("good.h5");
  writeDataset(good, smallBatch(1), DatasetMetadata{});
  const std::string bytes = bytesOf(good);
  const std::string truncated = temp("truncated.h5");
  std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  EXPECT_NE(errorOf(truncated).rfind(truncated + ": ", 0), std::string::npos);
  EXPECT_NE(errorOf(truncated), "");

  // A valid HDF5 file that is not ours.
  const std::string foreign = temp("foreign.h5");
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fcreate(foreign.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  H5Fclose(f);
  EXPECT_EQ(errorOf(foreign), foreign + ": missing attribute 'format'");

  // Ours, but with a future version.
  const std::string future = temp("future.h5");
  writeDataset(future, smallBatch(1), DatasetMetadata{});
  {
    const hid_t ff = H5Fopen(future.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    const hid_t a = H5Aopen(ff, "version", H5P_DEFAULT);
    const int v = 99;
    H5Awrite(a, H5T_NATIVE_INT, &v);
    H5Aclose(a);
    H5Fclose(ff);
  }
  EXPECT_EQ(errorOf(future), future + ": dataset version 99 is not supported (expected 1)");
}

TEST(Hdf5Dataset, FailedWriteKeepsTheExistingFile) {
  const std::string path = temp("keep.h5");
  std::ofstream(path) << "precious";
  EXPECT_THROW(writeDataset("/nonexistent-dir/x.h5", smallBatch(1), DatasetMetadata{}), DatasetError);
  EXPECT_EQ(bytesOf(path), "precious");
}

}  // namespace
}  // namespace quadfdi
