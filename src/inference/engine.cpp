#include "inference/engine.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

#include "inference/kernel.h"

namespace quadfdi {

using inference::kRowBlock;

// The fastest kernel this CPU runs; QUADFDI_KERNEL=generic|avx2|avx512 forces one (tests, benchmarks).
static inference::Kernel chooseKernel() {
  const char* forced = std::getenv("QUADFDI_KERNEL");
  const std::string want = forced ? forced : "";
#if defined(QUADFDI_X86_KERNELS)
  __builtin_cpu_init();
  const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  const bool avx512 = avx2 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl");
  if (want == "avx512" || (want.empty() && avx512)) {
    if (!avx512) throw std::invalid_argument("QUADFDI_KERNEL=avx512: this CPU lacks AVX-512");
    return inference::avx512Kernel();
  }
  if (want == "avx2" || (want.empty() && avx2)) {
    if (!avx2) throw std::invalid_argument("QUADFDI_KERNEL=avx2: this CPU lacks AVX2/FMA");
    return inference::avx2Kernel();
  }
#endif
  if (!want.empty() && want != "generic")
    throw std::invalid_argument("QUADFDI_KERNEL must be generic, avx2 or avx512 (and supported here), got '" + want + "'");
  return inference::genericKernel();
}

// Subnormal weights (0 < |w| < 2^−126, FLT_MIN) are packed as zero. Training's weight decay leaves
// dead units' weights there, and on Intel cores every multiply-add that reads one takes a microcode
// assist: the shipped general TCN (206 subnormal weights of 19 k) ran 7.7× slower for them on the
// project's Intel Xeon VM (docs/benchmarks.md, "Subnormal numbers"). A product with one is below
// 2^−126·|x|, under half an ulp of any sum of normal size, so no output moves
// (tests/inference/engine_test.cpp).
static float flushSubnormal(float w) { return std::fpclassify(w) == FP_SUBNORMAL ? 0.0f : w; }

PackedDense packDense(const DenseWeights& d) {
  if (d.in < 1 || d.out < 1 || d.weight.size() != static_cast<std::size_t>(d.in) * d.out ||
      d.bias.size() != static_cast<std::size_t>(d.out))
    throw std::invalid_argument("InferenceEngine: inconsistent layer shapes");
  PackedDense p;
  p.in = d.in;
  p.out = d.out;
  p.blocks = (d.out + kRowBlock - 1) / kRowBlock;
  p.w.assign(static_cast<std::size_t>(p.blocks) * kRowBlock * d.in, 0.0f);
  p.b.assign(static_cast<std::size_t>(p.blocks) * kRowBlock, 0.0f);
  for (int r = 0; r < d.out; ++r) {
    p.b[static_cast<std::size_t>(r)] = flushSubnormal(d.bias[static_cast<std::size_t>(r)]);
    const int blk = r / kRowBlock, i = r % kRowBlock;
    for (int k = 0; k < d.in; ++k)
      p.w[(static_cast<std::size_t>(blk) * d.in + k) * kRowBlock + i] = flushSubnormal(d.weight[static_cast<std::size_t>(r) * d.in + k]);
  }
  return p;
}

InferenceEngine::InferenceEngine(const NetworkWeights& wts)
    : architecture_(wts.architecture), window_(wts.window), channels_(wts.channels), hidden_(wts.hidden),
      mean_(wts.mean), scale_(wts.scale) {
  const inference::Kernel kernel = chooseKernel();
  kernel_name_ = kernel.name;
  lanes_ = kernel.lanes;
  lstm_ = kernel.lstm;
  dense_stack_ = kernel.dense_stack;
  normalise_ = kernel.normalise;
  const auto n = static_cast<std::size_t>(channels_);
  const auto lanes = static_cast<std::size_t>(lanes_);
  if (window_ < 1 || channels_ < 1 || mean_.size() != n || scale_.size() != n || wts.head.empty())
    throw std::invalid_argument("InferenceEngine: inconsistent network weights");
  if (architecture_ == Architecture::kTcn) {
    tcn_ = std::make_unique<TcnStreamer>(wts, lanes_);
    tcn_rows_.assign(static_cast<std::size_t>(lanes_) * n, 0.0f);
    tcn_theta_.assign(static_cast<std::size_t>(lanes_) * 4, 0.0f);
    return;
  }
  std::size_t widest = 0;
  if (architecture_ == Architecture::kLstm) {
    if (wts.gates.in != channels_ + hidden_ || wts.gates.out != 4 * hidden_)
      throw std::invalid_argument("InferenceEngine: LSTM gate shapes do not match the hidden size");
    gates_ = packDense(wts.gates);
    z_.assign(static_cast<std::size_t>(channels_ + hidden_) * lanes, 0.0f);
    gate_out_.assign(static_cast<std::size_t>(gates_.blocks) * kRowBlock * lanes, 0.0f);
    cell_.assign(static_cast<std::size_t>(hidden_) * lanes, 0.0f);
    widest = static_cast<std::size_t>(hidden_);
  } else {
    widest = static_cast<std::size_t>(window_) * n;
  }
  int in = architecture_ == Architecture::kLstm ? hidden_ : window_ * channels_;
  for (const DenseWeights& d : wts.head) {
    if (d.in != in) throw std::invalid_argument("InferenceEngine: head layers do not chain");
    head_.push_back(packDense(d));
    widest = std::max(widest, static_cast<std::size_t>(head_.back().blocks) * kRowBlock);
    in = d.out;
  }
  if (in != 4) throw std::invalid_argument("InferenceEngine: the network must end in four outputs");
  if (head_.size() > kMaxLayers) throw std::invalid_argument("InferenceEngine: too many layers");
  for (const Packed& p : head_) {
    head_w_.push_back(p.w.data());
    head_b_.push_back(p.b.data());
    head_in_.push_back(p.in);
    head_out_.push_back(p.out);
    head_blocks_.push_back(p.blocks);
  }
  padded_.assign(static_cast<std::size_t>(window_) * n * lanes, 0.0f);
  act_a_.assign(widest * lanes, 0.0f);
  act_b_.assign(widest * lanes, 0.0f);
}

void InferenceEngine::predictGroup(const float* windows, int count, float* theta) {
  if (tcn_) {  // the windows as streams, in lock-step; the output after the last sample is the window's
    const std::size_t per = static_cast<std::size_t>(window_) * channels_, n = static_cast<std::size_t>(channels_);
    tcn_->reset();
    for (int t = 0; t < window_; ++t) {
      for (int i = 0; i < lanes_; ++i)  // a short group repeats its last window
        std::memcpy(tcn_rows_.data() + n * i, windows + per * std::min(i, count - 1) + n * t, n * sizeof(float));
      tcn_->step(tcn_rows_.data(), tcn_theta_.data());
    }
    std::memcpy(theta, tcn_theta_.data(), sizeof(float) * 4 * static_cast<std::size_t>(count));
    return;
  }
  // Pad the group to a full one by repeating the last window; lanes never mix.
  const std::size_t per = static_cast<std::size_t>(window_) * channels_;
  const float* group = windows;
  if (count < lanes_) {
    for (int lane = 0; lane < lanes_; ++lane)
      std::memcpy(padded_.data() + per * lane, windows + per * std::min(lane, count - 1), per * sizeof(float));
    group = padded_.data();
  }
  if (architecture_ == Architecture::kLstm) {
    const inference::LstmArgs a{group, window_, channels_, hidden_, mean_.data(), scale_.data(), gates_.w.data(),
                                gates_.b.data(), gates_.in, gates_.out, gates_.blocks, z_.data(), gate_out_.data(),
                                cell_.data(), act_a_.data()};
    lstm_(a);
  } else {
    normalise_(group, static_cast<int>(per), channels_, mean_.data(), scale_.data(), act_a_.data());
  }
  const int layers = static_cast<int>(head_.size());
  dense_stack_({head_w_.data(), head_b_.data(), head_in_.data(), head_out_.data(), head_blocks_.data(), layers,
                act_a_.data(), act_b_.data()});
  const float* result = (layers % 2 == 0) ? act_a_.data() : act_b_.data();
  for (int i = 0; i < count; ++i)
    for (int m = 0; m < 4; ++m) theta[i * 4 + m] = result[m * lanes_ + i];
}

void InferenceEngine::predict(const float* windows, int count, float* theta) {
  const std::size_t per = static_cast<std::size_t>(window_) * channels_;
  for (int first = 0; first < count; first += lanes_)
    predictGroup(windows + per * static_cast<std::size_t>(first), std::min(lanes_, count - first), theta + 4 * first);
}

}  // namespace quadfdi

