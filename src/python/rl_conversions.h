// roar_rl_core's conversions between the rl library's spaces, values and results and NumPy, written once
// for every environment class the module registers (EnvPool's py_envpool.h is the model): spaces described
// as dicts, batched observation and info arrays written in place (no Python call, so the stepping threads
// write their rows without the GIL), batched actions read with errors naming the entry, and the guard that
// lets one Python thread in at a time.
#pragma once
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "roar/config/yaml_section.h"
#include "roar/rl/racing_env.h"
#include "roar/rl/vector_env.h"

namespace roar::python {

namespace py = pybind11;

// A space as the dict python/roar_rl turns into a Gymnasium space.
inline py::dict describe(const rl::Space& space) {
  py::dict d;
  d["kind"] = rl::kindName(space.kind);
  if (space.kind == rl::Space::Kind::kDict) {
    py::dict entries;
    for (std::size_t i = 0; i < space.keys.size(); ++i) entries[py::str(space.keys[i])] = describe(space.entries[i]);
    d["spaces"] = entries;
    return d;
  }
  d["shape"] = py::tuple(py::cast(space.shape));
  d["low"] = space.low;
  d["high"] = space.high;
  d["dtype"] = rl::dtypeName(space.dtype);
  d["n"] = space.n;
  d["start"] = space.start;
  return d;
}

// Where a leaf of a (possibly Dict) space lives in a Value and in the batched buffers.
struct Leaf {
  std::vector<std::string> path;  // keys from the root
  const rl::Space* space;
  std::size_t elements;
};

inline void leavesOf(const rl::Space& space, std::vector<std::string> path, std::vector<Leaf>* out) {
  if (space.kind == rl::Space::Kind::kDict) {
    for (std::size_t i = 0; i < space.keys.size(); ++i) {
      auto p = path;
      p.push_back(space.keys[i]);
      leavesOf(space.entries[i], p, out);
    }
    return;
  }
  out->push_back({path, &space, space.elements()});
}

inline const rl::Value& valueAt(const rl::Value& root, const Leaf& leaf) {
  const rl::Value* v = &root;
  for (const auto& key : leaf.path) v = &v->at(key);
  return *v;
}

inline rl::Value& valueAt(rl::Value& root, const Leaf& leaf) {
  rl::Value* v = &root;
  for (const auto& key : leaf.path) v = &v->at(key);
  return *v;
}

inline py::dtype dtypeOf(const rl::Space& space) {
  if (space.kind == rl::Space::Kind::kDiscrete) return py::dtype::of<std::int64_t>();
  if (space.kind == rl::Space::Kind::kMultiBinary) return py::dtype::of<std::int8_t>();
  switch (space.dtype) {
    case rl::DType::kFloat32:
      return py::dtype::of<float>();
    case rl::DType::kFloat64:
      return py::dtype::of<double>();
    case rl::DType::kInt64:
      return py::dtype::of<std::int64_t>();
    case rl::DType::kUInt8:
      return py::dtype::of<std::uint8_t>();
  }
  return py::dtype::of<float>();
}

template <class T>
inline void writeRow(char* base, std::size_t row, const std::vector<double>& numbers) {
  T* data = reinterpret_cast<T*>(base) + row * numbers.size();
  for (std::size_t k = 0; k < numbers.size(); ++k) data[k] = static_cast<T>(numbers[k]);
}

// Batched arrays, one per leaf, and the dict (or single array) Python sees. The arrays' memory and element
// types are taken once: the hot path makes no Python call.
struct Batch {
  enum class Element { kFloat32, kFloat64, kUInt8, kInt8, kInt64 };
  std::vector<Leaf> leaves;
  std::vector<py::array> arrays;
  std::vector<char*> data;
  std::vector<Element> elements;
  py::object view;  // a dict of the arrays (nested as the space), or the one array

