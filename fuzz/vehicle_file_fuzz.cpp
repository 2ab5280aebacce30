// Vehicle description files (io/vehicle_file.h): any bytes give a description that validates or
// one ConfigError naming the file; an accepted description round-trips through its file form.
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "io/key_value.h"
#include "io/vehicle_file.h"

using namespace quadfdi;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  VehicleDescription d;
  try {
    d = vehicleDescriptionFromText(fuzz::text(data, size), "fuzz-vehicle.toml");
  } catch (const ConfigError& e) {
    fuzz::report(e);
    QUADFDI_FUZZ_CHECK(std::string(e.what()).rfind("fuzz-vehicle.toml", 0) == 0);
    return 0;
  }
  QUADFDI_FUZZ_CHECK(validate(d.params).empty());
  const std::string written = vehicleDescriptionToText(d);
  const VehicleDescription back = vehicleDescriptionFromText(written, "written");  // must not throw
  QUADFDI_FUZZ_CHECK(vehicleDescriptionToText(back) == written);
  return 0;
}
