// Runs the real ambler-cli binary, as a user or script would.
#include <gtest/gtest.h>

#include <cmath>

#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include <Eigen/Core>

#include "TempDir.h"
#include "io/Tiff.h"
#include "link/Signing.h"
#include "missionlog/MissionLog.h"
#include "sensor/RangeImageFile.h"

namespace {

struct Run {
  int exit_code;
  std::string out;  // stdout and stderr together
};

Run runProgram(const std::string& program, const std::string& args) {
  const std::string command = program + " " + args + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return {-1, "popen failed"};
  std::string out;
  std::array<char, 4096> buffer{};
  while (std::size_t n = fread(buffer.data(), 1, buffer.size(), pipe)) out.append(buffer.data(), n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

Run runCli(const std::string& args) { return runProgram(AMBLER_CLI, args); }

// ambler-sim sits next to ambler-cli.
Run runSim(const std::string& args) {
  return runProgram((std::filesystem::path(AMBLER_CLI).parent_path() / "ambler-sim").string(),
                    args);
}

TEST(Cli, SimScanWritesScanAndGroundTruthThatInfoDescribes) {
  TempDir dir;
  const auto run = runCli("sim-scan --seed 2 --rows 48 --cols 64 --resolution 0.25 --out " +
                          dir.path().string());
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const auto summary = nlohmann::json::parse(run.out);
  EXPECT_EQ(summary["rows"], 48);
  EXPECT_GT(summary["returns"].get<int>(), 48 * 64 * 9 / 10);

  for (const char* f : {"scan.tif", "scan.json", "truth_z.tif", "truth_visible.tif", "truth.json"})
    EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
  const auto scan = ambler::sensor::readRangeImage(dir / "scan.tif");
  EXPECT_EQ(scan.cols(), 64);
  // The sensor sits 5 m (default mount) above the ground at the start.
  EXPECT_NEAR(scan.sensor_to_world.translation().z(), 5.0, 0.5);

  const auto visible = ambler::io::readByteTiff(dir / "truth_visible.tif");
  const auto truth = nlohmann::json::parse(std::ifstream(dir / "truth.json"));
  EXPECT_EQ(truth["rows"], visible.rows);
  EXPECT_EQ(truth["resolution"], 0.25);
  int counts[3] = {0, 0, 0};
  for (auto v : visible.pixels) {
    ASSERT_LE(v, 2);
    ++counts[v];
  }
  EXPECT_GT(counts[0], 0);  // the course has visible ground,
  EXPECT_GT(counts[2], 0);  // rocks and obstacles casting shadows,
  EXPECT_GT(counts[1], 0);  // and the footprint's corners are outside the fan

  // Any terrain family: the slope family's ground rises 10-30 degrees across
  // the footprint, several metres where the course is within a metre of level.
  TempDir sloped;
  ASSERT_EQ(runCli("sim-scan --family slope --seed 2 --rows 32 --cols 32 --resolution 0.5 --out " +
                   sloped.path().string())
                .exit_code,
            0);
  const auto slope_z = ambler::io::readFloatTiff(sloped / "truth_z.tif");
  float lo = INFINITY, hi = -INFINITY;
  for (const float z : slope_z.pixels)
    if (std::isfinite(z)) lo = std::min(lo, z), hi = std::max(hi, z);
  EXPECT_GT(hi - lo, 3.0f);

  const auto info = runCli("info " + (dir / "scan.tif").string());
  ASSERT_EQ(info.exit_code, 0) << info.out;
  const auto described = nlohmann::json::parse(info.out);
  EXPECT_EQ(described["type"], "range_image");
  EXPECT_EQ(described["returns"], summary["returns"]);
  EXPECT_LT(described["range_m"]["min"].get<double>(), described["range_m"]["max"].get<double>());
}

TEST(Cli, SimStriperAndInfo) {
  TempDir dir;
  const auto run = runCli("sim-striper --seed 3 --out " + (dir / "striper").string());
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const auto info = runCli("info " + (dir / "striper").string());
  ASSERT_EQ(info.exit_code, 0) << info.out;
  const auto described = nlohmann::json::parse(info.out);
  EXPECT_EQ(described["type"], "striper_image");
  EXPECT_EQ(described["points"], nlohmann::json::parse(run.out)["points"]);
}

// fit-rock on a simulated tray of rocks resting on the sand: every
// automatic seed gives a rock the size of the tray's (2.5-8 cm semi-axes)
// and a grasp; a seed off the rocks is refused with the reason.
TEST(Cli, FitRockFitsTheTraysRocksAndRefusesABadSeed) {
  TempDir dir;
  const auto striper = (dir / "striper").string();
  ASSERT_EQ(runCli("sim-striper --seed 3 --burial 0,0.2 --out " + striper).exit_code, 0);
  const auto run = runCli("fit-rock --striper " + striper + " --auto --robust");
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const auto out = nlohmann::json::parse(run.out);
  EXPECT_EQ(out["method"], "robust");
  ASSERT_EQ(out["rocks"].size(), 5u);
  for (const auto& rock : out["rocks"]) {
    ASSERT_TRUE(rock.contains("superquadric")) << rock.dump();
    for (double a : rock["superquadric"]["size_m"]) {
      EXPECT_GT(a, 0.015);
      EXPECT_LT(a, 0.1);
    }
    EXPECT_TRUE(rock["grasp"]["ok"]) << rock.dump();
  }
  const auto bad = runCli("fit-rock --striper " + striper + " --seed 2,2");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.out.find("seed (2, 2)"), std::string::npos) << bad.out;
  const auto far = runCli("fit-rock --striper " + striper + " --seed 1e30,5");
  EXPECT_EQ(far.exit_code, 1);
  EXPECT_NE(far.out.find("seed (1e+30, 5) is outside the image"), std::string::npos) << far.out;
  const auto fractional = runCli("fit-rock --striper " + striper + " --seed 10.5,20");
  EXPECT_EQ(fractional.exit_code, 1);
  EXPECT_NE(fractional.out.find("whole pixels"), std::string::npos) << fractional.out;
  EXPECT_EQ(runCli("fit-rock --striper " + striper).exit_code, 1);
}

// A simulated scan's cloud, meshed, and a path across it: the path stays
// on the mesh and its simplification keeps within 5 % of the raw cost.
TEST(Cli, MeshAndPathOverASimulatedScan) {
  TempDir dir;
  const auto scan = (dir / "scan").string();
  ASSERT_EQ(runCli("sim-scan --seed 1 --out " + scan).exit_code, 0);
  const auto mesh = runCli("mesh --cloud " + scan + "/cloud.pcd --out " + scan + "/mesh.ply");
  ASSERT_EQ(mesh.exit_code, 0) << mesh.out;
  EXPECT_GT(nlohmann::json::parse(mesh.out)["mesh_triangles"].get<int>(), 100);
  const auto run = runCli("path --mesh " + scan + "/mesh.ply --from 0,7 --to 1,17 --cost slope");
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const auto out = nlohmann::json::parse(run.out);
  EXPECT_GE(out["path_len_m"].get<double>(), std::hypot(1.0, 10.0) - 1e-6);
  EXPECT_LT(out["waypoints"].size(), out["raw_waypoints"].get<std::size_t>());
  EXPECT_LE(out["cost_value"].get<double>(), 1.05 * out["raw_cost_value"].get<double>());
  const auto off = runCli("path --mesh " + scan + "/mesh.ply --from 0,7 --to 1,40");
  EXPECT_EQ(off.exit_code, 1);
  EXPECT_NE(off.out.find("the goal is not on the mesh"), std::string::npos) << off.out;
  EXPECT_EQ(runCli("mesh --cloud " + scan + "/missing.pcd --out " + scan + "/m.ply").exit_code, 1);
}

// Every reader of user files ends a hostile file in one line naming the file
// and the problem, and exit 1: the PCD on which PCL read past its buffer
// (tests/fuzz/corpus/fuzz_pcd), a cut PLY, a text file as camera image, a
// text file as mission log.
TEST(Cli, HostileFilesEndInAnErrorNamingTheFile) {
  TempDir dir;
  const auto pcd = dir / "bad.pcd";
  std::filesystem::copy_file(
      std::filesystem::path(AMBLER_FUZZ_CORPUS_DIR) / "fuzz_pcd" / "pcl-readheader-overflow.pcd",
      pcd);
  std::ofstream(dir / "cut.ply") << "ply\nformat ascii 1.0\nelement vertex 3\n";
  std::ofstream(dir / "words.txt") << "not an image, not a database, not a cloud";
  const std::string bad = pcd.string(), words = (dir / "words.txt").string();
  const std::pair<std::string, std::string> cases[] = {
      {"info " + bad, bad + ": PCD VIEWPOINT"},
      {"mesh --cloud " + bad + " --out " + (dir / "m.ply").string(), bad + ": PCD VIEWPOINT"},
      {"register " + bad + " " + bad, bad + ": PCD VIEWPOINT"},
      {"path --mesh " + (dir / "cut.ply").string() + " --from 0,0 --to 1,1",
       (dir / "cut.ply").string() + ": PLY header ends before end_header"},
      {"danger " + words + " --out " + (dir / "d").string(), words + ": image is not PNG"},
      {"log summary " + words, words + ": not a mission log"}};
  for (const auto& [args, message] : cases) {
    const auto run = runCli(args);
    EXPECT_EQ(run.exit_code, 1) << args << "\n" << run.out;
    EXPECT_EQ(run.out.rfind("ambler-cli: error: " + message, 0), 0u) << args << "\n" << run.out;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "m.ply"));
}

// Two simulated views of course 3, both in the world frame: ICP from a
// start 0.25 m and 2 degrees off lands within 1 % of the 2.9 m between
// them, on the identity. The first view's levelled cloud, without a prior,
// is found in the course's 1 m model at the sensor's pose.
TEST(Cli, RegisterAlignsTwoViewsAndLocalizesAScanInTheModel) {
  TempDir dir;
  const auto a = (dir / "a").string(), b = (dir / "b").string();
  const auto sim = runCli("sim-scan --seed 3 --at 2,-1,40 --out " + a);
  ASSERT_EQ(sim.exit_code, 0) << sim.out;
  ASSERT_EQ(runCli("sim-scan --seed 3 --at 1,1.5,47 --out " + b).exit_code, 0);
  const auto icp = runCli("register " + b + "/cloud.pcd " + a +
                          "/cloud.pcd --initial 0.2,-0.15,0.05,2 --out " + b + "/moved.pcd");
  ASSERT_EQ(icp.exit_code, 0) << icp.out;
  const auto r = nlohmann::json::parse(icp.out);
  const auto t = r["translation_m"];
  EXPECT_LT(std::hypot(t[0].get<double>(), t[1].get<double>(), t[2].get<double>()), 0.029);
  EXPECT_LT(std::abs(r["yaw_deg"].get<double>()), 0.2);
  EXPECT_TRUE(std::filesystem::exists(b + "/moved.pcd"));

  const auto global = runCli("register " + a + "/cloud_level.pcd " + a + "/model.pcd --global");
  ASSERT_EQ(global.exit_code, 0) << global.out;
  const auto g = nlohmann::json::parse(global.out);
  const auto pose = nlohmann::json::parse(sim.out)["sensor_pose"];
  EXPECT_LT(std::hypot(g["translation_m"][0].get<double>() - pose["x"].get<double>(),
                       g["translation_m"][1].get<double>() - pose["y"].get<double>()),
            0.5);
  EXPECT_LT(std::abs(g["yaw_deg"].get<double>() - 40.0), 2.0);

  const auto missing = runCli("register " + a + "/none.pcd " + a + "/cloud.pcd");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.out.find("none.pcd"), std::string::npos) << missing.out;
  const auto bad = runCli("register " + b + "/cloud.pcd " + a + "/cloud.pcd --initial 1,2,x,4");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.out.find("--initial"), std::string::npos) << bad.out;
  const auto spun =
      runCli("register " + b + "/cloud.pcd " + a + "/cloud.pcd --initial 0,0,0,1e30,0,0");
  EXPECT_EQ(spun.exit_code, 1);
  EXPECT_NE(spun.out.find("--initial roll 1e+30 deg is outside -360..360"), std::string::npos)
      << spun.out;
}

