// Vehicle parameter files (io/params_file.h): any bytes give a valid VehicleParams or one
// ConfigError naming the file; an accepted set round-trips through its file form exactly.
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "io/key_value.h"
#include "io/params_file.h"

using namespace quadfdi;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  VehicleParams p;
  try {
    p = vehicleParamsFromText(fuzz::text(data, size), "fuzz-vehicle.toml");
  } catch (const ConfigError& e) {
    fuzz::report(e);
    QUADFDI_FUZZ_CHECK(std::string(e.what()).rfind("fuzz-vehicle.toml", 0) == 0);
    return 0;
  }
  QUADFDI_FUZZ_CHECK(validate(p).empty());
  const std::string written = vehicleParamsToText(p);
  const VehicleParams back = vehicleParamsFromText(written, "written");  // must not throw
  QUADFDI_FUZZ_CHECK(vehicleParamsToText(back) == written);
  return 0;
}
