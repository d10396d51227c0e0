// SPDX-License-Identifier: MIT
/// @file Bounded reads and atomic writes (include/cmmcomp/io/file_io.hpp), on POSIX file
/// descriptors: the checks must be made on the file actually opened, not on its name.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace cmmcomp::io {
namespace {

std::string errno_text() { return std::strerror(errno); }

// Closes a descriptor on every path out of a function.
class Descriptor {
 public:
  explicit Descriptor(int fd) : fd_(fd) {}
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const { return fd_; }
  /// Closes now and reports whether close succeeded (a write error can surface only here).
  bool close() {
    const int fd = fd_;
    fd_ = -1;
    return ::close(fd) == 0;
  }

 private:
  int fd_;
};

bool write_all(int fd, const std::string& text) {
  const char* p = text.data();
  std::size_t left = text.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  return true;
}

std::string directory_of(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

}  // namespace

std::string read_file_bounded(const std::string& path, const char* what, std::uintmax_t max_bytes) {
  // Non-blocking: opening a FIFO with no writer would otherwise wait forever.
  Descriptor fd(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC));
  if (fd.get() < 0) throw ConfigError(path + ": cannot open " + what + " (" + errno_text() + ")");
  struct stat st {};
  if (::fstat(fd.get(), &st) != 0) {
    throw ConfigError(path + ": cannot read " + what + " (" + errno_text() + ")");
  }
  if (!S_ISREG(st.st_mode)) {
    throw ConfigError(path + ": not a regular file (a " + what + " must be one)");
  }
  if (static_cast<std::uintmax_t>(st.st_size) > max_bytes) {
    throw ConfigError(path + ": " + std::to_string(st.st_size) + " bytes, more than the " +
                      std::to_string(max_bytes) + " bytes a " + what + " may have");
  }
  std::string text;
  text.reserve(static_cast<std::size_t>(st.st_size));
  char chunk[65536];
  for (;;) {
    const ssize_t n = ::read(fd.get(), chunk, sizeof chunk);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw ConfigError(path + ": cannot read " + what + " (" + errno_text() + ")");
    if (n == 0) break;
    text.append(chunk, static_cast<std::size_t>(n));
    // The file may grow while it is read: the limit holds for what is read, too.
    if (text.size() > max_bytes) {
      throw ConfigError(path + ": more than the " + std::to_string(max_bytes) + " bytes a " + what +
                        " may have");
    }
  }
  return text;
}

void write_file_atomically(const std::string& path, const std::string& text) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    if (S_ISDIR(st.st_mode)) throw Error(path + ": is a directory, not an output file");
    // A device, FIFO or terminal: it cannot be replaced, so it is written as is.
    Descriptor fd(::open(path.c_str(), O_WRONLY | O_CLOEXEC));
    if (fd.get() < 0) throw Error(path + ": cannot open for writing (" + errno_text() + ")");
    if (!write_all(fd.get(), text)) throw Error(path + ": write failed (" + errno_text() + ")");
    if (!fd.close()) throw Error(path + ": write failed (" + errno_text() + ")");
    return;
  }
  std::string tmp = path + ".tmp.XXXXXX";
  std::vector<char> name(tmp.begin(), tmp.end());
  name.push_back('\0');
  Descriptor fd(::mkstemp(name.data()));
  if (fd.get() < 0) {
    throw Error(path + ": cannot create a temporary file in " + directory_of(path) + " (" +
                errno_text() + ")");
  }
  tmp = name.data();
  const auto fail = [&](const char* step) {
    const std::string reason = errno_text();
    ::unlink(tmp.c_str());
    throw Error(path + ": " + step + " failed (" + reason + "); nothing was replaced");
  };
  const mode_t mask = ::umask(0);
  ::umask(mask);
  if (::fchmod(fd.get(), 0666 & ~mask) != 0) fail("setting permissions");
  if (!write_all(fd.get(), text)) fail("write");
  if (::fsync(fd.get()) != 0) fail("fsync");
  if (!fd.close()) fail("close");
  if (::rename(tmp.c_str(), path.c_str()) != 0) fail("rename");
}

}  // namespace cmmcomp::io
