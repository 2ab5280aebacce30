// One-off generator of the fuzzers' binary seeds: tiny model files and a tiny dataset.
//   build/fuzz/fuzz/fuzz_make_seeds DIR   → DIR/model/*.qfdi, DIR/weights/*.qfdw, DIR/dataset/*.h5
// (The committed corpora in fuzz/corpus/ were started from these and minimised with -merge=1.)
#include <hdf5.h>
#include <sys/stat.h>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "data/trajectory_batch.h"
#include "io/hdf5_dataset.h"
#include "inference/weights_file.h"
#include "networks/model.h"

using namespace quadfdi;

namespace {

// A tiny seeded network (TCN: 8 channels, kernel 2, dilations 1 and 2).
FaultIdentifier tinyNetwork(Architecture a, FeatureSet f, int window, int hidden) {
  ModelMetadata m;
  m.architecture = a;
  m.features = f;
  m.window = window;
  m.hidden = hidden;
  m.tcn.channels = 8;
  m.tcn.kernel = 2;
  m.tcn.dilations = {1, 2};
  m.scale = "fuzz-seed";
  m.command = "fuzz_make_seeds";
  return FaultIdentifier::create(m, 1);
}

// As a LibTorch archive (checkpoints, model_file target).
void saveModel(Architecture a, FeatureSet f, int window, int hidden, const std::string& path) {
  tinyNetwork(a, f, window, hidden).save(path);
}

// As a weights file (.qfdw), what detect and evaluate load (weights_file target).
void saveWeights(Architecture a, FeatureSet f, int window, int hidden, const std::string& path) {
  const FaultIdentifier net = tinyNetwork(a, f, window, hidden);
  std::ofstream(path, std::ios::binary) << encodeWeightsFile(net.metadata(), exportWeights(net));
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: fuzz_make_seeds DIR\n";
    return 2;
  }
  const std::string dir = argv[1];
  ::mkdir(dir.c_str(), 0755);
  ::mkdir((dir + "/model").c_str(), 0755);
  ::mkdir((dir + "/dataset").c_str(), 0755);
  ::mkdir((dir + "/weights").c_str(), 0755);
  saveWeights(Architecture::kLstm, FeatureSet::kModelFree, 3, 4, dir + "/weights/lstm-tiny.qfdw");
  saveWeights(Architecture::kMlp, FeatureSet::kModelFree, 2, 3, dir + "/weights/mlp-tiny.qfdw");
  saveWeights(Architecture::kTcn, FeatureSet::kModelFreeHeading, 4, 4, dir + "/weights/tcn-tiny.qfdw");
  saveModel(Architecture::kLstm, FeatureSet::kModelFree, 3, 4, dir + "/model/lstm-tiny.qfdi");
  saveModel(Architecture::kMlp, FeatureSet::kResidualOnly, 2, 3, dir + "/model/mlp-tiny.qfdi");
  // Metadata that disagrees with the weights: saved with H = 4, the metadata then says H = 5
  // (same window and features), so the LibTorch archive itself is intact.
  {
    std::string text = slurp(dir + "/model/lstm-tiny.qfdi");
    const std::size_t at = text.find("\"hidden\":4");
    if (at == std::string::npos) return 1;
    text.replace(at, 10, "\"hidden\":5");
    std::ofstream(dir + "/model/lstm-hidden-mismatch.qfdi", std::ios::binary) << text;
  }

  // One trajectory, T = 3 (7 samples), the fault at step 3.
  TrajectoryBatch b;
  b.resize(1, 7);
  for (std::size_t k = 0; k < 7; ++k) {
    for (std::size_t c = 0; c < kOutputDim; ++c) b.outputs[k * kOutputDim + c] = 0.01f * static_cast<float>(k + c);
    for (std::size_t c = 0; c < kInputDim; ++c) b.inputs[k * kInputDim + c] = 0.0662f;
    for (std::size_t c = 0; c < kStateDim; ++c) b.states[k * kStateDim + c] = 0.01f * static_cast<float>(k);
    for (std::size_t c = 0; c < kOutputDim; ++c) b.residuals[k * kOutputDim + c] = k == 0 ? 0.0f : 1e-4f;
  }
  b.theta = {1.0f, 0.0f, 1.0f, 1.0f};
  b.fault_step = {3};
  b.length = {7};
  b.end_status = {0};
  b.goal = {0.0, 0.0, 1.0};
  DatasetMetadata meta;
  meta.window = 3;
  meta.fault_step = 3;
  writeDataset(dir + "/dataset/tiny.h5", b, meta);

  // The same file whose `outputs` claims 2^30 trajectories but stores nothing (HDF5 allocates
  // contiguous storage late, so the file stays a few kilobytes).
  writeDataset(dir + "/dataset/huge-shape.h5", b, meta);
  {
    const hid_t file = H5Fopen((dir + "/dataset/huge-shape.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    H5Ldelete(file, "trajectories/outputs", H5P_DEFAULT);
    const hsize_t dims[3] = {hsize_t{1} << 30, 7, kOutputDim};
    const hid_t space = H5Screate_simple(3, dims, nullptr);
    const hid_t ds = H5Dcreate2(file, "trajectories/outputs", H5T_IEEE_F32LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (file < 0 || space < 0 || ds < 0) return 1;
    H5Dclose(ds);
    H5Sclose(space);
    H5Fclose(file);
  }
  std::cout << "seeds written under " << dir << "\n";
  return 0;
}
