#include "cli/import_command.h"

#include <cstdio>
#include <iostream>
#include <memory>

#include "cli/cli_util.h"
#include "io/atomic_file.h"
#include "io/telemetry_csv.h"

namespace quadfdi::cli {

CLI::App* addImportCommand(CLI::App& app, ImportCommandOptions& o) {
  CLI::App* cmd = app.add_subcommand(
      "import",
      "Convert a flight log (PX4 ULog, ArduPilot DataFlash, Crazyflie micro-SD; recognised from its content) into\n"
      "telemetry CSV t,x,y,z,roll,pitch,yaw,u1..u4 (then p,q,r where the log records body rates) on the model's clock,\n"
      "airborne phases only, and print the import report: each signal's topic, rate and span, the conventions applied,\n"
      "the thrust scaling, the flight phases.");
  cmd->add_option("input", o.input, "Flight log, or - for one piped in on standard input with its --format named")->required();
  auto t = std::make_shared<OptionTable>();
  t->addConfigFile(o.config);
  t->add("--output,-o", o.output, "Telemetry CSV, or - for standard output");
  t->add("--report", o.report, "Also write the import report to this file");
  t->add("--dt", o.dt, "Clock period [s] (the model's: the shipped model's is 0.002)").above(0.0);
  t->add("--max-gap", o.max_gap, "Holes in a signal longer than this [s] are not bridged (the detector's --max-gap)").above(0.0);
  t->add("--quiet,-q", o.quiet, "No report on the terminal");
  addLogInputOptions(*t, o.log);
  attachOptions(*cmd, t);
  return cmd;
}

int runImport(const ImportCommandOptions& o) {
  csvInVehicleNumbering(o.log);  // --csv-numbering vehicle needs --vehicle: checked before any work; openFlightLog renumbers
  const std::string format = resolveInputFormat(o.input, o.log.format);
  require(format != "csv", o.input + ": already telemetry CSV (or not a flight log: --format names one)");
  refuseOptionsUnreadBy(format, o.log);
  const std::optional<VehicleDescription> vehicle = describedVehicle(o.log);  // the one read of --vehicle
  const TelemetryReaderOptions reading = format == "csv-merged" ? csvReadingOptions(o.log, vehicle) : TelemetryReaderOptions{};
  OpenedLog log = openFlightLog(o.input, format, o.log, vehicle, reading, o.dt, o.max_gap);  // throws one line
  std::unique_ptr<AtomicFileWriter> file_out;
  if (o.output != "-") file_out = std::make_unique<AtomicFileWriter>(o.output);
  std::ostream& out = file_out ? file_out->stream() : std::cout;
  const bool rates = log.source->carriesRates();  // the log records body rates: they go along, as p,q,r
  writeTelemetryCsvHeader(out, log.source->report().numbering, rates);  // detect reads the autopilot's motor numbers back
  TelemetrySample s;
  std::string problem;
  long rows = 0, skipped = 0;
  for (SampleSource::Next n; (n = log.source->next(s, problem)) != SampleSource::Next::kEnd;) {
    if (n == SampleSource::Next::kSkipped) {
      if (!o.quiet && ++skipped <= 10) std::fprintf(stderr, "import: warning: %s\n", problem.c_str());
      continue;
    }
    writeTelemetryCsvRow(out, s, rates);
    ++rows;
  }
  if (!o.quiet && skipped > 10) std::fprintf(stderr, "import: warning: %ld more samples dropped\n", skipped - 10);
  out.flush();
  if (!out) throw std::runtime_error(o.output + ": write failed");
  const std::string report = log.source->report().text();
  if (!o.report.empty()) {
    AtomicFileWriter r(o.report);
    r.stream() << report;
    r.commit();
  }
  if (file_out) file_out->commit();
  if (!o.quiet) {
    for (const std::string& w : log.warnings) std::fprintf(stderr, "import: warning: %s\n", w.c_str());
    // The report goes where the CSV does not.
    std::FILE* to = file_out ? stdout : stderr;
    std::fprintf(to, "%s", report.c_str());
    std::fprintf(to, "import: %ld rows written to %s\n", rows, o.output == "-" ? "standard output" : o.output.c_str());
  }
  return 0;
}

}  // namespace quadfdi::cli
