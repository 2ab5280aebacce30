// Writes a file so that readers never see it half-written and an existing file is
// never lost to a failed run: write "<path>.tmp.<pid>", flush, then rename over <path>.
#pragma once

#include <fstream>
#include <string>

namespace quadfdi {

class AtomicFileWriter {
 public:
  // Opens the temporary file; throws std::runtime_error("PATH: cannot write: reason").
  explicit AtomicFileWriter(const std::string& path);
  ~AtomicFileWriter();  // removes the temporary file unless commit() succeeded
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

  std::ostream& stream() { return out_; }
  // Flushes, checks for write errors (disk full…), renames. Throws std::runtime_error.
  void commit();

 private:
  std::string path_;
  std::string temp_path_;
  std::ofstream out_;
  bool committed_ = false;
};

}  // namespace quadfdi