// A pair of noise-free scans from sim-pairs, in the world frame, from the
// guess it gives (six numbers turning about the source's scanner): within
// 1 % of the distance at that scanner, with a verdict. A pair of two
// different terrains is refused: exit 1, saying so.
TEST(Cli, SimPairsRegisterFromAFullGuessAndRefuseTwoDifferentTerrains) {
  TempDir dir;
  const auto out = (dir / "pairs").string();
  const auto sim = runCli("sim-pairs --tuning --count 1 --foreign 1 --noise 0 --out " + out);
  ASSERT_EQ(sim.exit_code, 0) << sim.out;
  std::ifstream file(out + "/pairs.json");
  const auto pairs = nlohmann::json::parse(file)["pairs"];
  ASSERT_EQ(pairs.size(), 2u);
  const auto& same = pairs[0]["world"];
  const auto run =
      runCli("register " + same["source"].get<std::string>() + " " +
             same["target"].get<std::string>() + " --initial " +
             same["initial"].get<std::string>() + " --about " + same["about"].get<std::string>());
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const auto r = nlohmann::json::parse(run.out);
  Eigen::Matrix4d m;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) m(i, j) = r["transform"][i][j].get<double>();
  Eigen::Vector4d scanner(0, 0, 0, 1);
  std::istringstream about(same["about"].get<std::string>());
  char comma = 0;
  about >> scanner[0] >> comma >> scanner[1] >> comma >> scanner[2];
  // The truth is the identity: the scanner stays where it is.
  EXPECT_LT((m * scanner - scanner).norm(), 0.01 * pairs[0]["distance_m"].get<double>());
  EXPECT_NE(r["quality"]["verdict"], "no overlap");
  EXPECT_GT(r["ms"].get<double>(), r["read_ms"].get<double>());

  const auto& other = pairs[1]["levelled"];
  const auto refused = runCli("register " + other["source"].get<std::string>() + " " +
                              other["target"].get<std::string>() + " --initial " +
                              other["initial"].get<std::string>());
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.out.find("do not overlap"), std::string::npos) << refused.out;
}

