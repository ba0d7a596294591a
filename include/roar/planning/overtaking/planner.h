#pragma once
// Wheel-to-wheel racing on the racing line. Each tick a car's window ahead is chosen among candidate
// trajectories that leave the racing line sideways (a smooth lateral shift inside the road) or stay on
// it, each with the speed profile of its own path and the car's limits. Every other car is predicted
// along the racing line (overtaking/prediction.cpp); a candidate is kept only while the predicted gap to
// every car alongside or ahead stays above the cars' size plus a margin over the horizon. Which candidate
// is taken is the race modes' state machine (overtaking/transitions.cpp: one named transition each); a
// guard under every plan follows a car ahead in its path (overtaking/guard.cpp).
//
// A plan goes in stages: gather the car's surroundings and predict the cars in them; let a lapping car
// by or defend if that is called for; generate the candidates (one file per manoeuvre under
// src/planning/overtaking/); choose by the state machine; guard and commit.
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "roar/planning/overtaking/decision.h"
#include "roar/planning/overtaking/options.h"
#include "roar/planning/trajectory.h"
#include "roar/planning/vehicle_limits.h"
#include "roar/track/track.h"

namespace roar::planning {

class OvertakePlanner {
 public:
  // line: the closed racing trajectory every car follows; track: its road (for the edges).
  OvertakePlanner(const track::Track& track, Trajectory line, const VehicleLimits& limits, OvertakeOptions options);

  // The window (behind .. ahead metres around s) for `car` at (s, lateral, speed) on the racing line,
  // with the others of `traffic` (the car itself may be in it; it is skipped by name), driven at `pace`
  // (the share of the line's speeds the car is planned at).
  Trajectory plan(const std::string& car, double s, double lateral, double speed,
                  const std::vector<TrafficCar>& traffic, double behind, double ahead, double pace = 1.0);
  // What the last plan for `car` chose.
  RaceDecision decision(const std::string& car) const;
  // What the last plan for `car` predicted of the cars near it (alongside or ahead in its window); empty
  // unless OvertakeOptions::prediction.keep.
  std::vector<PredictedPath> predictions(const std::string& car) const;
  const Trajectory& line() const { return line_; }

  // Room from the racing line to the left and right road edges at line s (m, both positive when inside).
  double roomLeft(double s) const;
  double roomRight(double s) const;
  // The share of the lap from which a lane runs beside a car on the racing line, on the side `side`
  // (+1 left, -1 right), for at least `run` metres on: room for a passer (its width and air from the
  // car, its edge margin from the road's edge), where it could stay alongside that far. A pass gaining a
  // fraction f of its speed on the car needs about 2 (car length + longitudinal margin) / f metres.
  double laneShare(int side, double run) const;
  // Metres on from line s (up to `longest`) over which a pass under way has room beside a car `beside`
  // metres towards the side `side` of the racing line (its lateral place times side).
  double laneRun(int side, double s, double beside, double longest) const;

  // A move of the racing line's window sideways: `from` metres left of the line before line s `ramp_s`,
  // `to` a shift_length after, a smooth step between (clamped inside the road), undone again from window s
  // `back_s` (infinite: never).
  struct Move {
    double ramp_s = 0.0;
    double from = 0.0;
    double to = 0.0;
    double back_s = std::numeric_limits<double>::infinity();
    // m/s the car had at ramp_s: the move is made in shift_time at that speed where it is below the racing
    // line's there (0: at the line's).
    double ramp_speed = 0.0;
    // Planned as a pass is, more cautiously (the edge margin kept at apexes, the curvature of the moved
    // points differenced); otherwise exactly, and a path moved by nothing is the racing line.
    bool pass = false;
    static Move of(const RaceDecision& decision);  // the decision's move under way
  };
  // What a moved window's speeds are planned on.
  struct MoveGrip {
    double drag_share = 1.0;  // of the free-air drag (below 1: in a car's slipstream)
    // Up to this line s the path is planned on settle_grip wherever it is (a car still moving sideways from
    // a move it has just made).
    double settle_s = -std::numeric_limits<double>::infinity();
  };
  // The window moved as `move` goes, its speeds planned afresh for the new path.
  Trajectory shifted(const Trajectory& window, const Move& move, const MoveGrip& grip) const;
  Trajectory shifted(const Trajectory& window, const Move& move) const { return shifted(window, move, MoveGrip()); }

 private:
  struct Candidate {
    Trajectory window;
    RaceDecision decision;
    bool clear = true;
  };
  // Another car's predicted motion over the horizon: metres ahead of the planning car's s every
  // kPredictionStep seconds, and its lateral place (from its own last plan where that is trusted).
  struct Prediction {
    std::vector<double> ahead;
    double lateral = 0.0;
    double lateral_speed = 0.0;        // m/s, kept for lateral_lookahead when it has no plan to go by
    const Trajectory* plan = nullptr;  // its last window, if it is one of ours
    double s = 0.0;                    // its line s now
    double at(double t) const;
  };
  // What the planner remembers of a car from one plan to the next. Each fact has one writer: decision and
  // plan commit() (decide() alone on the line), predictions predictAll(), abort_* decide() (engagement()
  // counts down), doubts and headway_* continuePass() (decide() clears headway_* when no pass is on), hold
  // decide(), settle_until settle(), yield letByCandidate(), defended_against and defence_plans
  // defenceCandidate().
  struct CarMemory {
    RaceDecision decision;                   // the last plan's
    std::optional<Trajectory> plan;          // its last window (none: on the racing line alone)
    std::vector<PredictedPath> predictions;  // its last plan's view of the others (prediction.keep)
    std::string abort_other;                 // the car a pass on was given up, and for how many plans more
    int abort_plans_left = 0;
    int doubts = 0;                      // plans in a row a committed pass has looked blocked
    std::optional<double> hold;          // the lateral place (m) held while another car is alongside
    std::optional<double> settle_until;  // line s up to which a car moving sideways is planned on settle_grip
    std::string headway_other;           // the car a pass is on, the nearest it came (m) and the time since
    double headway_best_gap = 0.0;       // it last came a metre nearer (s)
    double headway_stalled = 0.0;
    std::optional<std::pair<std::string, int>> yield;  // the car being let by, and the side moved to
    std::string defended_against;                      // no second defensive move while that car is near
    int defence_plans = 0;                             // plans a defensive move has been held
  };
  struct PlanContext;  // src/planning/overtaking/plan_context.h

