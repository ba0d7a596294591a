// roar_bench --traffic --batch: the table's races as one batch on Dask (python3 -m roar_batch, kind traffic),
// read back from the batch's results.json.
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "roar/planning/overtaking/option_table.h"
#include "traffic_table.h"

extern char** environ;

namespace roar::bench {

namespace {

namespace fs = std::filesystem;

std::string number(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

// The overtaking options that differ from the planner's defaults, by name (the batch's cells carry only
// those, as roar_batch's matrices do).
std::vector<std::pair<std::string, std::string>> changedOptions(const planning::OvertakeOptions& options) {
  planning::OvertakeOptions set = options, plain;
  const auto mine = planning::overtakeOptionTable(&set), defaults = planning::overtakeOptionTable(&plain);
  std::vector<std::pair<std::string, std::string>> out;
  for (std::size_t i = 0; i < mine.size(); ++i) {
    std::visit(
        [&](auto* field) {
          const auto* other = std::get<std::remove_reference_t<decltype(field)>>(defaults[i].field);
          if (*field != *other) out.emplace_back(mine[i].name, number(static_cast<double>(*field)));
        },
        mine[i].field);
  }
  return out;
}

std::string matrixText(const std::vector<TrafficRace>& races, const TrafficTableOptions& table) {
  std::vector<std::string> maps, fields;
  int seeds = 0;
  for (const auto& r : races) {
    if (std::find(maps.begin(), maps.end(), r.map) == maps.end()) maps.push_back(r.map);
    if (std::find(fields.begin(), fields.end(), r.field) == fields.end()) fields.push_back(r.field);
    seeds = std::max(seeds, r.seed + 1);
  }
  auto list = [](const std::vector<std::string>& v) {
    std::string out = "[";
    for (const auto& s : v) out += (out.size() > 1 ? ", \"" : "\"") + s + "\"";
    return out + "]";
  };
  std::string text = "name: roar_bench_traffic\nkind: traffic\nmaps: " + list(maps) + "\nfields: " + list(fields) +
                     "\nseeds: " + std::to_string(seeds) + "\nlaps: " + std::to_string(table.laps) +
                     "\npace_step: " + number(table.pace_step) + "\n";
  const auto changed = changedOptions(table.overtake);
  if (!changed.empty()) {
    text += "overtake:\n";
    for (const auto& [name, value] : changed) text += "  " + name + ": " + value + "\n";
  }
  return text;
}

// The compiled roar_core beside this program (devel/lib/roar_ros/roar_bench: devel/lib/python3/dist-packages)
// and the source tree's Python packages, for the batch's client and its embedded workers.
std::string pythonPath() {
  const fs::path exe = fs::read_symlink("/proc/self/exe");
  std::string path = (fs::path(ROAR_SOURCE_DIR) / "python").string() + ":" +
                     (exe.parent_path().parent_path() / "python3" / "dist-packages").string();
  if (const char* old = std::getenv("PYTHONPATH"); old && *old) path += std::string(":") + old;
  return path;
}

// Runs python3 -m roar_batch, its own output on stderr (the table is stdout's); its exit status.
int runBatch(const fs::path& matrix, const fs::path& out, const TrafficTableOptions::Batch& batch) {
  std::vector<std::string> args = {"/usr/bin/python3", "-m",           "roar_batch", matrix.string(), "--out",
                                   out.string(),       "--no-progress"};
  if (!batch.scheduler.empty()) {
    args.insert(args.end(), {"--scheduler", batch.scheduler});
  } else if (batch.workers > 0) {
    args.insert(args.end(), {"--workers", std::to_string(batch.workers)});
  }
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::vector<std::string> env_text = {"PYTHONPATH=" + pythonPath()};
  for (char** e = environ; *e; ++e) {
    if (std::string(*e).rfind("PYTHONPATH=", 0) != 0) env_text.emplace_back(*e);
  }
  std::vector<char*> envp;
  for (auto& e : env_text) envp.push_back(e.data());
  envp.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, STDERR_FILENO, STDOUT_FILENO);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) throw std::runtime_error("could not start /usr/bin/python3 -m roar_batch");
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

harness::TrafficTotals totalsOf(const YAML::Node& row) {
  harness::TrafficTotals t;
  std::array<int, 12> won{};
  for (auto& [name, figure] : harness::trafficFigures(&t, &won)) {
    const YAML::Node value = row[name];
    if (!value) throw std::runtime_error("a batch row has no '" + name + "'");
    std::visit(
        [&](auto* field) {
          using Field = std::remove_reference_t<decltype(*field)>;
          *field = value.as<Field>();
        },
        figure);
  }
  harness::setWon(&t, won);
  return t;
}

}  // namespace

std::vector<harness::TrafficTotals> raceAsBatch(const std::vector<TrafficRace>& races,
                                                const TrafficTableOptions& table) {
  if (races.empty()) return {};
  char folder_template[] = "/tmp/roar_bench_traffic_XXXXXX";
  const char* made = mkdtemp(folder_template);
  if (!made) throw std::runtime_error("could not make a folder for the batch in /tmp");
  const fs::path folder(made);
  struct Remove {
    fs::path path;
    ~Remove() {
      std::error_code ignored;
      fs::remove_all(path, ignored);
    }
  } remove{folder};
  std::ofstream(folder / "traffic.yaml") << matrixText(races, table);
  const int status = runBatch(folder / "traffic.yaml", folder / "out", table.batch);
  if (status != 0) throw std::runtime_error("the batch ended with status " + std::to_string(status));
  const YAML::Node rows = YAML::LoadFile((folder / "out" / "results.json").string());
  std::map<std::tuple<std::string, std::string, int>, harness::TrafficTotals> by_race;
  for (const auto& row : rows) {
    const YAML::Node cell = row["cell"];
    const auto key =
        std::make_tuple(cell["map"].as<std::string>(), cell["field"].as<std::string>(), cell["seed"].as<int>());
    if (row["status"].as<std::string>() != "done") {
      throw std::runtime_error(std::get<0>(key) + " " + std::get<1>(key) + " seed " + std::to_string(std::get<2>(key)) +
                               ": " + row["error"].as<std::string>());
    }
    by_race[key] = totalsOf(row);
  }
  std::vector<harness::TrafficTotals> out;
  for (const auto& r : races) {
    const auto it = by_race.find({r.map, r.field, r.seed});
    if (it == by_race.end()) throw std::runtime_error("the batch has no row for " + r.map + " " + r.field);
    out.push_back(it->second);
  }
  return out;
}

}  // namespace roar::bench
