// Which flight-log format a file's first bytes announce (each format's magic), and whether they
// are text at all: shared by the command line's format detection and the CSV reader's refusal of
// a log read as CSV.
#pragma once

#include "logs/decoded_log.h"

namespace quadfdi {

// "ulog", "dataflash" or "crazyflie" (the --format names) when `head` starts with that format's
// magic (for DataFlash also its text form's first line, "FMT, …"); nullptr otherwise.
const char* logFormatOfMagic(ByteSpan head);

// True when `bytes` hold a control byte other than tab, line feed and carriage return (a NUL
// included): no CSV telemetry.
bool looksBinary(ByteSpan bytes);

}  // namespace quadfdi
