#include "io/hdf5_dataset.h"

#include <hdf5.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <vector>

namespace quadfdi {
namespace {

// RAII for HDF5 identifiers.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

// HDF5 prints an error stack for every failed call by default; we report our own one line.
void silenceHdf5() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

class Writer {
 public:
  Writer(const std::string& path, const std::string& shown) : shown_(shown) {
    Handle fcpl(H5Pcreate(H5P_FILE_CREATE), H5Pclose);
    file_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, fcpl.get(), H5P_DEFAULT);
    if (file_ < 0) throw DatasetError(shown_ + ": cannot create HDF5 file");
    gcpl_ = H5Pcreate(H5P_GROUP_CREATE);
    H5Pset_obj_track_times(gcpl_, 0);  // no timestamps: same data, same bytes
    group_ = H5Gcreate2(file_, "trajectories", H5P_DEFAULT, gcpl_, H5P_DEFAULT);
    if (group_ < 0) throw DatasetError(shown_ + ": cannot create group");
  }
  ~Writer() {
    if (group_ >= 0) H5Gclose(group_);
    if (gcpl_ >= 0) H5Pclose(gcpl_);
    if (file_ >= 0) H5Fclose(file_);
  }
  void close() {
    H5Gclose(group_);
    group_ = -1;
    H5Pclose(gcpl_);
    gcpl_ = -1;
    const herr_t status = H5Fclose(file_);
    file_ = -1;
    if (status < 0) throw DatasetError(shown_ + ": write failed (disk full or I/O error)");
  }

