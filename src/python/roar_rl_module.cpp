// roar_rl_core: the C++ vectorised racing environment (rl::VectorEnv) for Python. Observations and infos
// come back as NumPy arrays with a leading environment axis, written in place into buffers this object
// owns (a Dict observation is a dict of batched arrays); actions go in the same way. The GIL is released
// while the environments step. The Python side (python/roar_rl) adds Gymnasium's vector API and spaces.
// The conversions are rl_conversions.h's; this file registers the environments and the policy calls.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "rl_conversions.h"
#include "roar/rl/async_vector_env.h"
#include "roar/rl/env_options.h"
#include "roar/rl/policy.h"
#include "roar/rl/policy_laps.h"
#include "roar/rl/racing_env.h"
#include "roar/rl/vector_env.h"
#include "roar/track/map_folder.h"
#include "roar/vehicle/vehicle_config.h"

namespace py = pybind11;
using namespace roar;
using namespace roar::python;

namespace {

std::vector<std::unique_ptr<rl::RacingEnv>> makeEnvs(const std::string& map_folder, const std::string& options_path,
                                                     const std::string& model, const std::string& urdf_dir,
                                                     const std::string& vehicle_dir, int num_envs, int num_threads) {
  if (num_envs < 1 || num_envs > 4096)
    throw py::value_error("num_envs must be in [1, 4096], got " + std::to_string(num_envs));
  if (num_threads < 1 || num_threads > 1024)
    throw py::value_error("num_threads must be in [1, 1024], got " + std::to_string(num_threads));
  const track::Track track = track::loadMapFolder(map_folder);
  const vehicle::VehicleParams car = vehicle::loadVehicleModel(model, urdf_dir, vehicle_dir);
  const rl::EnvOptions options = rl::readEnvOptions(options_path);
  std::vector<std::unique_ptr<rl::RacingEnv>> envs;
  for (int i = 0; i < num_envs; ++i) envs.push_back(std::make_unique<rl::RacingEnv>(track, car, options));
  return envs;
}

class PyVectorEnv {
 public:
  PyVectorEnv(const std::string& map_folder, const std::string& options_path, const std::string& model,
              const std::string& urdf_dir, const std::string& vehicle_dir, int num_envs, int num_threads) {
    env_ = std::make_unique<rl::VectorEnv>(
        makeEnvs(map_folder, options_path, model, urdf_dir, vehicle_dir, num_envs, num_threads), num_threads);
    const std::size_t n = env_->size();
    out_ = std::make_unique<StepBuffers>(env_->observationSpace(), n);
    actions_ = std::make_unique<BatchedActions>(env_->actionSpace(), n);
  }

  std::size_t numEnvs() const { return env_->size(); }
  py::dict actionSpace() const { return describe(env_->actionSpace()); }
  py::dict observationSpace() const { return describe(env_->observationSpace()); }

  py::tuple reset(std::uint64_t seed) {
    const auto one_caller = caller_.enter("reset");
    std::vector<rl::ResetResult> results;
    {
      py::gil_scoped_release released;
      results = env_->reset(seed);
    }
    for (std::size_t i = 0; i < results.size(); ++i) {
      out_->observations->write(i, results[i].observation);
      out_->infos->write(i, results[i].info);
    }
    return py::make_tuple(out_->observations->view, out_->infos->view);
  }

  py::tuple step(const py::object& actions) {
    const auto one_caller = caller_.enter("step");
    const std::size_t n = env_->size();
    const std::vector<rl::Value>& values = actions_->read(actions, n);
    // VectorEnv::step checks every action first (naming actions[i] and the field) and steps nothing then.
    {
      // Each result is copied into its NumPy rows by the thread that stepped it, not one by one after.
      py::gil_scoped_release released;
      env_->step(values, [this](std::size_t i, const rl::StepResult& r, const std::optional<rl::Value>& ended) {
        out_->write(i, r, ended);
      });
    }
    return out_->views();
  }

