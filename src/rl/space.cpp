#include "roar/rl/space.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>

namespace roar::rl {

namespace {

std::string number(double v) {
  if (std::isinf(v)) return v > 0 ? ".inf" : "-.inf";
  std::ostringstream out;
  out.precision(9);
  out << v;
  return out.str();
}

std::string join(const std::vector<double>& values) {
  std::string out = "[";
  for (std::size_t i = 0; i < values.size(); ++i) out += (i ? ", " : "") + number(values[i]);
  return out + "]";
}

std::string shapeText(const std::vector<int>& shape) {
  std::string out = "[";
  for (std::size_t i = 0; i < shape.size(); ++i) out += (i ? ", " : "") + std::to_string(shape[i]);
  return out + "]";
}

std::size_t product(const std::vector<int>& shape) {
  std::size_t n = 1;
  for (int d : shape) n *= static_cast<std::size_t>(d);
  return n;
}

std::size_t keyIndex(const std::vector<std::string>& keys, const std::string& key) {
  return static_cast<std::size_t>(std::lower_bound(keys.begin(), keys.end(), key) - keys.begin());
}

void flattenInto(const Space& space, const Value& value, std::vector<float>* out) {
  switch (space.kind) {
    case Space::Kind::kBox:
    case Space::Kind::kMultiBinary:
      for (double v : value.numbers) out->push_back(static_cast<float>(v));
      break;
    case Space::Kind::kDiscrete: {
      const std::size_t at = out->size();
      out->resize(at + static_cast<std::size_t>(space.n), 0.0f);
      const auto k = static_cast<std::int64_t>(value.numbers.at(0)) - space.start;
      if (k < 0 || k >= space.n) throw SpaceError("a Discrete value is off its range");
      (*out)[at + static_cast<std::size_t>(k)] = 1.0f;
      break;
    }
    case Space::Kind::kDict:
      for (std::size_t i = 0; i < space.keys.size(); ++i) flattenInto(space.entries[i], value.at(space.keys[i]), out);
      break;
  }
}

Value unflattenFrom(const Space& space, const std::vector<float>& flat, std::size_t* at) {
  Value v;
  switch (space.kind) {
    case Space::Kind::kBox:
    case Space::Kind::kMultiBinary:
      for (std::size_t i = 0; i < space.elements(); ++i) v.numbers.push_back(flat[(*at)++]);
      break;
    case Space::Kind::kDiscrete: {
      const auto begin = flat.begin() + static_cast<std::ptrdiff_t>(*at);
      const auto best = std::max_element(begin, begin + space.n);
      v.numbers.push_back(static_cast<double>(space.start + (best - begin)));
      *at += static_cast<std::size_t>(space.n);
      break;
    }
    case Space::Kind::kDict:
      for (std::size_t i = 0; i < space.keys.size(); ++i)
        v.at(space.keys[i]) = unflattenFrom(space.entries[i], flat, at);
      break;
  }
  return v;
}

void flattenBounds(const Space& space, std::vector<double>* low, std::vector<double>* high) {
  switch (space.kind) {
    case Space::Kind::kBox:
      low->insert(low->end(), space.low.begin(), space.low.end());
      high->insert(high->end(), space.high.begin(), space.high.end());
      break;
    case Space::Kind::kMultiBinary:
    case Space::Kind::kDiscrete:
      low->resize(low->size() + space.flatDim(), 0.0);
      high->resize(high->size() + space.flatDim(), 1.0);
      break;
    case Space::Kind::kDict:
      for (const auto& entry : space.entries) flattenBounds(entry, low, high);
      break;
  }
}

void yamlInto(const Space& space, const std::string& indent, std::string* out) {
  switch (space.kind) {
    case Space::Kind::kBox:
      *out += indent + "type: Box\n" + indent + "dtype: " + dtypeName(space.dtype) + "\n" + indent +
              "shape: " + shapeText(space.shape) + "\n" + indent + "low: " + join(space.low) + "\n" + indent +
              "high: " + join(space.high) + "\n";
      break;
    case Space::Kind::kDiscrete:
      *out += indent + "type: Discrete\n" + indent + "dtype: int64\n" + indent + "n: " + std::to_string(space.n) +
              "\n" + indent + "start: " + std::to_string(space.start) + "\n";
      break;
    case Space::Kind::kMultiBinary:
      *out += indent + "type: MultiBinary\n" + indent + "dtype: int8\n" + indent + "shape: " + shapeText(space.shape) +
              "\n";
      break;
    case Space::Kind::kDict:
      *out += indent + "type: Dict\n" + indent + "spaces:\n";
      for (std::size_t i = 0; i < space.keys.size(); ++i) {
        *out += indent + "  " + space.keys[i] + ":\n";
        yamlInto(space.entries[i], indent + "    ", out);
      }
      break;
  }
}

}  // namespace

const char* kindName(Space::Kind kind) {
  switch (kind) {
    case Space::Kind::kBox:
      return "Box";
    case Space::Kind::kDiscrete:
      return "Discrete";
    case Space::Kind::kMultiBinary:
      return "MultiBinary";
    case Space::Kind::kDict:
      return "Dict";
  }
  return "?";
}

const char* dtypeName(DType dtype) {
  switch (dtype) {
    case DType::kFloat32:
      return "float32";
    case DType::kFloat64:
      return "float64";
    case DType::kInt64:
      return "int64";
    case DType::kUInt8:
      return "uint8";
  }
  return "?";
}

Space Space::box(double low, double high, std::vector<int> shape, DType dtype) {
  const std::size_t n = product(shape);
  return box(std::vector<double>(n, low), std::vector<double>(n, high), std::move(shape), dtype);
}

Space Space::box(std::vector<double> low, std::vector<double> high, std::vector<int> shape, DType dtype) {
  for (int d : shape) {
    if (d <= 0) throw SpaceError("Box shape " + shapeText(shape) + " has a dimension that is not positive");
  }
  const std::size_t n = product(shape);
  if (low.size() != n || high.size() != n) {
    throw SpaceError("Box of shape " + shapeText(shape) + " needs " + std::to_string(n) + " bounds a side, got " +
                     std::to_string(low.size()) + " and " + std::to_string(high.size()));
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (std::isnan(low[i]) || std::isnan(high[i]) || low[i] > high[i]) {
      throw SpaceError("Box bound " + std::to_string(i) + ": low " + number(low[i]) + " and high " + number(high[i]) +
                       " are not an interval");
    }
  }
  Space s;
  s.kind = Kind::kBox;
  s.shape = std::move(shape);
  s.low = std::move(low);
  s.high = std::move(high);
  s.dtype = dtype;
  return s;
}

Space Space::discrete(std::int64_t n, std::int64_t start) {
  if (n <= 0) throw SpaceError("Discrete needs n > 0, got " + std::to_string(n));
  Space s;
  s.kind = Kind::kDiscrete;
  s.n = n;
  s.start = start;
  s.dtype = DType::kInt64;
  return s;
}

Space Space::multiBinary(int n) {
  if (n <= 0) throw SpaceError("MultiBinary needs n > 0, got " + std::to_string(n));
  Space s;
  s.kind = Kind::kMultiBinary;
  s.shape = {n};
  return s;
}

Space Space::dict(std::vector<std::pair<std::string, Space>> entries) {
  std::sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  Space s;
  s.kind = Kind::kDict;
  for (auto& [key, space] : entries) {
    if (!s.keys.empty() && s.keys.back() == key) throw SpaceError("Dict key '" + key + "' is given twice");
    s.keys.push_back(key);
    s.entries.push_back(std::move(space));
  }
  return s;
}

std::size_t Space::elements() const {
  switch (kind) {
    case Kind::kBox:
    case Kind::kMultiBinary:
      return product(shape);
    case Kind::kDiscrete:
      return 1;
    case Kind::kDict: {
      std::size_t n = 0;
      for (const auto& e : entries) n += e.elements();
      return n;
    }
  }
  return 0;
}

std::size_t Space::flatDim() const {
  if (kind == Kind::kDiscrete) return static_cast<std::size_t>(n);
  if (kind != Kind::kDict) return elements();
  std::size_t d = 0;
  for (const auto& e : entries) d += e.flatDim();
  return d;
}

bool Space::has(const std::string& key) const {
  const std::size_t i = keyIndex(keys, key);
  return kind == Kind::kDict && i < keys.size() && keys[i] == key;
}

const Space& Space::at(const std::string& key) const {
  if (!has(key)) throw SpaceError("the space has no key '" + key + "'");
  return entries[keyIndex(keys, key)];
}

Value Value::of(std::vector<double> numbers) {
  Value v;
  v.numbers = std::move(numbers);
  return v;
}

bool Value::has(const std::string& key) const {
  const std::size_t i = keyIndex(keys, key);
  return i < keys.size() && keys[i] == key;
}

Value& Value::at(const std::string& key) {
  const std::size_t i = keyIndex(keys, key);
  if (i == keys.size() || keys[i] != key) {
    keys.insert(keys.begin() + static_cast<std::ptrdiff_t>(i), key);
    entries.insert(entries.begin() + static_cast<std::ptrdiff_t>(i), Value());
  }
  return entries[i];
}

const Value& Value::at(const std::string& key) const {
  if (!has(key)) throw SpaceError("the value has no key '" + key + "'");
  return entries[keyIndex(keys, key)];
}

namespace {

// check() on the hot path (every action of every step): where a value is in its space is named only when
// it is not, so a valid value costs no string.
using PathOf = std::function<std::string()>;

void checkAt(const Space& space, const Value& value, const PathOf& name) {
  if (space.kind == Space::Kind::kDict) {
    for (const auto& key : value.keys) {
      if (!space.has(key)) throw SpaceError(name() + ": unknown key '" + key + "'");
    }
    for (std::size_t i = 0; i < space.keys.size(); ++i) {
      const PathOf path = [&] { return name() + "['" + space.keys[i] + "']"; };
      if (!value.has(space.keys[i])) throw SpaceError(path() + " is missing");
      checkAt(space.entries[i], value.at(space.keys[i]), path);
    }
    return;
  }
  if (!value.keys.empty()) throw SpaceError(name() + " is a Dict, but its space is not");
  if (value.numbers.size() != space.elements()) {
    throw SpaceError(name() + " has " + std::to_string(value.numbers.size()) + " numbers; its space " +
                     (space.kind == Space::Kind::kBox ? "(shape " + shapeText(space.shape) + ") " : "") + "has " +
                     std::to_string(space.elements()));
  }
  for (std::size_t i = 0; i < value.numbers.size(); ++i) {
    const double v = value.numbers[i];
    auto at = [&] { return space.kind == Space::Kind::kDiscrete ? name() : name() + "[" + std::to_string(i) + "]"; };
    if (std::isnan(v)) throw SpaceError(at() + " is NaN");
    switch (space.kind) {
      case Space::Kind::kBox:
        if (v < space.low[i] || v > space.high[i]) {
          throw SpaceError(at() + " = " + number(v) + " is outside [" + number(space.low[i]) + ", " +
                           number(space.high[i]) + "]");
        }
        break;
      case Space::Kind::kDiscrete:
        if (v != std::floor(v) || v < static_cast<double>(space.start) ||
            v > static_cast<double>(space.start + space.n - 1)) {
          throw SpaceError(at() + " = " + number(v) + " is not one of " + std::to_string(space.start) + " .. " +
                           std::to_string(space.start + space.n - 1));
        }
        break;
      case Space::Kind::kMultiBinary:
        if (v != 0.0 && v != 1.0) throw SpaceError(at() + " = " + number(v) + " is not 0 or 1");
        break;
      case Space::Kind::kDict:
        break;
    }
  }
}

}  // namespace

void check(const Space& space, const Value& value, const std::string& name) {
  checkAt(space, value, [&] { return name; });
}

bool contains(const Space& space, const Value& value) {
  try {
    check(space, value);
    return true;
  } catch (const SpaceError&) {
    return false;
  }
}

std::vector<float> flatten(const Space& space, const Value& value) {
  // Not check(): observations are flattened every step and are in their space by construction. Only the
  // shape is checked here.
  std::vector<float> out;
  out.reserve(space.flatDim());
  flattenInto(space, value, &out);
  if (out.size() != space.flatDim()) {
    throw SpaceError("the value flattens to " + std::to_string(out.size()) + " numbers; its space to " +
                     std::to_string(space.flatDim()));
  }
  return out;
}

Value unflatten(const Space& space, const std::vector<float>& flat) {
  if (flat.size() != space.flatDim()) {
    throw SpaceError("a flat value of this space has " + std::to_string(space.flatDim()) + " numbers, got " +
                     std::to_string(flat.size()));
  }
  std::size_t at = 0;
  return unflattenFrom(space, flat, &at);
}

Space flattenSpace(const Space& space) {
  std::vector<double> low, high;
  flattenBounds(space, &low, &high);
  return Space::box(low, high, {static_cast<int>(low.size())}, DType::kFloat32);
}

Value sample(const Space& space, std::mt19937_64& rng) {
  Value v;
  switch (space.kind) {
    case Space::Kind::kBox:
      for (std::size_t i = 0; i < space.elements(); ++i) {
        const double lo = space.low[i], hi = space.high[i];
        double x;
        if (std::isfinite(lo) && std::isfinite(hi)) {
          x = std::uniform_real_distribution<double>(lo, hi)(rng);
          if (space.dtype == DType::kInt64 || space.dtype == DType::kUInt8) x = std::floor(x + 0.5);
        } else if (std::isfinite(lo)) {
          x = lo + std::exponential_distribution<double>(1.0)(rng);
        } else if (std::isfinite(hi)) {
          x = hi - std::exponential_distribution<double>(1.0)(rng);
        } else {
          x = std::normal_distribution<double>(0.0, 1.0)(rng);
        }
        v.numbers.push_back(std::clamp(x, lo, hi));
      }
      break;
    case Space::Kind::kDiscrete:
      v.numbers.push_back(
          static_cast<double>(space.start + std::uniform_int_distribution<std::int64_t>(0, space.n - 1)(rng)));
      break;
    case Space::Kind::kMultiBinary:
      for (std::size_t i = 0; i < space.elements(); ++i)
        v.numbers.push_back(std::uniform_int_distribution<int>(0, 1)(rng));
      break;
    case Space::Kind::kDict:
      for (std::size_t i = 0; i < space.keys.size(); ++i) v.at(space.keys[i]) = sample(space.entries[i], rng);
      break;
  }
  return v;
}

Value zeros(const Space& space) {
  Value v;
  switch (space.kind) {
    case Space::Kind::kBox:
      for (std::size_t i = 0; i < space.elements(); ++i)
        v.numbers.push_back(std::clamp(0.0, space.low[i], space.high[i]));
      break;
    case Space::Kind::kDiscrete:
      v.numbers.push_back(static_cast<double>(space.start));
      break;
    case Space::Kind::kMultiBinary:
      v.numbers.assign(space.elements(), 0.0);
      break;
    case Space::Kind::kDict:
      for (std::size_t i = 0; i < space.keys.size(); ++i) v.at(space.keys[i]) = zeros(space.entries[i]);
      break;
  }
  return v;
}

std::string toYaml(const Space& space) {
  std::string out;
  yamlInto(space, "", &out);
  return out;
}

}  // namespace roar::rl
