// The key = value configuration format (io/key_value.h): parsing, then every typed accessor on
// every entry, as the vehicle, controller, generate and train configurations read them. Any
// bytes must give a document or one ConfigError "SOURCE:LINE: problem".
#include <cmath>
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "io/key_value.h"

using namespace quadfdi;

namespace {

bool startsWithSource(const ConfigError& e) { return std::string(e.what()).rfind("fuzz.toml:", 0) == 0; }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  KeyValueDocument doc;
  try {
    doc = parseKeyValue(fuzz::text(data, size), "fuzz.toml");
  } catch (const ConfigError& e) {
    fuzz::report(e);
    QUADFDI_FUZZ_CHECK(startsWithSource(e));
    return 0;
  }
  int previous_line = 0;
  for (const KeyValueEntry& entry : doc.entries) {
    QUADFDI_FUZZ_CHECK(entry.line > previous_line && !entry.key.empty() && !entry.value.empty());
    previous_line = entry.line;
    QUADFDI_FUZZ_CHECK(doc.find(entry.key) == &entry);  // keys are unique
    try {
      const double v = doc.number(entry);
      QUADFDI_FUZZ_CHECK(std::isfinite(v));
    } catch (const ConfigError& e) {
      fuzz::report(e);
      QUADFDI_FUZZ_CHECK(startsWithSource(e));
    }
    try {
      const long long v = doc.integer(entry);
      QUADFDI_FUZZ_CHECK(v >= -9000000000000000LL && v <= 9000000000000000LL);
    } catch (const ConfigError& e) {
      fuzz::report(e);
      QUADFDI_FUZZ_CHECK(startsWithSource(e));
    }
    try {
      (void)doc.boolean(entry);
    } catch (const ConfigError& e) {
      fuzz::report(e);
      QUADFDI_FUZZ_CHECK(startsWithSource(e));
    }
    try {
      (void)doc.string(entry);
    } catch (const ConfigError& e) {
      fuzz::report(e);
      QUADFDI_FUZZ_CHECK(startsWithSource(e));
    }
    try {
      for (double v : doc.numberList(entry)) QUADFDI_FUZZ_CHECK(std::isfinite(v));
    } catch (const ConfigError& e) {
      fuzz::report(e);
      QUADFDI_FUZZ_CHECK(startsWithSource(e));
    }
  }
  return 0;
}