// Real terrain (USGS's Jacksboro fault DEM, Debian's python-matplotlib-data):
// the path keeps to triangles under its slope limit and its simplification
// within 5 % of the raw cost; three 5 km windows, turned and moved, are
// found in the 400 m model within half a cell and 2 degrees.
TEST(Cli, EvalDemMeshesPlansAndLocalizesOnRealTerrain) {
  const auto run = runCli("eval dem --windows 3 --json");
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const auto out = nlohmann::json::parse(run.out);
  EXPECT_EQ(out["points"].get<int>(), 344 * 403);
  EXPECT_GT(out["mesh_triangles"].get<int>(), 1000);
  const auto& path = out["path"];
  ASSERT_TRUE(path["found"].get<bool>()) << path.dump();
  EXPECT_LE(path["steepest_triangle_deg"].get<double>(), path["max_slope_deg"].get<double>());
  EXPECT_LT(path["waypoints"].get<int>(), path["raw_waypoints"].get<int>());
  EXPECT_LE(path["cost_value"].get<double>(), 1.05 * path["raw_cost_value"].get<double>());
  EXPECT_EQ(out["global_loc"]["success_rate"].get<double>(), 1.0) << out["global_loc"].dump();
  const auto bad = runCli("eval dem --dem /nonexistent.npz");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.out.find("no such file"), std::string::npos) << bad.out;
}

// A 640 x 480 grey image of bright sand with a dark rough patch near the
// rover: danger.tif finds the patch (recall >= 0.9 at D > 0.5), the sky
// above the horizon is NaN, and a bad camera file is named.
TEST(Cli, DangerWritesTheDegreeOfDangerOfAnImage) {
  TempDir dir;
  std::mt19937 rng(1);
  std::normal_distribution<double> sand(200, 3), rock(90, 40);
  std::string pixels;
  auto patch = [](int r, int c) { return r >= 380 && r < 440 && c >= 200 && c < 300; };
  for (int r = 0; r < 480; ++r)
    for (int c = 0; c < 640; ++c)
      pixels += char(std::clamp(int(patch(r, c) ? rock(rng) : sand(rng)), 0, 255));
  std::ofstream(dir / "ground.pgm", std::ios::binary) << "P5\n640 480\n255\n" << pixels;
  const auto run =
      runCli("danger " + (dir / "ground.pgm").string() + " --out " + (dir / "d").string());
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const auto out = nlohmann::json::parse(run.out);
  const int y_h = out["bands_rows_from_bottom"]["y_h"].get<int>();
  const auto danger = ambler::io::readFloatTiff(dir / "d" / "danger.tif");
  ASSERT_EQ(danger.rows, 480);
  int in = 0, found = 0;
  for (int r = 0; r < 480; ++r)
    for (int c = 0; c < 640; ++c) {
      if (479 - r >= y_h) {
        EXPECT_TRUE(std::isnan(danger(r, c)));
      }
      if (patch(r, c)) ++in, found += danger(r, c) > 0.5;
    }
  EXPECT_GE(double(found) / in, 0.9) << found << " of " << in;
  // The route and the sensing plan: found, starting with F, never on the
  // patch.
  const auto& route = out["route"];
  ASSERT_TRUE(route["found"].get<bool>()) << route.dump();
  for (const auto& p : route["route"])
    EXPECT_FALSE(patch(int(p[1].get<double>()), int(p[0].get<double>()))) << p.dump();
  EXPECT_EQ(out["sensing"][0]["action"].get<std::string>().substr(0, 2), "F:");
  std::ofstream(dir / "camera.json") << R"({"rows": 480, "alpha_deg": 10, "beta_deg": 40})";
  const auto bad = runCli("danger " + (dir / "ground.pgm").string() + " --camera " +
                          (dir / "camera.json").string() + " --out " + (dir / "e").string());
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.out.find("camera.json"), std::string::npos) << bad.out;
}