 private:
  std::unique_ptr<rl::VectorEnv> env_;
  OneCaller caller_;
  std::unique_ptr<StepBuffers> out_;
  std::unique_ptr<BatchedActions> actions_;
};

// EnvPool's asynchronous batching (rl::AsyncVectorEnv): send() actions to chosen environments, recv()
// the first batch_size done, in buffers of batch_size rows with the environments' ids. Each result is
// copied into its rows by the thread that stepped it (AsyncVectorEnv's sink: its number says which batch
// and row), not one after another in the caller's thread after recv(). Batches go round a ring of buffers,
// one more than the batches the environments can fill at once, so results done while Python still reads a
// batch (its environments sent again already) go to other buffers: a batch's arrays stay as they are until
// the next recv().
class PyAsyncVectorEnv {
 public:
  PyAsyncVectorEnv(const std::string& map_folder, const std::string& options_path, const std::string& model,
                   const std::string& urdf_dir, const std::string& vehicle_dir, int num_envs, int num_threads,
                   int batch_size) {
    if (batch_size < 1 || batch_size > num_envs) {
      throw py::value_error("batch_size must be in [1, num_envs = " + std::to_string(num_envs) + "], got " +
                            std::to_string(batch_size));
    }
    env_ = std::make_unique<rl::AsyncVectorEnv>(
        makeEnvs(map_folder, options_path, model, urdf_dir, vehicle_dir, num_envs, num_threads), num_threads);
    batch_ = static_cast<std::size_t>(batch_size);
    const std::size_t n = env_->size();
    for (std::size_t k = 0; k < (n + batch_ - 1) / batch_ + 1; ++k) {
      ring_.push_back(std::make_unique<StepBuffers>(env_->observationSpace(), batch_));
      env_ids_.emplace_back(static_cast<py::ssize_t>(batch_));
      env_id_data_.push_back(env_ids_.back().mutable_data());
    }
    first_observations_ = std::make_unique<Batch>(env_->observationSpace(), n);
    first_infos_ = std::make_unique<Infos>(n);
    actions_ = std::make_unique<BatchedActions>(env_->actionSpace(), n);
  }

  // The pool's threads first: they finish the jobs queued, and the sink writes into the ring.
  ~PyAsyncVectorEnv() {
    py::gil_scoped_release released;
    env_.reset();
  }
  PyAsyncVectorEnv(const PyAsyncVectorEnv&) = delete;
  PyAsyncVectorEnv& operator=(const PyAsyncVectorEnv&) = delete;

  std::size_t numEnvs() const { return env_->size(); }
  std::size_t batchSize() const { return batch_; }
  py::dict actionSpace() const { return describe(env_->actionSpace()); }
  py::dict observationSpace() const { return describe(env_->observationSpace()); }

  // Every environment reset (environment i with seed + i): their first observations and infos, by id.
  py::tuple reset(std::uint64_t seed) {
    const auto one_caller = caller_.enter("reset");
    std::vector<std::size_t> ids;
    {
      py::gil_scoped_release released;
      while (env_->inFlight() > 0) env_->recv(env_->inFlight());  // results nobody asked for: dropped
      env_->setResultSink(nullptr);
      env_->reset(seed);
      ids = env_->recv(env_->size());
      // From here on, results fill batches of batch_ in the order they are done.
      first_number_ = env_->received();
      env_->setResultSink([this](std::size_t number, const rl::AsyncResult& r) {
        const std::size_t k = number - first_number_;
        const std::size_t buffer = (k / batch_) % ring_.size(), row = k % batch_;
        ring_[buffer]->write(row, r.step, r.final_observation);
        env_id_data_[buffer][row] = static_cast<std::int64_t>(r.env_id);
      });
    }
    for (const std::size_t id : ids) {
      first_observations_->write(id, env_->result(id).step.observation);
      first_infos_->write(id, env_->result(id).step.info);
    }
    return py::make_tuple(first_observations_->view, first_infos_->view);
  }

