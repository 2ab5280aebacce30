// ArduPilot DataFlash logs as text (logs/dataflash_text.h) and the ArduPilot extractor: the
// checks of dataflash_check.h on any bytes; what the text reader accepts also names lines only.
#include <cstdint>

#include "dataflash_check.h"
#include "logs/dataflash_text.h"

using namespace quadfdi;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  DecodedLog log;
  const LogIssue issue = readDataflashText(ByteSpan{data, size}, log);
  if (looksLikeDataflashText(ByteSpan{data, size})) QUADFDI_FUZZ_CHECK(issue.status != LogStatus::kWrongMagic);
  QUADFDI_FUZZ_CHECK(issue.ok() || issue.line > 0);
  for (const std::string& w : log.warnings) QUADFDI_FUZZ_CHECK(w.rfind("byte ", 0) != 0);  // lines, never bytes of the re-encoding
  fuzz::checkDataflashRead(data, size, issue, log);
  return 0;
}