// Shaded images of course 1 from the simulator, facing the box and the
// ramp (0 deg) and across the course (90 deg): most of their pixels are
// dangerous, and the route found keeps off them.
TEST(Cli, EvalDangerOnShadedCourseImages) {
  const auto run = runCli("eval danger --seeds 1 --headings 0,90 --json");
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const auto out = nlohmann::json::parse(run.out);
  EXPECT_GE(out["recall"]["median"].get<double>(), 0.8) << out.dump();
  ASSERT_GE(out["routes_found"].get<int>(), 1);
  EXPECT_EQ(out["route_share_on_rough"]["max"].get<double>(), 0.0);
  // The same image as files, for the Danger map tab or `danger`.
  TempDir dir;
  const auto shot = runCli("sim-camera --seed 1 --at 0,0,90 --out " + (dir / "cam").string());
  ASSERT_EQ(shot.exit_code, 0) << shot.out;
  const auto image = ambler::io::readByteTiff(dir / "cam" / "image.tif");
  EXPECT_EQ(image.rows, 480);
  EXPECT_EQ(image.cols, 640);
  const auto danger =
      runCli("danger " + (dir / "cam" / "image.tif").string() + " --out " + (dir / "d").string());
  ASSERT_EQ(danger.exit_code, 0) << danger.out;
  EXPECT_TRUE(nlohmann::json::parse(danger.out)["route"]["found"].get<bool>());
}

// eval rocks on two trays: the figures the issue asks for, per method.
TEST(Cli, EvalRocksReportsEachMethod) {
  const auto run = runCli("eval rocks --seeds 1,2 --json");
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const auto out = nlohmann::json::parse(run.out);
  for (const char* condition : {"resting", "partly_buried"}) {
    const auto& c = out[condition];
    EXPECT_GE(c["auto_seed_recall"].get<double>(), 0.8);
    EXPECT_GE(c["contour_iou"]["median"].get<double>(), 0.8);
    for (const char* method : {"lm", "robust", "lm_solina"})
      for (const char* key : {"size_err_pct", "center_err_mm", "eps_err", "ms_per_fit"})
        EXPECT_TRUE(c[method].contains(key)) << condition << " " << method << " " << key;
  }
  // Resting rocks, robust fits: the median within the issue's bounds.
  EXPECT_LT(out["resting"]["robust"]["center_err_mm"]["median"].get<double>(), 5.0);
  EXPECT_LT(out["resting"]["robust"]["size_err_pct"]["median"].get<double>(), 10.0);
}

TEST(Cli, InfoDescribesAPcdPointCloud) {
  TempDir dir;
  std::ofstream(dir / "cloud.pcd") << "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\n"
                                      "TYPE F F F\nCOUNT 1 1 1\nWIDTH 3\nHEIGHT 1\n"
                                      "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n"
                                      "0 0 0\n1 2 3\n-1 5 0.5\n";
  const auto info = runCli("info " + (dir / "cloud.pcd").string());
  ASSERT_EQ(info.exit_code, 0) << info.out;
  const auto j = nlohmann::json::parse(info.out);
  EXPECT_EQ(j["points"], 3);
  EXPECT_EQ(j["bounds_m"]["min"][0], -1.0);
  EXPECT_EQ(j["bounds_m"]["max"][1], 5.0);
}

TEST(Cli, BadInputGivesAClearMessageAndNonZeroExit) {
  TempDir dir;
  std::ofstream(dir / "scan.tif") << "garbage";
  std::ofstream(dir / "scan.json") << "{}";
  const auto bad_file = runCli("info " + (dir / "scan.tif").string());
  EXPECT_EQ(bad_file.exit_code, 1);
  EXPECT_NE(bad_file.out.find("ambler-cli: error:"), std::string::npos) << bad_file.out;
  EXPECT_NE(bad_file.out.find("\"model\" is missing"), std::string::npos) << bad_file.out;

  std::ofstream(dir / "broken.pcd") << "# .PCD v0.7\nFIELDS x y\nPOINTS 9\n";
  const auto bad_pcd = runCli("info " + (dir / "broken.pcd").string());
  EXPECT_EQ(bad_pcd.exit_code, 1) << bad_pcd.out;
  EXPECT_NE(bad_pcd.out.find("broken.pcd: PCD no VERSION before FIELDS"), std::string::npos)
      << bad_pcd.out;
  // An empty cloud crashed PCL's reader (found by fuzz_pcd).
  std::ofstream(dir / "empty.pcd").flush();
  for (const char* command : {"info ", "mesh --out /dev/null --cloud ", "register "}) {
    std::string args = command + (dir / "empty.pcd").string();
    if (std::string(command) == "register ") args += " " + (dir / "empty.pcd").string();
    const auto empty = runCli(args);
    EXPECT_EQ(empty.exit_code, 1) << command << empty.out;
    EXPECT_NE(empty.out.find("empty.pcd: PCD file is empty"), std::string::npos) << empty.out;
  }

  const auto bad_region = runCli("sim-scan --out " + dir.path().string() + " --region 1,2,x,4");
  EXPECT_EQ(bad_region.exit_code, 1);
  EXPECT_NE(bad_region.out.find("'x' is not a number"), std::string::npos) << bad_region.out;

  // A kilometre square at 5 cm is 400 million cells: refused at once (eval
  // elevation had grown to 2.5 GB after 12 s, and kept on).
  for (const char* command : {"eval elevation --json", "sim-scan --out /dev/null"}) {
    const auto huge = runCli(std::string(command) + " --region 0,0,1000,1000");
    EXPECT_EQ(huge.exit_code, 1) << command << huge.out;
    EXPECT_NE(huge.out.find("of 20000x20000 cells is too large"), std::string::npos) << huge.out;
  }

  const auto out_of_range = runCli("sim-scan --out " + dir.path().string() + " --tilt 95");
  EXPECT_NE(out_of_range.exit_code, 0);
  EXPECT_NE(out_of_range.out.find("--tilt"), std::string::npos) << out_of_range.out;

  for (const char* command : {"sim-scan", "sim-camera"}) {
    const auto spun = runCli(std::string(command) + " --out /dev/null --at 0,0,1e30");
    EXPECT_EQ(spun.exit_code, 1) << command << spun.out;
    EXPECT_NE(spun.out.find("--at heading 1e+30 deg is outside -360..360"), std::string::npos)
        << spun.out;
  }

  const auto bad_family = runCli("sim-scan --out " + dir.path().string() + " --family dunes");
  EXPECT_NE(bad_family.exit_code, 0);
  EXPECT_NE(bad_family.out.find("unknown terrain family 'dunes'"), std::string::npos)
      << bad_family.out;

  // One column of rays has a footprint without width: refused before any
  // file is written (it used to fail on writing a 0-column truth TIFF, after
  // the scan and clouds were already out).
  const auto one_ray =
      runCli("sim-scan --out " + (dir / "one-ray").string() + " --rows 1 --cols 1");
  EXPECT_EQ(one_ray.exit_code, 1) << one_ray.out;
  EXPECT_NE(one_ray.out.find("truth grid covers no cells"), std::string::npos) << one_ray.out;
  EXPECT_FALSE(std::filesystem::exists(dir / "one-ray"));

  EXPECT_NE(runCli("info " + (dir / "nothing.xyz").string()).out.find("unknown kind"),
            std::string::npos);
}

