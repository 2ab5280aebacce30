// Controller configuration files: LQR weights, CBF-QP safe set and PID gains (see
// configs/controller-example.toml). Values not in the file keep those of `base`.
#pragma once

#include <string>

#include "control/controller_factory.h"

namespace quadfdi {

// Throws ConfigError("FILE:LINE: problem") on unknown keys, bad values or wrong list sizes.
ControllerConfig controllerConfigFromText(const std::string& text, const std::string& source,
                                          const ControllerConfig& base);
ControllerConfig loadControllerConfig(const std::string& path, const ControllerConfig& base);

}  // namespace quadfdi
