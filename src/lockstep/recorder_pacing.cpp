#include "roar/lockstep/recorder_pacing.h"

#include <algorithm>

namespace roar::lockstep {

RecorderPacing::RecorderPacing(const std::vector<std::string>& recorders, double tick, double timeout)
    : tick_(tick), timeout_(timeout) {
  for (const auto& name : recorders) recorders_.push_back({name});
}

RecorderPacing::Recorder* RecorderPacing::find(const std::string& name) {
  for (auto& r : recorders_) {
    if (r.name == name) return &r;
  }
  return nullptr;
}

const RecorderPacing::Recorder* RecorderPacing::find(const std::string& name) const {
  return const_cast<RecorderPacing*>(this)->find(name);
}

bool RecorderPacing::recorded(const std::string& recorder, double sim_time, double wall_now) {
  Recorder* r = find(recorder);
  if (!r) return false;
  r->recorded = std::max(r->recorded, sim_time);
  r->heard_wall = wall_now;
  const bool back = r->given_up;
  r->given_up = false;
  return back;
}

void RecorderPacing::gone(const std::string& recorder) {
  if (Recorder* r = find(recorder)) r->given_up = true;
}

std::string RecorderPacing::waitingFor(double next_time, double wall_now, std::vector<std::string>* given_up) {
  // The tick at next_time may go out once the clock kRecorderMaxLag ticks before it is written (half a
  // tick of slack: clocks are multiples of the tick, reported through doubles).
  const double needed = next_time - (kRecorderMaxLag + 0.5) * tick_;
  if (needed < 0.0) return "";  // the first ticks: no clock before them to have been written
  for (auto& r : recorders_) {
    if (r.given_up || r.recorded >= needed) continue;
    if (r.heard_wall < 0.0) r.heard_wall = wall_now;
    if (wall_now - r.heard_wall > timeout_) {
      r.given_up = true;
      if (given_up) given_up->push_back(r.name);
      continue;
    }
    return r.name;
  }
  return "";
}

bool RecorderPacing::givenUp(const std::string& recorder) const {
  const Recorder* r = find(recorder);
  return r && r->given_up;
}

double RecorderPacing::lastRecorded(const std::string& recorder) const {
  const Recorder* r = find(recorder);
  return r ? r->recorded : -std::numeric_limits<double>::infinity();
}

}  // namespace roar::lockstep
