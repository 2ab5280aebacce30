// Randomisation files (io/randomisation_file.h): any bytes give a randomisation that validates or
// one ConfigError naming the file. Inputs naming a path (a '/') are skipped: loading the vehicles
// they name is the vehicle file's target, and a fuzzer must not open the machine's files (a named
// pipe waits for a writer); the named parameter sets ("nominal", …) still exercise the vehicle list.
#include <cmath>
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "io/key_value.h"
#include "io/randomisation_file.h"
#include "simulation/rng.h"

using namespace quadfdi;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = fuzz::text(data, size);
  if (text.find('/') != std::string::npos) return 0;
  Randomisation r;
  try {
    r = randomisationFromText(text, "fuzz-randomisation.toml");
  } catch (const ConfigError& e) {
    fuzz::report(e);
    QUADFDI_FUZZ_CHECK(std::string(e.what()).rfind("fuzz-randomisation.toml", 0) == 0);
    return 0;
  }
  QUADFDI_FUZZ_CHECK(validate(r).empty());
  // Ranges that validate give synthetic airframes that do.
  for (const VehicleParams& p : drawAirframes(r.airframes)) QUADFDI_FUZZ_CHECK(validate(p).empty());
  // A flight drawn from them flies a heading sweep that the reference accepts (amplitude in
  // [0, π], period > 0) and faces its velocity only when it moves.
  Rng rng(1, 0);
  const FlightDraw d = drawFlight(r, 0.002, rng);
  QUADFDI_FUZZ_CHECK(d.manoeuvre.yaw_sweep_amplitude >= 0.0 && d.manoeuvre.yaw_sweep_amplitude <= M_PI);
  QUADFDI_FUZZ_CHECK(std::isfinite(d.manoeuvre.yaw_sweep_period) && d.manoeuvre.yaw_sweep_period > 0.0);
  QUADFDI_FUZZ_CHECK(!d.manoeuvre.facing_velocity || d.manoeuvre.kind != ManoeuvreKind::kHover);
  // Its nose's slew limit is finite and >= 0, and rides on a nose-first circle alone (a figure-eight's
  // reference refuses one).
  QUADFDI_FUZZ_CHECK(std::isfinite(d.manoeuvre.facing_yaw_rate_max) && d.manoeuvre.facing_yaw_rate_max >= 0.0);
  QUADFDI_FUZZ_CHECK(d.manoeuvre.facing_yaw_rate_max == 0.0 ||
                     (d.manoeuvre.facing_velocity && d.manoeuvre.kind == ManoeuvreKind::kCircle));
  // Its file form (vehicles by name, as recorded in model files) reads back to the same ranges.
  // The vehicles line names files by their stem, which resolve only where the files are (a base
  // or a working directory can bring vehicles from files): read it back with a named set instead.
  const auto ranges = [](const std::string& text) { return text.substr(text.find('\n') + 1); };  // all but the vehicles line
  const std::string written = ranges(randomisationToText(r));
  const Randomisation back = randomisationFromText("vehicles = [\"nominal\"]\n" + written, "written");  // must not throw
  QUADFDI_FUZZ_CHECK(ranges(randomisationToText(back)) == written);
  return 0;
}
