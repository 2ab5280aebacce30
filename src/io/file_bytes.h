// Whole-file reads with a size bound, for every reader that takes a file whole (configs,
// calibrations, models, flight logs). An unbounded read of a device (/dev/zero, /dev/urandom)
// or an endless pipe never returns; these refuse it in one line instead.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace quadfdi {

// "PATH: problem"; each reader rethrows it as its own error type (ConfigError, ModelError).
class FileReadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// [bytes] Largest configuration file (vehicle, randomisation, controller, parameters, --config,
// calibration): the shipped ones are 0.5–15 kB and a PX4 parameter dump ~60 kB; a larger file is
// some other file, and reading it whole would only delay the refusal.
constexpr std::uintmax_t kMaxConfigFileBytes = std::uintmax_t{1} << 20;
// [bytes] Largest flight log: an hour of PX4 logging at its high-rate profile is ~1 GB; four
// times that is read into memory whole, anything larger is refused rather than exhausting it.
constexpr std::uintmax_t kMaxLogFileBytes = std::uintmax_t{4} << 30;

// Whether a named pipe (a shell's process substitution, `<(zcat log.ulg.gz)`) is read: a pipe
// gives its bytes once, so only a file read once per run may be one.
enum class PipeReading { kRead, kRefuse };

// The file's bytes. Reads regular files and, where asked, pipes; refuses a folder, a device or a
// socket, a file that cannot be opened, and more than max_bytes (a regular file by its size,
// before reading; a pipe once it has passed the bound). `kind` names what the file should have
// been, in the refusal ("a vehicle file").
std::string readFileBounded(const std::string& path, std::uintmax_t max_bytes, const std::string& kind, PipeReading pipes);

// Standard input's bytes to its end, as readFileBounded reads a pipe (`zcat log.ulg.gz | quadfdi
// detect --format ulog`), named "<stdin>" in its refusals; a terminal is refused, unread.
std::string readStandardInputBounded(std::uintmax_t max_bytes, const std::string& kind);

}  // namespace quadfdi