  void dataset(const char* name, hid_t mem_type, hid_t file_type, const std::vector<hsize_t>& dims, const void* data) {
    Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
    Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
    H5Pset_obj_track_times(dcpl.get(), 0);
    Handle ds(H5Dcreate2(group_, name, file_type, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT), H5Dclose);
    if (!ds.valid()) throw DatasetError(shown_ + ": cannot create dataset " + name);
    hsize_t total = 1;
    for (hsize_t d : dims) total *= d;
    if (total > 0 && H5Dwrite(ds.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
      throw DatasetError(shown_ + ": cannot write dataset " + name + " (disk full?)");
  }

  void attribute(const char* name, hid_t mem_type, hid_t file_type, const void* value) {
    Handle space(H5Screate(H5S_SCALAR), H5Sclose);
    Handle a(H5Acreate2(file_, name, file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
    if (!a.valid() || H5Awrite(a.get(), mem_type, value) < 0) throw DatasetError(shown_ + ": cannot write attribute " + name);
  }
  void attribute(const char* name, const std::string& value) {
    Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(type.get(), value.empty() ? 1 : value.size());
    H5Tset_strpad(type.get(), H5T_STR_NULLPAD);
    H5Tset_cset(type.get(), H5T_CSET_UTF8);
    attribute(name, type.get(), type.get(), value.c_str());
  }

 private:
  std::string shown_;
  hid_t file_ = -1, gcpl_ = -1, group_ = -1;
};

class Reader {
 public:
  explicit Reader(const std::string& path) : path_(path) {
    if (access(path.c_str(), R_OK) != 0) throw DatasetError(path + ": cannot open for reading");
    if (H5Fis_hdf5(path.c_str()) <= 0) throw DatasetError(path + ": not an HDF5 file (or truncated)");
    file_ = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    if (file_ < 0) throw DatasetError(path + ": cannot open HDF5 file (truncated or corrupt?)");
  }
  ~Reader() {
    if (file_ >= 0) H5Fclose(file_);
  }

  std::string stringAttribute(const char* name) {
    Handle a(H5Aopen(file_, name, H5P_DEFAULT), H5Aclose);
    if (!a.valid()) fail(std::string("missing attribute '") + name + "'");
    Handle type(H5Aget_type(a.get()), H5Tclose);
    if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) > 0)
      fail(std::string("attribute '") + name + "' is not a fixed-length string");
    const std::size_t size = H5Tget_size(type.get());
    if (size > 4096) fail(std::string("attribute '") + name + "' is implausibly long");
    std::string value(size, '\0');
    // Read with the file's own string type: no character-set conversion to fail.
    if (H5Aread(a.get(), type.get(), value.data()) < 0) fail(std::string("cannot read attribute '") + name + "'");
    value.resize(value.find('\0') == std::string::npos ? value.size() : value.find('\0'));
    return value;
  }
  template <typename T>
  T numberAttribute(const char* name, hid_t mem_type) {
    Handle a(H5Aopen(file_, name, H5P_DEFAULT), H5Aclose);
    if (!a.valid()) fail(std::string("missing attribute '") + name + "'");
    Handle space(H5Aget_space(a.get()), H5Sclose);
    Handle type(H5Aget_type(a.get()), H5Tclose);
    const H5T_class_t cls = H5Tget_class(type.get());
    if (H5Sget_simple_extent_npoints(space.get()) != 1 || (cls != H5T_INTEGER && cls != H5T_FLOAT))
      fail(std::string("attribute '") + name + "' is not a number");
    T value{};
    if (H5Aread(a.get(), mem_type, &value) < 0) fail(std::string("cannot read attribute '") + name + "'");
    return value;
  }

  template <typename T>
  void dataset(const char* name, hid_t mem_type, H5T_class_t expected_class, const std::vector<hsize_t>& dims,
               std::vector<T>& out) {
    const std::string full = std::string("trajectories/") + name;
    Handle ds(H5Dopen2(file_, full.c_str(), H5P_DEFAULT), H5Dclose);
    if (!ds.valid()) fail("missing dataset '" + full + "'");
    Handle type(H5Dget_type(ds.get()), H5Tclose);
    if (H5Tget_class(type.get()) != expected_class) fail("dataset '" + full + "' has the wrong element type");
    Handle space(H5Dget_space(ds.get()), H5Sclose);
    const int rank = H5Sget_simple_extent_ndims(space.get());
    if (rank != static_cast<int>(dims.size())) fail("dataset '" + full + "' has the wrong rank");
    std::vector<hsize_t> actual(static_cast<std::size_t>(rank));
    H5Sget_simple_extent_dims(space.get(), actual.data(), nullptr);
    hsize_t total = 1;
    for (std::size_t i = 0; i < dims.size(); ++i) {
      if (actual[i] != dims[i])
        fail("dataset '" + full + "' has shape mismatch in dimension " + std::to_string(i) + " (" +
             std::to_string(actual[i]) + " instead of " + std::to_string(dims[i]) + ")");
      total *= dims[i];
    }
    // The file must hold what the shape claims before we allocate for it: writeDataset stores
    // every dataset in full, and compression (deflate) cannot shrink data below 1/1100.
    if (total > 0) {
      Handle dcpl(H5Dget_create_plist(ds.get()), H5Pclose);
      const hsize_t ratio = dcpl.valid() && H5Pget_nfilters(dcpl.get()) > 0 ? 1100 : 1;
      const hsize_t element = H5Tget_size(type.get());
      if (element == 0 || H5Dget_storage_size(ds.get()) / element < total / ratio)
        fail("dataset '" + full + "' stores less data than its shape needs (truncated or corrupt file?)");
    }
    out.resize(static_cast<std::size_t>(total));
    if (total > 0 && H5Dread(ds.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
      fail("cannot read dataset '" + full + "' (truncated or corrupt file?)");
  }

  bool hasDataset(const char* name) const {
    const std::string full = std::string("trajectories/") + name;
    return H5Lexists(file_, "trajectories", H5P_DEFAULT) > 0 && H5Lexists(file_, full.c_str(), H5P_DEFAULT) > 0;
  }

  // Shape of a dataset in the trajectories group.
  std::vector<hsize_t> shape(const char* name) {
    const std::string full = std::string("trajectories/") + name;
    Handle ds(H5Dopen2(file_, full.c_str(), H5P_DEFAULT), H5Dclose);
    if (!ds.valid()) fail("missing dataset '" + full + "'");
    Handle space(H5Dget_space(ds.get()), H5Sclose);
    const int rank = H5Sget_simple_extent_ndims(space.get());
    if (rank < 1 || rank > 8) fail("dataset '" + full + "' has an unexpected rank");
    std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
    H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
    return dims;
  }

  [[noreturn]] void fail(const std::string& problem) const { throw DatasetError(path_ + ": " + problem); }

 private:
  std::string path_;
  hid_t file_ = -1;
};

}  // namespace

void writeDataset(const std::string& path, const TrajectoryBatch& b, const DatasetMetadata& meta) {
  silenceHdf5();
  const std::string temp = path + ".tmp." + std::to_string(::getpid());
  try {
    Writer w(temp, path);
    const auto n = static_cast<hsize_t>(b.count), s = static_cast<hsize_t>(b.samples);
    w.attribute("format", kDatasetFormat);
    const int version = kDatasetVersion;
    w.attribute("version", H5T_NATIVE_INT, H5T_STD_I32LE, &version);
    w.attribute("dt", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, &meta.dt);
    w.attribute("window", H5T_NATIVE_INT, H5T_STD_I32LE, &meta.window);
    w.attribute("fault_step", H5T_NATIVE_INT, H5T_STD_I32LE, &meta.fault_step);
    w.attribute("samples_per_trajectory", H5T_NATIVE_INT, H5T_STD_I32LE, &b.samples);
    w.attribute("seed", H5T_NATIVE_UINT64, H5T_STD_U64LE, &meta.seed);
    w.attribute("preroll_max_steps", H5T_NATIVE_INT, H5T_STD_I32LE, &meta.preroll_max_steps);
    w.attribute("controller", meta.controller);
    w.attribute("params", meta.params);
    w.attribute("residual_params", meta.residual_params);
    w.attribute("output", meta.output);
    w.attribute("integrator", meta.integrator);
    w.attribute("generator", meta.generator);
    w.dataset("outputs", H5T_NATIVE_FLOAT, H5T_IEEE_F32LE, {n, s, kOutputDim}, b.outputs.data());
    w.dataset("inputs", H5T_NATIVE_FLOAT, H5T_IEEE_F32LE, {n, s, kInputDim}, b.inputs.data());
    w.dataset("states", H5T_NATIVE_FLOAT, H5T_IEEE_F32LE, {n, s, kStateDim}, b.states.data());
    w.dataset("residuals", H5T_NATIVE_FLOAT, H5T_IEEE_F32LE, {n, s, kOutputDim}, b.residuals.data());
    if (!b.rates.empty()) w.dataset("rates", H5T_NATIVE_FLOAT, H5T_IEEE_F32LE, {n, s, kRateDim}, b.rates.data());
    w.dataset("theta", H5T_NATIVE_FLOAT, H5T_IEEE_F32LE, {n, kInputDim}, b.theta.data());
    w.dataset("fault_step", H5T_NATIVE_INT32, H5T_STD_I32LE, {n}, b.fault_step.data());
    w.dataset("length", H5T_NATIVE_INT32, H5T_STD_I32LE, {n}, b.length.data());
    w.dataset("end_status", H5T_NATIVE_UINT8, H5T_STD_U8LE, {n}, b.end_status.data());
    w.dataset("initial_state", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, {n, kStateDim}, b.initial_state.data());
    w.dataset("goal", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, {n, 3}, b.goal.data());
    w.dataset("scenario_index", H5T_NATIVE_UINT64, H5T_STD_U64LE, {n}, b.scenario_index.data());
    w.close();
  } catch (...) {
    std::remove(temp.c_str());
    throw;
  }
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    std::remove(temp.c_str());
    throw DatasetError(path + ": cannot replace the output file");
  }
}

TrajectoryBatch readDataset(const std::string& path, DatasetMetadata* meta_out) {
  silenceHdf5();
  Reader r(path);
  if (r.stringAttribute("format") != kDatasetFormat) r.fail("not a quadfdi dataset (format attribute)");
  const int version = r.numberAttribute<int>("version", H5T_NATIVE_INT);
  if (version != kDatasetVersion)
    r.fail("dataset version " + std::to_string(version) + " is not supported (expected " +
           std::to_string(kDatasetVersion) + ")");
  DatasetMetadata meta;
  meta.dt = r.numberAttribute<double>("dt", H5T_NATIVE_DOUBLE);
  meta.window = r.numberAttribute<int>("window", H5T_NATIVE_INT);
  meta.fault_step = r.numberAttribute<int>("fault_step", H5T_NATIVE_INT);
  const int samples = r.numberAttribute<int>("samples_per_trajectory", H5T_NATIVE_INT);
  meta.seed = r.numberAttribute<std::uint64_t>("seed", H5T_NATIVE_UINT64);
  meta.preroll_max_steps = r.numberAttribute<int>("preroll_max_steps", H5T_NATIVE_INT);
  meta.controller = r.stringAttribute("controller");
  meta.params = r.stringAttribute("params");
  meta.residual_params = r.stringAttribute("residual_params");
  meta.output = r.stringAttribute("output");
  meta.integrator = r.stringAttribute("integrator");
  meta.generator = r.stringAttribute("generator");
  if (!(meta.dt > 0.0 && std::isfinite(meta.dt))) r.fail("attribute 'dt' must be > 0");
  if (meta.window < 1 || samples <= meta.window || samples > 10000000) r.fail("inconsistent window / samples_per_trajectory");
  if (meta.output != "position-euler" && meta.output != "position-rates") r.fail("unknown output kind '" + meta.output + "'");

  const std::vector<hsize_t> outputs_shape = r.shape("outputs");
  if (outputs_shape.size() != 3) r.fail("dataset 'trajectories/outputs' must have rank 3");
  const hsize_t n = outputs_shape[0];
  if (n > (1u << 30)) r.fail("implausible trajectory count");
  TrajectoryBatch b;
  b.count = static_cast<int>(n);
  b.samples = samples;
  const auto s = static_cast<hsize_t>(samples);
  r.dataset("outputs", H5T_NATIVE_FLOAT, H5T_FLOAT, {n, s, kOutputDim}, b.outputs);
  r.dataset("inputs", H5T_NATIVE_FLOAT, H5T_FLOAT, {n, s, kInputDim}, b.inputs);
  r.dataset("states", H5T_NATIVE_FLOAT, H5T_FLOAT, {n, s, kStateDim}, b.states);
  r.dataset("residuals", H5T_NATIVE_FLOAT, H5T_FLOAT, {n, s, kOutputDim}, b.residuals);
  // Optional: files written before 2026-12-02 have no body rates (b.rates stays empty).
  if (r.hasDataset("rates")) r.dataset("rates", H5T_NATIVE_FLOAT, H5T_FLOAT, {n, s, kRateDim}, b.rates);
  r.dataset("theta", H5T_NATIVE_FLOAT, H5T_FLOAT, {n, kInputDim}, b.theta);
  r.dataset("fault_step", H5T_NATIVE_INT32, H5T_INTEGER, {n}, b.fault_step);
  r.dataset("length", H5T_NATIVE_INT32, H5T_INTEGER, {n}, b.length);
  r.dataset("end_status", H5T_NATIVE_UINT8, H5T_INTEGER, {n}, b.end_status);
  r.dataset("initial_state", H5T_NATIVE_DOUBLE, H5T_FLOAT, {n, kStateDim}, b.initial_state);
  r.dataset("goal", H5T_NATIVE_DOUBLE, H5T_FLOAT, {n, 3}, b.goal);
  r.dataset("scenario_index", H5T_NATIVE_UINT64, H5T_INTEGER, {n}, b.scenario_index);
  for (std::size_t i = 0; i < n; ++i) {
    if (b.length[i] < 0 || b.length[i] > samples) r.fail("trajectory " + std::to_string(i) + " has an invalid length");
    if (b.fault_step[i] < 0 || b.fault_step[i] > samples) r.fail("trajectory " + std::to_string(i) + " has an invalid fault step");
    if (b.end_status[i] > static_cast<std::uint8_t>(StepStatus::kBelowGround))
      r.fail("trajectory " + std::to_string(i) + " has an invalid end status");
    for (int j = 0; j < kInputDim; ++j) {
      const float t = b.theta[i * kInputDim + static_cast<std::size_t>(j)];
      if (!(t >= 0.0f && t <= 1.0f)) r.fail("trajectory " + std::to_string(i) + " has theta outside [0, 1]");
    }
  }
  if (meta_out) *meta_out = meta;
  return b;
}

}  // namespace quadfdi
