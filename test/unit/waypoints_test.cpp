#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "roar/harness/time_trial.h"
#include "roar/sim/world.h"
#include "roar/track/circuit_builder.h"
#include "roar/track/map_folder.h"
#include "roar/track/npz.h"
#include "roar/track/waypoints.h"
#include "test_support.h"

using namespace roar;
using test::errorOf;
namespace fs = std::filesystem;

namespace {

struct TempDir {
  TempDir() : path(fs::temp_directory_path() / ("roar_wp_" + std::to_string(::getpid()) + "_" + std::to_string(n++))) {
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  std::string file(const std::string& name) const { return (path / name).string(); }
  static inline int n = 0;
  fs::path path;
};

std::vector<track::Waypoint> someWaypoints() {
  std::vector<track::Waypoint> w;
  for (int i = 0; i < 50; ++i) {
    track::Waypoint p;
    const double a = 2 * M_PI * i / 50;
    p.location = {100 * std::cos(a) + 0.123456789012, 100 * std::sin(a), 0.1 * i};
    p.roll_pitch_yaw = {0.0, -0.01, track::wrapAngle(a + M_PI / 2)};
    p.lane_width = 10 + 0.01 * i;
    w.push_back(p);
  }
  return w;
}

bool haveNumpy() { return std::system("/usr/bin/python3 -c 'import numpy' 2>/dev/null") == 0; }

}  // namespace

TEST(Waypoints, LineRepresentationLikeRoarPy) {
  track::Waypoint w;
  w.lane_width = 10;
  auto [left, right] = track::lineRepresentation(w);
  EXPECT_TRUE(left.isApprox(Eigen::Vector3d(0, 5, 0)));
  EXPECT_TRUE(right.isApprox(Eigen::Vector3d(0, -5, 0)));
  w.roll_pitch_yaw.z() = M_PI / 2;
  std::tie(left, right) = track::lineRepresentation(w);
  EXPECT_NEAR(left.x(), -5, 1e-12);
  const auto back = track::fromLineRepresentation(left, right);
  EXPECT_NEAR(back.roll_pitch_yaw.z(), M_PI / 2, 1e-12);
  EXPECT_NEAR(back.lane_width, 10, 1e-12);
  EXPECT_TRUE(back.location.isApprox(w.location));
}

TEST(Waypoints, InterpolationTakesTheShortWayRound) {
  track::Waypoint a, b;
  a.roll_pitch_yaw.z() = 3.1;
  b.roll_pitch_yaw.z() = -3.1;
  a.lane_width = 10;
  b.lane_width = 12;
  b.location = {2, 0, 0};
  const auto m = track::interpolate(a, b, 0.5);
  EXPECT_NEAR(std::abs(m.roll_pitch_yaw.z()), M_PI, 1e-9);
  EXPECT_NEAR(m.lane_width, 11, 1e-12);
  EXPECT_NEAR(m.location.x(), 1, 1e-12);
}

TEST(Waypoints, NpzRoundTripIsExact) {
  TempDir dir;
  const auto w = someWaypoints();
  track::writeRoarWaypoints(dir.file("w.npz"), w);
  const auto back = track::readRoarWaypoints(dir.file("w.npz"));
  ASSERT_EQ(back.size(), w.size());
  for (std::size_t i = 0; i < w.size(); ++i) {
    EXPECT_EQ(back[i].location, w[i].location);
    EXPECT_EQ(back[i].roll_pitch_yaw, w[i].roll_pitch_yaw);
    EXPECT_EQ(back[i].lane_width, w[i].lane_width);
  }
}

TEST(Waypoints, NumpyReadsOurFilesAndWeReadNumpys) {
  if (!haveNumpy()) GTEST_SKIP() << "Debian's python3-numpy is not installed (scripts/setup installs it)";
  TempDir dir;
  track::writeRoarWaypoints(dir.file("ours.npz"), someWaypoints());
  const std::string script = dir.file("check.py");
  std::ofstream(script) << "import numpy as np, sys\n"
                           "d = np.load(sys.argv[1])\n"
                           "assert d['locations'].shape == (50, 3) and d['lane_widths'].shape == (50,)\n"
                           "assert abs(d['locations'][0, 0] - 100.123456789012) < 1e-12\n"
                           "np.savez_compressed(sys.argv[2], locations=d['locations'] * 2, rotations=d['rotations'],"
                           " lane_widths=d['lane_widths'].astype(np.float32))\n";
  ASSERT_EQ(
      std::system(("/usr/bin/python3 " + script + " " + dir.file("ours.npz") + " " + dir.file("theirs.npz")).c_str()),
      0);
  const auto theirs = track::readRoarWaypoints(dir.file("theirs.npz"));
  ASSERT_EQ(theirs.size(), 50u);
  EXPECT_EQ(theirs[0].location.x(), 2 * 100.123456789012);
  EXPECT_NEAR(theirs[3].lane_width, 10.03, 1e-6) << "float32 widths are read too";
}

TEST(Waypoints, CsvToMapToNpzToMapKeepsTheWaypoints) {
  TempDir dir;
  const auto track = track::loadMapFolder(test::sourceDir() + "/maps/roar_ring");
  track::writeRoarWaypoints(dir.file("ring.npz"), track::waypointsOf(track));
  const auto again = track::trackFromWaypoints(track::readRoarWaypoints(dir.file("ring.npz")), track.info());
  ASSERT_EQ(again.size(), track.size());
  for (std::size_t i = 0; i < track.size(); ++i) {
    EXPECT_NEAR(again.point(i).x, track.point(i).x, 1e-9);
    EXPECT_NEAR(again.point(i).y, track.point(i).y, 1e-9);
    EXPECT_NEAR(again.point(i).width_left + again.point(i).width_right,
                track.point(i).width_left + track.point(i).width_right, 1e-9);
  }
}

TEST(Waypoints, MalformedNpzIsAClearError) {
  TempDir dir;
  const std::string good = dir.file("good.npz");
  track::writeRoarWaypoints(good, someWaypoints());
  // Truncated archive.
  const auto size = fs::file_size(good);
  fs::copy_file(good, dir.file("cut.npz"));
  fs::resize_file(dir.file("cut.npz"), size / 2);
  auto msg = errorOf([&] { track::readRoarWaypoints(dir.file("cut.npz")); });
  EXPECT_NE(msg.find(dir.file("cut.npz") + ": not a readable .npz"), std::string::npos) << msg;
  // Not a zip at all.
  std::ofstream(dir.file("text.npz")) << "locations,rotations\n";
  EXPECT_NE(errorOf([&] { track::readRoarWaypoints(dir.file("text.npz")); }).find("not a readable .npz"),
            std::string::npos);
  // Missing key, wrong shape, NaN.
  track::NpyArray loc{{5, 3}, std::vector<double>(15, 1.0)}, rot{{5, 3}, std::vector<double>(15, 0.0)};
  track::writeNpz(dir.file("nokey.npz"), {{"locations", loc}, {"rotations", rot}});
  msg = errorOf([&] { track::readRoarWaypoints(dir.file("nokey.npz")); });
  EXPECT_NE(msg.find("missing array 'lane_widths' (the file has: locations, rotations)"), std::string::npos) << msg;
  track::NpyArray flat{{5, 2}, std::vector<double>(10, 1.0)};
  track::writeNpz(dir.file("shape.npz"), {{"locations", flat}, {"rotations", rot}});
  msg = errorOf([&] { track::readRoarSpawnPoints(dir.file("shape.npz")); });
  EXPECT_NE(msg.find("array 'locations' has shape (5, 2), expected (N, 3)"), std::string::npos) << msg;
  loc.data[3 * 3 + 1] = std::nan("");
  track::writeNpz(dir.file("nan.npz"), {{"locations", loc}, {"rotations", rot}});
  msg = errorOf([&] { track::readRoarSpawnPoints(dir.file("nan.npz")); });
  EXPECT_NE(msg.find("array 'locations' row 3 is not finite"), std::string::npos) << msg;
}

TEST(Waypoints, EveryBitFlipIsRefusedOrHarmless) {
  // numpy refuses every corrupted archive (zip's CRC-32); so do we: a flipped bit anywhere in the file is
  // either refused or changes nothing that is read (zip metadata numpy ignores too).
  TempDir dir;
  const std::string good = dir.file("good.npz");
  track::NpyArray loc{{8, 3}, {}}, rot{{8, 3}, std::vector<double>(24, 0.25)};
  for (int i = 0; i < 24; ++i) loc.data.push_back(1000.0 + 7.3 * i);
  track::writeNpz(good, {{"locations", loc}, {"rotations", rot}});
  std::ifstream in(good, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  int refused = 0, harmless = 0;
  for (std::size_t k = 0; k < bytes.size(); ++k) {
    std::string flipped = bytes;
    flipped[k] = static_cast<char>(flipped[k] ^ 0x10);
    const std::string path = dir.file("flip.npz");
    std::ofstream(path, std::ios::binary | std::ios::trunc) << flipped;
    try {
      const auto arrays = track::readNpz(path);
      ASSERT_EQ(arrays.at("locations").data, loc.data) << "byte " << k << ": read, with other coordinates";
      ASSERT_EQ(arrays.at("rotations").data, rot.data) << "byte " << k;
      ++harmless;
    } catch (const track::NpzError&) {
      ++refused;
    } catch (const std::out_of_range&) {
      ++refused;  // an array's name changed: the reader of waypoints names the missing one
    }
  }
  EXPECT_GT(refused, static_cast<int>(bytes.size()) / 2) << harmless << " harmless";
}

TEST(Waypoints, AnArchiveCannotClaimMoreMemoryThanItsArrays) {
  if (std::system("/usr/bin/python3 -c 'import zipfile' 2>/dev/null") != 0) GTEST_SKIP() << "no /usr/bin/python3";
  TempDir dir;
  // Hand-made .npy entries (Python's zipfile, stored): a header that declares 3e8 values with 48 bytes of
  // data, and one that declares 12 values with 48 bytes.
  const std::string script = dir.file("craft.py");
  std::ofstream(script) << R"(import sys, zipfile, struct
def npy(shape):
    h = "{'descr': '<f8', 'fortran_order': False, 'shape': %s, }" % shape
    h += ' ' * (117 - len(h)) + '\n'
    return b'\x93NUMPY\x01\x00' + struct.pack('<H', len(h)) + h.encode() + bytes(48)
for name, shape in (('huge', '(100000000, 3)'), ('short', '(4, 3)')):
    with zipfile.ZipFile(sys.argv[1] + '/' + name + '.npz', 'w') as z:
        z.writestr('locations.npy', npy(shape))
)";
  ASSERT_EQ(std::system(("/usr/bin/python3 " + script + " " + dir.path.string()).c_str()), 0);
  auto msg = errorOf([&] { track::readNpz(dir.file("huge.npz")); });
  EXPECT_NE(msg.find("array 'locations': shape (100000000, 3) is more than"), std::string::npos) << msg;
  msg = errorOf([&] { track::readNpz(dir.file("short.npz")); });
  EXPECT_NE(msg.find("array 'locations': the archive says"), std::string::npos) << msg;
}

// ROAR_PY's own files, from ../shared when present (the project's other tests make their own files).
TEST(Waypoints, RoarPyMonzaImportsAsARaceableMap) {
  const std::string dir = test::sourceDir() + "/../shared/fixtures/roar_py";
  if (!fs::exists(dir + "/Monza_waypoints.npz")) GTEST_SKIP() << "ROAR_PY fixtures not present beside the checkout";
  const auto waypoints = track::readRoarWaypoints(dir + "/Monza_waypoints.npz");
  ASSERT_EQ(waypoints.size(), 2775u);
  EXPECT_DOUBLE_EQ(waypoints[0].lane_width, 12.0);
  track::TrackInfo info;
  info.name = "Monza";
  const auto monza = track::trackFromWaypoints(waypoints, info);
  EXPECT_NEAR(monza.length(), 5600, 300);
  track::checkEdges(monza, dir + "/Monza_waypoints.npz", {});
  const auto race = harness::runTimeTrial(monza, test::sedan(), {});
  ASSERT_TRUE(race.finished);
  EXPECT_EQ(race.barrier_contacts, 0);
  EXPECT_LT(race.worst_offroad, 0.0);
  RecordProperty("monza_lap_s", std::to_string(race.lap_times.at(0)));
  const auto spawns = track::readRoarSpawnPoints(dir + "/BerkMajor_spawn_points.npz");
  EXPECT_EQ(spawns.size(), 11u);
  const auto berk = track::readRoarWaypoints(dir + "/BerkMajor_waypoints.npz");
  EXPECT_EQ(berk.size(), 6942u);
  const auto berk_track = track::trackFromWaypoints(berk, info);
  double lo = 1e9, hi = -1e9;
  for (const auto& p : berk_track.points()) lo = std::min(lo, p.z), hi = std::max(hi, p.z);
  EXPECT_GT(hi - lo, 300.0) << "Berkeley's hills agree with their recorded pitch and are kept";
  // Its recording drives 46 m on over its start: cut there, it closes (track_tool import does this).
  std::size_t cut = 0;
  const auto lap = track::trimRetracedTail(berk_track.points(), &cut);
  EXPECT_EQ(cut, 23u);
  EXPECT_FALSE(track::loopGap(lap).open());
  EXPECT_NEAR(track::Track(lap, info).length(), 16242, 50);
}

TEST(Waypoints, ElevationAndBankingSurviveCsvAndNpz) {
  TempDir dir;
  std::string csv = "# x_m,y_m,w_tr_right_m,w_tr_left_m,z_m,banking_rad\n";
  for (int i = 0; i < 120; ++i) {
    const double a = 2 * M_PI * i / 120;
    csv += std::to_string(150 * std::cos(a)) + "," + std::to_string(150 * std::sin(a)) + ",6,6," +
           std::to_string(5 + 2 * std::sin(a)) + ",0.1\n";
  }
  std::ofstream(dir.file("centerline.csv")) << csv;
  std::ofstream(dir.file("track.yaml")) << "name: banked\n";
  const auto track = track::loadMapFolder(dir.path.string());
  EXPECT_NEAR(track.point(30).z, 7.0, 1e-6);
  EXPECT_DOUBLE_EQ(track.point(30).banking, 0.1);
  EXPECT_NEAR(track.surfaceHeight(30, 6.0), 7.0 + 6 * std::tan(0.1), 1e-6) << "the left (inner) edge is higher";
  track::writeRoarWaypoints(dir.file("banked.npz"), track::waypointsOf(track));
  const auto waypoints = track::readRoarWaypoints(dir.file("banked.npz"));
  EXPECT_NEAR(waypoints[30].location.z(), 7.0, 1e-6);
  EXPECT_DOUBLE_EQ(waypoints[30].roll_pitch_yaw.x(), 0.1);
  EXPECT_LT(waypoints[0].roll_pitch_yaw.y(), 0.0) << "climbing at the start: nose up is negative pitch";
  const auto again = track::trackFromWaypoints(waypoints, track.info());
  for (std::size_t i = 0; i < track.size(); i += 13) {
    EXPECT_NEAR(again.point(i).z, track.point(i).z, 1e-9);
    EXPECT_NEAR(again.point(i).banking, track.point(i).banking, 1e-9);
  }
  const auto bad = dir.file("bad.csv");
  std::ofstream(bad) << "0,0,5,5,0,1.2\n100,0,5,5,0,0\n100,100,5,5,0,0\n";
  EXPECT_NE(errorOf([&] { track::readCentreLineCsv(bad); }).find(bad + ":1: banking_rad"), std::string::npos);

  // A car set down on the raised, banked road rests on it.
  sim::World world(track, {});
  const auto pose = track.gridSpawnPoints(1)[0];
  world.spawnVehicle("ego", test::sedan(), track::poseOnTrack(pose));
  for (int i = 0; i < 40; ++i) world.step();
  const auto s = world.vehicleState("ego");
  const auto pr = track.project(s.pose.position.head<2>());
  EXPECT_NEAR(s.pose.position.z(), track.surfaceHeightAt(pr.s, pr.lateral), 0.02);
  EXPECT_LT(s.speed, 0.1);
}

TEST(Waypoints, ImplausibleHeightStepsAreSmoothedAndPlausibleProfilesKept) {
  std::vector<track::CentreLinePoint> pts;
  for (int i = 0; i < 943; ++i) {  // 2 m apart, as Monza's waypoints
    const double a = 2 * M_PI * i / 943;
    pts.push_back({300 * std::cos(a), 300 * std::sin(a), 5, 5, 20 * std::sin(a), 0});  // a 40 m hill, 7 % at most
  }
  auto plausible = pts;
  EXPECT_FALSE(track::repairElevation(&plausible));
  for (std::size_t i = 0; i < pts.size(); ++i) EXPECT_EQ(plausible[i].z, pts[i].z);
  for (int i = 400; i < 460; ++i) pts[i].z -= 0.742;  // a stretch 0.742 m down in 2 m, as in ROAR_PY's Monza
  EXPECT_TRUE(track::repairElevation(&pts));
  double steepest = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const auto &a = pts[i], &b = pts[(i + 1) % pts.size()];
    steepest = std::max(steepest, std::abs(b.z - a.z) / std::hypot(b.x - a.x, b.y - a.y));
  }
  EXPECT_LT(steepest, 0.1) << "the steps became ramps";
  EXPECT_NEAR(pts[236].z, 20.0, 0.1) << "the hill's top is kept";
}

