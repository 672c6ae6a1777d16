// Skill runtime benchmarks (Google Benchmark): table lookup, discretization, step() with and
// without smoothing, the executor's differential-IK tick, a whole control tick (step + new
// target + first joint command), the scenes' move, bundle loading.
//
// Usage: bench_skill BUNDLE ROBOTS_DIR [benchmark options]
//   BUNDLE      a skill bundle (benchmarks/bench_runtime.py writes a learned push skill)
//   ROBOTS_DIR  example-robot-data's robots/ (python -m a2l.robot --robots-dir)
// Besides the mean, the *_latency benchmarks time every call and report percentiles as
// counters (p50_ns, p99_ns, p999_ns, max_ns); the clock's own cost is measured by
// BM_clock_latency and is included in those figures.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "a2l/bundle.hpp"
#include "a2l/executor.hpp"
#include "a2l/kinematics.hpp"
#include "a2l/scene/bullet.hpp"
#include "a2l/scene/virtual.hpp"
#include "a2l/skill.hpp"

namespace {

using Clock = std::chrono::steady_clock;

std::string g_bundle, g_robots;
a2l::Skill g_skill;
a2l::Kinematics g_kin;
Eigen::VectorXd g_neutral(7);

// Contexts around the object: eef on a disc of radius 0.25 m at the object's height, every
// effect; mostly known contexts as in a run (the share is reported as a counter).
std::vector<a2l::Context> make_contexts(std::size_t n) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-0.25, 0.25);
  const int n_effects =
      g_skill.discretizer().effect_axis() < 0
          ? 1
          : g_skill.discretizer().variable(g_skill.discretizer().effect_axis()).n_bins;
  std::vector<a2l::Context> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    out[i].object = {0.58, -0.18, 0.11};
    out[i].eef = out[i].object + Eigen::Vector3d(u(rng), u(rng), 0.0);
    out[i].effect = static_cast<int>(i % static_cast<std::size_t>(n_effects));
  }
  return out;
}

void report_latency(benchmark::State& state, std::vector<double>& ns) {
  std::sort(ns.begin(), ns.end());
  auto pct = [&](double q) {
    return ns[std::min(ns.size() - 1,
                       static_cast<std::size_t>(q * static_cast<double>(ns.size())))];
  };
  state.counters["p50_ns"] = pct(0.50);
  state.counters["p99_ns"] = pct(0.99);
  state.counters["p999_ns"] = pct(0.999);
  state.counters["max_ns"] = ns.back();
}

void BM_table_lookup(benchmark::State& state) {
  const a2l::PolicyTable& t = g_skill.table();
  std::mt19937_64 rng(2);
  std::vector<int> bins(4096 * static_cast<std::size_t>(t.n_axes()));
  for (std::size_t i = 0; i < 4096; ++i) {
    for (int a = 0; a < t.n_axes(); ++a) {
      bins[i * static_cast<std::size_t>(t.n_axes()) + static_cast<std::size_t>(a)] =
          std::uniform_int_distribution<int>(0, t.shape()[static_cast<std::size_t>(a)] - 1)(rng);
    }
  }
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(t.lookup(&bins[(i++ & 4095) * static_cast<std::size_t>(t.n_axes())]));
  }
}

void BM_discretize(benchmark::State& state) {
  const auto ctx = make_contexts(4096);
  int bins[a2l::kMaxVariables];
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(g_skill.discretizer().discretize(ctx[i++ & 4095], bins));
    benchmark::ClobberMemory();
  }
}

void step_bench(benchmark::State& state, a2l::Smoothing smoothing) {
  const auto ctx = make_contexts(4096);
  a2l::SkillState st(g_skill, 1024);
  st.smoothing = smoothing;
  a2l::StepOutput out;
  std::size_t i = 0, ok = 0, n = 0;
  for (auto _ : state) {
    if (st.steps() >= g_skill.settings().step_cap) st.reset();
    ok += a2l::step(g_skill, st, ctx[i++ & 4095], out) == a2l::Status::ok;
    ++n;
    benchmark::DoNotOptimize(out);
  }
  state.counters["known_share"] = static_cast<double>(ok) / static_cast<double>(n);
}
void BM_step(benchmark::State& s) { step_bench(s, a2l::Smoothing::off); }
void BM_step_smoothing(benchmark::State& s) { step_bench(s, a2l::Smoothing::on); }

