#pragma once
// numpy .npz archives as numpy's savez_compressed writes them: a zip of .npy files, deflate-compressed.
// Arrays of float64/float32/int64/int32, C order, are read as doubles; arrays are written as float64.
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace roar::track {

class NpzError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct NpyArray {
  std::vector<std::size_t> shape;
  std::vector<double> data;  // row-major
  std::size_t rows() const { return shape.empty() ? 1 : shape[0]; }
};

// Throws NpzError naming the file, and the array where there is one.
std::map<std::string, NpyArray> readNpz(const std::string& path);
void writeNpz(const std::string& path, const std::map<std::string, NpyArray>& arrays);

// The array `key`, checked to be finite and of shape (N) or (N, columns); names file, key and problem.
const NpyArray& requireArray(const std::map<std::string, NpyArray>& arrays, const std::string& key, std::size_t columns,
                             const std::string& path);

}  // namespace roar::track
