// Golden files (issue 7): fixed seeds, outputs checked in under tests/golden/. Any change in
// numerical behaviour shows up here as a failure that names the first differing line; accept it
// on purpose with scripts/update-goldens.sh and review the diff.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "cli/cli_support.h"
#include "io/hdf5_dataset.h"

namespace {

using quadfdi::test::CommandResult;
std::string temp(const std::string& name) { return ::testing::TempDir() + "quadfdi_golden_" + name; }
std::string golden(const std::string& name) { return std::string(QUADFDI_SOURCE_DIR) + "/tests/golden/" + name; }

std::string readFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// Exact comparison, with the first differing line in the message.
void expectSameText(const std::string& actual, const std::string& golden_path) {
  const std::string expected = readFile(golden_path);
  ASSERT_FALSE(expected.empty()) << golden_path << " is missing: run scripts/update-goldens.sh";
  if (actual == expected) return;
  std::istringstream a(actual), e(expected);
  std::string la, le;
  int line = 0;
  while (true) {
    ++line;
    const bool ga = static_cast<bool>(std::getline(a, la)), ge = static_cast<bool>(std::getline(e, le));
    if (!ga && !ge) break;
    if (la != le || ga != ge) {
      ADD_FAILURE() << golden_path << ":" << line << " differs\n  golden: " << le << "\n  now:    " << la
                    << "\n(accept on purpose with scripts/update-goldens.sh)";
      return;
    }
  }
  ADD_FAILURE() << golden_path << " differs";
}

// FNV-1a over the bytes of a vector.
template <class T>
void hashInto(std::uint64_t& h, const std::vector<T>& v) {
  const auto* p = reinterpret_cast<const unsigned char*>(v.data());
  for (std::size_t i = 0; i < v.size() * sizeof(T); ++i) h = (h ^ p[i]) * 0x100000001b3ull;
}

TEST(Golden, SimulatedFlight) {
  const CommandResult r = quadfdi::test::runQuadfdi(
      "simulate --motor 2 --theta 0.3 --fault-step 60 --steps 120 --seed 1 --full-state --output -", false);
  ASSERT_EQ(r.exit_code, 0);
  expectSameText(r.out, golden("flight-motor2-theta0.3-seed1.csv"));
}

TEST(Golden, CbfFlight) {
  const CommandResult r = quadfdi::test::runQuadfdi(
      "simulate --controller cbf --motor 4 --theta 0 --fault-step 50 --steps 150 --seed 3 --output -", false);
  ASSERT_EQ(r.exit_code, 0);
  expectSameText(r.out, golden("flight-cbf-motor4-seed3.csv"));
}

TEST(Golden, TinyDatasetContent) {
  const std::string path = temp("tiny.h5");
  ASSERT_EQ(quadfdi::test::runQuadfdi("generate --scale tiny --seed 2 --threads 2 -q -o " + path).exit_code, 0);
  const quadfdi::TrajectoryBatch b = quadfdi::readDataset(path);
  std::uint64_t h = 0xcbf29ce484222325ull;
  hashInto(h, b.outputs);
  hashInto(h, b.inputs);
  hashInto(h, b.states);
  hashInto(h, b.residuals);
  hashInto(h, b.theta);
  hashInto(h, b.length);
  char text[64];
  std::snprintf(text, sizeof text, "%d trajectories, content FNV-1a %016llx\n", b.count, static_cast<unsigned long long>(h));
  expectSameText(text, golden("dataset-tiny-seed2.txt"));
}

// The shipped model through the detector on the golden flight, with the portable generic kernel
// (no FMA, so the same bits on every x86-64 machine).
TEST(Golden, ShippedModelDetections) {
  const CommandResult r = quadfdi::test::runQuadfdi(
      "simulate --motor 3 --theta 0 --fault-step 150 --steps 260 --seed 5 --output - 2>/dev/null | QUADFDI_KERNEL=generic " +
          std::string(QUADFDI_EXE) + " detect --input - -q",
      false);
  ASSERT_EQ(r.exit_code, 0);
  expectSameText(r.out, golden("detect-motor3-seed5.jsonl"));
}

}  // namespace
