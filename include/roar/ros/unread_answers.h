#pragma once
// The bytes of service answers that roscpp holds because their callers have not read them yet (a caller
// that never reads keeps its answer in the server's memory until it disconnects). A node counts them by
// advertising its services through counting(), and refuses work while overBudget(), so unread answers hold
// at most about the budget (unread_answers_test; test_roar_py_ros
// test_unread_camera_frames_hold_a_bounded_memory_in_roar_sim).
#include <ros/service_callback_helper.h>

#include <atomic>
#include <cstddef>
#include <memory>
#include <string>

namespace roar::ros_bridge {

class UnreadAnswers {
 public:
  explicit UnreadAnswers(std::size_t budget_bytes) : budget_(budget_bytes) {}
  // A helper that answers as `helper` does and counts each answer's bytes until roscpp lets go of them
  // (written to the socket, or the connection dropped).
  ros::ServiceCallbackHelperPtr counting(ros::ServiceCallbackHelperPtr helper) const;
  std::size_t bytes() const { return state_->bytes.load(); }
  std::size_t answers() const { return state_->answers.load(); }
  bool overBudget() const { return bytes() > budget_; }
  std::size_t budget() const { return budget_; }
  // "3 answers of 75.2 MB in all are unread by their callers (at most 64.0 MB)": for a refusal.
  std::string describe() const;

 private:
  struct State {
    std::atomic<std::size_t> bytes{0}, answers{0};
  };
  std::shared_ptr<State> state_ = std::make_shared<State>();
  std::size_t budget_;
};

}  // namespace roar::ros_bridge