  Batch(const rl::Space& space, std::size_t n) {
    leavesOf(space, {}, &leaves);
    for (const auto& leaf : leaves) {
      std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(n)};
      for (int d : leaf.space->shape) shape.push_back(d);
      arrays.emplace_back(dtypeOf(*leaf.space), shape);
      data.push_back(static_cast<char*>(arrays.back().mutable_data()));
      const auto kind = arrays.back().dtype().kind();
      const auto size = arrays.back().dtype().itemsize();
      elements.push_back(kind == 'f'   ? (size == 4 ? Element::kFloat32 : Element::kFloat64)
                         : kind == 'u' ? Element::kUInt8
                         : size == 1   ? Element::kInt8
                                       : Element::kInt64);
    }
    if (space.kind != rl::Space::Kind::kDict) {
      view = arrays.front();
      return;
    }
    py::dict root;
    for (std::size_t i = 0; i < leaves.size(); ++i) {
      py::dict node = root;
      for (std::size_t k = 0; k + 1 < leaves[i].path.size(); ++k) {
        py::str key(leaves[i].path[k]);
        if (!node.contains(key)) node[key] = py::dict();
        node = node[key].cast<py::dict>();
      }
      node[py::str(leaves[i].path.back())] = arrays[i];
    }
    view = root;
  }

  void write(std::size_t row, const rl::Value& value) {
    for (std::size_t i = 0; i < leaves.size(); ++i) {
      const auto& numbers = valueAt(value, leaves[i]).numbers;
      if (numbers.size() != leaves[i].elements) throw std::logic_error("an observation does not fit its space");
      switch (elements[i]) {
        case Element::kFloat32:
          writeRow<float>(data[i], row, numbers);
          break;
        case Element::kFloat64:
          writeRow<double>(data[i], row, numbers);
          break;
        case Element::kUInt8:
          writeRow<std::uint8_t>(data[i], row, numbers);
          break;
        case Element::kInt8:
          writeRow<std::int8_t>(data[i], row, numbers);
          break;
        case Element::kInt64:
          writeRow<std::int64_t>(data[i], row, numbers);
          break;
      }
    }
  }
};

// The info of every environment: one array per field.
struct Infos {
  static constexpr const char* kFields[] = {
      "progress", "track_s",   "lateral", "speed",         "collision_impulse", "collided",      "off_track",
      "stalled",  "wrong_way", "laps",    "last_lap_time", "episode_time",      "episode_steps", "episode_return"};
  static constexpr std::size_t kCount = sizeof(kFields) / sizeof(kFields[0]);
  std::vector<py::array_t<double>> arrays;
  std::vector<double*> data;
  py::dict view;

  explicit Infos(std::size_t n) {
    for (const char* field : kFields) {
      arrays.emplace_back(static_cast<py::ssize_t>(n));
      data.push_back(arrays.back().mutable_data());
      view[field] = arrays.back();
    }
  }
  void write(std::size_t row, const rl::StepInfo& i) {
    const double values[kCount] = {i.progress,
                                   i.track_s,
                                   i.lateral,
                                   i.speed,
                                   i.collision_impulse,
                                   double(i.collided),
                                   double(i.off_track),
                                   double(i.stalled),
                                   double(i.wrong_way),
                                   double(i.laps),
                                   i.last_lap_time,
                                   i.episode_time,
                                   double(i.episode_steps),
                                   i.episode_return};
    for (std::size_t k = 0; k < kCount; ++k) data[k][row] = values[k];
  }
};

// The arrays a step (or a recv) returns, `rows` of them, owned by the module and written in place.
// write() touches only its row's memory and makes no Python call: the threads that step the environments
// call it without the GIL, each for its own rows.
struct StepBuffers {
  std::unique_ptr<Batch> observations, final_observations;
  std::unique_ptr<Infos> infos;
  py::array_t<double> rewards;
  py::array_t<bool> terminations, truncations, final_mask;
  double* reward_data;
  bool *terminated_data, *truncated_data, *final_data;