TEST(Cli, MapWritesTheElevationMapOfAScanWithTheTruthGrid) {
  TempDir dir;
  ASSERT_EQ(runCli("sim-scan --seed 3 --region=-6,6,6,16 --out " + dir.path().string()).exit_code,
            0);
  const auto run = runCli("map --range " + (dir / "scan.tif").string() +
                          " --region=-6,6,6,16 --resolution 0.05 --out " + (dir / "map").string());
  ASSERT_EQ(run.exit_code, 0) << run.out;
  // The scanner's k = 2e-4: sqrt(0.3 m / (4 sqrt(2) k)).
  EXPECT_NEAR(nlohmann::json::parse(run.out)["oblique_beyond_m"].get<double>(), 16.28, 0.01);
  for (const char* f : {"elevation.tif", "sigma.tif", "state.tif", "count.tif", "map.json"})
    EXPECT_TRUE(std::filesystem::exists(dir / "map" / f)) << f;
  const auto header = nlohmann::json::parse(std::ifstream(dir / "map" / "map.json"));
  EXPECT_EQ(header["rows"], 200);
  EXPECT_EQ(header["cols"], 240);
  EXPECT_EQ(header["frame"], "world");
  // Same grid as the simulator's truth: compare cell by cell.
  const auto z = ambler::io::readFloatTiff(dir / "map" / "elevation.tif");
  const auto state = ambler::io::readByteTiff(dir / "map" / "state.tif");
  const auto truth_z = ambler::io::readFloatTiff(dir / "truth_z.tif");
  const auto truth_state = ambler::io::readByteTiff(dir / "truth_visible.tif");
  // Known or oblique (state 3: beyond 16.3 m this scanner's noise could hide
  // a foot-sized gap), each visible cell has a height.
  int with_height = 0, visible = 0, close = 0;
  for (std::size_t i = 0; i < z.pixels.size(); ++i) {
    if (truth_state.pixels[i] != 0) continue;
    ++visible;
    if (state.pixels[i] != 0 && state.pixels[i] != 3) continue;
    ++with_height;
    close += std::abs(z.pixels[i] - truth_z.pixels[i]) < 0.05;
  }
  EXPECT_GT(with_height, visible * 95 / 100);
  EXPECT_GT(close, with_height * 98 / 100);
}

TEST(Cli, MapRefusesBadArgumentsWithAMessage) {
  TempDir dir;
  ASSERT_EQ(runCli("sim-scan --rows 32 --cols 32 --out " + dir.path().string()).exit_code, 0);
  const std::string scan = (dir / "scan.tif").string();
  auto run = runCli("map --range " + scan + " --region=1,2,3 --out " + (dir / "m").string());
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.out.find("XMIN,YMIN,XMAX,YMAX"), std::string::npos) << run.out;
  run = runCli("map --range " + scan + " --region=0,0,1,1 --method spline --out " +
               (dir / "m").string());
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.out.find("spline"), std::string::npos) << run.out;
  // A rule's length is above 0, or inf to turn the rule off; NaN is no length.
  for (const char* value : {"nan", "0", "-0.3"}) {
    run = runCli("map --range " + scan + " --region=0,0,1,1 --max-gap-hidden-by-noise " + value +
                 " --out " + (dir / "m").string());
    EXPECT_EQ(run.exit_code, 105) << value;
    EXPECT_NE(run.out.find(std::string("'") + value + "' is not a length"), std::string::npos)
        << run.out;
  }
  run = runCli("map --range " + scan + " --region=0,0,1,1 --max-gap-hidden-by-noise inf " +
               "--max-sample-spacing inf --out " + (dir / "m").string());
  EXPECT_EQ(run.exit_code, 0) << run.out;
}

