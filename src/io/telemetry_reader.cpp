#include "io/telemetry_reader.h"

#include <algorithm>

#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <iostream>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "logs/dataflash_text.h"
#include "logs/log_magic.h"
#include "model/vehicle_params.h"

namespace quadfdi {
namespace {

std::string numberText(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

constexpr double kMaxMagnitude = 1e9;  // [SI] larger values are no flight telemetry (and overflow float)
// [s] t is not fed to the network and may be an absolute clock: seconds since 1970 (1.7e9), or
// milliseconds (1.7e12, refused later as sampled too coarsely, with a hint at the unit). Beyond it
// (microseconds, nanoseconds since 1970) a double no longer holds the model's sample period.
constexpr double kMaxTime = 1e13;

std::string trim(const std::string& s) {
  std::size_t b = 0, e = s.size();
  while (b < e && (s[b] == ' ' || s[b] == '\t' || s[b] == '"')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '"' || s[e - 1] == '\r')) --e;
  return s.substr(b, e - b);
}

// The separator of a header line: a comma wherever there is one, else a tab, else a semicolon
// (spreadsheets in locales with a decimal comma), else runs of blanks (kBlankRuns: plain text
// tables, gnuplot and MATLAB data files). Whatever the header uses, every row uses.
constexpr char kBlankRuns = ' ';
char separatorOf(const std::string& header) {
  for (const char c : {',', '\t', ';'})
    if (header.find(c) != std::string::npos) return c;
  return kBlankRuns;
}

// Splits on `separator` into `cells` (reused); kBlankRuns: on runs of spaces and tabs, the line's
// leading and trailing blanks ignored. No quoting: telemetry is numbers.
void split(const std::string& line, char separator, std::vector<std::string>& cells) {
  cells.clear();
  if (separator == kBlankRuns) {
    std::size_t b = line.find_first_not_of(" \t\r");
    while (b != std::string::npos) {
      const std::size_t e = line.find_first_of(" \t\r", b);
      cells.push_back(trim(line.substr(b, e == std::string::npos ? std::string::npos : e - b)));
      b = e == std::string::npos ? e : line.find_first_not_of(" \t\r", e);
    }
    if (cells.empty()) cells.emplace_back();
    return;
  }
  std::size_t start = 0;
  for (;;) {
    const std::size_t at = line.find(separator, start);
    cells.push_back(trim(line.substr(start, at == std::string::npos ? std::string::npos : at - start)));
    if (at == std::string::npos) break;
    start = at + 1;
  }
}

// "NAME [UNIT]" or "NAME (UNIT)" → NAME and UNIT (trimmed); false for a cell without that suffix.
bool splitUnit(const std::string& cell, std::string& name, std::string& unit) {
  if (cell.size() < 3 || (cell.back() != ']' && cell.back() != ')')) return false;
  const std::size_t open = cell.rfind(cell.back() == ']' ? '[' : '(');
  if (open == std::string::npos || open == 0) return false;
  name = trim(cell.substr(0, open));
  unit = trim(cell.substr(open + 1, cell.size() - open - 2));
  return !name.empty();
}

// Days from 1970-01-01 to the proleptic Gregorian date y-m-d (the "days from civil" count: years
// taken from March, so the leap day ends a year; 146097 days every 400 years).
long daysSince1970(long y, int m, int d) {
  y -= m <= 2 ? 1 : 0;
  const long era = (y >= 0 ? y : y - 399) / 400;
  const long year_of_era = y - era * 400;
  const long day_of_year = (153 * (m > 2 ? m - 3 : m + 9) + 2) / 5 + d - 1;
  const long day_of_era = year_of_era * 365 + year_of_era / 4 - year_of_era / 100 + day_of_year;
  return era * 146097 + day_of_era - 719468;
}

// An ISO 8601 date and time, YYYY-MM-DD[T or blank]hh:mm:ss[.fraction][Z | ±hh:mm | ±hhmm] (pandas,
// spreadsheets, ROS tools write it), → seconds since 1970-01-01 00:00 UTC; without a zone, the time
// is read as UTC (only differences between rows matter to the detector). False if `text` is not one.
bool parseDateTime(const std::string& text, double& seconds) {
  std::size_t i = 0;
  auto digits = [&](int n, long& value) {
    value = 0;
    for (int k = 0; k < n; ++k, ++i) {
      if (i >= text.size() || text[i] < '0' || text[i] > '9') return false;
      value = value * 10 + (text[i] - '0');
    }
    return true;
  };
  auto expect = [&](const char* allowed) {
    if (i >= text.size() || std::string(allowed).find(text[i]) == std::string::npos) return false;
    ++i;
    return true;
  };
  long year = 0, month = 0, day = 0, hour = 0, minute = 0, second = 0;
  if (!digits(4, year) || !expect("-") || !digits(2, month) || !expect("-") || !digits(2, day) || !expect("T ") ||
      !digits(2, hour) || !expect(":") || !digits(2, minute) || !expect(":") || !digits(2, second))
    return false;
  static const int kDaysIn[12] = {31, 29, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  const bool leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
  if (month < 1 || month > 12 || day < 1 || day > kDaysIn[month - 1] || (month == 2 && day == 29 && !leap) || hour > 23 ||
      minute > 59 || second > 60)  // 60: a leap second
    return false;
  double fraction = 0.0;
  if (i < text.size() && (text[i] == '.' || text[i] == ',')) {
    const std::size_t start = ++i;
    double scale = 0.1;
    for (; i < text.size() && text[i] >= '0' && text[i] <= '9'; ++i, scale *= 0.1) fraction += (text[i] - '0') * scale;
    if (i == start) return false;
  }
  long offset = 0;  // [s] the zone's offset east of UTC
  if (i < text.size() && text[i] == 'Z') {
    ++i;
  } else if (i < text.size() && (text[i] == '+' || text[i] == '-')) {
    const long sign = text[i++] == '-' ? -1 : 1;
    long zone_hours = 0, zone_minutes = 0;
    if (!digits(2, zone_hours)) return false;
    if (i < text.size() && text[i] == ':') ++i;
    if (!digits(2, zone_minutes) || zone_hours > 23 || zone_minutes > 59) return false;
    offset = sign * (zone_hours * 3600 + zone_minutes * 60);
  }
  if (i != text.size()) return false;
  const long whole = daysSince1970(year, static_cast<int>(month), static_cast<int>(day)) * 86400 + hour * 3600 +
                     minute * 60 + second - offset;
  seconds = static_cast<double>(whole) + fraction;
  return true;
}

}  // namespace

double secondsPerTimeUnit(const std::string& unit) {
  return unit == "s" ? 1.0 : unit == "ms" ? 1e-3 : unit == "us" || unit == "\u00b5s" ? 1e-6 : unit == "ns" ? 1e-9 : 0.0;
}

const char* const TelemetryReader::kColumns[kColumnCount] = {"t",  "x",  "y",  "z",  "roll", "pitch", "yaw", "u1", "u2",
                                                            "u3", "u4", "qw", "qx", "qy",   "qz",    "p",   "q",  "r"};

namespace {
constexpr int kRoll = 4, kU1 = 7, kQw = 11, kP = 15;  // indices into kColumns
constexpr int kColumnCount = TelemetryReader::kColumnCount;
// [bytes] Longest line: a CSV exported from a ROS bag or PlotJuggler with a thousand columns is
// ~30 kB a line; a longer one is no telemetry (a device or a binary file read as CSV, which
// std::getline would read into memory without end).
constexpr std::size_t kMaxLineBytes = std::size_t{1} << 20;

// std::getline with a bound: false at the end of the input with nothing read; throws past the
// bound. Read in chunks by istream::getline, which scans the stream's buffer as std::getline does
// (a character at a time through the buffer read 14 % fewer rows a second: bench readTelemetryCsv).
bool getBoundedLine(std::istream& in, std::string& text, const std::string& name, long line) {
  text.clear();
  char chunk[4096];
  for (;;) {
    in.getline(chunk, sizeof chunk);
    const auto got = static_cast<std::size_t>(in.gcount());
    const bool end = in.eof(), delimited = !end && !in.fail();  // else a full chunk: the line goes on
    text.append(chunk, delimited ? got - 1 : got);  // the newline is counted, not stored
    if (text.size() > kMaxLineBytes)
      throw TelemetryError(name + ":" + std::to_string(line) + ": a line longer than " + std::to_string(kMaxLineBytes) + " bytes: not CSV telemetry");
    if (delimited) return true;
    if (end) return !text.empty();  // the last line needs no newline
    in.clear(in.rdstate() & ~std::ios::failbit);
  }
}
}  // namespace

bool TelemetryReader::readLine(std::string& text) {
  while (getBoundedLine(in_, text, name_, line_ + 1)) {
    ++line_;
    if (line_ == 1 && text.size() >= 3 && text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);  // BOM
    const std::string t = trim(text);
    if (!t.empty() && t[0] == '#' && column_[0] < 0) readNumberingComment(t);  // before the header only
    if (t.empty() || t[0] == '#') continue;
    return true;
  }
  return false;
}

// "# motor_numbering: NAME = A B C D [turned DEG]": A..D a permutation of 1..4 (the autopilot's
// numbers of quadfdi's motors 1..4); DEG, a multiple of 45, the turn of the axes a plus or
// props-out frame was read in (core/frames.h). Other comments are ignored; this one, malformed, is an error.
void TelemetryReader::readNumberingComment(const std::string& comment) {
  static const std::string kKey = "motor_numbering:";
  const std::string body = trim(comment.substr(1));
  if (body.compare(0, kKey.size(), kKey) != 0) return;
  const std::string value = body.substr(kKey.size());
  const std::size_t eq = value.rfind('=');
  const std::string bad = where() + ": '# motor_numbering: NAME = A B C D [turned DEG]' expects the autopilot's numbers of quadfdi's "
                                    "motors 1..4 (a permutation of 1 2 3 4), then optionally the turn of the body axes (a multiple of "
                                    "45°), got '" + trim(value) + "'";
  if (eq == std::string::npos || trim(value.substr(0, eq)).empty()) throw TelemetryError(bad);
  MotorNumbering n;
  n.name = trim(value.substr(0, eq));
  std::istringstream numbers(value.substr(eq + 1));
  std::array<bool, kMotors> seen{};
  for (int& m : n.autopilot_motor) {
    if (!(numbers >> m) || m < 1 || m > kMotors || seen[static_cast<std::size_t>(m - 1)]) throw TelemetryError(bad);
    seen[static_cast<std::size_t>(m - 1)] = true;
  }
  if (std::string word; numbers >> word) {
    int degrees = 0;
    if (word != "turned" || !(numbers >> degrees) || degrees % 45 != 0 || degrees <= -180 || degrees > 180) throw TelemetryError(bad);
    n.body_turn = BodyTurn{degrees / 45};
  }
  if (std::string rest; numbers >> rest) throw TelemetryError(bad);
  numbering_ = n;
}

TelemetryReader::TelemetryReader(std::istream& in, std::string name, const TelemetryReaderOptions& options)
    : in_(in), name_(std::move(name)), options_(options) {
  if (options_.commands == CommandQuantity::kThrottle || options_.commands == CommandQuantity::kPwm) {
    const CommandCurve& c = options_.curve;
    if (!(c.max_thrust > 0.0) || !(c.model_factor >= 0.0 && c.model_factor <= 1.0) || !(c.pwm_min >= 0.0) ||
        !(c.pwm_max > c.pwm_min) || !std::isfinite(c.max_thrust) || !std::isfinite(c.pwm_max))
      throw std::invalid_argument("TelemetryReader: a command curve needs max_thrust > 0, model_factor in [0, 1] and "
                                  "0 <= pwm_min < pwm_max");
  }
  if (!(options_.time_unit > 0.0) || !std::isfinite(options_.time_unit))
    throw std::invalid_argument("TelemetryReader: the time unit must be > 0 s");
  std::array<int, kInputDim> sorted = options_.file_motor;
  std::sort(sorted.begin(), sorted.end());
  if (sorted != std::array<int, kInputDim>{1, 2, 3, 4})
    throw std::invalid_argument("TelemetryReader: file_motor must be a permutation of 1..4");
  for (int r = 0; r < kColumnCount; ++r) label_[static_cast<std::size_t>(r)] = kColumns[r];
  std::array<bool, kColumnCount> renamed{};
  for (const auto& [column, header_name] : options_.header_names) {
    int r = 0;
    while (r < kColumnCount && column != kColumns[r]) ++r;
    if (r == kColumnCount || renamed[static_cast<std::size_t>(r)] || header_name.empty())
      throw std::invalid_argument("TelemetryReader: header name '" + header_name + "' given for '" + column +
                                  "', which is no column (t, x, y, z, roll, pitch, yaw, u1..u4, qw..qz, p, q, r), or given twice");
    renamed[static_cast<std::size_t>(r)] = true;
    label_[static_cast<std::size_t>(r)] = header_name;
  }
  column_.fill(-1);  // no header yet: readLine takes the numbering comment until it is read
  std::string header;
  if (!readLine(header)) throw TelemetryError(name_ + ": empty input (expected the header t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4)");
  // Binary (standard input holding a flight log, or --format csv on one): said so, not "lacks column 't'".
  if (const ByteSpan bytes{reinterpret_cast<const std::uint8_t*>(header.data()), header.size()}; looksBinary(bytes)) {
    const char* magic = logFormatOfMagic(bytes);
    throw TelemetryError(where() + ": binary, not CSV telemetry" +
                         (magic ? std::string(" (the ") + magic + " magic: a flight log; read it with --format " + magic + ")"
                                : std::string(" (a flight log? name its format: --format ulog, dataflash or crazyflie)")));
  }
  // ArduPilot's DataFlash log as text (Mission Planner's .log) opens with a FMT line, typically the
  // FMT message's own: "FMT, 128, 89, FMT, BBnNZ, Type,Length,Name,Format,Columns".
  if (looksLikeDataflashText(ByteSpan{reinterpret_cast<const std::uint8_t*>(header.data()), header.size()}))
    throw TelemetryError(where() + ": an ArduPilot DataFlash log as text (Mission Planner's .log), not CSV telemetry: "
                                   "read it with --format dataflash");
  std::vector<std::string> cells;
  separator_ = separatorOf(header);
  split(header, separator_, cells);
  cells_ = static_cast<int>(cells.size());
  bool angle_unit_read = false;
  const std::array<std::string, kColumnCount> header_names = label_;  // a column named with a unit is then labelled so
  for (int c = 0; c < cells_; ++c)
    for (int r = 0; r < kColumnCount; ++r) {
      if (r >= kP && !options_.read_rates) continue;  // extra columns then: not looked at
      const std::string& cell = cells[static_cast<std::size_t>(c)];
      const std::string& wanted = header_names[static_cast<std::size_t>(r)];
      std::string base, unit;
      const bool with_unit = cell != wanted && splitUnit(cell, base, unit) && base == wanted;
      if (cell != wanted && !with_unit) continue;
      if (column_[static_cast<std::size_t>(r)] >= 0)
        throw TelemetryError(where() + ": column '" + wanted + "' appears twice in the header");
      column_[static_cast<std::size_t>(r)] = c;
      if (with_unit) {
        label_[static_cast<std::size_t>(r)] = cell;
        readHeaderUnit(r, unit, angle_unit_read);
      }
    }
  // A fifth motor's command (u5, u6 …: a hexacopter's or an octocopter's telemetry) would be an
  // extra column here, and its first four motors read as a quad's: refused instead.
  const auto isDigit = [](char c) { return c >= '0' && c <= '9'; };
  for (const std::string& cell : cells) {
    std::string base = cell, unit;
    if (!splitUnit(cell, base, unit)) base = cell;
    if (base.size() >= 2 && base.size() <= 3 && base[0] == 'u' && base[1] != '0' &&
        std::all_of(base.begin() + 1, base.end(), isDigit) && std::stoi(base.substr(1)) > kInputDim)
      throw TelemetryError(where() + ": column '" + cell + "': a motor beyond the fourth — quadfdi detects faults on quadrotors, "
                                     "whose four motors are u1..u4; a hexacopter's or octocopter's telemetry is not read as a quad's");
  }
  auto has = [&](int r) { return column_[static_cast<std::size_t>(r)] >= 0; };
  // The attitude: Euler angles when the header names any of them (all three then needed), else
  // the quaternion, whole (an absent attitude is reported as Euler's first column).
  quaternion_ = !has(kRoll) && !has(kRoll + 1) && !has(kRoll + 2) && (has(kQw) || has(kQw + 1) || has(kQw + 2) || has(kQw + 3));
  // Body rates: all three or none (a header with one of them meant to give them).
  rates_ = has(kP) || has(kP + 1) || has(kP + 2);  // never when !read_rates: not matched
  for (int r = kP; r < kP + 3 && rates_; ++r)
    if (!has(r))
      throw TelemetryError(where() + ": the header has body rates and lacks column '" + label(r) +
                           "' (p, q, r [rad/s] come together, or not at all)");
  for (int r = 0; r < kColumnCount; ++r)
    if (!has(r) && isRead(r)) {
      if (renamed[static_cast<std::size_t>(r)])
        throw TelemetryError(where() + ": the header lacks column '" + label(r) + "' (read as " +
                             kColumns[r] + ", --csv-columns)");
      const std::string needs = quaternion_ ? "t,x,y,z,qw,qx,qy,qz,u1,u2,u3,u4" : "t,x,y,z,roll,pitch,yaw,u1,u2,u3,u4";
      throw TelemetryError(where() + ": the header lacks column '" + kColumns[r] + "' (needs " + needs +
                           (quaternion_ ? "" : ", or qw,qx,qy,qz for the attitude") +
                           "; others are ignored; --csv-columns reads a column named otherwise)");
    }
}

// A unit in the header ("t [ms]", "roll (deg)") sets what the options leave at their default and
// must agree with what they set; a unit quadfdi does not read is refused, naming the column.
void TelemetryReader::readHeaderUnit(int column, const std::string& unit, bool& angle_unit_read) {
  const std::string cell = "'" + label(column) + "'";
  const bool unitless = unit.empty() || unit == "-" || unit == "1";
  auto refuse = [&](const std::string& why) { throw TelemetryError(where() + ": column " + cell + ": " + why); };
  if (column == 0) {
    const double seconds = secondsPerTimeUnit(unit);
    if (seconds == 0.0) refuse("the unit '" + unit + "' is no time unit read here (s, ms, us or ns)");
    if (options_.time_unit != 1.0 && options_.time_unit != seconds)
      refuse("the header says " + unit + ", --csv-time-unit another unit");
    options_.time_unit = seconds;
  } else if (column < kRoll) {
    if (unit != "m") refuse("the unit '" + unit + "' is not read here: positions are in metres (m)");
  } else if (column < kU1) {
    const bool degrees = unit == "deg" || unit == "\u00b0" || unit == "degrees";
    if (!degrees && unit != "rad" && unit != "radians") refuse("the unit '" + unit + "' is no angle unit read here (rad or deg)");
    if (degrees != options_.angles_in_degrees && (angle_unit_read || options_.angles_in_degrees))
      refuse("the header says " + unit + (angle_unit_read ? " here and another unit for another angle" : ", --csv-angle-unit deg"));
    options_.angles_in_degrees = degrees;
    angle_unit_read = true;
  } else if (column < kQw) {
    const bool fits = options_.commands == CommandQuantity::kThrust     ? unit == "N"
                      : options_.commands == CommandQuantity::kPwm      ? unit == "us" || unit == "\u00b5s"
                      : options_.commands == CommandQuantity::kThrottle ? unitless
                                                                        : true;  // rotor speed: any unit, read squared
    if (!fits)
      refuse("the unit '" + unit + "' does not fit the commands read (" +
             (options_.commands == CommandQuantity::kThrust     ? "thrust in N; rotor speeds, throttle or PWM pulses: --csv-commands rotor-speed, throttle or pwm"
              : options_.commands == CommandQuantity::kPwm      ? "--csv-commands pwm: pulses in us"
                                                                : "--csv-commands throttle: a fraction without unit") +
             ")");
  } else if (column >= kP) {
    const bool degrees = unit == "deg/s" || unit == "\u00b0/s" || unit == "dps";
    if (!degrees && unit != "rad/s") refuse("the unit '" + unit + "' is no angular rate unit read here (rad/s or deg/s)");
    if (degrees != options_.rates_in_degrees && (rate_unit_read_ || options_.rates_in_degrees))
      refuse("the header says " + unit + (rate_unit_read_ ? " here and another unit for another rate" : ", --csv-rate-unit deg/s"));
    options_.rates_in_degrees = degrees;
    rate_unit_read_ = true;
  } else if (!unitless) {
    refuse("a quaternion has no unit, the header says '" + unit + "'");
  }
}

bool TelemetryReader::isRead(int column) const {
  if (column >= kRoll && column < kRoll + 3) return !quaternion_;
  if (column >= kP) return rates_;
  if (column >= kQw) return quaternion_;
  return true;
}

// Splits the next data line and parses every read column: `present[r]` false for an empty,
// non-finite or absurd cell, with `why[r]` saying which. Throws for what no row may hold.
bool TelemetryReader::readCells(double (&values)[kColumnCount], bool (&present)[kColumnCount], std::string (&why)[kColumnCount]) {
  std::string text;
  if (!readLine(text)) {
    if (in_.bad()) throw TelemetryError(name_ + ": read error after line " + std::to_string(line_));
    return false;
  }
  std::vector<std::string>& cells = cells_buffer_;
  split(text, separator_, cells);
  if (static_cast<int>(cells.size()) != cells_)
    throw TelemetryError(where() + ": " + std::to_string(cells.size()) + " cells, the header has " + std::to_string(cells_));
  blank_.fill(false);
  for (int r = 0; r < kColumnCount; ++r) {
    present[r] = false;
    if (!isRead(r)) continue;
    const std::string& cell = cells[static_cast<std::size_t>(column_[static_cast<std::size_t>(r)])];
    if (cell.empty()) {
      why[r] = where() + ": column '" + label(r) + "' is empty";
      blank_[static_cast<std::size_t>(r)] = true;
      continue;
    }
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(cell.c_str(), &end);
    if (r == 0 && *end == '-' && end - cell.c_str() == 4) {  // "YYYY-": a date and time, in its own unit
      if (!parseDateTime(cell, values[0]))
        throw TelemetryError(where() + ": t = '" + cell.substr(0, 40) +
                             "' is no date and time (YYYY-MM-DD hh:mm:ss[.fraction][Z or ±hh:mm]) nor a number");
      present[0] = true;
      continue;
    }
    if (end == cell.c_str() || *end != '\0')
      throw TelemetryError(where() + ": column '" + label(r) + "': '" + cell.substr(0, 40) + "' is not a number" +
                           (separator_ != ',' && cell.find(',') != std::string::npos
                                ? " (a decimal comma? numbers are read with a decimal point)"
                                : ""));
    if (!std::isfinite(v)) {
      why[r] = where() + ": column '" + label(r) + "' is " + cell;
      continue;
    }
    if (r == 0 && std::abs(v * options_.time_unit) > kMaxTime)
      throw TelemetryError(where() + ": t = " + cell.substr(0, 40) +
                           (options_.time_unit == 1.0 ? " is no time in seconds (over 1e13 s): microseconds or nanoseconds since 1970? "
                                                        "detect reads seconds (--csv-time-unit us or ns)"
                                                      : " is over 1e13 s in the time unit given (--csv-time-unit)"));
    if (r != 0 && std::abs(v) > kMaxMagnitude) {  // finite in a double, but no telemetry: it would overflow the network's floats
      why[r] = where() + ": column '" + label(r) + "' = " + cell.substr(0, 40) + " is out of range";
      continue;
    }
    values[r] = r == 0 ? v * options_.time_unit : v;
    present[r] = true;
  }
  return true;
}

std::string TelemetryReader::cellText(int column) const {
  return cells_buffer_[static_cast<std::size_t>(column_[static_cast<std::size_t>(column)])].substr(0, 40);
}

// The attitude of a row whose attitude cells are all present, in quadfdi's frame; false (with
// `problem`) for the zero quaternion an estimator writes before its first attitude.
bool TelemetryReader::attitudeOf(const double (&values)[kColumnCount], EulerZyx& attitude, std::string& problem) const {
  if (quaternion_) {
    // The columns in the header's qw, qx, qy, qz places, read as --csv-quaternion says.
    const Quaternion q = quaternionOfColumns({values[kQw], values[kQw + 1], values[kQw + 2], values[kQw + 3]}, options_.quaternion);
    const double w = q.w, x = q.x, y = q.y, z = q.z;
    const double norm = std::sqrt(w * w + x * x + y * y + z * z);
    if (norm == 0.0) {  // written before an estimator's first attitude
      problem = where() + ": the quaternion qw,qx,qy,qz is zero";
      return false;
    }
    // A quaternion written rounded to 4–5 digits is unit within 1e-4; one off by more than 1 % is
    // no attitude quaternion (another column, another quantity) and is refused.
    constexpr double kNormTolerance = 0.01;  // [-]
    if (std::abs(norm - 1.0) > kNormTolerance)
      throw TelemetryError(where() + ": qw,qx,qy,qz = " + cellText(kQw) + "," + cellText(kQw + 1) + "," + cellText(kQw + 2) + "," +
                           cellText(kQw + 3) + " is no unit quaternion (norm " + std::to_string(norm) +
                           "): the attitude is the Hamilton quaternion (w, x, y, z) of the body → world rotation (docs/conventions.md)");
    attitude = inQuadfdisFrame(eulerZyxFromUnitQuaternion(w / norm, x / norm, y / norm, z / norm));
    return true;
  }
  // ZYX Euler angles in radians have roll in [−π, π] and pitch in [−π/2, π/2], whatever the flight:
  // a value outside is another unit or convention (degrees, most often), not a manoeuvre, and
  // read as radians it would be a tumbling vehicle. Refused, naming the line.
  constexpr double kSlack = 1e-6;  // [rad] round-off of converters (asin, atan2 of a unit quaternion)
  const bool degrees = options_.angles_in_degrees;
  const double unit = degrees ? M_PI / 180.0 : 1.0;  // [rad] per unit of the columns
  const double roll = values[kRoll] * unit, pitch = values[kRoll + 1] * unit;
  const bool pitch_out = std::abs(pitch) > M_PI / 2 + kSlack;
  if (pitch_out || std::abs(roll) > M_PI + kSlack)
    throw TelemetryError(where() + ": " +
                         (pitch_out ? "pitch = " + cellText(kRoll + 1) + " is outside " + (degrees ? "±90°" : "±π/2")
                                    : "roll = " + cellText(kRoll) + " is outside " + (degrees ? "±180°" : "±π")) +
                         (degrees ? ": roll, pitch, yaw are ZYX Euler angles (read in degrees: --csv-angle-unit deg; docs/conventions.md)"
                                  : ": roll, pitch, yaw are ZYX Euler angles in radians (degrees? --csv-angle-unit deg; docs/conventions.md)"));
  attitude = inQuadfdisFrame({roll, pitch, values[kRoll + 2] * unit});
  return true;
}

int TelemetryReader::commandColumn(std::size_t motor) const { return kU1 + options_.file_motor[motor] - 1; }

// Column r (one of u1..u4) of a row whose cell is present → thrust of that motor (or squared
// speed). Each motor's command is converted alone: a merged export may give them on rows of their own.
double TelemetryReader::commandOf(const double (&values)[kColumnCount], int r) const {
  // Commands in newtons per motor: the largest quadrotor motors make ~100 N (10 kg of thrust), so
  // hundreds are another unit (PWM µs, a raw 0–65535 command), which the thrust map must convert.
  constexpr double kMaxMotorThrust = 500.0;  // [N] five times the largest heavy-lift motor's thrust
  // A throttle a little outside [0, 1] is a controller's round-off (clamped); far outside, another
  // quantity. A pulse beyond the range by its width again is no pulse (a raw 0–65535 command).
  constexpr double kThrottleSlack = 0.05;  // [-]
  const CommandQuantity quantity = options_.commands;
  const CommandCurve& curve = options_.curve;
  const double v = values[r];
  if (quantity == CommandQuantity::kThrust && std::abs(v) > kMaxMotorThrust)
    throw TelemetryError(where() + ": column '" + label(r) + "' = " + cellText(r) +
                         " is no thrust in newtons (over 500 N a motor): PWM or a throttle? read it with --csv-commands "
                         "pwm or throttle and the vehicle's thrust curve (docs/conventions.md)");
  if (quantity == CommandQuantity::kThrottle && !(v >= -kThrottleSlack && v <= 1.0 + kThrottleSlack))
    throw TelemetryError(where() + ": column '" + label(r) + "' = " + cellText(r) +
                         " is no throttle in [0, 1] (--csv-commands throttle): a PWM pulse (--csv-commands pwm) or a "
                         "thrust in newtons (--csv-commands thrust)?");
  if (quantity == CommandQuantity::kPwm && !(v >= 0.0 && v <= 2.0 * curve.pwm_max - curve.pwm_min))
    throw TelemetryError(where() + ": column '" + label(r) + "' = " + cellText(r) + " is no PWM pulse in µs between " +
                         numberText(curve.pwm_min) + " and " + numberText(curve.pwm_max) +
                         " (--csv-commands pwm; the range: --csv-pwm-min, --csv-pwm-max)");
  switch (quantity) {
    case CommandQuantity::kThrust: return v;
    case CommandQuantity::kRotorSpeed: return v * v;
    case CommandQuantity::kThrottle: return thrustAtCommand(curve.max_thrust, curve.model_factor, v);  // c clamped to [0, 1]
    case CommandQuantity::kPwm:
      return thrustAtCommand(curve.max_thrust, curve.model_factor, (v - curve.pwm_min) / (curve.pwm_max - curve.pwm_min));
  }
  return v;
}

// Position and attitude from the file's frame into quadfdi's (north, east, down and FRD → north,
// west, up and FLU: both turned 180° about x).
std::array<double, 3> TelemetryReader::positionOf(const double (&values)[kColumnCount]) const {
  if (options_.frame == TelemetryFrame::kNed) return {values[1], -values[2], -values[3]};
  return {values[1], values[2], values[3]};
}

// Body rates from the file's unit and body frame into rad/s, FLU (FRD → FLU: q and r change sign,
// the body turned 180° about x); a rate beyond any gyro's range is another unit, refused.
std::array<double, 3> TelemetryReader::ratesOf(const double (&values)[kColumnCount]) const {
  const double unit = options_.rates_in_degrees ? M_PI / 180.0 : 1.0;
  for (int r = kP; r < kP + 3; ++r)
    if (std::abs(values[r] * unit) > kMaxBodyRate)
      throw TelemetryError(where() + ": " + label(r) + " = " + cellText(r) + " is no body rate" +
                           (options_.rates_in_degrees ? " in deg/s (over 100 rad/s)"
                                                      : " in rad/s (over 100 rad/s): degrees per second? --csv-rate-unit deg/s"));
  const double sign = options_.frame == TelemetryFrame::kNed ? -1.0 : 1.0;
  return bodyVectorInTurnedAxes({values[kP] * unit, sign * values[kP + 1] * unit, sign * values[kP + 2] * unit}, options_.body_turn);
}

EulerZyx TelemetryReader::inQuadfdisFrame(const EulerZyx& attitude) const {
  return attitudeOfTurnedAxes(options_.frame == TelemetryFrame::kNed ? turnedAboutX(attitude) : attitude, options_.body_turn);
}

SampleSource::Next TelemetryReader::next(TelemetrySample& sample, std::string& problem) {
  double values[kColumnCount];
  bool present[kColumnCount];
  std::string why[kColumnCount];
  if (!readCells(values, present, why)) return Row::kEnd;
  for (int r = 0; r < kColumnCount; ++r)
    if (isRead(r) && !present[r]) {
      problem = why[r] + "; row skipped";
      return Row::kSkipped;
    }
  EulerZyx attitude;
  if (!attitudeOf(values, attitude, problem)) {
    problem += "; row skipped";
    return Row::kSkipped;
  }
  std::array<double, kInputDim> u{};
  for (std::size_t i = 0; i < kInputDim; ++i) u[i] = commandOf(values, commandColumn(i));
  sample.t = values[0];
  const std::array<double, 3> p = positionOf(values);
  sample.y = {p[0], p[1], p[2], attitude.roll, attitude.pitch, attitude.yaw};
  sample.u = u;
  sample.rates = rates_ ? ratesOf(values) : std::array<double, 3>{};
  return Row::kSample;
}

SampleSource::Next TelemetryReader::nextParts(TelemetryRowParts& parts, std::string& problem) {
  double values[kColumnCount];
  bool present[kColumnCount];
  std::string why[kColumnCount];
  if (!readCells(values, present, why)) return Row::kEnd;
  parts = TelemetryRowParts{};
  if (!present[0]) {
    problem = why[0] + "; row skipped";
    return Row::kSkipped;
  }
  parts.t = values[0];
  // A signal is in the row when all its cells are; one with some cells and not others is dropped, saying why.
  auto whole = [&](int first, int count, bool& has) {
    int n = 0, missing = -1;
    for (int r = first; r < first + count; ++r) {
      if (present[r]) ++n;
      else if (missing < 0) missing = r;
    }
    has = n == count;
    if (n > 0 && !has && parts.dropped.empty()) parts.dropped = why[missing];
  };
  whole(1, 3, parts.has_position);
  whole(quaternion_ ? kQw : kRoll, quaternion_ ? 4 : 3, parts.has_attitude);
  // Each motor's command stands alone (a merged export may give them on rows of their own); an
  // empty cell gives none, a NaN, infinite or absurd one is a problem, said as a partial signal's is.
  for (std::size_t i = 0; i < kInputDim; ++i) {
    const int c = commandColumn(i);
    parts.has_u[i] = present[c];
    if (!present[c] && !blank_[static_cast<std::size_t>(c)] && parts.dropped.empty()) parts.dropped = why[c];
  }
  parts.has_commands = present[kU1] && present[kU1 + 1] && present[kU1 + 2] && present[kU1 + 3];
  if (parts.has_position) parts.position = positionOf(values);
  if (parts.has_attitude) {
    EulerZyx attitude;
    std::string zero;
    parts.has_attitude = attitudeOf(values, attitude, zero);
    if (!parts.has_attitude && parts.dropped.empty()) parts.dropped = zero;
    parts.attitude = {attitude.roll, attitude.pitch, attitude.yaw};
  }
  for (std::size_t i = 0; i < kInputDim; ++i)
    if (parts.has_u[i]) parts.u[i] = commandOf(values, commandColumn(i));
  if (rates_) {
    whole(kP, 3, parts.has_rates);
    if (parts.has_rates) parts.rates = ratesOf(values);
  }
  return Row::kSample;
}

bool TelemetryReader::moreReady() const {
  if (in_.rdbuf()->in_avail() > 0) return true;
  if (&in_ != &std::cin) return true;  // a file: everything is there
  pollfd p{STDIN_FILENO, POLLIN, 0};
  return poll(&p, 1, 0) > 0 && (p.revents & POLLIN) != 0;
}

}  // namespace quadfdi
