#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <yaml-cpp/yaml.h>
#include <algorithm>
#include <cstdio>

#include <filesystem>
#include <fstream>

#include "roar/track/circuit_builder.h"
#include "roar/track/map_folder.h"
#include "roar/track/road_mesh.h"
#include "test_support.h"

using namespace roar;
using test::errorOf;
namespace fs = std::filesystem;

using test::TempDir;

TEST(Track, CircleGeometry) {
  const auto track = test::circleTrack(50.0);
  EXPECT_NEAR(track.length(), 2 * M_PI * 50.0, 0.1);
  for (std::size_t i = 0; i < track.size(); i += 17) {
    EXPECT_NEAR(track.curvature(i), 1.0 / 50.0, 1e-3);  // counter-clockwise: left turn, positive
  }
  // heading at angle 0 (point (50, 0)) is +y
  EXPECT_NEAR(track::wrapAngle(track.heading(0) - M_PI / 2), 0.0, 1e-3);
}

TEST(Track, ProjectionSignAndProgress) {
  const auto track = test::circleTrack(50.0);
  // Inside the circle is to the left of a counter-clockwise driver.
  const auto inside = track.project({45.0, 0.0});
  EXPECT_NEAR(inside.lateral, 5.0, 0.05);
  EXPECT_TRUE(inside.on_track());
  const auto outside = track.project({57.0, 0.0});
  EXPECT_NEAR(outside.lateral, -7.0, 0.05);
  EXPECT_FALSE(outside.on_track());
  // progress rises monotonically along the lap
  double last = -1;
  for (int k = 0; k < 100; ++k) {
    const double a = 2 * M_PI * k / 100.0;
    const auto pr = track.project({50 * std::cos(a), 50 * std::sin(a)});
    EXPECT_GT(pr.s, last);
    last = pr.s;
    EXPECT_NEAR(track.projectNear({50 * std::cos(a), 50 * std::sin(a)}, pr.s, 30).s, pr.s, 1e-9);
  }
}

TEST(Track, PoseAtAndForwardDistance) {
  const auto track = test::circleTrack(50.0);
  const auto pose = track.poseAt(track.length() / 4);
  EXPECT_NEAR(pose.position.x(), 0.0, 0.05);
  EXPECT_NEAR(pose.position.y(), 50.0, 0.05);
  EXPECT_NEAR(track.forwardDistance(track.length() - 10, 5), 15.0, 1e-9);
  EXPECT_NEAR(track.wrap(-1.0), track.length() - 1.0, 1e-9);
}

TEST(Track, GridSpawnPointsBehindTheLineFacingForward) {
  const auto track = test::circleTrack(100.0);
  const auto grid = track.gridSpawnPoints(4);
  ASSERT_EQ(grid.size(), 4u);
  for (std::size_t k = 0; k < grid.size(); ++k) {
    const auto pr = track.project(grid[k].position);
    EXPECT_TRUE(pr.on_track());
    EXPECT_NEAR(track.forwardDistance(pr.s, 0.0), 10.0 + 8.0 * k, 0.2);
    EXPECT_NEAR(track::wrapAngle(grid[k].heading - pr.heading), 0.0, 0.01);
  }
  EXPECT_LT(grid[0].position.norm(), 99.0) << "pole is on the left: the inside of a counter-clockwise circle";
  EXPECT_GT(grid[1].position.norm(), 101.0);
}

TEST(Track, ShippedDefaultMapLoadsAndCloses) {
  const auto maps = track::listMaps(test::sourceDir() + "/maps");
  ASSERT_FALSE(maps.empty());
  for (const auto& name : maps) {
    SCOPED_TRACE(name);
    const auto track = track::loadMapFolder(track::resolveMapFolder(name, test::sourceDir() + "/maps"));
    EXPECT_GT(track.length(), 1000.0);
    const auto gap = (track.position(0) - track.position(track.size() - 1)).norm();
    if (track.closed()) {
      EXPECT_LT(gap, 10.0) << "closes";
    } else {
      EXPECT_GT(gap, 100.0) << "a point-to-point course ends far from where it starts";
      EXPECT_GT(track.raceDistance(), 1000.0);
    }
  }
}

