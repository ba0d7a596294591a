// The lockstep protocol whole, ROS-free: a simulator (DriverRoll, RecorderPacing), a planner
// (TickGathering) and each car's controller (WindowPairing) exchange odometry, windows, controls and a
// recorder's progress through a network that delays every message by a random time, as a loaded machine
// does. Whatever the delays, each car's control of tick t is driven with the window planned from every
// car's odometry of t, the recorder is never more than kRecorderMaxLag ticks behind, and the race's
// answers are the same run after run; a driver that stops answering is waited for once, then lost, and
// waited for again when it answers.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "roar/lockstep/driver_roll.h"
#include "roar/lockstep/recorder_pacing.h"
#include "roar/lockstep/tick_gathering.h"
#include "roar/lockstep/window_pairing.h"

using namespace roar::lockstep;

namespace {

constexpr double kDt = 0.05;              // s simulated a tick
constexpr double kLockstepTimeout = 1.0;  // wall s the simulator waits for controls
constexpr double kTickWait = 0.25;        // wall s the planner waits for a tick's odometry
constexpr double kWindowWait = 0.5;       // wall s a controller waits for its window
constexpr double kRecorderTimeout = 5.0;  // wall s before a silent recorder is given up
const std::string kRecorder = "/recorder";

double stampOf(int tick) { return tick * kDt; }

struct Message {
  enum Kind { kOdometryToPlanner, kOdometryToController, kWindow, kControl, kRecorded } kind;
  std::string car;
  double stamp = 0.0;  // the odometry's, the window's (planned from), the control's (answered), the clock's
  double window = -1;  // a control's: the window it was driven with
};

struct Answer {
  double odometry, window;
  bool operator==(const Answer& o) const { return odometry == o.odometry && window == o.window; }
};

class LockstepRace {
 public:
  LockstepRace(const std::vector<std::string>& cars, unsigned seed, int max_delay_ms)
      : cars_(cars),
        random_(seed),
        delay_(0, max_delay_ms),
        planner_(cars, kTickWait),
        pacing_({kRecorder}, kDt, kRecorderTimeout) {
    for (const auto& car : cars) {
      drivers_.add(car);
      controllers_.emplace(car, Controller{WindowPairing(kWindowWait)});
    }
  }

  // Runs until the simulator has ticked `ticks` times; `kill` stops a car's driver from one wall time to
  // another (its publisher stays registered, as a killed process's can).
  void run(int ticks, const std::string& kill = "", double kill_from = 0.0, double kill_until = 0.0) {
    killed_ = kill;
    kill_from_ = kill_from;
    kill_until_ = kill_until;
    // From the first tick: a window stamped 0 is an unstamped one (WindowPairing), so time 0 plans nothing.
    tick_ = 1;
    publishTick();
    for (now_ms_ = 0; tick_ < ticks && now_ms_ < 600000; ++now_ms_) {
      deliver();
      for (const auto& t : planner_.expire(wall())) plan(t);
      for (auto& [car, c] : controllers_) {
        if (alive(car) && c.held && c.pairing.waitedTooLong(wall())) answer(car, true);
      }
      stepSimulator();
    }
  }

  std::map<std::string, std::vector<Answer>> answers;  // per car, the simulator's view of its controls
  std::vector<std::size_t> cars_per_planned_tick;
  std::vector<std::string> lost, back;
  int most_recorder_lag = 0;
  int tick_ = 0;  // the simulator's, its time stampOf(tick_)

 private:
  struct Controller {
    WindowPairing pairing;
    bool held = false;
    double held_stamp = 0.0;
    double window = -1.0;
  };

  double wall() const { return now_ms_ * 1e-3; }
  bool alive(const std::string& car) const { return car != killed_ || wall() < kill_from_ || wall() >= kill_until_; }

  void send(Message m) { network_.emplace(now_ms_ + delay_(random_), std::move(m)); }

  void publishTick() {
    for (const auto& car : cars_) {
      send({Message::kOdometryToPlanner, car, stampOf(tick_)});
      send({Message::kOdometryToController, car, stampOf(tick_)});
    }
    send({Message::kRecorded, "", stampOf(tick_)});  // the recorder writes the clock and reports it
    waiting_since_ = wall();
  }

  void deliver() {
    while (!network_.empty() && network_.begin()->first <= now_ms_) {
      const Message m = network_.begin()->second;
      network_.erase(network_.begin());
      switch (m.kind) {
        case Message::kOdometryToPlanner:
          for (const auto& t : planner_.arrive(m.car, m.stamp, wall())) plan(t);
          break;
        case Message::kOdometryToController: {
          if (!alive(m.car)) break;
          Controller& c = controllers_.at(m.car);
          c.held_stamp = m.stamp;
          c.held = true;
          if (c.pairing.onOdometry(m.stamp, wall())) answer(m.car, false);
          break;
        }
        case Message::kWindow: {
          if (!alive(m.car)) break;
          Controller& c = controllers_.at(m.car);
          c.window = m.stamp;
          if (c.pairing.onWindow(m.stamp) && c.held) answer(m.car, false);
          break;
        }
        case Message::kControl:
          answers[m.car].push_back({m.stamp, m.window});
          if (drivers_.control(m.car, m.stamp)) back.push_back(m.car);
          break;
        case Message::kRecorded:
          pacing_.recorded(kRecorder, m.stamp, wall());
          break;
      }
    }
  }

