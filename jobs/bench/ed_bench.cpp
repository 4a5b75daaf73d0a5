// granpack_ed_bench: the event-driven hard-sphere engine (dynamics/hard_sphere_md.h) on the
// melt of the `ed_gas` stage of deck A (docs/event-driven.md, docs/performance.md): an FCC
// lattice of 4 nc^3 unit-diameter spheres at solid fraction phi, Maxwellian velocities
// (kT = 1, zero momentum), run for a fixed number of collisions per grain.
//
//   build/granpack_ed_bench [collisions_per_grain=100] [repeat=3] [nc=10] [phi=0.45] [seed=1]
//
// Prints, per try, the collisions per CPU second (user + system time of this process from
// getrusage, so other jobs on a shared machine do not count) and per wall second; then the
// best of the tries, the relative energy drift and a checksum (FNV-1a of the bytes of the
// final positions, velocities and clock), equal between two builds exactly when their
// trajectories are bit for bit the same. For instruction counts run one short try under
// valgrind --tool=callgrind (docs/performance.md gives the command). MPI-free: links
// granpack_physics only.
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numbers>
#include <random>
#include <vector>

#include "granpack/dynamics/hard_sphere_md.h"

namespace {

using granpack::HardSphereMD;
using granpack::Vec;

double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

HardSphereMD<3> fcc_gas(int nc, double phi, std::uint64_t seed) {
  const int n = 4 * nc * nc * nc;
  const double l = std::cbrt(n * std::numbers::pi / 6.0 / phi);
  const double a = l / nc;
  const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  std::vector<Vec<3>> x;
  for (int i = 0; i < nc; ++i)
    for (int j = 0; j < nc; ++j)
      for (int k = 0; k < nc; ++k)
        for (const auto& b : basis)
          x.push_back(a * Vec<3>(i + b[0] + 0.25, j + b[1] + 0.25, k + b[2] + 0.25));
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<Vec<3>> v(x.size());
  Vec<3> p = Vec<3>::Zero();
  for (auto& vi : v) {
    for (int c = 0; c < 3; ++c)
      vi[c] = g(rng);
    p += vi;
  }
  double k = 0;
  for (auto& vi : v) {
    vi -= p / static_cast<double>(n);
    k += 0.5 * vi.squaredNorm();
  }
  const double f = std::sqrt(1.5 * n / k);
  for (auto& vi : v)
    vi *= f;
  return HardSphereMD<3>(Vec<3>::Constant(l), std::move(x), std::vector<double>(n, 0.5),
                         std::vector<double>(n, 1.0), std::move(v));
}

std::uint64_t fnv1a(std::uint64_t h, const void* data, std::size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < bytes; ++i) {
    h ^= p[i];
    h *= 1099511628211ULL;
  }
  return h;
}

} // namespace

int main(int argc, char** argv) {
  const double per_grain = argc > 1 ? std::atof(argv[1]) : 100.0;
  const int repeat = argc > 2 ? std::atoi(argv[2]) : 3;
  const int nc = argc > 3 ? std::atoi(argv[3]) : 10;
  const double phi = argc > 4 ? std::atof(argv[4]) : 0.45;
  const auto seed = static_cast<std::uint64_t>(argc > 5 ? std::atoll(argv[5]) : 1);
  if (per_grain <= 0 || repeat < 1 || nc < 1 || !(phi > 0 && phi < 0.74)) {
    std::fprintf(stderr, "usage: granpack_ed_bench [collisions_per_grain=100] [repeat=3] "
                         "[nc=10] [phi=0.45] [seed=1]\n");
    return 2;
  }
  double best_cpu = 0, best_wall = 0, drift = 0;
  std::uint64_t sum = 0;
  std::int64_t total = 0;
  for (int r = 0; r < repeat; ++r) {
    auto md = fcc_gas(nc, phi, seed);
    const auto n = static_cast<std::int64_t>(md.size());
    total = std::llround(per_grain * static_cast<double>(n));
    const double k0 = md.kinetic_energy();
    const double c0 = cpu_seconds();
    const auto w0 = std::chrono::steady_clock::now();
    md.run_collisions(total);
    const double cpu = cpu_seconds() - c0;
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
    const double rate_cpu = static_cast<double>(total) / cpu;
    const double rate_wall = static_cast<double>(total) / wall;
    std::printf("try %d: %lld collisions of %lld spheres at phi %.3f: %.3f CPU s, %.3f wall s: "
                "%.4g collisions per CPU s, %.4g per wall s\n",
                r + 1, static_cast<long long>(total), static_cast<long long>(n), phi, cpu, wall,
                rate_cpu, rate_wall);
    best_cpu = std::max(best_cpu, rate_cpu);
    best_wall = std::max(best_wall, rate_wall);
    drift = md.kinetic_energy() / k0 - 1.0;
    std::uint64_t h = 1469598103934665603ULL;
    h = fnv1a(h, md.positions().data(), md.positions().size() * sizeof(Vec<3>));
    h = fnv1a(h, md.velocities().data(), md.velocities().size() * sizeof(Vec<3>));
    const double t = md.time();
    h = fnv1a(h, &t, sizeof t);
    sum = h;
  }
  std::printf("best of %d: %.4g collisions per CPU s (%.4g per wall s); energy drift %.2e; "
              "checksum %016llx\n",
              repeat, best_cpu, best_wall, drift, static_cast<unsigned long long>(sum));
  return 0;
}
