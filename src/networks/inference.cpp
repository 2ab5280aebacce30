#include "networks/inference.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

#include "networks/inference_kernel.h"

namespace quadfdi {

using inference::kRowBlock;

namespace {

// The fastest kernel this CPU runs; QUADFDI_KERNEL=generic|avx2|avx512 forces one (tests, benchmarks).
inference::Kernel chooseKernel() {
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

}  // namespace

InferenceEngine::Packed InferenceEngine::pack(const DenseWeights& d) {
  if (d.in < 1 || d.out < 1 || d.weight.size() != static_cast<std::size_t>(d.in) * d.out ||
      d.bias.size() != static_cast<std::size_t>(d.out))
    throw std::invalid_argument("InferenceEngine: inconsistent layer shapes");
  Packed p;
  p.in = d.in;
  p.out = d.out;
  p.blocks = (d.out + kRowBlock - 1) / kRowBlock;
  p.w.assign(static_cast<std::size_t>(p.blocks) * kRowBlock * d.in, 0.0f);
  p.b.assign(static_cast<std::size_t>(p.blocks) * kRowBlock, 0.0f);
  for (int r = 0; r < d.out; ++r) {
    p.b[static_cast<std::size_t>(r)] = d.bias[static_cast<std::size_t>(r)];
    const int blk = r / kRowBlock, i = r % kRowBlock;
    for (int k = 0; k < d.in; ++k)
      p.w[(static_cast<std::size_t>(blk) * d.in + k) * kRowBlock + i] = d.weight[static_cast<std::size_t>(r) * d.in + k];
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
  std::size_t widest = 0;
  if (architecture_ == Architecture::kLstm) {
    if (wts.gates.in != channels_ + hidden_ || wts.gates.out != 4 * hidden_)
      throw std::invalid_argument("InferenceEngine: LSTM gate shapes do not match the hidden size");
    gates_ = pack(wts.gates);
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
    head_.push_back(pack(d));
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
