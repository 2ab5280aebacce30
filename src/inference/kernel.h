// Internal to networks/inference.cpp: the inference engine's compute kernels, built once per
// instruction set (generic x86-64 / other CPUs, AVX2 + FMA, AVX-512) from inference_kernel.inc
// and chosen at run time, so one portable binary runs at the speed the CPU allows.
#pragma once

namespace quadfdi::inference {

struct LstmArgs {
  const float* windows;  // `lanes` windows, each T × n
  int window, channels, hidden;
  const float *mean, *scale;         // normalisation per channel
  const float *gate_w, *gate_b;      // packed gate layer (rows in blocks of kRowBlock)
  int gate_in, gate_out, gate_blocks;
  float *z, *gates, *cell;           // scratch [rows][lanes]
  float* relu_h;                     // out: relu(h_T) [hidden][lanes]
};

struct DenseStackArgs {
  const float* const* w;
  const float* const* b;
  const int *in, *out, *blocks;
  int layers;
  float *x, *y;  // ping-pong [rows][lanes]; x holds the input; the sigmoid output ends in x if
                 // layers is even, else in y
};

// Row-vectorised dense layer for a few streams at once (the TCN's streaming step): for each of
// `streams` inputs x_s (in values each), y_s = W·x_s + b, with W packed in blocks of kRowBlock
// rows, column-major within a block (the same packing as the lane kernels). Each stream's sum
// runs in input order: its result does not depend on the other streams.
struct DenseRowsArgs {
  const float *w, *b;
  int in, blocks;
  const float* x;  // [streams][x_stride]
  int x_stride;
  int streams;
  float* y;        // [streams][y_stride], y_stride ≥ blocks·kRowBlock
  int y_stride;
};

struct Kernel {
  const char* name;
  int lanes;  // windows per group
  void (*lstm)(const LstmArgs&);
  void (*dense_stack)(const DenseStackArgs&);
  void (*normalise)(const float* windows, int per_window, int channels, const float* mean, const float* scale,
                    float* out);  // MLP input: [per_window][lanes]
  void (*dense_rows)(const DenseRowsArgs&);
};

inline constexpr int kRowBlock = 8;  // output rows per block: eight accumulators hide FMA latency

Kernel genericKernel();
Kernel avx2Kernel();    // only on x86-64 builds
Kernel avx512Kernel();  // only on x86-64 builds

}  // namespace quadfdi::inference
