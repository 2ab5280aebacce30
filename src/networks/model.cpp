#include <dlfcn.h>
#include <unistd.h>

#include <caffe2/serialize/inline_container.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "networks/torch_net.h"
#include "inference/weights_file.h"

namespace quadfdi {

FaultNetImpl::FaultNetImpl(const ModelMetadata& m) : architecture(m.architecture) {
  const int n = m.channels();
  mean = register_buffer("mean", torch::zeros({n}));
  scale = register_buffer("scale", torch::ones({n}));
  if (architecture == Architecture::kLstm) {
    lstm = register_module("lstm", torch::nn::LSTM(torch::nn::LSTMOptions(n, m.hidden).batch_first(true)));
    head1 = register_module("head1", torch::nn::Linear(m.hidden, 64));
    head2 = register_module("head2", torch::nn::Linear(64, 4));
  } else if (architecture == Architecture::kTcn) {
    const TcnShape& s = m.tcn;
    for (std::size_t i = 0; i < s.dilations.size(); ++i) {
      const int in = i == 0 ? n : s.channels;
      convs.push_back(register_module("conv" + std::to_string(i),
                                      torch::nn::Conv1d(torch::nn::Conv1dOptions(in, s.channels, s.kernel).dilation(s.dilations[i]))));
    }
    head1 = register_module("head1", torch::nn::Linear(s.channels, 64));
    head2 = register_module("head2", torch::nn::Linear(64, 4));
  } else {
    mlp = register_module(
        "mlp", torch::nn::Sequential(torch::nn::Linear(n * m.window, m.hidden), torch::nn::ReLU(),
                                     torch::nn::Linear(m.hidden, m.hidden), torch::nn::ReLU(),
                                     torch::nn::Linear(m.hidden, m.hidden), torch::nn::ReLU(),
                                     torch::nn::Linear(m.hidden, m.hidden), torch::nn::ReLU(),
                                     torch::nn::Linear(m.hidden, 64), torch::nn::ReLU(), torch::nn::Linear(64, 4)));
  }
}

torch::Tensor FaultNetImpl::forward(torch::Tensor x) {
  x = (x - mean) / scale;
  if (architecture == Architecture::kLstm) {
    const torch::Tensor out = std::get<0>(lstm->forward(x));       // [B, T, H]
    const torch::Tensor last = torch::relu(out.select(1, out.size(1) - 1));
    return torch::sigmoid(head2->forward(torch::relu(head1->forward(last))));
  }
  if (architecture == Architecture::kTcn) {
    // The last position sees exactly the last receptive-field samples, as the streaming form does
    // (inference/engine.h).
    const torch::Tensor last = tcnColumns(x).select(2, -1);
    return torch::sigmoid(head2->forward(torch::relu(head1->forward(last))));
  }
  return torch::sigmoid(mlp->forward(x.flatten(1)));
}

torch::Tensor FaultNetImpl::tcnColumns(const torch::Tensor& normalised) {
  // Valid (unpadded) causal convolutions: output column j depends on input samples j … j + R − 1.
  torch::Tensor h = normalised.transpose(1, 2);  // [B, n, L]
  for (std::size_t i = 0; i < convs.size(); ++i) {
    const torch::Tensor y = torch::relu(convs[i]->forward(h));
    h = i == 0 ? y : y + h.narrow(2, h.size(2) - y.size(2), y.size(2));  // residual, aligned on the end
  }
  return h;  // [B, C, L − R + 1]
}

torch::Tensor FaultNetImpl::forwardSequence(torch::Tensor x) {
  if (architecture != Architecture::kTcn) throw std::logic_error("forwardSequence: only a TCN is causal per position");
  const torch::Tensor columns = tcnColumns((x - mean) / scale).transpose(1, 2);  // [B, L − R + 1, C]
  return torch::sigmoid(head2->forward(torch::relu(head1->forward(columns))));
}

void loadNormalisation(FaultIdentifier::Impl& impl) {
  const ModelMetadata& m = impl.metadata;
  const auto n = static_cast<std::size_t>(m.channels());
  torch::NoGradGuard no_grad;
  if (m.feature_mean.size() == n) impl.net->mean.copy_(torch::tensor(m.feature_mean));
  if (m.feature_std.size() == n) impl.net->scale.copy_(torch::tensor(m.feature_std));
}

FaultIdentifier::FaultIdentifier(std::shared_ptr<Impl> impl) : impl_(std::move(impl)) {}

FaultIdentifier FaultIdentifier::create(const ModelMetadata& metadata, std::uint64_t seed) {
  auto impl = std::make_shared<Impl>();
  impl->metadata = metadata;
  torch::manual_seed(seed);
  impl->net = FaultNet(metadata);
  loadNormalisation(*impl);
  return FaultIdentifier(impl);
}

const ModelMetadata& FaultIdentifier::metadata() const { return impl_->metadata; }
ModelMetadata& FaultIdentifier::metadata() { return impl_->metadata; }

void FaultIdentifier::predict(const float* windows, int count, float* theta) const {
  torch::NoGradGuard no_grad;
  impl_->net->eval();
  const ModelMetadata& m = impl_->metadata;
  const int per_window = m.window * m.channels();
  constexpr int kChunk = 4096;
  for (int first = 0; first < count; first += kChunk) {
    const int n = std::min(kChunk, count - first);
    const torch::Tensor x = torch::from_blob(const_cast<float*>(windows) + static_cast<std::ptrdiff_t>(first) * per_window,
                                             {n, m.window, m.channels()}, torch::kFloat32);
    const torch::Tensor y = impl_->net->forward(x).contiguous();
    std::memcpy(theta + static_cast<std::ptrdiff_t>(first) * 4, y.data_ptr<float>(), sizeof(float) * 4 * static_cast<std::size_t>(n));
  }
}

void FaultIdentifier::predictSequences(const float* sequences, int count, int length, float* theta) const {
  torch::NoGradGuard no_grad;
  impl_->net->eval();
  const ModelMetadata& m = impl_->metadata;
  const torch::Tensor x = torch::from_blob(const_cast<float*>(sequences), {count, length, m.channels()}, torch::kFloat32);
  const torch::Tensor y = impl_->net->forwardSequence(x).contiguous();
  std::memcpy(theta, y.data_ptr<float>(), sizeof(float) * static_cast<std::size_t>(y.numel()));
}

namespace {

// Floats in the parameters and buffers of the network `m` describes (FaultNetImpl's layers). The
// weights block stores them uncompressed, so a smaller block cannot hold them.
std::int64_t parameterCount(const ModelMetadata& m) {
  const std::int64_t n = m.channels(), h = m.hidden, t = m.window;
  const std::int64_t buffers = 2 * n, head = (h * 64 + 64) + (64 * 4 + 4);
  if (m.architecture == Architecture::kLstm) return buffers + 4 * h * (n + h) + 8 * h + head;
  if (m.architecture == Architecture::kTcn) {
    const std::int64_t c = m.tcn.channels, k = m.tcn.kernel;
    const auto layers = static_cast<std::int64_t>(m.tcn.dilations.size());
    return buffers + (c * n * k + c) + (layers - 1) * (c * c * k + c) + (c * 64 + 64) + (64 * 4 + 4);
  }
  return buffers + (n * t * h + h) + 3 * (h * h + h) + head;
}

// Name, type, device and shape of every parameter and buffer. torch::load replaces each tensor
// whole, shape included, so it alone would accept an intact archive of another architecture.
std::vector<std::string> layout(const FaultNet& net) {
  std::vector<std::string> out;
  auto add = [&](const std::string& name, const torch::Tensor& t) {
    std::ostringstream s;
    s << "'" << name << "' " << t.scalar_type() << ' ' << t.device() << ' ' << t.sizes();
    out.push_back(s.str());
  };
  for (const auto& p : net->named_parameters()) add(p.key(), p.value());
  for (const auto& b : net->named_buffers()) add(b.key(), b.value());
  return out;
}

// Name and CRC-32 of every record in a zip's central directory (zip64 too, as torch::save writes).
// Throws std::out_of_range where the structure does not fit in the bytes.
std::vector<std::pair<std::string, std::uint32_t>> zipDirectory(const std::string& z) {
  auto le = [&](std::uint64_t at, int bytes) {
    if (at > z.size() || static_cast<std::uint64_t>(bytes) > z.size() - at) throw std::out_of_range("zip");
    std::uint64_t v = 0;
    for (int i = bytes - 1; i >= 0; --i) v = v << 8 | static_cast<unsigned char>(z[static_cast<std::size_t>(at) + i]);
    return v;
  };
  const std::size_t eocd = z.rfind(std::string("PK\x05\x06", 4));  // end of central directory
  if (eocd == std::string::npos || eocd < 20) throw std::out_of_range("zip");
  std::uint64_t entries = le(eocd + 10, 2), at = le(eocd + 16, 4);
  if (entries == 0xFFFF || at == 0xFFFFFFFF) {  // zip64: the locator before it points at the zip64 record
    const std::uint64_t record = le(eocd - 20 + 8, 8);
    if (le(record, 4) != 0x06064b50) throw std::out_of_range("zip");
    entries = le(record + 32, 8);
    at = le(record + 48, 8);
  }
  std::vector<std::pair<std::string, std::uint32_t>> out;
  for (std::uint64_t e = 0; e < entries; ++e) {  // each entry is at least 46 bytes: ends within the data
    if (le(at, 4) != 0x02014b50) throw std::out_of_range("zip");
    const std::uint64_t name = le(at + 28, 2), extra = le(at + 30, 2), comment = le(at + 32, 2);
    if (name > 0) le(at + 46 + name - 1, 1);
    out.emplace_back(z.substr(static_cast<std::size_t>(at) + 46, static_cast<std::size_t>(name)),
                     static_cast<std::uint32_t>(le(at + 16, 4)));
    at += 46 + name + extra + comment;
  }
  return out;
}

// LibTorch's archive reader is built without CRC checks and trusts every byte: one flipped bit
// loads silently wrong weights or crashes its unpickler. So every record is read (and inflated)
// by LibTorch's zip reader first and checked against its CRC-32. Returns "" or the problem.
std::string checkArchive(const std::string& weights) {
  try {
    const auto directory = zipDirectory(weights);
    std::istringstream in(weights);
    caffe2::serialize::PyTorchStreamReader reader(&in);
    for (const auto& [name, crc] : directory) {
      const std::size_t slash = name.find('/');  // records are named relative to the archive's folder
      if (slash == std::string::npos) return "weights record '" + name + "' is outside the archive (corrupt file?)";
      const auto [data, size] = reader.getRecord(name.substr(slash + 1));
      if (crc32(static_cast<const std::uint8_t*>(data.get()), size) != crc)
        return "weights record '" + name + "' fails its CRC-32 check (corrupt file?)";
    }
  } catch (const std::out_of_range&) {
    return "weights are not a LibTorch zip archive (corrupt file?)";
  } catch (const c10::Error&) {
    return "cannot read the weights archive (corrupt file?)";
  }
  return {};
}

}  // namespace

void FaultIdentifier::save(const std::string& path) const {
  std::ostringstream weights;
  try {
    torch::save(impl_->net, weights);
  } catch (const c10::Error& e) {
    throw ModelError(path + ": cannot serialise the network");
  }
  const std::string w = weights.str();
  const std::string temp = path + ".tmp." + std::to_string(::getpid());
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    if (!out) throw ModelError(path + ": cannot write");
    out << kModelFormat << ' ' << kModelVersion << '\n' << metadataToJson(impl_->metadata) << '\n';
    out << "weights " << w.size() << '\n';
    out.write(w.data(), static_cast<std::streamsize>(w.size()));
    out.flush();
    if (!out) {
      std::remove(temp.c_str());
      throw ModelError(path + ": write failed (disk full or I/O error)");
    }
  }
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    std::remove(temp.c_str());
    throw ModelError(path + ": cannot replace the output file");
  }
}

