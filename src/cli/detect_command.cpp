#include "cli/detect_command.h"

#include <poll.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>

#include "cli/cli_util.h"
#include "detection/detector.h"
#include "io/atomic_file.h"
#include "io/telemetry_reader.h"
#include "networks/inference.h"

#ifndef QUADFDI_DEFAULT_MODEL
#define QUADFDI_DEFAULT_MODEL "models/lstm-model-free.qfdi"
#endif

namespace quadfdi::cli {

std::string defaultModelPath() {
  if (const char* env = std::getenv("QUADFDI_MODEL"); env && *env) return env;
  return QUADFDI_DEFAULT_MODEL;
}

CLI::App* addDetectCommand(CLI::App& app, DetectOptions& o) {
  CLI::App* cmd = app.add_subcommand(
      "detect",
      "Online fault detection on flight telemetry (SPEC §8): reads the CSV t,x,y,z,roll,pitch,yaw,u1..u4\n"
      "(SI units, z up, ZYX Euler angles, u = commanded thrust per motor [N], Crazyflie numbering; extra\n"
      "columns ignored; any rate down to 125 Hz, resampled to the model's), writes one JSON object per\n"
      "sample from the first full window on: {\"t\", \"theta\": [4], \"alarm\", \"motor\"}. A summary goes to stderr.");
  cmd->add_option("--model,-m", o.model, "Model file (default: the shipped model, or $QUADFDI_MODEL)");
  cmd->add_option("--input,-i", o.input, "Telemetry CSV, or - for standard input (streamed line by line)")->capture_default_str();
  cmd->add_option("--output,-o", o.output, "JSON Lines output, or - for standard output")->capture_default_str();
  cmd->add_option("--stride", o.stride, "Evaluate every N samples while all Θ̂ are above --watch (extra first-look delay ≤ N−1 samples)")
      ->capture_default_str()->check(CLI::Range(1, 1000));
  cmd->add_option("--watch", o.watch, "Below this min Θ̂, evaluate every sample")->capture_default_str()->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--raise-below", o.raise_below, "Alarm evidence: the weakest motor's Θ̂ below this")
      ->capture_default_str()->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--clear-above", o.clear_above, "Healthy evidence: every Θ̂ above this")->capture_default_str()->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--raise-after", o.raise_after, "Consecutive evaluations of evidence (same motor) to raise the alarm")
      ->capture_default_str()->check(CLI::Range(1, 100000));
  cmd->add_option("--watch-samples", o.watch_samples, "Full-rate evaluations after Θ̂ first dips below --watch")
      ->capture_default_str()->check(CLI::Range(0, 100000));
  cmd->add_option("--clear-after", o.clear_after, "Samples of healthy evidence (every Θ̂ above --clear-above) to clear it")
      ->capture_default_str()->check(CLI::Range(1, 100000));
  cmd->add_option("--max-input-period", o.max_input_period, "Refuse logs sampled coarser than this [s]")->capture_default_str();
  cmd->add_option("--max-gap", o.max_gap, "A longer hole in the log restarts the detector [s]")->capture_default_str();
  cmd->add_flag("--quiet,-q", o.quiet, "No summary or warnings on stderr (errors still go there)");
  return cmd;
}

namespace {

// True when more standard input is ready without waiting: the stream then reads ahead like a
// file (same output, since a window's estimate does not depend on its batch), and only a
// live, idle pipe gets each sample evaluated the moment it arrives.
bool moreInputReady() {
  if (std::cin.rdbuf()->in_avail() > 0) return true;
  pollfd p{STDIN_FILENO, POLLIN, 0};
  return poll(&p, 1, 0) > 0 && (p.revents & POLLIN) != 0;
}

std::string fmtMs(double seconds) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g ms", 1000.0 * seconds);
  return buf;
}

void writeJson(std::ostream& out, const DetectorOutput& d) {
  char buf[256];
  const int n = std::snprintf(buf, sizeof buf, "{\"t\": %.10g, \"theta\": [%.4f, %.4f, %.4f, %.4f], \"alarm\": %s, \"motor\": ", d.t,
                              static_cast<double>(d.theta[0]), static_cast<double>(d.theta[1]),
                              static_cast<double>(d.theta[2]), static_cast<double>(d.theta[3]), d.alarm ? "true" : "false");
  out.write(buf, n);
  if (d.motor > 0) out << d.motor << "}\n";
  else out << "null}\n";
}

}  // namespace

