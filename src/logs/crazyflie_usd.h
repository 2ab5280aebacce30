// Reader of the Crazyflie micro-SD card deck's event logs (file format versions 1 and 2), as
// described in docs/logs/crazyflie-usd.md: bytes in, one LogTopic per event type out. Pure: no
// I/O, no exceptions; every problem comes back as a LogIssue (status, byte offset, message).
#pragma once

#include <cstddef>
#include <cstdint>

#include "logs/decoded_log.h"

namespace quadfdi {

// Limits on what a file may declare before the reader allocates for it (kTooLarge beyond).
// The stock firmware writes at most 20 event types of at most 20 log variables (usddeck.c:
// MAX_USD_LOG_EVENTS, MAX_USD_LOG_VARIABLES_PER_EVENT), plus a few payload fields per named
// event; forks raise these (48 variables seen), so the caps leave a wide margin.
struct CrazyflieUsdLimits {
  std::size_t max_event_types = 256;          // [count] event types in the header
  std::size_t max_variables_per_event = 256;  // [count] variables (payload + log variables) per event type
  std::size_t max_name_bytes = 256;           // [bytes] one event or variable name, without its NUL
};

// A cheap test for format detection: the magic byte 0xBC and a version this reader knows.
bool looksLikeCrazyflieUsd(ByteSpan bytes);

// Decodes a whole log. On success `out` holds one topic per event type of the header (name =
// event name, fields = its variables "group.name" with their types, timestamp_us exact), the
// format facts in `out.info` ("usd.version", "usd.crc32", "usd.event.<name>.id", …) and any
// problems read past in `out.warnings` (a missing CRC32 or a truncated last record: the log was
// not closed). On failure `out` holds what was decoded before the problem.
LogIssue readCrazyflieUsd(ByteSpan bytes, DecodedLog& out);
LogIssue readCrazyflieUsd(ByteSpan bytes, DecodedLog& out, const CrazyflieUsdLimits& limits);

// CRC-32 as the deck computes it (IEEE 802.3, reflected polynomial 0xEDB88320, initial value and
// final XOR 0xFFFFFFFF: zlib's crc32, which bitcraze's cfusdlog.py uses to check the files).
std::uint32_t crc32Ieee(const std::uint8_t* data, std::size_t size);

}  // namespace quadfdi