FaultIdentifier FaultIdentifier::load(const std::string& path) {
  // A folder opens and reads as empty; a device (/dev/zero) would be read as one endless first line.
  std::error_code ignored;
  const std::filesystem::file_status status = std::filesystem::status(path, ignored);
  if (std::filesystem::is_directory(status)) throw ModelError(path + ": is a folder, not a model file");
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status))
    throw ModelError(path + ": is not a regular file, not a model file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ModelError(path + ": cannot open for reading");
  std::string magic;
  if (!std::getline(in, magic)) throw ModelError(path + ": empty file, not a quadfdi model");
  const std::string expected = std::string(kModelFormat) + " ";
  if (magic.rfind(expected, 0) != 0) throw ModelError(path + ": not a quadfdi model file (bad first line)");
  if (magic != expected + std::to_string(kModelVersion))
    throw ModelError(path + ": model format '" + magic.substr(expected.size()) + "' is not supported (expected " +
                     std::to_string(kModelVersion) + ")");
  std::string json_line;
  if (!std::getline(in, json_line)) throw ModelError(path + ": truncated (no metadata)");
  auto impl = std::make_shared<Impl>();
  impl->metadata = metadataFromJson(json_line, path + ":2");
  std::string header;
  if (!std::getline(in, header) || header.rfind("weights ", 0) != 0) throw ModelError(path + ": truncated (no weights)");
  std::size_t size = 0;
  try {
    size = std::stoull(header.substr(8));
  } catch (const std::exception&) {
    throw ModelError(path + ":3: bad weights header");
  }
  if (size > (std::size_t{1} << 32)) throw ModelError(path + ":3: implausible weights size");
  // Check the claims against the file before allocating: a few bytes must not cost gigabytes.
  if (const std::streamoff here = in.tellg(); here >= 0 && in.seekg(0, std::ios::end)) {
    const std::streamoff end = in.tellg();
    in.seekg(here);
    if (end >= here && size > static_cast<std::size_t>(end - here)) throw ModelError(path + ": truncated (weights incomplete)");
  }
  if (const std::int64_t floats = parameterCount(impl->metadata); size < 4 * static_cast<std::size_t>(floats))
    throw ModelError(path + ":3: weights do not match the architecture in the metadata (" + std::to_string(size) +
                     " bytes for " + std::to_string(floats) + " float parameters)");
  std::string w(size, '\0');
  in.read(w.data(), static_cast<std::streamsize>(size));
  if (static_cast<std::size_t>(in.gcount()) != size) throw ModelError(path + ": truncated (weights incomplete)");
  if (in.peek() != std::char_traits<char>::eof()) throw ModelError(path + ": trailing data after the weights");
  if (const std::string problem = checkArchive(w); !problem.empty()) throw ModelError(path + ": " + problem);
  impl->net = FaultNet(impl->metadata);
  const std::vector<std::string> expected_layout = layout(impl->net);
  try {
    std::istringstream ws(w);
    torch::load(impl->net, ws);
  } catch (const c10::Error&) {
    throw ModelError(path + ": weights do not match the architecture in the metadata (corrupt file?)");
  } catch (const std::exception&) {
    throw ModelError(path + ": cannot read the weights (corrupt file?)");
  }
  const std::vector<std::string> loaded_layout = layout(impl->net);
  for (std::size_t i = 0; i < loaded_layout.size(); ++i)
    if (loaded_layout[i] != expected_layout[i])
      throw ModelError(path + ": weights do not match the architecture in the metadata (" + loaded_layout[i] +
                       ", expected " + expected_layout[i] + ")");
  // A NaN weight makes every estimate NaN or constant: the detector would never raise an alarm.
  for (const auto& tensors : {impl->net->named_parameters(), impl->net->named_buffers()})
    for (const auto& t : tensors)
      if (!torch::isfinite(t.value()).all().item<bool>())
        throw ModelError(path + ": weights hold non-finite values (in '" + t.key() + "')");
  return FaultIdentifier(impl);
}

