// ArduPilot DataFlash (.BIN) log reader: bytes in, a DecodedLog out (docs/logs/dataflash.md).
//
// The format describes itself. Every message starts with the header 0xA3 0x95 and a one-byte
// type; FMT messages (type 128, 89 bytes) define every other type: its length (header
// included), a name of up to 4 characters, up to 16 format characters and up to 64 characters
// of comma-separated column labels. FMTU messages attach a unit id and a multiplier id to every
// field of a type; UNIT and MULT messages say what those ids mean. Sources: ArduPilot
// libraries/AP_Logger/LogStructure.h (struct log_Format, log_Format_Units, log_Unit,
// log_Format_Multiplier and the list of format characters) and the "Downloading and Analyzing
// Data Logs" page of the ArduPilot documentation.
//
// What the reader does with each message:
//  * data messages → one LogTopic per (type, instance); numeric fields become columns, string
//    fields (n, N, Z) are dropped; a[32] becomes 32 columns "F[0]".."F[31]".
//  * format scalings are applied: c, C, e, E ×0.01; L ×1e-7 (degrees of latitude/longitude).
//  * FMTU multipliers (MULT) are applied to every other numeric field (LogField::multiplier says
//    which), FMTU units (UNIT) go to LogField::unit, the field whose unit id is '#' is the
//    instance (LogTopic::instance).
//  * TimeUS [µs] → LogTopic::timestamp_us (not repeated as a column); TimeMS [ms] ×1000 in old
//    logs; a type with neither gets the time of the latest timed message before it.
//  * PARM → DecodedLog::parameters (last value), MSG → DecodedLog::messages, VER →
//    DecodedLog::info ("VER.<label>", plus "firmware"), the first MSG naming the firmware
//    ("ArduCopter V…") → info["firmware"] if VER did not say. FMT, FMTU, UNIT, MULT, PARM and MSG
//    make no topic.
//
// Problems: bytes that are not a header of a known type are skipped up to the next 0xA3 0x95
// with a defined type (FMT included), with a warning "byte OFFSET: …" naming the count; a
// truncated last message is dropped with a warning; a FMT that contradicts the format (its
// length does not match its format characters, unknown character, …) is skipped the same way,
// except the first message of the log, whose failure is fatal. Pure function: no I/O, no
// exceptions.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "logs/decoded_log.h"

namespace quadfdi {

// The format's fixed numbers, shared with the text reader (LogStructure.h: HEAD_BYTE1, HEAD_BYTE2,
// LOG_FORMAT_MSG, and the char arrays of log_Format and of the 'a' format character).
inline constexpr std::uint8_t kDataflashHead1 = 0xA3;
inline constexpr std::uint8_t kDataflashHead2 = 0x95;
inline constexpr std::uint8_t kDataflashFmtType = 128;  // FMT
inline constexpr std::size_t kDataflashNameLen = 4;     // [chars] log_Format::name
inline constexpr std::size_t kDataflashFormatLen = 16;  // [chars] log_Format::format
inline constexpr std::size_t kDataflashLabelsLen = 64;  // [chars] log_Format::labels
inline constexpr std::size_t kDataflashArrayLen = 32;   // 'a': int16_t[32]

// Largest log the reader accepts [bytes]: decoded columns take up to 8× the log's size in
// memory (a one-byte field becomes a double); 2 GiB keeps that within a workstation. Our choice.
inline constexpr std::uint64_t kDataflashMaxBytes = std::uint64_t{1} << 31;

// Largest number of warnings kept; the rest are counted in one last warning. Our choice.
inline constexpr std::size_t kDataflashMaxWarnings = 100;

// Cheap test: the log starts with 0xA3 0x95 and a FMT (type 128).
bool looksLikeDataflash(ByteSpan bytes);

// [bytes] the length of a message of this format, the 3-byte header included (what its FMT's
// Length must say); 0 when a character is not a DataFlash format character. Shared with the text
// reader (logs/dataflash_text.h), which re-encodes each text line by it.
std::size_t dataflashMessageLength(const std::string& format);

// Reads a whole DataFlash log into `out` (cleared first). Fatal problems (empty, not DataFlash,
// the first FMT truncated or broken, too large) come back as the LogIssue, with what was read;
// problems read past are in out.warnings, each "byte OFFSET: …".
LogIssue readDataflash(ByteSpan bytes, DecodedLog& out);

}  // namespace quadfdi
