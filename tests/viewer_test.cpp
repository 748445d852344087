// The run viewer's data: traces read back exactly, what is thinned and what is kept, and the
// HTML page and SVG figure built from them. (The page itself is tested in a browser:
// tests/browser/viewer_test.mjs.)
#include "plumetrace/view/viewer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/trace_io.hpp"
#include "plumetrace/sim/trace.hpp"
#include "plumetrace/sim/world.hpp"
#include "support/command.hpp"
#include "support/temp_path.hpp"
#include "view/view_data.hpp"

namespace plumetrace {
namespace {

using nlohmann::json;

// a run of every layer: casting from 6 m, filaments every second
RecordedRun recorded_run(double snapshot_interval = 1.0) {
  Scenario s;
  s.robot.start.x = 6.0;
  s.supervisor.timeout = 120.0;
  RecordedRun run;
  run.scenario = s;
  run.info = {"casting", 7, 2};
  run.version = std::string(version());
  TraceRecorder recorder(run.trace, snapshot_interval, s.sim.dt);
  run.result = run_once(s, 7, 2, std::ref(recorder));
  return run;
}

std::vector<TraceStep> steps_with_states(const std::vector<std::string>& states) {
  std::vector<TraceStep> steps(states.size());
  for (std::size_t i = 0; i < steps.size(); ++i) {
    steps[i].time = 0.032 * static_cast<double>(i);
    steps[i].pose = {0.003 * static_cast<double>(i), 0.2 * std::sin(0.002 * static_cast<double>(i)),
                     0.0};
    steps[i].state = states[i];
  }
  return steps;
}

double segment_distance(double px, double py, double ax, double ay, double bx, double by) {
  const double dx = bx - ax, dy = by - ay;
  double t = ((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy);
  t = std::max(0.0, std::min(1.0, t));
  return std::hypot(px - ax - t * dx, py - ay - t * dy);
}

TEST(Viewer, SimplifyKeepsTheEndsOfAStraightLineOnly) {
  std::vector<double> x, y;
  for (int i = 0; i < 100; ++i) x.push_back(0.1 * i), y.push_back(0.05 * i);
  EXPECT_EQ(view::simplify(x, y, 1e-9), (std::vector<std::size_t>{0, 99}));
  EXPECT_EQ(view::simplify({1.0}, {2.0}, 0.1), (std::vector<std::size_t>{0}));
  EXPECT_TRUE(view::simplify({}, {}, 0.1).empty());
}

TEST(Viewer, SimplifiedPathStaysWithinTheTolerance) {
  // a spiral sampled finely: 20 000 points, most of them dropped
  std::vector<double> x, y;
  for (int i = 0; i < 20000; ++i) {
    const double a = 0.002 * i;
    x.push_back(0.1 * a * std::cos(a));
    y.push_back(0.1 * a * std::sin(a));
  }
  const double tol = 0.001;
  const auto kept = view::simplify(x, y, tol);
  ASSERT_GE(kept.size(), 2u);
  EXPECT_EQ(kept.front(), 0u);
  EXPECT_EQ(kept.back(), x.size() - 1);
  EXPECT_LT(kept.size(), x.size() / 10);
  for (std::size_t j = 1; j < kept.size(); ++j) {
    ASSERT_LT(kept[j - 1], kept[j]);
    for (std::size_t i = kept[j - 1] + 1; i < kept[j]; ++i) {
      ASSERT_LE(
          segment_distance(x[i], y[i], x[kept[j - 1]], y[kept[j - 1]], x[kept[j]], y[kept[j]]), tol)
          << "point " << i;
    }
  }
}

TEST(Viewer, PathVerticesKeepEveryChangeOfState) {
  std::vector<std::string> states;
  for (int i = 0; i < 3000; ++i) states.push_back((i / 700) % 2 ? "cast" : "surge");
  const auto steps = steps_with_states(states);
  const auto kept = view::path_steps(steps, 0.001);
  EXPECT_EQ(kept.front(), 0u);
  EXPECT_EQ(kept.back(), steps.size() - 1);
  // the last step before each change is a vertex, and each segment lies in one state
  for (std::size_t i = 1; i < steps.size(); ++i) {
    if (steps[i].state != steps[i - 1].state) {
      EXPECT_TRUE(std::binary_search(kept.begin(), kept.end(), i - 1)) << i;
    }
  }
  for (std::size_t j = 1; j < kept.size(); ++j) {
    for (std::size_t i = kept[j - 1] + 1; i <= kept[j]; ++i) {
      ASSERT_EQ(steps[i].state, steps[kept[j]].state) << "segment ending at " << kept[j];
    }
  }
  EXPECT_LT(kept.size(), steps.size() / 4);
}

TEST(Viewer, FramesFitTheBudgetAndKeepEveryChangeOfState) {
  std::vector<std::string> states(40001, "upwind");
  for (std::size_t i = 12345; i < 12350; ++i) states[i] = "crosswind";
  const auto steps = steps_with_states(states);
  const auto frames = view::frame_steps(steps, 1000);
  EXPECT_LE(frames.size(), 1000u + 2u);
  EXPECT_EQ(frames.front(), 0u);
  EXPECT_EQ(frames.back(), steps.size() - 1);
  EXPECT_TRUE(std::binary_search(frames.begin(), frames.end(), 12345u));
  EXPECT_TRUE(std::binary_search(frames.begin(), frames.end(), 12350u));
  // a short run keeps every step
  EXPECT_EQ(view::frame_steps(steps_with_states({"a", "a", "b"}), 1000).size(), 3u);
}

TEST(Viewer, ThinEvenlyKeepsTheEndsAndTheCount) {
  EXPECT_EQ(view::thin_evenly(5, 10), (std::vector<std::size_t>{0, 1, 2, 3, 4}));
  EXPECT_EQ(view::thin_evenly(11, 3), (std::vector<std::size_t>{0, 5, 10}));
  const auto kept = view::thin_evenly(4801, 600);
  EXPECT_EQ(kept.size(), 600u);
  EXPECT_EQ(kept.back(), 4800u);
  for (std::size_t j = 1; j < kept.size(); ++j) {
    EXPECT_GE(kept[j] - kept[j - 1], 8u);
    EXPECT_LE(kept[j] - kept[j - 1], 9u);
  }
  EXPECT_TRUE(view::thin_evenly(0, 10).empty());
}

TEST(Viewer, DetectionsKeepEveryOnsetAndThinTheRest) {
  auto steps = steps_with_states(std::vector<std::string>(200, "s"));
  for (std::size_t i = 0; i < steps.size(); ++i) {
    steps[i].pose = {static_cast<double>(i) / 256.0, 0.0, 0.0};  // 1/256 m per step, exactly
    steps[i].odor = (i >= 10 && i < 100) || i == 150;
  }
  const auto kept = view::detection_steps(steps, 5.0 / 256.0);
  // 90 steps in odor from step 10: one every 5 steps, then the onset at 150
  std::vector<std::size_t> expected;
  for (std::size_t i = 10; i < 100; i += 5) expected.push_back(i);
  expected.push_back(150);
  EXPECT_EQ(kept, expected);
}

TEST(Viewer, Base64MatchesRfc4648) {
  const auto b64 = [](const std::string& s) {
    return view::base64(std::vector<std::uint8_t>(s.begin(), s.end()));
  };
  EXPECT_EQ(b64(""), "");
  EXPECT_EQ(b64("f"), "Zg==");
  EXPECT_EQ(b64("fo"), "Zm8=");
  EXPECT_EQ(b64("foo"), "Zm9v");
  EXPECT_EQ(b64("foobar"), "Zm9vYmFy");
  EXPECT_EQ(view::base64({0xff, 0xfe, 0x00}), "//4A");
}

TEST(Trace, JsonTraceReadsBackBitForBit) {
  const RecordedRun run = recorded_run();
  const std::string path = testing::temp_path("trace", ".json");
  write_trace(path, run.trace, run.scenario, run.result, run.info);
  const RecordedRun back = read_trace(path);

  EXPECT_EQ(scenario_to_json(back.scenario), scenario_to_json(run.scenario));
  EXPECT_EQ(result_to_json(back.result, back.info), result_to_json(run.result, run.info));
  EXPECT_EQ(back.version, run.version);
  ASSERT_EQ(back.trace.steps.size(), run.trace.steps.size());
  for (std::size_t i = 0; i < run.trace.steps.size(); ++i) {
    const TraceStep &a = run.trace.steps[i], &b = back.trace.steps[i];
    ASSERT_EQ(std::memcmp(&a.pose, &b.pose, sizeof a.pose), 0) << i;
    ASSERT_EQ(a.time, b.time);
    ASSERT_EQ(a.odometer, b.odometer);
    ASSERT_EQ(a.state, b.state);
    ASSERT_EQ(a.odor, b.odor);
    ASSERT_EQ(a.concentration, b.concentration);
    ASSERT_EQ(a.wind_samples, b.wind_samples);
    if (a.wind_samples > 0) {
      ASSERT_EQ(a.wind_body.x, b.wind_body.x);
    }
  }
  ASSERT_EQ(back.trace.snapshots.size(), run.trace.snapshots.size());
  EXPECT_EQ(back.trace.snapshots.back().x, run.trace.snapshots.back().x);
  EXPECT_EQ(back.trace.snapshots.back().w, run.trace.snapshots.back().w);
}

TEST(Trace, SnapshotsCarryTheTrueWindOnTheTraceGridAndReadItBack) {
  RecordedRun run = recorded_run();
  const WindGrid& g = run.trace.wind_grid;
  // the default arena, 16 m by 4 m, in 1 m by 0.5 m cells at the sensor's height
  EXPECT_EQ(g.nx, 16);
  EXPECT_EQ(g.ny, 8);
  EXPECT_DOUBLE_EQ(g.x0, 0.5);
  EXPECT_DOUBLE_EQ(g.y0, -1.75);
  EXPECT_DOUBLE_EQ(g.z, run.scenario.odor.height);
  ASSERT_FALSE(run.trace.snapshots.empty());
  for (const auto& snap : run.trace.snapshots) {
    ASSERT_EQ(snap.wind_x.size(), g.size());
    ASSERT_EQ(snap.wind_y.size(), g.size());
    for (std::size_t k = 0; k < g.size(); ++k) {
      ASSERT_EQ(snap.wind_x[k], run.scenario.wind.velocity.x);
      ASSERT_EQ(snap.wind_y[k], run.scenario.wind.velocity.y);
    }
  }
  const std::string path = testing::temp_path("wind", ".json");
  write_trace(path, run.trace, run.scenario, run.result, run.info);
  const RecordedRun back = read_trace(path);
  EXPECT_EQ(back.trace.wind_grid.nx, g.nx);
  EXPECT_EQ(back.trace.wind_grid.dy, g.dy);
  EXPECT_EQ(back.trace.snapshots.back().wind_x, run.trace.snapshots.back().wind_x);

  // a snapshot whose wind does not fit the grid is refused, naming the file
  run.trace.snapshots.back().wind_x.pop_back();
  run.trace.snapshots.back().wind_y.pop_back();
  const std::string bad = testing::temp_path("badwind", ".json");
  write_trace(bad, run.trace, run.scenario, run.result, run.info);
  try {
    read_trace(bad);
    FAIL() << "a wind field of the wrong size was read";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("wind_grid"), std::string::npos) << e.what();
  }
}

TEST(Trace, JsonTraceWrittenPieceByPieceIsTheDumpOfTheWholeDocument) {
  const RecordedRun run = recorded_run();
  ASSERT_GT(run.trace.snapshots.size(), 2u);
  const std::string path = testing::temp_path("pieces", ".json");
  write_trace(path, run.trace, run.scenario, run.result, run.info);
  const std::string text = testing::read_file(path);
  // nlohmann's dump is canonical (sorted keys, no spaces, shortest round-trip numbers): the
  // file must be exactly that of the document it holds
  const auto doc = nlohmann::json::parse(text);
  EXPECT_EQ(doc.dump() + "\n", text);
  EXPECT_EQ(doc["snapshots"].size(), run.trace.snapshots.size());
  EXPECT_EQ(doc["steps"]["x"].size(), run.trace.steps.size());
}

TEST(Trace, ReadingABadTraceNamesTheFile) {
  const auto message = [](const std::string& path) -> std::string {
    try {
      read_trace(path);
    } catch (const std::exception& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_THROW(read_trace("no/such/trace.json"), IoError);
  EXPECT_NE(message("no/such/trace.json").find("no/such/trace.json"), std::string::npos);
  EXPECT_THROW(read_trace("run.csv"), ConfigError);
  EXPECT_NE(message("run.csv").find("CSV trace carries no configuration"), std::string::npos);

  const std::string not_json = testing::temp_path("broken", ".json");
  std::ofstream(not_json) << "{\"plumetrace_trace\": 1, \"config\": ";
  EXPECT_THROW(read_trace(not_json), ConfigError);
  EXPECT_NE(message(not_json).find(not_json), std::string::npos);

  const std::string other = testing::temp_path("other", ".json");
  std::ofstream(other) << "{\"points\": []}";
  EXPECT_NE(message(other).find("not a plumetrace trace"), std::string::npos);

  RecordedRun run = recorded_run(0.0);
  run.trace.steps.clear();
  const std::string empty = testing::temp_path("empty", ".json");
  write_trace(empty, run.trace, run.scenario, run.result, run.info);
  EXPECT_NE(message(empty).find("no steps"), std::string::npos) << message(empty);

  const std::string bad_key = testing::temp_path("badkey", ".json");
  std::ofstream(bad_key) << "{\"plumetrace_trace\": 1, \"config\": {\"wind\": {\"vq\": 1}}}";
  EXPECT_NE(message(bad_key).find("wind.vq"), std::string::npos);
}

// the JSON data the page carries
json page_data(const std::string& html) {
  const std::string open = "<script id=\"plumetrace-data\" type=\"application/json\">";
  const auto a = html.find(open) + open.size();
  const auto b = html.find("</script>", a);
  return json::parse(html.substr(a, b - a));
}

std::vector<std::uint8_t> unbase64(const std::string& s) {
  const std::string digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::vector<std::uint8_t> out;
  std::uint32_t acc = 0;
  int bits = 0;
  for (const char c : s) {
    if (c == '=') break;
    acc = (acc << 6) | static_cast<std::uint32_t>(digits.find(c));
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<std::uint8_t>((acc >> bits) & 0xff));
    }
  }
  return out;
}

std::vector<double> dequantize(const json& q) {
  const auto raw = unbase64(q["data"].get<std::string>());
  std::vector<double> out;
  for (std::size_t i = 0; i + 1 < raw.size(); i += 2) {
    out.push_back(q["origin"].get<double>() +
                  (raw[i] | (raw[i + 1] << 8)) * q["unit"].get<double>());
  }
  return out;
}

TEST(Viewer, PageIsSelfContainedAndCarriesTheRun) {
  const RecordedRun run = recorded_run();
  ViewerOptions options;
  options.max_snapshots = 10;
  const std::string html = viewer_html(run, options);
  EXPECT_EQ(html.find("http://"), std::string::npos);
  EXPECT_EQ(html.find("https://"), std::string::npos);
  EXPECT_EQ(html.find("src="), std::string::npos);
  EXPECT_EQ(html.find("/*PLUMETRACE_DATA*/"), std::string::npos);

  const json d = page_data(html);
  EXPECT_EQ(d["steps"], run.trace.steps.size());
  EXPECT_EQ(d["result"]["outcome"], outcome_name(run.result.outcome));
  EXPECT_EQ(d["frames"]["time"].size(), run.trace.steps.size());  // a short run keeps every step
  EXPECT_DOUBLE_EQ(d["frames"]["x"].back().get<double>(),
                   std::round(run.trace.steps.back().pose.x * 1e5) / 1e5);
  EXPECT_EQ(d["states"], (json{"upwind", "crosswind"}));

  // snapshots: thinned to 10, positions within half a quantum (<= 0.5 mm) of the trace's
  const json& snaps = d["snapshots"];
  ASSERT_EQ(snaps["time"].size(), 10u);
  EXPECT_EQ(snaps["time"].back(), run.trace.snapshots.back().time);
  const auto x = dequantize(snaps["x"]), w = dequantize(snaps["w"]);
  const auto& last = run.trace.snapshots.back();
  const std::size_t offset = x.size() - last.x.size();
  for (std::size_t k = 0; k < last.x.size(); ++k) {
    ASSERT_NEAR(x[offset + k], last.x[k], 0.5 * snaps["x"]["unit"].get<double>() + 1e-12);
    ASSERT_NEAR(w[offset + k], last.w[k], 0.5 * snaps["w"]["unit"].get<double>() + 1e-12);
  }
  EXPECT_LE(snaps["x"]["unit"].get<double>(), 1e-3);
  // shades span the range: the youngest (narrowest) filament is the darkest
  const auto shade = unbase64(snaps["shade"].get<std::string>());
  EXPECT_EQ(*std::max_element(shade.begin(), shade.end()), 255);
  EXPECT_EQ(*std::min_element(shade.begin(), shade.end()), 0);

  // every wind sample, rotated into the world frame
  std::size_t samples = 0;
  for (const auto& s : run.trace.steps) samples += s.wind_samples > 0;
  ASSERT_EQ(d["wind"]["u"].size(), samples);
  EXPECT_EQ(d["wind"]["true_u"][0], run.scenario.wind.velocity.x);
}

TEST(Viewer, DataCannotEndTheScriptElement) {
  RecordedRun run = recorded_run(0.0);
  run.info.algorithm = "</script><b>";
  for (auto& s : run.trace.steps) s.state = "<!--<script>";
  const std::string html = viewer_html(run, {});
  const json d = page_data(html);
  EXPECT_EQ(d["result"]["algorithm"], "</script><b>");
  EXPECT_EQ(d["states"], (json{"<!--<script>"}));
  // no '<' at all in the data, so nothing in it can end or disturb the script element
  const std::string open = "<script id=\"plumetrace-data\" type=\"application/json\">";
  const auto a = html.find(open) + open.size();
  EXPECT_EQ(html.substr(a, html.find("</script>", a) - a).find('<'), std::string::npos);
}

TEST(Viewer, FigureDrawsEveryLayer) {
  const RecordedRun run = recorded_run();
  const std::string svg = figure_svg(run, {});
  const auto count = [&](const std::string& what) {
    std::size_t n = 0;
    for (auto at = svg.find(what); at != std::string::npos; at = svg.find(what, at + 1)) ++n;
    return n;
  };
  // one polyline per stretch of one state
  std::size_t stretches = 0;
  for (std::size_t i = 1; i < run.trace.steps.size(); ++i) {
    stretches += i == 1 || run.trace.steps[i].state != run.trace.steps[i - 1].state;
  }
  EXPECT_EQ(count("<polyline"), stretches);
  // the filaments of the last snapshot, the wind samples, and the robot
  std::size_t samples = 0;
  for (const auto& s : run.trace.steps) samples += s.wind_samples > 0;
  EXPECT_EQ(count("marker-end=\"url(#arrow)\"/>") - 1, samples);  // one more in the legend
  const auto plume =
      svg.substr(svg.find("<g id=\"plume\""),
                 svg.find("</g>", svg.find("<g id=\"plume\"")) - svg.find("<g id=\"plume\""));
  std::size_t circles = 0;
  for (auto at = plume.find("<circle"); at != std::string::npos; at = plume.find("<circle", at + 1))
    ++circles;
  EXPECT_EQ(circles, run.trace.snapshots.back().x.size());
  EXPECT_NE(svg.find("<g id=\"robot\">"), std::string::npos);
  EXPECT_NE(svg.find(std::string(outcome_name(run.result.outcome)) + " at "), std::string::npos);
}

TEST(Viewer, ViewPathMustBeHtmlOrSvg) {
  EXPECT_THROW(check_view_path("run.png", "--view"), ConfigError);
  EXPECT_THROW(check_view_path("no/such/dir/run.html", "--view"), IoError);
  const std::string ok = testing::temp_path("view", ".svg");
  EXPECT_NO_THROW(check_view_path(ok, "--view"));
}

}  // namespace
}  // namespace plumetrace