void step_latency(benchmark::State& state, a2l::Smoothing smoothing) {
  const auto ctx = make_contexts(4096);
  a2l::SkillState st(g_skill, 1024);
  st.smoothing = smoothing;
  a2l::StepOutput out;
  std::vector<double> ns;
  ns.reserve(2000000);
  std::size_t i = 0;
  for (auto _ : state) {
    if (st.steps() >= g_skill.settings().step_cap) st.reset();
    const auto a = Clock::now();
    a2l::step(g_skill, st, ctx[i++ & 4095], out);
    const auto b = Clock::now();
    benchmark::DoNotOptimize(out);
    if (ns.size() < ns.capacity())
      ns.push_back(std::chrono::duration<double, std::nano>(b - a).count());
  }
  report_latency(state, ns);
}
void BM_step_latency(benchmark::State& s) { step_latency(s, a2l::Smoothing::off); }
void BM_step_smoothing_latency(benchmark::State& s) { step_latency(s, a2l::Smoothing::on); }

void BM_clock_latency(benchmark::State& state) {
  std::vector<double> ns;
  ns.reserve(2000000);
  for (auto _ : state) {
    const auto a = Clock::now();
    const auto b = Clock::now();
    if (ns.size() < ns.capacity())
      ns.push_back(std::chrono::duration<double, std::nano>(b - a).count());
  }
  report_latency(state, ns);
}

// The executor moves back and forth between two points 5 cm apart (as during a run).
struct TickFixture {
  a2l::Executor ex;
  Eigen::Vector3d p0;
  int leg = 0;
  TickFixture() {
    if (!ex.init(g_kin, g_neutral).ok()) std::abort();
    p0 = ex.position();
  }
  void next_target(const Eigen::Vector3d& d) {
    ex.set_target((++leg % 2) ? Eigen::Vector3d(p0 + d) : p0);
  }
};

void BM_executor_tick(benchmark::State& state) {
  TickFixture f;
  f.next_target(Eigen::Vector3d(0.05, 0.0, 0.0));
  for (auto _ : state) {
    if (f.ex.reached()) f.next_target(Eigen::Vector3d(0.05, 0.0, 0.0));
    benchmark::DoNotOptimize(f.ex.tick());
  }
}

// A whole control tick as a2l-run runs it when a movement ends: observe the context, step()
// for the next movement, set the new target, and issue the first joint command by
// differential IK. Ticks in the middle of a movement are only the executor's tick.
void control_tick(benchmark::State& state, bool latency) {
  TickFixture f;
  const auto ctx = make_contexts(4096);
  a2l::SkillState st(g_skill, 1024);
  a2l::StepOutput out;
  std::vector<double> ns;
  if (latency) ns.reserve(2000000);
  std::size_t i = 0;
  for (auto _ : state) {
    const auto a = Clock::now();
    if (st.steps() >= g_skill.settings().step_cap) st.reset();
    a2l::Context c = ctx[i++ & 4095];
    c.object = f.p0 + (c.object - c.eef);  // the context seen from the arm's position
    c.eef = f.ex.position();
    a2l::step(g_skill, st, c, out);
    f.next_target(out.movement >= 0 ? out.displacement : Eigen::Vector3d(0.05, 0.0, 0.0));
    benchmark::DoNotOptimize(f.ex.tick());
    const auto b = Clock::now();
    if (latency && ns.size() < ns.capacity()) {
      ns.push_back(std::chrono::duration<double, std::nano>(b - a).count());
    }
  }
  if (latency) report_latency(state, ns);
}
void BM_control_tick(benchmark::State& s) { control_tick(s, false); }
void BM_control_tick_latency(benchmark::State& s) { control_tick(s, true); }

