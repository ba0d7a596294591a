#pragma once
// The one way roar_ros reads a text file it was pointed at (a map's centre line, a YAML file, a URDF): only
// a regular file, only up to a size cap, checked before a byte is parsed, so a device (/dev/zero), a FIFO or
// a huge file is refused by name instead of blocking or eating memory (text_file_test).
#include <cstddef>
#include <string>

namespace roar::config {

// Caps by kind of file, each far above the largest file of its kind the package ships.
inline constexpr std::size_t kMaxYamlBytes = std::size_t{4} << 20;     // 4 MiB: options, sensor sets, scenarios
inline constexpr std::size_t kMaxPolicyBytes = std::size_t{64} << 20;  // 64 MiB: a policy's weights as YAML
inline constexpr std::size_t kMaxTableBytes = std::size_t{64} << 20;   // 64 MiB: centre lines, point lists
inline constexpr std::size_t kMaxUrdfBytes = std::size_t{4} << 20;

// Reads the file whole, or returns false with `*problem` saying why ("<path>: no such file", "... is not a
// regular file", "... is larger than N bytes", ...).
bool tryReadTextFile(const std::string& path, std::size_t max_bytes, std::string* text, std::string* problem);

// As above, throwing the caller's error type with the problem.
template <class Error>
std::string readTextFile(const std::string& path, std::size_t max_bytes) {
  std::string text, problem;
  if (!tryReadTextFile(path, max_bytes, &text, &problem)) throw Error(problem);
  return text;
}

// Whether `path` is a regular file within the cap (for readers that open the file themselves, as libzip).
bool checkRegularFile(const std::string& path, std::size_t max_bytes, std::string* problem);

}  // namespace roar::config
