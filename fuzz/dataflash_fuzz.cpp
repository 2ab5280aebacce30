// ArduPilot DataFlash logs (logs/dataflash.h) and the ArduPilot extractor: the checks of
// dataflash_check.h on any bytes.
#include <cstdint>

#include "dataflash_check.h"
#include "logs/dataflash.h"

using namespace quadfdi;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  DecodedLog log;
  const LogIssue issue = readDataflash(ByteSpan{data, size}, log);
  if (looksLikeDataflash(ByteSpan{data, size})) QUADFDI_FUZZ_CHECK(issue.status != LogStatus::kWrongMagic);
  fuzz::checkDataflashRead(data, size, issue, log);
  return 0;
}