  void send(const py::object& actions, const py::object& env_ids) {
    const auto one_caller = caller_.enter("send");
    const auto ids = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(env_ids);
    if (!ids || ids.ndim() != 1) throw py::value_error("env_ids must be a 1-d array of environment ids");
    std::vector<std::size_t> list;
    for (py::ssize_t k = 0; k < ids.size(); ++k) {
      if (ids.data()[k] < 0) throw py::value_error("env_ids[" + std::to_string(k) + "] is negative");
      list.push_back(static_cast<std::size_t>(ids.data()[k]));
    }
    const std::vector<rl::Value>& values = actions_->read(actions, list.size());
    py::gil_scoped_release released;
    env_->send(values, list);
  }

  py::tuple recv() {
    const auto one_caller = caller_.enter("recv");
    std::size_t buffer = 0;
    {
      py::gil_scoped_release released;
      buffer = ((env_->received() - first_number_) / batch_) % ring_.size();
      env_->recv(batch_);  // its rows are written: the sink ran for each result before recv() could return it
    }
    const StepBuffers& out = *ring_[buffer];
    return py::make_tuple(out.observations->view, out.rewards, out.terminations, out.truncations, out.infos->view,
                          out.final_observations->view, out.final_mask, env_ids_[buffer]);
  }

 private:
  std::unique_ptr<rl::AsyncVectorEnv> env_;
  OneCaller caller_;
  std::size_t batch_ = 1;
  std::size_t first_number_ = 0;  // the number of the first result of the first batch since reset()
  std::vector<std::unique_ptr<StepBuffers>> ring_;
  std::vector<py::array_t<std::int64_t>> env_ids_;
  std::vector<std::int64_t*> env_id_data_;
  std::unique_ptr<Batch> first_observations_;
  std::unique_ptr<Infos> first_infos_;
  std::unique_ptr<BatchedActions> actions_;
};

// The policy file format of rl_train and policy_driver (MlpPolicy): its input normalisation for the
// observation of an options file, and a file written from trained weights.
py::tuple mlpNormalisation(const std::string& options_path, const std::vector<int>& hidden) {
  const rl::MlpPolicy policy(rl::readEnvOptions(options_path).observation, hidden);
  rl::MlpPolicy copy = policy;
  return py::make_tuple(copy.mean(), copy.spread(), copy.params().size());
}

void writeMlpPolicy(const std::string& path, const std::string& options_path, const std::vector<int>& hidden,
                    const std::vector<float>& params) {
  rl::MlpPolicy policy(rl::readEnvOptions(options_path).observation, hidden);
  if (params.size() != policy.params().size()) {
    throw py::value_error("params: the policy has " + std::to_string(policy.params().size()) + " parameters, got " +
                          std::to_string(params.size()));
  }
  policy.params() = params;
  policy.save(path);
}

std::array<float, 2> mlpPolicyOutputs(const std::string& path, const std::vector<float>& flat_observation) {
  return rl::MlpPolicy::load(path).outputs(flat_observation);
}

// A policy file's laps from the pole position of a map (rl::driveLaps), in the environment of `options_path`
// observed as the policy observes.
py::dict policyLaps(const std::string& policy_path, const std::string& map_folder, const std::string& options_path,
                    const std::string& model, const std::string& urdf_dir, const std::string& vehicle_dir, int laps,
                    double time_limit) {
  if (laps < 1 || laps > 100) throw py::value_error("laps must be 1 to 100, got " + std::to_string(laps));
  if (!(time_limit > 0.0 && time_limit <= 36000.0))
    throw py::value_error("time_limit must be in (0, 36000] s, got " + std::to_string(time_limit));
  const rl::MlpPolicy policy = rl::MlpPolicy::load(policy_path);
  const track::Track track = track::loadMapFolder(map_folder);
  const vehicle::VehicleParams car = vehicle::loadVehicleModel(model, urdf_dir, vehicle_dir);
  const rl::EnvOptions options = rl::lapEnvironment(rl::readEnvOptions(options_path), policy, time_limit);
  rl::PolicyLaps run;
  {
    py::gil_scoped_release unlocked;
    rl::RacingEnv env(track, car, options);
    run = rl::driveLaps(env, policy, laps);
  }
  py::dict d;
  d["lap_times"] = run.laps;
  d["best_lap"] = run.laps.empty() ? py::object(py::none()) : py::cast(run.best());
  d["clean"] = run.clean;
  d["ended"] = run.ended;
  d["progress"] = run.progress;
  d["sim_time"] = run.sim_time;
  return d;
}

}  // namespace

