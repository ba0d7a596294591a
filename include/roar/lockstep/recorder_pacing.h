#pragma once
// How far the simulation may run ahead of the nodes recording it. A recorder reports the simulated time
// of the last /clock it has written; a tick goes out only while every recorder has written the clock of
// kRecorderMaxLag ticks before it, so that no more than that many ticks are ever on their way to a
// recorder and no publisher's or subscriber's queue (10 messages and more) can overflow on a busy
// machine. A recorder that reports nothing for `timeout` wall seconds while the simulation waits for it
// is given up (the recording misses ticks from then; the caller warns) until it reports again.
#include <limits>
#include <string>
#include <vector>

namespace roar::lockstep {

// Ticks a recorder may be behind: below the smallest queue (10) of any recorded topic.
constexpr int kRecorderMaxLag = 4;

class RecorderPacing {
 public:
  // recorders: the names the reports come under; tick: s of simulated time a tick; timeout: wall s.
  RecorderPacing(const std::vector<std::string>& recorders, double tick, double timeout);

  // A recorder has written the clock of simulated time `sim_time` (wall time `wall_now`). Returns true when
  // it had been given up and is recording again.
  bool recorded(const std::string& recorder, double sim_time, double wall_now);
  // A recorder has gone (its node died): not waited for from now until it reports again.
  void gone(const std::string& recorder);
  // The recorder a tick at simulated time `next_time` still waits for ("": none, the tick may go out).
  // Recorders silent for `timeout` since they were last heard of or first waited for are given up and
  // added to `given_up`.
  std::string waitingFor(double next_time, double wall_now, std::vector<std::string>* given_up);
  bool givenUp(const std::string& recorder) const;
  // The simulated time of the last clock the recorder wrote (-infinity: none yet).
  double lastRecorded(const std::string& recorder) const;

 private:
  struct Recorder {
    std::string name;
    double recorded = -std::numeric_limits<double>::infinity();  // s simulated
    double heard_wall = -1.0;  // wall s of its last report, or of the first wait for it
    bool given_up = false;
  };
  Recorder* find(const std::string& name);
  const Recorder* find(const std::string& name) const;

  std::vector<Recorder> recorders_;
  double tick_;
  double timeout_;
};

}  // namespace roar::lockstep
