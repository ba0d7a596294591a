// race_recorder: records a race to a bag through rosbag's C++ API without losing a message, and reports
// on ~recorded the simulated time of the last /clock it has written, so that roar_sim (its
// ~wait_for_recorders) never runs more than a few ticks ahead of it (lockstep/recorder_pacing.h). rosbag record
// cannot do this: its subscribers' queues hold 100 messages, and on a busy machine at 10x real time a
// recorder that falls half a second behind loses ticks.
//
//   rosrun roar_ros race_recorder _bag:=<file.bag> _topics:='<regex>'
//
// ~bag: the bag (its folder is created; written as <bag>.active and renamed when closed, as rosbag does);
// ~topics: the topics to record, a regular expression the whole name must match. Topics are subscribed to
// as they appear (the master is asked every ~poll_period wall seconds), with unbounded queues.
// ~thinned: topics (a regular expression) recorded at most once every ~thinned_period seconds of their
// messages' stamps (default 0.5 s): the planner's windows, 90% of a bag recorded every tick, are kept as
// samples. Empty (the default): every message of every topic.
// ~until_finished (false): the bag ends with the race: once /race_status says the race is finished, only
// what is stamped at or before the finish is still written (a car's odometry of the finishing tick may
// arrive after the status, on its own connection); progress is still reported, so that roar_sim does not
// wait for a recorder that is done.
#include <roar_ros/RaceStatus.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosgraph_msgs/Clock.h>
#include <topic_tools/shape_shifter.h>

#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <vector>

#include "roar/ros/param_reading.h"

using namespace roar;

namespace {

struct RecorderOptions {
  std::string bag;
  std::string topics;
  std::string thinned;
  double thinned_period = 0.5;
  double poll_period = 0.2;
  bool until_finished = false;
};

RecorderOptions readParameters(const ros::NodeHandle& pnh) {
  using namespace ros_bridge;
  RecorderOptions o;
  o.bag = readString(pnh, "bag", "");
  if (o.bag.empty()) throw ParamError(pnh.resolveName("bag") + ": the bag to write is not set");
  o.bag = std::filesystem::absolute(o.bag).lexically_normal().string();
  o.topics = readString(pnh, "topics", "");
  if (o.topics.empty()) throw ParamError(pnh.resolveName("topics") + ": no topics to record (a regular expression)");
  try {
    std::regex check(o.topics);
  } catch (const std::regex_error& e) {
    throw ParamError(pnh.resolveName("topics") + ": '" + o.topics + "' is not a regular expression: " + e.what());
  }
  o.thinned = readString(pnh, "thinned", "");
  try {
    std::regex check(o.thinned);
  } catch (const std::regex_error& e) {
    throw ParamError(pnh.resolveName("thinned") + ": '" + o.thinned + "' is not a regular expression: " + e.what());
  }
  o.thinned_period = readDouble(pnh, "thinned_period", o.thinned_period, 0.0, 3600.0);
  o.poll_period = readDouble(pnh, "poll_period", o.poll_period, 0.01, 10.0);
  o.until_finished = readBool(pnh, "until_finished", o.until_finished);
  return o;
}

// The first field of a message definition (its own, before the types it uses): comments and blank lines
// skipped, spaces trimmed.
std::string firstField(const std::string& definition) {
  std::size_t from = 0;
  while (from < definition.size()) {
    std::size_t to = definition.find('\n', from);
    if (to == std::string::npos) to = definition.size();
    std::string line = definition.substr(from, to - from);
    line = line.substr(0, line.find('#'));
    const auto first = line.find_first_not_of(" \t\r"), last = line.find_last_not_of(" \t\r");
    if (first != std::string::npos) return line.substr(first, last - first + 1);
    from = to + 1;
  }
  return "";
}

// The simulated time a message is of, read from its serialized bytes where its type puts it: a Header
// first (odometry, joint states, statuses, controls, trajectories: after its seq), a /tf message's first
// transform's header (after the array's length and the seq), a /clock's own time. None for anything else.
std::optional<ros::Time> stampOf(const topic_tools::ShapeShifter& message) {
  const std::string& type = message.getDataType();
  const std::string& definition = message.getMessageDefinition();
  std::size_t at;
  if (type == "rosgraph_msgs/Clock") {
    at = 0;
  } else if (type == "tf2_msgs/TFMessage") {
    at = 8;
  } else if (const std::string field = firstField(definition);
             field == "Header header" || field == "std_msgs/Header header") {
    at = 4;
  } else {
    return std::nullopt;
  }
  std::vector<std::uint8_t> bytes(message.size());
  if (bytes.size() < at + 8) return std::nullopt;
  ros::serialization::OStream out(bytes.data(), static_cast<std::uint32_t>(bytes.size()));
  message.write(out);
  std::uint32_t sec = 0, nsec = 0;
  std::memcpy(&sec, bytes.data() + at, 4);
  std::memcpy(&nsec, bytes.data() + at + 4, 4);
  return ros::Time(sec, nsec);
}

class RaceRecorder {
 public:
  RaceRecorder(ros::NodeHandle nh, ros::NodeHandle pnh, RecorderOptions options)
      : nh_(nh),
        options_(std::move(options)),
        pattern_(options_.topics),
        thinned_(options_.thinned),
        active_(options_.bag + ".active") {
    std::filesystem::create_directories(std::filesystem::path(options_.bag).parent_path());
    bag_.open(active_, rosbag::bagmode::Write);
    // Latched: a subscriber that connects late still hears how far the recording has got.
    recorded_pub_ = pnh.advertise<rosgraph_msgs::Clock>("recorded", 10, true);
    poll_ = nh_.createWallTimer(ros::WallDuration(options_.poll_period),
                                [this](const ros::WallTimerEvent&) { subscribeNew(); });
    subscribeNew();
  }