void BM_executor_tick_latency(benchmark::State& state) {
  TickFixture f;
  f.next_target(Eigen::Vector3d(0.05, 0.0, 0.0));
  std::vector<double> ns;
  ns.reserve(2000000);
  for (auto _ : state) {
    if (f.ex.reached()) f.next_target(Eigen::Vector3d(0.05, 0.0, 0.0));
    const auto a = Clock::now();
    benchmark::DoNotOptimize(f.ex.tick());
    const auto b = Clock::now();
    if (ns.size() < ns.capacity())
      ns.push_back(std::chrono::duration<double, std::nano>(b - a).count());
  }
  report_latency(state, ns);
}

void scene_move(benchmark::State& state, a2l::Scene& scene) {
  const Eigen::Vector3d box(0.0, 0.0, 0.04);
  int k = 0;
  int moved = 0;
  for (auto _ : state) {
    // One push of the box from behind, then the scene is reset.
    if (k++ % 4 == 0) scene.reset(Eigen::Vector3d(-0.2, 0.0, 0.04), box);
    moved += scene.move(Eigen::Vector3d(0.05, 0.0, 0.0));
  }
  state.counters["moved_share"] = static_cast<double>(moved) / k;
}
void BM_virtual_move(benchmark::State& state) {
  a2l::VirtualScene s;
  scene_move(state, s);
}
#if A2L_HAVE_BULLET
void BM_bullet_move(benchmark::State& state) {
  a2l::BulletScene s;
  scene_move(state, s);
}
#endif

void BM_load_bundle(benchmark::State& state) {
  std::ifstream f(g_bundle, std::ios::binary);
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(f)),
                                        std::istreambuf_iterator<char>());
  for (auto _ : state) {
    a2l::Skill s;
    benchmark::DoNotOptimize(a2l::load_bundle_from_memory(bytes.data(), bytes.size(), s));
  }
  state.counters["bytes"] = static_cast<double>(bytes.size());
}

}  // namespace

BENCHMARK(BM_table_lookup);
BENCHMARK(BM_discretize);
BENCHMARK(BM_step);
BENCHMARK(BM_step_smoothing);
BENCHMARK(BM_step_latency)->Iterations(1000000);
BENCHMARK(BM_step_smoothing_latency)->Iterations(1000000);
BENCHMARK(BM_clock_latency)->Iterations(1000000);
BENCHMARK(BM_executor_tick);
BENCHMARK(BM_executor_tick_latency)->Iterations(1000000);
BENCHMARK(BM_control_tick);
BENCHMARK(BM_control_tick_latency)->Iterations(1000000);
BENCHMARK(BM_virtual_move);
#if A2L_HAVE_BULLET
BENCHMARK(BM_bullet_move)->Unit(benchmark::kMicrosecond);
#endif
BENCHMARK(BM_load_bundle)->Unit(benchmark::kMicrosecond);

int main(int argc, char** argv) {
  if (argc < 3 || argv[1][0] == '-' || argv[2][0] == '-') {
    std::fprintf(stderr, "usage: %s BUNDLE ROBOTS_DIR [benchmark options]\n", argv[0]);
    return 2;
  }
  g_bundle = argv[1];
  g_robots = argv[2];
  if (const a2l::Result r = a2l::load_bundle(g_bundle, g_skill); !r.ok()) {
    std::fprintf(stderr, "%s\n", r.message.c_str());
    return 2;
  }
  if (const a2l::Result r = a2l::Kinematics::load(g_robots + "/baxter_description/urdf/baxter.urdf",
                                                  "base", "right_gripper", g_kin);
      !r.ok()) {
    std::fprintf(stderr, "%s\n", r.message.c_str());
    return 2;
  }
  g_neutral << 0.08, -1.0, 1.19, 1.94, -0.67, 1.03, 0.5;
  argv[2] = argv[0];
  argc -= 2;
  argv += 2;
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