PYBIND11_MODULE(roar_rl_core, m) {
  m.doc() = "roar_rl's C++ vectorised racing environment (use roar_rl.VectorEnv)";
  py::register_exception<rl::SpaceError>(m, "SpaceError", PyExc_ValueError);
  py::register_exception<rl::PolicyError>(m, "PolicyError", PyExc_ValueError);
  m.def("mlp_normalisation", &mlpNormalisation, py::arg("options_path"), py::arg("hidden"),
        "(mean, spread, parameter count) of an MlpPolicy observing as the options file says");
  m.def("write_mlp_policy", &writeMlpPolicy, py::arg("path"), py::arg("options_path"), py::arg("hidden"),
        py::arg("params"), "writes a policy file (rl_train's format, what policy_driver drives with)");
  m.def("mlp_policy_outputs", &mlpPolicyOutputs, py::arg("path"), py::arg("flat_observation"),
        "{steer, pedal} of a policy file for a flattened observation, as policy_driver computes them");
  m.def("policy_laps", &policyLaps, py::arg("policy_path"), py::arg("map_folder"), py::arg("options_path"),
        py::arg("model"), py::arg("urdf_dir"), py::arg("vehicle_dir"), py::arg("laps") = 2,
        py::arg("time_limit") = 600.0,
        "A policy file's laps from the pole position, judged as race control judges a car (rl_train's test): a dict "
        "of lap_times, best_lap (None without a lap), clean, ended (laps done, collision, off track, stalled, wrong "
        "way, time limit), progress (m), sim_time (s)");
  py::class_<PyVectorEnv>(m, "VectorEnv")
      .def(py::init<const std::string&, const std::string&, const std::string&, const std::string&, const std::string&,
                    int, int>(),
           py::arg("map_folder"), py::arg("options_path"), py::arg("model"), py::arg("urdf_dir"),
           py::arg("vehicle_dir"), py::arg("num_envs"), py::arg("num_threads"))
      .def_property_readonly("num_envs", &PyVectorEnv::numEnvs)
      .def("action_space", &PyVectorEnv::actionSpace)
      .def("observation_space", &PyVectorEnv::observationSpace)
      .def("reset", &PyVectorEnv::reset, py::arg("seed"))
      .def("step", &PyVectorEnv::step, py::arg("actions"));
  py::class_<PyAsyncVectorEnv>(m, "AsyncVectorEnv")
      .def(py::init<const std::string&, const std::string&, const std::string&, const std::string&, const std::string&,
                    int, int, int>(),
           py::arg("map_folder"), py::arg("options_path"), py::arg("model"), py::arg("urdf_dir"),
           py::arg("vehicle_dir"), py::arg("num_envs"), py::arg("num_threads"), py::arg("batch_size"))
      .def_property_readonly("num_envs", &PyAsyncVectorEnv::numEnvs)
      .def_property_readonly("batch_size", &PyAsyncVectorEnv::batchSize)
      .def("action_space", &PyAsyncVectorEnv::actionSpace)
      .def("observation_space", &PyAsyncVectorEnv::observationSpace)
      .def("reset", &PyAsyncVectorEnv::reset, py::arg("seed"))
      .def("send", &PyAsyncVectorEnv::send, py::arg("actions"), py::arg("env_ids"))
      .def("recv", &PyAsyncVectorEnv::recv);
}