// footfall on a simulated map: the printed best foothold is the minimum of
// the written score map, and the composite writes its cost layers.
TEST(Cli, FootfallWritesScoresAndPrintsTheBestFoothold) {
  TempDir dir;
  ASSERT_EQ(runCli("sim-scan --seed 3 --out " + dir.path().string()).exit_code, 0);
  ASSERT_EQ(runCli("map --range " + (dir / "scan.tif").string() +
                   " --region=-2,6,2,10 --resolution 0.02 --out " + (dir / "map").string())
                .exit_code,
            0);
  const std::string map = " --map " + (dir / "map").string();
  auto run = runCli("footfall" + map + " --region=-1,7,1,9 --criterion freevolume --out " +
                    (dir / "ff").string());
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const auto printed = nlohmann::json::parse(run.out);
  ASSERT_TRUE(printed["best"]["found"].get<bool>());
  EXPECT_EQ(printed["unit"], "m^3");
  const auto header = nlohmann::json::parse(std::ifstream(dir / "ff" / "footfall.json"));
  const auto score = ambler::io::readFloatTiff(dir / "ff" / "score.tif");
  EXPECT_EQ(score.rows, header["rows"].get<int>());
  EXPECT_EQ(score.cols, header["cols"].get<int>());
  float lowest = INFINITY;
  int valid = 0;
  for (const float v : score.pixels)
    if (std::isfinite(v)) lowest = std::min(lowest, v), ++valid;
  EXPECT_EQ(valid, printed["valid"].get<int>());
  EXPECT_GT(valid, 1000);
  EXPECT_FLOAT_EQ(printed["best"]["score"].get<float>(), lowest);

  run = runCli("footfall" + map + " --region=-1,7,1,9 --criterion composite --scanner 0,0,90,60 " +
               "--out " + (dir / "cost").string());
  ASSERT_EQ(run.exit_code, 0) << run.out;
  for (const char* f : {"score.tif", "roughness.tif", "slope.tif", "body_advance.tif",
                        "visibility.tif", "footfall.json"})
    EXPECT_TRUE(std::filesystem::exists(dir / "cost" / f)) << f;

  run = runCli("footfall" + map + " --region=50,50,51,51 --out " + (dir / "x").string());
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.out.find("no cell centre of the map"), std::string::npos) << run.out;
  run = runCli("footfall" + map + " --region=-1,7,1,9 --criterion composite --leg 1 --out " +
               (dir / "x").string());
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.out.find("X,Y"), std::string::npos) << run.out;
}

// A small slice of `eval elevation`: the locus method beats binning at each
// noise level and finds the shadows (docs and README carry the full run).
TEST(Cli, EvalElevationShowsLocusBeatingBinning) {
  const auto run = runCli(
      "eval elevation --json --families course --seeds 1 --poses 5:30 --noise 0,0.0002 "
      "--threads 2");
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const auto report = nlohmann::json::parse(run.out);
  EXPECT_EQ(report["scenes"], 2);
  EXPECT_EQ(report["seed_set"], "given");
  const auto& locus = report["methods"]["locus"];
  const auto& binning = report["methods"]["binning"];
  for (int level = 0; level < 2; ++level) {
    const auto &l = locus["by_noise"][level], &b = binning["by_noise"][level];
    EXPECT_LT(l["rmse_m"].get<double>(), b["rmse_m"].get<double>()) << level;
    // And on the cells both know, which are fewer than either knows.
    EXPECT_LT(l["rmse_on_shared_cells_m"].get<double>(), b["rmse_on_shared_cells_m"].get<double>())
        << level;
    EXPECT_EQ(l["shared_cells"], b["shared_cells"]);
    EXPECT_GT(l["shared_cells"].get<long>(), 0);
    EXPECT_LE(l["shared_cells"].get<long>(), b["known_cells"].get<long>());
  }
  // Without noise the map knows nearly all it sees; with it, ground beyond
  // 16.3 m, whose noise could hide a foot-sized gap, is oblique.
  EXPECT_GT(locus["by_noise"][0]["coverage"].get<double>(), 0.9);
  // What is seen but not known is oblique: grazing ground 15 m out.
  EXPECT_GT(locus["coverage"].get<double>() + locus["oblique_coverage"].get<double>(), 0.95);
  EXPECT_GT(locus["shadow_recall"].get<double>(), 0.9);
  EXPECT_GT(locus["shadow_precision"].get<double>(), 0.9);
  EXPECT_GE(locus["shadow_recall_within_1_cell"].get<double>(),
            locus["shadow_recall"].get<double>());
  EXPECT_GT(locus["ms_per_map"].get<double>(), 0.0);
  EXPECT_EQ(binning["shadow_recall"], 0.0);  // binning cannot tell a shadow
  EXPECT_EQ(report["families"].size(), 1u);
  EXPECT_TRUE(report["families"].contains("course"));
  // Nine foothold regions per map, two maps; noise-free on the course with
  // the scanner high, no best foothold stands on cells nobody saw.
  EXPECT_GT(locus["footholds"].get<int>(), 9);
  EXPECT_LE(locus["footholds"].get<int>(), 18);
  EXPECT_EQ(locus["by_noise"][0]["footholds_on_unseen_cells"], 0);
}

// Each terrain family builds and scores; names and placements that do not
// parse are refused with the option named.
TEST(Cli, EvalElevationCoversTheFamiliesAndRefusesBadOptions) {
  auto run = runCli(
      "eval elevation --json --families rocks,craters,rough,negative,slope --seeds 1 "
      "--poses 4:30 --noise 0 --region=-4,4,4,12");
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const auto report = nlohmann::json::parse(run.out);
  EXPECT_EQ(report["families"].size(), 5u);
  for (const auto& [name, family] : report["families"].items())
    EXPECT_GT(family["methods"]["locus"]["coverage"].get<double>(), 0.8) << name;
  run = runCli("eval elevation --families moon --seeds 1 --noise 0");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.out.find("moon"), std::string::npos) << run.out;
  run = runCli("eval elevation --families course --poses 30 --seeds 1 --noise 0");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.out.find("HEIGHT:TILT"), std::string::npos) << run.out;
}

}  // namespace