  StepBuffers(const rl::Space& observation_space, std::size_t rows)
      : observations(std::make_unique<Batch>(observation_space, rows)),
        final_observations(std::make_unique<Batch>(observation_space, rows)),
        infos(std::make_unique<Infos>(rows)),
        rewards(static_cast<py::ssize_t>(rows)),
        terminations(static_cast<py::ssize_t>(rows)),
        truncations(static_cast<py::ssize_t>(rows)),
        final_mask(static_cast<py::ssize_t>(rows)),
        reward_data(rewards.mutable_data()),
        terminated_data(terminations.mutable_data()),
        truncated_data(truncations.mutable_data()),
        final_data(final_mask.mutable_data()) {}

  void write(std::size_t row, const rl::StepResult& r, const std::optional<rl::Value>& final_observation) {
    observations->write(row, r.observation);
    infos->write(row, r.info);
    reward_data[row] = r.reward;
    terminated_data[row] = r.terminated;
    truncated_data[row] = r.truncated;
    final_data[row] = final_observation.has_value();
    if (final_observation) final_observations->write(row, *final_observation);
  }

  // (observations, rewards, terminations, truncations, infos, final observations, final mask)
  py::tuple views() const {
    return py::make_tuple(observations->view, rewards, terminations, truncations, infos->view, final_observations->view,
                          final_mask);
  }
};

// One call at a time: the GIL is released while environments step, so a second Python thread could enter
// the same environments (and their buffers) mid-step. It gets a clear error instead (test_roar_rl).
class OneCaller {
 public:
  std::unique_lock<std::mutex> enter(const char* what) {
    std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock()) {
      throw std::runtime_error(std::string("VectorEnv.") + what +
                               " while another thread is inside this VectorEnv: call it from one thread at a "
                               "time (or give each thread its own VectorEnv)");
    }
    return lock;
  }

 private:
  std::mutex mutex_;
};

// Actions from Python, a dict of arrays (or one array) with a leading axis of `rows`, read into Values
// whose tree keeps its shape from call to call (each leaf's Value found once).
class BatchedActions {
 public:
  BatchedActions(const rl::Space& space, std::size_t capacity) : space_(&space) {
    leavesOf(space, {}, &leaves_);
    for (const auto& leaf : leaves_) {
      std::vector<py::str> keys;
      for (const auto& key : leaf.path) keys.emplace_back(key);
      keys_.push_back(std::move(keys));
    }
    actions_ = std::vector<rl::Value>(capacity, rl::zeros(space));
    for (std::size_t i = 0; i < capacity; ++i) {
      for (const auto& leaf : leaves_) {
        values_.push_back(space.kind == rl::Space::Kind::kDict ? &valueAt(actions_[i], leaf) : &actions_[i]);
      }
    }
  }

  // The first `rows` actions, read from `actions`; throws KeyError/ValueError naming the entry. Every step
  // passes here: the keys are Python strings made once, and the entry's name is written only for an error.
  const std::vector<rl::Value>& read(const py::object& actions, std::size_t rows) {
    for (std::size_t l = 0; l < leaves_.size(); ++l) {
      const Leaf& leaf = leaves_[l];
      PyObject* entry = actions.ptr();
      for (std::size_t k = 0; k < keys_[l].size(); ++k) {
        entry = PyDict_Check(entry) ? PyDict_GetItemWithError(entry, keys_[l][k].ptr()) : nullptr;
        if (!entry) {
          if (PyErr_Occurred()) throw py::error_already_set();
          throw py::key_error(entryName(leaf, k + 1) +
                              " is missing: an action is a dict of arrays with a leading axis of " +
                              std::to_string(rows) + " environments");
        }
      }
      const auto array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(
          py::reinterpret_borrow<py::object>(entry));
      if (!array || !shapeFits(array, rows, *leaf.space)) {
        throw py::value_error(entryName(leaf, leaf.path.size()) + " has shape " + shapeText(array) + ", must be " +
                              expectedShape(rows, *leaf.space) + " (one row per environment)");
      }
      const double* data = array.data();
      for (std::size_t i = 0; i < rows; ++i) {
        values_[i * leaves_.size() + l]->numbers.assign(data + i * leaf.elements, data + (i + 1) * leaf.elements);
      }
    }
    checkNoOtherKeys(actions, *space_, "actions");
    if (rows == actions_.size()) return actions_;
    some_.assign(actions_.begin(), actions_.begin() + static_cast<std::ptrdiff_t>(rows));
    return some_;
  }

