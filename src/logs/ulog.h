// PX4 ULog reader (format: PX4 docs "ULog File Format", versions 1 and 2): bytes in, a
// DecodedLog out. What is read, how each message type is handled and the truncation /
// corruption policy: docs/logs/ulog.md.
#pragma once

#include "logs/decoded_log.h"

namespace quadfdi {

// Limits that protect memory against a hostile or damaged file; exceeding one gives kTooLarge.
struct UlogLimits {
  std::size_t max_columns = std::size_t{1} << 18;       // [columns] all topics together (a full PX4 log: ~10⁴)
  std::size_t max_name_bytes = std::size_t{1} << 25;    // [bytes] of flattened field names, all formats and topics
  int max_nesting_depth = 16;                           // [levels] of nested formats (PX4 uses 2–3)
  std::size_t max_stored_warnings = 100;                // [warnings] kept; the rest are counted in one last line
};

// True when the bytes start with the ULog magic ("ULog" 0x01 0x12 0x35). Cheap: for picking a reader.
bool looksLikeUlog(ByteSpan bytes);

// Reads a whole ULog. On kOk `out` holds every subscribed topic instance (fields flattened,
// `timestamp` kept exactly in timestamp_us and not repeated as a column), parameters, default
// parameters, info, text messages and dropouts; problems read past are in out.warnings. On any
// other status `out` holds what was read before issue.offset (for diagnostics only).
LogIssue readUlog(ByteSpan bytes, DecodedLog& out, const UlogLimits& limits = {});

}  // namespace quadfdi
