// `quadfdi detect --plot FILE.png`: Θ̂ per motor against time, alarm intervals shaded, the
// evaluated flight phases, the first alarm marked; drawn by gnuplot (Debian: gnuplot-nox, PNG
// through its pngcairo terminal, else the libgd png terminal).
#pragma once

#include <string>
#include <vector>

#include "detection/detector.h"

namespace quadfdi::cli {

struct PlotPhase {
  double begin = 0.0, end = 0.0;  // [s]
};

struct DetectionPlotData {
  std::vector<DetectorOutput> outputs;
  std::vector<PlotPhase> phases;  // evaluated stretches
  std::string title;
  double max_gap = 0.02;          // [s] the line is broken across longer jumps in t
};

// Throws std::runtime_error("--plot needs gnuplot …") when gnuplot is not on the PATH. Cheap: call
// it before any work so that a missing gnuplot costs nothing.
void requireGnuplot();

// Writes the data file and script to a fresh temporary folder, runs gnuplot, and moves the PNG to
// `png_path` (an existing file is replaced only by a complete plot). Throws std::runtime_error.
void plotDetections(const DetectionPlotData& data, const std::string& png_path);

}  // namespace quadfdi::cli
