#pragma once
#include <ros/callback_queue.h>

namespace roar::ros_bridge {

// A callback queue whose arrivals also wake whoever waits on another queue: roar_sim waits on its topics'
// queue and answers its services' queue as soon as a request arrives, not at the next poll
// (sim_node_test ServiceRequestsWakeTheTopicsWait; bench/roar_py_bench.py measures the step's round trip).
class WakingCallbackQueue : public ros::CallbackQueue {
 public:
  explicit WakingCallbackQueue(ros::CallbackQueueInterface* wakes) : wakes_(wakes) {}
  void addCallback(const ros::CallbackInterfacePtr& callback, uint64_t removal_id = 0) override;

 private:
  ros::CallbackQueueInterface* wakes_;
};

}  // namespace roar::ros_bridge
