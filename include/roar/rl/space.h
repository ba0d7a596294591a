#pragma once
// Spaces as Gymnasium describes them (Box, Discrete, MultiBinary, Dict) and values in them, so that an
// environment's actions and observations read like ROAR_PY's (gymnasium.spaces) and flatten the same way.
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace roar::rl {

// numpy's element types.
enum class DType { kFloat32, kFloat64, kInt64, kUInt8 };
const char* dtypeName(DType dtype);  // "float32", "float64", "int64", "uint8"

class SpaceError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

struct Space {
  enum class Kind { kBox, kDiscrete, kMultiBinary, kDict };
  Kind kind = Kind::kBox;
  std::vector<int> shape;         // Box; MultiBinary: {n}; Discrete: {}
  std::vector<double> low, high;  // Box: one bound per element, row-major (may be infinite)
  DType dtype = DType::kFloat32;  // Box; Discrete is int64 and MultiBinary int8 in Gymnasium
  std::int64_t n = 0;             // Discrete: the values start .. start + n - 1
  std::int64_t start = 0;
  std::vector<std::string> keys;  // Dict: sorted, as Gymnasium sorts a dict's keys
  std::vector<Space> entries;     // Dict: the space of each key

  static Space box(double low, double high, std::vector<int> shape, DType dtype = DType::kFloat32);
  static Space box(std::vector<double> low, std::vector<double> high, std::vector<int> shape,
                   DType dtype = DType::kFloat32);
  static Space discrete(std::int64_t n, std::int64_t start = 0);
  static Space multiBinary(int n);
  // Throws SpaceError for a key given twice.
  static Space dict(std::vector<std::pair<std::string, Space>> entries);

  // Numbers in a value: a Box's or MultiBinary's elements, 1 for a Discrete, a Dict's sum.
  std::size_t elements() const;
  // gymnasium.spaces.flatdim: as elements(), but a Discrete counts n (it flattens one-hot).
  std::size_t flatDim() const;
  // A Dict's entry; throws SpaceError naming the key.
  const Space& at(const std::string& key) const;
  bool has(const std::string& key) const;
};

// Gymnasium's class name of a kind of space: "Box", "Discrete", "MultiBinary", "Dict".
const char* kindName(Space::Kind kind);

// A value of a space: a Box's, Discrete's or MultiBinary's numbers in row-major order, or a Dict's values
// by (sorted) key.
struct Value {
  std::vector<double> numbers;
  std::vector<std::string> keys;
  std::vector<Value> entries;

  static Value of(std::vector<double> numbers);
  // A Dict's entry, made when missing (kept in key order); const: throws SpaceError naming the key.
  Value& at(const std::string& key);
  const Value& at(const std::string& key) const;
  bool has(const std::string& key) const;
};

// Throws SpaceError naming where (`name['steer'][0]`) a value leaves its space: a key missing or unknown,
// a wrong number of elements, NaN, a number outside a Box's bounds, a Discrete off its range or not
// whole, a MultiBinary entry other than 0 or 1.
void check(const Space& space, const Value& value, const std::string& name = "value");
bool contains(const Space& space, const Value& value);

// gymnasium.spaces.flatten / unflatten: Dict entries in key order, a Discrete one-hot (unflatten takes the
// largest entry). flatten checks the value's shape only (check() its bounds first where they matter).
std::vector<float> flatten(const Space& space, const Value& value);
Value unflatten(const Space& space, const std::vector<float>& flat);
// gymnasium.spaces.flatten_space: the Box that flattened values lie in.
Space flattenSpace(const Space& space);

// Uniform over bounded sides, like Space.sample(); an unbounded side draws from an exponential, both
// sides unbounded from a normal distribution (Gymnasium's rule).
Value sample(const Space& space, std::mt19937_64& rng);
// A value with every number zero, or a Box's lower bound where zero is outside (a Discrete: its start).
Value zeros(const Space& space);

// The space in YAML, in Gymnasium's terms: {type: Box, dtype: float32, shape: [1], low: [...], high: [...]}.
std::string toYaml(const Space& space);

}  // namespace roar::rl
