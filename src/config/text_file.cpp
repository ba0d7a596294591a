#include "roar/config/text_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace roar::config {

namespace {

struct FileDescriptor {
  int fd;
  ~FileDescriptor() {
    if (fd >= 0) ::close(fd);
  }
};

std::string sizeText(std::size_t bytes) {
  return bytes >= (std::size_t{1} << 20) ? std::to_string(bytes >> 20) + " MiB" : std::to_string(bytes) + " bytes";
}

// The problem with the open file `fd`, or "".
std::string problemOf(int fd, const std::string& path, std::size_t max_bytes) {
  struct stat st {};
  if (::fstat(fd, &st) != 0) return path + ": cannot be read (" + std::strerror(errno) + ")";
  if (S_ISDIR(st.st_mode)) return path + ": is a folder, not a file";
  if (!S_ISREG(st.st_mode)) return path + ": is not a regular file (a device, FIFO or socket is not read)";
  if (static_cast<std::size_t>(st.st_size) > max_bytes)
    return path + ": is larger than " + sizeText(max_bytes) + " (" + sizeText(st.st_size) + ")";
  return "";
}

// Opens without blocking (a FIFO with no writer would wait for ever) and without becoming a terminal's owner.
int openForReading(const std::string& path, std::string* problem) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) {
    *problem =
        path + (errno == ENOENT ? ": no such file" : ": cannot be read (" + std::string(std::strerror(errno)) + ")");
  }
  return fd;
}

}  // namespace

bool checkRegularFile(const std::string& path, std::size_t max_bytes, std::string* problem) {
  FileDescriptor file{openForReading(path, problem)};
  if (file.fd < 0) return false;
  *problem = problemOf(file.fd, path, max_bytes);
  return problem->empty();
}

bool tryReadTextFile(const std::string& path, std::size_t max_bytes, std::string* text, std::string* problem) {
  FileDescriptor file{openForReading(path, problem)};
  if (file.fd < 0) return false;
  *problem = problemOf(file.fd, path, max_bytes);
  if (!problem->empty()) return false;
  text->clear();
  char buffer[65536];
  for (;;) {
    const ssize_t got = ::read(file.fd, buffer, sizeof buffer);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) {
      *problem = path + ": cannot be read (" + std::strerror(errno) + ")";
      return false;
    }
    if (got == 0) return true;
    // A file that grows while it is read is held to the same cap.
    if (text->size() + static_cast<std::size_t>(got) > max_bytes) {
      *problem = path + ": is larger than " + sizeText(max_bytes);
      return false;
    }
    text->append(buffer, static_cast<std::size_t>(got));
  }
}

}  // namespace roar::config
