// The race modes and decisions in words.
#include "roar/planning/overtaking/decision.h"

namespace roar::planning {

const char* raceModeName(RaceMode mode) {
  switch (mode) {
    case RaceMode::kRacingLine:
      return "racing_line";
    case RaceMode::kFollow:
      return "follow";
    case RaceMode::kPass:
      return "pass";
    case RaceMode::kHold:
      return "hold";
    case RaceMode::kYield:
      return "yield";
    case RaceMode::kDefend:
      return "defend";
  }
  return "unknown";
}

std::string describe(const RaceDecision& d) {
  if (d.mode == RaceMode::kRacingLine) return "racing line";
  std::string text = raceModeName(d.mode);
  if (!d.other.empty()) {
    const bool towards = d.mode == RaceMode::kYield;
    const bool against = d.mode == RaceMode::kDefend;
    text += towards ? " to " : against ? " against " : (d.mode == RaceMode::kHold ? " beside " : " ");
    text += d.other;
  }
  if (d.side != 0 && d.mode != RaceMode::kFollow && d.mode != RaceMode::kHold) {
    text += d.side > 0 ? " on the left" : " on the right";
  }
  return text;
}

}  // namespace roar::planning
