// Google Benchmark cases: one plume step, one concentration query, one whole run per algorithm.
//
// --simd=LIST (before Google Benchmark's own options; LIST: "all", or names such as
// "scalar,avx2") runs the benchmarks of the vector loops once per path listed, named
// BM_PlumeStep<avx2>/0 and so on; without it they run on the path PLUMETRACE_SIMD chooses
// (docs/performance.md, "Vector paths").
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/core/math.hpp"
#include "plumetrace/core/simd.hpp"
#include "plumetrace/distributed/distributed.hpp"
#include "plumetrace/env/filament_plume.hpp"
#include "plumetrace/env/meander_wind.hpp"
#include "plumetrace/experiment/store.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/trace_io.hpp"
#include "plumetrace/sim/scenario.hpp"
#include "plumetrace/sim/vector_world.hpp"
#include "plumetrace/sim/world.hpp"

namespace plumetrace {
namespace {

// the scenario's wind field, as a run of seed 1, trial 0 makes it
std::unique_ptr<WindField> make_wind(const Scenario& s) {
  return make_wind_field(s.wind, wind_context(s), Rng(derive_seed(1, 0, Stream::kWind)));
}

// the default scenario, in the laminar wind (range 0) or the default meandering wind (1)
Scenario bench_scenario(std::int64_t meander) {
  Scenario s;
  if (meander != 0) s.wind.model = WindModel::kMeander;
  return s;
}

// a default plume after its 20 s warm-up: 1600 filaments (the wind is stepped with it)
FilamentPlume warm_plume(const Scenario& s, WindField& wind) {
  FilamentPlume plume(s.plume, s.source, s.arena.x_max, derive_seed(1, 0, Stream::kPlume));
  for (int i = 0; i < 625; ++i) {
    wind.step(s.sim.dt);
    plume.step(wind, s.sim.dt);
  }
  return plume;
}

// one plume step in a wind held still: range 0 laminar (one velocity per step), 1 the default
// meander (the velocity at each filament)
void BM_PlumeStep(benchmark::State& state) {
  const Scenario s = bench_scenario(state.range(0));
  state.SetLabel(state.range(0) != 0 ? "meander" : "laminar");
  const auto wind = make_wind(s);
  FilamentPlume plume = warm_plume(s, *wind);
  for (auto _ : state) plume.step(*wind, s.sim.dt);
  // reported per filament-step
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(plume.size()));
  // shown as seconds per filament-step ("3.1n" = 3.1 ns)
  state.counters["per_filament_step"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * static_cast<double>(plume.size()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// one step of the default meandering wind (17 x 5 nodes, dt 0.032 s): the corner noise, the
// edges and the inside's substeps
void BM_MeanderWindStep(benchmark::State& state) {
  const Scenario s = bench_scenario(1);
  MeanderWind wind(s.wind.get<MeanderParams>(), s.wind.velocity, wind_region(s.arena),
                   Rng(derive_seed(1, 0, Stream::kWind)));
  for (auto _ : state) wind.step(s.sim.dt);
  state.counters["substeps"] = wind.substeps();
}
BENCHMARK(BM_MeanderWindStep);

// a query at points along and across the corridor of the warm default plume, as a robot meets
// them
template <class Query>
void bench_query(benchmark::State& state, Query query) {
  const Scenario s;
  const auto wind = make_wind(s);
  const FilamentPlume plume = warm_plume(s, *wind);
  const Vec3 points[] = {{15.5, 0.0, 0.0}, {8.0, 0.3, 0.0}, {2.0, -0.5, 0.0}, {8.0, 1.5, 0.0}};
  std::size_t i = 0;
  double sum = 0.0;
  for (auto _ : state) sum += query(plume, points[i++ & 3], s.odor.threshold);
  benchmark::DoNotOptimize(sum);
}

void BM_ConcentrationQuery(benchmark::State& state) {
  bench_query(state, [](const OdorField& p, const Vec3& u, double) { return p.concentration(u); });
}

// what a robot asks each step: does the concentration reach the threshold
void BM_OdorQuery(benchmark::State& state) {
  bench_query(state, [](const OdorField& p, const Vec3& u, double threshold) {
    return p.reaches(u, threshold) ? 1.0 : 0.0;
  });
}

// one decision of 1024 vector-environment agents at decision interval 1 with random headings
// (redrawn every 16 steps), groups of range(0) agents per plume (range 1: 1 concentration
// observation, else binary), on range(2) threads (wall-clock time): what plumetrace.vector costs
// without Python
void BM_VectorStep(benchmark::State& state) {
  VectorSpec spec;
  spec.envs = 1024;
  spec.group = static_cast<int>(state.range(0));
  spec.observe.concentration = state.range(1) != 0;
  spec.threads = static_cast<int>(state.range(2));
  VectorWorld world(Scenario{}, spec);
  world.reset(std::vector<std::uint64_t>(1024, 1));
  Rng rng(7);
  std::vector<double> actions(1024);
  std::int64_t k = 0;
  for (auto _ : state) {
    if (k++ % 16 == 0) {
      for (double& a : actions) a = 2.0 * rng.uniform() - 1.0;
    }
    world.step(actions);
  }
  state.SetItemsProcessed(state.iterations() * 1024);
  state.SetLabel(state.range(1) != 0 ? "concentration" : "binary");
}
BENCHMARK(BM_VectorStep)
    ->ArgsProduct({{64, 1024}, {0, 1}, {1, 2}})
    ->UseRealTime()
    ->Unit(benchmark::kMicrosecond);

// one run per algorithm (range 0) in the laminar wind or the default meander (range 1)
void BM_WholeRun(benchmark::State& state) {
  Scenario s = bench_scenario(state.range(1));
  s.controller.algorithm = library_algorithms()[static_cast<std::size_t>(state.range(0))];
  state.SetLabel(std::string(algorithm_name(s.controller.algorithm)) +
                 (state.range(1) != 0 ? " meander" : ""));
  std::uint64_t trial = 0;
  std::int64_t steps = 0;
  for (auto _ : state) {
    steps += run_once(s, 1, trial++ % 8).steps;
  }
  state.counters["steps_per_run"] =
      static_cast<double>(steps) / static_cast<double>(state.iterations());
  // the time per robot step, warm-up included (a run in meander may last longer or shorter)
  state.counters["per_step"] =
      benchmark::Counter(static_cast<double>(steps + static_cast<std::int64_t>(state.iterations()) *
                                                         std::llround(s.sim.warmup / s.sim.dt)),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// one call of an elementary function, the model's own (range 1 = 0, plumetrace::math) or the C
// library's (1), over 1024 arguments in the range the model calls it on: exp, expm1 of [-40, 0];
// log of (0, 2]; log1p of [0, 4]; pow(x, 1.5) of x in [1, 4] (a spiral's curvature); sin, cos of
// [-pi, pi]; atan2, hypot of points of [-10, 10]^2; asinh of [0, 100]. Range 2 = 0 sums the
// results (calls overlap: throughput), 1 feeds each result into the next argument (latency, as in
// a Newton iteration). Shown per call (docs/performance.md, "The model's own maths functions")
void BM_Math(benchmark::State& state) {
  struct Function {
    const char* name;
    double lo, hi;
    double (*own)(double, double);
    double (*libc)(double, double);
  };
  static const Function functions[] = {
      {"exp", -40, 0, [](double x, double) { return math::exp(x); },
       [](double x, double) { return std::exp(x); }},
      {"expm1", -40, 0, [](double x, double) { return math::expm1(x); },
       [](double x, double) { return std::expm1(x); }},
      {"log", 1e-9, 2, [](double x, double) { return math::log(x); },
       [](double x, double) { return std::log(x); }},
      {"log1p", 0, 4, [](double x, double) { return math::log1p(x); },
       [](double x, double) { return std::log1p(x); }},
      {"pow", 1, 4, [](double x, double) { return math::pow(x, 1.5); },
       [](double x, double) { return std::pow(x, 1.5); }},
      {"sin", -3.14, 3.14, [](double x, double) { return math::sin(x); },
       [](double x, double) { return std::sin(x); }},
      {"cos", -3.14, 3.14, [](double x, double) { return math::cos(x); },
       [](double x, double) { return std::cos(x); }},
      {"atan2", -10, 10, [](double x, double y) { return math::atan2(y, x); },
       [](double x, double y) { return std::atan2(y, x); }},
      {"hypot", -10, 10, [](double x, double y) { return math::hypot(x, y); },
       [](double x, double y) { return std::hypot(x, y); }},
      {"asinh", 0, 100, [](double x, double) { return math::asinh(x); },
       [](double x, double) { return std::asinh(x); }},
  };
  const Function& f = functions[state.range(0)];
  const bool own = state.range(1) == 0, chained = state.range(2) != 0;
  const auto call = own ? f.own : f.libc;
  state.SetLabel(std::string(f.name) + (own ? " own" : " libc") +
                 (chained ? " latency" : " throughput"));
  constexpr int kArgs = 1024;
  std::vector<double> xs(kArgs), ys(kArgs);
  Rng rng(7);
  for (int i = 0; i < kArgs; ++i) {
    xs[i] = f.lo + (f.hi - f.lo) * rng.uniform();
    ys[i] = f.lo + (f.hi - f.lo) * rng.uniform();
  }
  for (auto _ : state) {
    double sum = 0.0;
    if (chained) {
      // the next argument depends on this result, by an amount that keeps it in range
      for (int i = 0; i < kArgs; ++i) sum = call(xs[i] + 1e-300 * sum, ys[i]);
    } else {
      for (int i = 0; i < kArgs; ++i) sum += call(xs[i], ys[i]);
    }
    benchmark::DoNotOptimize(sum);
  }
  state.counters["per_call"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * kArgs,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_Math)->ArgsProduct({benchmark::CreateDenseRange(0, 9, 1), {0, 1}, {0, 1}});

// one update of the particle filter at its default particle count (the decision it takes once
// per update_interval; the steps between add one wind sample each): the robot 3 m downwind of a
// cloud drawn at a first hit, hits and misses alternating in the steady tunnel wind
void BM_Decide_particle_filter(benchmark::State& state) {
  const ParticleFilterParams params;
  ParticleFilter filter(params, Rng(derive_seed(1, 0, Stream::kController)));
  filter.push_wind({1.0, 0.0});
  filter.update({0.0, 0.0}, true);
  bool hit = false;
  for (auto _ : state) {
    filter.push_wind({1.0, 0.0});
    benchmark::DoNotOptimize(filter.update({0.0, 0.0}, hit = !hit));
  }
  state.counters["particles"] = params.particles;
  state.counters["resamplings"] = filter.resamplings();
}
BENCHMARK(BM_Decide_particle_filter);

// a noiseless wind probe: upwind along pi in the odometry frame, seen from `heading`
class BenchWind final : public WindProbe {
 public:
  Vec2 measure_wind_body() override { return rotate({1.0, 0.0}, -heading); }
  double heading = 0.0;
};

// one decision of the scenario's controller, the robot obeying at once with a full-speed step
// (3.392 mm) and a concentration that rises and falls about the threshold
void bench_decide(benchmark::State& state, const Scenario& s) {
  std::unique_ptr<Controller> c = make_controller(s.controller, Rng(1));
  Observation obs;
  BenchWind wind;
  const double travel = s.robot.wheel_speed * s.sim.dt;
  std::int64_t k = 0;
  for (auto _ : state) {
    obs.time = static_cast<double>(k) * s.sim.dt;
    obs.concentration = 100.0 * (1.0 + std::sin(0.01 * static_cast<double>(k)));
    obs.odor = obs.concentration >= s.odor.threshold;
    wind.heading = obs.odometry.heading;
    const Command command = c->step(obs, wind);
    benchmark::DoNotOptimize(command);
    obs.odometry.heading = command.heading;
    obs.odometry.x += travel * std::cos(command.heading);
    obs.odometry.y += travel * std::sin(command.heading);
    obs.odometer += travel;
    ++k;
  }
}

// one decision of chemotaxis on the concentration (range 0 = 0) or the binary odor (1)
void BM_Decide_chemotaxis(benchmark::State& state) {
  Scenario s;
  s.controller.algorithm = Algorithm::kChemotaxis;
  if (state.range(0) != 0) s.controller.get<ChemotaxisParams>().signal = ChemotaxisSignal::kBinary;
  state.SetLabel(state.range(0) != 0 ? "binary" : "concentration");
  bench_decide(state, s);
}
BENCHMARK(BM_Decide_chemotaxis)->Arg(0)->Arg(1);

// one decision of a random walk (Params: CrwParams or LevyParams) without (range 0 = 0) or
// with an upwind bias of 0.5 (1)
template <class Params>
void decide_walk(benchmark::State& state, Algorithm algorithm) {
  Scenario s;
  s.controller.algorithm = algorithm;
  s.controller.get<Params>().upwind_bias = state.range(0) != 0 ? 0.5 : 0.0;
  state.SetLabel(state.range(0) != 0 ? "upwind_bias 0.5" : "no bias");
  bench_decide(state, s);
}

void BM_Decide_crw(benchmark::State& state) { decide_walk<CrwParams>(state, Algorithm::kCrw); }
BENCHMARK(BM_Decide_crw)->Arg(0)->Arg(1);

void BM_Decide_levy(benchmark::State& state) { decide_walk<LevyParams>(state, Algorithm::kLevy); }
BENCHMARK(BM_Decide_levy)->Arg(0)->Arg(1);

// one whole run in the laminar wind with walls that block (a walk meets walls often; with
// walls that end the run, its cost would measure only how soon it meets one): surge-cast (range
// 0 = 0), chemotaxis on the concentration (1) and binary (2), crw (3), biased crw (4), levy (5),
// biased levy (6); the same seeds and trials as BM_WholeRun
void BM_WholeRunWalks(benchmark::State& state) {
  Scenario s;
  s.supervisor.walls = WallRule::kBlock;
  const char* labels[] = {"surge-cast",     "chemotaxis", "chemotaxis binary", "crw",
                          "crw biased 0.5", "levy",       "levy biased 0.5"};
  const Algorithm algorithms[] = {
      Algorithm::kSurgeCast, Algorithm::kChemotaxis, Algorithm::kChemotaxis, Algorithm::kCrw,
      Algorithm::kCrw,       Algorithm::kLevy,       Algorithm::kLevy};
  const auto i = static_cast<std::size_t>(state.range(0));
  s.controller.algorithm = algorithms[i];
  if (i == 2) s.controller.get<ChemotaxisParams>().signal = ChemotaxisSignal::kBinary;
  if (i == 4) s.controller.get<CrwParams>().upwind_bias = 0.5;
  if (i == 6) s.controller.get<LevyParams>().upwind_bias = 0.5;
  state.SetLabel(labels[i]);
  std::uint64_t trial = 0;
  std::int64_t steps = 0;
  for (auto _ : state) {
    steps += run_once(s, 1, trial++ % 8).steps;
  }
  state.counters["steps_per_run"] =
      static_cast<double>(steps) / static_cast<double>(state.iterations());
  state.counters["per_step"] =
      benchmark::Counter(static_cast<double>(steps + static_cast<std::int64_t>(state.iterations()) *
                                                         std::llround(s.sim.warmup / s.sim.dt)),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_WholeRunWalks)->DenseRange(0, 6)->Unit(benchmark::kMillisecond);

// one decision of hayes on its spiral, fed a new odometer each step: range 0 alone; range 1 with
// two teammates' hits a step pooled toward a declaration that never comes (declare_hits at its
// maximum), so each decision also counts the hits remembered
void BM_Decide_hayes(benchmark::State& state) {
  HayesParams params;
  const bool team = state.range(0) != 0;
  if (team) params.declare_hits = 100000;
  state.SetLabel(team ? "two teammates' hits a step, counting" : "alone");
  Hayes hayes(params, Rng(1));
  class Still final : public WindProbe {
    Vec2 measure_wind_body() override { return {1.0, 0.0}; }
  } wind;
  std::vector<Message> inbox(team ? 2 : 0);
  Observation obs;
  std::int64_t k = 0;
  for (auto _ : state) {
    ++k;
    obs.time = static_cast<double>(k) * 0.032;
    obs.odometer = static_cast<double>(k) * 0.0034;
    for (std::size_t i = 0; i < inbox.size(); ++i) {
      // hits behind the robot (+x of its frame), so that it keeps spiralling
      inbox[i] = {
          static_cast<int>(i) + 1, obs.time, {5.0 + obs.time, 0.1 * i, Hayes::kHitTag, 0.0}};
    }
    obs.messages = inbox;
    benchmark::DoNotOptimize(hayes.step(obs, wind));
  }
}
BENCHMARK(BM_Decide_hayes)->Arg(0)->Arg(1);

// a whole run of a team of three hayes robots released outside the laminar plume (robot 0 8 m
// downwind and 1 m to the side, the others 0.4 m either side), sharing hits (range 0 = 1) or out
// of range (0); compare with BM_WholeRun of surge-cast, one robot from the paper's start
void BM_TeamRun_hayes(benchmark::State& state) {
  const auto set = [](const char* key, ConfigValue v) {
    return Setting{key, std::move(v), false, "bench", Layer::kCommandLine};
  };
  const bool shared = state.range(0) != 0;
  const Scenario s = build_scenario(
      {set("controller.algorithm", std::string("hayes")), set("robot.start_offset_x", 8.0),
       set("robot.start_offset_y", 1.0), set("team.count", std::int64_t{3}),
       set("team.spacing", 0.4), set("team.range", shared ? INFINITY : 0.0),
       set("member.1.hayes.origin_y", 0.4), set("member.2.hayes.origin_y", -0.4)});
  state.SetLabel(shared ? "3 robots sharing hits" : "3 robots out of range");
  std::uint64_t trial = 0;
  std::int64_t steps = 0;
  for (auto _ : state) {
    for (const RunResult& r : run_team(s, 1, trial++ % 8)) steps += r.steps;
  }
  state.counters["robot_steps_per_run"] =
      static_cast<double>(steps) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_TeamRun_hayes)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

// one decision of infotaxis at its default grid (69 x 19 cells): the Bayes update at the cell
// reached (no hit during a 2.4 s move) and the choice among the four neighbours, on the belief
// left by a hit at the start cell and 20 cells walked upwind without one
void BM_Decide_infotaxis(benchmark::State& state) {
  const InfotaxisParams p;
  const int nx = p.cells_upwind + p.cells_downwind + 1, ny = 2 * p.cells_crosswind + 1;
  const int i0 = p.cells_downwind, j0 = p.cells_crosswind;
  const double move = p.cell / p.speed;
  InfotaxisBelief base(p, nx, ny, {-1.0, 0.0});
  base.update(i0, j0, true, 0.032);
  for (int k = 1; k <= 20; ++k) base.update(i0 + k, j0, false, move);
  const std::vector<char> blocked(static_cast<std::size_t>(nx) * ny, 0);
  InfotaxisBelief b = base;
  for (auto _ : state) {
    b.set_probability(base.probability());
    b.update(i0 + 21, j0, false, move);
    benchmark::DoNotOptimize(b.choose_move(i0 + 21, j0, move, blocked));
  }
}
BENCHMARK(BM_Decide_infotaxis)->Unit(benchmark::kMicrosecond);

// casting that also reads the concentration, so that each step sums every filament near the
// sensor rather than stopping at the threshold
class ReadingCasting final : public Controller {
 public:
  explicit ReadingCasting(std::unique_ptr<Controller> inner) : inner_(std::move(inner)) {}
  Command step(const Observation& obs, WindProbe& wind) override {
    benchmark::DoNotOptimize(obs.concentration);
    return inner_->step(obs, wind);
  }
  std::string_view state() const override { return inner_->state(); }
  int losses() const override { return inner_->losses(); }
  unsigned reads() const override { return kReadsConcentration; }

 private:
  std::unique_ptr<Controller> inner_;
};

// one step of a World with a team of N robots (range 0) casting on one plume, with the binary
// sensor (range 1 = 0) or reading the concentration (1), contacts on; the robots start spread
// over the default start rectangle, walls block and only a declaration ends a run, so the team
// stays whole. The marginal cost of a robot is (T(N) - T(1)) / (N - 1) (docs/performance.md)
void BM_TeamStep(benchmark::State& state) {
  Scenario s;
  s.team.count = static_cast<int>(state.range(0));
  s.start.region = StartRegion::kRectangle;
  s.supervisor.walls = WallRule::kBlock;
  s.supervisor.success = SuccessRule::kDeclare;
  s.supervisor.timeout = 1e5;
  validate(s);
  const bool reading = state.range(1) != 0;
  state.SetLabel(std::to_string(s.team.count) +
                 (reading ? " robots, concentration" : " robots, binary"));
  ControllerFactory factory;
  if (reading) {
    factory = [](const Scenario& sc, Rng rng) -> std::unique_ptr<Controller> {
      return std::make_unique<ReadingCasting>(make_controller(sc.controller, rng));
    };
  }
  World world({&s}, 1, 0, factory);
  for (auto _ : state) world.step();
  state.counters["per_robot_step"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * static_cast<double>(s.team.count),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_TeamStep)->ArgsProduct({{1, 10, 100}, {0, 1}});

// rows as a sweep makes them: one point, consecutive trials from `first`
std::vector<RunRow> sample_rows(std::size_t count, std::uint64_t first) {
  std::vector<RunRow> rows(count);
  for (std::size_t i = 0; i < count; ++i) {
    rows[i] = {"G", 3, first + i, 0, "0123456789abcdef", {}};
    rows[i].result = {Outcome::kSuccess, 81.3,      9.7, 8.1, 1.2, 2, 0.4, 2540, 3, 0.0, 0.0, NAN,
                      20080101,          first + i, 0};
  }
  return rows;
}

// the store's write rate, which bounds a distributed sweep's rate (rank 0 writes every row): one
// transaction per batch of range(0) rows
void BM_StoreInsert(benchmark::State& state) {
  const auto path = std::filesystem::temp_directory_path() / "plumetrace_bench_store.sqlite";
  std::filesystem::remove(path);
  Store store(path.string(), "{}", version(), true);
  const auto batch = static_cast<std::size_t>(state.range(0));
  std::uint64_t trial = 0;
  for (auto _ : state) {
    store.insert(sample_rows(batch, trial));
    trial += batch;
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(trial));
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path.string() + suffix);
}
BENCHMARK(BM_StoreInsert)->Arg(10)->Arg(1000);

// a batch of rows through the message format between ranks, both ways
void BM_RowMessage(benchmark::State& state) {
  const auto rows = sample_rows(static_cast<std::size_t>(state.range(0)), 0);
  for (auto _ : state) benchmark::DoNotOptimize(decode_rows(encode_rows(rows)));
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_RowMessage)->Arg(10);

// the benchmarks that run the vector loops, registered in main once per path --simd lists
struct PathBenchmark {
  const char* name;
  void (*run)(benchmark::State&);
  void (*shape)(benchmark::internal::Benchmark*);
};

const PathBenchmark kPathBenchmarks[] = {
    {"BM_PlumeStep", BM_PlumeStep, [](benchmark::internal::Benchmark* b) { b->Arg(0)->Arg(1); }},
    {"BM_ConcentrationQuery", BM_ConcentrationQuery, [](benchmark::internal::Benchmark*) {}},
    {"BM_OdorQuery", BM_OdorQuery, [](benchmark::internal::Benchmark*) {}},
    // why: every built-in algorithm, the baselines included, without listing their indices
    {"BM_WholeRun", BM_WholeRun,
     [](benchmark::internal::Benchmark* b) {
       b->ArgsProduct({benchmark::CreateDenseRange(
                           0, static_cast<std::int64_t>(library_algorithms().size()) - 1, 1),
                       {0, 1}})
           ->Unit(benchmark::kMillisecond);
     }},
};

// the paths --simd=LIST names ("all": every available one), in the order listed
std::vector<simd::Path> parse_paths(const std::string& list) {
  if (list == "all") return simd::available();
  std::vector<simd::Path> paths;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = list.find(',', start);
    paths.push_back(simd::parse(list.substr(start, comma - start)));
    if (comma == std::string::npos) return paths;
    start = comma + 1;
  }
}

}  // namespace
}  // namespace plumetrace

int main(int argc, char** argv) {
  using namespace plumetrace;
  // --simd=LIST, taken out before Google Benchmark reads the rest
  std::string list;
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--simd=", 7) == 0) {
      list = argv[i] + 7;
    } else {
      argv[kept++] = argv[i];
    }
  }
  argc = kept;
  std::vector<simd::Path> paths;
  simd::Path chosen;
  try {
    chosen = simd::active();
    if (!list.empty()) paths = parse_paths(list);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr,
                 "plumetrace_bench: %s (--simd=all, or a list such as --simd=scalar,avx2)\n",
                 e.what());
    return 2;
  }
  for (const PathBenchmark& b : kPathBenchmarks) {
    if (paths.empty()) {
      b.shape(benchmark::RegisterBenchmark(b.name, b.run));
      continue;
    }
    for (const simd::Path path : paths) {
      const std::string name = std::string(b.name) + "<" + std::string(simd::name(path)) + ">";
      b.shape(benchmark::RegisterBenchmark(name.c_str(), [b, path, chosen](benchmark::State& s) {
        simd::select(path);
        b.run(s);
        simd::select(chosen);  // the other benchmarks run on the path chosen at the start
      }));
    }
  }
  benchmark::AddCustomContext("simd", simd::describe());
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
