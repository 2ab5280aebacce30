// HDF5 dataset files (schema: docs/dataset-format.md). One file per dataset, readable with h5py.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

#include "data/trajectory_batch.h"

namespace quadfdi {

inline constexpr const char* kDatasetFormat = "quadfdi-dataset";
inline constexpr int kDatasetVersion = 1;

struct DatasetMetadata {
  double dt = 0.002;               // [s]
  int window = 100;                // T [samples]
  int fault_step = 100;            // F [steps]
  std::string controller = "lqr";  // lqr | cbf
  std::string params = "nominal";  // plant parameter set name or file
  std::string residual_params = "nominal";
  std::string output = "position-euler";  // position-euler | position-rates
  std::string integrator = "rk4";
  std::uint64_t seed = 0;
  int preroll_max_steps = 0;
  std::string generator = "quadfdi 0.1.0";
};

// "FILE: problem" — for unreadable, foreign, truncated or inconsistent files.
class DatasetError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Writes to "<path>.tmp.<pid>" and renames, so a failed write never leaves a partial file nor
// destroys an existing one. The bytes depend only on the data (no timestamps).
void writeDataset(const std::string& path, const TrajectoryBatch& batch, const DatasetMetadata& meta);

// Reads and validates (format, version, every dataset's type and shape, value ranges).
TrajectoryBatch readDataset(const std::string& path, DatasetMetadata* meta = nullptr);

}  // namespace quadfdi
