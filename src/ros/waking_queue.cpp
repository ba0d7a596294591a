#include "roar/ros/waking_queue.h"

#include <boost/make_shared.hpp>

namespace roar::ros_bridge {
namespace {

// Does nothing when called: its arrival in the other queue ends that queue's wait.
class Wake : public ros::CallbackInterface {
 public:
  CallResult call() override { return Success; }
};

}  // namespace

void WakingCallbackQueue::addCallback(const ros::CallbackInterfacePtr& callback, uint64_t removal_id) {
  ros::CallbackQueue::addCallback(callback, removal_id);
  wakes_->addCallback(boost::make_shared<Wake>());
}

}  // namespace roar::ros_bridge
