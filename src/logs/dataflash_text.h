// ArduPilot DataFlash log as text (Mission Planner's `.log`, written beside each `.BIN` it
// downloads, and the text logs of older ground stations): text in, the same DecodedLog as the
// binary log gives (docs/logs/dataflash.md, "The text form").
//
// The text form prints each binary message as one line: its name, then its fields in FMT order,
// separated by ", " (some tools write ","): "FMT, 129, 23, PARM, QNf, TimeUS,Name,Value",
// "ATT, 123456789, 0.00, 1.52, …". Values are printed in their physical units — c, C, e, E already
// ×0.01, L already in degrees — and strings without their padding. Sources: ArduPilot
// libraries/AP_Logger/LogStructure.h (the messages and format characters) and pymavlink's
// DFReader.py text reader, read as a description of the form (no code taken from it).
//
// How it is read: each line is re-encoded into the binary message it was printed from (values
// back to their stored integers: 12.34 in a c field → 1234) and the binary reader
// (logs/dataflash.h) decodes the result, so that FMT rules, time, units and multipliers (FMTU,
// UNIT, MULT), instances, PARM, MSG and VER mean exactly what they mean in a .BIN. Differences:
//  * a flight-mode field (M) may be printed as the mode's name; it is read as a number where it
//    is one and as NaN where it is a name (its column's type is then kFloat);
//  * an int16[32] array (a) is read from 32 integers separated by spaces, with or without [ ];
//  * UNIT's and MULT's Id (a character stored as int8) may be printed as its code or as itself
//    (a digit, ambiguous, is read as a code);
//  * the FMT line of FMT itself is the text form's own layout: it is checked, not needed.
//
// Problems: a line that cannot be read (an undefined message name, a field that is not a number
// of its type or lies outside its type's range, too few or too many fields, a broken FMT) is
// skipped with a warning "line N: …" (the first of each kind with its line, the rest counted in
// it); lines before the first FMT line (a banner) are skipped with one warning; a text with no FMT
// line within its first lines, or an empty one, is fatal (LogIssue::line). Pure function: no I/O,
// no exceptions.
#pragma once

#include <cstddef>

#include "logs/decoded_log.h"

namespace quadfdi {

// Non-blank lines of text allowed before the first FMT line: older firmware (APM 2, ArduCopter 3.1)
// printed a banner of a few lines ("ArduCopter V3.1.5 (3c57e771)", "Free RAM: 990", "APM 2").
// Our choice: a banner's few lines with room to spare; a CSV is never scanned past them.
inline constexpr std::size_t kDataflashTextPreambleLines = 16;

// Cheap test: after an optional UTF-8 byte-order mark, a line starting "FMT," among the first
// non-blank lines (up to kDataflashTextPreambleLines before it).
bool looksLikeDataflashText(ByteSpan bytes);

// Reads a whole text DataFlash log into `out` (cleared first; out.format is kDataflash).
LogIssue readDataflashText(ByteSpan bytes, DecodedLog& out);

}  // namespace quadfdi
