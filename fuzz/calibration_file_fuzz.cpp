// Decision calibration files (io/calibration_file.h, JSON): any bytes give a calibration or one
// ConfigError naming the file; an accepted calibration round-trips through its JSON exactly.
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "io/calibration_file.h"
#include "io/key_value.h"

using namespace quadfdi;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  DecisionCalibration c;
  try {
    c = calibrationFromJson(fuzz::text(data, size), "fuzz-calibration.json");
  } catch (const ConfigError& e) {
    fuzz::report(e);
    QUADFDI_FUZZ_CHECK(std::string(e.what()).rfind("fuzz-calibration.json", 0) == 0);
    return 0;
  }
  const std::string written = calibrationToJson(c);
  const DecisionCalibration back = calibrationFromJson(written, "written");  // must not throw
  QUADFDI_FUZZ_CHECK(calibrationToJson(back) == written);
  return 0;
}
