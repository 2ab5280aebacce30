// PX4 ULog (logs/ulog.h) and the PX4 extractor (logs/px4_signals.h): any bytes must give a
// DecodedLog or one LogIssue — never a crash, a hang, a sanitizer report or an inconsistent table.
#include <cmath>
#include <cstdint>

#include "conventions_check.h"
#include "fuzz_support.h"
#include "logs/px4_signals.h"
#include "logs/ulog.h"

using namespace quadfdi;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // Smaller caps than the defaults: the same code paths (kTooLarge included), but a mutated
  // "uint8_t[60000]" no longer builds 2^18 columns per input (≈ 200 inputs/s under ASan).
  UlogLimits limits;
  limits.max_columns = 4096;
  limits.max_name_bytes = std::size_t{1} << 18;
  DecodedLog log;
  const LogIssue issue = readUlog(ByteSpan{data, size}, log, limits);
  QUADFDI_FUZZ_CHECK(issue.offset <= size);
  QUADFDI_FUZZ_CHECK(issue.ok() == issue.message.empty());
  if (!issue.ok()) return 0;
  QUADFDI_FUZZ_CHECK(looksLikeUlog(ByteSpan{data, size}));
  for (const LogTopic& t : log.topics) {
    QUADFDI_FUZZ_CHECK(t.columns.size() == t.fields.size());
    for (const auto& c : t.columns) QUADFDI_FUZZ_CHECK(c.size() == t.rows());
    QUADFDI_FUZZ_CHECK(log.find(t.name, t.instance) != nullptr);
  }
  FlightSignals signals;
  const LogIssue extracted = extractPx4Signals(log, Px4SignalOptions{}, signals);
  if (!extracted.ok()) return 0;
  for (std::size_t i = 1; i < signals.position.t.size(); ++i) QUADFDI_FUZZ_CHECK(signals.position.t[i] > signals.position.t[i - 1]);
  for (const auto& a : signals.attitude.v)
    for (double x : a) QUADFDI_FUZZ_CHECK(std::isfinite(x));
  for (const auto& u : signals.command.v)
    for (double x : u) QUADFDI_FUZZ_CHECK(x >= 0.0 && x <= 1.0);
  checkConventionsLayer(signals, log.format, size % 2 == 0);
  return 0;
}
