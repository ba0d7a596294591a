#pragma once
// The overtaking planner's fixed tuning, named in one place: what is not an option because no race asks
// to change it (roar_bench --traffic measured each).
#include <limits>

namespace roar::planning::tuning {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

// ---- paths ----
inline constexpr double kSteadyOffsetSlope = 0.005;  // m across per m along: a path holding its offset under this
inline constexpr double kMarginBend = 0.3;           // m: a pass path bends onto a road margin over about 2 x this
inline constexpr double kMinSpan = 1.0;              // m a path's derivatives are taken over at least
inline constexpr double kLaneStep = 1.0;             // m between the points laneShare checks
inline constexpr double kMoveAir = 0.3;  // m beyond a car's width and air a lateral move is sized and aimed for

// ---- prediction ----
inline constexpr double kPredictionStep = 0.1;       // s
inline constexpr double kShownPredictionStep = 0.5;  // s between the predicted positions kept for rviz
inline constexpr double kHeldSlack = 0.3;            // m/s a car held to a speed is predicted above it (its wobble)
inline constexpr double kTooSoonToChange = 0.3;      // s from now within which a conflict changes nothing

// ---- moves ----
inline constexpr double kSettledLateralSpeed = 0.5;  // m/s sideways across the line a car is settled under
inline constexpr double kSettleTime = 2.0;           // s at speed it is planned on settle_grip after that
inline constexpr double kMoveBrakeSlack = 1.5;       // m/s a move's window may ask the car to shed at once
inline constexpr double kOnLine = 0.5;               // m from the racing line within which a car is on it
inline constexpr double kClosingDoor = 0.5;          // m/s across towards a pass's side: the door is closing
inline constexpr double kLeaderLane = 2.0;           // m beyond a car's width and air a car ahead is in the lane
inline constexpr double kSameTarget = 0.5;           // m a move's target may change and the move go on

// ---- passing ----
inline constexpr double kPassedLevelGap = 0.1;  // m taken as the gap to the car a pass is level with
inline constexpr double kLetByRate = 3.0;       // m/s below a car level beside it that a car lets it by at
inline constexpr double kMinEngageSpeed = 5.0;  // m/s the engage distance is reckoned at at least
inline constexpr double kPassStayFactor = 1.5;  // the engage distance a pass under way keeps its car within
inline constexpr double kPassClearAhead = 2.0;  // m beyond level a passer clears the car passed by
inline constexpr double kBetterBy = 0.5;        // m of progress a candidate must get more to be taken over another
inline constexpr double kMinTow = 0.01;         // share of the drag a tow must take away to be planned with

}  // namespace roar::planning::tuning