void configureCpu(int threads) {
  using SetThreads = void (*)(int);
  if (auto* set_blas = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) set_blas(1);
  if (threads > 0) torch::set_num_threads(threads);
  at::globalContext().setFlushDenormal(true);
}

bool cudaAvailable() { return torch::cuda::is_available(); }

}  // namespace quadfdi

namespace quadfdi {
namespace {

std::vector<float> toVector(const torch::Tensor& t) {
  const torch::Tensor c = t.detach().to(torch::kCPU, torch::kFloat32).contiguous();
  return std::vector<float>(c.data_ptr<float>(), c.data_ptr<float>() + c.numel());
}

DenseWeights denseOf(const torch::nn::LinearImpl& l) {
  DenseWeights d;
  d.in = static_cast<int>(l.weight.size(1));
  d.out = static_cast<int>(l.weight.size(0));
  d.weight = toVector(l.weight);
  d.bias = toVector(l.bias);
  return d;
}

}  // namespace

NetworkWeights exportWeights(const FaultIdentifier& model) {
  torch::NoGradGuard no_grad;
  const ModelMetadata& m = model.metadata();
  const FaultNet& net = model.impl()->net;
  NetworkWeights w;
  w.architecture = m.architecture;
  w.window = m.window;
  w.channels = m.channels();
  w.hidden = m.hidden;
  w.mean = toVector(net->mean);
  w.scale = toVector(net->scale);
  if (m.architecture == Architecture::kLstm) {
    torch::Tensor w_ih, w_hh, b_ih, b_hh;
    for (const auto& p : net->lstm->named_parameters()) {
      if (p.key() == "weight_ih_l0") w_ih = p.value();
      if (p.key() == "weight_hh_l0") w_hh = p.value();
      if (p.key() == "bias_ih_l0") b_ih = p.value();
      if (p.key() == "bias_hh_l0") b_hh = p.value();
    }
    if (!w_ih.defined() || !w_hh.defined() || !b_ih.defined() || !b_hh.defined())
      throw ModelError("exportWeights: the LSTM lacks its layer-0 parameters");
    w.gates.in = w.channels + w.hidden;
    w.gates.out = 4 * w.hidden;
    w.gates.weight = toVector(torch::cat({w_ih, w_hh}, 1));
    w.gates.bias = toVector(b_ih + b_hh);
    w.head = {denseOf(*net->head1), denseOf(*net->head2)};
  } else if (m.architecture == Architecture::kTcn) {
    for (std::size_t i = 0; i < net->convs.size(); ++i) {
      const torch::nn::Conv1dImpl& c = *net->convs[i];
      ConvWeights cw;
      cw.out = static_cast<int>(c.weight.size(0));
      cw.in = static_cast<int>(c.weight.size(1));
      cw.kernel = static_cast<int>(c.weight.size(2));
      cw.dilation = m.tcn.dilations[i];
      cw.weight = toVector(c.weight);
      cw.bias = toVector(c.bias);
      w.convs.push_back(std::move(cw));
    }
    w.head = {denseOf(*net->head1), denseOf(*net->head2)};
  } else {
    for (const auto& module : net->mlp->children())
      if (const auto* linear = module->as<torch::nn::LinearImpl>()) w.head.push_back(denseOf(*linear));
  }
  return w;
}

namespace {

// Copies `values` into `target` (a parameter or buffer), refusing a size mismatch.
void assign(torch::Tensor target, const std::vector<float>& values, const std::string& name) {
  if (static_cast<std::int64_t>(values.size()) != target.numel())
    throw ModelError("importWeights: " + name + " holds " + std::to_string(values.size()) + " values, the network " +
                     std::to_string(target.numel()));
  target.copy_(torch::tensor(values).reshape(target.sizes()));
}

void assignDense(torch::nn::LinearImpl& l, const DenseWeights& d, const std::string& name) {
  assign(l.weight, d.weight, name + ".weight");
  assign(l.bias, d.bias, name + ".bias");
}

}  // namespace

FaultIdentifier importWeights(const ModelMetadata& metadata, const NetworkWeights& w) {
  if (w.architecture != metadata.architecture || w.channels != metadata.channels() || w.window != metadata.window)
    throw ModelError("importWeights: the weights are not for this network (architecture, channels or window)");
  FaultIdentifier model = FaultIdentifier::create(metadata, 0);
  FaultNet& net = model.impl()->net;
  torch::NoGradGuard no_grad;
  assign(net->mean, w.mean, "mean");
  assign(net->scale, w.scale, "scale");
  ModelMetadata& m = model.metadata();
  m.feature_mean = w.mean;
  m.feature_std = w.scale;
  if (metadata.architecture == Architecture::kLstm) {
    const std::int64_t n = w.channels;
    for (auto& p : net->lstm->named_parameters()) {
      if (p.key() == "weight_ih_l0" || p.key() == "weight_hh_l0") {
        const torch::Tensor gates = torch::tensor(w.gates.weight);
        if (gates.numel() != 4 * metadata.hidden * (n + metadata.hidden))
          throw ModelError("importWeights: LSTM gate weights do not match the hidden size");
        const torch::Tensor both = gates.reshape({4 * metadata.hidden, n + metadata.hidden});
        p.value().copy_(p.key() == "weight_ih_l0" ? both.narrow(1, 0, n) : both.narrow(1, n, metadata.hidden));
      } else if (p.key() == "bias_ih_l0") {
        assign(p.value(), w.gates.bias, "gates.bias");
      } else if (p.key() == "bias_hh_l0") {
        p.value().zero_();
      }
    }
    if (w.head.size() != 2) throw ModelError("importWeights: an LSTM needs two head layers");
    assignDense(*net->head1, w.head[0], "head1");
    assignDense(*net->head2, w.head[1], "head2");
  } else if (metadata.architecture == Architecture::kTcn) {
    if (w.convs.size() != net->convs.size() || w.head.size() != 2)
      throw ModelError("importWeights: the TCN's layers do not match the network");
    for (std::size_t i = 0; i < net->convs.size(); ++i) {
      if (w.convs[i].dilation != metadata.tcn.dilations[i])
        throw ModelError("importWeights: conv" + std::to_string(i) + "'s dilation differs from the network's");
      assign(net->convs[i]->weight, w.convs[i].weight, "conv" + std::to_string(i) + ".weight");
      assign(net->convs[i]->bias, w.convs[i].bias, "conv" + std::to_string(i) + ".bias");
    }
    assignDense(*net->head1, w.head[0], "head1");
    assignDense(*net->head2, w.head[1], "head2");
  } else {
    std::size_t layer = 0;
    for (const auto& module : net->mlp->children())
      if (auto* linear = module->as<torch::nn::LinearImpl>()) {
        if (layer >= w.head.size()) throw ModelError("importWeights: the MLP has more layers than the weights");
        assignDense(*linear, w.head[layer], "mlp" + std::to_string(layer));
        ++layer;
      }
    if (layer != w.head.size()) throw ModelError("importWeights: the weights have more layers than the MLP");
  }
  return model;
}

}  // namespace quadfdi