namespace quadfdi {

TcnStreamer::TcnStreamer(const NetworkWeights& w, int streams) : streams_(streams), channels_(w.channels) {
  const inference::Kernel kernel = chooseKernel();
  kernel_name_ = kernel.name;
  dense_rows_ = kernel.dense_rows;
  const auto n = static_cast<std::size_t>(channels_);
  if (w.architecture != Architecture::kTcn || streams < 1 || channels_ < 1 || w.mean.size() != n || w.scale.size() != n ||
      w.convs.empty() || w.head.empty())
    throw std::invalid_argument("TcnStreamer: inconsistent TCN weights");
  mean_ = w.mean;
  scale_ = w.scale;
  int in = channels_;
  std::size_t widest = n;
  long span = 0;
  for (const ConvWeights& c : w.convs) {
    if (c.in != in || c.out < 1 || c.kernel < 1 || c.dilation < 1 ||
        c.weight.size() != static_cast<std::size_t>(c.out) * c.in * c.kernel || c.bias.size() != static_cast<std::size_t>(c.out))
      throw std::invalid_argument("TcnStreamer: convolution layers do not chain");
    if (&c != &w.convs.front() && c.out != c.in) throw std::invalid_argument("TcnStreamer: residual layers must keep their width");
    // Flatten the taps: column j·in + m of the dense layer is W[:, m, j], tap j reads x(t − (K−1−j)·d).
    DenseWeights flat;
    flat.in = c.in * c.kernel;
    flat.out = c.out;
    flat.bias = c.bias;
    flat.weight.resize(static_cast<std::size_t>(flat.in) * flat.out);
    for (int r = 0; r < c.out; ++r)
      for (int m = 0; m < c.in; ++m)
        for (int j = 0; j < c.kernel; ++j)
          flat.weight[static_cast<std::size_t>(r) * flat.in + static_cast<std::size_t>(j) * c.in + m] =
              c.weight[(static_cast<std::size_t>(r) * c.in + m) * c.kernel + j];
    Layer layer;
    layer.dense = packDense(flat);
    layer.in = c.in;
    layer.kernel = c.kernel;
    layer.dilation = c.dilation;
    const long needed = static_cast<long>(c.kernel - 1) * c.dilation + 1;
    layer.ring = 1;
    while (layer.ring < needed) layer.ring *= 2;
    layer.history.assign(static_cast<std::size_t>(layer.ring) * streams * c.in, 0.0f);
    span += needed - 1;
    widest = std::max({widest, static_cast<std::size_t>(flat.in), static_cast<std::size_t>(layer.dense.blocks) * inference::kRowBlock});
    layers_.push_back(std::move(layer));
    in = c.out;
  }
  receptive_field_ = static_cast<int>(span + 1);
  for (const DenseWeights& d : w.head) {
    if (d.in != in) throw std::invalid_argument("TcnStreamer: head layers do not chain");
    head_.push_back(packDense(d));
    widest = std::max(widest, static_cast<std::size_t>(head_.back().blocks) * inference::kRowBlock);
    in = d.out;
  }
  if (in != 4) throw std::invalid_argument("TcnStreamer: the network must end in four outputs");
  const auto s = static_cast<std::size_t>(streams);
  taps_.assign(s * widest, 0.0f);
  out_.assign(s * widest, 0.0f);
  head_a_.assign(s * widest, 0.0f);
  head_b_.assign(s * widest, 0.0f);
}

void TcnStreamer::reset() {
  for (Layer& l : layers_) std::fill(l.history.begin(), l.history.end(), 0.0f);
  samples_ = 0;
}

void TcnStreamer::step(const float* rows, float* theta) {
  const auto s = static_cast<std::size_t>(streams_);
  const std::size_t stride = out_.size() / s;  // per-stream room in every scratch buffer
  // Layer input of this sample, per stream: the normalised features first, then each layer's output.
  const float* input = nullptr;
  for (std::size_t l = 0; l < layers_.size(); ++l) {
    Layer& layer = layers_[l];
    const auto in = static_cast<std::size_t>(layer.in);
    const long slot = samples_ & (layer.ring - 1);
    float* now = layer.history.data() + static_cast<std::size_t>(slot) * s * in;
    for (std::size_t i = 0; i < s; ++i)
      for (std::size_t m = 0; m < in; ++m)
        now[i * in + m] = l == 0 ? (rows[i * in + m] - mean_[m]) / scale_[m] : input[i * stride + m];
    for (int j = 0; j < layer.kernel; ++j) {  // gather the taps, oldest first
      const long at = (samples_ - static_cast<long>(layer.kernel - 1 - j) * layer.dilation) & (layer.ring - 1);
      const float* src = layer.history.data() + static_cast<std::size_t>(at) * s * in;
      for (std::size_t i = 0; i < s; ++i)
        std::memcpy(taps_.data() + i * stride + static_cast<std::size_t>(j) * in, src + i * in, in * sizeof(float));
    }
    dense_rows_({layer.dense.w.data(), layer.dense.b.data(), layer.dense.in, layer.dense.blocks, taps_.data(),
                 static_cast<int>(stride), streams_, out_.data(), static_cast<int>(stride)});
    const auto out = static_cast<std::size_t>(layer.dense.out);
    for (std::size_t i = 0; i < s; ++i)
      for (std::size_t r = 0; r < out; ++r) {
        float& v = out_[i * stride + r];
        v = std::max(v, 0.0f) + (l == 0 ? 0.0f : now[i * in + r]);  // ReLU, then the residual
      }
    std::swap(out_, head_a_);  // head_a_ holds this layer's output; out_ is free again
    input = head_a_.data();
  }
  float* x = head_a_.data();
  float* y = head_b_.data();
  for (std::size_t l = 0; l < head_.size(); ++l) {
    const PackedDense& d = head_[l];
    dense_rows_({d.w.data(), d.b.data(), d.in, d.blocks, x, static_cast<int>(stride), streams_, y, static_cast<int>(stride)});
    if (l + 1 < head_.size())
      for (std::size_t i = 0; i < s; ++i)
        for (int r = 0; r < d.out; ++r) y[i * stride + static_cast<std::size_t>(r)] = std::max(y[i * stride + static_cast<std::size_t>(r)], 0.0f);
    std::swap(x, y);
  }
  for (std::size_t i = 0; i < s; ++i)
    for (std::size_t m = 0; m < 4; ++m) theta[i * 4 + m] = 1.0f / (1.0f + std::exp(-x[i * stride + m]));
  ++samples_;
}

}  // namespace quadfdi
