// Controller configuration files (io/controller_config.h): any bytes give a configuration
// within the documented ranges or one ConfigError naming the file.
#include <cmath>
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "io/controller_config.h"
#include "io/key_value.h"

using namespace quadfdi;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const ControllerConfig base;
  ControllerConfig c;
  try {
    c = controllerConfigFromText(fuzz::text(data, size), "fuzz-controller.toml", base);
  } catch (const ConfigError& e) {
    fuzz::report(e);
    QUADFDI_FUZZ_CHECK(std::string(e.what()).rfind("fuzz-controller.toml:", 0) == 0);
    return 0;
  }
  for (int i = 0; i < c.lqr.q_diag.size(); ++i) QUADFDI_FUZZ_CHECK(std::isfinite(c.lqr.q_diag(i)) && c.lqr.q_diag(i) >= 0.0);
  for (int i = 0; i < c.lqr.r_diag.size(); ++i) QUADFDI_FUZZ_CHECK(std::isfinite(c.lqr.r_diag(i)) && c.lqr.r_diag(i) > 0.0);
  QUADFDI_FUZZ_CHECK(std::isfinite(c.cbf.min_altitude));
  QUADFDI_FUZZ_CHECK(c.cbf.max_tilt > 0.0 && c.cbf.max_tilt < 1.5);
  for (double a : {c.cbf.altitude_alpha1, c.cbf.altitude_alpha2, c.cbf.tilt_alpha1, c.cbf.tilt_alpha2})
    QUADFDI_FUZZ_CHECK(std::isfinite(a) && a > 0.0);
  return 0;
}