namespace {

// walk prints the issue's keys; a broken rover configuration is named.
// The Ambler crosses a 20 % Golombek-Rapp rock field and a crater field
// (the simulator's truth counts CSP violations and leg collisions).
TEST(Cli, WalksOnARockFieldAndACraterField) {
  for (const char* course : {"rocks20", "craters"}) {
    const auto run =
        runCli(std::string("walk --course ") + course + " --seed 1001 --steps 8 --json");
    ASSERT_EQ(run.exit_code, 0) << run.out;
    const auto j = nlohmann::json::parse(run.out);
    EXPECT_EQ(j["steps"], 8) << course;
    EXPECT_EQ(j["csp_violations"], 0) << course;
    EXPECT_EQ(j["leg_collisions"], 0) << course;
    EXPECT_GT(j["distance_m"].get<double>(), 2.5) << course;
  }
  EXPECT_NE(runCli("walk --course moon --steps 2").exit_code, 0);
}

// Long evaluations show where they are on a terminal (script(1) gives the
// command one), and nothing but JSON when read by a program, as in every
// other test here.
TEST(Cli, LongEvaluationsShowProgressOnATerminalOnly) {
  TempDir dir;
  const std::string eval = std::string(AMBLER_CLI) +
                           " eval walk --course rocks20 --seeds 3 --steps 2 --repetitions 0 "
                           "--json > " +
                           (dir / "walk.json").string();
  const auto on_terminal = runProgram("script", "-qec '" + eval + "' /dev/null");
  ASSERT_EQ(on_terminal.exit_code, 0) << on_terminal.out;
  EXPECT_NE(on_terminal.out.find("eval walk: 1 of 1, rocks20 seed 3, 2 steps ..."),
            std::string::npos)
      << on_terminal.out;
  EXPECT_EQ(nlohmann::json::parse(std::ifstream(dir / "walk.json"))["walks"], 1);

  const auto piped =
      runCli("eval walk --course rocks20 --seeds 3 --steps 2 --repetitions 0 --json");
  ASSERT_EQ(piped.exit_code, 0) << piped.out;
  EXPECT_EQ(piped.out.find("eval walk:"), std::string::npos) << piped.out;
  EXPECT_EQ(nlohmann::json::parse(piped.out)["walks"], 1);
}

TEST(Cli, WalkPrintsTheWalksFigures) {
  const auto run = runCli("walk --seed 4 --steps 6 --json");
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const auto j = nlohmann::json::parse(run.out);
  for (const char* key :
       {"steps", "distance_m", "min_stability_margin_m", "csp_violations", "leg_collisions",
        "plan_ms_median", "pose_error_final_m", "pose_error_max_m", "dead_reckoning_error_final_m",
        "dead_reckoning_error_max_m", "scans_registered"})
    EXPECT_TRUE(j.contains(key)) << key;
  // One scan before each step and the closing scan; the first has no map
  // to be matched against.
  EXPECT_EQ(j["scans_registered"].get<int>() + j["scans_not_registered"].get<int>(), 7);
  EXPECT_GE(j["scans_not_registered"].get<int>(), 1);
  EXPECT_EQ(j["steps"], 6);
  EXPECT_EQ(j["csp_violations"], 0);
  EXPECT_GT(j["distance_m"].get<double>(), 1.0);

  TempDir dir;
  std::ofstream(dir / "rover.json") << R"({"gait": {"csp_margin_m": -1}})";
  const auto bad = runCli("walk --steps 2 --config " + (dir / "rover.json").string());
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.out.find("csp_margin_m"), std::string::npos) << bad.out;
  EXPECT_NE(bad.out.find("rover.json"), std::string::npos) << bad.out;
  EXPECT_NE(runCli("walk --radius 5 --turn left").exit_code, 0);  // one or the other
  // An arc needs a radius it can follow: NaN once walked nowhere, saying
  // that no leg could reach a foothold.
  for (const char* radius : {"nan", "inf", "0"}) {
    const auto arc = runCli(std::string("walk --steps 1 --radius ") + radius);
    EXPECT_NE(arc.exit_code, 0) << radius;
    EXPECT_NE(arc.out.find("--radius: must be a finite number"), std::string::npos) << arc.out;
  }
}

TEST(Cli, EvalWalkComparesConcurrentAndSequentialPlanning) {
  const auto run = runCli("eval walk --seeds 3,4 --steps 5 --repetitions 3 --json");
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const auto j = nlohmann::json::parse(run.out);
  EXPECT_EQ(j["walks"], 2);
  EXPECT_EQ(j["course"], "traverse");
  EXPECT_EQ(j["csp_violations"], 0);
  EXPECT_EQ(j["leg_collisions"], 0);
  EXPECT_GT(j["distance_m"]["median"].get<double>(), 1.0);
  EXPECT_LT(j["pose_error_final_m"]["max"].get<double>(), 0.05);
  ASSERT_EQ(j["per_walk"].size(), 2u);
  for (const auto& w : j["per_walk"]) {
    EXPECT_EQ(w["steps"], 5);
    EXPECT_GE(w["registered"]["max_m"].get<double>(), w["registered"]["final_m"].get<double>());
    EXPECT_GE(w["dead_reckoning"]["max_m"].get<double>(),
              w["dead_reckoning"]["final_m"].get<double>());
    // The root mean square over the steps lies between nothing and the worst.
    for (const char* estimate : {"registered", "dead_reckoning"}) {
      const double rms = w[estimate]["rms_m"].get<double>();
      EXPECT_GT(rms, 0.0) << estimate;
      EXPECT_LE(rms, w[estimate]["max_m"].get<double>()) << estimate;
      EXPECT_GT(w[estimate]["heading_rms_rad"].get<double>(), 0.0) << estimate;
      EXPECT_LT(w[estimate]["heading_rms_rad"].get<double>(), 0.05) << estimate;
    }
    EXPECT_GT(w["scans_registered"].get<int>(), 0);
  }
  EXPECT_EQ(j["wall_saving_pct"]["runs"], 3);
  EXPECT_LE(j["wall_saving_pct"]["min"].get<double>(),
            j["wall_saving_pct"]["median"].get<double>());
  EXPECT_GT(j["speed_while_moving_m_per_min"].get<double>(), 0.0);
}

