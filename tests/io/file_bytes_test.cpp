#include "io/file_bytes.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>

#include "io/key_value.h"
#include "scratch_path.h"

namespace quadfdi {
namespace {

std::string refusalOf(const std::string& path, std::uintmax_t max_bytes, PipeReading pipes = PipeReading::kRead) {
  try {
    readFileBounded(path, max_bytes, "a vehicle file", pipes);
  } catch (const FileReadError& e) {
    return e.what();
  }
  return "accepted";
}

std::string writeFile(const std::string& name, const std::string& bytes) {
  const std::string path = test::scratchPath("FileBytes", name);
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

TEST(FileBytes, ARegularFileReadsBackByteForByteUpToTheBound) {
  const std::string bytes("mass = 0.03\n\0\xff\r\n", 17);
  const std::string path = writeFile("exact", bytes);
  EXPECT_EQ(readFileBounded(path, bytes.size(), "a vehicle file", PipeReading::kRead), bytes);  // the bound itself is allowed
  EXPECT_EQ(refusalOf(path, bytes.size() - 1), path + ": larger than 16 bytes, not a vehicle file");
  EXPECT_EQ(readFileBounded(writeFile("empty", ""), 0, "a vehicle file", PipeReading::kRefuse), "");
  std::remove(path.c_str());
}

TEST(FileBytes, AFolderADeviceAndAMissingFileAreRefusedInOneLine) {
  const std::string folder = test::scratchPath("FileBytes", "folder");
  std::filesystem::create_directories(folder);
  EXPECT_EQ(refusalOf(folder, 1 << 20), folder + ": is a folder, not a vehicle file");
  // A device is refused unread: /dev/zero read whole would never end.
  EXPECT_EQ(refusalOf("/dev/zero", 1 << 20), "/dev/zero: is a device or socket, not a vehicle file (it would be read without end)");
  EXPECT_EQ(refusalOf(folder + "/none.toml", 1 << 20), folder + "/none.toml: cannot open for reading (No such file or directory)");
  std::filesystem::remove_all(folder);
}

// A pipe (a shell's process substitution, <(…)) has no size: it is read, and refused once past
// the bound; where a file may be read twice, it is refused unopened (opening waits for a writer).
TEST(FileBytes, APipeIsReadAndRefusedPastTheBoundOrRefusedUnopened) {
  const std::string fifo = test::scratchPath("FileBytes", "fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto feed = [&](const std::string& bytes) {
    // One write below PIPE_BUF: complete before the reader can close, so no SIGPIPE.
    return std::thread([&fifo, bytes] { std::ofstream(fifo, std::ios::binary) << bytes; });
  };
  std::thread writer = feed("mass = 0.03\n");
  EXPECT_EQ(readFileBounded(fifo, 12, "a vehicle file", PipeReading::kRead), "mass = 0.03\n");
  writer.join();
  writer = feed("mass = 0.03\n");
  EXPECT_EQ(refusalOf(fifo, 11), fifo + ": larger than 11 bytes, not a vehicle file");
  writer.join();
  EXPECT_EQ(refusalOf(fifo, 1 << 20, PipeReading::kRefuse),
            fifo + ": is a pipe, not a vehicle file (quadfdi may read it more than once, and a pipe gives its bytes once: write it to a file)");
  std::remove(fifo.c_str());
}

// Every configuration reader goes through readTextFile: its bound and refusals, as ConfigError.
TEST(FileBytes, ConfigurationFilesAreBoundedAndRefusedAsConfigErrors) {
  const std::string large = writeFile("large.toml", std::string(kMaxConfigFileBytes + 1, '#'));
  try {
    readKeyValueFile(large);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), large + ": larger than 1048576 bytes, not a configuration file");
  }
  try {
    readTextFile("/dev/zero", "a controller file");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), "/dev/zero: is a device or socket, not a controller file (it would be read without end)");
  }
  std::remove(large.c_str());
}

}  // namespace
}  // namespace quadfdi
