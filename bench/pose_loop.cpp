// The public per-pose call alone, in a loop: `stiffmsa_pose_loop ROBOT ROUNDS [SETTING]` solves
// the 16 poses of an example robot (6axis or tripteron, bench_models.hpp) ROUNDS times through
// one workspace and prints the time per pose. SETTING is one of
//
//   linear              the linear mode as a caller asks for it by default (no critical load
//                       factor: these robots' files have nothing that makes their results
//                       carry one); the default
//   linear-critical     the linear mode with the critical load factor (critical_load = true)
//   loaded              the loaded mode as by default (docs/theory.md §15): its results carry
//                       the critical load factor
//   loaded-no-critical  the loaded mode without it (critical_load = false)
//   all                 the four in turn, each through a workspace of its own
//
// so that the loaded mode's cost can be set against the linear one's with the critical load on
// both sides and on neither. On this VM the time of one run drifts by 20–60 %, so a change to
// the pose's code is also compared by the instructions it executes, which do not drift: run it
// under callgrind with collection limited to the loops,
//
//   valgrind --tool=callgrind --toggle-collect='*run_poses*' stiffmsa_pose_loop 6axis 20
//
// and divide "Collected" by 16 × (ROUNDS + 1) poses (one warm-up round is collected too); with
// `all`, each setting's loop is a function of its own (run_poses_linear, …) whose inclusive
// count (callgrind_annotate --inclusive=yes) divides alike.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "bench_models.hpp"

namespace {

using namespace stiffmsa;

constexpr int kPoses = 16;

// The loop itself; its callers are what callgrind's --toggle-collect names (a function of this
// name pattern called inside another would toggle the collection off).
inline double solve_each_pose(Workspace& workspace, const std::vector<Model>& poses, int rounds,
                              const SolveOptions& options) {
  double sum = 0;  // used, so that no solve is optimised away
  for (int round = 0; round < rounds; ++round)
    for (const Model& pose : poses)
      sum += (*solve(workspace, pose, options).end_effectors.front().compliance)(0, 0);
  return sum;
}

// Not inlined, so that callgrind can collect exactly these loops, one per setting.
[[gnu::noinline]] double run_poses_linear(Workspace& w, const std::vector<Model>& poses, int rounds,
                                          const SolveOptions& options) {
  return solve_each_pose(w, poses, rounds, options);
}
[[gnu::noinline]] double run_poses_linear_critical(Workspace& w, const std::vector<Model>& poses,
                                                   int rounds, const SolveOptions& options) {
  return solve_each_pose(w, poses, rounds, options);
}
[[gnu::noinline]] double run_poses_loaded(Workspace& w, const std::vector<Model>& poses, int rounds,
                                          const SolveOptions& options) {
  return solve_each_pose(w, poses, rounds, options);
}
[[gnu::noinline]] double run_poses_loaded_no_critical(Workspace& w, const std::vector<Model>& poses,
                                                      int rounds, const SolveOptions& options) {
  return solve_each_pose(w, poses, rounds, options);
}

struct Setting {
  const char* name;
  double (*run)(Workspace&, const std::vector<Model>&, int, const SolveOptions&);
  std::optional<AnalysisMode> mode;
  std::optional<bool> critical_load;
};

const Setting kSettings[] = {
    {"linear", run_poses_linear, std::nullopt, std::nullopt},
    {"linear-critical", run_poses_linear_critical, std::nullopt, true},
    {"loaded", run_poses_loaded, AnalysisMode::loaded, std::nullopt},
    {"loaded-no-critical", run_poses_loaded_no_critical, AnalysisMode::loaded, false},
};

// A warm-up round, then ROUNDS timed; prints the time per pose.
void measure(const std::string& robot, const std::vector<Model>& poses, int rounds,
             const Setting& setting) {
  SolveOptions options;
  options.mode = setting.mode;
  options.critical_load = setting.critical_load;
  Workspace workspace(poses.front());
  setting.run(workspace, poses, 1, options);  // warm-up
  const auto start = std::chrono::steady_clock::now();
  const double sum = setting.run(workspace, poses, rounds, options);
  const double us =
      std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
  std::printf("%s (%s): %.2f us per pose over %d poses (checksum %.6g)\n", robot.c_str(),
              setting.name, us / (kPoses * rounds), kPoses * rounds, sum);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string robot = argc > 1 ? argv[1] : "6axis";
  const int rounds = argc > 2 ? std::atoi(argv[2]) : 1000;
  const std::string asked = argc > 3 ? argv[3] : "linear";
  bool known = asked == "all";
  for (const Setting& setting : kSettings) known = known || asked == setting.name;
  if ((robot != "6axis" && robot != "tripteron") || rounds < 1 || !known) {
    std::fprintf(stderr,
                 "usage: stiffmsa_pose_loop [6axis|tripteron] [ROUNDS >= 1] "
                 "[linear|linear-critical|loaded|loaded-no-critical|all]\n");
    return 2;
  }
  const std::vector<Model> poses =
      robot == "6axis"
          ? bench::industrial_poses(bench::load_example("industrial-6axis.yaml"), kPoses)
          : bench::tripteron_poses(bench::load_example("tripteron.yaml"), kPoses);
  for (const Setting& setting : kSettings)
    if (asked == "all" || asked == setting.name) measure(robot, poses, rounds, setting);
  return 0;
}