TEST(MapFolder, CsvWithTumftmHeader) {
  TempDir dir;
  const auto path =
      dir.write("c.csv", "# x_m,y_m,w_tr_right_m,w_tr_left_m\n0,0,5,5\n100,0,5,5\n100,100,5,5\n0,100,5,5\n0,0,5,5\n");
  const auto file = track::readCentreLineCsv(path);
  ASSERT_EQ(file.points.size(), 4u) << "a repeated closing point is dropped";
  EXPECT_EQ(file.lines[1], 3);
}

TEST(MapFolder, MissingColumnNamesFileAndLine) {
  TempDir dir;
  const auto path = dir.write("c.csv", "x_m,y_m,w_tr_right_m,w_tr_left_m\n0,0,5,5\n100,0,5\n100,100,5,5\n");
  const auto msg = errorOf([&] { track::readCentreLineCsv(path); });
  EXPECT_NE(msg.find(path + ":3:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("expected 4 columns"), std::string::npos) << msg;
}

TEST(MapFolder, FewerThanThreePoints) {
  TempDir dir;
  const auto path = dir.write("c.csv", "0,0,5,5\n100,0,5,5\n");
  const auto msg = errorOf([&] { track::readCentreLineCsv(path); });
  EXPECT_NE(msg.find("at least 3"), std::string::npos) << msg;
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
}

TEST(MapFolder, NegativeWidthAndNaN) {
  TempDir dir;
  const auto neg = dir.write("n.csv", "0,0,5,5\n100,0,-5,5\n100,100,5,5\n");
  auto msg = errorOf([&] { track::readCentreLineCsv(neg); });
  EXPECT_NE(msg.find(neg + ":2: w_tr_right_m must be positive"), std::string::npos) << msg;
  const auto nan = dir.write("nan.csv", "0,0,5,5\n100,nan,5,5\n100,100,5,5\n");
  msg = errorOf([&] { track::readCentreLineCsv(nan); });
  EXPECT_NE(msg.find(nan + ":2: column y_m is not finite"), std::string::npos) << msg;
  const auto text = dir.write("t.csv", "0,0,5,5\n100,abc,5,5\n100,100,5,5\n");
  msg = errorOf([&] { track::readCentreLineCsv(text); });
  EXPECT_NE(msg.find(text + ":2: column y_m is not a number"), std::string::npos) << msg;
}

TEST(MapFolder, RowsThatDoNotMatchTheFirstPointsColumnsAreRefused) {
  TempDir dir;
  const std::string square = "0,0,5,5\n100,0,5,5\n100,100,5,5\n0,100,5,5\n";
  // A stray column on one row would otherwise be read as that point's elevation.
  const auto stray = dir.write("stray.csv", "0,0,5,5\n100,0,5,5,9999,0.7\n100,100,5,5\n0,100,5,5\n");
  EXPECT_EQ(errorOf([&] { track::readCentreLineCsv(stray); }),
            stray + ":2: expected 4 columns as the first point has, found 6 (a stray comma, or a decimal comma?)");
  const auto comma = dir.write("comma.csv", "0,0,5,5\n100,0,1,5,8\n100,100,5,5\n0,100,5,5\n");
  EXPECT_NE(errorOf([&] {
              track::readCentreLineCsv(comma);
            }).find(comma + ":2: expected 4 columns as the first point has, found 5"),
            std::string::npos);
  const auto wide = dir.write("wide.csv", "0,0,5,5,0,0,1\n100,0,5,5,0,0,1\n100,100,5,5,0,0,1\n");
  EXPECT_NE(errorOf([&] { track::readCentreLineCsv(wide); }).find(wide + ":1: expected 4 columns"), std::string::npos);
  EXPECT_EQ(track::readCentreLineCsv(dir.write("ok.csv", square)).points.size(), 4u);
}

TEST(MapFolder, OnlyALineOfWordsIsAHeader) {
  TempDir dir;
  const auto words = dir.write("w.csv", "x_m,y_m,w_tr_right_m,w_tr_left_m\n0,0,5,5\n100,0,5,5\n100,100,5,5\n");
  EXPECT_EQ(track::readCentreLineCsv(words).points.size(), 3u);
  // A first point written with spaces is a broken row, not a header to skip.
  const auto spaces = dir.write("s.csv", "0 0 5 5\n100,0,5,5\n100,100,5,5\n0,100,5,5\n");
  EXPECT_EQ(errorOf([&] { track::readCentreLineCsv(spaces); }),
            spaces + ":1: expected 4 columns x_m,y_m,w_tr_right_m,w_tr_left_m (then z_m,banking_rad), found 1");
}

TEST(MapFolder, ARoadNarrowerThanACarAndAnImpossibleGradeAreRefused) {
  TempDir dir;
  const auto narrow = dir.write("n.csv", "0,0,5,5\n100,0,0.001,0.001\n100,100,5,5\n0,100,5,5\n");
  EXPECT_EQ(errorOf([&] { track::readCentreLineCsv(narrow); }),
            narrow + ":2: the road is 0.002 m wide (w_tr_right_m + w_tr_left_m), less than 2.5 m");
  const auto spike = dir.write("z.csv", "0,0,5,5,0\n100,0,5,5,0\n101,0,5,5,9999\n100,100,5,5,0\n");
  EXPECT_NE(errorOf([&] { track::readCentreLineCsv(spike); }).find(spike + ":3: z_m rises 9999"), std::string::npos);
  const auto ramp = dir.write("r.csv", "0,0,5,5,0\n100,0,5,5,10\n100,100,5,5,10\n0,100,5,5,0\n");
  EXPECT_EQ(track::readCentreLineCsv(ramp).points[1].z, 10.0) << "a 10% ramp is a road";
}

TEST(MapFolder, ValuesOutsidePhysicalRangesAreRefusedByColumn) {
  // Finite is not enough: a map scaled by 1e300 once loaded as a circuit "inf m" long.
  TempDir dir;
  const struct {
    const char* line;
    const char* expected;
  } cases[] = {
      {"100,1e300,5,5", "column y_m = 1e+300 is outside [-1e+06, 1e+06]"},
      {"2e6,0,5,5", "column x_m = 2e+06 is outside"},
      {"100,0,500,5", "column w_tr_right_m = 500 is outside [0.001, 100]"},
      {"100,0,5,1e-30", "column w_tr_left_m = 1e-30 is outside"},
      {"100,0,5,5,1e5", "column z_m = 100000 is outside"},
      {"100,0,5,5,0,1.2", "banking_rad must be within (-pi/4, pi/4)"},
  };
  for (const auto& c : cases) {
    // Every row has as many columns as the one under test.
    const std::string line = c.line;
    std::string padded;
    for (auto extra = std::count(line.begin(), line.end(), ',') - 3; extra > 0; --extra) padded += ",0";
    const auto path = dir.write("r.csv", "0,0,5,5" + padded + "\n" + c.line + "\n100,100,5,5" + padded + "\n");
    const auto msg = errorOf([&] { track::readCentreLineCsv(path); });
    EXPECT_NE(msg.find(path + ":2: " + c.expected), std::string::npos) << c.line << ": " << msg;
  }
  // The Track itself checks what other readers give it (waypoint files), and counts its points.
  std::vector<track::CentreLinePoint> far = {{0, 0, 5, 5}, {1e300, 0, 5, 5}, {0, 100, 5, 5}};
  EXPECT_NE(errorOf([&] { track::Track(far, {}); }).find("centre-line point 1: column x_m = 1e+300"),
            std::string::npos);
  std::string many;
  for (std::size_t k = 0; k <= track::kMaxCentreLinePoints; ++k) {
    const double a = 2 * M_PI * static_cast<double>(k) / (track::kMaxCentreLinePoints + 1.0);
    many += std::to_string(30000 * std::cos(a)) + "," + std::to_string(30000 * std::sin(a)) + ",5,5\n";
  }
  const auto huge = dir.write("huge.csv", many);
  const auto msg = errorOf([&] { track::readCentreLineCsv(huge); });
  EXPECT_NE(msg.find(huge + ":200001: more than 200000 centre-line points"), std::string::npos) << msg;
}

TEST(MapFolder, SelfIntersectingEdgeIsRefused) {
  TempDir dir;
  // A figure eight: the centre line (and so both edges) crosses itself.
  std::string csv = "# x_m,y_m,w_tr_right_m,w_tr_left_m\n";
  for (int i = 0; i < 80; ++i) {
    const double t = 2 * M_PI * i / 80;
    csv += std::to_string(200 * std::sin(t)) + "," + std::to_string(100 * std::sin(2 * t)) + ",4,4\n";
  }
  dir.write("centerline.csv", csv);
  dir.write("track.yaml", "name: eight\n");
  const auto msg = errorOf([&] { track::loadMapFolder(dir.str()); });
  EXPECT_NE(msg.find("centerline.csv:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("crosses"), std::string::npos) << msg;
}

TEST(MapFolder, CornerTooTightForTheWidthIsRefused) {
  TempDir dir;
  std::string csv;
  for (int i = 0; i < 60; ++i) {
    const double t = 2 * M_PI * i / 60;
    csv += std::to_string(8 * std::cos(t)) + "," + std::to_string(8 * std::sin(t)) +
           ",3,10\n";  // left (inner) edge past the centre
  }
  dir.write("centerline.csv", csv);
  dir.write("track.yaml", "name: tight\n");
  const auto msg = errorOf([&] { track::loadMapFolder(dir.str()); });
  EXPECT_NE(msg.find("left edge runs backwards"), std::string::npos) << msg;
  EXPECT_NE(msg.find("too tight for the width"), std::string::npos) << msg;
}

TEST(MapFolder, TrackYamlErrorsNameTheField) {
  TempDir dir;
  dir.write("centerline.csv", "0,0,5,5\n100,0,5,5\n100,100,5,5\n0,100,5,5\n");
  dir.write("track.yaml", "name: x\nfriction: lots\n");
  auto msg = errorOf([&] { track::loadMapFolder(dir.str()); });
  EXPECT_NE(msg.find("track.yaml: friction: is not a number"), std::string::npos) << msg;
  dir.write("track.yaml", "name: x\nsectors: 0\n");
  msg = errorOf([&] { track::loadMapFolder(dir.str()); });
  EXPECT_NE(msg.find("track.yaml: sectors: 0"), std::string::npos) << msg;
  // Misspelt keys are refused (they used to fall back to the default without a word), and numbers must
  // be physical, not just finite.
  dir.write("track.yaml", "name: x\nfrcition: 0.9\n");
  msg = errorOf([&] { track::loadMapFolder(dir.str()); });
  EXPECT_NE(msg.find("track.yaml: frcition: is not a known key (did you mean 'friction'?)"), std::string::npos) << msg;
  dir.write("track.yaml", "name: x\norigin: {latitude: 37.87, longitud: -122.26}\n");
  msg = errorOf([&] { track::loadMapFolder(dir.str()); });
  EXPECT_NE(msg.find("origin.longitud: is not a known key"), std::string::npos) << msg;
  for (const char* bad : {"barrier_height: 1e300", "barrier_offset: -1", "friction: .nan", "ground_friction: 0"}) {
    dir.write("track.yaml", std::string("name: x\n") + bad + "\n");
    msg = errorOf([&] { track::loadMapFolder(dir.str()); });
    const std::string key = std::string(bad).substr(0, std::string(bad).find(':'));
    EXPECT_NE(msg.find("track.yaml: " + key + ":"), std::string::npos) << bad << ": " << msg;
  }
  dir.write("track.yaml", "name: x\norigin: {latitude: 37.87, longitude: -122.26, altitude: 50}\nfriction: 0.9\n");
  const auto track = track::loadMapFolder(dir.str());
  EXPECT_DOUBLE_EQ(track.info().origin.latitude, 37.87);
  EXPECT_DOUBLE_EQ(track.info().friction, 0.9);
  msg = errorOf([&] { track::resolveMapFolder("no_such_map", dir.str()); });
  EXPECT_NE(msg.find("unknown map 'no_such_map'"), std::string::npos) << msg;
}

TEST(MapFolder, FilesOutsideTheFolderAreNotReadAndContentIsNotQuoted) {
  TempDir dir;
  const auto secret = dir.write("secret.txt", "root:x:0:0:root:/root:/bin/bash\n");
  fs::create_directory(fs::path(dir.str()) / "map");
  const std::string map = (fs::path(dir.str()) / "map").string();
  for (const std::string& named : {std::string("../secret.txt"), secret, std::string(".."), std::string("sub/c.csv")}) {
    std::ofstream(map + "/track.yaml") << "centerline: '" << named << "'\n";
    const auto msg = errorOf([&] { track::loadMapFolder(map); });
    EXPECT_NE(msg.find("track.yaml: centerline: must be a file name in the map folder"), std::string::npos) << msg;
  }
  std::ofstream(map + "/track.yaml") << "waypoints: /etc/passwd\n";
  EXPECT_NE(errorOf([&] { track::loadMapFolder(map); }).find("waypoints: must be a file name in the map folder"),
            std::string::npos);
  // A file that is no centre line is named with its line and column, never with what it holds.
  const auto text = dir.write("t.csv", "root:x:0:0,secret,5,5\n100,0,5,5\n100,100,5,5\n");
  const auto msg = errorOf([&] { track::readCentreLineCsv(text); });
  EXPECT_EQ(msg, text + ":1: column x_m is not a number");
}

TEST(MapFolder, CsvRoundTrip) {
  TempDir dir;
  const auto track = test::circleTrack(40.0);
  const auto path = (fs::path(dir.str()) / "c.csv").string();
  track::writeCentreLineCsv(path, track.points());
  const auto back = track::readCentreLineCsv(path);
  ASSERT_EQ(back.points.size(), track.size());
  for (std::size_t i = 0; i < track.size(); ++i) {
    EXPECT_EQ(back.points[i].x, track.point(i).x);
    EXPECT_EQ(back.points[i].y, track.point(i).y);
  }
}

TEST(CircuitBuilder, ClosedSmoothEvenlySpaced) {
  const std::vector<track::ControlPoint> controls = {{0, 0, 12}, {300, 0, 12}, {350, 100, 10}, {0, 150, 12}};
  const auto pts = track::buildCircuit(controls, 3.0);
  track::Track track(pts, {});
  for (std::size_t i = 0; i < track.size(); ++i) {
    const double seg = (track.position((i + 1) % track.size()) - track.position(i)).norm();
    EXPECT_NEAR(seg, 3.0, 0.3);
  }
  EXPECT_THROW(track::buildCircuit({{0, 0, 10}, {1, 1, 10}}, 3.0), std::invalid_argument);
}

// The run-off reaches from each road edge under the barrier, level with the edge across (banked and
// climbing roads too), and faces up: the grass a wheel over the edge rolls on.
TEST(RoadMesh, TheRunOffLiesLevelWithEachEdgeOutToBeyondTheBarrier) {
  std::vector<track::CentreLinePoint> points;
  for (int i = 0; i < 120; ++i) {
    const double a = 2 * M_PI * i / 120;
    points.push_back({200 * std::cos(a), 200 * std::sin(a), 6, 5, 10 + 4 * std::sin(a), 0.08});
  }
  const track::Track track(points, {});
  const auto runoff = track::runoffMesh(track);
  ASSERT_EQ(runoff.triangles.size(), 4 * track.size());
  for (const auto& t : runoff.triangles) {
    const Eigen::Vector3d n =
        (runoff.vertices[t[1]] - runoff.vertices[t[0]]).cross(runoff.vertices[t[2]] - runoff.vertices[t[0]]);
    EXPECT_GT(n.z(), 0) << "faces up";
  }
  const std::size_t n = track.size();
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = track.point(i);
    // Each side's strip has two vertices a station: the left's from its edge out, the right's from out in.
    const Eigen::Vector3d left_in = runoff.vertices[2 * i], left_out = runoff.vertices[2 * i + 1];
    const Eigen::Vector3d right_out = runoff.vertices[2 * n + 2 * i], right_in = runoff.vertices[2 * n + 2 * i + 1];
    for (const auto& v : {left_in, left_out}) EXPECT_NEAR(v.z(), track.surfaceHeight(i, p.width_left), 1e-9);
    for (const auto& v : {right_in, right_out}) EXPECT_NEAR(v.z(), track.surfaceHeight(i, -p.width_right), 1e-9);
    EXPECT_NEAR((left_in.head<2>() - track.leftEdge(i)).norm(), 0.0, 1e-9) << "from the road's edge";
    EXPECT_NEAR((right_in.head<2>() - track.rightEdge(i)).norm(), 0.0, 1e-9);
    EXPECT_GT((left_out.head<2>() - left_in.head<2>()).norm(), track.info().barrier_offset) << "under the barrier";
    EXPECT_GT((right_out.head<2>() - right_in.head<2>()).norm(), track.info().barrier_offset);
  }
}

TEST(RoadMesh, CoversTheRoadAndWallsStandOutside) {
  const auto track = test::circleTrack(50.0);
  const auto road = track::roadSurfaceMesh(track);
  EXPECT_EQ(road.triangles.size(), 2 * track.size());
  const auto walls = track::barrierMesh(track);
  for (const auto& v : walls.vertices) {
    const double r = v.head<2>().norm();
    EXPECT_TRUE(r <= 50 - 6 - track.info().barrier_offset + 1e-6 || r >= 50 + 6 + track.info().barrier_offset - 1e-6)
        << r;
  }
}

TEST(CircuitBuilder, ResamplingKeepsTheLength) {
  const auto track = track::loadMapFolder(test::sourceDir() + "/maps/roar_ring");
  for (double spacing : {0.5, 2.0, 5.0}) {
    const track::Track resampled(track::resampleClosed(track.points(), spacing), track.info());
    EXPECT_NEAR(resampled.length(), track.length(), 0.001 * track.length()) << spacing;
    EXPECT_NEAR(resampled.length() / resampled.size(), spacing, 0.01 * spacing);
  }
}

TEST(Track, EvenSpawnPointsLieOnTheTrackFacingTheDrivingDirection) {
  const auto track = track::loadMapFolder(test::sourceDir() + "/maps/roar_sprint");
  const auto spawns = track.evenSpawnPoints(7);
  ASSERT_EQ(spawns.size(), 7u);
  for (std::size_t k = 0; k < spawns.size(); ++k) {
    const auto pr = track.project(spawns[k].position);
    EXPECT_TRUE(pr.on_track());
    EXPECT_LT(std::abs(pr.lateral), 0.05);
    EXPECT_NEAR(track::wrapAngle(spawns[k].heading - pr.heading), 0.0, 0.05);
    EXPECT_NEAR(track.forwardDistance(track.info().start_finish_s, pr.s), k * track.length() / 7, 0.5);
  }
}

TEST(MapFolder, WrittenMapsLoadBackAndBadPointListsAreRefused) {
  TempDir dir;
  const auto track = test::circleTrack(80.0);
  track::TrackInfo info = track.info();
  info.name = "written";
  info.sectors = 4;
  const std::string folder = dir.str() + "/written";
  track::writeMapFolder(folder, track.points(), info);
  const auto back = track::loadMapFolder(folder);
  EXPECT_EQ(back.info().name, "written");
  EXPECT_EQ(back.info().sectors, 4);
  EXPECT_EQ(back.size(), track.size());
  const auto list = dir.write("points.txt", "# x y\n0 0\n100,0\n100 100\n");
  EXPECT_EQ(track::readPointList(list, 10).size(), 3u);
  const auto bad = dir.write("bad.txt", "0 0\n100 zero\n100 100\n");
  EXPECT_NE(errorOf([&] { track::readPointList(bad, 10); }).find(bad + ":2: expected two numbers"), std::string::npos);
  EXPECT_NE(errorOf([&] {
              track::writeMapFolder(dir.str() + "/eight",
                                    {{0, 0, 5, 5}, {100, 100, 5, 5}, {100, 0, 5, 5}, {0, 100, 5, 5}}, info);
            }).find("crosses"),
            std::string::npos)
      << "a crossing centre line is refused before anything is written";
  EXPECT_FALSE(fs::exists(dir.str() + "/eight"));
}

TEST(CircuitBuilder, ALoopThatStopsShortIsBridgedOneThatRunsPastItsStartIsNot) {
  // A 100 m circle at 2 m steps without its last 40 m: 40 m short of its start.
  std::vector<track::CentreLinePoint> points;
  const double length = 2 * M_PI * 100.0;
  for (double s = 0; s < length - 40.0; s += 2.0)
    points.push_back({100 * std::cos(s / 100), 100 * std::sin(s / 100), 5, 5});
  const auto gap = track::loopGap(points);
  EXPECT_TRUE(gap.open());
  EXPECT_NEAR(gap.median_step, 2.0, 0.01);
  EXPECT_TRUE(gap.bridgeable());
  const auto closed = track::closeLoopGap(points);
  EXPECT_FALSE(track::loopGap(closed).open());
  TempDir dir;
  track::writeMapFolder(dir.str() + "/bridged", closed, {});
  EXPECT_NEAR(track::loadMapFolder(dir.str() + "/bridged").length(), length, 1.0);
  // The same circle running 40 m on past its start (its last point beyond the first): no straight closes it.
  std::vector<track::CentreLinePoint> overlapping;
  for (double s = 0; s < length + 40.0; s += 2.0)
    overlapping.push_back({100 * std::cos(s / 100) + 0.01 * s, 100 * std::sin(s / 100), 5, 5});
  EXPECT_TRUE(track::loopGap(overlapping).open());
  EXPECT_FALSE(track::loopGap(overlapping).bridgeable());
}

TEST(CircuitBuilder, ARecordedLapThatDrivesOnOverItsStartIsCutWhereItComesBack) {
  // A 100 m circle at 2 m steps driven 40 m on over its start, 0.3 m to one side of its first lap.
  const double length = 2 * M_PI * 100.0;
  std::vector<track::CentreLinePoint> points;
  for (double s = 0; s < length + 40.0; s += 2.0) {
    const double r = s < length ? 100.0 : 100.3;
    points.push_back({r * std::cos(s / 100), r * std::sin(s / 100), 2, 2});
  }
  std::size_t cut = 0;
  const auto trimmed = track::trimRetracedTail(points, &cut);
  EXPECT_GE(cut, 20u);
  EXPECT_LE(cut, 22u);
  EXPECT_EQ(trimmed.size(), points.size() - cut);
  EXPECT_FALSE(track::loopGap(trimmed).open()) << "closes";
  TempDir dir;
  track::writeMapFolder(dir.str() + "/lap", trimmed, {});
  EXPECT_NEAR(track::loadMapFolder(dir.str() + "/lap").length(), length, 2.0);
  // Running on past the start beside it (3 m off, beyond half the road) is not the same road: kept.
  std::vector<track::CentreLinePoint> beside = points;
  for (auto& p : beside) {
    if (std::hypot(p.x, p.y) > 100.1) p.x *= 103.0 / 100.3, p.y *= 103.0 / 100.3;
  }
  track::trimRetracedTail(beside, &cut);
  EXPECT_EQ(cut, 0u);
  // Nor is a loop that ends where it began, or a course driven the other way over its start.
  track::trimRetracedTail(std::vector<track::CentreLinePoint>(points.begin(), points.begin() + 314), &cut);
  EXPECT_EQ(cut, 0u);
  std::vector<track::CentreLinePoint> reversed = points;
  for (std::size_t k = 0; k < reversed.size(); ++k) {
    const double s = 2.0 * static_cast<double>(k);
    if (s >= length) reversed[k] = {100 * std::cos(-(s - length) / 100), 100 * std::sin(-(s - length) / 100), 2, 2};
  }
  track::trimRetracedTail(reversed, &cut);
  EXPECT_EQ(cut, 0u) << "the other way round is not a retrace";
}

TEST(MapFolder, RewritingAMapWritesTheCentreLineItsTrackYamlNames) {
  // track_tool resample once wrote centerline.csv beside a track.yaml naming another file: no effect.
  TempDir dir;
  const std::string folder = dir.str() + "/named";
  const auto track = test::circleTrack(80.0);
  track::writeMapFolder(folder, track.points(), track.info());
  fs::rename(folder + "/centerline.csv", folder + "/other.csv");
  std::ifstream in(folder + "/track.yaml");
  std::string yaml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  yaml.replace(yaml.find("centerline.csv"), std::string("centerline.csv").size(), "other.csv");
  dir.write("named/track.yaml", yaml);
  const auto half = track::resampleClosed(track.points(), 2.0 * track.length() / track.size());
  track::writeMapFolder(folder, half, track.info());
  EXPECT_FALSE(fs::exists(folder + "/centerline.csv"));
  EXPECT_EQ(track::loadMapFolder(folder).size(), half.size());
}

TEST(MapFolder, ACentreLineThatDoesNotCloseIsRefused) {
  TempDir dir;
  std::string csv;
  for (int i = 0; i <= 100; ++i) {  // half a circle: the ends are 200 m apart
    const double a = M_PI * i / 100;
    csv += std::to_string(100 * std::cos(a)) + "," + std::to_string(100 * std::sin(a)) + ",5,5\n";
  }
  dir.write("centerline.csv", csv);
  dir.write("track.yaml", "name: open\n");
  const auto msg = errorOf([&] { track::loadMapFolder(dir.str()); });
  EXPECT_NE(msg.find("does not close"), std::string::npos) << msg;
}

TEST(Track, ProjectionOnAStraight) {
  std::vector<track::CentreLinePoint> pts;
  for (double x = 0; x < 500; x += 5) pts.push_back({x, 0, 4, 6});
  for (double x = 500; x > 0; x -= 5) pts.push_back({x, 60, 4, 6});
  const track::Track track(pts, {});
  const auto left = track.project({123.0, 2.5});
  EXPECT_NEAR(left.s, 123.0, 1e-9);
  EXPECT_NEAR(left.lateral, 2.5, 1e-9);
  EXPECT_TRUE(left.on_track());
  const auto right = track.project({77.0, -4.5});
  EXPECT_NEAR(right.lateral, -4.5, 1e-9);
  EXPECT_FALSE(right.on_track()) << "4 m to the right edge";
  EXPECT_NEAR(track.project({77.0, -3.5}).width_right, 4.0, 1e-9);
}

TEST(MapFolder, EveryNumberOfTrackYamlAtEveryExtremeIsRefusedByNameOrLoadsFinite) {
  // Property test (issue 17): each number of a shipped track.yaml set to 0, -1, 1e-30, 1e30, 1e300, NaN and
  // inf in turn: refused naming the field, or a map whose length, friction and barriers are finite.
  TempDir dir;
  const std::string folder = dir.str() + "/sprint";
  fs::create_directories(folder);
  fs::copy_file(test::sourceDir() + "/maps/roar_sprint/centerline.csv", folder + "/centerline.csv");
  const YAML::Node original = YAML::LoadFile(test::sourceDir() + "/maps/roar_sprint/track.yaml");
  const std::vector<std::pair<std::string, std::string>> fields = {
      {"origin", "latitude"}, {"origin", "longitude"}, {"origin", "altitude"},
      {"", "friction"},       {"", "ground_friction"}, {"start_finish", "s"},
      {"", "sectors"},        {"", "barrier_offset"},  {"", "barrier_height"}};
  int refused = 0, loaded = 0;
  for (const auto& [parent, key] : fields) {
    for (const char* extreme : {"0", "-1", "1e-30", "1e30", "1e300", ".nan", ".inf"}) {
      YAML::Node doc = YAML::Clone(original);
      (parent.empty() ? doc[key] : doc[parent][key]) = YAML::Load(extreme);
      std::ofstream(folder + "/track.yaml") << YAML::Dump(doc) << "\n";
      std::string error;
      try {
        const auto track = track::loadMapFolder(folder);
        const auto& info = track.info();
        EXPECT_TRUE(std::isfinite(track.length()) && std::isfinite(info.friction) &&
                    std::isfinite(info.barrier_offset) && std::isfinite(info.origin.latitude) &&
                    std::isfinite(info.start_finish_s))
            << key << " = " << extreme << " loaded a map with a non-finite value";
        ++loaded;
      } catch (const std::exception& e) {
        EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << key << " = " << extreme << ": " << e.what();
        ++refused;
      }
    }
  }
  std::printf("track.yaml property test: %zu fields x 7 extremes: %d refused by name, %d loaded finite\n",
              fields.size(), refused, loaded);
  EXPECT_GT(refused, 40);
}
