#pragma once
// Who was at fault when two cars touched, by where and how they met: a car that runs into the back of
// another is at fault; of two cars alongside, the one that moved sideways into the other is; when neither
// did (or both did alike) it is a racing incident with nobody at fault.
#include <Eigen/Core>
#include <string>

#include "roar/vehicle/car_size.h"

namespace roar::race {

struct CarAtContact {
  std::string name;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  // m, map frame (the same point of every car: base_link)
  double yaw = 0.0;                                    // rad
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();  // m/s, map frame
};

struct ContactFault {
  std::string at_fault;  // the car at fault; empty: a racing incident
  std::string kind;      // "from behind" or "alongside"
};

struct ContactFaultOptions {
  double car_length = vehicle::kDefaultCarLength;  // m
  double alongside_overlap = 0.5;                  // share of a car's length the two must overlap by to be alongside
  double sideways_margin = 0.3;  // m/s more sideways speed towards the other that makes one car the mover
};

// road_heading: the road's direction where they touched (rad): "sideways" is across it, so a car that
// follows the road's bend is not taken for one that moves over.
ContactFault attributeContact(const CarAtContact& a, const CarAtContact& b, double road_heading,
                              const ContactFaultOptions& options = {});

}  // namespace roar::race
