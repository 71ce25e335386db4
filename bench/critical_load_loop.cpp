// The critical load factor alone, in a loop: `stiffmsa_critical_load_loop EXAMPLE ROUNDS` solves
// examples/EXAMPLE ROUNDS times through one workspace with the critical load factor asked for
// (docs/theory.md §14), then as often without, and prints the time per solve of each and their
// difference. On this VM one run's times drift by 20–60 %, so the factor's cost is also counted
// in instructions, which do not drift: run it under callgrind with collection limited to the
// solves that find it,
//
//   valgrind --tool=callgrind --toggle-collect='*solve_with_critical_load*' \
//     stiffmsa_critical_load_loop industrial-6axis.yaml 10
//
// and read the inclusive count of stiffmsa::detail::critical_load over its calls (one per load
// case per solve) in callgrind_annotate --inclusive=yes.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "bench_models.hpp"

namespace {

using namespace stiffmsa;

// Not inlined, so that callgrind can collect exactly these loops.
[[gnu::noinline]] double solve_with_critical_load(Workspace& workspace, const Model& model,
                                                  int rounds, const SolveOptions& options) {
  double sum = 0;  // used, so that no solve is optimised away
  for (int round = 0; round < rounds; ++round) {
    const Result result = solve(workspace, model, options);
    sum +=
        result.critical_load && result.critical_load->factor ? *result.critical_load->factor : 0.0;
  }
  return sum;
}

[[gnu::noinline]] double solve_without(Workspace& workspace, const Model& model, int rounds,
                                       const SolveOptions& options) {
  double sum = 0;
  for (int round = 0; round < rounds; ++round) sum += solve(workspace, model, options).links.size();
  return sum;
}

double microseconds_per_solve(const std::chrono::steady_clock::time_point& start, int rounds) {
  return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start)
             .count() /
         rounds;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string example = argc > 1 ? argv[1] : "industrial-6axis.yaml";
  const int rounds = argc > 2 ? std::atoi(argv[2]) : 100;
  if (rounds < 1) {
    std::fprintf(stderr, "usage: stiffmsa_critical_load_loop [EXAMPLE.yaml] [ROUNDS >= 1]\n");
    return 2;
  }
  const Model model = bench::load_example(example);
  Workspace workspace(model);
  SolveOptions with;
  with.critical_load = true;
  SolveOptions without;
  solve_with_critical_load(workspace, model, 1, with);  // warm-up
  auto start = std::chrono::steady_clock::now();
  const double factor = solve_with_critical_load(workspace, model, rounds, with) / rounds;
  const double us_with = microseconds_per_solve(start, rounds);
  start = std::chrono::steady_clock::now();
  solve_without(workspace, model, rounds, without);
  const double us_without = microseconds_per_solve(start, rounds);
  std::printf(
      "%s: %.2f us per solve with the critical load factor (%.9g), %.2f us without: %.2f us\n",
      example.c_str(), us_with, factor, us_without, us_with - us_without);
  return 0;
}
