#include "roar/ros/unread_answers.h"

#include <boost/make_shared.hpp>
#include <cstdio>
#include <functional>

namespace roar::ros_bridge {
namespace {

class CountingHelper : public ros::ServiceCallbackHelper {
 public:
  CountingHelper(ros::ServiceCallbackHelperPtr inner, std::function<void(std::ptrdiff_t)> count)
      : inner_(std::move(inner)), count_(std::move(count)) {}

  bool call(ros::ServiceCallbackHelperCallParams& params) override {
    const bool ok = inner_->call(params);
    const boost::shared_array<uint8_t> buffer = params.response.buf;
    const std::ptrdiff_t size = static_cast<std::ptrdiff_t>(params.response.num_bytes);
    if (!buffer) return ok;
    count_(size);
    // The same bytes under a handle whose last copy (roscpp's, once written or dropped) uncounts them.
    const auto count = count_;
    params.response.buf = boost::shared_array<uint8_t>(buffer.get(), [buffer, count, size](uint8_t*) { count(-size); });
    return ok;
  }

 private:
  ros::ServiceCallbackHelperPtr inner_;
  std::function<void(std::ptrdiff_t)> count_;
};

}  // namespace

ros::ServiceCallbackHelperPtr UnreadAnswers::counting(ros::ServiceCallbackHelperPtr helper) const {
  const std::shared_ptr<State> state = state_;
  return boost::make_shared<CountingHelper>(std::move(helper), [state](std::ptrdiff_t size) {
    state->bytes += static_cast<std::size_t>(size);  // wraps back on the matching negative
    if (size > 0) {
      ++state->answers;
    } else {
      --state->answers;
    }
  });
}

std::string UnreadAnswers::describe() const {
  char text[160];
  std::snprintf(text, sizeof text, "%zu answers of %.1f MB in all are unread by their callers (at most %.1f MB)",
                answers(), bytes() / 1e6, budget_ / 1e6);
  return text;
}

}  // namespace roar::ros_bridge