// A map may carry the waypoints its source recorded (track.yaml's `waypoints`): ROAR's Monza carries
// ROAR_PY's own, which are then its waypoints point for point; a file that does not fit the centre line
// (another count, or points off it) is refused naming both files.
TEST(Waypoints, AMapsRecordedWaypointsAreItsWaypointsPointForPoint) {
  const std::string monza = test::sourceDir() + "/maps/monza";
  const auto track = track::loadMapFolder(monza);
  const auto recorded = track::readRoarWaypoints(monza + "/waypoints.npz");
  ASSERT_EQ(recorded.size(), 2775u) << "ROAR_PY's count";
  const auto waypoints = track::waypointsOf(track);
  ASSERT_EQ(waypoints.size(), recorded.size());
  for (std::size_t i = 0; i < recorded.size(); ++i) {
    ASSERT_EQ(waypoints[i].location, recorded[i].location) << i;
    ASSERT_EQ(waypoints[i].roll_pitch_yaw, recorded[i].roll_pitch_yaw) << i;
    ASSERT_EQ(waypoints[i].lane_width, recorded[i].lane_width) << i;
  }
  TempDir dir;
  for (const char* file : {"centerline.csv", "track.yaml"}) fs::copy_file(monza + "/" + file, dir.file(file));
  auto shorter = recorded;
  shorter.pop_back();
  track::writeRoarWaypoints(dir.file("waypoints.npz"), shorter);
  auto msg = errorOf([&] { track::loadMapFolder(dir.path.string()); });
  EXPECT_NE(msg.find("waypoints.npz (the waypoints"), std::string::npos) << msg;
  EXPECT_NE(msg.find("2774 recorded waypoints for 2775 centre-line points"), std::string::npos) << msg;
  auto moved = recorded;
  moved[100].location.x() += 1.0;
  track::writeRoarWaypoints(dir.file("waypoints.npz"), moved);
  msg = errorOf([&] { track::loadMapFolder(dir.path.string()); });
  EXPECT_NE(msg.find("recorded waypoint 100 is not centre-line point 100"), std::string::npos) << msg;
  fs::remove(dir.file("waypoints.npz"));
  msg = errorOf([&] { track::loadMapFolder(dir.path.string()); });
  EXPECT_NE(msg.find("waypoints.npz"), std::string::npos) << msg;
}
