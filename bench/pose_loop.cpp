// The public per-pose call alone, in a loop: `stiffmsa_pose_loop ROBOT ROUNDS` solves the 16
// poses of an example robot (6axis or tripteron, bench_models.hpp) ROUNDS times through one
// workspace and prints the time per pose. On this VM the time of one run drifts by 20–60 %, so
// a change to the pose's code is also compared by the instructions it executes, which do not
// drift: run it under callgrind with collection limited to the loop,
//
//   valgrind --tool=callgrind --toggle-collect='*run_poses*' stiffmsa_pose_loop 6axis 20
//
// and divide "Collected" by 16 × (ROUNDS + 1) poses (one warm-up round is collected too).
// A third argument `loaded` solves each pose in the loaded mode (docs/theory.md §15).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "bench_models.hpp"

namespace {

using namespace stiffmsa;

// Not inlined, so that callgrind can collect exactly this loop.
[[gnu::noinline]] double run_poses(Workspace& workspace, const std::vector<Model>& poses,
                                   int rounds, const SolveOptions& options) {
  double sum = 0;  // used, so that no solve is optimised away
  for (int round = 0; round < rounds; ++round)
    for (const Model& pose : poses)
      sum += (*solve(workspace, pose, options).end_effectors.front().compliance)(0, 0);
  return sum;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string robot = argc > 1 ? argv[1] : "6axis";
  const int rounds = argc > 2 ? std::atoi(argv[2]) : 1000;
  SolveOptions options;
  if (argc > 3 && std::string(argv[3]) == "loaded") options.mode = AnalysisMode::loaded;
  if ((robot != "6axis" && robot != "tripteron") || rounds < 1) {
    std::fprintf(stderr, "usage: stiffmsa_pose_loop [6axis|tripteron] [ROUNDS >= 1]\n");
    return 2;
  }
  constexpr int kPoses = 16;
  const std::vector<Model> poses =
      robot == "6axis"
          ? bench::industrial_poses(bench::load_example("industrial-6axis.yaml"), kPoses)
          : bench::tripteron_poses(bench::load_example("tripteron.yaml"), kPoses);
  Workspace workspace(poses.front());
  run_poses(workspace, poses, 1, options);  // warm-up
  const auto start = std::chrono::steady_clock::now();
  const double sum = run_poses(workspace, poses, rounds, options);
  const double us =
      std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
  std::printf("%s%s: %.2f us per pose over %d poses (checksum %.6g)\n", robot.c_str(),
              options.mode ? " (loaded)" : "", us / (kPoses * rounds), kPoses * rounds, sum);
  return 0;
}
