// The one refusal helper the configuration-file tests share: what a parser says when it refuses.
#pragma once

#include <string>

#include "io/key_value.h"

namespace quadfdi::test {

// What configRefusal returns when `parse` throws nothing; no real message reads like this.
inline const std::string kAccepted = "(accepted)";

// The one-line ConfigError message `parse()` throws, or kAccepted if it accepts its input.
template <class Parse>
std::string configRefusal(Parse&& parse) {
  try {
    parse();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return kAccepted;
}

}  // namespace quadfdi::test