  void plan(const TickGathering::Tick& t) {
    cars_per_planned_tick.push_back(t.cars.size());
    for (const auto& car : t.cars) send({Message::kWindow, car, t.stamp});
  }

  void answer(const std::string& car, bool late) {
    Controller& c = controllers_.at(car);
    send({Message::kControl, car, c.held_stamp, c.window});
    late ? c.pairing.answeredLate() : c.pairing.answered();
    c.held = false;
  }

  void stepSimulator() {
    const bool timed_out = wall() - waiting_since_ > kLockstepTimeout;
    std::vector<std::string> given_up;
    if (!(drivers_.answered(stampOf(tick_)) || timed_out)) return;
    if (!pacing_.waitingFor(stampOf(tick_ + 1), wall(), &given_up).empty()) return;
    if (timed_out) {
      for (const auto& car : drivers_.silent(stampOf(tick_))) {
        drivers_.lose(car);
        lost.push_back(car);
      }
    }
    ++tick_;
    const double recorded = pacing_.lastRecorded(kRecorder);
    if (recorded > -1.0)
      most_recorder_lag = std::max(most_recorder_lag, tick_ - static_cast<int>(recorded / kDt + 0.5));
    publishTick();
  }

  std::vector<std::string> cars_;
  std::mt19937 random_;
  std::uniform_int_distribution<int> delay_;
  std::multimap<int, Message> network_;  // by the wall ms it arrives; equal times in the order sent
  long now_ms_ = 0;
  double waiting_since_ = 0.0;
  DriverRoll drivers_{[](const std::string&) { return true; }};
  TickGathering planner_;
  std::map<std::string, Controller> controllers_;
  RecorderPacing pacing_;
  std::string killed_;
  double kill_from_ = 0.0, kill_until_ = 0.0;
};

void expectEveryControlPaired(const std::vector<std::string>& cars, unsigned seed) {
  LockstepRace race(cars, seed, 60);
  race.run(200);
  ASSERT_EQ(race.tick_, 200);
  EXPECT_TRUE(race.lost.empty());
  for (std::size_t n : race.cars_per_planned_tick) ASSERT_EQ(n, cars.size()) << "a tick planned without every car";
  for (const auto& car : cars) {
    const auto& a = race.answers[car];
    ASSERT_GE(a.size(), 199u) << car;
    for (std::size_t i = 0; i < a.size(); ++i) {
      ASSERT_EQ(a[i].window, a[i].odometry) << car << "'s control " << i << " drove another tick's window";
      ASSERT_EQ(a[i].odometry, stampOf(static_cast<int>(i) + 1)) << car << " skipped a tick";
    }
  }
  EXPECT_LE(race.most_recorder_lag, kRecorderMaxLag);
  EXPECT_GT(race.most_recorder_lag, 0) << "the recorder never lagged: the pacing was not tried";
}

}  // namespace

TEST(Lockstep, EveryControlIsDrivenWithTheWindowOfItsOwnTickWhateverTheDelays) {
  const std::vector<std::string> cars = {"ego", "rival", "third"};
  for (unsigned seed = 1; seed <= 8; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    expectEveryControlPaired(cars, seed);
  }
}

TEST(Lockstep, TheRaceIsTheSameRunAfterRunHoweverLateTheMessagesCome) {
  const std::vector<std::string> cars = {"ego", "rival"};
  LockstepRace quick(cars, 7, 5);
  quick.run(120);
  EXPECT_TRUE(quick.lost.empty());
  for (unsigned seed = 8; seed < 12; ++seed) {
    LockstepRace slow(cars, seed, 200);
    slow.run(120);
    EXPECT_EQ(quick.answers, slow.answers) << "seed " << seed;
    EXPECT_TRUE(slow.lost.empty()) << "seed " << seed;
  }
}

TEST(Lockstep, ADriverThatStopsIsWaitedForOnceThenLostAndWaitedForAgainWhenItAnswers) {
  const std::vector<std::string> cars = {"ego", "rival"};
  LockstepRace race(cars, 3, 30);
  race.run(400, "rival", 2.0, 6.0);
  ASSERT_EQ(race.tick_, 400) << "a dead driver stalled the race";
  EXPECT_EQ(race.lost, std::vector<std::string>{"rival"}) << "lost once, after one wait";
  EXPECT_EQ(race.back, std::vector<std::string>{"rival"});
  for (const auto& a : race.answers["ego"]) ASSERT_EQ(a.window, a.odometry) << "ego left lockstep";
  // Once back, the rival answers every tick again with its own tick's window.
  const auto& rival = race.answers["rival"];
  ASSERT_GT(rival.size(), 20u);
  for (std::size_t i = rival.size() - 20; i + 1 < rival.size(); ++i) {
    EXPECT_NEAR(rival[i + 1].odometry - rival[i].odometry, kDt, 1e-9);
    EXPECT_EQ(rival[i].window, rival[i].odometry);
  }
}