  // m, centre to centre, within which two cars are level (a car's length and the longitudinal margin).
  double levelDistance() const { return options_.car.length + options_.margins.longitudinal; }
  // m of road a lane beside a car on the racing line needs from the line to the edge.
  double laneNeed(double margin_share) const;
  // The window moved as a decision's move goes, planned as any move but a pass is, in free air.
  Trajectory shifted(const Trajectory& window, const RaceDecision& move,
                     double settle_s = -std::numeric_limits<double>::infinity()) const;
  // ---- the pieces of a move (overtaking/paths.cpp) ----
  // m of line a move takes from the one side to the other.
  double shiftLength(const Move& move) const;
  // (lowest, highest) m left of the line a pass may run at line s: the edge margin from either edge.
  std::pair<double, double> passBounds(double s) const;
  // Moves the window's points as `move` goes; returns each point's offset from the racing line.
  std::vector<double> moveWindow(Trajectory* window, Move move) const;
  // A moved window's speeds, accelerations and lap time for its offsets `d`, steps and curvatures.
  void planMovedSpeeds(Trajectory* window, const std::vector<double>& d, const std::vector<double>& step,
                       const std::vector<double>& curvature, const MoveGrip& grip) const;
  // The window's speeds as a car in a slipstream (drag_share of its drag) can drive them.
  Trajectory towed(const Trajectory& window, double drag_share) const;

  // ---- prediction (overtaking/prediction.cpp) ----
  Prediction predict(const TrafficCar& other, double s0) const;
  double lateralAt(const Prediction& p, double t) const;
  double plannedLateral(const TrafficCar& car, double s) const;
  const Trajectory* trustedPlan(const TrafficCar& car) const;
  double plannedLateral(const Trajectory* plan, double now, double s) const;
  using MotionVisitor = std::function<bool(std::size_t, double, double, double)>;
  double driveAlong(const Trajectory& plan, double s0, double v0, const MotionVisitor& visit) const;
  bool clearOf(const Trajectory& plan, double s0, double v0, const std::vector<Prediction>& others, double* progress,
               double margin_share = 1.0, double within = std::numeric_limits<double>::infinity()) const;
  double passCompleteAt(const Trajectory& plan, double s0, double v0, const Prediction& leader) const;
  bool drawsAlongside(const Trajectory& plan, double s0, double v0, const Prediction& leader) const;

  // ---- the stages of a plan (overtaking/planner.cpp) ----
  PlanContext gather(const std::string& car, double s, double lateral, double speed,
                     const std::vector<TrafficCar>& traffic, double behind, double ahead, double pace);
  void settle(PlanContext& ctx) const;
  void surroundings(PlanContext& ctx) const;
  void predictAll(PlanContext& ctx);
  void engagement(PlanContext& ctx) const;
  void place(PlanContext& ctx) const;
  Trajectory commit(PlanContext& ctx, Trajectory window, const RaceDecision& decision, bool clear_pass = false);

  // ---- the candidates, one file each under overtaking/ ----
  RaceDecision move(const PlanContext& ctx, RaceMode mode, int side, const std::string& other, double to) const;
  Candidate considerMove(const PlanContext& ctx, const RaceDecision& d) const;          // racing_line.cpp
  void racingLineCandidate(const PlanContext& ctx, std::vector<Candidate>* out) const;  // racing_line.cpp
  void holdCandidate(const PlanContext& ctx, std::vector<Candidate>* out) const;        // hold.cpp
  void passCandidates(const PlanContext& ctx, std::vector<Candidate>* out) const;       // pass.cpp
  Candidate considerPass(const PlanContext& ctx, const RaceDecision& d) const;          // pass.cpp
  Candidate followCandidate(const PlanContext& ctx) const;                              // follow.cpp
  std::optional<Candidate> letByCandidate(PlanContext& ctx);                            // let_by.cpp
  std::optional<Candidate> defenceCandidate(PlanContext& ctx);                          // defend.cpp

  // ---- the race modes' transitions (overtaking/transitions.cpp) ----
  const Candidate* continuePass(PlanContext& ctx, const std::vector<Candidate>& candidates,
                                const Candidate& follow) const;
  const Candidate* chooseFreely(const PlanContext& ctx, const std::vector<Candidate>& candidates,
                                const Candidate& follow) const;
  Trajectory decide(PlanContext& ctx);

  // ---- the guard under every plan (overtaking/guard.cpp) ----
  void guard(Trajectory* window, double s, double speed, const std::vector<TrafficCar>& others,
             const std::vector<Prediction>& predicted, bool clear_pass = false) const;

  Trajectory line_;
  VehicleLimits limits_;
  OvertakeOptions options_;
  std::vector<double> room_s_, room_left_, room_right_;
  std::map<std::string, CarMemory> memory_;
};

}  // namespace roar::planning
