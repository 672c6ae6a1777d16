// Kinematics benchmarks (Google Benchmark): FK, Jacobian and IK per call on Baxter's right arm.
// Besides the mean, each benchmark reports per-call percentiles as counters (p50_us, p99_us):
// FK and Jacobian are timed in batches of 16 calls (clock overhead), IK call by call.
// Usage: bench_kinematics <robots_dir> [google benchmark flags]
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "a2l/kinematics.hpp"

namespace {

std::string g_robots_dir;

const a2l::Kinematics& baxter() {
  static a2l::Kinematics kin = [] {
    a2l::Kinematics k;
    const a2l::Result r = a2l::Kinematics::load(
        g_robots_dir + "/baxter_description/urdf/baxter.urdf", "base", "right_gripper", k);
    if (!r.ok()) {
      std::cerr << r.message << "\n";
      std::exit(2);
    }
    return k;
  }();
  return kin;
}

std::vector<a2l::JointVector> random_configurations(int n, std::uint64_t seed) {
  const a2l::Kinematics& k = baxter();
  std::mt19937_64 rng(seed);
  std::vector<a2l::JointVector> out;
  for (int t = 0; t < n; ++t) {
    a2l::JointVector q(k.n_joints());
    for (int i = 0; i < k.n_joints(); ++i) {
      q[i] = std::uniform_real_distribution<double>(k.lower()[i], k.upper()[i])(rng);
    }
    out.push_back(q);
  }
  return out;
}

void set_percentiles(benchmark::State& state, std::vector<double>& us) {
  if (us.empty()) return;
  std::sort(us.begin(), us.end());
  auto pct = [&](double p) { return us[static_cast<size_t>(p * (us.size() - 1))]; };
  state.counters["p50_us"] = pct(0.50);
  state.counters["p99_us"] = pct(0.99);
}

using Clock = std::chrono::steady_clock;

void BM_fk(benchmark::State& state) {
  const a2l::Kinematics& k = baxter();
  const auto qs = random_configurations(1024, 1);
  Eigen::Isometry3d pose;
  std::vector<double> batch_us;
  size_t i = 0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    for (int b = 0; b < 16; ++b) {
      k.fk(qs[(i + b) & 1023], pose);
      benchmark::DoNotOptimize(pose);
    }
    batch_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / 16);
    i += 16;
  }
  state.SetItemsProcessed(state.iterations() * 16);
  set_percentiles(state, batch_us);
}

void BM_jacobian(benchmark::State& state) {
  const a2l::Kinematics& k = baxter();
  const auto qs = random_configurations(1024, 2);
  a2l::Jacobian jac(6, 7);
  std::vector<double> batch_us;
  size_t i = 0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    for (int b = 0; b < 16; ++b) {
      k.jacobian(qs[(i + b) & 1023], jac);
      benchmark::DoNotOptimize(jac);
    }
    batch_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / 16);
    i += 16;
  }
  state.SetItemsProcessed(state.iterations() * 16);
  set_percentiles(state, batch_us);
}

void BM_ik(benchmark::State& state) {
  const a2l::Kinematics& k = baxter();
  const auto qs = random_configurations(1000, 3);
  std::vector<Eigen::Isometry3d> targets(qs.size());
  for (size_t t = 0; t < qs.size(); ++t) k.fk(qs[t], targets[t]);
  a2l::JointVector neutral(7), sol(7);
  neutral << 0.08, -1.0, 1.19, 1.94, -0.67, 1.03, 0.5;
  std::vector<double> us;
  size_t i = 0, ok = 0;
  for (auto _ : state) {
    a2l::IkOptions opt;
    opt.seed = i;
    const auto t0 = Clock::now();
    const a2l::Status s = k.ik(targets[i % targets.size()], neutral, sol, opt);
    us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
    ok += s == a2l::Status::ok;
    ++i;
  }
  state.counters["success"] = static_cast<double>(ok) / static_cast<double>(i);
  set_percentiles(state, us);
}

}  // namespace

BENCHMARK(BM_fk)->MinTime(0.5);
BENCHMARK(BM_jacobian)->MinTime(0.5);
BENCHMARK(BM_ik)->Iterations(1000);

int main(int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') {
    std::cerr << "usage: bench_kinematics <example-robot-data robots dir> [benchmark flags]\n";
    return 2;
  }
  g_robots_dir = argv[1];
  argv[1] = argv[0];
  --argc;
  ++argv;
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