int runDetect(const DetectOptions& o) {
  require(o.clear_above >= o.raise_below, "--clear-above must not be below --raise-below");
  require(o.watch >= o.raise_below, "--watch must not be below --raise-below (the alarm must be decided at full rate)");
  require(o.max_input_period > 0.0 && o.max_gap >= o.max_input_period, "--max-gap must be at least --max-input-period (> 0)");
  const std::string model_path = o.model.empty() ? defaultModelPath() : o.model;
  const FaultIdentifier model = FaultIdentifier::load(model_path);
  const ModelMetadata& m = model.metadata();
  require(m.features == FeatureSet::kModelFree && m.output == OutputKind::kPositionEuler,
          model_path + ": the detector needs a model-free (y, u) network on position and Euler angles; this one reads " +
              toString(m.features) + " features");
  InferenceEngine engine(exportWeights(model));

  DetectorConfig config;
  config.window = m.window;
  config.trained_motor = m.trained_motor;
  config.symmetry = m.symmetry;
  config.stride = o.stride;
  config.watch = o.watch;
  config.watch_samples = o.watch_samples;
  config.resampler.dt = m.dt;
  config.resampler.max_input_period = o.max_input_period;
  config.resampler.max_gap = o.max_gap;
  config.alarm.raise_below = o.raise_below;
  config.alarm.clear_above = o.clear_above;
  config.alarm.raise_after = o.raise_after;
  config.alarm.clear_after = o.clear_after;
  Detector detector(config, engine);

  const bool streaming = o.input == "-";
  std::ios::sync_with_stdio(false);  // buffered standard input: see moreInputReady
  std::ifstream file;
  if (!streaming) {
    file.open(o.input);
    require(file.is_open(), o.input + ": cannot open");
  }
  std::istream& in = streaming ? std::cin : file;
  const std::string name = streaming ? std::string("<stdin>") : o.input;
  TelemetryReader reader(in, name);  // throws on an empty file or a bad header

  std::unique_ptr<AtomicFileWriter> file_out;
  if (o.output != "-") file_out = std::make_unique<AtomicFileWriter>(o.output);
  std::ostream& out = file_out ? file_out->stream() : std::cout;

  long skipped = 0;
  TelemetrySample sample;
  std::string problem;
  for (;;) {
    const TelemetryReader::Row row = reader.next(sample, problem);
    if (row == TelemetryReader::Row::kEnd) break;
    if (row == TelemetryReader::Row::kSkipped) {
      if (!o.quiet && skipped < 10) std::fprintf(stderr, "detect: warning: %s\n", problem.c_str());
      ++skipped;
      continue;
    }
    const bool look_ahead = !streaming || moreInputReady();
    const ResampleStatus status = detector.push(sample, look_ahead);
    if (status == ResampleStatus::kNotIncreasing)
      throw TelemetryError(reader.where() + ": time goes backwards or repeats (t = " + std::to_string(sample.t) + " s)");
    if (status == ResampleStatus::kTooCoarse)
      throw TelemetryError(reader.where() + ": the log is sampled too coarsely: most of its first intervals exceed " +
                           fmtMs(o.max_input_period) + " (--max-input-period); the model needs " + fmtMs(m.dt) + " samples");
    if (!o.quiet && status == ResampleStatus::kRestarted)
      std::fprintf(stderr, "detect: warning: %s: gap of more than %.0f ms in the log; the detector starts again (needs %.2f s)\n",
                   reader.where().c_str(), 1000.0 * o.max_gap, m.window * m.dt);
    DetectorOutput d;
    while (detector.pop(d)) writeJson(out, d);
    if (streaming && !look_ahead) out.flush();  // a live pipe sees each decision at once
  }
  detector.finish();
  DetectorOutput d;
  while (detector.pop(d)) writeJson(out, d);
  const DetectorSummary& s = detector.summary();
  // Before the commit: a header-only log must not replace an existing output file.
  if (s.input_samples == 0) throw TelemetryError(name + ": no telemetry rows after the header");
  out.flush();
  if (!out) throw std::runtime_error(o.output + ": write failed");
  if (file_out) file_out->commit();
  if (!o.quiet) {
    if (skipped > 10) std::fprintf(stderr, "detect: warning: %ld rows skipped in all (non-finite or empty cells)\n", skipped);
    if (s.outputs == 0)
      std::fprintf(stderr, "detect: %s: %ld samples, shorter than one window (%.2f s): no decision\n", name.c_str(),
                   s.input_samples, m.window * m.dt);
    else if (s.alarms_raised == 0)
      std::fprintf(stderr, "detect: no fault: %ld samples, %ld decisions, no alarm\n", s.input_samples, s.outputs);
    else
      std::fprintf(stderr,
                   "detect: FAULT in motor %d at t = %.3f s (Θ̂ = %.2f when raised, lowest %.2f while it held); %ld alarm%s "
                   "over %ld samples\n",
                   s.first_alarm_motor, s.first_alarm_t, static_cast<double>(s.first_alarm_theta),
                   static_cast<double>(s.lowest_theta), s.alarms_raised, s.alarms_raised == 1 ? "" : "s", s.input_samples);
  }
  return 0;
}

}  // namespace quadfdi::cli