 private:
  // (rows,) + the leaf's shape; a leaf of one number may also come as (rows,).
  static bool shapeFits(const py::array& array, std::size_t rows, const rl::Space& space) {
    if (array.ndim() == 1 && space.elements() == 1) return static_cast<std::size_t>(array.shape(0)) == rows;
    if (static_cast<std::size_t>(array.ndim()) != space.shape.size() + 1) return false;
    if (static_cast<std::size_t>(array.shape(0)) != rows) return false;
    for (std::size_t d = 0; d < space.shape.size(); ++d) {
      if (array.shape(static_cast<py::ssize_t>(d + 1)) != space.shape[d]) return false;
    }
    return true;
  }
  static std::string shapeText(const py::array& array) {
    if (!array) return "(not an array of numbers)";
    std::string text = "(";
    for (py::ssize_t d = 0; d < array.ndim(); ++d) text += (d ? ", " : "") + std::to_string(array.shape(d));
    return text + (array.ndim() == 1 ? ",)" : ")");
  }
  static std::string expectedShape(std::size_t rows, const rl::Space& space) {
    std::string text = "(" + std::to_string(rows);
    for (int d : space.shape) text += ", " + std::to_string(d);
    return text + (space.shape.empty() ? ",)" : ")");
  }
  // A key the space does not have is a typo (a misspelt 'steer' would otherwise go unread).
  static void checkNoOtherKeys(const py::handle& actions, const rl::Space& space, const std::string& where) {
    if (space.kind != rl::Space::Kind::kDict || !PyDict_Check(actions.ptr())) return;
    const py::dict given = py::reinterpret_borrow<py::dict>(actions);
    if (static_cast<std::size_t>(given.size()) == space.keys.size()) {
      for (std::size_t i = 0; i < space.keys.size(); ++i) {
        if (space.entries[i].kind == rl::Space::Kind::kDict)
          checkNoOtherKeys(given[py::str(space.keys[i])], space.entries[i], where + "['" + space.keys[i] + "']");
      }
      return;
    }
    for (const auto& item : given) {
      const std::string key = py::str(item.first);
      if (std::find(space.keys.begin(), space.keys.end(), key) != space.keys.end()) continue;
      const std::string near = config::nearestKey(key, space.keys);
      std::string keys;
      for (const auto& k : space.keys) keys += (keys.empty() ? "" : ", ") + k;
      throw py::key_error(where + " has no entry '" + key + "'" +
                          (near.empty() ? "" : " (did you mean '" + near + "'?)") + "; its entries: " + keys);
    }
  }

  // actions['a']['b'], the leaf's first `depth` keys.
  static std::string entryName(const Leaf& leaf, std::size_t depth) {
    std::string where = "actions";
    for (std::size_t k = 0; k < depth; ++k) where += "['" + leaf.path[k] + "']";
    return where;
  }

  const rl::Space* space_;  // the environment's, which outlives this
  std::vector<Leaf> leaves_;
  std::vector<std::vector<py::str>> keys_;  // per leaf, its path as Python strings
  std::vector<rl::Value> actions_, some_;
  std::vector<rl::Value*> values_;  // env-major, one per action leaf
};

}  // namespace roar::python