// `eval all` runs the chosen evaluations and lines their headline figures
// up with the papers'; evaluations left out have no figure.
TEST(Cli, EvalAllCombinesTheEvaluationsWithASummary) {
  const auto run = runCli("eval all --only link --json");
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const auto json_start = run.out.find("{\n");  // progress lines come first on stderr
  ASSERT_NE(json_start, std::string::npos) << run.out;
  const auto j = nlohmann::json::parse(run.out.substr(json_start));
  ASSERT_TRUE(j.contains("link"));
  EXPECT_FALSE(j.contains("elevation"));
  EXPECT_GT(j["link"]["range_images_per_s"].get<double>(), 0.0);
  bool link_row = false, elevation_row = false;
  for (const auto& row : j["summary"]) {
    const std::string from = row["from"];
    if (from.rfind("/link/", 0) == 0) {
      link_row = true;
      EXPECT_TRUE(row["measured"].is_number()) << from;
    }
    if (from.rfind("/elevation/", 0) == 0) {
      elevation_row = true;
      EXPECT_TRUE(row["measured"].is_null()) << from;
    }
  }
  EXPECT_TRUE(link_row && elevation_row);
  EXPECT_NE(run.out.find("eval all: [1/1] link"), std::string::npos) << run.out;
  EXPECT_NE(runCli("eval all --only nonsense").exit_code, 0);
}

TEST(Cli, KeygenMakesAKeyForTheConsoleAndTheRoversEntry) {
  TempDir dir;
  const auto file = (dir / "alice.key").string();
  const auto run = runCli("keygen --operator alice --out " + file);
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const auto j = nlohmann::json::parse(run.out);
  const auto key = ambler::link::readOperatorKey(file);
  EXPECT_EQ(key.operator_id, "alice");
  EXPECT_EQ(j["rover_entry"]["key_hex"], ambler::link::keyHex(key));
  const auto again = runCli("keygen --operator alice --out " + file);
  EXPECT_EQ(again.exit_code, 1);
  EXPECT_NE(again.out.find("not replacing"), std::string::npos) << again.out;
  EXPECT_EQ(ambler::link::readOperatorKey(file).key, key.key);
}

TEST(Cli, LogSummaryCountsMessagesAndDecisions) {
  TempDir dir;
  const auto path = dir / "mission.sqlite";
  {
    ambler::missionlog::MissionLog log(path, "summary test");
    for (int i = 0; i < 3; ++i)
      log.record(100.0 + i, ambler::link::Telemetry{1, 0.0, ambler::link::Heartbeat{}});
    ambler::link::Command c;
    c.operator_id = "alice", c.sequence = 1, c.body = ambler::link::Hold{};
    log.record(101.5, c);
    log.record({102.5, "alice", 1, ambler::missionlog::Verdict::kApproved, ""});
    log.record({103.5, "alice", 2, ambler::missionlog::Verdict::kRejected, "in shadow"});
  }
  const auto run = runCli("log summary " + path.string() + " --json");
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const auto summary = nlohmann::json::parse(run.out);
  EXPECT_EQ(summary["mission"], "summary test");
  EXPECT_EQ(summary["messages"], 4);
  EXPECT_EQ(summary["from_rover"]["Heartbeat"], 3);
  EXPECT_EQ(summary["to_rover"]["Hold"], 1);
  EXPECT_DOUBLE_EQ(summary["duration_s"].get<double>(), 3.5);
  EXPECT_EQ(summary["steps_approved"], 1);
  EXPECT_EQ(summary["steps_rejected"], 1);

  const auto bad = runCli("log summary " + (dir / "none.sqlite").string());
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.out.find("none.sqlite: no such file"), std::string::npos) << bad.out;
}

TEST(Cli, EvalLinkTimesRoundTripsThroughAmblerSim) {
  // ambler-sim sits next to ambler-cli; a domain of this process's own.
  const auto domain = std::to_string(20 + ::getpid() % 200);
  const auto run = runCli("eval link --round-trips 20 --scans 2 --domain " + domain);
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const auto j = nlohmann::json::parse(run.out);
  const auto& rt = j["round_trip_ms"];
  EXPECT_EQ(rt["n"], 20);
  EXPECT_GT(rt["p50"].get<double>(), 0.0);
  EXPECT_GE(rt["p99"].get<double>(), rt["p50"].get<double>());
  EXPECT_GE(rt["max"].get<double>(), rt["p99"].get<double>());
  EXPECT_GT(j["range_images_per_s"].get<double>(), 0.0);
  EXPECT_GT(j["range_image_kb"].get<double>(), 0.0);
}

// ambler-sim stands the rover on a terrain family's ground, as ambler-gs
// --family does, and says so when ready; an unknown family, or one beside
// a terrain model, is refused.
TEST(Cli, AmblerSimServesATerrainFamily) {
  const auto domain = std::to_string(20 + ::getpid() % 200);
  const auto run = runSim("--family craters --seed 4 --duration 0.2 --domain " + domain);
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const auto at = run.out.find("{\"ambler_sim\":\"ready\"");
  ASSERT_NE(at, std::string::npos) << run.out;
  const auto ready = nlohmann::json::parse(run.out.substr(at, run.out.find('\n', at) - at));
  EXPECT_EQ(ready["terrain"], "craters");
  EXPECT_EQ(ready["seed"], 4);
  const auto moon = runSim("--family moon --duration 0.2");
  EXPECT_NE(moon.exit_code, 0);
  EXPECT_NE(moon.out.find("moon not in"), std::string::npos) << moon.out;
  const auto both = runSim("--family rocks --dtm " + std::string(AMBLER_CLI) + " --duration 0.2");
  EXPECT_NE(both.exit_code, 0);
  EXPECT_NE(both.out.find("excludes"), std::string::npos) << both.out;
}

TEST(Cli, DriveRefusesToRunWithoutAnOperatorOrAutoApprove) {
  TempDir dir;
  std::ofstream(dir / "alice.json")
      << R"({"operator": "alice", "key_hex": ")" << std::string(64, '7') << R"("})";
  const auto run = runCli("drive --domain 231 --key " + (dir / "alice.json").string() + " --log " +
                          (dir / "m.db").string());
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.out.find("pass --auto-approve"), std::string::npos) << run.out;
  // The walk's path is checked as `walk` checks it, before anything is sent.
  const auto arc = runCli("drive --auto-approve --radius nan --key " +
                          (dir / "alice.json").string() + " --log " + (dir / "m.db").string());
  EXPECT_NE(arc.exit_code, 0);
  EXPECT_NE(arc.out.find("--radius: must be a finite number"), std::string::npos) << arc.out;
}

}  // namespace