  // Writes what is still arriving after a stop was asked for: the finishing tick's controls may be in flight
  // when roslaunch ends the race (test_a_recorded_race_stays_lean). Returns once nothing has come for
  // kQuiet, or after kMostDrain.
  void drain() {
    constexpr double kQuiet = 0.3, kMostDrain = 2.0;  // s of wall time
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(kMostDrain);
    last_message_ = ros::WallTime::now();
    while (ros::WallTime::now() < deadline && (ros::WallTime::now() - last_message_).toSec() < kQuiet) {
      ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(0.02));
    }
  }

  // Closes the bag and gives it its name; says what it holds.
  void close() {
    bag_.close();
    std::filesystem::rename(active_, options_.bag);
    std::size_t total = 0;
    for (const auto& [topic, count] : counts_) total += count;
    std::printf("race_recorder: %zu messages on %zu topics in %s\n", total, counts_.size(), options_.bag.c_str());
    std::fflush(stdout);
  }

 private:
  void subscribeNew() {
    ros::master::V_TopicInfo topics;
    if (!ros::master::getTopics(topics)) return;
    for (const auto& info : topics) {
      if (subscribers_.count(info.name) || !std::regex_match(info.name, pattern_)) continue;
      const std::string topic = info.name;
      ros::SubscribeOptions ops;
      ops.topic = topic;
      ops.queue_size = 0;  // unbounded: roar_sim's pacing, not a dropped message, bounds what waits here
      ops.md5sum = ros::message_traits::md5sum<topic_tools::ShapeShifter>();
      ops.datatype = ros::message_traits::datatype<topic_tools::ShapeShifter>();
      ops.transport_hints = ros::TransportHints().tcpNoDelay();
      ops.helper = boost::make_shared<
          ros::SubscriptionCallbackHelperT<const ros::MessageEvent<const topic_tools::ShapeShifter>&>>(
          [this, topic](const ros::MessageEvent<const topic_tools::ShapeShifter>& event) { write(topic, event); });
      subscribers_[topic] = nh_.subscribe(ops);
    }
  }

  void write(const std::string& topic, const ros::MessageEvent<const topic_tools::ShapeShifter>& event) {
    // Stamped with wall time, as rosbag record does: the recorded /clock carries the simulated time.
    const ros::WallTime wall = ros::WallTime::now();
    last_message_ = wall;
    const auto& message = event.getConstMessage();
    if ((!finished_ || stampedBy(*message, finish_)) && keptSample(topic, *message)) {
      bag_.write(topic, ros::Time(wall.sec, wall.nsec), *message, event.getConnectionHeaderPtr());
      ++counts_[topic];
    }
    if (topic == "/clock" && message->getDataType() == "rosgraph_msgs/Clock")
      recorded_pub_.publish(message->instantiate<rosgraph_msgs::Clock>());
    if (options_.until_finished && !finished_ && topic == "/race_status" &&
        message->getDataType() == "roar_ros/RaceStatus") {
      const auto status = message->instantiate<roar_ros::RaceStatus>();
      if (!status->finished) return;
      finished_ = true;
      finish_ = status->header.stamp;
      ROS_INFO("race_recorder: the race is finished: %s ends here", options_.bag.c_str());
    }
  }

  // A thinned topic's message is kept when its stamp is ~thinned_period after the last kept one.
  bool keptSample(const std::string& topic, const topic_tools::ShapeShifter& message) {
    if (options_.thinned.empty() || !std::regex_match(topic, thinned_)) return true;
    const auto stamp = stampOf(message);
    if (!stamp) return true;
    auto last = last_kept_.find(topic);
    if (last != last_kept_.end() && (*stamp - last->second).toSec() < options_.thinned_period) return false;
    last_kept_[topic] = *stamp;
    return true;
  }

  ros::NodeHandle nh_;
  RecorderOptions options_;
  std::regex pattern_, thinned_;
  std::map<std::string, ros::Time> last_kept_;
  std::string active_;
  rosbag::Bag bag_;
  ros::Publisher recorded_pub_;
  ros::WallTimer poll_;
  std::map<std::string, ros::Subscriber> subscribers_;
  std::map<std::string, std::size_t> counts_;
  bool finished_ = false;
  ros::Time finish_;  // the stamp of the /race_status that said so
  ros::WallTime last_message_;

  static bool stampedBy(const topic_tools::ShapeShifter& message, const ros::Time& finish) {
    const auto stamp = stampOf(message);
    return stamp && *stamp <= finish;
  }
};

}  // namespace

// SIGTERM as SIGINT: what is in flight is still written, then the bag is closed and named (a bag left
// .active is unindexed). The node stays up meanwhile, so its subscriptions keep delivering.
volatile std::sig_atomic_t g_stop_requested = 0;
void requestStop(int) { g_stop_requested = 1; }

int main(int argc, char** argv) {
  ros::init(argc, argv, "race_recorder", ros::init_options::NoSigintHandler);
  std::signal(SIGINT, requestStop);
  std::signal(SIGTERM, requestStop);
  ros::NodeHandle nh, pnh("~");
  try {
    RaceRecorder recorder(nh, pnh, readParameters(pnh));
    ros_bridge::refuseUnknownParameters(pnh);
    while (!g_stop_requested && ros::ok()) ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(0.05));
    recorder.drain();
    recorder.close();
    ros::shutdown();
  } catch (const std::exception& e) {
    ROS_FATAL("race_recorder: %s", e.what());
    return 1;
  }
  return 0;
}
