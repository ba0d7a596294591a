#pragma once
// The fixed frame the world is published in: the default of roar_sim's ~map_frame, the planner's ~frame
// and waypoint_server's ~frame_id, and the frame of race_control's markers.
namespace roar::ros_bridge {

inline constexpr char kMapFrame[] = "map";

}  // namespace roar::ros_bridge
