#include "io/file_bytes.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace quadfdi {

namespace {

// Closes the descriptor on every path out, the throwing ones included.
struct Descriptor {
  int fd = -1;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

std::string tooLarge(const std::string& path, std::uintmax_t max_bytes, const std::string& kind) {
  return path + ": larger than " + std::to_string(max_bytes) + " bytes, not " + kind;
}

// The descriptor's bytes to its end, at most max_bytes (`info`: its fstat: a regular file past the
// bound is refused unread, one within it has its size reserved).
std::string readToEnd(int fd, const struct stat& info, const std::string& name, std::uintmax_t max_bytes, const std::string& kind) {
  std::string bytes;
  if (S_ISREG(info.st_mode)) {
    if (static_cast<std::uintmax_t>(info.st_size) > max_bytes) throw FileReadError(tooLarge(name, max_bytes, kind));
    bytes.reserve(static_cast<std::size_t>(info.st_size));
  }
  char chunk[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, chunk, sizeof chunk);
    if (n == 0) break;
    if (n < 0) {
      if (errno == EINTR) continue;
      throw FileReadError(name + ": read error after " + std::to_string(bytes.size()) + " bytes (" + std::strerror(errno) + ")");
    }
    // A regular file that grows while read, or a pipe: the bound holds for what was read.
    if (bytes.size() + static_cast<std::size_t>(n) > max_bytes) throw FileReadError(tooLarge(name, max_bytes, kind));
    bytes.append(chunk, static_cast<std::size_t>(n));
  }
  return bytes;
}

}  // namespace

std::string readFileBounded(const std::string& path, std::uintmax_t max_bytes, const std::string& kind, PipeReading pipes) {
  // What the path is, before opening it: opening a pipe waits for its writer, so one refused must not be opened.
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) throw FileReadError(path + ": cannot open for reading (" + std::strerror(errno) + ")");
  if (S_ISDIR(info.st_mode)) throw FileReadError(path + ": is a folder, not " + kind);
  if (S_ISFIFO(info.st_mode) && pipes == PipeReading::kRefuse)
    throw FileReadError(path + ": is a pipe, not " + kind + " (quadfdi may read it more than once, and a pipe gives its bytes once: write it to a file)");
  if (!S_ISREG(info.st_mode) && !S_ISFIFO(info.st_mode))
    throw FileReadError(path + ": is a device or socket, not " + kind + " (it would be read without end)");
  Descriptor file;
  // Without O_NONBLOCK, opening a pipe waits for its writer as a shell's `cat` would (with it, a
  // pipe whose writer has not started yet would read as empty).
  do file.fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  while (file.fd < 0 && errno == EINTR);
  if (file.fd < 0) throw FileReadError(path + ": cannot open for reading (" + std::strerror(errno) + ")");
  if (::fstat(file.fd, &info) != 0) throw FileReadError(path + ": cannot read (" + std::strerror(errno) + ")");
  return readToEnd(file.fd, info, path, max_bytes, kind);
}

std::string readStandardInputBounded(std::uintmax_t max_bytes, const std::string& kind) {
  const std::string name = "<stdin>";
  struct stat info {};
  if (::fstat(STDIN_FILENO, &info) != 0) throw FileReadError(name + ": cannot read (" + std::strerror(errno) + ")");
  if (::isatty(STDIN_FILENO)) throw FileReadError(name + ": is a terminal, not " + kind + ": pipe the file in or name it with --input");
  if (S_ISDIR(info.st_mode)) throw FileReadError(name + ": is a folder, not " + kind);
  if (!S_ISREG(info.st_mode) && !S_ISFIFO(info.st_mode) && !S_ISSOCK(info.st_mode))
    throw FileReadError(name + ": is a device, not " + kind + " (it would be read without end)");
  return readToEnd(STDIN_FILENO, info, name, max_bytes, kind);
}

}  // namespace quadfdi
