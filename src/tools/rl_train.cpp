// rl_train: learns to drive a circuit from scratch with evolution strategies on the racing environment,
// on every core it is given, within a time budget. Every few generations the policy drives from the pole
// position for two laps; the fastest clean lap so far is kept. Writes to the output folder:
//   policy.yaml          the policy of the fastest clean lap (or, without one, the last), for policy_driver
//   learning_curve.png   the candidates' mean and best return by generation (20-generation averages)
//   lap_times.png        the clean laps from the grid by generation, against the planner/controller stack's
//   learning_curve.csv   every generation's numbers
// and compares the laps with the planner/controller stack's on the same circuit (raced first).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>

#include "roar/config/number.h"
#include "roar/config/package_layout.h"
#include "roar/harness/time_trial.h"
#include "roar/race/race_control.h"
#include "roar/report/race_report.h"
#include "roar/rl/evolution.h"
#include "roar/rl/policy_laps.h"
#include "roar/track/map_folder.h"
#include "roar/vehicle/vehicle_config.h"

using namespace roar;
namespace fs = std::filesystem;

namespace {

struct Args {
  std::string source = ROAR_SOURCE_DIR;
  std::string map = "roar_sprint";
  std::string env;  // default: <source>/config/rl/state.yaml
  std::string model = config::kDefaultModel;
  std::string out;
  double minutes = 15.0;
  int generations = 100000;
  int eval_every = 10;
  double episode_seconds = 40.0;
  bool compare = true;
  rl::EvolutionOptions es;
};

// On `out`; returns the exit status: 0 when asked for, 2 after a wrong command line.
int usage(std::ostream& out = std::cerr) {
  out << "usage: rl_train [--map NAME] [--env FILE.yaml] [--model NAME] [--out DIR] [--minutes M]\n"
         "                [--generations N] [--threads N] [--seed N] [--directions N] [--sigma S]\n"
         "                [--learning-rate R] [--hidden N[,N...]] [--episodes N] [--episode-seconds S]\n"
         "                [--eval-every N] [--no-compare]\n"
         "  Trains a policy for MAP (default roar_sprint) within M minutes (default 15) of wall time.\n";
  return &out == &std::cout ? 0 : 2;
}

std::vector<int> parseHidden(const std::string& text) {
  std::vector<int> sizes;
  std::size_t at = 0;
  while (at < text.size()) {
    const std::size_t comma = text.find(',', at);
    sizes.push_back(static_cast<int>(roar::config::wholeNumberArgument("--hidden", text.substr(at, comma - at), 1)));
    at = comma == std::string::npos ? text.size() : comma + 1;
  }
  return sizes;
}

std::optional<Args> parse(int argc, char** argv) {
  Args a;
  if (const char* env = std::getenv("ROAR_SOURCE_DIR")) a.source = env;
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if (flag == "--no-compare") {
      a.compare = false;
      continue;
    }
    if (i + 1 >= argc) return std::nullopt;
    const std::string v = argv[++i];
    if (flag == "--map")
      a.map = v;
    else if (flag == "--env")
      a.env = v;
    else if (flag == "--model")
      a.model = v;
    else if (flag == "--out")
      a.out = v;
    else if (flag == "--minutes")
      a.minutes = roar::config::numberArgument(flag, v);
    else if (flag == "--generations")
      a.generations = static_cast<int>(roar::config::wholeNumberArgument(flag, v, 0));
    else if (flag == "--threads")
      a.es.threads = static_cast<int>(roar::config::wholeNumberArgument(flag, v, 1));
    else if (flag == "--seed")
      a.es.seed = static_cast<std::uint64_t>(roar::config::wholeNumberArgument(flag, v, 0, 1LL << 53));
    else if (flag == "--directions")
      a.es.directions = static_cast<int>(roar::config::wholeNumberArgument(flag, v, 1));
    else if (flag == "--sigma")
      a.es.sigma = roar::config::numberArgument(flag, v);
    else if (flag == "--learning-rate")
      a.es.learning_rate = roar::config::numberArgument(flag, v);
    else if (flag == "--hidden")
      a.es.hidden = parseHidden(v);
    else if (flag == "--episodes")
      a.es.episodes = static_cast<int>(roar::config::wholeNumberArgument(flag, v, 1));
    else if (flag == "--episode-seconds")
      a.episode_seconds = roar::config::numberArgument(flag, v);
    else if (flag == "--eval-every")
      a.eval_every = static_cast<int>(roar::config::wholeNumberArgument(flag, v, 1));
    else
      return std::nullopt;
  }
  if (a.env.empty()) a.env = config::PackageLayout{a.source}.rl() + "/state.yaml";
  if (a.out.empty()) {
    char stamp[32];
    const std::time_t now = std::time(nullptr);
    std::strftime(stamp, sizeof(stamp), "%Y%m%d_%H%M%S", std::localtime(&now));
    a.out = a.source + "/output/rl_" + a.map + "_" + stamp;
  }
  return a;
}

}  // namespace

int main(int argc, char** argv) {
  if (config::helpRequested(argc, argv)) return usage(std::cout);
  std::optional<Args> parsed;
  try {
    parsed = parse(argc, argv);
  } catch (const std::invalid_argument& e) {  // a value that is not a number: named, before anything runs
    std::fprintf(stderr, "rl_train: %s\n", e.what());
    return 2;
  }
  if (!parsed) return usage();
  const Args& args = *parsed;
  try {
    const config::PackageLayout layout{args.source};
    const track::Track track = track::loadMapFolder(track::resolveMapFolder(args.map, layout.maps()));
    const vehicle::VehicleParams car = vehicle::loadVehicleModel(args.model, layout.urdf(), layout.vehicles());
    rl::EnvOptions training = rl::readEnvOptions(args.env);
    training.termination.time_limit = args.episode_seconds;
    rl::EnvOptions laps = training;
    laps.spawn = rl::SpawnMode::kGrid;
    laps.termination.time_limit = 600.0;
    fs::create_directories(args.out);

    std::printf("rl_train: %s (%.0f m), env %s, %d thread(s), %.1f min, output %s\n", track.info().name.c_str(),
                track.length(), args.env.c_str(), args.es.threads, args.minutes, args.out.c_str());
    rl::EvolutionStrategy es([&] { return std::make_unique<rl::RacingEnv>(track, car, training); }, args.es);
    rl::RacingEnv lap_env(track, car, laps);
    std::printf("rl_train: %zu parameters, %d candidates per generation\n", es.policy().params().size(),
                2 * args.es.directions);

    std::ofstream csv(args.out + "/learning_curve.csv");
    csv << "generation,minutes,env_steps,mean_return,best_return,mean_progress_m,eval_progress_m,eval_best_lap_s,eval_"
           "clean\n";
    std::optional<harness::TimeTrialResult> stack_lap;
    if (args.compare) {
      harness::TimeTrialOptions trial;
      trial.laps = 1;
      stack_lap = harness::runTimeTrial(track, car, trial);
      std::printf("rl_train: the planner + controller stack laps %s in %.2f s (its profile promises %.2f s)\n",
                  track.info().name.c_str(), stack_lap->best_lap(), stack_lap->promised_lap);
    }
    std::vector<double> generations, mean_returns, best_returns;
    report::Series lap_curve{"learned policy, clean lap from the grid", {}, {}, {90, 220, 90}};
    std::optional<rl::MlpPolicy> best_policy;
    double best_lap = 0.0;
    std::int64_t steps = 0;
    const auto start = std::chrono::steady_clock::now();
    auto minutes = [&] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / 60.0;
    };
    while (es.generation() < args.generations && minutes() < args.minutes) {
      const rl::GenerationReport g = es.runGeneration();
      steps += g.env_steps;
      generations.push_back(g.generation);
      mean_returns.push_back(g.mean_return);
      best_returns.push_back(g.best_return);
      std::string eval_text;
      rl::PolicyLaps test;
      const bool evaluate = g.generation % args.eval_every == 0;
      if (evaluate) {
        test = rl::driveLaps(lap_env, es.policy(), 2);
        if (test.clean && !test.laps.empty()) {
          lap_curve.x.push_back(g.generation);
          lap_curve.y.push_back(test.best());
        }
        char text[160];
        std::snprintf(text, sizeof(text), "  grid: %.0f m, %zu lap(s)", test.progress, test.laps.size());
        eval_text = text;
        if (!test.laps.empty()) {
          std::snprintf(text, sizeof(text), ", best %.2f s", test.best());
          eval_text += text;
        }
        if (test.clean) eval_text += ", clean";
        if (test.clean && !test.laps.empty() && (best_lap == 0.0 || test.best() < best_lap)) {
          best_lap = test.best();
          best_policy = es.policy();
          best_policy->save(args.out + "/policy.yaml");
          eval_text += "  <- best clean lap, saved";
        }
      }
      csv << g.generation << "," << minutes() << "," << steps << "," << g.mean_return << "," << g.best_return << ","
          << g.mean_progress << "," << (evaluate ? std::to_string(test.progress) : "") << ","
          << (evaluate && !test.laps.empty() ? std::to_string(test.best()) : "") << ","
          << (evaluate ? (test.clean ? "1" : "0") : "") << "\n";
      csv.flush();
      std::printf("gen %4d  %5.1f min  %8.2fM steps  return mean %8.1f best %8.1f  progress %6.0f m%s\n", g.generation,
                  minutes(), steps / 1e6, g.mean_return, g.best_return, g.mean_progress, eval_text.c_str());
      std::fflush(stdout);
    }
    if (!best_policy) es.policy().save(args.out + "/policy.yaml");
    // Each generation meets other spawn points, so single returns jump about: plot running averages.
    auto averaged = [&](const std::vector<double>& y) {
      std::vector<double> out;
      double sum = 0.0;
      for (std::size_t i = 0; i < y.size(); ++i) {
        sum += y[i] - (i >= 20 ? y[i - 20] : 0.0);
        out.push_back(sum / static_cast<double>(std::min<std::size_t>(i + 1, 20)));
      }
      return out;
    };
    const std::string title = "ES on " + track.info().name + ": " + std::to_string(es.generation()) + " generations, " +
                              std::to_string(steps / 1000000) + "M steps, " +
                              std::to_string(static_cast<int>(minutes() + 0.5)) + " min";
    report::renderPlot(args.out + "/learning_curve.png", title, "generation", "return",
                       {{"best candidate (20-gen. average)", generations, averaged(best_returns), {90, 220, 90}},
                        {"mean of candidates (20-gen. average)", generations, averaged(mean_returns), {255, 170, 60}}});
    std::vector<report::Series> laps_plot = {lap_curve};
    if (stack_lap && !generations.empty()) {
      laps_plot.push_back({"planner + controller stack",
                           {generations.front(), generations.back()},
                           {stack_lap->best_lap(), stack_lap->best_lap()},
                           {80, 80, 255}});
    }
    report::renderPlot(args.out + "/lap_times.png", "Clean laps of " + track.info().name + " from the grid",
                       "generation", "lap time (s)", laps_plot);
    const double seconds = minutes() * 60.0;
    std::printf("rl_train: %d generations, %.1fM environment steps in %.0f s (%.0f steps/s)\n", es.generation(),
                steps / 1e6, seconds, steps / std::max(seconds, 1e-9));
    if (best_policy) {
      std::printf("rl_train: learned policy's best clean lap from the grid: %.2f s -> %s/policy.yaml\n", best_lap,
                  args.out.c_str());
    } else {
      std::printf("rl_train: no clean lap yet; the last policy is in %s/policy.yaml\n", args.out.c_str());
    }
    if (stack_lap && best_policy) {
      std::printf("rl_train: learned %.2f s against the stack's %.2f s: %.3f times the stack's lap\n", best_lap,
                  stack_lap->best_lap(), best_lap / stack_lap->best_lap());
    }
    std::printf("rl_train: learning curve %s/learning_curve.png, laps %s/lap_times.png\n", args.out.c_str(),
                args.out.c_str());
    return best_policy ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rl_train: %s\n", e.what());
    return 1;
  }
}
